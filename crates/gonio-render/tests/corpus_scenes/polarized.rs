//! The polarized corpus scenes: the `polarizer` sheets (their S0 rows are in the parent's
//! table), the Cornell box under `stokes` and the `pplastic` scenes under `stokes`, layer by layer
//! against Mitsuba 3.9.1's `scalar_spectral_polarized` renders.

use super::*;

// Polarization (issue 12): Mitsuba 3.9.1 `scalar_spectral_polarized` references at 256 spp, made
// by `testdata/mitsuba-corpus/make_polarized_references.py` (which also prints Mitsuba's own
// noise: two renders at 32 spp, seeds 1 and 2).
//
// The polarizer scenes (`bsdf_polarizer_*`: linear polarizer sheets before the museum
// environment, over `include/shape_scene.xml` at 120 × 90) render polarized by themselves (they
// contain a `polarizer`); their image is S0, compared as the other rows (gonio-gonio | gonio vs
// reference, seeds 1 2 0 | Mitsuba-Mitsuba):
//
// | scene | gonio-gonio | gonio-reference | Mitsuba-Mitsuba |
// |---|---|---|---|
// | bsdf_polarizer_aligned | 4.87e-4 | 3.97e-4 4.32e-4 4.42e-4 | 1.23e-3 |
// | bsdf_polarizer_middle | 4.32e-4 | 3.46e-4 3.71e-4 4.15e-4 | 1.45e-3 |
// | bsdf_polarizer_absorbing | 4.51e-4 | 3.83e-4 4.18e-4 4.20e-4 | 1.09e-3 |
//
// `integrator_stokes_cbox` (Mitsuba's Cornell box with two glass spheres and a metal one under
// `stokes`, at 48 × 48) is compared layer by layer: R, G, B and S0..S3, each against the
// reference's layer of the same name, with thresholds from [`measure_stokes`].

pub(super) const POL_ALIGNED: f64 = 4.87e-4;
pub(super) const POL_MIDDLE: f64 = 4.32e-4;
pub(super) const POL_ABSORBING: f64 = 4.51e-4;

/// Samples per pixel of `integrator_stokes_cbox` in CI: its S1 and S2 come from the glass and
/// metal spheres, partly through caustic paths that a path tracer finds rarely (measured when
/// gonio's light subpaths were off in polarized mode), so at 32 spp the block errors are heavy-tailed (gonio-vs-gonio
/// 3.9e-4 on S1, gonio-vs-reference 6.0e-4 / 6.2e-4 / 2.8e-4); at 1024 spp gonio is 6.0e-5 from
/// the reference on S1 (S1 sums within 1.7 %).
const STOKES_SPP: u32 = 128;

/// Layer of `integrator_stokes_cbox` (`""` for R, G, B) and threshold. At this spp the
/// reference's own noise (256 spp, measured as gonio at 1024 spp against it) is not negligible,
/// so the threshold is the level of a difference of two noisy renders plus that of the reference:
/// gonio-vs-gonio at [`STOKES_SPP`] (seeds 1 and 2) + gonio(1024 spp)-vs-reference. Mitsuba's own
/// level is at 32 spp (seeds 1 and 2, `make_polarized_references.py --noise`).
///
/// | layer | gonio-gonio | gonio(1024)-reference | threshold | gonio-reference (seeds 1 2 0) | Mitsuba-Mitsuba (32 spp) |
/// |---|---|---|---|---|---|
/// | R, G, B | 9.32e-4 | 2.93e-4 | 1.23e-3 | 7.78e-4 1.26e-3 6.79e-4 | 4.89e-3 |
/// | S0 | 9.32e-4 | 2.93e-4 | 1.23e-3 | 7.78e-4 1.26e-3 6.79e-4 | 4.89e-3 |
/// | S1 | 1.45e-4 | 5.98e-5 | 2.05e-4 | 2.02e-4 2.23e-4 1.62e-4 | 8.44e-5 |
/// | S2 | 8.55e-5 | 6.11e-5 | 1.47e-4 | 1.15e-4 2.06e-4 1.36e-4 | 3.39e-4 |
/// | S3 | 3.71e-6 | 4.87e-7 | 4.20e-6 | 3.38e-6 4.62e-8 4.97e-7 | 7.73e-6 |
///
/// (S1 and S2 come from the spheres, partly through paths a path tracer finds rarely, so their
/// block errors are heavy-tailed; Mitsuba's 32-spp S1 level is low because both of its renders
/// missed those paths.)
///
/// With the light subpaths on in polarized mode (thresholds unchanged), at [`STOKES_SPP`]:
/// gonio-vs-gonio R, G, B = S0 1.97e-4, S1 1.44e-4, S2 8.23e-5, S3 3.69e-6; gonio-vs-reference
/// (seeds 1 2 0) S0 4.56e-4 4.84e-4 3.50e-4, S1 1.96e-4 2.20e-4 1.62e-4, S2 1.18e-4 2.06e-4
/// 1.35e-4, S3 3.37e-6 4.45e-8 4.97e-7: the caustics on the walls (depolarized there) lower the
/// image's noise; S1..S3 come from the spheres seen directly and barely change.
const STOKES_CBOX: [(&str, f64); 5] = [
    ("", 1.23e-3),
    ("S0", 1.23e-3),
    ("S1", 2.05e-4),
    ("S2", 1.47e-4),
    ("S3", 4.20e-6),
];

fn stokes_reference() -> ChannelImage {
    ChannelImage::read(corpus().join("reference/integrator_stokes_cbox.exr")).expect("reference reads")
}

#[test]
fn polarizer_scenes_match_mitsuba_polarized() {
    check("bsdf_polarizer_aligned");
    check("bsdf_polarizer_middle");
    check("bsdf_polarizer_absorbing");
}

#[test]
fn stokes_cbox_matches_mitsuba_polarized_layer_by_layer() {
    let img = render_channels("integrator_stokes_cbox", STOKES_SPP, 0);
    let r = stokes_reference();
    assert_eq!(
        img.names,
        [
            "R", "G", "B", "S0.R", "S0.G", "S0.B", "S1.R", "S1.G", "S1.B", "S2.R", "S2.G", "S2.B", "S3.R",
            "S3.G", "S3.B"
        ],
        "Mitsuba's channel names, in its order"
    );
    for (layer, threshold) in STOKES_CBOX {
        let a = img.layer_rgb(layer).expect("gonio writes the layer");
        let b = r.layer_rgb(layer).expect("the reference has the layer");
        let e = block_relmse(&a, &b, 8).expect("same size");
        println!(
            "integrator_stokes_cbox layer {layer:?}: relMSE vs Mitsuba {e:.3e} (threshold {threshold:.3e})"
        );
        assert!(
            e < threshold,
            "integrator_stokes_cbox layer {layer:?}: 8x8-block relMSE against Mitsuba {e:.3e} ≥ noise level {threshold:.3e}"
        );
    }
}

#[test]
#[ignore = "measurement, run by hand: prints the noise levels of the stokes layers"]
fn measure_stokes() {
    let name = "integrator_stokes_cbox";
    let (a, b, c) = (
        render_channels(name, STOKES_SPP, 1),
        render_channels(name, STOKES_SPP, 2),
        render_channels(name, STOKES_SPP, 0),
    );
    let r = stokes_reference();
    for (layer, _) in STOKES_CBOX {
        let e = |x: &ChannelImage, y: &ChannelImage| {
            block_relmse(&x.layer_rgb(layer).unwrap(), &y.layer_rgb(layer).unwrap(), 8).unwrap()
        };
        println!(
            "{name} {layer:?}: gonio-vs-gonio {:.3e}, gonio-vs-reference {:.3e} / {:.3e} / {:.3e}",
            e(&a, &b),
            e(&a, &r),
            e(&b, &r),
            e(&c, &r)
        );
    }
}

// `bsdf_pplastic_diffuse_stokes` and `bsdf_pplastic_specular_stokes` (Mitsuba's pplastic scenes
// under `stokes`, `include/matpreview_stokes.xml` at 120 × 90): compared layer by layer (R, G, B
// and S0..S3) against the `scalar_spectral_polarized` references (256 spp) at [`CI_SPP`].
// Measured by [`measure_pplastic_stokes`] (gonio-vs-gonio: seeds 1 and 2; gonio-vs-reference:
// seeds 1, 2, 0) and `make_polarized_references.py --noise` (Mitsuba-vs-Mitsuba, 32 spp, seeds 1
// and 2):
//
// | scene | layer | gonio-gonio | gonio-reference | Mitsuba-Mitsuba | threshold |
// |---|---|---|---|---|---|
// | bsdf_pplastic_diffuse_stokes | R, G, B = S0 | 5.11e-4 | 3.94e-4 4.37e-4 4.55e-4 | 1.37e-3 | 5.11e-4 |
// | | S1 | 3.23e-7 | 3.50e-7 2.10e-7 4.17e-7 | 9.05e-7 | 9.05e-7 |
// | | S2 | 4.99e-7 | 3.36e-7 3.10e-7 2.81e-7 | 1.15e-6 | 1.15e-6 |
// | | S3 | 0 | 0 0 0 | 0 | 1e-12 |
// | bsdf_pplastic_specular_stokes | R, G, B = S0 | 6.22e-4 | 3.73e-4 4.85e-4 4.97e-4 | 1.44e-3 | 6.22e-4 |
// | | S1 | 2.96e-5 | 1.52e-5 2.95e-5 1.87e-5 | 9.97e-5 | 9.97e-5 |
// | | S2 | 1.08e-4 | 2.26e-5 9.85e-5 3.51e-5 | 1.36e-4 | 1.36e-4 |
// | | S3 | 0 | 0 0 0 | 0 | 1e-12 |
//
// Re-measured on 2026-12-07 (after the colour-balanced wavelengths of issue #13 lowered gonio's
// own noise), the thresholds kept:
//
// | scene | layer | gonio-gonio | gonio-reference |
// |---|---|---|---|
// | bsdf_pplastic_diffuse_stokes | R, G, B = S0 | 1.14e-4 | 1.93e-4 1.92e-4 1.92e-4 |
// | | S1 | 1.30e-7 | 2.04e-7 1.51e-7 1.30e-7 |
// | | S2 | 1.07e-7 | 9.49e-8 2.06e-7 2.19e-7 |
// | bsdf_pplastic_specular_stokes | R, G, B = S0 | 1.65e-4 | 2.26e-4 2.20e-4 2.06e-4 |
// | | S1 | 2.48e-5 | 1.76e-5 2.07e-5 1.44e-5 |
// | | S2 | 3.27e-5 | 3.57e-5 2.60e-5 1.98e-5 |
//
// gonio-vs-reference now exceeds gonio-vs-gonio on the image: the 256-spp reference's own level
// (Mitsuba-vs-Mitsuba at 32 spp / 8, about 1.7e-4) is as large as gonio's at [`CI_SPP`].
//
// Thresholds: the gonio-vs-gonio level for the image (as the other rows); for S1 and S2, whose
// values are small next to the 10⁻² of the relMSE's denominator, so that the block statistic
// of two noisy renders is itself noisy (gonio-vs-reference exceeds gonio-vs-gonio at seed 0 on
// the diffuse S1), Mitsuba's own level at the same spp; pplastic makes no circular light, and
// S3 is exactly zero in both renderers.
//
// `bsdf_measured_polarized_synthetic_stokes`: Mitsuba's `bsdf_measured_polarized_gold_stokes`
// (same include) with its table replaced by the synthetic one of `testdata/measured_polarized`
// (the KAIST gold is not in the corpus); `alpha_sample` 0.02 and `wavelength` 550 as Mitsuba's
// scene has them, so every wavelength sees the 550 nm matrices and the colour is the light's. It
// is compared twice: as gonio renders it, and with Mitsuba's estimators (`+mitsuba_estimators`:
// among others Mitsuba's `envmap` lookup and light sampling), against the same reference.
// Measured as above:
//
// | scene | layer | gonio-gonio | gonio-reference | Mitsuba-Mitsuba | threshold |
// |---|---|---|---|---|---|
// | bsdf_measured_polarized_synthetic_stokes | R, G, B = S0 | 1.04e-2 | 9.53e-3 6.89e-4 2.07e-3 | 2.74e-3 | 1.04e-2 |
// | | S1 | 1.66e-4 | 7.50e-5 1.35e-4 2.93e-4 | 3.44e-4 | 3.44e-4 |
// | | S2 | 2.95e-3 | 2.79e-3 1.70e-4 2.88e-4 | 5.37e-4 | 2.95e-3 |
// | | S3 | 2.95e-3 | 2.87e-3 1.25e-4 4.73e-4 | 2.37e-4 | 2.95e-3 |
// | bsdf_measured_polarized_synthetic_stokes+mitsuba_estimators | R, G, B = S0 | 9.39e-4 | 8.34e-4 7.57e-4 1.00e-3 | 2.74e-3 | 2.74e-3 |
// | | S1 | 1.65e-4 | 1.05e-4 1.32e-4 1.49e-4 | 3.44e-4 | 3.44e-4 |
// | | S2 | 1.56e-4 | 1.34e-4 1.31e-4 1.23e-4 | 5.37e-4 | 5.37e-4 |
// | | S3 | 1.91e-4 | 8.44e-5 1.12e-4 1.30e-4 | 2.37e-4 | 2.37e-4 |
//
// Thresholds: the larger of the two renderers' own levels (gonio-vs-gonio, Mitsuba-vs-Mitsuba),
// because the block statistic is heavy-tailed here. The sampling lobe (GGX 0.02, 10 % cosine)
// is much narrower than the table's lobe (GGX 0.22-0.34), and as gonio renders the scene the
// envmap's `product_sampling` (its density is zero for tiles below the horizon of the normal
// cell's centre, left to BSDF sampling) now and then leaves a bright direction to a BSDF sample
// of weight up to 10π f: seed 1 has one 8 x 8 block carrying 9.7e-3 of the image's 1.03e-2,
// seed 0 one carrying 4.0e-4 of S3's 4.7e-4 (2 of seeds 0..9 have such a block; with
// `product_sampling` false seeds 0 and 1 have none; with Mitsuba's estimators none of seeds 0..9
// has one so large, the worst, seed 5, reaching 4.6e-4 on S1; nor has any of Mitsuba's 32-spp
// renders with seeds 1..10).
// With Mitsuba's estimators gonio-vs-reference at seed 0 exceeds gonio-vs-gonio on the image
// (the 256-spp reference's own noise: 1.8e-4 against a 4096-spp Mitsuba render). These are
// levels at seed 0, not bounds for every seed (Mitsuba's own 32-spp renders reach 6.1e-4 on S1
// against the reference). Beyond noise the two agree: at 4096 spp with Mitsuba's estimators,
// against Mitsuba at 4096 spp, the object's mean S0 within 0.02 %, S1 0.2 %, S2 0.4-0.7 % (R,
// G; 2.3 % on B, where S2 is smallest), S3 0.2 %, signs alike (S1, S2 < 0, S3 > 0). As gonio
// renders it the whole image is 1.2 % darker in R and 0.4 % brighter in B than Mitsuba's, as in
// the pplastic scenes: its `envmap` lookup (`lookup="mitsuba"` alone removes the difference).

/// Layers of the `stokes` matpreview scenes (pplastic, measured_polarized) and their thresholds
/// (see the tables above).
const PPLASTIC_STOKES: [(&str, [(&str, f64); 5]); 4] = [
    (
        "bsdf_pplastic_diffuse_stokes",
        [
            ("", 5.11e-4),
            ("S0", 5.11e-4),
            ("S1", 9.05e-7),
            ("S2", 1.15e-6),
            ("S3", 1e-12),
        ],
    ),
    (
        "bsdf_pplastic_specular_stokes",
        [
            ("", 6.22e-4),
            ("S0", 6.22e-4),
            ("S1", 9.97e-5),
            ("S2", 1.36e-4),
            ("S3", 1e-12),
        ],
    ),
    (
        "bsdf_measured_polarized_synthetic_stokes",
        [
            ("", 1.04e-2),
            ("S0", 1.04e-2),
            ("S1", 3.44e-4),
            ("S2", 2.95e-3),
            ("S3", 2.95e-3),
        ],
    ),
    (
        "bsdf_measured_polarized_synthetic_stokes+mitsuba_estimators",
        [
            ("", 2.74e-3),
            ("S0", 2.74e-3),
            ("S1", 3.44e-4),
            ("S2", 5.37e-4),
            ("S3", 2.37e-4),
        ],
    ),
];

/// Mitsuba's render of a row of [`PPLASTIC_STOKES`] (of its scene, for a `+mitsuba_estimators` row).
fn stokes_reference_of(name: &str) -> ChannelImage {
    let scene = name.strip_suffix(MITSUBA_ESTIMATORS).unwrap_or(name);
    ChannelImage::read(corpus().join("reference").join(format!("{scene}.exr"))).expect("reference reads")
}

/// 8 × 8-block relMSE of one layer (`""`: R, G, B) of two multi-layer images.
fn layer_relmse(a: &ChannelImage, b: &ChannelImage, layer: &str) -> f64 {
    let (x, y) = (
        a.layer_rgb(layer).expect("the layer is written"),
        b.layer_rgb(layer).expect("the layer is written"),
    );
    block_relmse(&x, &y, 8).expect("same size")
}

#[test]
fn pplastic_stokes_scenes_match_mitsuba_polarized_layer_by_layer() {
    for (name, layers) in PPLASTIC_STOKES {
        let img = render_channels(name, CI_SPP, 0);
        let r = stokes_reference_of(name);
        for (layer, threshold) in layers {
            let e = layer_relmse(&img, &r, layer);
            println!("{name} layer {layer:?}: relMSE vs Mitsuba {e:.3e} (threshold {threshold:.3e})");
            assert!(
                e < threshold,
                "{name} layer {layer:?}: 8x8-block relMSE against Mitsuba {e:.3e} ≥ noise level {threshold:.3e}"
            );
        }
    }
}

#[test]
#[ignore = "measurement, run by hand: prints the noise levels of the pplastic stokes layers"]
fn measure_pplastic_stokes() {
    for (name, layers) in PPLASTIC_STOKES {
        let (a, b, c) = (
            render_channels(name, CI_SPP, 1),
            render_channels(name, CI_SPP, 2),
            render_channels(name, CI_SPP, 0),
        );
        let r = stokes_reference_of(name);
        for (layer, _) in layers {
            println!(
                "{name} {layer:?}: gonio-vs-gonio {:.3e}, gonio-vs-reference {:.3e} / {:.3e} / {:.3e}",
                layer_relmse(&a, &b, layer),
                layer_relmse(&a, &r, layer),
                layer_relmse(&b, &r, layer),
                layer_relmse(&c, &r, layer)
            );
        }
    }
}
