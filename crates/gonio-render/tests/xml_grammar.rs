//! The grammar: parameters, references, includes, values, transforms, legacy names.

use glam::{Affine3A, Vec2, Vec3};
use gonio_core::Spectrum;
use gonio_render::material::{ConductorMaterial, DiffuseMaterial};
use gonio_render::scene::{EmitterDesc, Geometry, Scene};
use gonio_render::texture::Texture;
use gonio_render::xml::{load_scene_file, load_scene_str};
use std::path::PathBuf;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

const SENSOR: &str = "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>";

fn load(body: &str) -> Scene {
    let t = format!("<scene version=\"3.0.0\">\n{SENSOR}\n{body}\n</scene>");
    load_scene_str(&t, data(), &[]).unwrap_or_else(|e| panic!("{e}\n{t}"))
}

fn load_with(body: &str, defines: &[(&str, &str)]) -> Scene {
    let t = format!("<scene version=\"3.0.0\">\n{SENSOR}\n{body}\n</scene>");
    let d: Vec<(String, String)> = defines
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    load_scene_str(&t, data(), &d).unwrap_or_else(|e| panic!("{e}\n{t}"))
}

fn sphere(s: &Scene, i: usize) -> (Vec3, f32) {
    match s.shapes[i].geometry {
        Geometry::Sphere { center, radius } => (center, radius),
        _ => panic!("shape {i} is not a sphere"),
    }
}

fn to_world(body: &str) -> Affine3A {
    let s = load(&format!(
        "<shape type=\"rectangle\"><transform name=\"to_world\">{body}</transform></shape>"
    ));
    s.shapes[0].to_world
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn defaults_substitute_longest_name_first_and_defines_override() {
    let body = r#"<default name="r" value="0.25"/>
<default name="r2" value="0.5"/>
<shape type="sphere"><float name="radius" value="$r2"/></shape>
<shape type="sphere"><float name="radius" value="$r"/><point name="center" value="$r, 1, $r2"/></shape>"#;
    let s = load(body);
    assert_eq!(sphere(&s, 0).1, 0.5);
    assert_eq!(sphere(&s, 1), (Vec3::new(0.25, 1.0, 0.5), 0.25));
    let s = load_with(body, &[("r", "2")]);
    assert_eq!(sphere(&s, 0).1, 0.5);
    assert_eq!(sphere(&s, 1).1, 2.0);
    // A define without a matching default still substitutes.
    let s = load_with(
        "<shape type=\"sphere\"><float name=\"radius\" value=\"$big\"/></shape>",
        &[("big", "3")],
    );
    assert_eq!(sphere(&s, 0).1, 3.0);
}

#[test]
fn references_named_positional_and_forward() {
    let s = load(
        r#"<shape type="sphere"><ref id="later"/></shape>
<shape type="sphere"><ref name="bsdf" id="later"/></shape>
<shape type="sphere"><bsdf type="diffuse"><float name="reflectance" value="0.25"/></bsdf></shape>
<bsdf type="diffuse" id="later"><float name="reflectance" value="0.75"/></bsdf>
<alias id="later" as="other"/>
<shape type="sphere"><ref id="other"/></shape>"#,
    );
    assert_eq!(s.shapes[0].material, s.shapes[1].material);
    assert_eq!(
        s.shapes[0].material, s.shapes[3].material,
        "an alias names the same object"
    );
    assert_ne!(s.shapes[0].material, s.shapes[2].material);
    let refl = |i: usize| match s.materials[s.shapes[i].material].get::<DiffuseMaterial>() {
        Some(DiffuseMaterial { reflectance, .. }) => {
            reflectance.as_spectrum().unwrap().as_constant().unwrap()
        }
        None => panic!("{:?}", s.materials[s.shapes[i].material]),
    };
    assert_eq!((refl(0), refl(2)), (0.75, 0.25));
    assert_eq!(s.materials.len(), 2);
}

#[test]
fn include_merges_and_shares_parameters() {
    let t = r#"<scene version="3.0.0">
    <default name="radius" value="0.125"/>
    <sensor type="perspective"/>
    <include filename="inc_nested_parent.xml"/>
    <shape type="sphere"><ref id="from_include"/></shape>
</scene>"#;
    let s = load_scene_str(t, data(), &[]).unwrap();
    assert_eq!(s.shapes.len(), 2);
    assert_eq!(sphere(&s, 0).1, 0.125);
    assert_eq!(s.shapes[0].material, s.shapes[1].material);
    // Files are resolved relative to the including file: load from disk too.
    let dir = std::env::temp_dir().join(format!("gonio-xml-include-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(
        dir.join("main.xml"),
        "<scene version=\"3.0.0\"><include filename=\"sub/a.xml\"/></scene>",
    )
    .unwrap();
    std::fs::write(
        dir.join("sub/a.xml"),
        "<scene version=\"3.0.0\"><include filename=\"b.xml\"/></scene>",
    )
    .unwrap();
    std::fs::write(
        dir.join("sub/b.xml"),
        "<scene version=\"3.0.0\"><shape type=\"ply\"><string name=\"filename\" value=\"m.ply\"/></shape></scene>",
    )
    .unwrap();
    std::fs::copy(data().join("quad_ascii.ply"), dir.join("sub/m.ply")).unwrap();
    let l = gonio_render::xml::load_scene_file_with_warnings(dir.join("main.xml"), &[]);
    std::fs::remove_dir_all(&dir).ok();
    let l = l.unwrap();
    assert_eq!(l.scene.shapes.len(), 1);
    // No integrator and no sensor: defaults with warnings (Mitsuba 3.9.1 has none).
    assert_eq!(l.warnings.len(), 2, "{:?}", l.warnings);
    assert!(
        (l.scene.sensor.fov_x_deg - 38.1848).abs() < 1e-3,
        "{}",
        l.scene.sensor.fov_x_deg
    );
}

#[test]
fn transforms_apply_in_document_order() {
    // scale 2, then translate x 1: (1, 0, 0) → (3, 0, 0); the other order gives (4, 0, 0).
    let a = to_world("<scale value=\"2\"/><translate x=\"1\"/>");
    assert!(close(a.transform_point3(Vec3::X), Vec3::new(3.0, 0.0, 0.0)));
    let b = to_world("<translate value=\"1, 0, 0\"/><scale value=\"2\"/>");
    assert!(close(b.transform_point3(Vec3::X), Vec3::new(4.0, 0.0, 0.0)));
    // rotate about +z by 90° (counter-clockwise): x → y.
    let r = to_world("<rotate z=\"1\" angle=\"90\"/>");
    assert!(close(r.transform_point3(Vec3::X), Vec3::Y));
    let r = to_world("<rotate value=\"0, 0, 2\" angle=\"90\"/>");
    assert!(close(r.transform_point3(Vec3::X), Vec3::Y));
    // rotate x −90°: the rectangle normal +z becomes +y (the floor of
    // testdata/mitsuba/scenes/materials.xml).
    let f = to_world("<scale value=\"10\"/><rotate x=\"1\" angle=\"-90\"/>");
    assert!(close(f.transform_vector3(Vec3::Z).normalize(), Vec3::Y));
    // Non-uniform scale with missing components = 1.
    let s = to_world("<scale y=\"3\"/>");
    assert!(close(s.transform_point3(Vec3::ONE), Vec3::new(1.0, 3.0, 1.0)));
    // Row-major 4×4 = scale 0.5, rotate x +90°, translate y 4: (x, y, z) → (0.5x, 4 − 0.5z, 0.5y).
    let m = to_world("<matrix value=\"0.5 0 0 0  0 0 -0.5 4  0 0.5 0 0  0 0 0 1\"/>");
    assert!(close(
        m.transform_point3(Vec3::new(1.0, 2.0, 3.0)),
        Vec3::new(0.5, 2.5, 1.0)
    ));
    let e = to_world("<scale value=\"0.5\"/><rotate x=\"1\" angle=\"90\"/><translate y=\"4\"/>");
    assert!(close(
        e.transform_point3(Vec3::new(1.0, 2.0, 3.0)),
        Vec3::new(0.5, 2.5, 1.0)
    ));
    // 3×3 matrix embeds without translation.
    let m3 = to_world("<matrix value=\"0 -1 0  1 0 0  0 0 1\"/>");
    assert!(close(m3.transform_point3(Vec3::X), Vec3::Y));
}

#[test]
fn lookat_follows_mitsuba() {
    let m = to_world("<lookat origin=\"1, 2, 3\" target=\"1, 2, 13\" up=\"0, 1, 0\"/>");
    // Columns: left, up, dir, origin. Looking along +z with +y up, "left" is +x.
    assert!(close(m.transform_point3(Vec3::ZERO), Vec3::new(1.0, 2.0, 3.0)));
    assert!(close(m.transform_vector3(Vec3::Z), Vec3::Z));
    assert!(close(m.transform_vector3(Vec3::Y), Vec3::Y));
    assert!(close(m.transform_vector3(Vec3::X), Vec3::X));
    // Looking along −z (the usual camera), camera +x (left) is world −x.
    let m = to_world("<lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/>");
    assert!(close(m.transform_vector3(Vec3::X), Vec3::NEG_X));
    assert!(close(m.transform_vector3(Vec3::Z), Vec3::NEG_Z));
    // A non-orthogonal up is orthogonalized.
    let m = to_world("<lookat origin=\"0, 0, 0\" target=\"0, 0, 1\" up=\"0, 1, 1\"/>");
    assert!(close(m.transform_vector3(Vec3::Y), Vec3::Y));
    // Without up a perpendicular one is generated.
    let m = to_world("<lookat origin=\"0, 0, 0\" target=\"0, 3, 0\"/>");
    let up = m.transform_vector3(Vec3::Y);
    assert!(close(m.transform_vector3(Vec3::Z), Vec3::Y));
    assert!(up.dot(Vec3::Y).abs() < 1e-6 && (up.length() - 1.0).abs() < 1e-6);
}

#[test]
fn legacy_camel_case_names() {
    let t = r#"<scene version="0.5.0">
    <integrator type="path"><integer name="maxDepth" value="7"/><integer name="rrDepth" value="3"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <transform name="toWorld"><translate x="5"/></transform>
        <sampler type="independent"><integer name="sampleCount" value="9"/></sampler>
    </sensor>
    <bsdf type="diffuse" id="d"><float name="diffuseReflectance" value="0.3"/></bsdf>
    <shape type="rectangle">
        <bsdf type="diffuse">
            <texture type="checkerboard" name="reflectance">
                <float name="uscale" value="4"/><float name="vscale" value="2"/><float name="uoffset" value="0.5"/>
            </texture>
        </bsdf>
    </shape>
    <shape type="sphere"><boolean name="flipNormals" value="true"/><ref id="d"/></shape>
</scene>"#;
    let s = load_scene_str(t, data(), &[]).unwrap();
    assert_eq!((s.integrator.max_depth, s.integrator.rr_depth), (7, 3));
    assert_eq!(s.sensor.sampler.sample_count, 9);
    assert!(close(
        s.sensor.to_world.transform_point3(Vec3::ZERO),
        Vec3::new(5.0, 0.0, 0.0)
    ));
    assert!(s.shapes[1].flip_normals);
    let Some(DiffuseMaterial { reflectance, .. }) = s.materials[s.shapes[1].material].get() else {
        panic!()
    };
    assert_eq!(reflectance.as_spectrum().unwrap().as_constant(), Some(0.3));
    let Some(DiffuseMaterial {
        reflectance: Texture::Checkerboard { to_uv, .. },
        ..
    }) = s.materials[s.shapes[0].material].get()
    else {
        panic!()
    };
    // scale (4, 2) then offset (0.5, 0).
    assert_eq!(to_uv.transform_point2(Vec2::new(1.0, 1.0)), Vec2::new(4.5, 2.0));
}

#[test]
fn spectrum_forms() {
    let s = load(
        r#"<shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" value="0.3"/></bsdf></shape>
<shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" value="400:0.1, 500:0.3 600:0.2"/></bsdf></shape>
<shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" filename="flat.spd"/></bsdf></shape>
<shape type="sphere"><emitter type="area"><spectrum name="radiance" type="blackbody"><float name="temperature" value="3000"/></spectrum></emitter></shape>
<shape type="sphere"><emitter type="area"><spectrum name="radiance" type="d65"/></emitter></shape>
<shape type="sphere"><emitter type="area"><float name="radiance" value="2"/></emitter></shape>
<shape type="sphere"><emitter type="area"><spectrum name="radiance" value="2"/></emitter></shape>"#,
    );
    let refl = |i: usize| match s.materials[s.shapes[i].material].get::<DiffuseMaterial>() {
        Some(DiffuseMaterial { reflectance, .. }) => reflectance.as_spectrum().unwrap().clone(),
        None => panic!("{:?}", s.materials[s.shapes[i].material]),
    };
    assert_eq!(refl(0).as_constant(), Some(0.3));
    let p = refl(1);
    assert!((p.eval(450.0) - 0.2).abs() < 1e-6 && (p.eval(550.0) - 0.25).abs() < 1e-6);
    assert_eq!(p.eval(399.0), 0.0, "0 outside the given range");
    let f = refl(2);
    assert!((f.eval(450.0) - 0.375).abs() < 1e-6);
    let radiance = |i: usize| {
        s.shapes[i]
            .emitter
            .as_ref()
            .unwrap()
            .radiance
            .as_spectrum()
            .unwrap()
            .clone()
    };
    let bb = radiance(3);
    // Planck at 3000 K rises through the visible range.
    assert!(bb.eval(700.0) > bb.eval(500.0) && bb.eval(500.0) > bb.eval(400.0));
    assert_eq!(radiance(4), Spectrum::d65());
    // A number on an emitter is a grey illuminant: 2 × D65.
    let two = radiance(5);
    for l in [420.0, 560.0, 690.0] {
        assert!((two.eval(l) - 2.0 * Spectrum::d65().eval(l)).abs() < 1e-4 * two.eval(l).max(1.0));
    }
    // A uniform <spectrum> stays uniform, also on an emitter (Mitsuba's `uniform`).
    assert_eq!(radiance(6), Spectrum::Constant(2.0));
}

#[test]
fn rgb_roles() {
    let s = load(
        r#"<bsdf type="conductor" id="c"><rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.4, 2.2"/></bsdf>
<shape type="sphere"><ref id="c"/></shape>
<emitter type="constant"><rgb name="radiance" value="0.5, 0.5, 0.5"/></emitter>
<emitter type="point"><point name="position" x="1" y="2" z="3"/><rgb name="intensity" value="5"/></emitter>"#,
    );
    let Some(ConductorMaterial { model, .. }) = s.materials[0].get() else {
        panic!()
    };
    // Unbounded: values above 1 survive (k ≈ 3.9 in the red).
    assert!(model.k.eval(640.0) > 3.0, "{}", model.k.eval(640.0));
    assert!(model.eta.eval(450.0) > 0.8);
    let EmitterDesc::Constant { radiance } = &s.emitters[0] else {
        panic!()
    };
    assert!((radiance.eval(560.0) - 0.5 * Spectrum::d65().eval(560.0)).abs() < 1e-3);
    let EmitterDesc::Point { position, intensity } = &s.emitters[1] else {
        panic!()
    };
    assert_eq!(*position, Vec3::new(1.0, 2.0, 3.0));
    assert!((intensity.eval(500.0) - 5.0 * Spectrum::d65().eval(500.0)).abs() < 1e-3);
}

#[test]
fn comments_and_whitespace_are_ignored_and_scene_file_loads() {
    let s = load("<!-- a comment -->\n   \n<shape type=\"disk\"/>");
    assert!(matches!(s.shapes[0].geometry, Geometry::Disk));
    let s = load_scene_file(data().join("inc_child.xml"), &[("radius".into(), "4".into())]).unwrap();
    assert_eq!(sphere(&s, 0).1, 4.0);
}

/// Mitsuba keeps the first definition of a `<default>`: a scene's own defaults hold over those
/// of the files it includes (its `medium_homogeneous_sss` sets `volpath` before including a
/// set-up whose default is `path`).
#[test]
fn the_first_default_wins() {
    let text = "<scene version=\"3.0.0\"><default name=\"d\" value=\"7\"/><default name=\"d\" value=\"3\"/>\
        <integrator type=\"path\"><integer name=\"max_depth\" value=\"$d\"/></integrator></scene>";
    assert_eq!(load_scene_str(text, data(), &[]).unwrap().integrator.max_depth, 7);
}
