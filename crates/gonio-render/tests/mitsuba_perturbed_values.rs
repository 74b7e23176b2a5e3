//! Agreement of `normalmap` (the perturbed-frame adapter `gonio_core::bsdfs::PerturbedFrame`)
//! with Mitsuba 3.9.1 (`testdata/mitsuba/reference/mitsuba-perturbed-values.json`, made by
//! `testdata/mitsuba/make_perturbed_values.py`): a constant map of three tilts around a
//! `diffuse` and an anisotropic GGX `roughconductor`, with `flip_invalid_normals` and
//! `use_shadowing_function` each on and off, at 32 pairs of directions (a quarter of them
//! grazing views, where the flip applies).
//!
//! Mitsuba's `eval` includes the cosine in the nested BSDF's (perturbed) frame and the
//! terminator's shadowing; gonio's `eval` times the unperturbed |cos θo| must equal it, within
//! 2e-4 relative (the map's 8-bit texel decoded the same way on both sides), and the pdf too. The
//! anisotropic nested model checks the perturbed tangent (Mitsuba 3.9.1: the shading frame's x
//! made orthogonal to n'); the grazing views check the flip; `use_shadowing_function` off checks
//! that the shadowing is all that differs.

use crate::mitsuba_json::{self, num, vec3};
use glam::Vec2;
use gonio_core::{BsdfContext, SampledWavelengths};
use gonio_render::xml::load_bsdf_str;

#[test]
fn normalmap_eval_and_pdf_agree_with_mitsuba() {
    let data = mitsuba_json::parse(include_str!(
        "../../../testdata/mitsuba/reference/mitsuba-perturbed-values.json"
    ));
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/mitsuba/reference/perturbed"
    );
    let nested = |name: &str| match name {
        "diffuse" => r#"<bsdf type="diffuse"><spectrum name="reflectance" value="0.5"/></bsdf>"#,
        "roughconductor-aniso" => {
            r#"<bsdf type="roughconductor"><string name="material" value="none"/><string name="distribution" value="ggx"/><float name="alpha_u" value="0.25"/><float name="alpha_v" value="0.05"/></bsdf>"#
        }
        other => panic!("unknown nested BSDF {other}"),
    };
    let (mut checked, mut lit, mut flipped_lit) = (0, 0, 0);
    let mut worst = 0.0f64;
    for config in data["configs"].as_array().unwrap() {
        let (flip, shadow) = (
            config["flip_invalid_normals"].as_bool().unwrap(),
            config["use_shadowing_function"].as_bool().unwrap(),
        );
        let xml = format!(
            r#"<bsdf version="3.0.0" type="normalmap">
                <boolean name="flip_invalid_normals" value="{flip}"/>
                <boolean name="use_shadowing_function" value="{shadow}"/>
                <texture name="normalmap" type="bitmap">
                    <string name="filename" value="{dir}/{}"/>
                    <boolean name="raw" value="true"/>
                    <string name="filter_type" value="nearest"/>
                </texture>
                {}
            </bsdf>"#,
            config["png"].as_str().unwrap(),
            nested(config["nested"].as_str().unwrap())
        );
        let what = format!(
            "{} {:?} flip {flip} shadowing {shadow}",
            config["nested"], config["texel"]
        );
        let material = load_bsdf_str(&xml).unwrap_or_else(|e| panic!("{what}: {e}"));
        let wl = SampledWavelengths::fixed(550.0);
        for q in config["values"].as_array().unwrap() {
            let (wi, wo) = (vec3(&q["wi"]), vec3(&q["wo"]));
            let (f, pdf) = material.with_bsdf(Vec2::splat(0.5), |b| {
                b.eval_pdf(&BsdfContext::radiance(), wi, wo, &wl)
            });
            let g = f[0] as f64 * wo.z.abs() as f64;
            let (m, mpdf) = (num(q, "eval_cos"), num(q, "pdf"));
            assert!(
                (g - m).abs() <= 2e-4 * m.abs().max(1e-5),
                "{what}: eval·cos at wi {wi} wo {wo}: gonio {g} vs Mitsuba {m}"
            );
            assert!(
                (pdf as f64 - mpdf).abs() <= 2e-4 * mpdf.abs().max(1e-5),
                "{what}: pdf at wi {wi} wo {wo}: gonio {pdf} vs Mitsuba {mpdf}"
            );
            if m > 1e-4 {
                worst = worst.max((g / m - 1.0).abs());
                lit += 1;
                flipped_lit += usize::from(flip && wi.z < 0.25);
            }
            checked += 1;
        }
    }
    eprintln!(
        "normalmap vs Mitsuba 3.9.1: {checked} queries, {lit} lit, worst relative difference {worst:.2e}"
    );
    assert_eq!(checked, 24 * 32);
    // The data are not mostly black (460 of the 768 are lit), and the flip lights grazing views.
    assert!(
        lit > 400 && flipped_lit > 40,
        "{lit} lit, {flipped_lit} lit grazing views with the flip"
    );
}

/// An `<rgb>` map is its three values, as Mitsuba 3.9.1's RGB variants read it: rgb (0.7, 0.5,
/// 0.9) around `diffuse` (0.5), ωi = z, ωo = (0.6, 0, 0.8): Mitsuba `scalar_rgb` eval 0.155906
/// (its spectral variants give 0.125921, from the uplifted spectrum's coefficients read as RGB).
#[test]
fn an_rgb_normal_map_is_its_three_values() {
    let material = load_bsdf_str(
        r#"<bsdf version="3.0.0" type="normalmap"><rgb name="normalmap" value="0.7, 0.5, 0.9"/>
           <bsdf type="diffuse"><spectrum name="reflectance" value="0.5"/></bsdf></bsdf>"#,
    )
    .unwrap();
    let wl = SampledWavelengths::fixed(550.0);
    let wo = glam::Vec3::new(0.6, 0.0, 0.8);
    let f = material.with_bsdf(Vec2::splat(0.5), |b| {
        b.eval(&BsdfContext::radiance(), glam::Vec3::Z, wo, &wl)
    });
    let g = f[0] * wo.z;
    assert!((g - 0.155906).abs() < 2e-4 * 0.155906, "{g}");
}

/// Regression: Mitsuba's test scene `test_normalmap_identity_roughconductor_path.xml` writes its
/// constant map as a nested `<spectrum type="srgb">`, which gonio refused ("must be a bitmap
/// or a constant"). It is the same map as the `<rgb>` value, nested or referenced.
#[test]
fn normalmap_takes_an_srgb_spectrum_object_as_its_constant() {
    let with = |map: &str| {
        let xml = format!(
            r#"<scene version="3.0.0">
                <spectrum type="srgb" id="tilt"><rgb name="color" value="0.7, 0.5, 0.9"/></spectrum>
                <bsdf type="normalmap" id="m">{map}<bsdf type="roughconductor"/></bsdf>
                <shape type="sphere"><ref id="m"/></shape>
            </scene>"#
        );
        let s = gonio_render::xml::load_scene_str(&xml, std::path::PathBuf::from("."), &[])
            .unwrap_or_else(|e| panic!("{map}: {e}"));
        let wl = SampledWavelengths::fixed(550.0);
        let (wi, wo) = (
            glam::Vec3::new(0.3, 0.1, 0.95).normalize(),
            glam::Vec3::new(-0.2, 0.3, 0.93).normalize(),
        );
        s.materials[s.shapes[0].material].with_bsdf(Vec2::splat(0.5), |b| {
            b.eval_pdf(&BsdfContext::radiance(), wi, wo, &wl)
        })
    };
    let rgb = with(r#"<rgb name="normalmap" value="0.7, 0.5, 0.9"/>"#);
    let nested = with(
        r#"<spectrum name="normalmap" type="srgb"><rgb name="color" value="0.7, 0.5, 0.9"/></spectrum>"#,
    );
    let referenced = with(r#"<ref name="normalmap" id="tilt"/>"#);
    let raw = with(
        r#"<texture name="normalmap" type="rawconstant"><rgb name="value" value="0.7, 0.5, 0.9"/></texture>"#,
    );
    assert_eq!(raw, rgb, "a rawconstant colour is the same map");
    let flat = with(r#"<rgb name="normalmap" value="0.5, 0.5, 1"/>"#);
    assert!(rgb.1 > 0.0 && rgb != flat, "the tilt changes the frame");
    assert_eq!(nested, rgb);
    assert_eq!(referenced, rgb);
}
