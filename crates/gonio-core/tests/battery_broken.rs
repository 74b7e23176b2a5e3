//! The property battery on deliberately broken models (`gonio_core::check::broken`): each must
//! fail the rows its defect breaks, so every check is shown able to fail. Same α as the
//! correct models of `battery.rs`.

use gonio_core::check::broken::{
    Anisotropic, DiffuseTransmitter, EnergyGain, EvalPdfMismatch, FalselyAnisotropic, MinimalGlass,
    MislabelledLobe, NanAtGrazing, NonReciprocal, PdfOffByFactor, WrongSampler, WrongWeight,
};

use crate::battery_support::*;

// ---- negative controls: every check can fail --------------------------------------------------

#[test]
fn broken_pdf_off_by_factor_fails() {
    assert_fails(
        "PdfOffByFactor 0.8",
        &PdfOffByFactor { factor: 0.8 },
        &["chi2", "sample_pdf_vs_pdf", "pdf_normalization"],
    );
}

#[test]
fn broken_pdf_too_large_fails_integral() {
    assert_fails(
        "PdfOffByFactor 1.3",
        &PdfOffByFactor { factor: 1.3 },
        &["pdf_integral", "chi2"],
    );
}

#[test]
fn broken_sampler_fails_chi2() {
    assert_fails("WrongSampler", &WrongSampler, &["chi2"]);
}

#[test]
fn broken_weight_fails() {
    assert_fails(
        "WrongWeight",
        &WrongWeight,
        &["weight_vs_eval", "albedo_estimators"],
    );
}

#[test]
fn broken_energy_gain_fails() {
    assert_fails("EnergyGain", &EnergyGain, &["energy"]);
}

#[test]
fn broken_non_reciprocal_fails() {
    assert_fails("NonReciprocal", &NonReciprocal, &["reciprocity", "adjoint"]);
}

#[test]
fn broken_anisotropic_fails() {
    assert_fails("Anisotropic", &Anisotropic, &["isotropy"]);
}

#[test]
fn broken_nan_fails_health() {
    assert_fails("NanAtGrazing", &NanAtGrazing, &["health"]);
}

#[test]
fn broken_glass_without_eta2_fails() {
    assert_fails(
        "MinimalGlass without η²",
        &MinimalGlass {
            eta: 1.5,
            scale_radiance: false,
        },
        &["delta_reciprocity"],
    );
}

#[test]
fn broken_lobe_flags_fail() {
    assert_fails("MislabelledLobe", &MislabelledLobe, &["lobe_flags"]);
}

#[test]
fn broken_anisotropy_flag_fails() {
    assert_fails("FalselyAnisotropic", &FalselyAnisotropic, &["isotropy"]);
}

#[test]
fn broken_eval_pdf_fails() {
    assert_fails("EvalPdfMismatch", &EvalPdfMismatch, &["eval_pdf"]);
}

#[test]
fn broken_transmitter_fails_eta2_law() {
    assert_fails(
        "DiffuseTransmitter η=1.5",
        &DiffuseTransmitter {
            rho_t: 0.7,
            claimed_eta: 1.5,
        },
        &["eta2_law"],
    );
}

#[test]
fn broken_pdf_off_by_three_percent_fails() {
    // Sensitivity: a 3 % normalization error adds ≈ N·0.03² = 900 to χ² (σ ≈ 71 at 2500 dof)
    // and is ≈ 10 standard errors for the pdf normalization.
    assert_fails(
        "PdfOffByFactor 0.97",
        &PdfOffByFactor { factor: 0.97 },
        &["chi2", "pdf_normalization"],
    );
}
