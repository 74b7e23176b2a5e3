//! `gonio render` end to end: outputs by extension, determinism across `--threads`, the default
//! scene, clear errors for bad input, and Ctrl-C still writing the image.

use gonio_render::image::RgbImage;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn gonio() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gonio"))
}

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../testdata/mitsuba/scenes/{name}.xml"))
}

/// A fresh temporary folder, removed when the handle drops (hold it for the test's length).
fn tempdir(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("gonio-render-cli-{tag}-"))
        .tempdir()
        .unwrap()
}

fn run(args: &[&str], cwd: &Path) -> Output {
    gonio().args(args).current_dir(cwd).output().expect("gonio runs")
}

#[test]
fn renders_exr_and_png_and_is_deterministic_across_threads() {
    let dir = tempdir("basic");
    let dir = dir.path();
    let s = scene("cornell-spheres");
    let s = s.to_str().unwrap();
    let common = [
        "render",
        s,
        "-D",
        "width=40",
        "-D",
        "height=32",
        "--spp",
        "4",
        "--seed",
        "5",
    ];
    let a = run(&[&common[..], &["-o", "a.exr", "--threads", "1"]].concat(), dir);
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    let b = run(&[&common[..], &["-o", "b.exr", "--threads", "2"]].concat(), dir);
    assert!(b.status.success());
    let (ia, ib) = (
        RgbImage::read(dir.join("a.exr")).unwrap(),
        RgbImage::read(dir.join("b.exr")).unwrap(),
    );
    assert_eq!((ia.width, ia.height), (40, 32));
    assert!(ia.data == ib.data, "--threads 1 and 2 must give the same image");
    let stderr = String::from_utf8_lossy(&a.stderr);
    assert!(
        stderr.contains("40x32") && stderr.contains("4 spp"),
        "summary line: {stderr}"
    );

    // Mitsuba's independent sampler gives another (noisier) image of the same scene.
    let ind = run(
        &[&common[..], &["-o", "d.exr", "--sampler", "independent"]].concat(),
        dir,
    );
    assert!(ind.status.success());
    assert!(RgbImage::read(dir.join("d.exr")).unwrap().data != ia.data);
    std::fs::remove_file(dir.join("d.exr")).unwrap();

    let p = run(&[&common[..], &["-o", "c.png"]].concat(), dir);
    assert!(p.status.success());
    let bytes = std::fs::read(dir.join("c.png")).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    // No temporary files are left behind.
    let names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 3, "{names:?}");
}

#[test]
fn no_scene_renders_the_default_gallery_to_png_and_exr() {
    let dir = tempdir("default");
    let dir = dir.path();
    let out = run(
        &[
            "render",
            "-D",
            "width=32",
            "-D",
            "height=16",
            "-D",
            "spp=2",
            "--quiet",
        ],
        dir,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        out.stderr.is_empty(),
        "--quiet prints nothing: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let exr = RgbImage::read(dir.join("gonio.exr")).unwrap();
    let png = RgbImage::read(dir.join("gonio.png")).unwrap();
    assert_eq!((exr.width, exr.height, png.width, png.height), (32, 16, 32, 16));
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = tempdir("errors");
    let dir = dir.path();
    let missing = run(&["render", "no-such-scene.xml", "-o", "x.exr"], dir);
    assert_eq!(missing.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("no-such-scene.xml"));

    let s = scene("furnace");
    let s = s.to_str().unwrap();
    let bad_define = run(&["render", s, "-D", "width"], dir);
    assert_eq!(bad_define.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad_define.stderr).contains("NAME=VALUE"));

    let bad_ext = run(&["render", s, "-o", "x.tiff", "--spp", "1"], dir);
    assert_eq!(bad_ext.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad_ext.stderr).contains("x.tiff"));

    let bad_sampler = run(&["render", s, "--sampler", "halton", "--spp", "1"], dir);
    assert_eq!(
        bad_sampler.status.code(),
        Some(2),
        "clap rejects an unknown sampler"
    );

    let zero = run(&["render", s, "--spp", "0"], dir);
    assert_eq!(zero.status.code(), Some(2));

    let unused = run(&["render", s, "-D", "nonsense=3", "--spp", "1"], dir);
    assert_eq!(
        unused.status.code(),
        Some(2),
        "an unused -D is an error, as in Mitsuba"
    );
    assert_eq!(
        std::fs::read_dir(dir).unwrap().count(),
        0,
        "nothing written on error"
    );
}

#[test]
fn ctrl_c_still_writes_the_image() {
    let dir = tempdir("sigint");
    let dir = dir.path();
    let s = scene("cornell-spheres");
    let child = gonio()
        .args([
            "render",
            s.to_str().unwrap(),
            "--spp",
            "100000",
            "-D",
            "width=64",
            "-D",
            "height=64",
            "-o",
            "i.exr",
        ])
        .current_dir(dir)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("interrupted"));
    let img = RgbImage::read(dir.join("i.exr")).expect("the partial image is written");
    assert_eq!((img.width, img.height), (64, 64));
    assert!(img.data.iter().any(|c| c[0] > 0.0));
}

#[test]
fn loader_warnings_reach_the_user() {
    // A scene without an integrator renders with Mitsuba's defaults, and says so on stderr with
    // the file and position of the scene element.
    let dir = tempdir("warnings");
    let dir = dir.path();
    std::fs::write(
        dir.join("nointeg.xml"),
        r#"<scene version="3.0.0">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="6"/></film></sensor>
    <shape type="sphere"/>
    <emitter type="constant"/>
</scene>"#,
    )
    .unwrap();
    let out = run(&["render", "nointeg.xml", "-o", "ni.exr"], dir);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("warning") && err.contains("nointeg.xml:1:1") && err.contains("integrator"),
        "{err}"
    );
    assert!(dir.join("ni.exr").exists());
}

/// A tiny scene: a sphere in the middle of a 16 × 16 film, lit by a point light, no
/// environment, with the given `hdrfilm` settings.
fn film_scene(dir: &Path, name: &str, film_settings: &str) -> PathBuf {
    let xml = format!(
        r#"<scene version="3.0.0">
    <default name="spp" value="4"/>
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/>
            {film_settings}
        </film>
    </sensor>
    <shape type="sphere"><float name="radius" value="0.8"/><bsdf type="diffuse"/></shape>
    <emitter type="point"><point name="position" x="0" y="3" z="5"/><rgb name="intensity" value="20"/></emitter>
</scene>"#
    );
    let path = dir.join(name);
    std::fs::write(&path, xml).unwrap();
    path
}

fn read_exr(path: &Path) -> exr::image::FlatImage {
    exr::prelude::read_all_flat_layers_from_file(path).expect("a readable EXR")
}

#[test]
fn output_goes_next_to_the_scene_in_the_films_format_as_in_mitsuba() {
    // No -o: `<scene folder>/<scene name>.<file_format's extension>`, whatever the working
    // directory; several scenes in one call; Mitsuba's -t and --define spellings.
    let dir = tempdir("beside");
    let dir = dir.path();
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let a = film_scene(&scenes, "a.xml", "");
    let b = film_scene(&scenes, "b.xml", r#"<string name="file_format" value="pfm"/>"#);
    let c = film_scene(&scenes, "c.xml", r#"<string name="file_format" value="rgbe"/>"#);
    let out = run(
        &[
            "render",
            a.to_str().unwrap(),
            b.to_str().unwrap(),
            c.to_str().unwrap(),
            "-t",
            "1",
            "--define",
            "spp=2",
            "-q",
        ],
        dir,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(scenes.join("a.exr").exists() && scenes.join("b.pfm").exists() && scenes.join("c.hdr").exists());
    assert_eq!(
        std::fs::read_dir(dir).unwrap().count(),
        1,
        "nothing in the working directory"
    );
    let pfm = std::fs::read(scenes.join("b.pfm")).unwrap();
    assert!(pfm.starts_with(b"PF\n16 16\n-1.0\n") && pfm.len() == 14 + 16 * 16 * 3 * 4);
    let hdr = RgbImage::read(scenes.join("c.hdr")).expect("a Radiance file gonio reads back");
    let exr = RgbImage::read(scenes.join("a.exr")).unwrap();
    // The sphere's centre, lit: both formats hold the same value within RGBE's 8-bit mantissa.
    let (h, e) = (hdr.get(8, 8), exr.get(8, 8));
    assert!(
        e[0] > 0.01 && (h[0] - e[0]).abs() < 0.01 * e[0] + 1e-3,
        "{h:?} vs {e:?}"
    );
    // One -o for several scenes is ambiguous.
    let two = run(
        &["render", a.to_str().unwrap(), b.to_str().unwrap(), "-o", "x.exr"],
        dir,
    );
    assert_eq!(two.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&two.stderr).contains("-o"));
}

#[test]
fn film_pixel_and_component_formats_are_honoured() {
    use exr::prelude::{AttributeValue, FlatSamples};
    let dir = tempdir("formats");
    let dir = dir.path();
    let rgba = film_scene(
        dir,
        "rgba.xml",
        r#"<string name="pixel_format" value="rgba"/><string name="component_format" value="float32"/>"#,
    );
    let lum = film_scene(
        dir,
        "lum.xml",
        r#"<string name="pixel_format" value="luminance"/>"#,
    );
    let out = run(
        &[
            "render",
            rgba.to_str().unwrap(),
            lum.to_str().unwrap(),
            "--seed",
            "7",
            "-q",
        ],
        dir,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));

    let img = read_exr(&dir.join("rgba.exr"));
    let layer = &img.layer_data[0];
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    assert_eq!(names, ["A", "B", "G", "R"]);
    let alpha = &layer.channel_data.list[0].sample_data;
    assert!(matches!(alpha, FlatSamples::F32(_)), "component_format float32");
    // Alpha: 1 on the sphere (centre), 0 in the empty corner (no environment behind it).
    assert_eq!(alpha.value_by_flat_index(8 * 16 + 8).to_f32(), 1.0);
    assert_eq!(alpha.value_by_flat_index(0).to_f32(), 0.0);
    // The header records how the image was made.
    let attrs = &layer.attributes.other;
    let text = |k: &str| match attrs.get(&exr::prelude::Text::from(k)) {
        Some(AttributeValue::Text(t)) => t.to_string(),
        other => panic!("{k}: {other:?}"),
    };
    assert!(text("generatedBy").starts_with("gonio "));
    assert_eq!(text("spp"), "4");
    assert_eq!(text("seed"), "7");
    assert!(text("renderTime").ends_with(" s"));

    let img = read_exr(&dir.join("lum.exr"));
    let list = &img.layer_data[0].channel_data.list;
    assert_eq!(list.len(), 1);
    assert_eq!(list[0].name.to_string(), "Y");
    assert!(
        matches!(list[0].sample_data, FlatSamples::F16(_)),
        "Mitsuba's default: half floats"
    );
    // Y is the luminance of the colour the RGBA render holds (same seed, same samples).
    let rgb = RgbImage::read(dir.join("rgba.exr")).unwrap().get(8, 8);
    let y = list[0].sample_data.value_by_flat_index(8 * 16 + 8).to_f32();
    let expect = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
    assert!((y - expect).abs() < 2e-3 * expect, "{y} vs {expect}");
}

/// `--mitsuba-estimators` renders a scene as if every estimator parameter of ours were written
/// with Mitsuba's value: here a `roughplastic` sphere (`coat_averages`) renders bit-identically to
/// the same scene with `coat_averages="mitsuba"` written out, and differently from the default.
#[test]
fn mitsuba_estimators_flag_equals_writing_mitsubas_values() {
    let dir = tempdir("mitsuba-estimators");
    let dir = dir.path();
    let write = |name: &str, bsdf: &str| {
        let xml = std::fs::read_to_string(film_scene(dir, name, "")).unwrap();
        let xml = xml.replace(r#"<bsdf type="diffuse"/>"#, bsdf);
        std::fs::write(dir.join(name), xml).unwrap();
        dir.join(name)
    };
    let plain = write("plain.xml", r#"<bsdf type="roughplastic"/>"#);
    let written = write(
        "written.xml",
        r#"<bsdf type="roughplastic"><string name="coat_averages" value="mitsuba"/></bsdf>"#,
    );
    let render = |scene: &Path, out: &str, flag: bool| {
        let out = dir.join(out);
        let mut args = vec!["render", "-q", "-t", "1", "-o", out.to_str().unwrap()];
        if flag {
            args.push("--mitsuba-estimators");
        }
        args.push(scene.to_str().unwrap());
        let o = run(&args, dir);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        RgbImage::read(&out).unwrap().data
    };
    let flagged = render(&plain, "flagged.exr", true);
    assert_eq!(flagged, render(&written, "written.exr", false));
    assert_ne!(flagged, render(&plain, "plain.exr", false));
}

#[test]
fn a_mesh_scene_without_embree_says_its_meshes_use_our_bvh() {
    // Two cubes (24 triangles, past the flat list's 16 primitives): Embree's work when loaded.
    let dir = tempdir("embree-note");
    let dir = dir.path();
    let xml = r#"<scene version="3.0.0">
    <integrator type="path"/>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0, 8" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
        <sampler type="independent"><integer name="sample_count" value="1"/></sampler>
    </sensor>
    <shape type="cube"><transform name="to_world"><translate x="-1.5"/></transform></shape>
    <shape type="cube"><transform name="to_world"><translate x="1.5"/></transform></shape>
    <emitter type="constant"/>
</scene>"#;
    let s = dir.join("cubes.xml");
    std::fs::write(&s, xml).unwrap();
    let render = |embree: Option<&str>| {
        let mut c = gonio();
        c.args(["render", s.to_str().unwrap(), "-o", "cubes.exr"])
            .current_dir(dir);
        if let Some(v) = embree {
            c.env("GONIO_EMBREE", v);
        }
        let out = c.output().expect("gonio runs");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let note = "traced by gonio's own BVH";
    let off = render(Some("off"));
    assert!(off.contains(note), "GONIO_EMBREE=off: no note in {off:?}");
    // As the process finds it: the note exactly when Embree is missing.
    let default = render(None);
    assert_eq!(
        default.contains(note),
        !gonio_render::accel::embree::available(),
        "{default:?}"
    );
    // Quiet stays quiet.
    let mut c = gonio();
    c.args(["render", s.to_str().unwrap(), "-o", "cubes.exr", "--quiet"])
        .current_dir(dir)
        .env("GONIO_EMBREE", "off");
    let out = c.output().expect("gonio runs");
    assert!(out.status.success() && out.stderr.is_empty(), "{:?}", out);
}

/// A spectral film (`specfilm`) is written as OpenEXR with one channel per band, the default
/// output takes `.exr`, and any other extension is refused before rendering (no file).
#[test]
fn a_spectral_film_writes_its_bands_to_exr_only() {
    let dir = tempdir("specfilm");
    let dir = dir.path();
    let s = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/specfilm/bands.xml");
    let s = s.to_str().unwrap();
    let out = run(&["render", s, "--spp", "2", "-q", "-o", "bands.exr"], dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let img = gonio_render::image::ChannelImage::read(dir.join("bands.exr")).unwrap();
    let mut names = img.names.clone();
    names.sort();
    assert_eq!(names, ["band1_blue", "band2_green", "band3_red", "band4_nir"]);
    assert_eq!((img.width, img.height), (32, 24));
    for ext in ["png", "hdr", "pfm"] {
        let out = run(
            &["render", s, "--spp", "2", "-q", "-o", &format!("bands.{ext}")],
            dir,
        );
        assert!(!out.status.success());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("specfilm") && stderr.contains(".exr"), "{stderr}");
        assert!(!dir.join(format!("bands.{ext}")).exists());
    }
}
