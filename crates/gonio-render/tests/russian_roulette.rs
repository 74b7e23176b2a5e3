//! Russian roulette: its survival cap (`rr_survival`, ours: 0.99; Mitsuba's fixed 0.95) and the
//! factor of the throughput in its probability (`rr_scale`, ours: 4; Mitsuba's 1).
//!
//! Light that enters a block of rough glass is trapped by total internal reflection: its
//! throughput stays near one for dozens of bounces, so Russian roulette continues it with the
//! capped probability q_max and a survivor of n roulettes carries q_max⁻ⁿ. At 0.95 the rare
//! paths that escape after 50 bounces arrive 13× too bright (the fireflies of Mitsuba's
//! `bsdf_roughdielectric_glass` preview); at 0.99, 1.7×. Both are unbiased: the image means
//! agree (four standard errors of independent renders) and the pixels' variance is lower with
//! the higher cap.

use crate::render_stats::{prepare, same_mean_less_noise};
use gonio_render::scene::IntegratorDesc;
use gonio_render::xml::{LoadOptions, load_scene_file_with};

/// The cube under a lamp and a dim sky; lobe splitting off, so that the roulette alone decides
/// where trapped light leaves (with it, light leaves at every exit it meets and the two caps
/// differ less).
fn scene(rr_survival: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path"><boolean name="split_escapes" value="false"/>{rr_survival}</integrator>
    <sensor type="perspective">
        <float name="fov" value="35"/>
        <transform name="to_world"><lookat origin="2.2, 1.8, 3" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="20"/><integer name="height" value="20"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="cube">
        <transform name="to_world"><rotate y="1" angle="20"/></transform>
        <bsdf type="roughdielectric">
            <string name="distribution" value="beckmann"/>
            <float name="alpha" value="0.03"/>
        </bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.4"/><rotate x="1" angle="90"/><translate x="0.5" y="3" z="0.3"/></transform>
        <emitter type="area"><rgb name="radiance" value="20"/></emitter>
    </shape>
    <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
</scene>"#
    )
}

/// The cap at 0.99 and at Mitsuba's 0.95: the same image mean, and at most 0.4 times the
/// pixels' variance (measured 0.16).
#[test]
fn rr_survival_keeps_trapped_light_from_becoming_fireflies() {
    let high = prepare(&scene(""), false);
    let mitsuba = prepare(&scene(r#"<float name="rr_survival" value="0.95"/>"#), false);
    assert_eq!(high.scene.integrator.rr_survival, 0.99);
    same_mean_less_noise(&high, &mitsuba, 16, "light trapped in a rough glass cube", 0.4);
}

/// `--mitsuba-estimators` restores Mitsuba's 0.95; a cap of 1 (paths that never end in a white
/// furnace) or a NaN is refused with the file, line and value.
#[test]
fn rr_survival_defaults_and_refusals() {
    float_row_defaults_and_refusals(
        "rr_survival",
        |i| i.rr_survival,
        (0.99, 0.95),
        &["1", "0", "nan", "-0.5"],
    );
}

/// The `path` row `name` (read from the integrator by `get`): `defaults` (ours, Mitsuba's under
/// `--mitsuba-estimators`) when the scene does not write it, and each of `bad` refused with the
/// file, the line and the value.
fn float_row_defaults_and_refusals(
    name: &str,
    get: fn(&IntegratorDesc) -> f32,
    defaults: (f32, f32),
    bad: &[&str],
) {
    let dir = std::env::temp_dir().join(format!("gonio-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.xml");
    let load = |xml: &str, mitsuba: bool| {
        std::fs::write(&path, xml).unwrap();
        let options = LoadOptions {
            mitsuba_estimators: mitsuba,
            ..LoadOptions::default()
        };
        load_scene_file_with(&path, &options).map(|s| get(&s.scene.integrator))
    };
    let plain = r#"<scene version="3.0.0"><integrator type="path"/></scene>"#;
    assert_eq!(load(plain, false).unwrap(), defaults.0);
    assert_eq!(load(plain, true).unwrap(), defaults.1);
    for bad in bad {
        let xml = format!(
            "<scene version=\"3.0.0\">\n<integrator type=\"path\">\n<float name=\"{name}\" value=\"{bad}\"/>\n</integrator></scene>"
        );
        let e = load(&xml, false).unwrap_err().to_string();
        assert!(
            e.contains("scene.xml") && e.contains(":3") && e.contains(name) && e.to_lowercase().contains(bad),
            "{bad}: {e}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A room of dark grey walls (albedo 0.25) lit by a small lamp, roulette from the first bounce:
/// most of a pixel's light arrives after several bounces, each of which a throughput-only
/// roulette (`rr_scale` 1) kills with probability ¾.
fn dark_room(rr_scale: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path"><integer name="rr_depth" value="1"/>{rr_scale}</integrator>
    <sensor type="perspective">
        <float name="fov" value="60"/>
        <transform name="to_world"><lookat origin="0, 0, 0.8" target="0, -0.2, -1" up="0, 1, 0"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="cube">
        <boolean name="flip_normals" value="true"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.25"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.15"/><rotate x="1" angle="90"/><translate y="0.99"/></transform>
        <emitter type="area"><rgb name="radiance" value="40"/></emitter>
    </shape>
</scene>"#
    )
}

/// `rr_scale` 4 (ours) against Mitsuba's 1: the same image mean, and at most 0.3 times the
/// pixels' variance (measured 0.12) for paths that go on while their throughput is above ¼.
#[test]
fn rr_scale_keeps_dark_rooms_from_losing_their_bounces() {
    let ours = prepare(&dark_room(""), false);
    let mitsuba = prepare(&dark_room(r#"<float name="rr_scale" value="1"/>"#), false);
    assert_eq!(ours.scene.integrator.rr_scale, 4.0);
    same_mean_less_noise(
        &ours,
        &mitsuba,
        16,
        "a dark room, roulette from the first bounce",
        0.3,
    );
}

/// `--mitsuba-estimators` restores Mitsuba's 1; zero, a negative number, a NaN or an infinity
/// is refused with the file, line and value.
#[test]
fn rr_scale_defaults_and_refusals() {
    float_row_defaults_and_refusals("rr_scale", |i| i.rr_scale, (4.0, 1.0), &["0", "-1", "nan", "inf"]);
}
