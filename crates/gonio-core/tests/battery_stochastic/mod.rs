//! Battery runs of the stochastic models (Heitz et al. 2016 random walks: `roughdiffuse
//! model="microfacet"`, `multiple_scattering` on `roughconductor` and `roughdielectric`), whose
//! `pdf` is for MIS weights only: they pass the battery's stochastic rows instead of the
//! exact-density ones. Part of the `battery` test binary (its Šidák family, `RUNS`).

use super::*;

#[test]
fn roughdiffuse_microfacet_ggx_stochastic() {
    // Heitz et al. 2016 Lambertian microfacets: walk sampling, stochastic eval, MIS-only pdf.
    let rho = piecewise(&[400.0, 0.2, 550.0, 0.9, 700.0, 0.5]);
    let m = RoughDiffuse::new(rho, 0.8, RoughDiffuseModel::Microfacet(MicrofacetKind::Ggx));
    assert_passes_stochastic("roughdiffuse microfacet ggx α=0.8 spectral ρ", &m, 1024);
}

// ---- roughconductor / roughdielectric with multiple scattering (pdf for MIS only) -----------

/// A stochastic model (Heitz et al. 2016 walk) passes the battery's stochastic rows: the
/// weighted sample histogram against eval's cell integrals at every incidence, the MIS
/// identities, energy, and the laws in expectation.
fn assert_passes_stochastic(name: &str, bsdf: &dyn Bsdf, evals_per_cell: usize) {
    assert!(!bsdf.pdf_is_exact(), "{name}: flagged exact");
    // Each call is a random walk (two for eval): fewer samples than the exact models' runs,
    // sized to a few seconds per model; the thresholds follow from the standard errors.
    let config = CheckConfig {
        consistency_samples: 20_000,
        energy_samples: 8_192,
        energy_wavelengths: vec![450.0, 650.0],
        health_queries: 5_000,
        sample_vs_eval_samples: 100_000,
        sample_vs_eval_evals_per_cell: evals_per_cell,
        ..crate::battery_support::config()
    };
    let t = std::time::Instant::now();
    let rows = gonio_core::check::battery(bsdf, &config);
    eprintln!("== {name} ({:.2} s)", t.elapsed().as_secs_f64());
    for r in &rows {
        eprintln!("   {r}");
    }
    assert!(all_passed(&rows), "{name} failed:\n{}", failures(&rows));
    let n = rows.iter().filter(|r| r.name == "sample_vs_eval").count();
    assert!(n >= 3, "{name}: only {n} sample_vs_eval rows");
    for must in [
        "health",
        "sample_pdf_vs_pdf",
        "eval_pdf",
        "energy",
        "albedo_estimators",
        "reciprocity",
        "adjoint",
    ] {
        assert!(rows.iter().any(|r| r.name == must), "{name}: no `{must}` row");
    }
    for never in ["chi2", "weight_vs_eval", "pdf_integral", "pdf_normalization"] {
        assert!(
            !rows.iter().any(|r| r.name == never),
            "{name}: exact-pdf row `{never}`"
        );
    }
}

fn ms_conductor(kind: MicrofacetKind, au: f32, av: f32, eta: Spectrum, k: Spectrum) -> RoughConductor {
    let mut c = RoughConductor::new(eta, k, MicrofacetDistribution::new(kind, au, av, true));
    c.multiple_scattering = true;
    c
}

#[test]
fn roughconductor_ms_ggx_white() {
    let c = ms_conductor(
        MicrofacetKind::Ggx,
        0.7,
        0.7,
        Spectrum::Constant(0.0),
        Spectrum::Constant(1.0),
    );
    assert_passes_stochastic("roughconductor multiple_scattering ggx α=0.7 white", &c, 256);
}

#[test]
fn roughconductor_ms_beckmann_gold_like() {
    let eta = piecewise(&[400.0, 1.46, 500.0, 0.97, 600.0, 0.25, 700.0, 0.16]);
    let k = piecewise(&[400.0, 1.95, 500.0, 1.87, 600.0, 2.98, 700.0, 3.95]);
    let c = ms_conductor(MicrofacetKind::Beckmann, 0.5, 0.5, eta, k);
    assert_passes_stochastic(
        "roughconductor multiple_scattering beckmann α=0.5 Au-like",
        &c,
        256,
    );
}

#[test]
fn roughconductor_ms_ggx_anisotropic() {
    let c = ms_conductor(
        MicrofacetKind::Ggx,
        0.9,
        0.3,
        Spectrum::Constant(0.2),
        Spectrum::Constant(3.9),
    );
    assert_passes_stochastic("roughconductor multiple_scattering ggx α=(0.9, 0.3)", &c, 256);
}

#[test]
fn roughconductor_ms_beckmann_anisotropic() {
    let c = ms_conductor(
        MicrofacetKind::Beckmann,
        0.3,
        0.8,
        Spectrum::Constant(0.0),
        Spectrum::Constant(1.0),
    );
    assert_passes_stochastic(
        "roughconductor multiple_scattering beckmann α=(0.3, 0.8) white",
        &c,
        256,
    );
}

#[test]
fn roughdielectric_ms_ggx() {
    // Both sides: the battery's incidences include one from inside.
    let d = MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.6);
    let mut r = RoughDielectric::new(Ior::Constant(1.5), Ior::Constant(1.0), d);
    r.multiple_scattering = true;
    assert_passes_stochastic("roughdielectric multiple_scattering ggx α=0.6 η=1.5", &r, 2048);
}
