//! Every error path of the XML reader: the error names the file, line and column, and quotes the
//! offending value.

use gonio_render::xml::{ErrorKind, SceneError, load_bsdf_str, load_scene_file, load_scene_str};
use std::path::PathBuf;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// 1-based (line, column) of the first occurrence of `needle` in `text` (columns in characters).
fn at(text: &str, needle: &str) -> (u32, u32) {
    let i = text
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not in the test scene"));
    let before = &text[..i];
    let line = before.matches('\n').count() as u32 + 1;
    let col = before.rsplit('\n').next().unwrap().chars().count() as u32 + 1;
    (line, col)
}

/// Wraps body in a scene with a valid sensor.
fn scene(body: &str) -> String {
    format!(
        "<scene version=\"3.0.0\">\n    <sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n{body}\n</scene>\n"
    )
}

fn load_err(text: &str) -> SceneError {
    match load_scene_str(text, data(), &[]) {
        Ok(_) => panic!("expected an error for\n{text}"),
        Err(e) => e,
    }
}

#[track_caller]
fn check(e: &SceneError, kind: ErrorKind, pos: (u32, u32), quotes: &[&str]) {
    assert_eq!(e.kind, kind, "{e}");
    assert_eq!((e.location.line, e.location.column), pos, "{e}");
    let msg = e.to_string();
    assert!(
        msg.starts_with(&format!("<string>:{}:{}: ", pos.0, pos.1)),
        "{msg}"
    );
    for q in quotes {
        assert!(msg.contains(q), "{msg:?} should mention {q:?}");
    }
}

#[test]
fn malformed_xml() {
    let t = "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n  </shap>\n</scene>";
    let e = load_err(t);
    assert_eq!(e.kind, ErrorKind::Syntax, "{e}");
    assert_eq!(e.location.line, 3, "{e}");
    assert!(e.to_string().contains("shap"), "{e}");
}

/// Mitsuba's animated transforms (its motion-blur test scenes) are named as what they are.
#[test]
fn animated_transforms_are_refused_by_name() {
    let t = scene(
        "    <shape type=\"sphere\">\n        <animation name=\"to_world\">\n            <transform time=\"0\"><translate x=\"1\"/></transform>\n        </animation>\n    </shape>",
    );
    let e = load_err(&t);
    check(
        &e,
        ErrorKind::Grammar,
        at(&t, "<animation"),
        &["<animation>", "motion blur", "<transform>"],
    );
}

#[test]
fn unknown_plugin() {
    let t = scene("    <shape type=\"sphere\"><bsdf type=\"measuredpolarized\"/></shape>");
    let e = load_err(&t);
    check(
        &e,
        ErrorKind::UnknownPlugin,
        at(&t, "measuredpolarized"),
        &["\"measuredpolarized\"", "diffuse"],
    );
    let t = scene("    <shape type=\"torus\"/>");
    check(
        &load_err(&t),
        ErrorKind::UnknownPlugin,
        at(&t, "torus"),
        &["\"torus\""],
    );
    let t = scene("    <integrator type=\"bdpt\"/>");
    check(
        &load_err(&t),
        ErrorKind::UnknownPlugin,
        at(&t, "bdpt"),
        &["\"bdpt\""],
    );
    let t = scene("    <emitter type=\"timed_sunsky\"/>");
    check(
        &load_err(&t),
        ErrorKind::UnknownPlugin,
        at(&t, "timed_sunsky"),
        &["\"timed_sunsky\""],
    );
}

#[test]
fn unused_parameter() {
    let t = scene("    <shape type=\"sphere\">\n        <float name=\"radiuss\" value=\"2\"/>\n    </shape>");
    let e = load_err(&t);
    check(
        &e,
        ErrorKind::UnusedParameter,
        at(&t, "<float name=\"radiuss\""),
        &["\"radiuss\"", "sphere"],
    );
    // A nested object nobody takes (a texture directly inside a shape).
    let t = scene("    <shape type=\"sphere\">\n        <texture type=\"checkerboard\"/>\n    </shape>");
    let e = load_err(&t);
    check(
        &e,
        ErrorKind::UnusedParameter,
        at(&t, "<texture"),
        &["checkerboard"],
    );
    // A parameter in the wrong plugin: k given with a material preset.
    let t = scene(
        "    <bsdf type=\"conductor\" id=\"c\">\n        <string name=\"material\" value=\"Au\"/>\n        <float name=\"k\" value=\"2\"/>\n    </bsdf>",
    );
    let e = load_err(&t);
    check(&e, ErrorKind::Grammar, at(&t, "<float name=\"k\""), &["Au"]);
}

#[test]
fn wrong_type() {
    let t =
        scene("    <shape type=\"sphere\">\n        <string name=\"radius\" value=\"big\"/>\n    </shape>");
    let e = load_err(&t);
    let (l, c) = at(&t, "big");
    check(
        &e,
        ErrorKind::WrongType,
        (l, c),
        &["\"radius\"", "float", "\"big\""],
    );
    let t = scene("    <integrator type=\"path\"><float name=\"max_depth\" value=\"3.5\"/></integrator>");
    check(
        &load_err(&t),
        ErrorKind::WrongType,
        at(&t, "3.5"),
        &["max_depth", "integer", "3.5"],
    );
    // A reference to a texture where a BSDF is expected.
    let t = scene(
        "    <texture type=\"checkerboard\" id=\"tex\"/>\n    <shape type=\"sphere\"><ref id=\"tex\"/></shape>",
    );
    let e = load_err(&t);
    assert_eq!(e.kind, ErrorKind::UnusedParameter, "{e}");
}

#[test]
fn bad_numbers() {
    let t = scene("    <shape type=\"sphere\"><float name=\"radius\" value=\"1.0x\"/></shape>");
    check(&load_err(&t), ErrorKind::BadValue, at(&t, "1.0x"), &["\"1.0x\""]);
    let t = scene("    <integrator type=\"path\"><integer name=\"max_depth\" value=\"7.0\"/></integrator>");
    check(&load_err(&t), ErrorKind::BadValue, at(&t, "7.0"), &["\"7.0\""]);
    let t = scene("    <shape type=\"sphere\"><point name=\"center\" value=\"1, 2\"/></shape>");
    check(&load_err(&t), ErrorKind::BadValue, at(&t, "1, 2"), &["\"1, 2\""]);
    let t = scene("    <shape type=\"sphere\"><boolean name=\"flip_normals\" value=\"yes\"/></shape>");
    check(&load_err(&t), ErrorKind::BadValue, at(&t, "yes"), &["\"yes\""]);
    let t = scene("    <shape type=\"sphere\"><float name=\"radius\" value=\"-2\"/></shape>");
    check(&load_err(&t), ErrorKind::BadValue, at(&t, "-2"), &["-2"]);
    let t = scene(
        "    <bsdf type=\"diffuse\" id=\"d\"><rgb name=\"reflectance\" value=\"0.5, 1.5, 0.2\"/></bsdf>",
    );
    check(&load_err(&t), ErrorKind::BadValue, at(&t, "0.5, 1.5"), &["1.5"]);
    let t = scene(
        "    <bsdf type=\"diffuse\" id=\"d\"><spectrum name=\"reflectance\" value=\"500:0.5, 400:0.2\"/></bsdf>",
    );
    check(
        &load_err(&t),
        ErrorKind::BadValue,
        at(&t, "500:0.5"),
        &["400", "500"],
    );
    let t = scene(
        "    <shape type=\"rectangle\"><transform name=\"to_world\"><matrix value=\"1 0 0\"/></transform></shape>",
    );
    check(
        &load_err(&t),
        ErrorKind::BadValue,
        at(&t, "1 0 0\""),
        &["\"1 0 0\""],
    );
}

#[test]
fn undefined_parameter() {
    let t = scene("    <shape type=\"sphere\"><float name=\"radius\" value=\"$rad\"/></shape>");
    check(&load_err(&t), ErrorKind::Undefined, at(&t, "$rad"), &["$rad"]);
    // -D of a parameter the scene never uses.
    let t = scene("");
    let e = load_scene_str(&t, data(), &[("spp".into(), "4".into())]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Undefined, "{e}");
    assert!(e.to_string().contains("spp=4"), "{e}");
}

#[test]
fn missing_reference() {
    let t = scene("    <shape type=\"sphere\"><ref id=\"nowhere\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::Reference,
        at(&t, "nowhere"),
        &["\"nowhere\""],
    );
    let t = scene("    <bsdf type=\"diffuse\" id=\"a\"/>\n    <bsdf type=\"diffuse\" id=\"a\"/>");
    let e = load_err(&t);
    let (first_line, _) = at(&t, "<bsdf type=\"diffuse\" id=\"a\"/>");
    // The second definition, at the value of its id (column 30 of "    <bsdf type="diffuse" id="a"/>").
    assert_eq!(e.kind, ErrorKind::Reference, "{e}");
    assert_eq!((e.location.line, e.location.column), (first_line + 1, 30), "{e}");
    assert!(e.to_string().contains("\"a\" is already defined"), "{e}");
}

#[test]
fn cyclic_reference() {
    let t = scene(
        "    <bsdf type=\"twosided\" id=\"a\"><ref id=\"b\"/></bsdf>\n    <bsdf type=\"twosided\" id=\"b\"><ref id=\"a\"/></bsdf>",
    );
    let e = load_err(&t);
    assert_eq!(e.kind, ErrorKind::Cycle, "{e}");
    assert!(e.to_string().contains("id=\"a\""), "{e}");
}

#[test]
fn cyclic_include() {
    let e = load_scene_file(data().join("cycle_a.xml"), &[]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Cycle, "{e}");
    assert!(e.location.file.ends_with("cycle_b.xml"), "{e}");
    assert_eq!((e.location.line, e.location.column), (2, 24), "{e}");
    assert!(e.to_string().contains("cycle_a.xml"), "{e}");
}

#[test]
fn missing_files() {
    let t = scene("    <include filename=\"nope.xml\"/>");
    check(
        &load_err(&t),
        ErrorKind::Io,
        at(&t, "nope.xml"),
        &["\"nope.xml\""],
    );
    let t = scene("    <shape type=\"obj\"><string name=\"filename\" value=\"missing.obj\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::Io,
        at(&t, "missing.obj"),
        &["\"missing.obj\""],
    );
    let t = scene("    <shape type=\"ply\"><string name=\"filename\" value=\"missing.ply\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::Io,
        at(&t, "missing.ply"),
        &["\"missing.ply\""],
    );
    let t = scene(
        "    <bsdf type=\"diffuse\" id=\"d\"><texture type=\"bitmap\" name=\"reflectance\"><string name=\"filename\" value=\"missing.png\"/></texture></bsdf>",
    );
    check(
        &load_err(&t),
        ErrorKind::Io,
        at(&t, "missing.png"),
        &["\"missing.png\""],
    );
    let t = scene("    <emitter type=\"envmap\"><string name=\"filename\" value=\"sky.exr\"/></emitter>");
    check(&load_err(&t), ErrorKind::Io, at(&t, "sky.exr"), &["\"sky.exr\""]);
    let t = scene(
        "    <bsdf type=\"diffuse\" id=\"d\"><spectrum name=\"reflectance\" filename=\"none.spd\"/></bsdf>",
    );
    check(
        &load_err(&t),
        ErrorKind::Io,
        at(&t, "none.spd"),
        &["\"none.spd\""],
    );
    let e = load_scene_file(data().join("no_such_scene.xml"), &[]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Io);
    assert!(e.to_string().contains("no_such_scene.xml"), "{e}");
}

#[test]
fn broken_files() {
    let t = scene("    <shape type=\"obj\"><string name=\"filename\" value=\"broken.obj\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::Mesh,
        at(&t, "broken.obj"),
        &["broken.obj"],
    );
    let t = scene("    <shape type=\"ply\"><string name=\"filename\" value=\"truncated.ply\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::Mesh,
        at(&t, "truncated.ply"),
        &["truncated.ply", "end of file"],
    );
    let t = scene("    <shape type=\"ply\"><string name=\"filename\" value=\"bad_index.ply\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::Mesh,
        at(&t, "bad_index.ply"),
        &["bad_index.ply", "vertex"],
    );
    let t = scene(
        "    <bsdf type=\"diffuse\" id=\"d\"><texture type=\"bitmap\" name=\"reflectance\"><string name=\"filename\" value=\"broken.png\"/></texture></bsdf>",
    );
    check(
        &load_err(&t),
        ErrorKind::Image,
        at(&t, "broken.png"),
        &["broken.png"],
    );
    let t = scene(
        "    <bsdf type=\"diffuse\" id=\"d\"><spectrum name=\"reflectance\" filename=\"bad.spd\"/></bsdf>",
    );
    check(
        &load_err(&t),
        ErrorKind::BadValue,
        at(&t, "bad.spd"),
        &["bad.spd", "line 2"],
    );
}

#[test]
fn bad_ior() {
    for (v, what) in [("nan", "NaN"), ("-1.5", "-1.5"), ("0", "0")] {
        let t = scene(&format!(
            "    <bsdf type=\"dielectric\" id=\"g\">\n        <float name=\"int_ior\" value=\"{v}\"/>\n    </bsdf>"
        ));
        let e = load_err(&t);
        let (l, c) = at(&t, &format!("value=\"{v}\""));
        check(&e, ErrorKind::BadValue, (l, c + 7), &["int_ior", what]);
    }
    // Also through the lone-bsdf loader.
    let e = load_bsdf_str("<bsdf type=\"thindielectric\"><float name=\"ext_ior\" value=\"-1\"/></bsdf>")
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::BadValue);
    assert!(
        e.to_string().contains("ext_ior") && e.to_string().contains("-1"),
        "{e}"
    );
}

#[test]
fn unknown_presets() {
    let t = scene(
        "    <bsdf type=\"dielectric\" id=\"g\"><string name=\"int_ior\" value=\"unobtainium\"/></bsdf>",
    );
    check(
        &load_err(&t),
        ErrorKind::UnknownPreset,
        at(&t, "unobtainium"),
        &["\"unobtainium\"", "bk7", "SF11"],
    );
    let t =
        scene("    <bsdf type=\"conductor\" id=\"m\"><string name=\"material\" value=\"Mithril\"/></bsdf>");
    check(
        &load_err(&t),
        ErrorKind::UnknownPreset,
        at(&t, "Mithril"),
        &["\"Mithril\"", "Au"],
    );
    // A dispersive IOR where plastic needs a number.
    let t = scene("    <bsdf type=\"plastic\" id=\"p\"><string name=\"int_ior\" value=\"SF11\"/></bsdf>");
    check(&load_err(&t), ErrorKind::BadValue, at(&t, "SF11"), &["int_ior"]);
}

#[test]
fn grammar_errors() {
    let t = "<scene>\n</scene>";
    let e = load_err(t);
    check(&e, ErrorKind::Grammar, (1, 1), &["version"]);
    let t = scene("    <shape type=\"sphere\" colour=\"red\"/>");
    check(
        &load_err(&t),
        ErrorKind::Grammar,
        at(&t, "colour"),
        &["\"colour\""],
    );
    let t = scene(
        "    <shape type=\"sphere\"><float name=\"radius\" value=\"1\"/><float name=\"radius\" value=\"2\"/></shape>",
    );
    let second = t.rfind("<float").unwrap();
    let e = load_err(&t);
    assert_eq!(e.kind, ErrorKind::Grammar);
    assert_eq!(
        e.location.column as usize,
        second - t[..second].rfind('\n').unwrap(),
        "{e}"
    );
    let t = scene("    <widget/>");
    check(
        &load_err(&t),
        ErrorKind::Grammar,
        at(&t, "<widget"),
        &["<widget>"],
    );
    let t = scene("    <shape type=\"sphere\"><point name=\"center\" value=\"1\" x=\"2\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::Grammar,
        at(&t, "1\" x=\"2\""),
        &["value"],
    );
    let t = scene(
        "    <shape type=\"rectangle\"><transform name=\"to_world\"><rotate angle=\"30\"/></transform></shape>",
    );
    let e = load_err(&t);
    assert_eq!(e.kind, ErrorKind::BadValue, "{e}");
    assert!(e.to_string().contains("axis"), "{e}");
    let t = scene(
        "    <shape type=\"rectangle\"><transform name=\"to_world\"><shear value=\"1\"/></transform></shape>",
    );
    check(&load_err(&t), ErrorKind::Grammar, at(&t, "<shear"), &["<shear>"]);
    let t = scene("    <shape type=\"sphere\"><emitter type=\"point\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::UnknownPlugin,
        at(&t, "point\"/>"),
        &["\"point\""],
    );
    let t = scene("    <emitter type=\"area\"/>");
    check(&load_err(&t), ErrorKind::Grammar, at(&t, "<emitter"), &["area"]);
    let t = scene(
        "    <bsdf type=\"blendbsdf\" id=\"b\"><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf>",
    );
    check(
        &load_err(&t),
        ErrorKind::Grammar,
        at(&t, "<bsdf type=\"blendbsdf\""),
        &["weight"],
    );
    let t = scene("    <bsdf type=\"twosided\" id=\"b\"><bsdf type=\"dielectric\"/></bsdf>");
    check(
        &load_err(&t),
        ErrorKind::BadValue,
        at(&t, "<bsdf type=\"dielectric\""),
        &["dielectric"],
    );
    let t = scene(
        "    <shape type=\"sphere\"><transform name=\"to_world\"><scale x=\"2\" y=\"1\" z=\"1\"/></transform></shape>",
    );
    check(
        &load_err(&t),
        ErrorKind::BadValue,
        at(&t, "<shape"),
        &["non-uniform"],
    );
    let t = "<scene version=\"3.0.0\">\n    <sensor type=\"perspective\"><float name=\"fov\" value=\"180\"/></sensor>\n</scene>";
    check(&load_err(t), ErrorKind::BadValue, at(t, "180"), &["180"]);
    let t = scene("    <sensor type=\"perspective\"><string name=\"fov_axis\" value=\"z\"/></sensor>");
    check(&load_err(&t), ErrorKind::BadValue, at(&t, "z\"/>"), &["\"z\""]);
    let t = "<scene version=\"3.0.0\">\n    <sensor type=\"perspective\"><transform name=\"to_world\"><scale value=\"2\"/></transform></sensor>\n</scene>";
    check(
        &load_err(t),
        ErrorKind::BadValue,
        at(t, "<transform"),
        &["scale", "2"],
    );
    // A mirror flip keeps unit axes and is allowed (Blender exports use it).
    let t = "<scene version=\"3.0.0\">\n    <sensor type=\"perspective\"><transform name=\"to_world\"><scale x=\"-1\"/></transform></sensor>\n</scene>";
    assert!(load_scene_str(t, data(), &[]).is_ok());
    let e = load_bsdf_str("<scene version=\"3.0.0\"/>").unwrap_err();
    assert_eq!(e.kind, ErrorKind::Grammar);
    assert!(e.to_string().contains("<scene>"), "{e}");
}

#[test]
fn errors_in_included_files_name_that_file() {
    let dir = std::env::temp_dir().join(format!("gonio-xml-errors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("child.xml"),
        "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n    <float name=\"radius\" value=\"oops\"/>\n  </shape>\n</scene>\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("main.xml"),
        "<scene version=\"3.0.0\">\n  <include filename=\"child.xml\"/>\n</scene>\n",
    )
    .unwrap();
    let e = load_scene_file(dir.join("main.xml"), &[]).unwrap_err();
    std::fs::remove_dir_all(&dir).ok();
    assert!(e.location.file.ends_with("child.xml"), "{e}");
    assert_eq!((e.location.line, e.location.column), (3, 33), "{e}");
    assert!(e.to_string().contains("\"oops\""), "{e}");
}

#[test]
fn a_scene_version_newer_than_gonio_understands_is_an_error() {
    // Mitsuba 2.x and every 3.x minor version load (the format is Mitsuba 3's); a major version
    // past 3 is a format gonio cannot know, named with its location.
    for v in ["2.0.0", "2.2.1", "3.0.0", "3.9.1", "3.42"] {
        let t = format!("<scene version=\"{v}\">\n  <shape type=\"sphere\"/>\n</scene>");
        assert!(load_scene_str(&t, data(), &[]).is_ok(), "{v}");
    }
    let t = "<scene version=\"4.0.0\">\n  <shape type=\"sphere\"/>\n</scene>";
    let e = load_err(t);
    check(&e, ErrorKind::BadValue, at(t, "4.0.0"), &["4.0.0"]);
    assert!(e.to_string().contains("newer than gonio understands"), "{e}");
}

/// `shapegroup`, `instance`, `sdfgrid` and the curves: missing and corrupt files, instances of
/// unknown or wrong objects, what a group may not hold.
#[test]
fn instancing_sdf_and_curve_errors() {
    let group = "    <shape type=\"shapegroup\" id=\"g\"><shape type=\"sphere\"/></shape>\n";
    let t = scene(&format!(
        "{group}    <shape type=\"instance\"><ref id=\"nogroup\"/></shape>"
    ));
    let e = load_err(&t);
    assert!(e.to_string().contains("nogroup"), "{e}");
    assert_eq!(e.location.line, at(&t, "nogroup").0, "{e}");
    let t =
        scene("    <bsdf type=\"diffuse\" id=\"b\"/>\n    <shape type=\"instance\"><ref id=\"b\"/></shape>");
    let e = load_err(&t);
    assert!(e.to_string().contains("shapegroup"), "{e}");
    let t =
        scene("    <shape type=\"sphere\" id=\"s\"/>\n    <shape type=\"instance\"><ref id=\"s\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::BadValue,
        at(&t, "<ref id=\"s\""),
        &["\"sphere\""],
    );
    let t = scene("    <shape type=\"instance\"/>");
    check(
        &load_err(&t),
        ErrorKind::Grammar,
        at(&t, "<shape type=\"instance\""),
        &["shapegroup"],
    );
    let t = scene(&format!(
        "{group}    <shape type=\"instance\"><ref id=\"g\"/><ref id=\"g\"/></shape>"
    ));
    let e = load_err(&t);
    assert!(e.to_string().contains("single shapegroup"), "{e}");
    let t = scene(&format!(
        "{group}    <shape type=\"instance\"><ref id=\"g\"/><boolean name=\"flip_normals\" value=\"true\"/></shape>"
    ));
    check(
        &load_err(&t),
        ErrorKind::UnusedParameter,
        at(&t, "<boolean"),
        &["flip_normals"],
    );
    let t = scene(
        "    <shape type=\"shapegroup\" id=\"g\"><shape type=\"sphere\"><emitter type=\"area\"/></shape></shape>",
    );
    let e = load_err(&t);
    assert!(e.to_string().contains("instancing of emitters"), "{e}");
    let t = scene(&format!(
        "{group}    <shape type=\"shapegroup\" id=\"h\"><shape type=\"instance\"><ref id=\"g\"/></shape></shape>"
    ));
    let e = load_err(&t);
    assert!(e.to_string().contains("nested instancing"), "{e}");
    // A group and an instance load; the group alone adds no shape, the instance one per member.
    let t = scene(&format!(
        "{group}    <shape type=\"instance\"><ref id=\"g\"/></shape>\n    <shape type=\"instance\"><ref id=\"g\"/></shape>"
    ));
    assert_eq!(load_scene_str(&t, data(), &[]).unwrap().shapes.len(), 2);

    let t = scene("    <shape type=\"sdfgrid\"><string name=\"filename\" value=\"missing.vol\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::Io,
        at(&t, "missing.vol"),
        &["\"missing.vol\""],
    );
    let t = scene("    <shape type=\"sdfgrid\"><string name=\"filename\" value=\"quad.obj\"/></shape>");
    check(
        &load_err(&t),
        ErrorKind::BadValue,
        at(&t, "quad.obj"),
        &["\"quad.obj\"", "VOL"],
    );
    let t = scene(
        "    <shape type=\"sdfgrid\"><string name=\"filename\" value=\"sphere_sdf.vol\"/><string name=\"normals\" value=\"flat\"/></shape>",
    );
    check(
        &load_err(&t),
        ErrorKind::BadValue,
        at(&t, "flat"),
        &["\"flat\"", "analytic"],
    );
    let t = scene(
        "    <shape type=\"sdfgrid\"><string name=\"filename\" value=\"sphere_sdf.vol\"/><emitter type=\"area\"/></shape>",
    );
    let e = load_err(&t);
    assert!(e.to_string().contains("cannot be an area emitter"), "{e}");
    for ty in ["linearcurve", "bsplinecurve"] {
        let t = scene(&format!(
            "    <shape type=\"{ty}\"><string name=\"filename\" value=\"missing.txt\"/></shape>"
        ));
        check(
            &load_err(&t),
            ErrorKind::Io,
            at(&t, "missing.txt"),
            &["\"missing.txt\""],
        );
        let t = scene(&format!(
            "    <shape type=\"{ty}\"><string name=\"filename\" value=\"quad.obj\"/></shape>"
        ));
        check(
            &load_err(&t),
            ErrorKind::Mesh,
            at(&t, "quad.obj"),
            &["\"quad.obj\"", "line "],
        );
    }
}

/// `mask`, `normalmap` and `bumpmap`: a missing or extra nested BSDF, a missing or unusable
/// texture, each located and named.
#[test]
fn wrapper_bsdf_errors() {
    let err = |t: &str| load_bsdf_str(t).expect_err(t);
    let pos = |e: &SceneError| (e.location.line, e.location.column);
    // mask without its nested BSDF, and with two.
    let e = err("<bsdf type=\"mask\"><float name=\"opacity\" value=\"0.3\"/></bsdf>");
    assert_eq!((e.kind, pos(&e)), (ErrorKind::Grammar, (1, 1)), "{e}");
    assert!(e.to_string().contains("mask needs a nested BSDF"), "{e}");
    let t = "<bsdf type=\"mask\">\n<bsdf type=\"diffuse\"/>\n<bsdf type=\"conductor\"/>\n</bsdf>";
    let e = err(t);
    assert_eq!((e.kind, pos(&e).0), (ErrorKind::Grammar, 3), "{e}");
    assert!(e.to_string().contains("exactly one nested BSDF, found 2"), "{e}");
    // normalmap without its map, with a map it cannot read as RGB, and without a BSDF.
    let e = err("<bsdf type=\"normalmap\"><bsdf type=\"diffuse\"/></bsdf>");
    assert_eq!(e.kind, ErrorKind::Grammar, "{e}");
    assert!(e.to_string().contains("\"normalmap\" texture"), "{e}");
    let t = "<bsdf type=\"normalmap\">\n<texture name=\"normalmap\" type=\"checkerboard\"/>\n<bsdf type=\"diffuse\"/></bsdf>";
    let e = err(t);
    assert_eq!((e.kind, pos(&e).0), (ErrorKind::BadValue, 2), "{e}");
    assert!(e.to_string().contains("bitmap or a constant"), "{e}");
    let e = err("<bsdf type=\"normalmap\"><float name=\"normalmap\" value=\"0.5\"/></bsdf>");
    assert!(
        e.to_string()
            .contains("normalmap needs exactly one nested BSDF, found none"),
        "{e}"
    );
    // bumpmap without a height texture, with two, with a non-finite scale.
    let e = err("<bsdf type=\"bumpmap\"><bsdf type=\"diffuse\"/></bsdf>");
    assert!(e.to_string().contains("bumpmap needs a nested texture"), "{e}");
    let t = "<bsdf type=\"bumpmap\">\n<texture name=\"a\" type=\"checkerboard\"/>\n<texture name=\"b\" type=\"checkerboard\"/>\n<bsdf type=\"diffuse\"/></bsdf>";
    let e = err(t);
    assert_eq!(pos(&e).0, 3, "{e}");
    assert!(
        e.to_string().contains("exactly one nested texture, found 2"),
        "{e}"
    );
    let e = err("<bsdf type=\"bumpmap\"><texture name=\"h\" type=\"checkerboard\"/></bsdf>");
    assert!(
        e.to_string().contains("bumpmap needs exactly one nested BSDF"),
        "{e}"
    );
    // An unknown parameter is still an error.
    let e = err("<bsdf type=\"null\"><float name=\"opacity\" value=\"1\"/></bsdf>");
    assert!(e.to_string().contains("opacity"), "{e}");
}
