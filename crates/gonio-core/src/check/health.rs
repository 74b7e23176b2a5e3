//! Numerical health: `eval`, `pdf`, `eval_pdf` and
//! `sample` never return NaN, ±∞ or negative values, for random directions on both hemispheres,
//! for the degenerate ones a renderer meets (exactly grazing z = 0, |z| ≤ 1e-6, the poles,
//! wi = ±wo) and for wavelengths across 360–830 nm including both ends; and a returned sample
//! honours the trait contract (unit `wo`, finite non-negative weight, pdf > 0, a delta
//! selection probability ≤ 1, eta > 0).
//!
//! Rows: `health` (number of violations) and `lobe_flags` (number of samples whose flags are not
//! among the model's, or whose reflection/transmission flag contradicts the sides of wi and wo).

use super::{Bound, CheckConfig, CheckResult, random_wavelengths, uniform_sphere};
use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags};
use crate::rng::ONE_MINUS_EPSILON;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// Degenerate and grazing directions every model must survive (both hemispheres).
pub fn special_directions() -> Vec<Vec3> {
    let mut v = vec![
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::new(0.6, 0.8, 0.0),
        Vec3::new(-0.0, -1.0, -0.0),
    ];
    for z in [1e-6f32, 1e-7, 1e-30, f32::MIN_POSITIVE, 1e-3] {
        for s in [1.0f32, -1.0] {
            let r = (1.0 - z * z).sqrt();
            v.push(Vec3::new(0.8 * r, -0.6 * r, s * z));
        }
    }
    // Nearly normal.
    v.push(Vec3::new(1e-7, 0.0, 1.0));
    v.push(Vec3::new(0.0, -1e-7, -1.0));
    v
}

/// Wavelengths at and near the ends of the visible range, and the middle.
pub const SPECIAL_WAVELENGTHS: [f32; 5] = [360.0, 360.001, 555.0, 829.999, 830.0];

struct Tally {
    count: usize,
    examples: Vec<String>,
}

impl Tally {
    fn fail(&mut self, msg: impl FnOnce() -> String) {
        self.count += 1;
        if self.examples.len() < 3 {
            self.examples.push(msg());
        }
    }
    fn detail(&self, queries: usize) -> String {
        format!(
            "{} violations in {queries} queries; e.g. {}",
            self.count,
            self.examples.join(" | ")
        )
    }
}

fn spectrum_ok(s: SampledSpectrum) -> bool {
    s.is_finite() && s.min_component() >= 0.0
}

/// Health of `eval`, `pdf` and `eval_pdf` at one query: `Err` describes a NaN, infinite or
/// negative value.
pub fn check_eval(
    bsdf: &dyn Bsdf,
    ctx: &BsdfContext,
    wi: Vec3,
    wo: Vec3,
    wl: &SampledWavelengths,
) -> Result<(), String> {
    let f = bsdf.eval(ctx, wi, wo, wl);
    let p = bsdf.pdf(ctx, wi, wo, wl);
    let (f2, p2) = bsdf.eval_pdf(ctx, wi, wo, wl);
    if spectrum_ok(f) && spectrum_ok(f2) && p.is_finite() && p >= 0.0 && p2.is_finite() && p2 >= 0.0 {
        Ok(())
    } else {
        Err(format!(
            "eval/pdf wi={wi:?} wo={wo:?} λ={:?} {:?}: f={f:?} pdf={p} eval_pdf=({f2:?}, {p2})",
            wl.lambdas(),
            ctx.mode
        ))
    }
}

/// Problems of one `sample` call.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SampleProblems {
    /// Contract violation: non-unit or non-finite `wo`, weight NaN/∞/negative, pdf not in
    /// (0, ∞) (or a delta selection probability above 1), eta not positive, corrupted
    /// wavelengths. (A zero weight is allowed: a smooth sample is returned wherever its pdf is
    /// positive, even from a black lobe, so that mixtures stay unbiased.)
    pub health: Option<String>,
    /// Flags not among the model's, not exactly one of reflection/transmission, or contradicting
    /// the sides of wi and wo (checked when both |cos θ| > 1e-4).
    pub flags: Option<String>,
}

/// Health of one `sample` call (a `None` sample is healthy).
pub fn check_sample(
    bsdf: &dyn Bsdf,
    ctx: &BsdfContext,
    wi: Vec3,
    u1: f32,
    u2: Vec2,
    wl: &SampledWavelengths,
) -> SampleProblems {
    let mut out = SampleProblems::default();
    let mut wl2 = *wl;
    let Some(s) = bsdf.sample(ctx, wi, u1, u2, &mut wl2) else {
        return out;
    };
    let at = || {
        format!(
            "sample wi={wi:?} u1={u1} u2={u2} λ={:?} {:?}: {s:?}",
            wl.lambdas(),
            ctx.mode
        )
    };
    let unit = s.wo.is_finite() && (s.wo.length() - 1.0).abs() < 1e-3;
    let pdf_ok = s.pdf.is_finite() && s.pdf > 0.0 && (!s.flags.is_delta() || s.pdf <= 1.0 + 1e-6);
    if !(unit && spectrum_ok(s.weight) && pdf_ok && s.eta.is_finite() && s.eta > 0.0) {
        out.health = Some(at());
    } else if !wl2.pdf().is_finite() || wl2.lambdas().iter().any(|l| !l.is_finite()) {
        out.health = Some(format!("{} corrupted the wavelengths", at()));
    }
    let flags = bsdf.flags();
    let kinds = BsdfFlags(s.flags.0 & 0b11111);
    let one_side = s.flags.is_reflection() != s.flags.is_transmission();
    let sides_known = wi.z.abs() > 1e-4 && s.wo.z.abs() > 1e-4;
    let side_ok = !sides_known || (s.flags.is_reflection() == (wi.z * s.wo.z > 0.0));
    if !flags.contains(kinds) || !one_side || !side_ok {
        out.flags = Some(format!("{} (model flags {flags})", at()));
    }
    out
}

/// The `health` and `lobe_flags` rows.
pub fn health(bsdf: &dyn Bsdf, config: &CheckConfig) -> Vec<CheckResult> {
    let mut rng = config.rng(0x004e_a174);
    let mut h = Tally {
        count: 0,
        examples: Vec::new(),
    };
    let mut lf = Tally {
        count: 0,
        examples: Vec::new(),
    };
    let mut queries = 0usize;
    let specials = special_directions();
    let ctxs = [BsdfContext::radiance(), BsdfContext::importance()];

    let eval_query = |wi: Vec3, wo: Vec3, wl: &SampledWavelengths, ctx: &BsdfContext, h: &mut Tally| {
        if let Err(e) = check_eval(bsdf, ctx, wi, wo, wl) {
            h.fail(|| e);
        }
    };
    let sample_query = |wi: Vec3,
                        u1: f32,
                        u2: Vec2,
                        wl: &SampledWavelengths,
                        ctx: &BsdfContext,
                        h: &mut Tally,
                        lf: &mut Tally| {
        let p = check_sample(bsdf, ctx, wi, u1, u2, wl);
        if let Some(e) = p.health {
            h.fail(|| e);
        }
        if let Some(e) = p.flags {
            lf.fail(|| e);
        }
    };

    // Degenerate directions × special wavelengths × both modes.
    for &lambda in &SPECIAL_WAVELENGTHS {
        let wl = SampledWavelengths::fixed(lambda);
        for ctx in &ctxs {
            for &wi in &specials {
                for &wo in &specials {
                    queries += 1;
                    eval_query(wi, wo, &wl, ctx, &mut h);
                }
                eval_query(wi, -wi, &wl, ctx, &mut h);
                for u1 in [0.0, 0.5, ONE_MINUS_EPSILON] {
                    for u2 in [
                        Vec2::ZERO,
                        Vec2::splat(0.5),
                        Vec2::splat(ONE_MINUS_EPSILON),
                        Vec2::new(0.0, ONE_MINUS_EPSILON),
                    ] {
                        queries += 1;
                        sample_query(wi, u1, u2, &wl, ctx, &mut h, &mut lf);
                    }
                }
            }
        }
    }
    // Random queries: random directions (every fourth one grazing), random wavelengths and u.
    for k in 0..config.health_queries {
        let mut wi = uniform_sphere(&mut rng);
        let mut wo = uniform_sphere(&mut rng);
        if k % 4 == 0 {
            wi.z = wi.z.signum() * 1e-6 * rng.next_f32();
            wi = wi.normalize();
        } else if k % 4 == 1 {
            wo.z = 0.0;
            wo = wo.normalize();
        }
        let wl = random_wavelengths(&mut rng);
        let ctx = &ctxs[k % 2];
        queries += 2;
        eval_query(wi, wo, &wl, ctx, &mut h);
        let u1 = rng.next_f32();
        sample_query(wi, u1, rng.next_vec2(), &wl, ctx, &mut h, &mut lf);
    }
    vec![
        CheckResult::compare("health", h.count as f64, Bound::AtMost, 0.0, h.detail(queries)),
        CheckResult::compare(
            "lobe_flags",
            lf.count as f64,
            Bound::AtMost,
            0.0,
            lf.detail(queries),
        ),
    ]
}
