//! The property checks every BSDF must pass, shared by the test suite and by `gonio check`
//! ("one implementation"): each check returns [`CheckResult`] rows instead of panicking, and
//! [`battery`] runs every check that applies to a model.
//!
//! | row | measures | module | source |
//! |---|---|---|---|
//! | `chi2` | histogram of `sample` vs the integral of `pdf` (p-value) | [`chi2`] | Mitsuba 3 `chi2.py`, pbrt-v4 `bsdfs_test.cpp` |
//! | `weight_vs_eval` | weight = f·\|cos θo\|/pdf at sampled directions | [`consistency`] | Mitsuba 3 `test_twosided.py`, `test_blendbsdf.py` |
//! | `sample_pdf_vs_pdf` | the pdf `sample` reports = `pdf(wo)` | [`consistency`] | Mitsuba 3 `test_twosided.py` |
//! | `eval_pdf` | `eval_pdf` = (`eval`, `pdf`) | [`consistency`] | Mitsuba `test_eval_pdf` |
//! | `pdf_integral` | ∫ pdf dω ≤ 1 | [`consistency`] | Mitsuba 3 `chi2.py` sanity check |
//! | `pdf_normalization` | ∫ pdf dω = probability that `sample` returns a smooth lobe | [`consistency`] | (ours) |
//! | `energy` | directional albedo R + T ≤ 1 in importance mode | [`energy`] | pbrt-v4 energy test (`bsdfs_test.cpp`) |
//! | `albedo_estimators` | mean sample weight = uniform-sphere integral of f·\|cos\| | [`energy`] | (ours) |
//! | `reciprocity`, `eta2_law`, `adjoint`, `delta_reciprocity` | f(a,b) = f(b,a); f(a,b)/η_a² = f(b,a)/η_b²; f_imp(a,b) = f_rad(b,a) | [`reciprocity`] | Veach 1997, §5.2 |
//! | `isotropy` | f under a common rotation about the normal | [`isotropy`] | lecture slide "BRDF properties" |
//! | `mueller_physical` | `eval_mueller` and `sample_mueller` map physical Stokes vectors to physical ones (\|S1..S3\| ≤ S0) | [`polarization`] | (ours; Chipman et al., *Polarized Light and Optical Systems*, ch. 6) |
//! | `health`, `lobe_flags` | no NaN/Inf/negative values, grazing included; flags match sides | [`health`] | (ours) |
//! | `sample_vs_eval`, in-expectation `reciprocity`/`adjoint`/`eta2_law` | for stochastic models whose pdf is for MIS only ([`Bsdf::pdf_is_exact`]): weighted sample histogram = cell integrals of eval·\|cos\|; laws on means of reseeded evals | [`stochastic`] | (ours; Heitz et al. 2016 validate eval against sample the same way) |
//!
//! # Thresholds
//!
//! Two kinds, never tuned to make a model pass:
//! * **statistical** rows (χ², pdf integrals, albedos) share a family-wise false-alarm rate
//!   α = [`CheckConfig::alpha`] (0.01), split with the Šidák correction α′ = 1 − (1 − α)^(1/m)
//!   over the m statistical rows, and again over the comparisons inside a row; Monte Carlo means
//!   are compared at k standard errors with k the normal quantile of that α′ ([`z_quantile`]).
//! * **identities** (weight = f·cos/pdf, reciprocity, isotropy) are exact in real arithmetic;
//!   they are compared with a relative tolerance [`CheckConfig::rel_tol`] that only absorbs `f32`
//!   rounding (1e-4 = ~1000 ulps).
//!
//! Deliberately broken models, kept to prove that each row can fail, are in `broken`, compiled
//! only with the `test-support` feature (the crate's tests enable it through a dev-dependency
//! on the crate itself).

#[cfg(feature = "test-support")]
pub mod broken;
pub mod chi2;
pub mod consistency;
pub mod energy;
pub mod health;
pub mod isotropy;
pub mod polarization;
pub mod reciprocity;
pub mod stochastic;

use crate::bsdf::Bsdf;
use crate::rng::Pcg32;
use crate::spectrum::SampledWavelengths;
use glam::Vec3;
use serde::{Serialize, Serializer};
use std::fmt;

/// How a row's figure is compared with its threshold (serialized as `"at_most"`, `"at_least"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Bound {
    /// Passes when `figure <= threshold` (errors, asymmetries, albedos, counts).
    AtMost,
    /// Passes when `figure >= threshold` (p-values).
    AtLeast,
}

/// One row of a check report: a measured figure, its threshold and the verdict. Serializes (for
/// `gonio check --json`) to `{"name", "figure", "threshold", "bound", "passed", "detail"}`,
/// non-finite figures as strings ("NaN", "inf"), since JSON has no such numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CheckResult {
    /// Which check (`chi2`, `energy`, ...; see the module table).
    pub name: &'static str,
    /// The measured figure (p-value, max relative error, max albedo, number of bad values).
    #[serde(serialize_with = "number_or_string")]
    pub figure: f64,
    /// The threshold the figure is compared with.
    #[serde(serialize_with = "number_or_string")]
    pub threshold: f64,
    /// Direction of the comparison.
    pub bound: Bound,
    /// The verdict. A non-finite figure always fails.
    pub passed: bool,
    /// Configuration and supporting numbers, human-readable.
    pub detail: String,
}

impl CheckResult {
    /// A row whose verdict is the comparison of `figure` with `threshold`.
    pub fn compare(name: &'static str, figure: f64, bound: Bound, threshold: f64, detail: String) -> Self {
        let passed = figure.is_finite()
            && match bound {
                Bound::AtMost => figure <= threshold,
                Bound::AtLeast => figure >= threshold,
            };
        Self {
            name,
            figure,
            threshold,
            bound,
            passed,
            detail,
        }
    }

    /// A row with an explicit verdict (when the pass rule is not a single comparison, e.g. "every
    /// incidence angle within its own k·σ"); `figure` and `threshold` describe the worst case.
    pub fn with_verdict(
        name: &'static str,
        figure: f64,
        bound: Bound,
        threshold: f64,
        passed: bool,
        detail: String,
    ) -> Self {
        Self {
            name,
            figure,
            threshold,
            bound,
            passed: passed && !figure.is_nan(),
            detail,
        }
    }
}

/// A finite number as a JSON number, NaN and ±∞ as the strings "NaN", "inf", "-inf".
fn number_or_string<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_f64(*x)
    } else {
        s.serialize_str(&x.to_string())
    }
}

impl CheckResult {
    /// The row as one compact JSON object (see [`CheckResult`] for the fields).
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("a check row always serializes (string keys only)")
    }
}

impl fmt::Display for CheckResult {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let op = match self.bound {
            Bound::AtMost => "<=",
            Bound::AtLeast => ">=",
        };
        write!(
            f,
            "{:<4} {:<18} {:>12.6e} {op} {:<12.6e} {}",
            if self.passed { "ok" } else { "FAIL" },
            self.name,
            self.figure,
            self.threshold,
            self.detail
        )
    }
}

/// Which uniform points drive `sample` in the χ² test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    /// Independent PCG32 uniforms for u1 and u2.
    Independent,
    /// u2 on a jittered √N × √N grid ([`crate::rng::Stratified2D`]), u1 jittered 1-D strata in
    /// random order (Latin-hypercube padding).
    Stratified,
    /// (u1, u2) from Roberts' R₃ sequence with a random shift ([`crate::rng::Kronecker`]).
    Kronecker,
}

impl fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SamplerKind::Independent => "independent",
            SamplerKind::Stratified => "stratified",
            SamplerKind::Kronecker => "kronecker-R3",
        })
    }
}

/// Settings of the χ² test (defaults: Mitsuba 3's recipe, `src/python/python/chi2.py`).
#[derive(Clone, Debug, PartialEq)]
pub struct Chi2Config {
    /// Number of `sample` calls per configuration with the independent sampler (10⁶).
    pub samples: usize,
    /// Number of `sample` calls per configuration with the stratified sampler (10⁶; rounded
    /// down to a square). Its histograms test the same distribution from jittered inputs (a
    /// warp that reuses or rescales its random numbers badly shows there); the test suite sizes
    /// them at a quarter of `samples`. The Kronecker sampler takes `samples`.
    pub stratified_samples: usize,
    /// cos θ bins; φ gets `res / 2` (101 → 50 × 101 cells; odd keeps a bin edge off the horizon).
    pub res: usize,
    /// Quadrature nodes per cell and axis for the expected counts (odd, composite Simpson; 5).
    pub ires: usize,
    /// Adaptive quadrature: at most this many quadrant subdivisions of a cell (3).
    pub max_depth: usize,
    /// Adaptive quadrature: a cell of E expected samples is integrated to `rel_tol`·√E samples,
    /// so quadrature error adds at most `rel_tol`² to its χ² term (0.05: ≤ 0.0025 per cell,
    /// ≤ 6 over 2500 cells, against the statistic's standard deviation √(2·dof) ≈ 70).
    pub rel_tol: f64,
    /// Query directions `wi` (normalized on use).
    pub incidences: Vec<Vec3>,
    /// Samplers; every incidence is tested with every sampler.
    pub samplers: Vec<SamplerKind>,
    /// Also test each incidence with delta lobes masked out of the context (models that have
    /// both delta and smooth lobes), not only with delta samples skipped.
    pub masked_context: bool,
}

impl Default for Chi2Config {
    fn default() -> Self {
        Self {
            samples: 1_000_000,
            stratified_samples: 1_000_000,
            res: 101,
            ires: 5,
            max_depth: 3,
            rel_tol: 0.05,
            incidences: vec![
                Vec3::Z,
                Vec3::new(0.5, 0.3, 0.8),
                Vec3::new(0.8, 0.3, 0.05),  // grazing (Mitsuba roughdielectric test)
                Vec3::new(0.2, -0.6, -0.5), // from below / inside
            ],
            samplers: vec![
                SamplerKind::Independent,
                SamplerKind::Stratified,
                SamplerKind::Kronecker,
            ],
            masked_context: true,
        }
    }
}

/// Settings of [`battery`]. Sample counts are sized so one model's battery takes about a second
/// in release mode on one core.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckConfig {
    /// Seed of every random stream (each check uses its own stream).
    pub seed: u64,
    /// Family-wise false-alarm rate of the statistical rows (0.01), Šidák-split.
    pub alpha: f64,
    /// Relative tolerance of exact identities (`f32` rounding only): 1e-4.
    pub rel_tol: f64,
    /// χ² settings.
    pub chi2: Chi2Config,
    /// Samples for weight/pdf consistency.
    pub consistency_samples: usize,
    /// Query directions for the pdf integral, and uniform directions per query.
    pub pdf_integral_queries: usize,
    /// Uniform-sphere directions per query of the pdf integral.
    pub pdf_integral_samples: usize,
    /// Samples per (angle, side, wavelength, mode) albedo estimate.
    pub energy_samples: usize,
    /// Incidence angles of the energy check, degrees from the normal (both sides are tested).
    pub energy_angles_deg: Vec<f32>,
    /// Wavelengths of the energy check, nm.
    pub energy_wavelengths: Vec<f32>,
    /// Random direction pairs for reciprocity and isotropy.
    pub pairs: usize,
    /// Random queries of the health check (plus a fixed set of grazing and degenerate ones).
    pub health_queries: usize,
    /// `sample` calls per incidence of [`stochastic::sample_vs_eval`] (stochastic models).
    pub sample_vs_eval_samples: usize,
    /// `eval` calls per cell of [`stochastic::sample_vs_eval`].
    pub sample_vs_eval_evals_per_cell: usize,
}

impl Default for CheckConfig {
    fn default() -> Self {
        Self {
            seed: 0,
            alpha: 0.01,
            rel_tol: 1e-4,
            chi2: Chi2Config::default(),
            consistency_samples: 100_000,
            pdf_integral_queries: 8,
            pdf_integral_samples: 200_000,
            energy_samples: 32_768,
            energy_angles_deg: vec![0.0, 30.0, 60.0, 80.0, 89.0],
            energy_wavelengths: vec![400.0, 550.0, 700.0],
            pairs: 20_000,
            health_queries: 20_000,
            sample_vs_eval_samples: 200_000,
            sample_vs_eval_evals_per_cell: 512,
        }
    }
}

impl CheckConfig {
    /// A cheaper configuration (10× fewer samples, independent sampler only) for interactive use.
    pub fn quick() -> Self {
        let mut c = Self::default();
        c.chi2.samples = 100_000;
        c.chi2.stratified_samples = 100_000;
        c.chi2.samplers = vec![SamplerKind::Independent];
        c.consistency_samples /= 10;
        c.pdf_integral_samples /= 10;
        c.energy_samples /= 10;
        c.pairs /= 10;
        c.health_queries /= 10;
        c.sample_vs_eval_samples /= 10;
        c.sample_vs_eval_evals_per_cell /= 4;
        c
    }

    /// The random stream of one check (`stream` distinguishes checks and configurations).
    pub fn rng(&self, stream: u64) -> Pcg32 {
        Pcg32::new(self.seed, stream)
    }
}

/// Šidák's per-test level: m independent tests at α′ each have family-wise rate α.
pub fn sidak(alpha: f64, m: usize) -> f64 {
    if m <= 1 {
        return alpha;
    }
    // 1 − (1 − α)^(1/m), computed without cancellation.
    -((-alpha).ln_1p() / m as f64).exp_m1()
}

/// The standard normal quantile z with P(|Z| > z) = α (two-sided), via the inverse error
/// function: z = √2 · erf⁻¹(1 − α).
pub fn z_quantile(alpha: f64) -> f64 {
    std::f64::consts::SQRT_2 * puruspe::inverf(1.0 - alpha)
}

/// |a − b| / max(|a|, |b|), 0 when both are below `floor` in magnitude (rounding noise of tiny
/// values is not an asymmetry).
pub fn rel_diff(a: f64, b: f64, floor: f64) -> f64 {
    let m = a.abs().max(b.abs());
    if m <= floor { 0.0 } else { (a - b).abs() / m }
}

/// A uniformly distributed unit vector.
pub fn uniform_sphere(rng: &mut Pcg32) -> Vec3 {
    crate::warp::square_to_uniform_sphere(rng.next_vec2())
}

/// Wavelengths drawn like a path's (hero from the visible pdf, three rotated).
pub fn random_wavelengths(rng: &mut Pcg32) -> SampledWavelengths {
    SampledWavelengths::sample_visible(rng.next_f32())
}

/// A direction `theta_deg` from the normal, azimuth `phi_deg`, on the side of `sign` (±1).
pub fn direction(theta_deg: f32, phi_deg: f32, sign: f32) -> Vec3 {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    Vec3::new(st * cp, st * sp, sign * ct)
}

/// Runs every check that applies to `bsdf` (by its [`Bsdf::flags`]): χ² and the pdf checks
/// only for models with a smooth lobe, the delta-lobe reciprocity only for models with a delta
/// lobe. Rows of one statistical family share the Šidák-corrected α of `config`.
///
/// A model whose pdf is for MIS only ([`Bsdf::pdf_is_exact`] false) gets the [`stochastic`] rows
/// in place of `chi2`, `weight_vs_eval`, `pdf_integral`, `pdf_normalization`, the pointwise
/// reciprocity rows and `isotropy` (exact identities its random `eval` does not satisfy).
pub fn battery(bsdf: &dyn Bsdf, config: &CheckConfig) -> Vec<CheckResult> {
    if !bsdf.pdf_is_exact() {
        return stochastic_battery(bsdf, config);
    }
    let flags = bsdf.flags();
    let chi2_plan = chi2::plan(bsdf, config);
    // Statistical rows: the χ² configurations, pdf_integral, pdf_normalization, energy,
    // albedo_estimators.
    let n_stat = chi2_plan.len() + if flags.has_smooth() { 4 } else { 2 };
    let alpha_row = sidak(config.alpha, n_stat);

    let mut rows = Vec::new();
    rows.extend(health::health(bsdf, config));
    if flags.has_smooth() {
        rows.extend(chi2::run_plan(bsdf, config, &chi2_plan, alpha_row));
        rows.extend(consistency::consistency(bsdf, config));
        rows.extend(consistency::pdf_integral(bsdf, config, alpha_row));
    }
    rows.extend(energy::energy(bsdf, config, alpha_row));
    rows.extend(reciprocity::reciprocity(bsdf, config));
    rows.push(isotropy::isotropy(bsdf, config));
    rows.push(polarization::mueller_physical(bsdf, config));
    rows
}

/// [`battery`] for a model whose pdf is for MIS only.
fn stochastic_battery(bsdf: &dyn Bsdf, config: &CheckConfig) -> Vec<CheckResult> {
    let n_inc = config.chi2.incidences.len();
    // Statistical rows: sample_vs_eval per incidence, energy, albedo_estimators, and the three
    // in-expectation laws.
    let alpha_row = sidak(config.alpha, n_inc + 5);
    let mut rows = Vec::new();
    rows.extend(health::health(bsdf, config));
    rows.extend(stochastic::sample_vs_eval(bsdf, config, alpha_row));
    rows.extend(
        consistency::consistency(bsdf, config)
            .into_iter()
            .filter(|r| r.name != "weight_vs_eval"),
    );
    rows.extend(energy::energy(bsdf, config, alpha_row));
    rows.extend(stochastic::reciprocity_in_expectation(bsdf, config, alpha_row));
    rows.push(polarization::mueller_physical(bsdf, config));
    rows
}

/// One row per check name, in first-appearance order: the worst figure (smallest p-value, largest
/// error), passed only if every row of that name passed, the worst row's detail prefixed with the
/// number of rows merged. For a compact `gonio check` report of the several χ² configurations.
pub fn summarize(rows: &[CheckResult]) -> Vec<CheckResult> {
    let mut out: Vec<(CheckResult, usize, bool)> = Vec::new();
    for r in rows {
        match out.iter_mut().find(|(o, _, _)| o.name == r.name) {
            None => out.push((r.clone(), 1, r.passed)),
            Some((worst, n, all)) => {
                *n += 1;
                *all &= r.passed;
                // NaN counts as worst.
                let worse = r.figure.is_nan()
                    || match r.bound {
                        Bound::AtMost => r.figure > worst.figure,
                        Bound::AtLeast => r.figure < worst.figure,
                    };
                if worse || (!r.passed && worst.passed) {
                    *worst = r.clone();
                }
            }
        }
    }
    out.into_iter()
        .map(|(mut r, n, all)| {
            r.passed = all;
            if n > 1 {
                r.detail = format!("worst of {n}: {}", r.detail);
            }
            r
        })
        .collect()
}

/// True when every row passed.
pub fn all_passed(rows: &[CheckResult]) -> bool {
    rows.iter().all(|r| r.passed)
}

/// The rows that failed, one per line, for assertion messages.
pub fn failures(rows: &[CheckResult]) -> String {
    rows.iter()
        .filter(|r| !r.passed)
        .map(|r| format!("{r}\n"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sidak_and_quantiles() {
        // pbrt-v4 src/pbrt/bsdfs_test.cpp: CHI2_RUNS = 5 at CHI2_SLEVEL = 0.01 → 0.0020080.
        assert!((sidak(0.01, 5) - 0.002008).abs() < 1e-6);
        assert_eq!(sidak(0.01, 1), 0.01);
        // Normal quantiles: two-sided 5 % → 1.959964, 1 % → 2.575829.
        assert!((z_quantile(0.05) - 1.959_964).abs() < 1e-5);
        assert!((z_quantile(0.01) - 2.575_829).abs() < 1e-5);
    }

    #[test]
    fn json_rows_are_escaped() {
        let r = CheckResult::compare("chi2", 0.25, Bound::AtLeast, 0.01, "a \"q\" \\ b\nc".into());
        assert_eq!(
            r.to_json(),
            r#"{"name":"chi2","figure":0.25,"threshold":0.01,"bound":"at_least","passed":true,"detail":"a \"q\" \\ b\nc"}"#
        );
        let r = CheckResult::compare("x", f64::NAN, Bound::AtMost, 0.0, String::new());
        assert!(r.to_json().contains(r#""figure":"NaN""#) && r.to_json().contains(r#""passed":false"#));
    }

    #[test]
    fn summary_keeps_the_worst_row_per_check() {
        let rows = vec![
            CheckResult::compare("chi2", 0.5, Bound::AtLeast, 0.01, "a".into()),
            CheckResult::compare("energy", 0.9, Bound::AtMost, 1.0, "e".into()),
            CheckResult::compare("chi2", 0.001, Bound::AtLeast, 0.01, "b".into()),
            CheckResult::compare("chi2", 0.2, Bound::AtLeast, 0.01, "c".into()),
        ];
        let s = summarize(&rows);
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].name, s[0].figure, s[0].passed), ("chi2", 0.001, false));
        assert_eq!(s[0].detail, "worst of 3: b");
        assert_eq!((s[1].name, s[1].passed), ("energy", true));
    }

    #[test]
    fn rows_compare_and_reject_nan() {
        assert!(CheckResult::compare("x", 0.5, Bound::AtMost, 1.0, String::new()).passed);
        assert!(!CheckResult::compare("x", 1.5, Bound::AtMost, 1.0, String::new()).passed);
        assert!(CheckResult::compare("x", 0.5, Bound::AtLeast, 0.01, String::new()).passed);
        assert!(!CheckResult::compare("x", f64::NAN, Bound::AtMost, 1.0, String::new()).passed);
        assert!(!CheckResult::compare("x", f64::NAN, Bound::AtLeast, 0.0, String::new()).passed);
    }
}
