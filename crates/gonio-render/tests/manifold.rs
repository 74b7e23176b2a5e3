//! Manifold next-event estimation through mirror spheres (`manifold_nee`,
//! `integrator::manifold`) against the path tracer without it.
//!
//! The camera sees a diffuse floor only in a mirror sphere; a second mirror sphere on the floor
//! throws a small light's reflection onto it (the caustic `E S D S L`, which no light subpath
//! can join: the camera-side neighbour of the floor point is the first sphere). Every estimator
//! is unbiased, so with and without the strategy the image means agree (four standard errors of
//! the means of independent renders); with it the pixels' variance is lower. Checked with the
//! caustic light subpaths off and on, with a rectangular and a spherical light and with the
//! gold of Mitsuba's `conductor` (a coloured Fresnel weight at the mirror).

use crate::render_stats::{prepare, same_mean_less_noise};

/// Beside the second sphere, at its height, facing it: the floor sees the light only at grazing
/// angles, and its reflection in the sphere far more.
const RECTANGLE_LIGHT: &str = r#"<shape type="rectangle">
        <transform name="to_world"><scale value="0.3"/><rotate y="1" angle="-90"/><translate x="1.3" y="0.5" z="-0.6"/></transform>
        <emitter type="area"><rgb name="radiance" value="20"/></emitter>
    </shape>"#;
const SPHERE_LIGHT: &str = r#"<shape type="sphere">
        <point name="center" value="1.3, 0.55, -0.4"/><float name="radius" value="0.2"/>
        <emitter type="area"><rgb name="radiance" value="20"/></emitter>
    </shape>"#;

fn scene(manifold: bool, caustics: bool, light: &str, metal: &str) -> String {
    let bsdf = format!(r#"<bsdf type="conductor"><string name="material" value="{metal}"/></bsdf>"#);
    scene_with(manifold, caustics, light, &bsdf)
}

/// [`scene`] with the second sphere's BSDF written out.
fn scene_with(manifold: bool, caustics: bool, light: &str, second: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path">
        <integer name="max_depth" value="5"/>
        <boolean name="manifold_nee" value="{manifold}"/>
        <boolean name="caustic_paths" value="{caustics}"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="17"/>
        <transform name="to_world"><lookat origin="0.2, 1.1, 3.6" target="0, 0.5, 1.4" up="0, 1, 0"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="20"/><integer name="height" value="20"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="20"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="0, 0.5, 1.4"/><float name="radius" value="0.5"/>
        <bsdf type="conductor"><string name="material" value="none"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="0.1, 0.45, -0.6"/><float name="radius" value="0.45"/>
        {second}
    </shape>
    {light}
</scene>"#
    )
}

/// Samples per pixel of each render.
const SPP: u32 = 128;

/// With and without the strategy: the same image mean within four standard errors, and the
/// pixels' variance at most `gain` times the one without (measured 0.05 for the rectangle light
/// and 0.004 for the sphere light and gold; with the path tracer's share of these paths left at
/// one, as if the strategy did not take part, the rectangle light's means differ by 4.4
/// standard errors and the sphere light's pixel variance exceeds the one without).
fn same_expectation_less_noise(caustics: bool, light: &str, metal: &str, what: &str, gain: f64) {
    let on = prepare(&scene(true, caustics, light, metal), false);
    let off = prepare(&scene(false, caustics, light, metal), false);
    let m_on = same_mean_less_noise(&on, &off, SPP, what, gain);
    assert!(m_on > 1e-3, "{what}: the floor must be lit ({m_on})");
}

#[test]
fn manifold_nee_keeps_the_expectation_of_a_caustic_seen_in_a_mirror() {
    same_expectation_less_noise(
        false,
        RECTANGLE_LIGHT,
        "none",
        "rectangle light, path tracer",
        0.25,
    );
}

#[test]
fn manifold_nee_keeps_the_expectation_with_light_subpaths_a_sphere_light_and_gold() {
    same_expectation_less_noise(
        true,
        SPHERE_LIGHT,
        "Au",
        "sphere light, gold, light subpaths",
        0.25,
    );
}

/// A mirror sphere seen through a normal map is no mirror sphere: its normals lean away from
/// the sphere's, so the strategy's specular constraint (the sphere's own normal) would place
/// the caustic where the mapped mirror does not reflect. Such a sphere is left to the other
/// estimators, and the image is the one without the strategy (before the adapter's flags
/// said so, its material passed for a mirror and the two renders disagreed).
#[test]
fn a_normal_mapped_mirror_sphere_is_not_taken_for_a_mirror() {
    let mapped = r#"<bsdf type="normalmap">
            <rgb name="normalmap" value="0.75, 0.5, 0.9"/>
            <bsdf type="conductor"><string name="material" value="none"/></bsdf>
        </bsdf>"#;
    let on = prepare(&scene_with(true, false, RECTANGLE_LIGHT, mapped), false);
    let off = prepare(&scene_with(false, false, RECTANGLE_LIGHT, mapped), false);
    let m = same_mean_less_noise(&on, &off, 8 * SPP, "normal-mapped mirror", 1.5);
    assert!(m > 1e-3, "the floor must be lit ({m})");
}

/// The strategy is a render parameter of `path`: on by default, off under
/// `--mitsuba-estimators` (Mitsuba's path tracer has no such strategy), what the scene writes
/// either way.
#[test]
fn manifold_nee_is_on_by_default_and_off_for_mitsuba() {
    use gonio_render::xml::{LoadOptions, load_scene_file_with};
    let dir = std::env::temp_dir().join(format!("gonio-manifold-switch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let load = |params: &str, mitsuba: bool| {
        let path = dir.join("scene.xml");
        std::fs::write(
            &path,
            format!(r#"<scene version="3.0.0"><integrator type="path">{params}</integrator></scene>"#),
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
            .manifold_nee
    };
    let on = r#"<boolean name="manifold_nee" value="true"/>"#;
    assert_eq!((load("", false), load("", true)), (true, false));
    assert_eq!((load(on, false), load(on, true)), (true, true));
    let _ = std::fs::remove_dir_all(&dir);
}
