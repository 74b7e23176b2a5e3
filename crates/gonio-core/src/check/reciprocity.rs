//! Reciprocity and adjointness (lecture slide "BRDF properties").
//!
//! In Mitsuba's argument order, with η_x the index on x's side (Veach 1997, §5.2):
//!
//! ```text
//!     reflection:    f(a, b) = f(b, a)
//!     transmission:  f_rad(a, b) / η_a² = f_rad(b, a) / η_b²
//!     adjoint:       f_imp(a, b) = f_rad(b, a)
//! ```
//!
//! Rows:
//! * `reciprocity`: max relative asymmetry |f(a,b) − f(b,a)| / max over random pairs on the
//!   same side, radiance mode, smooth lobes (`eval`).
//! * `eta2_law`: the transmission law over random pairs on opposite sides; η_b/η_a is read from
//!   the `eta` of a transmission sampled from a (1 if the model cannot transmit). Only reported
//!   when some pair has a non-zero smooth transmission.
//! * `adjoint`: f_imp(a, b) = f_rad(b, a) over all pairs (importance mode is the transpose).
//! * `delta_reciprocity`: the same laws for delta lobes, where f is a Dirac delta and only
//!   the throughput τ (weight × selection probability, summed over the lobes that land on the
//!   same direction: [`delta_throughput`]) is a number. Transforming
//!   the delta by the refraction Jacobian η_a² cos θa dωa = η_b² cos θb dωb turns the
//!   transmission law into τ_rad(a→b)·e_ab² = τ_rad(b→a)·e_ba² with e = `BsdfSample::eta`, and
//!   the adjoint into τ_imp(a→b) = τ_rad(a→b)·e_ab²: importance throughput is symmetric. For
//!   random a, every delta direction b reachable from a must lead back to a with the
//!   matching throughput, in both modes; directions are recomputed in `f32`, so the tolerance
//!   is 10 × `rel_tol` and directions with |cos θ| < 0.05 are skipped.

use super::{Bound, CheckConfig, CheckResult, rel_diff, uniform_sphere};
use crate::bsdf::{Bsdf, BsdfContext, BsdfSample, TransportMode};
use crate::rng::ONE_MINUS_EPSILON;
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

const TINY: f64 = 1e-12;

/// Delta events with |cos θ| below this on either side are skipped: near grazing, 1 − F varies
/// like cos θ, so the ~1e-6 error of a direction recomputed in `f32` becomes a relative
/// throughput error of ~1e-6/|cos θ| (1e-3 at cos θ = 0.01), which is rounding, not physics.
const GRAZING: f32 = 0.05;

/// u1 values probing every lobe a sample can pick: both ends and `n` midpoints.
fn u1_grid(n: usize) -> impl Iterator<Item = f32> {
    std::iter::once(0.0f32)
        .chain((0..n).map(move |j| (j as f32 + 0.5) / n as f32))
        .chain(std::iter::once(ONE_MINUS_EPSILON))
}

/// n(other side)/n(a's side), from the first transmission `sample` produces from `a`, and
/// whether that refraction terminated the secondary wavelengths (a dispersive index: the eta
/// holds for the hero wavelength only). (1, false) when no transmission is sampled.
///
/// u2 = (0.5, 0.5) is tried first, then an 8 × 8 grid (the facet a rough interface draws at
/// (0.5, 0.5) may face away from a).
pub fn eta_across(bsdf: &dyn Bsdf, a: Vec3, wl: &SampledWavelengths) -> (f32, bool) {
    let ctx = BsdfContext::importance();
    let grid = (0..64).map(|k| Vec2::new((k % 8) as f32 + 0.5, (k / 8) as f32 + 0.5) / 8.0);
    for u2 in std::iter::once(Vec2::splat(0.5)).chain(grid) {
        for u1 in u1_grid(64) {
            let mut wl2 = *wl;
            if let Some(s) = bsdf.sample(&ctx, a, u1, u2, &mut wl2)
                && s.flags.is_transmission()
                && s.eta.is_finite()
                && s.eta > 0.0
            {
                return (s.eta, wl2.secondary_terminated() && !wl.secondary_terminated());
            }
        }
    }
    (1.0, false)
}

/// η_b/η_a for a pair on opposite sides: [`eta_across`] from `a`, or, when `a` samples no
/// transmission (a rough interface seen beyond the critical angle from the denser side, where
/// most facets reflect totally), the reciprocal of the one from `b`.
fn eta_between(bsdf: &dyn Bsdf, a: Vec3, b: Vec3, wl: &SampledWavelengths) -> (f32, bool) {
    let from_a = eta_across(bsdf, a, wl);
    if from_a != (1.0, false) {
        return from_a;
    }
    let (e, dispersive) = eta_across(bsdf, b, wl);
    (1.0 / e, dispersive)
}

fn max_rel(a: SampledSpectrum, b: SampledSpectrum, slots: usize) -> f64 {
    (0..slots)
        .map(|i| rel_diff(a[i] as f64, b[i] as f64, TINY))
        .fold(0.0, |m, x| if x.is_nan() { f64::INFINITY } else { m.max(x) })
}

/// The reciprocity rows of `bsdf` (see the module docs).
pub fn reciprocity(bsdf: &dyn Bsdf, config: &CheckConfig) -> Vec<CheckResult> {
    let mut rng = config.rng(0x0004_ec19);
    let rad = BsdfContext::radiance();
    let imp = BsdfContext::importance();
    let (mut w_refl, mut w_tran, mut w_adj) = (
        (0.0f64, String::new()),
        (0.0f64, String::new()),
        (0.0f64, String::new()),
    );
    let (mut n_refl, mut n_tran) = (0usize, 0usize);
    for _ in 0..config.pairs {
        let (a, b) = (uniform_sphere(&mut rng), uniform_sphere(&mut rng));
        let wl = super::random_wavelengths(&mut rng);
        let fab = bsdf.eval(&rad, a, b, &wl);
        let fba = bsdf.eval(&rad, b, a, &wl);
        let at = || format!("a={a:.4} b={b:.4} λ={:.1}", wl.hero());
        let adj = max_rel(bsdf.eval(&imp, a, b, &wl), fba, N_SPECTRUM_SAMPLES);
        if adj > w_adj.0 {
            w_adj = (
                adj,
                format!(
                    "{} f_imp(a,b)={} f_rad(b,a)={}",
                    at(),
                    bsdf.eval(&imp, a, b, &wl),
                    fba
                ),
            );
        }
        if fab.is_black() && fba.is_black() {
            continue;
        }
        if a.z * b.z > 0.0 {
            n_refl += 1;
            let e = max_rel(fab, fba, N_SPECTRUM_SAMPLES);
            if e > w_refl.0 {
                w_refl = (e, format!("{} f(a,b)={fab} f(b,a)={fba}", at()));
            }
        } else {
            n_tran += 1;
            let (eta, dispersive) = eta_between(bsdf, a, b, &wl);
            let slots = if dispersive { 1 } else { N_SPECTRUM_SAMPLES };
            let e = max_rel(fab * (eta * eta), fba, slots);
            if e > w_tran.0 {
                w_tran = (
                    e,
                    format!("{} e={eta} f(a,b)·e²={} f(b,a)={fba}", at(), fab * (eta * eta)),
                );
            }
        }
    }
    let tol = config.rel_tol;
    let mut rows = vec![
        CheckResult::compare(
            "reciprocity",
            w_refl.0,
            Bound::AtMost,
            tol,
            format!(
                "max relative asymmetry over {n_refl} same-side pairs with f ≠ 0; worst {}",
                w_refl.1
            ),
        ),
        CheckResult::compare(
            "adjoint",
            w_adj.0,
            Bound::AtMost,
            tol,
            format!(
                "max relative |f_imp(a,b) − f_rad(b,a)| over {} pairs; worst {}",
                config.pairs, w_adj.1
            ),
        ),
    ];
    if n_tran > 0 {
        rows.push(CheckResult::compare(
            "eta2_law",
            w_tran.0,
            Bound::AtMost,
            tol,
            format!(
                "max relative |f(a,b)e² − f(b,a)| over {n_tran} opposite-side pairs with f ≠ 0; worst {}",
                w_tran.1
            ),
        ));
    }
    if bsdf.flags().is_delta() {
        rows.push(delta_reciprocity(bsdf, config));
    }
    rows
}

/// Throughput made mode-independent: τ·e² in radiance mode, τ in importance mode.
fn normalized_weight(s: &BsdfSample, mode: TransportMode) -> SampledSpectrum {
    match mode {
        TransportMode::Radiance => s.weight * (s.eta * s.eta),
        TransportMode::Importance => s.weight,
    }
}

/// Grid of the u1 integral in [`delta_throughput`]: a delta lobe selected with probability
/// below 1/`U1_CELLS` can hide between two grid points.
const U1_CELLS: usize = 256;

/// Total normalized delta throughput from `a` into direction `b` (within 1e-3) by lobes of the
/// given kind (reflection or not): τ̂(a→b) = ∫₀¹ 1[sample(u1) hits b]·weight·(e² in radiance
/// mode) du1. Each delta lobe l is selected on a u1-interval of length P_l with weight τ_l/P_l,
/// so the integral is Σ_l τ_l over every lobe that lands on b, however many coincide (a blend
/// of a glass and a plastic both mirror into the same direction). The integrand is piecewise
/// constant; its jumps between grid points are located by bisection to `f32` resolution.
pub fn delta_throughput(
    bsdf: &dyn Bsdf,
    mode: TransportMode,
    a: Vec3,
    b: Vec3,
    reflection: bool,
    u2: Vec2,
    wl: &SampledWavelengths,
) -> SampledSpectrum {
    let ctx = BsdfContext {
        mode,
        ..BsdfContext::radiance()
    };
    let integrand = |u1: f32| -> SampledSpectrum {
        let mut wl2 = *wl;
        match bsdf.sample(&ctx, a, u1.min(ONE_MINUS_EPSILON), u2, &mut wl2) {
            Some(s)
                if s.flags.is_delta()
                    && s.flags.is_reflection() == reflection
                    && (s.wo - b).length() < 1e-3 =>
            {
                normalized_weight(&s, mode)
            }
            _ => SampledSpectrum::ZERO,
        }
    };
    let mut total = SampledSpectrum::ZERO;
    let mut lo_u = 0.0f32;
    let mut lo_v = integrand(0.0);
    for j in 1..=U1_CELLS {
        let hi_u = j as f32 / U1_CELLS as f32;
        let hi_v = integrand(hi_u);
        if hi_v == lo_v {
            total += lo_v * (hi_u - lo_u);
        } else {
            // One jump inside (lo_u, hi_u]: bisect to the last u with the left value.
            let (mut l, mut h) = (lo_u, hi_u);
            for _ in 0..32 {
                let m = 0.5 * (l + h);
                if m <= l || m >= h {
                    break;
                }
                if integrand(m) == lo_v {
                    l = m;
                } else {
                    h = m;
                }
            }
            total += lo_v * (h - lo_u) + hi_v * (hi_u - h);
        }
        lo_u = hi_u;
        lo_v = hi_v;
    }
    total
}

/// The `delta_reciprocity` row (see the module docs).
pub fn delta_reciprocity(bsdf: &dyn Bsdf, config: &CheckConfig) -> CheckResult {
    let mut rng = config.rng(0xde17a);
    let tol = 10.0 * config.rel_tol;
    let queries = (config.pairs / 40).max(50);
    let (mut worst, mut at) = (0.0f64, String::new());
    let (mut tested, mut unmatched) = (0usize, 0usize);
    let mut record = |e: f64, what: &dyn Fn() -> String| {
        let e = if e.is_nan() { f64::INFINITY } else { e };
        if e > worst {
            worst = e;
            at = what();
        }
    };
    for _ in 0..queries {
        let a = uniform_sphere(&mut rng);
        let lambda = 360.0 + 470.0 * rng.next_f32();
        let u2 = rng.next_vec2();
        if a.z.abs() < GRAZING {
            continue;
        }
        let wl = SampledWavelengths::fixed(lambda);
        // The distinct delta directions reachable from a.
        let mut targets: Vec<(Vec3, bool)> = Vec::new();
        for u1 in u1_grid(64) {
            let mut wl2 = wl;
            let Some(s) = bsdf.sample(&BsdfContext::radiance(), a, u1, u2, &mut wl2) else {
                continue;
            };
            let kind = s.flags.is_reflection();
            if s.flags.is_delta()
                && s.wo.z.abs() >= GRAZING
                && !targets
                    .iter()
                    .any(|&(t, k)| k == kind && (t - s.wo).length() < 1e-3)
            {
                targets.push((s.wo, kind));
            }
        }
        for (b, refl) in targets {
            tested += 1;
            let t = |mode, from, to| delta_throughput(bsdf, mode, from, to, refl, u2, &wl);
            let (rad_ab, imp_ab) = (
                t(TransportMode::Radiance, a, b),
                t(TransportMode::Importance, a, b),
            );
            let (rad_ba, imp_ba) = (
                t(TransportMode::Radiance, b, a),
                t(TransportMode::Importance, b, a),
            );
            if rad_ba.is_black() && imp_ba.is_black() {
                unmatched += 1;
            }
            let what = || {
                format!(
                    "a={a:.4} b={b:.4} λ={lambda:.1} {}: τ̂_rad(a→b)={rad_ab:?} τ̂_rad(b→a)={rad_ba:?} τ̂_imp(a→b)={imp_ab:?} τ̂_imp(b→a)={imp_ba:?}",
                    if refl { "reflection" } else { "transmission" }
                )
            };
            record(max_rel(rad_ab, rad_ba, N_SPECTRUM_SAMPLES), &what);
            record(max_rel(imp_ab, imp_ba, N_SPECTRUM_SAMPLES), &what);
            record(max_rel(rad_ab, imp_ab, N_SPECTRUM_SAMPLES), &what);
        }
    }
    CheckResult::compare(
        "delta_reciprocity",
        worst,
        Bound::AtMost,
        tol,
        format!(
            "max relative asymmetry of τ̂ = τ·e² (radiance) or τ (importance), a→b vs b→a and radiance vs importance, over {tested} delta directions ({unmatched} not reachable back); worst {at}"
        ),
    )
}
