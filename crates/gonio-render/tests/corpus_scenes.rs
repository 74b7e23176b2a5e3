//! Mitsuba's own documentation scenes (issue #10), rendered as they are, agree with Mitsuba 3.9.1.
//!
//! The scenes are copies of Mitsuba's material-preview scenes (`docs/scenes/bsdf_*.xml`, which
//! include `include/matpreview.xml`: a `serialized` mesh on a checkerboard plane under the
//! `museum.exr` environment, Gaussian reconstruction filter, `fov_axis="smaller"`,
//! `focus_distance`), unchanged except the film, reduced to 120 × 90. Their references are
//! Mitsuba 3.9.1 `scalar_spectral` renders at 256 spp (`testdata/mitsuba-corpus/reference`, made
//! by `testdata/mitsuba-corpus/make_references.py`).
//!
//! # Measure
//!
//! As in `reference_scenes.rs`: relMSE of 8 × 8-block means (per channel, (a − b)²/(b² + 10⁻²)),
//! here at the film's own size (both renderers use the scene's Gaussian filter, so no
//! downsampling).
//!
//! # Thresholds
//!
//! Each scene's threshold is the level two independent gonio renders at [`CI_SPP`] show against
//! each other (seeds 1 and 2), printed by `cargo test --release -p gonio-render --test integration
//! corpus_scenes::measure -- --ignored --nocapture`: a correct renderer sits near half of it against a converged
//! reference. Adding a scene is one row in [`SCENES`] (and its reference from the script).

use gonio_render::compare::block_relmse;
use gonio_render::image::{ChannelImage, RgbImage};
use gonio_render::render::{PreparedScene, RenderOptions, render};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

mod deviations;
mod polarized;
use polarized::{POL_ABSORBING, POL_ALIGNED, POL_MIDDLE};

/// Samples per pixel in CI.
const CI_SPP: u32 = 32;

/// Samples per pixel of the `direct` scenes in CI (see [`SCENES`]: their error has a heavy tail
/// at [`CI_SPP`]).
const DIRECT_SPP: u32 = 128;

/// Samples per pixel of a row of [`SCENES`] in CI and in [`measure`].
fn ci_spp(name: &str) -> u32 {
    match name {
        "integrator_direct_both" | "integrator_direct_lum" => DIRECT_SPP,
        _ => CI_SPP,
    }
}

/// Scene name (file `docs/scenes/<name>.xml`) and threshold (the gonio-vs-gonio level measured
/// by [`measure`]).
///
/// Measured at 120 × 90, [`CI_SPP`] spp: the gonio-vs-gonio level, gonio-vs-reference for seeds
/// 1, 2, 0, and the level two Mitsuba 3.9.1 `scalar_spectral` renders (seeds 1 and 2, same size
/// and spp) show against each other:
///
/// | scene | gonio-gonio | gonio-reference | Mitsuba-Mitsuba |
/// |---|---|---|---|
/// | bsdf_diffuse_plain | 6.40e-4 | 4.59e-4 4.84e-4 5.12e-4 | 1.76e-3 |
/// | bsdf_conductor_gold | 1.31e-3 | 8.49e-4 8.12e-4 8.82e-4 | 2.29e-3 |
/// | bsdf_roughconductor_copper | 1.64e-3 | 8.68e-4 9.33e-4 1.02e-3 | 2.39e-3 |
/// | bsdf_plastic_default | 7.42e-4 | 5.23e-4 5.15e-4 5.83e-4 | 1.70e-3 |
/// | bsdf_dielectric_glass | 7.12e-3 | 4.21e-3 5.45e-3 2.95e-3 | 8.25e-3 |
/// | bsdf_roughconductor_anisotropic_aluminium | 2.38e-3 | 9.95e-4 1.61e-3 1.30e-3 | |
/// | bsdf_roughdielectric_glass | 7.39e-3 | 5.49e-3 4.15e-3 5.10e-3 | |
/// | bsdf_roughdielectric_rough | 8.53e-3 | 4.64e-3 5.28e-3 3.70e-3 | |
/// | bsdf_roughplastic_beckmann | 5.73e-4 | 3.91e-4 4.10e-4 4.51e-4 | |
/// | bsdf_roughplastic_ggx | 5.23e-4 | 3.85e-4 4.24e-4 4.61e-4 | |
/// | bsdf_roughplastic_preserve | 5.94e-4 | 4.01e-4 4.16e-4 4.58e-4 | |
/// | bsdf_roughdielectric_textured | 4.50e-3 | 6.65e-3 6.88e-3 6.79e-3 (see below) | |
/// | bsdf_roughdielectric_textured_cells_swapped | 5.81e-3 | 3.10e-3 3.66e-3 3.24e-3 | |
/// | bsdf_roughdielectric_textured+mitsuba_estimators | 4.71e-3 | 2.67e-3 3.14e-3 3.29e-3 | |
/// | bsdf_roughplastic_nopreserve | 5.94e-4 | 4.03e-4 4.14e-4 4.58e-4 | |
/// | principled_blend_creation/scene | 1.31e-3 | 1.01e-3 9.39e-4 8.09e-4 | |
/// | principled_blend_creation/scene_thin | 9.71e-4 | 8.53e-4 8.41e-4 7.49e-4 | |
/// | sensor_thinlens | 6.92e-4 | 5.72e-4 4.98e-4 5.41e-4 | |
/// | sensor_orthographic | 6.98e-4 | 5.27e-4 5.33e-4 4.77e-4 | |
/// | integrator_direct_both (at [`DIRECT_SPP`], see below) | 9.16e-4 (largest of five pairs) | 4.0e-4 3.7e-4 4.6e-4 against the 256-spp reference, 1.8e-4 1.9e-4 3.0e-4 against the 8192-spp one | 2.1e-3 6.2e-3 (128 spp) |
/// | integrator_direct_lum (at [`DIRECT_SPP`], see below) | 3.70e-2 (kept) | 9.3e-3 7.1e-3 9.5e-3 against the 8192-spp reference | |
/// | shape_cylinder_onesided | 5.60e-4 | 4.01e-4 4.93e-4 4.89e-4 | |
/// | shape_cylinder_twosided | 5.86e-4 | 4.19e-4 5.02e-4 4.79e-4 | |
/// | bsdf_roughconductor_textured_carbon_cells_swapped | 7.88e-4 | 5.20e-4 6.51e-4 6.10e-4 | |
/// | bsdf_roughconductor_textured_carbon+mitsuba_estimators | 6.67e-4 | 4.08e-4 4.98e-4 4.65e-4 | |
/// | shape_sdfgrid | 5.94e-4 | 4.17e-4 4.97e-4 4.87e-4 | |
/// | shape_sdfgrid_analytic | 5.80e-4 | 4.26e-4 5.11e-4 4.77e-4 | |
/// | shape_linearcurve_basic | 5.62e-4 | 4.09e-4 4.89e-4 4.68e-4 | |
/// | shape_linearcurve_parameterization | 5.38e-4 | 4.13e-4 4.82e-4 4.85e-4 | |
/// | shape_bsplinecurve_basic | 5.36e-4 | 4.02e-4 4.94e-4 4.82e-4 | |
/// | shape_bsplinecurve_parameterization | 5.38e-4 | 3.94e-4 4.89e-4 4.95e-4 | |
/// | bsdf_pplastic | 6.11e-4 | 4.03e-4 4.83e-4 4.91e-4 | |
/// | bsdf_pplastic_diffuse | 5.11e-4 | 3.94e-4 4.37e-4 4.54e-4 | |
/// | bsdf_pplastic_specular | 5.99e-4 | 3.71e-4 4.69e-4 4.94e-4 | |
/// | bsdf_hair_strands (ours, see below) | 2.03e-4 (largest of five pairs) | 1.22e-4 1.13e-4 1.27e-4 | |
/// | bsdf_mask_after | 5.50e-4 | 4.56e-4 6.08e-4 5.41e-4 (see below) | 1.94e-3 |
/// | bsdf_normalmap_with | 5.65e-4 | 4.08e-4 4.86e-4 5.28e-4 | 1.46e-3 |
/// | medium_homogeneous_sss | 4.36e-3 | 2.46e-3 3.06e-3 2.42e-3 | 5.95e-3 |
/// | bsdf_bumpmap_with | 6.06e-4 | 4.55e-4 4.48e-4 5.03e-4 | 1.43e-3 |
/// | bsdf_blendbsdf | 1.57e-3 | 1.44e-2 1.39e-2 1.77e-2 (gonio exact, see below) | |
/// | bsdf_blendbsdf_delta_pdf_mitsuba | 1.18e-3 | 8.10e-4 7.02e-4 6.78e-4 | |
/// | texture_mesh_attribute_face | 8.16e-4 | 5.37e-4 5.72e-4 5.59e-4 | 1.60e-3 |
/// | texture_mesh_attribute_vertex | 6.63e-4 | 4.94e-4 5.10e-4 5.07e-4 | 1.47e-3 |
/// | shape_sphere_light_analytic | 8.58e-5 | 7.45e-5 8.68e-5 7.43e-5 (gonio exact, see below) | |
/// | shape_sphere_light_analytic+mitsuba_estimators | 8.63e-5 | 3.72e-5 5.20e-5 4.30e-5 | |
/// | bsdf_measured_synthetic (ours, see below) | 2.16e-4 (+ 1.12e-4, the reference's own, = 3.28e-4) | 2.84e-4 2.81e-4 2.62e-4 | 1.79e-3 |
/// | bsdf_measured_synthetic+mitsuba_estimators | 4.61e-4 | 2.92e-4 3.55e-4 3.63e-4 | |
/// | bsdf_measured_synthetic_aniso (ours) | 2.95e-4 (+ 1.26e-4 = 4.21e-4) | 3.47e-4 3.23e-4 3.62e-4 | 2.02e-3 |
/// | bsdf_measured_synthetic_aniso+mitsuba_estimators | 6.39e-4 | 4.89e-4 4.50e-4 4.27e-4 | |
///
/// With the colour-balanced wavelengths of issue #13 (`gonio_core::spectrum::render_wavelength_pdf`,
/// 2026-12-05) the gonio-vs-gonio levels lie below the table's (most by 2–3×, from the
/// environment map's estimators since) but for `integrator_direct_lum` (4.12e-2 against 3.70e-2,
/// light sampling alone; seed 0 at 1.40e-2 against the reference), so the thresholds above stay
/// as measured; at this spp most gonio-vs-reference levels now exceed the gonio-vs-gonio ones,
/// the 256-spp references' own noise being the larger part (e.g. `bsdf_diffuse_plain` 2.57e-4 against 2.51e-4–2.79e-4,
/// `shape_cylinder_onesided` 1.71e-4 against 2.31e-4–2.79e-4).
///
/// `shape_sphere_light_analytic` (film 120 × 90) has a reference of 4096 spp: its rough floor
/// reflects the small bright sphere in fireflies that 256 spp leave in Mitsuba's render.
///
/// The `sdfgrid` scenes (Mitsuba's torus grid in a `shapegroup`, placed by an `instance`) and the
/// curve scenes (`linearcurve`, `bsplinecurve` over `meshes/curve_doc.txt`) use
/// `include/shape_scene.xml` (120 × 90) too; CI renders `shape_sdfgrid` and
/// `shape_linearcurve_parameterization` (whose checkerboard also tests the curve's uv),
/// `measure` all six.
///
/// The sensor scenes (Mitsuba's `sensor_thinlens.xml`, `sensor_orthographic.xml` over
/// `include/sensor_scene.xml`, 120 × 90) take `$spp` from the caller, as in Mitsuba. The `direct`
/// scenes are Veach's MIS plates (`include/veach_mis.xml`, 120 × 80): `direct` with one light and
/// one BSDF sample is, sample for sample, the path tracer at `max_depth = 2` (same random numbers,
/// same weights), so `integrator_direct_both` measures the path tracer's lights and
/// `roughplastic` plates as much as the integrator. Its error has a heavy tail (one light
/// sample on the sharper plates: a few renders in ten carry a firefly), so CI renders it at
/// [`DIRECT_SPP`] against a reference of 8192 spp, and its threshold is the largest
/// gonio-vs-gonio level of five pairs of seeds (`GONIO_PAIRS=5`), measured with the
/// colour-balanced wavelengths (2026-12-05): 2.79e-4 9.16e-4 2.61e-4 2.55e-4 4.81e-4. Against
/// the 8192-spp reference, seeds 0–9 at 128 spp give 1.8e-4–6.1e-4 and one 1.24e-3 (seed 4,
/// whose firefly also makes the pair's 9.16e-4); at 32 spp 5.3e-4–3.1e-3, over the old threshold
/// (1.38e-3, one pair) in three seeds of ten with the blend and four with the sech² wavelengths.
/// Mitsuba's own renders at 128 spp lie 6.1e-4–1.37e-3 from that reference. The former 256-spp
/// reference was 1.2–2.4 % brighter than the 8192-spp one (its fireflies), which is what this
/// table used to read as gonio's mean lying 0.7–1.5 % below Mitsuba's; gonio's mean over ten
/// seeds is 0.5 % above the new one (within its noise).
///
/// `integrator_direct_lum` (light sampling alone) had the same heavy tail: at 32 spp against
/// its 256-spp reference seeds 0–9 gave 1.4e-2–9.3e-2, over its threshold (3.70e-2, one pair)
/// in four of ten; that reference lay 1.2e-2 from an 8192-spp one. It too renders at
/// [`DIRECT_SPP`] against an 8192-spp reference, where seeds 0–9 give 7.1e-3–2.8e-2. Its
/// threshold is kept as measured: the five pairs at 128 spp (1.16e-2 3.56e-2 1.37e-1 2.35e-2
/// 1.57e-2) are no bound here, since a firefly that lands on a pixel the other render has dark
/// inflates a pair's relMSE (its denominator is that render).
///
/// The BSDF-sampling-only scene (`integrator_direct_bsdf`) is too noisy at this spp to test
/// anything and is left out (gonio-vs-gonio 1.19, gonio-vs-reference 0.32–0.44). The cylinder scenes
/// (`include/shape_scene.xml`, 120 × 90) compare our tessellated cylinder with Mitsuba's quadric.
///
/// The principled scenes (Mitsuba's `principled_blend_creation/`, a `principled` and a
/// `principledthin` sphere before a checkerboard under an environment map) are corrected in the
/// copy where Mitsuba itself rejects them (`type="Sphere"`, `"Rectangle"`), with a 96 × 96 film
/// and the map reduced to 256 × 128; both renderers read the same files.
///
/// `bsdf_hair_strands` is ours (Mitsuba's `hair` documentation scenes need a hair model the
/// corpus does not ship): 24 `bsplinecurve` strands of `hair`, backlit, under a constant sky. Its
/// transmitted lobes reach the camera only because curves are not hit from inside (rays that
/// enter a fibre leave it): with the tubes' insides hit, the strands render 22–33 % darker.
///
/// `bsdf_measured_synthetic` and `_aniso` are ours (Mitsuba's `measured` documentation scenes,
/// `bsdf_measured_aniso_morpho_melenaus` and `_cc_nothern_aurora`, read real RGL files the corpus
/// does not ship): the material preview with a `measured` object on the synthetic tables of
/// `testdata/measured` (`iso.bsdf`; `aniso.bsdf`, four-fold mirrored). Measured on 2026-12-07 with
/// the colour-balanced wavelengths, where gonio's own estimators are 8× less noisy than Mitsuba at
/// equal spp (gonio-vs-gonio 2.16e-4, Mitsuba-vs-Mitsuba 1.79e-3), so the 256-spp reference's own
/// level against the converged image (Mitsuba-vs-Mitsuba / 16: 1.12e-4, 1.26e-4) is as large as
/// gonio's: as for `emitter_spot_texture`, the threshold of the file as written is the sum of the
/// two. It also carries gonio's `envmap` lookup (see
/// `deviations::shape_scene_red_deficit_is_mitsubas_envmap_lookup`): at 4096 spp the whole image,
/// object and floor alike, is 1.1 % darker in red, 0.3 % in green and 0.5 % brighter in blue than
/// Mitsuba's 4096-spp render (gonio at 4096 spp against it: relMSE 5.7e-5, `_aniso` 5.9e-5, of the
/// levels above). With Mitsuba's estimators (the `+mitsuba_estimators` rows: gonio 2× noisier,
/// their threshold its own gonio-vs-gonio level as for the other rows) that is gone: relMSE 8.5e-6
/// (`_aniso` 9.7e-6) at 4096 spp, the object's mean per channel within 0.04 % of Mitsuba's
/// (`_aniso`: within 0.07 % of the mean of three 4096-spp Mitsuba renders, which scatter by 0.1 %).
/// Seeds 0–9 against the references stay below the thresholds (as written 2.3e-4–3.1e-4 and
/// 3.2e-4–4.0e-4; with Mitsuba's estimators 2.9e-4–3.6e-4 and 4.1e-4–5.4e-4). The isotropic table
/// rendered in place of the anisotropic one sits at 5.3e-2 against the latter's reference. CI
/// checks all but `_aniso+mitsuba_estimators`; `measure` all four.
///
/// `bsdf_roughplastic_preserve` keeps gonio's exact coat averages (its diffuse lobe up to 2 %
/// brighter than Mitsuba's where Mitsuba's 64-node mean loses energy, see
/// `mitsuba_roughplastic_values.rs`): under this map the difference stays inside the noise. Its
/// texture `floor_tiles.jpg` is Mitsuba's, reduced to 256 × 256 for the repository (both
/// renderers read the same file).
const SCENES: &[(&str, f64)] = &[
    ("bsdf_diffuse_plain", 6.40e-4),
    ("bsdf_conductor_gold", 1.31e-3),
    ("bsdf_roughconductor_copper", 1.64e-3),
    ("bsdf_plastic_default", 7.42e-4),
    ("bsdf_dielectric_glass", 7.12e-3),
    ("bsdf_roughconductor_anisotropic_aluminium", 2.38e-3),
    ("bsdf_roughdielectric_glass", 7.39e-3),
    ("bsdf_roughdielectric_rough", 8.53e-3),
    ("bsdf_roughplastic_beckmann", 5.73e-4),
    ("bsdf_roughplastic_ggx", 5.23e-4),
    ("bsdf_roughplastic_preserve", 5.94e-4),
    ("bsdf_roughdielectric_textured", 4.50e-3),
    ("bsdf_roughdielectric_textured_cells_swapped", 5.81e-3),
    ("bsdf_roughdielectric_textured+mitsuba_estimators", 4.71e-3),
    ("bsdf_roughplastic_nopreserve", 5.94e-4),
    ("principled_blend_creation/scene", 1.31e-3),
    ("principled_blend_creation/scene_thin", 9.71e-4),
    ("sensor_thinlens", 6.92e-4),
    ("sensor_orthographic", 6.98e-4),
    ("integrator_direct_both", 9.16e-4),
    ("integrator_direct_lum", 3.70e-2),
    ("shape_cylinder_onesided", 5.60e-4),
    ("shape_cylinder_twosided", 5.86e-4),
    ("bsdf_roughconductor_textured_carbon_cells_swapped", 7.88e-4),
    ("bsdf_roughconductor_textured_carbon+mitsuba_estimators", 6.67e-4),
    ("shape_sdfgrid", 5.94e-4),
    ("shape_sdfgrid_analytic", 5.80e-4),
    ("shape_linearcurve_basic", 5.62e-4),
    ("shape_linearcurve_parameterization", 5.38e-4),
    ("shape_bsplinecurve_basic", 5.36e-4),
    ("shape_bsplinecurve_parameterization", 5.38e-4),
    ("bsdf_pplastic", 6.11e-4),
    ("bsdf_pplastic_diffuse", 5.11e-4),
    ("bsdf_pplastic_specular", 5.99e-4),
    ("bsdf_mask_after", 5.50e-4),
    ("bsdf_normalmap_with", 5.65e-4),
    ("medium_homogeneous_sss", 4.36e-3),
    ("bsdf_bumpmap_with", 6.06e-4),
    ("emitter_spot_texture", 1.15e-4),
    ("emitter_projector_constant", 6.50e-4),
    ("bsdf_polarizer_aligned", POL_ALIGNED),
    ("bsdf_polarizer_middle", POL_MIDDLE),
    ("bsdf_polarizer_absorbing", POL_ABSORBING),
    ("bsdf_blendbsdf", 1.57e-3),
    ("bsdf_blendbsdf_delta_pdf_mitsuba", 1.18e-3),
    ("bsdf_hair_strands", 2.03e-4),
    ("texture_mesh_attribute_face", 8.16e-4),
    ("texture_mesh_attribute_vertex", 6.63e-4),
    ("bsdf_measured_synthetic", 3.28e-4),
    ("bsdf_measured_synthetic+mitsuba_estimators", 4.61e-4),
    ("bsdf_measured_synthetic_aniso", 4.21e-4),
    ("bsdf_measured_synthetic_aniso+mitsuba_estimators", 6.39e-4),
    ("shape_sphere_light_analytic", deviations::SPHERE_LIGHT),
    (
        "shape_sphere_light_analytic+mitsuba_estimators",
        deviations::SPHERE_LIGHT,
    ),
    ("texture_mesh_attribute_instance", deviations::INSTANCE_THRESHOLD),
    (
        "emitter_area_mesh_attribute",
        deviations::EMITTER_ATTRIBUTE_THRESHOLD,
    ),
    ("emitter_projector_textured", deviations::TEXTURED_PROJECTOR),
    (
        "emitter_projector_textured_whitepoint_mitsuba",
        deviations::TEXTURED_PROJECTOR_MITSUBA,
    ),
    (
        "bsdf_mask_after_lookup_mitsuba",
        deviations::MASK_AFTER_LOOKUP_MITSUBA,
    ),
];

/// A row whose name ends so renders its scene (the name without it) with Mitsuba's estimators
/// (`LoadOptions::mitsuba_estimators`, `gonio render --mitsuba-estimators`) and compares it with
/// Mitsuba's render of that scene.
const MITSUBA_ESTIMATORS: &str = "+mitsuba_estimators";

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mitsuba-corpus")
}

fn render_scene(name: &str, spp: u32, seed: u64) -> RgbImage {
    render_channels(name, spp, seed).rgb()
}

/// Every film channel of the render (`R`, `G`, `B`, and the layers of a `stokes` integrator).
fn render_channels(name: &str, spp: u32, seed: u64) -> ChannelImage {
    let (name, mitsuba_estimators) = match name.strip_suffix(MITSUBA_ESTIMATORS) {
        Some(file) => (file, true),
        None => (name, false),
    };
    let path = corpus().join("docs/scenes").join(format!("{name}.xml"));
    // Scenes that use `$spp` before any `<default name="spp">` (the sensor scenes) take it from
    // the caller, as Mitsuba's documentation renders them (`make_references.py` does the same).
    let text = std::fs::read_to_string(&path).expect("scene reads");
    let defines = if text.contains("$spp") && !text.contains(r#"<default name="spp""#) {
        vec![("spp".to_string(), spp.to_string())]
    } else {
        vec![]
    };
    let options = gonio_render::xml::LoadOptions {
        defines,
        mitsuba_estimators,
    };
    let scene = gonio_render::xml::load_scene_file_with(&path, &options)
        .expect("scene loads")
        .scene;
    crate::integrator::render_scene(scene, spp, seed).channels
}

/// Mitsuba's render of `name`; a `_delta_pdf_mitsuba`, `_whitepoint_mitsuba` or
/// `_lookup_mitsuba` copy (gonio's
/// switch to Mitsuba's behaviour, a parameter Mitsuba would reject) is compared with the
/// original's render.
fn reference(name: &str) -> RgbImage {
    let name = name.strip_suffix(MITSUBA_ESTIMATORS).unwrap_or(name);
    let source = name.strip_suffix("_delta_pdf_mitsuba").unwrap_or(name);
    // Mitsuba 3.9.1 renders the instanced bunny wrong (see `mesh_attribute_instance_...`): its
    // render of the bunny placed directly is the reference.
    // Mitsuba's render of the carbon scene is stored under its `_cells_swapped` copy's name
    // (`make_references.py`).
    let source = match source {
        "texture_mesh_attribute_instance" => "texture_mesh_attribute_vertex",
        "bsdf_roughconductor_textured_carbon" => "bsdf_roughconductor_textured_carbon_cells_swapped",
        s => s,
    };
    let source = source.strip_suffix("_whitepoint_mitsuba").unwrap_or(source);
    let source = source.strip_suffix("_lookup_mitsuba").unwrap_or(source);
    RgbImage::read(corpus().join("reference").join(format!("{source}.exr"))).expect("reference reads")
}

fn check(name: &str) {
    let threshold = SCENES.iter().find(|s| s.0 == name).expect("a row of SCENES").1;
    let img = render_scene(name, ci_spp(name), 0);
    let r = reference(name);
    assert_eq!(
        (img.width, img.height),
        (r.width, r.height),
        "{name}: the reduced film"
    );
    let e = block_relmse(&img, &r, 8).expect("same size");
    println!("{name}: relMSE vs Mitsuba {e:.3e} (threshold {threshold:.3e})");
    assert!(
        e < threshold,
        "{name}: 8x8-block relMSE against Mitsuba {e:.3e} ≥ noise level {threshold:.3e}"
    );
}

#[test]
#[ignore = "measurement, run by hand: prints the noise levels the thresholds come from"]
fn measure() {
    // GONIO_SCENES=a,b limits the measurement to some scenes; GONIO_PAIRS=n measures the
    // gonio-vs-gonio level on n pairs of seeds (1, 2), (3, 4), … and prints the largest too.
    let only = std::env::var("GONIO_SCENES").ok();
    let pairs: u64 = std::env::var("GONIO_PAIRS")
        .ok()
        .and_then(|p| p.parse().ok())
        .unwrap_or(1);
    for (name, _) in SCENES {
        if only.as_ref().is_some_and(|o| !o.split(',').any(|x| x == *name)) {
            continue;
        }
        let spp = ci_spp(name);
        let a = render_scene(name, spp, 1);
        let b = render_scene(name, spp, 2);
        let c = render_scene(name, spp, 0);
        let r = reference(name);
        let e = |x: &RgbImage, y: &RgbImage| block_relmse(x, y, 8).unwrap();
        let mut levels = vec![e(&a, &b)];
        for k in 1..pairs {
            let (x, y) = (
                render_scene(name, spp, 2 * k + 1),
                render_scene(name, spp, 2 * k + 2),
            );
            levels.push(e(&x, &y));
        }
        let max = levels.iter().copied().fold(0.0, f64::max);
        let levels: Vec<String> = levels.iter().map(|l| format!("{l:.3e}")).collect();
        println!(
            "{name} ({spp} spp): gonio-vs-gonio {} (max {max:.3e}), gonio-vs-reference {:.3e} / {:.3e} / {:.3e}",
            levels.join(" "),
            e(&a, &r),
            e(&b, &r),
            e(&c, &r)
        );
    }
}

#[test]
fn diffuse_plain_matches_mitsuba() {
    check("bsdf_diffuse_plain");
}

#[test]
fn conductor_gold_matches_mitsuba() {
    check("bsdf_conductor_gold");
}

#[test]
fn roughconductor_copper_matches_mitsuba() {
    check("bsdf_roughconductor_copper");
}

#[test]
fn plastic_default_matches_mitsuba() {
    check("bsdf_plastic_default");
}

#[test]
fn dielectric_glass_matches_mitsuba() {
    check("bsdf_dielectric_glass");
}

#[test]
fn roughconductor_anisotropic_aluminium_matches_mitsuba() {
    check("bsdf_roughconductor_anisotropic_aluminium");
}

#[test]
fn roughdielectric_glass_matches_mitsuba() {
    check("bsdf_roughdielectric_glass");
}

#[test]
fn roughdielectric_rough_matches_mitsuba() {
    check("bsdf_roughdielectric_rough");
}

#[test]
fn roughplastic_beckmann_matches_mitsuba() {
    check("bsdf_roughplastic_beckmann");
}

#[test]
fn roughplastic_ggx_matches_mitsuba() {
    check("bsdf_roughplastic_ggx");
}

#[test]
fn roughplastic_textured_preserve_matches_mitsuba() {
    check("bsdf_roughplastic_preserve");
}

#[test]
fn principled_blend_scene_matches_mitsuba() {
    check("principled_blend_creation/scene");
}

#[test]
fn principledthin_blend_scene_matches_mitsuba() {
    check("principled_blend_creation/scene_thin");
}

#[test]
fn thinlens_sensor_matches_mitsuba() {
    check("sensor_thinlens");
}

#[test]
fn orthographic_sensor_matches_mitsuba() {
    check("sensor_orthographic");
}

#[test]
fn direct_integrator_matches_mitsuba() {
    check("integrator_direct_both");
}

#[test]
fn direct_integrator_emitter_sampling_only_matches_mitsuba() {
    check("integrator_direct_lum");
}

#[test]
fn cylinder_matches_mitsuba() {
    check("shape_cylinder_onesided");
    check("shape_cylinder_twosided");
}

#[test]
fn sdfgrid_instance_matches_mitsuba() {
    check("shape_sdfgrid");
}

/// One curve scene in CI (the linear curve: tubes, joints and caps, its checkerboard testing
/// the uv); the B-spline's hits and uv are tested against Mitsuba in `xml_mesh.rs`.
#[test]
fn linearcurve_matches_mitsuba() {
    check("shape_linearcurve_parameterization");
}

#[test]
fn roughplastic_textured_nopreserve_matches_mitsuba() {
    check("bsdf_roughplastic_nopreserve");
}

/// Mitsuba 3.9.1 looks a checkerboard up as a float (`eval_1`, as for a roughness) with its two
/// cells exchanged relative to its colour lookup (`eval`), so `bsdf_roughdielectric_textured`
/// (α = 0 and 0.4 in a checkerboard) renders in Mitsuba with the rough and the smooth squares
/// swapped. gonio keeps one checkerboard for both lookups: its render of the file as it is
/// differs from Mitsuba's beyond the noise, and the copy with `color0` and `color1` exchanged
/// (`..._cells_swapped.xml`, compared with the same Mitsuba reference) agrees within it, as does
/// the file as it is under Mitsuba's estimators (the checkerboard's `float_cells="mitsuba"`).
#[test]
fn roughdielectric_textured_differs_from_mitsuba_only_by_its_checkerboard_cells() {
    let swapped = "bsdf_roughdielectric_textured_cells_swapped";
    check(swapped);
    check("bsdf_roughdielectric_textured+mitsuba_estimators");
    let name = "bsdf_roughdielectric_textured";
    let threshold = SCENES.iter().find(|s| s.0 == name).unwrap().1;
    let e = block_relmse(&render_scene(name, CI_SPP, 0), &reference(name), 8).unwrap();
    assert!(
        e > threshold,
        "{name} as written now matches Mitsuba ({e:.3e}): has Mitsuba's cell swap been fixed?"
    );
}

/// Mitsuba's `bsdf_roughconductor_textured_carbon` (amorphous carbon, preset `a-C`, anisotropic
/// Beckmann roughness from two checkerboards), compared as `bsdf_roughdielectric_textured` is:
/// with both checkerboards' cells exchanged in gonio's copy, because Mitsuba 3.9.1 looks up a
/// float checkerboard with its cells swapped, and as it is under Mitsuba's estimators.
#[test]
fn roughconductor_textured_carbon_matches_mitsuba() {
    check("bsdf_roughconductor_textured_carbon_cells_swapped");
    check("bsdf_roughconductor_textured_carbon+mitsuba_estimators");
}

/// Mitsuba 3.9.1's `blendbsdf` adds a delta child's discrete probability to the other child's
/// solid-angle density (`gonio_core::bsdfs::blendbsdf`: biased for delta + smooth mixes; its
/// albedos reproduced there). Mitsuba's `bsdf_blendbsdf` blends a rough plastic with a smooth gold
/// by a noise texture, so gonio's render of the file as it is differs from Mitsuba's beyond the
/// noise (brighter: the gold keeps its share), and the copy with `delta_pdf="mitsuba"` agrees
/// with Mitsuba's render of the original within it.
#[test]
fn blendbsdf_differs_from_mitsuba_only_by_its_delta_pdf() {
    check("bsdf_blendbsdf_delta_pdf_mitsuba");
    let name = "bsdf_blendbsdf";
    let threshold = SCENES.iter().find(|s| s.0 == name).unwrap().1;
    let (img, r) = (render_scene(name, CI_SPP, 0), reference(name));
    let e = block_relmse(&img, &r, 8).unwrap();
    assert!(
        e > 2.0 * threshold,
        "{name} as written now matches Mitsuba ({e:.3e}): has Mitsuba's blendbsdf bias been fixed?"
    );
    let mean = |im: &RgbImage| {
        im.data
            .iter()
            .map(|p| p.iter().map(|&v| v as f64).sum::<f64>())
            .sum::<f64>()
    };
    assert!(mean(&img) > mean(&r), "gonio's exact blend is the brighter one");
}

/// `pplastic` renders unpolarized here (the intensity of its Mueller matrices is `eval`), against
/// Mitsuba's `scalar_spectral`; the two components as Mitsuba's documentation shows them.
#[test]
fn pplastic_matches_mitsuba() {
    check("bsdf_pplastic");
}

#[test]
fn pplastic_diffuse_component_matches_mitsuba() {
    check("bsdf_pplastic_diffuse");
}

#[test]
fn pplastic_specular_component_matches_mitsuba() {
    check("bsdf_pplastic_specular");
}

/// Mitsuba's `bsdf_mask_after` (`include/shape_scene.xml`, 120 × 90): a `mask` whose opacity is
/// a leaf-shaped bitmap (`leaf_mask.png`, grey + alpha, read as its grey channel) over a diffuse
/// rectangle. gonio crosses the transparent part as a null lobe (shadow rays pass it, the path
/// does not count it as a bounce); Mitsuba's `path` samples it as a delta event and blocks shadow
/// rays there. Both estimate the same image. It sits at the noise level rather than below it
/// (gonio's red mean is 1.5 % below Mitsuba's; green and blue agree). The same deficit is in
/// `bsdf_mask_before`, the scene without the mask (red −1.6 %), so it is not the mask's.
#[test]
fn mask_after_matches_mitsuba() {
    check("bsdf_mask_after");
}

/// Mitsuba's `bsdf_normalmap_with` (material preview, 120 × 90): `roughplastic` under a
/// `normalmap` (`floor_tiles_normalmap.jpg`, reduced to 256 × 256 for the repository; both
/// renderers read the copy). The same scene without the map sits at 1.3e-3 against this
/// reference, twice the threshold: the test sees the perturbed frames.
#[test]
fn normalmap_matches_mitsuba() {
    check("bsdf_normalmap_with");
}

/// Mitsuba's subsurface-scattering documentation scene: a rough glass bunny filled with a
/// homogeneous medium (`volpath`, depth 64), chosen by the scene's own `<default>` over the
/// include's (the first definition wins).
#[test]
fn medium_homogeneous_sss_matches_mitsuba() {
    check("medium_homogeneous_sss");
}

/// Mitsuba's `bsdf_bumpmap_with` (material preview, 120 × 90): `roughplastic` under a
/// `bumpmap` of scale 0.02 (`floor_tiles_bumpmap.png`, reduced to 256 × 256). Without the bumps
/// gonio sits at 2.1e-3 against this reference, with the scale doubled at 1.6e-3.
#[test]
fn bumpmap_matches_mitsuba() {
    check("bsdf_bumpmap_with");
}

/// Mitsuba's `emitter_spot_texture` (`include/emitter_scene.xml`, 120 × 90): a `spot` whose
/// intensity is multiplied by `noise_01.jpg` (reduced to 256 × 256) projected over its cone. The
/// texture flipped in u or in v sits at 0.11–0.15 against this reference, untextured at 2.3.
/// Under a spot gonio is 12× less noisy than Mitsuba at equal spp (gonio-vs-gonio 6.48e-5,
/// Mitsuba-vs-Mitsuba 8.03e-4 at 32 spp), so the 256-spp reference's own noise against the
/// converged image (8.03e-4/16 = 5.0e-5) is not negligible here: the threshold is the sum of the
/// two, 1.15e-4 (gonio-vs-reference 8.74e-5 at seed 0).
#[test]
fn spot_texture_matches_mitsuba() {
    check("emitter_spot_texture");
}

/// Mitsuba's `emitter_projector_constant` (`include/emitter_scene.xml`, 120 × 90, under
/// `museum.exr`): a projector of constant RGB irradiance. Its textured sibling
/// (`emitter_projector_textured.xml`, `flower.bmp`, 100 × 67, `scale` 85.8; copied with its
/// reference) differs by Mitsuba's missing D65 on texture objects: see
/// `projector_textured_differs_from_mitsuba_only_by_its_whitepoint`.
#[test]
fn projector_matches_mitsuba() {
    check("emitter_projector_constant");
}

/// Mitsuba's `mesh_attribute` scenes: the bunny with a random colour per face and per vertex
/// (`meshes/bunny_attribute_color.ply`), over `include/shape_scene.xml` (120 × 90).
#[test]
fn mesh_attribute_face_and_vertex_colours_match_mitsuba() {
    check("texture_mesh_attribute_face");
    check("texture_mesh_attribute_vertex");
}

/// Mitsuba's `measured` on the synthetic RGL tables of `testdata/measured` (ours, see
/// [`SCENES`]): the isotropic table as gonio renders it and under Mitsuba's estimators, the
/// four-fold mirrored anisotropic one as gonio renders it.
#[test]
fn measured_synthetic_matches_mitsuba() {
    check("bsdf_measured_synthetic");
    check("bsdf_measured_synthetic+mitsuba_estimators");
}

#[test]
fn measured_synthetic_anisotropic_matches_mitsuba() {
    check("bsdf_measured_synthetic_aniso");
}
