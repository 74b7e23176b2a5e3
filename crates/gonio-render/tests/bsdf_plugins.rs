//! The BSDF plugin registry: the reader's errors come from it, and every plugin's per-hit value
//! equals its any-wavelength BSDF. The table checks and `docs/plugins.md` for every kind,
//! BSDFs included, are in `tests/plugins.rs`.

use glam::{Vec2, Vec3};
use gonio_core::rng::Pcg32;
use gonio_core::{Bsdf, BsdfContext, SampledWavelengths};
use gonio_render::material::BSDF_PLUGINS;
use gonio_render::xml::{ErrorKind, load_bsdf_str};

#[test]
fn unknown_plugin_error_lists_the_registry() {
    let e = load_bsdf_str("<bsdf type=\"velvet\"/>").unwrap_err();
    assert_eq!(e.kind, ErrorKind::UnknownPlugin);
    for plugin in BSDF_PLUGINS {
        assert!(e.to_string().contains(plugin.name), "{e}");
    }
}

#[test]
fn hair_refuses_what_mitsuba_refuses() {
    // Mitsuba 3.9.1 throws for each: pigments with `sigma_a`, equal indices, a roughness outside
    // [0, 1]; gonio names the line and the value.
    let cases = [
        (
            r#"<bsdf type="hair"><float name="eumelanin" value="0.5"/><rgb name="sigma_a" value="0.2, 0.3, 0.4"/></bsdf>"#,
            ErrorKind::Grammar,
            "either the pigments or `sigma_a`",
        ),
        (
            r#"<bsdf type="hair"><float name="int_ior" value="1.2"/><float name="ext_ior" value="1.2"/></bsdf>"#,
            ErrorKind::BadValue,
            "indices must differ",
        ),
        (
            r#"<bsdf type="hair"><float name="azimuthal_roughness" value="1.5"/></bsdf>"#,
            ErrorKind::BadValue,
            "azimuthal_roughness 1.5",
        ),
        (
            r#"<bsdf type="hair"><float name="pheomelanin" value="-1"/></bsdf>"#,
            ErrorKind::BadValue,
            "pheomelanin -1",
        ),
    ];
    for (text, kind, words) in cases {
        let e = load_bsdf_str(text).unwrap_err();
        assert_eq!(e.kind, kind, "{text}: {e}");
        let msg = e.to_string();
        assert!(msg.contains(words) && msg.contains(":1:"), "{text}: {msg}");
    }
}

#[test]
fn unused_parameter_error_lists_the_accepted_names() {
    let e =
        load_bsdf_str("<bsdf type=\"plastic\"><float name=\"int_iro\" value=\"1.5\"/></bsdf>").unwrap_err();
    assert_eq!(e.kind, ErrorKind::UnusedParameter);
    let msg = e.to_string();
    assert!(
        msg.contains("int_iro") && msg.contains("it accepts: diffuse_reflectance, nonlinear, int_ior"),
        "{msg}"
    );
}

#[test]
fn materials_nesting_more_than_a_hit_can_hold_are_refused() {
    // blend(blend(d, d), blend(d, d)) has 7 nodes: accepted; one more level of blends (15) is not.
    let leaf = "<bsdf type=\"diffuse\"/>";
    let blend = |a: &str, b: &str| {
        format!("<bsdf type=\"blendbsdf\"><float name=\"weight\" value=\"0.5\"/>{a}{b}</bsdf>")
    };
    let seven = blend(&blend(leaf, leaf), &blend(leaf, leaf));
    assert!(load_bsdf_str(&seven).is_ok());
    let fifteen = blend(&seven, &seven);
    let e = load_bsdf_str(&fifteen).unwrap_err();
    assert_eq!(e.kind, ErrorKind::BadValue);
    assert!(e.to_string().contains("at most 8"), "{e}");
}

/// For textured and untextured instances of every plugin, the per-hit `Copy` value
/// (`Material::bsdf_at`) and the any-wavelength BSDF (`Material::with_bsdf`) agree bit for bit.
#[test]
fn per_hit_value_equals_the_any_wavelength_bsdf() {
    let scenes = [
        "<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"0.2, 0.5, 0.9\"/></bsdf>",
        "<bsdf type=\"conductor\"><string name=\"material\" value=\"Au\"/></bsdf>",
        "<bsdf type=\"conductor\"><texture name=\"specular_reflectance\" type=\"checkerboard\"/></bsdf>",
        "<bsdf type=\"dielectric\"><string name=\"int_ior\" value=\"SF11\"/></bsdf>",
        "<bsdf type=\"thindielectric\"><texture name=\"specular_transmittance\" type=\"checkerboard\"/></bsdf>",
        "<bsdf type=\"plastic\"><texture name=\"diffuse_reflectance\" type=\"checkerboard\"/><boolean name=\"nonlinear\" value=\"true\"/></bsdf>",
        "<bsdf type=\"twosided\"><bsdf type=\"diffuse\"/><bsdf type=\"plastic\"/></bsdf>",
        "<bsdf type=\"roughconductor\"><string name=\"material\" value=\"Cu\"/><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha_u\" value=\"0.05\"/><float name=\"alpha_v\" value=\"0.3\"/></bsdf>",
        "<bsdf type=\"roughconductor\"><texture name=\"alpha\" type=\"checkerboard\"><float name=\"color0\" value=\"0.02\"/><float name=\"color1\" value=\"0.6\"/></texture><texture name=\"specular_reflectance\" type=\"checkerboard\"/><boolean name=\"sample_visible\" value=\"false\"/></bsdf>",
        "<bsdf type=\"roughdiffuse\"/>",
        "<bsdf type=\"roughdiffuse\"><string name=\"model\" value=\"microfacet\"/><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"0.8\"/></bsdf>",
        "<bsdf type=\"roughdiffuse\"><texture name=\"alpha\" type=\"checkerboard\"><float name=\"color0\" value=\"0\"/><float name=\"color1\" value=\"0.9\"/></texture><rgb name=\"reflectance\" value=\"0.7, 0.4, 0.2\"/><boolean name=\"useFastApprox\" value=\"true\"/></bsdf>",
        "<bsdf type=\"roughplastic\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"0.3\"/><boolean name=\"nonlinear\" value=\"true\"/></bsdf>",
        "<bsdf type=\"roughplastic\"><texture name=\"diffuse_reflectance\" type=\"checkerboard\"/><texture name=\"specular_reflectance\" type=\"checkerboard\"/><boolean name=\"sample_visible\" value=\"false\"/><string name=\"coat_averages\" value=\"mitsuba\"/></bsdf>",
        "<bsdf type=\"pplastic\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha_u\" value=\"0.3\"/><float name=\"alpha_v\" value=\"0.05\"/><rgb name=\"diffuse_reflectance\" value=\"0.05, 0.03, 0.1\"/></bsdf>",
        "<bsdf type=\"pplastic\"><texture name=\"diffuse_reflectance\" type=\"checkerboard\"/><texture name=\"specular_reflectance\" type=\"checkerboard\"/><boolean name=\"sample_visible\" value=\"false\"/></bsdf>",
        "<bsdf type=\"roughdielectric\"><string name=\"int_ior\" value=\"SF11\"/><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha_u\" value=\"0.05\"/><float name=\"alpha_v\" value=\"0.3\"/></bsdf>",
        "<bsdf type=\"roughdielectric\"><texture name=\"alpha\" type=\"checkerboard\"><float name=\"color0\" value=\"0.02\"/><float name=\"color1\" value=\"0.6\"/></texture><texture name=\"specular_transmittance\" type=\"checkerboard\"/><boolean name=\"sample_visible\" value=\"false\"/></bsdf>",
        "<bsdf type=\"principled\"><rgb name=\"base_color\" value=\"0.8, 0.3, 0.1\"/><float name=\"metallic\" value=\"0.3\"/><float name=\"spec_trans\" value=\"0.4\"/><float name=\"anisotropic\" value=\"0.5\"/><float name=\"spec_tint\" value=\"0.4\"/><float name=\"sheen\" value=\"0.5\"/><float name=\"sheen_tint\" value=\"0.5\"/><float name=\"clearcoat\" value=\"0.7\"/><float name=\"flatness\" value=\"0.3\"/></bsdf>",
        "<bsdf type=\"principled\"><texture name=\"base_color\" type=\"checkerboard\"/><texture name=\"roughness\" type=\"checkerboard\"><float name=\"color0\" value=\"0.05\"/><float name=\"color1\" value=\"0.7\"/></texture><texture name=\"metallic\" type=\"checkerboard\"/><float name=\"eta\" value=\"1.33\"/></bsdf>",
        "<bsdf type=\"principledthin\"><rgb name=\"base_color\" value=\"0.7, 0.1, 0.1\"/><float name=\"roughness\" value=\"0.15\"/><float name=\"spec_tint\" value=\"0.1\"/><float name=\"anisotropic\" value=\"0.5\"/><float name=\"spec_trans\" value=\"0.8\"/><float name=\"diff_trans\" value=\"0.3\"/><float name=\"eta\" value=\"1.33\"/><float name=\"sheen\" value=\"0.4\"/></bsdf>",
        "<bsdf type=\"principledthin\"><texture name=\"base_color\" type=\"checkerboard\"/><texture name=\"diff_trans\" type=\"checkerboard\"><float name=\"color0\" value=\"0.2\"/><float name=\"color1\" value=\"1.8\"/></texture><texture name=\"eta\" type=\"checkerboard\"><float name=\"color0\" value=\"1.2\"/><float name=\"color1\" value=\"1.6\"/></texture><float name=\"spec_trans\" value=\"0.5\"/></bsdf>",
        "<bsdf type=\"hair\"/>",
        "<bsdf type=\"hair\"><float name=\"eumelanin\" value=\"0.2\"/><float name=\"pheomelanin\" value=\"0.8\"/><float name=\"longitudinal_roughness\" value=\"0.15\"/><float name=\"azimuthal_roughness\" value=\"0.6\"/><float name=\"scale_tilt\" value=\"4\"/><float name=\"int_ior\" value=\"1.6\"/></bsdf>",
        "<bsdf type=\"hair\"><texture name=\"sigma_a\" type=\"checkerboard\"/><float name=\"scale\" value=\"3\"/></bsdf>",
        "<bsdf type=\"lambertsphere\"><rgb name=\"reflectance\" value=\"0.2, 0.5, 0.9\"/></bsdf>",
        "<bsdf type=\"lambertsphere\"><texture name=\"sphere_albedo\" type=\"checkerboard\"/><string name=\"model\" value=\"practical\"/></bsdf>",
        "<bsdf type=\"blendbsdf\"><texture name=\"weight\" type=\"checkerboard\"/><bsdf type=\"twosided\"><bsdf type=\"conductor\"/></bsdf><bsdf type=\"dielectric\"/></bsdf>",
        "<bsdf type=\"polarizer\"><float name=\"theta\" value=\"30\"/><texture name=\"transmittance\" type=\"checkerboard\"/></bsdf>",
        "<bsdf type=\"retarder\"><float name=\"theta\" value=\"45\"/><float name=\"delta\" value=\"180\"/><texture name=\"transmittance\" type=\"checkerboard\"/></bsdf>",
        "<bsdf type=\"circular\"><boolean name=\"left_handed\" value=\"true\"/><texture name=\"transmittance\" type=\"checkerboard\"/></bsdf>",
        "<bsdf type=\"null\"/>",
        "<bsdf type=\"mask\"><texture name=\"opacity\" type=\"checkerboard\"/><bsdf type=\"twosided\"><bsdf type=\"roughconductor\"/></bsdf></bsdf>",
        "<bsdf type=\"normalmap\"><float name=\"normalmap\" value=\"0.8\"/><bsdf type=\"plastic\"/></bsdf>",
        "<bsdf type=\"bumpmap\"><float name=\"scale\" value=\"0.5\"/><texture name=\"h\" type=\"checkerboard\"/><bsdf type=\"diffuse\"/></bsdf>",
    ];
    let mut rng = Pcg32::new(11, 5);
    let mut dir = || {
        let z: f32 = 2.0 * rng.next_f32() - 1.0;
        let phi = std::f32::consts::TAU * rng.next_f32();
        let s = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(s * phi.cos(), s * phi.sin(), z)
    };
    let mut u = Pcg32::new(3, 9);
    for text in scenes {
        let m = load_bsdf_str(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        for k in 0..300 {
            let uv = Vec2::new((k % 17) as f32 / 17.0, (k % 13) as f32 / 13.0);
            let wl = SampledWavelengths::sample_visible(u.next_f32());
            let (wi, wo) = (dir(), dir());
            let (u1, u2) = (u.next_f32(), Vec2::new(u.next_f32(), u.next_f32()));
            let hit = m.bsdf_at(uv, &wl);
            m.with_bsdf(uv, |any: &dyn Bsdf| {
                assert_eq!(hit.flags(), any.flags(), "{text}");
                for ctx in [BsdfContext::radiance(), BsdfContext::importance()] {
                    assert_eq!(hit.eval(&ctx, wi, wo, &wl), any.eval(&ctx, wi, wo, &wl), "{text}");
                    assert_eq!(hit.pdf(&ctx, wi, wo, &wl), any.pdf(&ctx, wi, wo, &wl), "{text}");
                    let (mut a, mut b) = (wl, wl);
                    assert_eq!(
                        hit.sample(&ctx, wi, u1, u2, &mut a),
                        any.sample(&ctx, wi, u1, u2, &mut b),
                        "{text}"
                    );
                    assert_eq!(a, b);
                    assert_eq!(
                        hit.null_transmission(wi, &wl),
                        any.null_transmission(wi, &wl),
                        "{text}"
                    );
                    // The polarized values too (Mueller matrices and their frames).
                    assert_eq!(
                        hit.eval_mueller(&ctx, wi, wo, &wl),
                        any.eval_mueller(&ctx, wi, wo, &wl),
                        "{text}"
                    );
                    let (mut a, mut b) = (wl, wl);
                    assert_eq!(
                        hit.sample_mueller(&ctx, wi, u1, u2, &mut a),
                        any.sample_mueller(&ctx, wi, u1, u2, &mut b),
                        "{text}"
                    );
                    assert_eq!(
                        hit.null_transmission_mueller(wi, &wl),
                        any.null_transmission_mueller(wi, &wl),
                        "{text}"
                    );
                }
            });
        }
    }
}
