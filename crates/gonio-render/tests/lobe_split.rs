//! Lobe splitting at rough glass (`split_escapes`, `integrator/lobe_split.rs`) and at the glass
//! the camera sees (`split_visible_glass`) against the path tracer's Fresnel choice (Mitsuba's
//! way).
//!
//! A rough glass cube and sphere (α = 0.02, as Mitsuba's `bsdf_roughdielectric_glass` preview)
//! under the preview's environment map: the environment reflected by the glass, and light
//! leaving the glass after bouncing inside it, are found on every visit instead of when the
//! Fresnel coin says so. Both estimators are unbiased: the image means agree (four standard
//! errors of independent renders), and the pixels' variance is lower with splitting.

use crate::render_stats::{MUSEUM, SENSOR, prepare, same_mean_less_noise};

/// The integrator (with `split_escapes` on or off, `split_visible_glass` off: these scenes test
/// the first) and the camera of the test scenes.
fn head(split: bool) -> String {
    head_with(split, false, "")
}

/// [`head`] with both kinds of splitting chosen, and `more` of the integrator's parameters.
fn head_with(split_escapes: bool, split_visible_glass: bool, more: &str) -> String {
    format!(
        r#"<integrator type="path">
        <boolean name="split_escapes" value="{split_escapes}"/>
        <boolean name="split_visible_glass" value="{split_visible_glass}"/>{more}
    </integrator>
    {SENSOR}"#
    )
}

fn scene(split: bool) -> String {
    let head = head(split);
    format!(
        r#"<scene version="3.0.0">
    {head}
    <shape type="cube">
        <transform name="to_world"><scale value="0.5"/><rotate y="1" angle="30"/><translate x="-0.7" y="0.5"/></transform>
        <bsdf type="roughdielectric"><float name="alpha" value="0.02"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="0.7, 0.6, 0.3"/><float name="radius" value="0.6"/>
        <bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.02"/></bsdf>
    </shape>
    {MUSEUM}
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

/// Glass under a lamp (no light at infinity): a smooth `dielectric` sphere and a rough cube, a
/// small `plastic` sphere, a diffuse floor, and a lamp near the camera whose reflections and
/// refractions in the glass (and reflection in the plastic's coat) the camera and the floor see. Where the outward lobe meets the lamp, its emission is
/// added whole instead of when the Fresnel coin says so. Without the floor (`floor` false) the
/// camera sees nothing but the lamp through the glass: the glints are most of the image.
fn lamp_scene(split: bool, lamp: &str, floor: bool) -> String {
    let floor = if floor {
        r#"<shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>"#
    } else {
        ""
    };
    let head = head(split);
    format!(
        r#"<scene version="3.0.0">
    {head}
    <shape type="sphere">
        <point name="center" value="0.6, 0.6, 0.2"/><float name="radius" value="0.6"/>
        <bsdf type="dielectric"/>
    </shape>
    <shape type="cube">
        <transform name="to_world"><scale value="0.4"/><rotate y="1" angle="30"/><translate x="-0.7" y="0.4"/></transform>
        <bsdf type="roughdielectric"><float name="alpha" value="0.05"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="-0.1, 0.25, 0.9"/><float name="radius" value="0.25"/>
        <bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.1, 0.25, 0.6"/></bsdf>
    </shape>
    {floor}
    {lamp}
</scene>"#
    )
}

/// The lamp: a small rectangle above the camera, facing the glass.
const LAMP: &str = r#"<shape type="rectangle">
        <transform name="to_world"><scale value="0.6"/><rotate x="1" angle="135"/><translate y="2.5" z="2.5"/></transform>
        <emitter type="area"><rgb name="radiance" value="20"/></emitter>
    </shape>"#;

/// Glints (the lamp met by the outward lobe of smooth and rough glass, added whole): the same
/// image mean within four standard errors, and the pixels' variance lower than with the coin
/// alone. With the floor, the paths the floor sends through the glass to the lamp are shared
/// with next-event estimation through glass and the light subpaths by MIS, whose weights the
/// split must keep (measured 0.64× the pixel variance); without it, the image is mostly glints
/// (measured 0.75×). Counting a glint twice moves the mean with the floor by 33 standard
/// errors.
#[test]
fn glints_keep_the_expectation_of_glass_under_a_lamp() {
    for (floor, gain) in [(true, 0.85), (false, 0.9)] {
        let on = prepare(&lamp_scene(true, LAMP, floor), false);
        let off = prepare(&lamp_scene(false, LAMP, floor), false);
        assert!(on.lights().infinite().is_empty());
        let what = if floor {
            "glass and floor under a lamp"
        } else {
            "glass alone under a lamp"
        };
        same_mean_less_noise(&on, &off, 128, what, gain);
    }
}

/// A light no ray can meet (a point light) gives nothing to split: no outward ray is traced,
/// and the image is bit for bit the one without splitting (which fails if the rule splits
/// there: the split lobes' weights round differently from the coin's; checked by removing the
/// gate).
#[test]
fn split_escapes_stays_off_where_no_ray_can_meet_a_light() {
    let point = r#"<emitter type="point"><point name="position" value="0, 2.5, 2.5"/><rgb name="intensity" value="20"/></emitter>"#;
    let (on, off) = (
        prepare(&lamp_scene(true, point, true), false),
        prepare(&lamp_scene(false, point, true), false),
    );
    assert!(on.lights().infinite().is_empty());
    let a = crate::render_stats::green(&on, 8, 3);
    let b = crate::render_stats::green(&off, 8, 3);
    assert!(a.iter().any(|&v| v > 0.0), "the point light lights the scene");
    assert_eq!(a, b);
}

/// A window pane (`thindielectric`, right) and a glass slab (`dielectric` with `slab`'s
/// parameters, left), each turned 50° and filling half the view of [`head`]'s camera.
fn pane_and_slab(slab: &str) -> String {
    format!(
        r#"<shape type="rectangle">
        <transform name="to_world"><scale x="0.8" y="1.5"/><rotate y="1" angle="-50"/><translate x="0.5" y="0.5" z="0.8"/></transform>
        <bsdf type="thindielectric"/>
    </shape>
    <shape type="cube">
        <transform name="to_world"><scale x="0.8" y="1.5" z="0.1"/><rotate y="1" angle="50"/><translate x="-0.5" y="0.5" z="0.8"/></transform>
        <bsdf type="dielectric">{slab}</bsdf>
    </shape>"#
    )
}

/// A window pane (`thindielectric`) and a glass slab (`dielectric`) that fill the view, before a
/// dark wall with bright stripes, under a uniform sky (thin-vs-thick in small): a dark part of
/// the wall seen through the glass mixes its own light with the much brighter sky the glass
/// reflects, which the Fresnel coin gives to a few samples of each pixel; with both lobes
/// followed where the camera sees the glass, every sample has both. The same image mean within
/// four standard errors (a reflection 10 % too bright moves it by 11), and the pixels' variance
/// lower (measured 0.37×).
#[test]
fn split_visible_glass_keeps_the_expectation_of_glass_seen_directly() {
    let scene = |split: bool| {
        let head = head_with(true, split, "");
        let glass = pane_and_slab("");
        format!(
            r#"<scene version="3.0.0">
    {head}
    <shape type="rectangle">
        <transform name="to_world"><scale x="4" y="3"/><translate y="0.5" z="-1.5"/></transform>
        <bsdf type="diffuse">
            <texture type="checkerboard" name="reflectance">
                <rgb name="color0" value="0.02"/><rgb name="color1" value="0.8"/>
                <transform name="to_uv"><scale x="8" y="0.5"/></transform>
            </texture>
        </bsdf>
    </shape>
    {glass}
    <emitter type="constant"><rgb name="radiance" value="0.6"/></emitter>
</scene>"#
        )
    };
    let on = prepare(&scene(true), false);
    let off = prepare(&scene(false), false);
    assert!(on.scene.integrator.split_visible_glass && !off.scene.integrator.split_visible_glass);
    same_mean_less_noise(&on, &off, 16, "a pane and a slab before a striped wall", 0.55);
}

/// The same with what else the two paths' MIS weights and states carry: a lamp whose
/// reflections in the glass the camera sees (and whose light through the slab, by next-event
/// estimation through glass and the caustic light subpaths) the split paths meet, Russian
/// roulette from the first bounce, and a dispersive slab (SF11), whose refraction ends the
/// secondary wavelengths of the sample both paths share. The same image mean within four
/// standard errors: a check of the interplay for gross errors (a glint counted twice, a lost
/// state), where the test above checks the weights (a reflection 10 % too bright moves this
/// mean by 2 standard errors only). The noise is not what this checks (measured 1.1×).
#[test]
fn split_visible_glass_keeps_the_expectation_with_a_lamp_roulette_and_dispersion() {
    let scene = |split: bool| {
        let head = head_with(true, split, r#"<integer name="rr_depth" value="1"/>"#);
        let glass = pane_and_slab(r#"<string name="int_ior" value="SF11"/>"#);
        format!(
            r#"<scene version="3.0.0">
    {head}
    <shape type="rectangle">
        <transform name="to_world"><scale x="4" y="3"/><translate y="0.5" z="-1.5"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    {glass}
    <shape type="rectangle">
        <transform name="to_world"><scale x="1" y="0.5"/><rotate x="1" angle="120"/><translate y="2.5" z="2.5"/></transform>
        <emitter type="area"><rgb name="radiance" value="6"/></emitter>
    </shape>
    <emitter type="constant"><rgb name="radiance" value="0.3"/></emitter>
</scene>"#
        )
    };
    let on = prepare(&scene(true), false);
    let off = prepare(&scene(false), false);
    same_mean_less_noise(&on, &off, 64, "a lamp, roulette and dispersion", 1.5);
}
