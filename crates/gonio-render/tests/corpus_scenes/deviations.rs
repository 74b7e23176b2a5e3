//! The corpus scenes where gonio departs from Mitsuba 3.9.1 on purpose (each test names the
//! physics and the switch that restores Mitsuba's behaviour), the `mesh_attribute` rows that
//! Mitsuba cannot render as written, and the colour of an emitter seen directly.

use super::*;

/// `shape_sphere_light_analytic` rows: gonio-vs-gonio at [`CI_SPP`] (table in the parent).
pub(super) const SPHERE_LIGHT: f64 = 8.63e-5;

/// Mitsuba's `shape_sphere_light_analytic`: a small bright sphere light over a `roughplastic`
/// floor (Beckmann α = 0.1, dark blue base). gonio's coat averages are exact
/// (`gonio_core::bsdfs::roughplastic`): Mitsuba's 64-node tables underestimate the coat's
/// internal reflectance R̄_int (0.5747 against the exact 0.5832 at α = 0.1), so its diffuse lobe,
/// ∝ 1/(1 − R̄_int), is 2.0 % too dark: (1 − 0.5747)/(1 − 0.5832) = 1.0204. Read with Mitsuba's
/// estimators (which take Mitsuba's tables) the scene agrees with Mitsuba's render within the
/// noise; as written it is brighter, by at most that factor.
#[test]
fn sphere_light_over_roughplastic_differs_from_mitsuba_only_by_its_coat_tables() {
    check("shape_sphere_light_analytic+mitsuba_estimators");
    let exact = render_scene("shape_sphere_light_analytic", CI_SPP, 0);
    let tables = render_scene("shape_sphere_light_analytic+mitsuba_estimators", CI_SPP, 0);
    // The floor: pixels well below the sphere's radiance (20) and its bright reflection.
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for (x, y) in exact.data.iter().zip(&tables.data) {
        if y.iter().all(|&v| v < 1.0) {
            a += x.iter().map(|&v| f64::from(v)).sum::<f64>();
            b += y.iter().map(|&v| f64::from(v)).sum::<f64>();
        }
    }
    println!("floor, exact / Mitsuba's tables: {:.5}", a / b);
    assert!(a / b > 1.005 && a / b < 1.0204, "{}", a / b);
}

// ---------------------------------------------------------------------------------------------
// `mesh_attribute` in instances and as an area emitter's radiance (references and Mitsuba's
// noise by `testdata/mitsuba-corpus/make_attr_references.py`), measured as the rows above:
//
// | scene | gonio-gonio | gonio-reference (seeds 1 2 0) | Mitsuba-Mitsuba |
// |---|---|---|---|
// | texture_mesh_attribute_instance | 6.62e-4 | 4.94e-4 5.10e-4 5.07e-4 (vs Mitsuba's direct placement) | (Mitsuba renders it wrong) |
// | emitter_area_mesh_attribute | 2.96e-5 | 2.03e-5 2.00e-5 1.88e-5 | 1.44e-3 (BSDF samples only) |

/// `texture_mesh_attribute_instance`: the bunny of `texture_mesh_attribute_vertex` placed by a
/// `shapegroup` + `instance`; threshold: its gonio-vs-gonio level.
pub(super) const INSTANCE_THRESHOLD: f64 = 6.62e-4;

/// `emitter_area_mesh_attribute`: gonio-vs-gonio at [`CI_SPP`] (seeds 1, 2) plus the level of
/// the 4096-spp BSDF-sampled reference, which is not negligible here (Mitsuba-vs-Mitsuba at 32
/// spp / 128 = 1.13e-5): 4.09e-5.
pub(super) const EMITTER_ATTRIBUTE_THRESHOLD: f64 = 4.09e-5;

/// Mitsuba's `texture_mesh_attribute_vertex` with its bunny placed by a `shapegroup` (scale,
/// first rotations) and an `instance` (the other rotations, the translation), compared with
/// Mitsuba's render of the bunny placed directly. Mitsuba 3.9.1 itself renders this file wrong
/// (mean pixel ≈ 10¹⁶: it recomputes the barycentrics from the world-space point against the
/// group-space vertices, right only for an identity instance; checked with the group holding
/// the whole placement, which Mitsuba renders as the direct file to 5e-6).
#[test]
fn mesh_attribute_instance_matches_mitsubas_direct_placement() {
    check("texture_mesh_attribute_instance");
}

/// A mesh emitter whose radiance is a `vertex_color` attribute over a diffuse floor, rendered by
/// the path tracer (camera hits, NEE and BSDF hits with MIS), against Mitsuba's render with BSDF
/// samples only (Mitsuba 3.9.1 crashes when it samples such an emitter for NEE).
#[test]
fn area_emitter_mesh_attribute_matches_mitsuba() {
    check("emitter_area_mesh_attribute");
}

/// Thresholds of the textured projector rows (gonio-vs-gonio at [`CI_SPP`], [`measure`]):
///
/// | scene | gonio-gonio | gonio-reference |
/// |---|---|---|
/// | emitter_projector_textured | 5.85e-4 | 1.23e-3 1.22e-3 1.13e-3 (D65 weighting, see below) |
/// | emitter_projector_textured_whitepoint_mitsuba | 5.94e-4 | 4.26e-4 4.16e-4 3.69e-4 |
pub(super) const TEXTURED_PROJECTOR: f64 = 5.85e-4;
pub(super) const TEXTURED_PROJECTOR_MITSUBA: f64 = 5.94e-4;

/// Mitsuba's `emitter_projector_textured` (`include/emitter_scene.xml`, 120 × 90, under
/// `museum.exr`): `flower.bmp` (100 × 67, `scale` 85.8) projected on the sphere and the plane.
/// gonio projects each texel's colour (E × D65, as for a colour given in place, see
/// `emitter::projector_texture_projects_its_own_colour_unless_whitepoint_mitsuba`); Mitsuba
/// 3.9.1 leaves a texture object without D65, so its projected light is redder (an equal-energy
/// white, not D65): the file as it is differs from Mitsuba's render beyond the noise, gonio's red
/// mean the lower, and the copy with `whitepoint="mitsuba"` agrees with it within the noise.
#[test]
fn projector_textured_differs_from_mitsuba_only_by_its_whitepoint() {
    check("emitter_projector_textured_whitepoint_mitsuba");
    let name = "emitter_projector_textured";
    let threshold = SCENES.iter().find(|s| s.0 == name).unwrap().1;
    let (img, r) = (render_scene(name, CI_SPP, 0), reference(name));
    let e = block_relmse(&img, &r, 8).unwrap();
    assert!(
        e > threshold,
        "{name} as written now matches Mitsuba ({e:.3e}): does Mitsuba weight textures by D65?"
    );
    let red = |im: &RgbImage| im.data.iter().map(|p| p[0] as f64).sum::<f64>();
    assert!(
        red(&img) < red(&r),
        "Mitsuba's equal-energy white is the redder light"
    );
}

/// Threshold of the `bsdf_mask_after_lookup_mitsuba` row (gonio-vs-gonio at [`CI_SPP`],
/// [`measure`]): 5.72e-4; gonio-vs-reference 3.89e-4 5.52e-4 4.68e-4 (seeds 1, 2, 0), the file as
/// it is 4.56e-4 6.08e-4 5.41e-4 against its 5.50e-4.
pub(super) const MASK_AFTER_LOOKUP_MITSUBA: f64 = 5.72e-4;

/// The scenes over `include/shape_scene.xml` (a diffuse checkerboard plane under `museum.exr`,
/// `bsdf_mask_after` here) show gonio's red mean about 1.2 % below Mitsuba's (green and blue
/// within 1 %). The environment map's lookup accounts for it: gonio interpolates the texels'
/// radiance, Mitsuba 3.9.1 multiplies separately interpolated shapes and scales and puts its rows
/// from pole to pole (see `emitter::envmap_blends_texels_as_radiance_unless_lookup_mitsuba`),
/// which comes out redder under this map. The copy whose include sets `lookup="mitsuba"`
/// (`include/shape_scene_lookup_mitsuba.xml`) agrees with Mitsuba's render of the original in
/// every channel's mean (within 0.2 % at seed 0); the file as it is keeps the red deficit.
#[test]
fn shape_scene_red_deficit_is_mitsubas_envmap_lookup() {
    check("bsdf_mask_after_lookup_mitsuba");
    let mean =
        |im: &RgbImage, c: usize| im.data.iter().map(|p| p[c] as f64).sum::<f64>() / im.data.len() as f64;
    let r = reference("bsdf_mask_after");
    let ratios = |name: &str| {
        let img = render_scene(name, CI_SPP, 0);
        [0, 1, 2].map(|c| mean(&img, c) / mean(&r, c))
    };
    let mitsuba = ratios("bsdf_mask_after_lookup_mitsuba");
    let ours = ratios("bsdf_mask_after");
    println!("channel means against Mitsuba: bilinear {ours:?}, mitsuba {mitsuba:?}");
    assert!(mitsuba.iter().all(|q| (q - 1.0).abs() < 0.004), "{mitsuba:?}");
    assert!(ours[0] < 0.992, "{ours:?}");
}

/// Mitsuba's `integrator_depth_1`/`_2` see the Cornell box's luminaire directly (emission
/// `400:0, 500:8, 600:15.6, 700:18.4`); their residual disagreement (relMSE 4e-6/1e-5) is
/// Mitsuba's wavelength noise: at 256 spp its fully covered luminaire pixels scatter by 1 % (red)
/// and 3.7 % (blue) per pixel and their mean sits within one standard error of the emitter's CIE
/// colour, which gonio's matches to 2e-4 (64 × 64, 256 spp). The physics: where an emitter fills
/// a pixel, the image is the CIE 1931 colour of its spectrum, linear sRGB (20.714, 10.854, 2.771)
/// by Mitsuba 3.9.1's colour-matching functions (`testdata/mitsuba-corpus/probe_emitter_colour.py`).
/// Here a rectangle with that emission fills a 4 × 4 film at 64 spp (under a second).
#[test]
fn directly_seen_emitter_is_its_cie_colour() {
    let xml = r#"<scene version="3.0.0">
        <integrator type="path"><integer name="max_depth" value="1"/></integrator>
        <sensor type="perspective"><float name="fov" value="20"/>
            <transform name="to_world"><lookat origin="0, 0, 3" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
            <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/>
                <rfilter type="box"/></film></sensor>
        <shape type="rectangle"><emitter type="area">
            <spectrum name="radiance" value="400:0, 500:8, 600:15.6, 700:18.4"/></emitter></shape>
    </scene>"#;
    let scene = gonio_render::xml::load_scene_str(xml, ".", &[]).expect("scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let options = RenderOptions::from_scene(&prepared.scene);
    let img = render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false))
        .channels
        .rgb();
    let expected = [20.714107, 10.854321, 2.771119];
    for (c, e) in expected.iter().enumerate() {
        let mean = img.data.iter().map(|p| p[c] as f64).sum::<f64>() / img.data.len() as f64;
        assert!((mean / e - 1.0).abs() < 1e-3, "channel {c}: {mean} vs {e}");
    }
}
