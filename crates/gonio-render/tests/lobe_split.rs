//! Lobe splitting at rough glass (`split_escapes`, `integrator/lobe_split.rs`) against the path
//! tracer's Fresnel choice (Mitsuba's way).
//!
//! A rough glass cube and sphere (α = 0.02, as Mitsuba's `bsdf_roughdielectric_glass` preview)
//! under the preview's environment map: the environment reflected by the glass, and light
//! leaving the glass after bouncing inside it, are found on every visit instead of when the
//! Fresnel coin says so. Both estimators are unbiased: the image means agree (four standard
//! errors of independent renders), and the pixels' variance is lower with splitting.

use crate::render_stats::{prepare, same_mean_less_noise};

fn scene(split: bool) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path"><boolean name="split_escapes" value="{split}"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 1.6, 3" target="0, 0.5, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="cube">
        <transform name="to_world"><scale value="0.5"/><rotate y="1" angle="30"/><translate x="-0.7" y="0.5"/></transform>
        <bsdf type="roughdielectric"><float name="alpha" value="0.02"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="0.7, 0.6, 0.3"/><float name="radius" value="0.6"/>
        <bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.02"/></bsdf>
    </shape>
    <emitter type="envmap">
        <string name="filename" value="../../testdata/mitsuba-corpus/common/textures/museum.exr"/>
        <transform name="to_world"><rotate x="1" angle="-90"/></transform>
    </emitter>
</scene>"#
    )
}

/// Split and not: the same image mean within four standard errors, and the pixels' variance at
/// most 0.8 times the one without (measured 0.65).
#[test]
fn split_escapes_keeps_the_expectation_of_rough_glass() {
    let on = prepare(&scene(true), false);
    let off = prepare(&scene(false), false);
    assert!(on.scene.integrator.split_escapes && !off.scene.integrator.split_escapes);
    same_mean_less_noise(&on, &off, 16, "rough glass under the museum", 0.8);
}

/// Without a light at infinity nothing can be gained from an escape, and no ray is traced for
/// one: the same scene under a lamp alone renders bit for bit the same with and without
/// splitting.
#[test]
fn split_escapes_stays_off_without_a_light_at_infinity() {
    let lamp = r#"<shape type="rectangle">
        <transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="3"/></transform>
        <emitter type="area"><rgb name="radiance" value="10"/></emitter>
    </shape>"#;
    let without_sky = |split: bool| {
        let xml = scene(split);
        let start = xml.find("    <emitter type=\"envmap\">").unwrap();
        format!("{}{lamp}\n</scene>", &xml[..start])
    };
    let (on, off) = (
        prepare(&without_sky(true), false),
        prepare(&without_sky(false), false),
    );
    assert!(on.lights().infinite().is_empty());
    let a = crate::render_stats::green(&on, 8, 3);
    let b = crate::render_stats::green(&off, 8, 3);
    assert!(a.iter().any(|&v| v > 0.0), "the lamp lights the glass");
    assert_eq!(a, b);
}
