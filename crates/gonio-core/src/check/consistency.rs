//! `eval` / `pdf` / `sample` consistency (as Mitsuba 3's `src/bsdfs/tests/*.py` check it).
//!
//! * `weight_vs_eval`: at every smooth sample, weight = f(wi, wo)·|cos θo| / pdf, per wavelength
//!   (Mitsuba measures ≤ 6e-8 for its models; `f32` rounding only).
//! * `sample_pdf_vs_pdf`: the density `sample` reports equals `pdf(wi, wo)` (Mitsuba: ≤ 8e-7
//!   relative); this is what MIS relies on.
//! * `eval_pdf`: the fused `eval_pdf` returns what `eval` and `pdf` return.
//! * `pdf_integral`: ∫ pdf dω ≤ 1, estimated with uniform directions on the sphere.
//! * `pdf_normalization`: ∫ pdf dω equals the probability that `sample` returns a smooth-lobe
//!   direction (estimated from the same number of `sample` calls). A pdf off by a constant
//!   factor, or a lobe-selection probability missing from the pdf, fails here even when the
//!   integral stays below 1.
//!
//! Queries cover random `wi` on both hemispheres, both transport modes and random visible
//! wavelengths.

use super::{
    Bound, CheckConfig, CheckResult, random_wavelengths, rel_diff, sidak, uniform_sphere, z_quantile,
};
use crate::bsdf::{Bsdf, BsdfContext};
use crate::warp::square_to_uniform_sphere_pdf;

/// Values below this are treated as zero when forming relative errors (`f32` denormal range and
/// values far below anything a renderer can see).
const TINY: f64 = 1e-12;

/// The `weight_vs_eval`, `sample_pdf_vs_pdf` and `eval_pdf` rows (smooth lobes only).
pub fn consistency(bsdf: &dyn Bsdf, config: &CheckConfig) -> Vec<CheckResult> {
    let mut rng = config.rng(0xc0_5157);
    let (mut worst_w, mut worst_p, mut worst_ep) = (0.0f64, 0.0f64, 0.0f64);
    let (mut at_w, mut at_p, mut at_ep) = (String::new(), String::new(), String::new());
    let mut smooth = 0usize;
    let mut ctx = BsdfContext::radiance();
    let mut wi = uniform_sphere(&mut rng);
    for k in 0..config.consistency_samples {
        if k % 16 == 0 {
            wi = uniform_sphere(&mut rng);
            ctx = if rng.next_f32() < 0.5 {
                BsdfContext::radiance()
            } else {
                BsdfContext::importance()
            };
        }
        let mut wl = random_wavelengths(&mut rng);
        let (u1, u2) = (rng.next_f32(), rng.next_vec2());
        let Some(s) = bsdf.sample(&ctx, wi, u1, u2, &mut wl) else {
            continue;
        };
        if s.flags.is_delta() {
            continue;
        }
        smooth += 1;
        let f = bsdf.eval(&ctx, wi, s.wo, &wl);
        let p = bsdf.pdf(&ctx, wi, s.wo, &wl);
        let (f2, p2) = bsdf.eval_pdf(&ctx, wi, s.wo, &wl);
        let where_ = || format!("wi={:.4} wo={:.4} u1={u1} u2={u2} {:?}", wi, s.wo, ctx.mode);
        let ep = rel_diff(s.pdf as f64, p as f64, TINY);
        if ep.is_nan() || ep > worst_p {
            worst_p = if ep.is_nan() { f64::INFINITY } else { ep };
            at_p = format!("{} sample pdf {} vs pdf {}", where_(), s.pdf, p);
        }
        let mut eep = rel_diff(p as f64, p2 as f64, TINY);
        for i in 0..4 {
            eep = eep.max(rel_diff(f[i] as f64, f2[i] as f64, TINY));
            let expect = f[i] as f64 * (s.wo.z as f64).abs() / s.pdf as f64;
            let e = rel_diff(s.weight[i] as f64, expect, TINY);
            if e.is_nan() || e > worst_w {
                worst_w = if e.is_nan() { f64::INFINITY } else { e };
                at_w = format!("{} weight {} vs f|cos|/pdf {expect}", where_(), s.weight[i]);
            }
        }
        if eep.is_nan() || eep > worst_ep {
            worst_ep = if eep.is_nan() { f64::INFINITY } else { eep };
            at_ep = format!("{} eval/pdf {f:?}/{p} vs eval_pdf {f2:?}/{p2}", where_());
        }
    }
    if smooth == 0 {
        return vec![CheckResult::compare(
            "weight_vs_eval",
            f64::INFINITY,
            Bound::AtMost,
            config.rel_tol,
            format!(
                "flags say smooth lobes but none of {} samples was smooth",
                config.consistency_samples
            ),
        )];
    }
    let tag = |s: &str| format!("max relative error over {smooth} smooth samples; worst: {s}");
    vec![
        CheckResult::compare(
            "weight_vs_eval",
            worst_w,
            Bound::AtMost,
            config.rel_tol,
            tag(&at_w),
        ),
        CheckResult::compare(
            "sample_pdf_vs_pdf",
            worst_p,
            Bound::AtMost,
            config.rel_tol,
            tag(&at_p),
        ),
        CheckResult::compare("eval_pdf", worst_ep, Bound::AtMost, config.rel_tol, tag(&at_ep)),
    ]
}

/// Estimates of ∫ pdf dω and of P(sample returns a smooth lobe) for one query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PdfIntegral {
    /// Uniform-sphere estimate of ∫ pdf(wi, ω) dω.
    pub integral: f64,
    /// Its standard error.
    pub integral_se: f64,
    /// Fraction of `sample` calls that returned a smooth-lobe direction.
    pub smooth_fraction: f64,
    /// Its binomial standard error.
    pub smooth_fraction_se: f64,
}

/// Estimates ∫ pdf dω (uniform sphere, `n` directions) and the smooth-sample probability (`n`
/// calls of `sample`) for one `wi`.
pub fn pdf_integral_at(
    bsdf: &dyn Bsdf,
    ctx: &BsdfContext,
    wi: glam::Vec3,
    n: usize,
    rng: &mut crate::rng::Pcg32,
) -> PdfIntegral {
    let wl = random_wavelengths(rng);
    let inv_pdf = 1.0 / square_to_uniform_sphere_pdf() as f64;
    let (mut s1, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let wo = uniform_sphere(rng);
        let v = bsdf.pdf(ctx, wi, wo, &wl) as f64 * inv_pdf;
        s1 += v;
        s2 += v * v;
    }
    let mean = s1 / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(0.0);
    let mut hits = 0usize;
    for _ in 0..n {
        let mut wl2 = wl;
        let u1 = rng.next_f32();
        if let Some(s) = bsdf.sample(ctx, wi, u1, rng.next_vec2(), &mut wl2) {
            hits += !s.flags.is_delta() as usize;
        }
    }
    let q = hits as f64 / n as f64;
    PdfIntegral {
        integral: mean,
        integral_se: (var / n as f64).sqrt(),
        smooth_fraction: q,
        smooth_fraction_se: (q * (1.0 - q) / n as f64).sqrt(),
    }
}

/// The `pdf_integral` and `pdf_normalization` rows, each at level `alpha_row` (Šidák-split
/// over the query directions).
pub fn pdf_integral(bsdf: &dyn Bsdf, config: &CheckConfig, alpha_row: f64) -> Vec<CheckResult> {
    let mut rng = config.rng(0x9df_1e9);
    let m = config.pdf_integral_queries.max(1);
    let a = sidak(alpha_row, m);
    // One-sided bound for ≤ 1 (z at 2a two-sided), two-sided for the equality.
    let (k1, k2) = (z_quantile(2.0 * a), z_quantile(a));
    let (mut pass1, mut pass2) = (true, true);
    let (mut worst1, mut worst2) = ((f64::NEG_INFINITY, 1.0, String::new()), (0.0f64, String::new()));
    for q in 0..m {
        // Half the queries from each side, the first straight down the normal.
        let mut wi = if q == 0 {
            glam::Vec3::Z
        } else {
            uniform_sphere(&mut rng)
        };
        if q % 2 == 1 {
            wi.z = -wi.z.abs();
        } else {
            wi.z = wi.z.abs();
        }
        let ctx = BsdfContext::radiance();
        let r = pdf_integral_at(bsdf, &ctx, wi, config.pdf_integral_samples, &mut rng);
        let thr = 1.0 + k1 * r.integral_se + 1e-6;
        pass1 &= r.integral.is_finite() && r.integral <= thr;
        let z1 = (r.integral - 1.0) / r.integral_se.max(1e-300);
        if z1 > worst1.0 || worst1.2.is_empty() {
            worst1 = (
                z1,
                r.integral,
                format!("wi={wi:.3}: {r:?}, threshold 1 + {k1:.2}σ = {thr:.5}"),
            );
        }
        let se = (r.integral_se.powi(2) + r.smooth_fraction_se.powi(2)).sqrt();
        // 1e-6 absorbs f32 rounding of a constant pdf (both standard errors can be 0).
        let d = ((r.integral - r.smooth_fraction).abs() - 1e-6).max(0.0);
        let z2 = if d == 0.0 { 0.0 } else { d / se.max(1e-300) };
        pass2 &= z2.is_finite() && z2 <= k2;
        if z2.is_nan() || z2 > worst2.0 || worst2.1.is_empty() {
            worst2 = (
                if z2.is_nan() { f64::INFINITY } else { z2 },
                format!("wi={wi:.3}: {r:?}"),
            );
        }
    }
    let thr1 = {
        // Report the threshold at the worst query.
        let se = if worst1.0.is_finite() && worst1.0 != 0.0 {
            (worst1.1 - 1.0) / worst1.0
        } else {
            0.0
        };
        1.0 + k1 * se.abs() + 1e-6
    };
    vec![
        CheckResult::with_verdict(
            "pdf_integral",
            worst1.1,
            Bound::AtMost,
            thr1,
            pass1,
            format!(
                "∫pdf dω over {m} queries × {} dirs; worst {}",
                config.pdf_integral_samples, worst1.2
            ),
        ),
        CheckResult::with_verdict(
            "pdf_normalization",
            worst2.0,
            Bound::AtMost,
            k2,
            pass2,
            format!("|∫pdf − P(smooth sample)| in standard errors; worst {}", worst2.1),
        ),
    ]
}
