//! Helpers shared by `battery.rs`, `battery_hair.rs` (correct models) and `battery_broken.rs` (negative
//! controls): the family-wise α, the report, and the pass/fail assertions.
#![allow(dead_code)] // each test module uses its part

use gonio_core::Bsdf;
use gonio_core::check::{CheckConfig, CheckResult, all_passed, battery, failures, sidak};
use gonio_core::spectra::{Extrapolation, PiecewiseLinear, Spectrum};
use std::sync::Arc;
use std::time::Instant;

/// Upper bound on the battery runs on correct models in `battery.rs`, its `battery_stochastic`
/// and `battery_measured` modules and `battery_hair.rs` (Šidák family size): 57
/// `assert_passes`, 6 anisotropic and 6 stochastic runs, 2 direct `report`s and 3 quick ones
/// (`roughdielectric_default`); pplastic: 2 `assert_passes` and 1 anisotropic; hair: 3;
/// measured_polarized: 3.
pub const RUNS: usize = 83;

/// The battery's defaults with the family-wise α split over [`RUNS`], and the stratified
/// sampler's χ² histograms at a quarter of the independent sampler's 10⁶ samples (Mitsuba's
/// recipe uses the independent one alone; the stratified and Kronecker rows are our extra ones,
/// each a third of a battery's χ² work; sized for CI's time budget).
///
/// Not the Kronecker rows: at 1.25·10⁵ and 2.5·10⁵ points the R₃ sequence fails the hair
/// fibre's χ² at every incidence (p down to 10⁻³¹²), at 5·10⁵, 10⁶ and 2·10⁶ it passes with p ≈ 1
/// (more even than chance, as a low-discrepancy sequence should be), and the independent sampler
/// passes at all five sizes with p spread over (0.3, 0.99). The fibre picks its lobe with u₁ and
/// reuses the remainder, magnified by 1/P(lobe), for the azimuth: the points of a rank-1 lattice
/// that fall in a narrow interval of u₁ form a coarse lattice in the other two coordinates until
/// there are enough of them. A property of the sequence, not of the model.
pub fn config() -> CheckConfig {
    let mut config = CheckConfig {
        alpha: sidak(0.01, RUNS),
        ..CheckConfig::default()
    };
    config.chi2.stratified_samples = config.chi2.samples / 4;
    config
}

pub fn piecewise(pairs: &[f32]) -> Spectrum {
    Spectrum::PiecewiseLinear(Arc::new(
        PiecewiseLinear::from_interleaved(pairs, Extrapolation::Clamp).unwrap(),
    ))
}

/// Runs the battery, prints the report, returns the rows.
pub fn report(name: &str, bsdf: &dyn Bsdf) -> Vec<CheckResult> {
    let t = Instant::now();
    let rows = battery(bsdf, &config());
    eprintln!("== {name} ({:.2} s)", t.elapsed().as_secs_f64());
    for r in &rows {
        eprintln!("   {r}");
    }
    rows
}

pub fn assert_passes(name: &str, bsdf: &dyn Bsdf) -> Vec<CheckResult> {
    let rows = report(name, bsdf);
    assert!(all_passed(&rows), "{name} failed:\n{}", failures(&rows));
    // The battery must actually have tested something of each kind.
    for must in [
        "health",
        "energy",
        "albedo_estimators",
        "reciprocity",
        "adjoint",
        "isotropy",
    ] {
        assert!(rows.iter().any(|r| r.name == must), "{name}: no `{must}` row");
    }
    if bsdf.flags().has_smooth() {
        let chi2 = rows.iter().filter(|r| r.name == "chi2").count();
        assert!(chi2 >= 3, "{name}: only {chi2} chi2 rows");
    }
    if bsdf.flags().is_delta() {
        assert!(
            rows.iter().any(|r| r.name == "delta_reciprocity"),
            "{name}: no delta_reciprocity row"
        );
    }
    rows
}

/// The broken model must fail every row in `expected` (and the report names them).
pub fn assert_fails(name: &str, bsdf: &dyn Bsdf, expected: &[&str]) {
    let rows = report(name, bsdf);
    for e in expected {
        let matching: Vec<_> = rows.iter().filter(|r| r.name == *e).collect();
        assert!(!matching.is_empty(), "{name}: no `{e}` row");
        assert!(
            matching.iter().any(|r| !r.passed),
            "{name}: `{e}` did not fail:\n{matching:#?}"
        );
    }
}
