//! Reciprocity and adjointness (testing.md §4; lecture slide "BRDF properties").
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
//!   the throughput τ = weight × (selection probability) of `sample` is a number. Transforming
//!   the delta by the refraction Jacobian η_a² cos θa dωa = η_b² cos θb dωb turns the
//!   transmission law into τ_rad(a→b)·e_ab² = τ_rad(b→a)·e_ba² with e = `BsdfSample::eta`, and
//!   the adjoint into τ_imp(a→b) = τ_rad(a→b)·e_ab²: importance throughput is symmetric. For
//!   random a, each delta lobe sampled from a (a grid of u1) must be reachable back from
//!   b = wo (some u1 returns a within 1e-3) with the matching throughput; directions are
//!   recomputed in `f32`, so the tolerance is 10 × `rel_tol` and events with |cos θ| < 0.05
//!   are skipped.

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
pub fn eta_across(bsdf: &dyn Bsdf, a: Vec3, wl: &SampledWavelengths) -> (f32, bool) {
    let ctx = BsdfContext::importance();
    for u1 in u1_grid(64) {
        let mut wl2 = *wl;
        if let Some(s) = bsdf.sample(&ctx, a, u1, Vec2::splat(0.5), &mut wl2) {
            if s.flags.is_transmission() && s.eta.is_finite() && s.eta > 0.0 {
                return (s.eta, wl2.secondary_terminated() && !wl.secondary_terminated());
            }
        }
    }
    (1.0, false)
}

fn max_rel(a: SampledSpectrum, b: SampledSpectrum, slots: usize) -> f64 {
    (0..slots)
        .map(|i| rel_diff(a[i] as f64, b[i] as f64, TINY))
        .fold(0.0, |m, x| if x.is_nan() { f64::INFINITY } else { m.max(x) })
}

/// The reciprocity rows of `bsdf` (see the module docs).
pub fn reciprocity(bsdf: &dyn Bsdf, config: &CheckConfig) -> Vec<CheckResult> {
    let mut rng = config.rng(0x4ec1_9);
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
                    "{} f_imp(a,b)={:?} f_rad(b,a)={:?}",
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
                w_refl = (e, format!("{} f(a,b)={fab:?} f(b,a)={fba:?}", at()));
            }
        } else {
            n_tran += 1;
            let (eta, dispersive) = eta_across(bsdf, a, &wl);
            let slots = if dispersive { 1 } else { N_SPECTRUM_SAMPLES };
            let e = max_rel(fab * (eta * eta), fba, slots);
            if e > w_tran.0 {
                w_tran = (
                    e,
                    format!(
                        "{} e={eta} f(a,b)·e²={:?} f(b,a)={fba:?}",
                        at(),
                        fab * (eta * eta)
                    ),
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
fn normalized_throughput(s: &BsdfSample, mode: TransportMode) -> SampledSpectrum {
    let tau = s.weight * s.pdf;
    match mode {
        TransportMode::Radiance => tau * (s.eta * s.eta),
        TransportMode::Importance => tau,
    }
}

/// The `delta_reciprocity` row (see the module docs).
pub fn delta_reciprocity(bsdf: &dyn Bsdf, config: &CheckConfig) -> CheckResult {
    let mut rng = config.rng(0xde17a);
    let tol = 10.0 * config.rel_tol;
    let queries = (config.pairs / 20).max(50);
    let (mut worst, mut at) = (0.0f64, String::new());
    let (mut tested, mut unmatched) = (0usize, 0usize);
    for _ in 0..queries {
        let a = uniform_sphere(&mut rng);
        if a.z.abs() < GRAZING {
            continue;
        }
        let lambda = 360.0 + 470.0 * rng.next_f32();
        let wl = SampledWavelengths::fixed(lambda);
        let u2 = rng.next_vec2();
        for mode in [TransportMode::Radiance, TransportMode::Importance] {
            let ctx = BsdfContext {
                mode,
                ..BsdfContext::radiance()
            };
            for u1 in u1_grid(8) {
                let mut wl2 = wl;
                let Some(s) = bsdf.sample(&ctx, a, u1, u2, &mut wl2) else {
                    continue;
                };
                if !s.flags.is_delta() || s.wo.z.abs() < GRAZING {
                    continue;
                }
                tested += 1;
                let t_ab = normalized_throughput(&s, mode);
                // Adjoint: the importance-mode sample with the same numbers is the same event.
                if mode == TransportMode::Radiance {
                    let mut wl3 = wl;
                    let si = bsdf.sample(&BsdfContext::importance(), a, u1, u2, &mut wl3);
                    let e = match si {
                        Some(si) if (si.wo - s.wo).length() < 1e-3 && si.flags == s.flags => max_rel(
                            t_ab,
                            normalized_throughput(&si, TransportMode::Importance),
                            N_SPECTRUM_SAMPLES,
                        ),
                        _ => f64::INFINITY,
                    };
                    if e > worst {
                        worst = e;
                        at = format!(
                            "adjoint at a={a:.4} u1={u1} λ={lambda:.1}: radiance {s:?} importance {si:?}"
                        );
                    }
                }
                // Reverse event: from b = wo back to a.
                let b = s.wo;
                let mut found = None;
                for v1 in u1_grid(64) {
                    let mut wl3 = wl;
                    if let Some(r) = bsdf.sample(&ctx, b, v1, u2, &mut wl3) {
                        if r.flags.is_delta()
                            && (r.wo - a).length() < 1e-3
                            && r.flags.is_reflection() == s.flags.is_reflection()
                        {
                            found = Some(r);
                            break;
                        }
                    }
                }
                let e = match found {
                    Some(r) => max_rel(t_ab, normalized_throughput(&r, mode), N_SPECTRUM_SAMPLES),
                    None => {
                        unmatched += 1;
                        f64::INFINITY
                    }
                };
                if e > worst {
                    worst = e;
                    at = format!(
                        "{mode:?} a={a:.4} → b={b:.4} (u1={u1}, λ={lambda:.1}): τ̂(a→b)={t_ab:?}, back: {found:?}"
                    );
                }
            }
        }
    }
    CheckResult::compare(
        "delta_reciprocity",
        worst,
        Bound::AtMost,
        tol,
        format!(
            "max relative asymmetry of τ·e² (radiance) / τ (importance) over {tested} delta events, {unmatched} not invertible; worst {at}"
        ),
    )
}
