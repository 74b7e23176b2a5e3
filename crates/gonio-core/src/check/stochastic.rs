//! Checks for stochastic BSDFs, whose `pdf` is for MIS only ([`Bsdf::pdf_is_exact`] false: the
//! Heitz et al. 2016 random walks). Their `eval` is an unbiased random estimate (a deterministic
//! function of its arguments through a seeded generator) and their `sample` has an unknown
//! density but an exact weight, so the exact-identity rows (`chi2` against the pdf,
//! `weight_vs_eval`, `pdf_integral`, `pdf_normalization`, pointwise `reciprocity`, `isotropy`)
//! do not apply. In their place:
//!
//! * `sample_vs_eval` (one row per incidence of [`super::Chi2Config::incidences`]): the sphere is
//!   cut into 64 cells (8 in cos θ × 8 in φ: large cells, so that each holds many evaluations; the estimator has rare large values at grazing angles); per cell, the mean of weight·1(wo ∈ cell) over
//!   `sample` calls and the stratified integral of eval·|cos θo| over the cell estimate the same
//!   number, ∫_cell f |cos θo| dωo. Each cell gives z = (A − B)/√(σ²_A + σ²_B); cells the
//!   sampler reached fewer than [`MIN_HITS`] times, or where fewer evaluations than that were
//!   non-zero (the estimator's rare large values make a small-sample variance unreliable), are
//!   pooled into one. The figure is the p-value
//!   of Σ z² against χ²(number of cells), compared with the row's α. A wrong walk, a biased
//!   eval, or a sampler that misses part of the lobe fail here.
//! * `reciprocity`, `adjoint`, `eta2_law` in expectation: for a few fixed pairs (a, b), the mean
//!   of [`REPS`]-many evaluations at directions nudged by 10⁻⁵ (which reseeds the estimator and
//!   changes the expected value by a negligible amount) on both sides of each law; each pair's
//!   difference in standard errors, Šidák over the pairs and laws, as a statistical row.
//!
//! `sample_pdf_vs_pdf` and `eval_pdf` (identities MIS relies on) and the energy rows still apply.

use super::{Bound, CheckConfig, CheckResult, sidak, z_quantile};
use crate::bsdf::{Bsdf, BsdfContext};
use crate::rng::Pcg32;
use crate::spectrum::SampledWavelengths;
use glam::Vec3;
use std::f64::consts::TAU;

/// Cells in cos θ and φ.
const NZ: usize = 8;
const NPHI: usize = 8;
/// Cells with fewer sampled directions are pooled (their weight means are not yet normal).
pub const MIN_HITS: u64 = 30;
/// Evaluations per side of a law, per pair.
pub const REPS: usize = 1500;
/// Fixed pairs of the in-expectation reciprocity rows.
const PAIRS: usize = 6;

fn cell_of(w: Vec3) -> usize {
    let iz = (((w.z as f64 + 1.0) * 0.5 * NZ as f64) as usize).min(NZ - 1);
    let phi = (w.y as f64).atan2(w.x as f64).rem_euclid(TAU);
    let ip = ((phi / TAU * NPHI as f64) as usize).min(NPHI - 1);
    iz * NPHI + ip
}

/// The `sample_vs_eval` rows, each at level `alpha_row`.
pub fn sample_vs_eval(bsdf: &dyn Bsdf, config: &CheckConfig, alpha_row: f64) -> Vec<CheckResult> {
    let mut rows = Vec::new();
    let ctx = BsdfContext::radiance();
    let wl = SampledWavelengths::fixed(550.0);
    let cells = NZ * NPHI;
    for (k, wi) in config.chi2.incidences.iter().enumerate() {
        let wi = wi.normalize();
        let mut rng = config.rng(0x5a_e0a1 + k as u64);
        let n = config.sample_vs_eval_samples;
        // Sampled: Σ weight, Σ weight², count per cell.
        let mut sam = vec![(0.0f64, 0.0f64, 0u64); cells];
        for _ in 0..n {
            let mut w = wl;
            let Some(s) = bsdf.sample(&ctx, wi, rng.next_f32(), rng.next_vec2(), &mut w) else {
                continue;
            };
            if s.flags.is_delta() {
                continue;
            }
            let v = s.weight[0] as f64;
            let c = &mut sam[cell_of(s.wo)];
            c.0 += v;
            c.1 += v * v;
            c.2 += 1;
        }
        // Evaluated: Σ v, Σ v² of eval·|cos θo|·area at area-uniform points of each cell.
        let m = config.sample_vs_eval_evals_per_cell;
        let area = (2.0 / NZ as f64) * (TAU / NPHI as f64);
        let mut ev = vec![(0.0f64, 0.0f64); cells];
        for (c, e) in ev.iter_mut().enumerate() {
            let (iz, ip) = (c / NPHI, c % NPHI);
            for _ in 0..m {
                let z = -1.0 + (iz as f64 + rng.next_f64()) * 2.0 / NZ as f64;
                let phi = (ip as f64 + rng.next_f64()) * TAU / NPHI as f64;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let wo = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                let v = bsdf.eval(&ctx, wi, wo, &wl)[0] as f64 * (wo.z as f64).abs() * area;
                e.0 += v;
                e.1 += v * v;
            }
        }
        let (nf, mf) = (n as f64, m as f64);
        // Kish's effective sample size (Σv)²/Σv²: small when a few values dominate.
        let ess = |s1: f64, s2: f64| if s2 > 0.0 { s1 * s1 / s2 } else { 0.0 };
        let (mut stat, mut dof, mut worst) = (0.0f64, 0usize, (0.0f64, String::new()));
        let mut compare = |sa: (f64, f64), se: (f64, f64, f64), at: String| {
            // sa: (Σ weight, Σ weight²) over n samples; se: (Σ v, Σ v², count) of evaluations.
            let a = sa.0 / nf;
            let va = (sa.1 / nf - a * a).max(0.0) / nf;
            let b = se.0 / se.2;
            let vb = (se.1 / se.2 - b * b).max(0.0) / se.2;
            if !(a > 0.0 || b > 0.0) {
                return;
            }
            let var = va + vb;
            let z2 = if var > 0.0 {
                (a - b) * (a - b) / var
            } else if (a - b).abs() < 1e-9 {
                0.0
            } else {
                f64::INFINITY
            };
            stat += z2;
            dof += 1;
            if z2 > worst.0 || z2.is_nan() {
                worst = (
                    z2,
                    format!(
                        "{at}: sampled {a:.5e}±{:.1e} vs eval {b:.5e}±{:.1e}",
                        va.sqrt(),
                        vb.sqrt()
                    ),
                );
            }
        };
        let mut pool_s = (0.0f64, 0.0f64, 0u64);
        let mut pool_e = (0.0f64, 0.0f64, 0.0f64);
        for c in 0..cells {
            let (s, e) = (sam[c], ev[c]);
            if s.2 >= MIN_HITS && (e.0 == 0.0 || ess(e.0, e.1) >= MIN_HITS as f64) {
                compare((s.0, s.1), (e.0, e.1, mf), format!("cell {c}"));
            } else {
                pool_s = (pool_s.0 + s.0, pool_s.1 + s.1, pool_s.2 + s.2);
                // Pooled cells add their integrals: Σ over cells of m evaluations each.
                pool_e = (pool_e.0 + e.0, pool_e.1 + e.1, pool_e.2 + 1.0);
            }
        }
        let mut skipped = String::new();
        if pool_e.2 > 0.0 {
            // The pooled integral is the sum of the cells' means: m evaluations of Σ_cells v.
            let pool_ess = ess(pool_e.0, pool_e.1);
            if pool_e.0 == 0.0 || pool_ess >= MIN_HITS as f64 {
                let k = pool_e.2;
                // Each evaluation of the pooled integral is k·(one cell's value) on average:
                // mean Σ_c mean_c = (Σ v)/m; its variance Σ_c var_c/m ≈ k·(Σv²/(k·m) − mean²/k²)/m.
                let mean = pool_e.0 / mf;
                let var_each = (pool_e.1 / mf - mean * mean / k).max(0.0);
                compare(
                    (pool_s.0, pool_s.1),
                    (mean * mf, (var_each + mean * mean) * mf, mf),
                    format!("pooled ({} cells, {} hits)", k, pool_s.2),
                );
            } else {
                skipped = format!(
                    "; {} pooled cells not compared (eval's effective count {pool_ess:.1}: sampled {:.3e}, eval {:.3e})",
                    pool_e.2,
                    pool_s.0 / nf,
                    pool_e.0 / mf
                );
            }
        }
        // No cell where either estimate is positive: both agree on a black configuration.
        let p = if dof == 0 {
            1.0
        } else {
            super::chi2::chi2_sf(dof as f64, stat)
        };
        rows.push(CheckResult::compare(
            "sample_vs_eval",
            p,
            Bound::AtLeast,
            alpha_row,
            format!(
                "wi={wi:.3}: Σz² = {stat:.1} over {dof} cells ({n} samples, {m} evals per cell); worst z² {:.2} at {}{skipped}",
                worst.0, worst.1
            ),
        ));
    }
    rows
}

/// Mean and standard error of channel 0 of `eval(ctx, a', b')` over `REPS` nudged copies.
fn mean_eval(
    bsdf: &dyn Bsdf,
    ctx: &BsdfContext,
    a: Vec3,
    b: Vec3,
    wl: &SampledWavelengths,
    rng: &mut Pcg32,
) -> (f64, f64) {
    let (mut s1, mut s2) = (0.0f64, 0.0f64);
    let nudge =
        |w: Vec3, rng: &mut Pcg32| (w + 1e-5 * (rng.next_vec2().extend(rng.next_f32()) - 0.5)).normalize();
    for _ in 0..REPS {
        let v = bsdf.eval(ctx, nudge(a, rng), nudge(b, rng), wl)[0] as f64;
        s1 += v;
        s2 += v * v;
    }
    let m = s1 / REPS as f64;
    (m, ((s2 / REPS as f64 - m * m).max(0.0) / REPS as f64).sqrt())
}

/// The in-expectation `reciprocity`, `adjoint` and (for models that transmit) `eta2_law` rows at
/// family level `alpha_row` (Šidák over pairs within each row).
pub fn reciprocity_in_expectation(bsdf: &dyn Bsdf, config: &CheckConfig, alpha_row: f64) -> Vec<CheckResult> {
    let mut rng = config.rng(0x5e_c1b0);
    let (rad, imp) = (BsdfContext::radiance(), BsdfContext::importance());
    let wl = SampledWavelengths::fixed(550.0);
    let k = z_quantile(sidak(alpha_row, PAIRS));
    let dirs = |t: f32, p: f32, s: f32| super::direction(t, p, s);
    let same = [
        (dirs(75.0, 0.0, 1.0), dirs(20.0, 160.0, 1.0)),
        (dirs(60.0, 30.0, 1.0), dirs(45.0, 250.0, 1.0)),
        (dirs(85.0, 10.0, 1.0), dirs(70.0, 180.0, 1.0)),
        (dirs(30.0, 0.0, -1.0), dirs(65.0, 120.0, -1.0)),
        (dirs(10.0, 90.0, 1.0), dirs(50.0, 300.0, 1.0)),
        (dirs(80.0, 200.0, -1.0), dirs(40.0, 20.0, -1.0)),
    ];
    let mut rows = Vec::new();
    let mut law = |name: &'static str,
                   pairs: &[(Vec3, Vec3)],
                   ab: &dyn Fn(Vec3, Vec3, &mut Pcg32) -> (f64, f64),
                   ba: &dyn Fn(Vec3, Vec3, &mut Pcg32) -> (f64, f64),
                   rng: &mut Pcg32| {
        let (mut worst, mut at, mut used) = (0.0f64, String::new(), 0usize);
        for &(a, b) in pairs {
            let (x, sx) = ab(a, b, rng);
            let (y, sy) = ba(a, b, rng);
            if x == 0.0 && y == 0.0 {
                continue;
            }
            used += 1;
            let se = (sx * sx + sy * sy).sqrt();
            let z = if se > 0.0 {
                (x - y).abs() / se
            } else if x == y {
                0.0
            } else {
                f64::INFINITY
            };
            if z > worst || z.is_nan() {
                worst = z;
                at = format!("a={a:.3} b={b:.3}: {x:.5e}±{sx:.1e} vs {y:.5e}±{sy:.1e}");
            }
        }
        rows.push(CheckResult::compare(
            name,
            worst,
            Bound::AtMost,
            k,
            format!(
                "in expectation ({REPS} reseeded evals per side) over {used} pairs, max |Δ|/σ; worst {at}"
            ),
        ));
    };
    let f = |ctx: BsdfContext| move |a: Vec3, b: Vec3, rng: &mut Pcg32| mean_eval(bsdf, &ctx, a, b, &wl, rng);
    law(
        "reciprocity",
        &same,
        &f(rad),
        &|a, b, rng| mean_eval(bsdf, &rad, b, a, &wl, rng),
        &mut rng,
    );
    law(
        "adjoint",
        &same,
        &f(imp),
        &|a, b, rng| mean_eval(bsdf, &rad, b, a, &wl, rng),
        &mut rng,
    );
    if bsdf.flags().is_transmission() {
        let across: Vec<(Vec3, Vec3)> = same.iter().map(|&(a, b)| (a, -b)).collect();
        let (eta, _) = super::reciprocity::eta_across(bsdf, across[0].0, &wl);
        // Which side is a's changes per pair; e = η_b/η_a from the first pair's side.
        let e_of = |a: Vec3| if a.z * across[0].0.z > 0.0 { eta } else { 1.0 / eta };
        law(
            "eta2_law",
            &across,
            &|a, b, rng| {
                let (m, s) = mean_eval(bsdf, &rad, a, b, &wl, rng);
                let e2 = (e_of(a) * e_of(a)) as f64;
                (m * e2, s * e2)
            },
            &|a, b, rng| mean_eval(bsdf, &rad, b, a, &wl, rng),
            &mut rng,
        );
    }
    rows
}
