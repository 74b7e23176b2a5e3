//! Every light sampled at each vertex (`split_lights`, `emitter::Lights::with_split`) against one
//! light chosen per vertex (Mitsuba's way).
//!
//! A diffuse floor with a sphere on it under two lights: a sun (`directional`, a delta light no
//! BSDF sample finds) and a sky (`constant`), and a small rectangle light and the sky. Every
//! estimator is unbiased, so with and without splitting the image means agree (four standard
//! errors of the means of independent renders); with it the noise of choosing between the
//! lights is gone, and the pixels' variance is lower.

use crate::render_stats::{prepare, same_mean_less_noise};

const SUN: &str = r#"<emitter type="directional">
        <vector name="direction" value="-0.5, -0.8, -0.3"/><rgb name="irradiance" value="3"/>
    </emitter>"#;
const LAMP: &str = r#"<shape type="rectangle">
        <transform name="to_world"><scale value="0.3"/><rotate x="1" angle="90"/><translate x="0.8" y="2.5" z="0.4"/></transform>
        <emitter type="area"><rgb name="radiance" value="12"/></emitter>
    </shape>"#;

fn scene(split: u32, light: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path">
        <integer name="max_depth" value="4"/>
        <integer name="split_lights" value="{split}"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 2.5, 4" target="0, 0.3, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="10"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="0, 0.6, 0"/><float name="radius" value="0.6"/>
        <bsdf type="roughplastic"><float name="alpha" value="0.2"/></bsdf>
    </shape>
    <emitter type="constant"><rgb name="radiance" value="0.4"/></emitter>
    {light}
</scene>"#
    )
}

/// Split and not: the same image mean within four standard errors, and the pixels' variance at
/// most `gain` times the one without (measured 0.34 under the sun, 0.43 under the lamp; with the
/// lights' choice probability left in the MIS weights of the BSDF samples, the means differ by
/// hundreds of standard errors).
fn same_expectation_less_noise(light: &str, what: &str, gain: f64) {
    let on = prepare(&scene(2, light), false);
    let off = prepare(&scene(0, light), false);
    assert!(on.lights().split() && !off.lights().split());
    same_mean_less_noise(&on, &off, 32, what, gain);
}

#[test]
fn split_lights_keeps_the_expectation_under_a_sun_and_a_sky() {
    same_expectation_less_noise(SUN, "sun and sky", 0.6);
}

#[test]
fn split_lights_keeps_the_expectation_under_a_lamp_and_a_sky() {
    same_expectation_less_noise(LAMP, "lamp and sky", 0.6);
}

/// One light, or more than `split_lights`: one light per vertex as before; the default is 2, and
/// `--mitsuba-estimators` restores Mitsuba's choice of one light per vertex.
#[test]
fn split_lights_applies_between_two_and_its_count() {
    let one = prepare(
        &scene(2, "").replace(
            r#"<emitter type="constant"><rgb name="radiance" value="0.4"/></emitter>"#,
            SUN,
        ),
        false,
    );
    assert!(!one.lights().split());
    let three = prepare(&scene(2, &format!("{SUN}{LAMP}")), false);
    assert!(!three.lights().split());
    let three_allowed = prepare(&scene(3, &format!("{SUN}{LAMP}")), false);
    assert!(three_allowed.lights().split());
    use gonio_render::xml::{LoadOptions, load_scene_file_with};
    let dir = std::env::temp_dir().join(format!("gonio-split-switch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let load = |mitsuba: bool| {
        let path = dir.join("scene.xml");
        std::fs::write(
            &path,
            r#"<scene version="3.0.0"><integrator type="path"/></scene>"#,
        )
        .unwrap();
        let options = LoadOptions {
            mitsuba_estimators: mitsuba,
            ..LoadOptions::default()
        };
        load_scene_file_with(&path, &options)
            .unwrap()
            .scene
            .integrator
            .split_lights
    };
    assert_eq!((load(false), load(true)), (2, 0));
    let _ = std::fs::remove_dir_all(&dir);
}
