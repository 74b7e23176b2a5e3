//! The integrator plugins as the reader builds them: Mitsuba's differentiable and volumetric
//! integrators as the path tracers they are for a forward render, and the settings
//! `--mitsuba-estimators` restores (and those it leaves alone).

use super::{data, load};
use gonio_render::material::BlendMaterial;
use gonio_render::scene::EmitterDesc;
use gonio_render::xml::load_scene_str;

/// Mitsuba's differentiable integrators render their primal image: `prb`, `prb_basic` and
/// `prb_projective` as the path tracer with Mitsuba's default depth 6, `direct_projective` as
/// `direct`; their derivative-only parameters are read and checked.
#[test]
fn differentiable_integrators_are_their_primal_integrators() {
    let path6 =
        load("<integrator type=\"path\"><integer name=\"max_depth\" value=\"6\"/></integrator>").integrator;
    for ty in ["prb", "prb_basic", "prb_projective"] {
        assert_eq!(
            load(&format!("<integrator type=\"{ty}\"/>")).integrator,
            path6,
            "{ty}"
        );
    }
    let custom = load(
        "<integrator type=\"prb_projective\"><integer name=\"max_depth\" value=\"3\"/><integer name=\"rr_depth\" value=\"2\"/>\
         <boolean name=\"hide_emitters\" value=\"true\"/><integer name=\"sppc\" value=\"4\"/><string name=\"guiding\" value=\"grid\"/>\
         <string name=\"project_seed\" value=\"bsdf\"/></integrator>",
    )
    .integrator;
    assert_eq!(
        (custom.max_depth, custom.rr_depth, custom.hide_emitters),
        (3, 2, true)
    );
    let direct = load("<integrator type=\"direct\"/>").integrator;
    assert_eq!(
        load("<integrator type=\"direct_projective\"/>").integrator,
        direct
    );
    for bad in [
        "<integrator type=\"prb\"><integer name=\"sppc\" value=\"4\"/></integrator>",
        "<integrator type=\"prb_projective\"><string name=\"guiding\" value=\"tree\"/></integrator>",
        "<integrator type=\"direct_projective\"><string name=\"project_seed\" value=\"all\"/></integrator>",
        "<integrator type=\"prb\"><integer name=\"rr_depth\" value=\"0\"/></integrator>",
    ] {
        let text = format!(
            "<scene version=\"3.0.0\"><sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>{bad}</scene>"
        );
        assert!(load_scene_str(&text, data(), &[]).is_err(), "{bad}");
    }
}

/// Mitsuba's volumetric path tracers are the path tracer's settings marked volumetric (media
/// take part where the scene has them, `tests/media.rs`): `volpath` and `volpathmis` with
/// `path`'s defaults, `prbvolpath` with the differentiable integrators' depth 6.
#[test]
fn volumetric_path_tracers_take_the_path_tracers_settings() {
    let path = load("<integrator type=\"path\"/>").integrator;
    assert!(!path.volumetric);
    let volumetric = |text: &str| {
        let mut i = load(text).integrator;
        assert!(i.volumetric, "{text}");
        i.volumetric = false;
        i
    };
    for ty in ["volpath", "volpathmis"] {
        assert_eq!(volumetric(&format!("<integrator type=\"{ty}\"/>")), path, "{ty}");
    }
    let path6 =
        load("<integrator type=\"path\"><integer name=\"max_depth\" value=\"6\"/></integrator>").integrator;
    assert_eq!(volumetric("<integrator type=\"prbvolpath\"/>"), path6);
    let custom = volumetric(
        "<integrator type=\"volpath\"><integer name=\"max_depth\" value=\"12\"/><integer name=\"rr_depth\" value=\"3\"/>\
         <boolean name=\"hide_emitters\" value=\"true\"/></integrator>",
    );
    assert_eq!(
        (custom.max_depth, custom.rr_depth, custom.hide_emitters),
        (12, 3, true)
    );
}

/// `LoadOptions::mitsuba_estimators` (`gonio render --mitsuba-estimators`) turns every default of
/// ours that departs from Mitsuba's estimator to Mitsuba's value, and only the defaults: a value
/// written in the scene still wins.
#[test]
fn mitsuba_estimators_restore_mitsubas_defaults_only() {
    use gonio_core::bsdfs::roughplastic::CoatAverages;
    use gonio_core::fresnel::fresnel_diffuse_reflectance_fit;
    use gonio_render::material::plastic::PlasticMaterial;
    use gonio_render::material::roughplastic::RoughPlasticMaterial;
    use gonio_render::xml::{LoadOptions, load_scene_file_with};
    let scene = |integrator: &str, coat: &str, delta: &str| {
        format!(
            r#"<scene version="3.0.0">
                 <integrator type="path">{integrator}</integrator>
                 <bsdf type="roughplastic" id="rp">{coat}</bsdf>
                 <bsdf type="plastic" id="pl">{coat}</bsdf>
                 <bsdf type="blendbsdf" id="bl"><float name="weight" value="0.5"/>{delta}
                   <bsdf type="diffuse"/><bsdf type="conductor"/></bsdf>
                 <shape type="sphere"><ref id="rp"/></shape>
                 <shape type="sphere"><ref id="bl"/></shape>
                 <shape type="sphere"><ref id="pl"/></shape>
               </scene>"#
        )
    };
    let dir = std::env::temp_dir().join(format!("gonio-mitsuba-estimators-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let load = |text: String, mitsuba: bool| {
        let path = dir.join("scene.xml");
        std::fs::write(&path, text).unwrap();
        let options = LoadOptions {
            mitsuba_estimators: mitsuba,
            ..LoadOptions::default()
        };
        let s = load_scene_file_with(&path, &options).unwrap().scene;
        let coat = s
            .materials
            .iter()
            .find_map(|m| m.get::<RoughPlasticMaterial>())
            .unwrap()
            .model
            .coat
            .averages();
        let delta = s
            .materials
            .iter()
            .find_map(|m| m.get::<BlendMaterial>())
            .unwrap()
            .mitsuba_delta_pdf;
        // `plastic`'s averages are Mitsuba's when its r̃ is the polynomial fit.
        let plastic = &s
            .materials
            .iter()
            .find_map(|m| m.get::<PlasticMaterial>())
            .unwrap()
            .model;
        let fits = plastic.fdr_int() == fresnel_diffuse_reflectance_fit(1.0 / plastic.eta());
        assert_eq!(
            fits,
            coat == CoatAverages::Mitsuba,
            "plastic follows roughplastic"
        );
        (s.integrator.thin_shadows, s.integrator.caustic_paths, coat, delta)
    };
    let bare = scene("", "", "");
    assert_eq!(
        load(bare.clone(), false),
        (true, true, CoatAverages::Exact, false)
    );
    assert_eq!(load(bare, true), (false, false, CoatAverages::Mitsuba, true));
    let written = scene(
        r#"<boolean name="thin_shadows" value="true"/><boolean name="caustic_paths" value="true"/>"#,
        r#"<string name="coat_averages" value="exact"/>"#,
        r#"<string name="delta_pdf" value="exact"/>"#,
    );
    assert_eq!(load(written, true), (true, true, CoatAverages::Exact, false));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The environment map's estimator switches of ours (`mis_compensation`, Mitsuba's parameter
/// with our default, and `product_sampling`) are on by default, off under
/// `LoadOptions::mitsuba_estimators`, and what the scene writes either way.
#[test]
fn envmap_estimator_switches_follow_mitsuba_estimators() {
    use gonio_render::image::RgbImage;
    use gonio_render::xml::{LoadOptions, load_scene_file_with};
    let dir = std::env::temp_dir().join(format!("gonio-envmap-switches-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    RgbImage::from_fn(8, 4, |x, y| [0.1 * (x + y) as f32; 3])
        .write_exr(dir.join("sky.exr"))
        .unwrap();
    let load = |params: &str, mitsuba: bool| {
        let path = dir.join("scene.xml");
        let text = format!(
            r#"<scene version="3.0.0"><emitter type="envmap"><string name="filename" value="sky.exr"/>{params}</emitter></scene>"#
        );
        std::fs::write(&path, text).unwrap();
        let options = LoadOptions {
            mitsuba_estimators: mitsuba,
            ..LoadOptions::default()
        };
        match &load_scene_file_with(&path, &options).unwrap().scene.emitters[..] {
            [
                EmitterDesc::EnvMap {
                    mis_compensation,
                    product_sampling,
                    ..
                },
            ] => (*mis_compensation, *product_sampling),
            other => panic!("{other:?}"),
        }
    };
    assert_eq!(load("", false), (true, true));
    assert_eq!(load("", true), (false, false));
    let on =
        r#"<boolean name="mis_compensation" value="true"/><boolean name="product_sampling" value="true"/>"#;
    let off =
        r#"<boolean name="mis_compensation" value="false"/><boolean name="product_sampling" value="false"/>"#;
    assert_eq!(load(on, true), (true, true));
    assert_eq!(load(off, false), (false, false));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `prb` and its relatives render as the path tracer, so they take the path tracer's estimator
/// defaults too: ours, and under `LoadOptions::mitsuba_estimators` every one of Mitsuba's (the
/// same as `path` then), keeping their own depth.
#[test]
fn differentiable_integrators_follow_mitsuba_estimators() {
    use gonio_render::scene::IntegratorDesc;
    use gonio_render::xml::{LoadOptions, load_scene_file_with};
    let dir = std::env::temp_dir().join(format!("gonio-prb-estimators-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let load = |ty: &str, mitsuba: bool| -> IntegratorDesc {
        let path = dir.join("scene.xml");
        std::fs::write(
            &path,
            format!(r#"<scene version="3.0.0"><integrator type="{ty}"><integer name="max_depth" value="6"/></integrator></scene>"#),
        )
        .unwrap();
        let options = LoadOptions {
            mitsuba_estimators: mitsuba,
            ..LoadOptions::default()
        };
        load_scene_file_with(&path, &options).unwrap().scene.integrator
    };
    for mitsuba in [false, true] {
        let path = load("path", mitsuba);
        for ty in ["prb", "prb_basic", "prb_projective"] {
            assert_eq!(load(ty, mitsuba), path, "{ty}, Mitsuba's estimators: {mitsuba}");
        }
    }
    let mitsuba = load("prb", true);
    assert_eq!(
        (
            mitsuba.thin_shadows,
            mitsuba.caustic_paths,
            mitsuba.refracted_nee,
            mitsuba.manifold_nee,
            mitsuba.split_escapes,
            mitsuba.split_visible_glass,
            mitsuba.split_lights,
            mitsuba.narrow_lobes,
            mitsuba.rr_survival
        ),
        (false, false, false, false, false, false, 0, false, 0.95)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
