//! Russian roulette's survival cap (`rr_survival`, ours: 0.99; Mitsuba's fixed 0.95).
//!
//! Light that enters a block of rough glass is trapped by total internal reflection: its
//! throughput stays near one for dozens of bounces, so Russian roulette continues it with the
//! capped probability q_max and a survivor of n roulettes carries q_max⁻ⁿ. At 0.95 the rare
//! paths that escape after 50 bounces arrive 13× too bright (the fireflies of Mitsuba's
//! `bsdf_roughdielectric_glass` preview); at 0.99, 1.7×. Both are unbiased: the image means
//! agree (four standard errors of independent renders) and the pixels' variance is lower with
//! the higher cap.

use crate::render_stats::{prepare, same_mean_less_noise};
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
    let dir = std::env::temp_dir().join(format!("gonio-rr-survival-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.xml");
    let load = |xml: &str, mitsuba: bool| {
        std::fs::write(&path, xml).unwrap();
        let options = LoadOptions {
            mitsuba_estimators: mitsuba,
            ..LoadOptions::default()
        };
        load_scene_file_with(&path, &options).map(|s| s.scene.integrator.rr_survival)
    };
    let plain = r#"<scene version="3.0.0"><integrator type="path"/></scene>"#;
    assert_eq!(load(plain, false).unwrap(), 0.99);
    assert_eq!(load(plain, true).unwrap(), 0.95);
    for bad in ["1", "0", "nan", "-0.5"] {
        let xml = format!(
            "<scene version=\"3.0.0\">\n<integrator type=\"path\">\n<float name=\"rr_survival\" value=\"{bad}\"/>\n</integrator></scene>"
        );
        let e = load(&xml, false).unwrap_err().to_string();
        assert!(
            e.contains("scene.xml") && e.contains(":3") && e.contains("rr_survival"),
            "{bad}: {e}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
