//! Next-event estimation through refraction (`refracted_nee`, `integrator::refracted`) against
//! the path tracer without it.
//!
//! A diffuse floor lit by a small light only through a parallel glass slab (its shadow is the
//! whole floor the camera sees, from below the slab): ordinary next-event estimation is blocked
//! there, so without the strategy the light arrives only by BSDF sampling through the slab (and
//! by the caustic light subpaths, when on). Every estimator is unbiased, so with and without
//! the strategy the image means agree; with it the noise is far lower. Both are checked with the
//! caustic light subpaths off (two strategies share the paths) and on (three), with a
//! rectangular and a spherical light and with a constant sky, the slab tilted so that nothing
//! is axis-aligned.
//!
//! Tolerances come from the spread of the means of independent renders (four standard errors).

use crate::render_stats::{prepare, same_mean_less_noise};

const RECTANGLE_LIGHT: &str = r#"<shape type="rectangle">
        <transform name="to_world"><scale value="0.2"/><rotate x="1" angle="90"/><translate x="0.1" y="2"/></transform>
        <emitter type="area"><rgb name="radiance" value="30"/></emitter>
    </shape>"#;
const SPHERE_LIGHT: &str = r#"<shape type="sphere">
        <point name="center" value="-0.1, 2, 0.2"/><float name="radius" value="0.12"/>
        <emitter type="area"><rgb name="radiance" value="30"/></emitter>
    </shape>"#;

const SKY: &str = r#"<emitter type="constant"><rgb name="radiance" value="0.8"/></emitter>"#;

fn slab_scene(refracted: bool, caustics: bool, light: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path">
        <integer name="max_depth" value="6"/>
        <boolean name="refracted_nee" value="{refracted}"/>
        <boolean name="caustic_paths" value="{caustics}"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="0, 0.45, 2.2" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="20"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="cube">
        <transform name="to_world">
            <scale x="3" y="0.08" z="3"/><rotate z="1" angle="8"/><rotate y="1" angle="20"/><translate y="0.9"/>
        </transform>
        <bsdf type="dielectric"><float name="int_ior" value="1.5"/></bsdf>
    </shape>
    {light}
</scene>"#
    )
}

/// With and without the strategy: the same image mean within four standard errors, and the
/// pixels' variance at most `gain` times the one without.
fn same_expectation_less_noise(caustics: bool, light: &str, what: &str, gain: f64) {
    same_expectation_less_noise_in(false, caustics, light, what, gain);
}

fn same_expectation_less_noise_in(polarized: bool, caustics: bool, light: &str, what: &str, gain: f64) {
    let on = prepare(&slab_scene(true, caustics, light), polarized);
    let off = prepare(&slab_scene(false, caustics, light), polarized);
    let m_on = same_mean_less_noise(&on, &off, 128, what, gain);
    assert!(
        m_on > 0.01,
        "{what}: the floor must be lit through the slab ({m_on})"
    );
}

#[test]
fn refracted_nee_keeps_the_expectation_under_a_glass_slab_without_light_subpaths() {
    same_expectation_less_noise(false, RECTANGLE_LIGHT, "rectangle light, path tracer", 0.4);
}

#[test]
fn refracted_nee_keeps_the_expectation_under_a_glass_slab_with_light_subpaths() {
    same_expectation_less_noise(true, SPHERE_LIGHT, "sphere light, with light subpaths", 0.4);
}

/// In polarized mode the refractions' Mueller matrices multiply in the path's order (the
/// transmittance of the chain, then the light), as the path tracer's do.
#[test]
fn refracted_nee_keeps_the_expectation_of_a_polarized_render() {
    same_expectation_less_noise_in(true, true, RECTANGLE_LIGHT, "rectangle light, polarized", 0.4);
}

/// A light at infinity through the slab: the refracted ray adds the sky along its last
/// direction; no light subpath starts there, so two strategies share the paths.
#[test]
fn refracted_nee_keeps_the_expectation_of_a_sky_seen_through_a_glass_slab() {
    same_expectation_less_noise(true, SKY, "constant sky", 0.8);
}

/// A rectangle light and the sky, each sampled at every vertex (`split_lights`: the selection
/// probability is then 1 in all three strategies' densities), with the light subpaths on
/// (measured: means 0.85 standard errors apart, 0.22× the pixel variance).
#[test]
fn refracted_nee_keeps_the_expectation_with_two_lights_each_sampled() {
    let lights = format!("{RECTANGLE_LIGHT}{SKY}");
    assert!(prepare(&slab_scene(true, true, &lights), false).lights().split());
    same_expectation_less_noise(true, &lights, "rectangle light and sky, split", 0.5);
}

#[test]
fn refracted_nee_parses_and_a_bad_value_is_refused() {
    let s =
        gonio_render::xml::load_scene_str(&slab_scene(false, true, SPHERE_LIGHT), ".", &[]).expect("loads");
    assert!(!s.integrator.refracted_nee);
    let s =
        gonio_render::xml::load_scene_str(&slab_scene(true, true, SPHERE_LIGHT), ".", &[]).expect("loads");
    assert!(s.integrator.refracted_nee);
    let bad = slab_scene(true, true, SPHERE_LIGHT).replace(
        r#"<boolean name="refracted_nee" value="true"/>"#,
        r#"<boolean name="refracted_nee" value="maybe"/>"#,
    );
    let err = gonio_render::xml::load_scene_str(&bad, ".", &[]).expect_err("a bad boolean is refused");
    assert!(err.to_string().contains("maybe"), "{err}");
}
