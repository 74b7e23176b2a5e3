//! The instrument commands end to end: `gonio plot`, `gonio check`, `gonio measure`, with
//! figures known in advance.

use glam::Vec3;
use gonio_core::bsdf::{Bsdf, BsdfContext};
use gonio_core::bsdfs::Plastic;
use gonio_core::{SampledWavelengths, instruments::spherical_direction};
use gonio_render::tabulated_io::read_tabulated;
use std::path::PathBuf;
use std::process::{Command, Output};

fn gonio(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gonio"))
        .args(args)
        .output()
        .unwrap()
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gonio-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

const DIFFUSE: &str = r#"<bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf>"#;
const GLASS: &str = r#"<bsdf type="dielectric"><float name="int_ior" value="1.5"/></bsdf>"#;
const MIRROR: &str = r#"<bsdf type="conductor"/>"#;

#[test]
fn plot_fresnel_writes_png_and_svg_with_the_angles_marked() {
    let d = tmpdir("fresnel");
    let out = d.join("glass");
    let o = gonio(&["plot", "fresnel", "--ior", "1.5", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{:?}", text(&o));
    let svg = std::fs::read_to_string(d.join("glass.svg")).unwrap();
    assert!(svg.contains("Brewster 56.3°") && svg.contains("critical 41.8°"));
    // The polarization panels: degree of polarization on both sides, the phase of TIR.
    assert!(svg.contains("degree of polarization") && svg.contains("|δ|, inside (TIR)"));
    let png = std::fs::read(d.join("glass.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    for args in [["--material", "Au"], ["--ior-spectrum", "N-BK7"]] {
        let o = gonio(&[
            "plot",
            "fresnel",
            args[0],
            args[1],
            "-o",
            d.join("x.png").to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{args:?}: {:?}", text(&o));
    }
    let o = gonio(&[
        "plot",
        "fresnel",
        "--material",
        "Unobtainium",
        "-o",
        d.join("y.png").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("Unobtainium"), "the error names the value");
    let _ = std::fs::remove_dir_all(d);
}

#[test]
fn plot_slices_polar_and_albedo() {
    let d = tmpdir("slices");
    let p = |n: &str| d.join(n).to_str().unwrap().to_string();
    let o = gonio(&["plot", "slice", MIRROR, "--theta", "30", "-o", &p("mirror.svg")]);
    assert!(o.status.success(), "{:?}", text(&o));
    let svg = std::fs::read_to_string(d.join("mirror.svg")).unwrap();
    assert!(
        svg.contains("δ reflection, 1.000"),
        "the mirror's delta is marked"
    );
    assert!(svg.contains("f = 0 off the delta lobes") && svg.contains("Lambert equal-area projection"));
    for extra in [
        &["--log", "--cosine"][..],
        &["--rgb", "--projection", "parabolic"][..],
        &["--fix", "view", "--lambda", "450"][..],
    ] {
        let mut args = vec!["plot", "slice", GLASS, "--theta", "40", "--resolution", "64"];
        args.extend_from_slice(extra);
        let out = p("glass.png");
        args.extend_from_slice(&["-o", &out]);
        let o = gonio(&args);
        assert!(o.status.success(), "{extra:?}: {:?}", text(&o));
    }
    let o = gonio(&[
        "plot",
        "polar",
        DIFFUSE,
        GLASS,
        "--theta-i",
        "45",
        "-o",
        &p("polar.svg"),
    ]);
    assert!(o.status.success(), "{:?}", text(&o));
    let svg = std::fs::read_to_string(d.join("polar.svg")).unwrap();
    assert!(svg.contains("δ transmission") && svg.contains("dielectric") && svg.contains("diffuse"));
    // Albedo: the known figures R = ρ for a Lambertian, R + T = 1 for lossless glass.
    let o = gonio(&[
        "plot",
        "albedo",
        DIFFUSE,
        GLASS,
        "--samples",
        "4000",
        "--lambda",
        "550",
        "--print",
        "-o",
        &p("albedo.png"),
    ]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    let rows: Vec<Vec<f64>> = out
        .lines()
        .filter(|l| !l.starts_with('#') && !l.ends_with(".png"))
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2 * 19, "{out}");
    for r in &rows[..19] {
        assert!((r[1] - 0.5).abs() < 1e-6 && r[3] == 0.0, "diffuse {r:?}");
    }
    for r in &rows[19..] {
        assert!((r[1] + r[3] - 1.0).abs() < 1e-4, "glass R + T = 1: {r:?}");
    }
    let o = gonio(&["plot", "slice", "<bsdf type=\"nosuch\"/>", "-o", &p("bad.png")]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("nosuch"), "{:?}", text(&o));
    let o = gonio(&["plot", "slice", DIFFUSE, "--theta", "200", "-o", &p("bad.png")]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("--theta 200"));
    let o = gonio(&["plot", "polar", DIFFUSE, "--lambda", "2000", "-o", &p("bad.png")]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("--lambda 2000"));
    let _ = std::fs::remove_dir_all(d);
}

#[test]
fn check_passes_a_good_bsdf_and_fails_an_energy_gaining_one() {
    let o = gonio(&["check", DIFFUSE, "--quick"]);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    assert!(
        out.contains("0 failed")
            && out.contains("chi2")
            && out.contains("reciprocity")
            && out.contains("isotropy")
    );
    // Reflectance 1.5 reflects more than it receives: the energy row must fail, exit status 1.
    let gain = r#"<bsdf type="diffuse"><float name="reflectance" value="1.5"/></bsdf>"#;
    let o = gonio(&["check", gain, "--quick", "--json"]);
    let (out, _) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{out}");
    let report: serde_json::Value = serde_json::from_str(&out).expect("the report is JSON");
    assert_eq!(report["passed"], false, "{out}");
    let rows = report["rows"].as_array().expect("rows");
    assert!(
        rows.iter().any(|r| r["name"] == "energy" && r["figure"] == 1.5),
        "{out}"
    );
    let o = gonio(&["check", "/no/such/file.xml"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn measured_tables_match_the_analytic_bsdf_within_their_noise() {
    let d = tmpdir("measure");
    let table = d.join("diffuse.txt");
    let o = gonio(&[
        "measure",
        DIFFUSE,
        "-o",
        table.to_str().unwrap(),
        "--incident",
        "4",
        "--outgoing",
        "6",
        "--azimuths",
        "7",
        "--photons",
        "200000",
        "--aperture",
        "5",
    ]);
    assert!(o.status.success(), "{:?}", text(&o));
    let t = read_tabulated(&table).unwrap();
    let err = t.stderr.as_ref().unwrap();
    for (v, e) in t.values.iter().zip(err) {
        assert!((v - 0.5 / std::f32::consts::PI).abs() < 4.5 * e, "{v} ± {e}");
    }

    // Plastic: away from its specular spike, the table is the analytic BRDF within its noise.
    let table = d.join("plastic.txt");
    let o = gonio(&[
        "measure",
        r#"<bsdf type="plastic"/>"#,
        "-o",
        table.to_str().unwrap(),
        "--incident",
        "4",
        "--outgoing",
        "6",
        "--azimuths",
        "7",
        "--photons",
        "400000",
        "--aperture",
        "5",
        "--lambda",
        "550",
    ]);
    assert!(o.status.success(), "{:?}", text(&o));
    let t = read_tabulated(&table).unwrap();
    let plastic = Plastic::default();
    let wl = SampledWavelengths::fixed(550.0);
    let (mut compared, mut worst) = (0, 0.0f32);
    for (i, &ti) in t.theta_i_deg.iter().enumerate() {
        for (o_, &to) in t.theta_o_deg.iter().enumerate() {
            for (p, &pd) in t.phi_d_deg.iter().enumerate() {
                let light = spherical_direction(ti.to_radians(), 0.0);
                let view = spherical_direction(to.to_radians(), pd.to_radians());
                let mirror = Vec3::new(-light.x, -light.y, light.z);
                if view.dot(mirror) > 15f32.to_radians().cos() {
                    continue; // the delta lobe reads as a bump there
                }
                let f = plastic.eval(&BsdfContext::radiance(), view, light, &wl)[0];
                let k = t.index(i, o_, p, 0);
                let z = (t.values[k] - f) / t.stderr.as_ref().unwrap()[k];
                worst = worst.max(z.abs());
                compared += 1;
            }
        }
    }
    assert!(
        compared > 120 && worst < 4.5,
        "{compared} readings, worst |z| = {worst}"
    );
    let o = gonio(&[
        "measure",
        DIFFUSE,
        "-o",
        table.to_str().unwrap(),
        "--aperture",
        "0",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("aperture"));
    let hf = d.join("hf.txt");
    let o = gonio(&[
        "measure",
        DIFFUSE,
        "-o",
        hf.to_str().unwrap(),
        "--heightfield",
        "4",
        "--incident",
        "2",
        "--outgoing",
        "2",
        "--azimuths",
        "3",
        "--photons",
        "20000",
    ]);
    assert!(o.status.success(), "{:?}", text(&o));
    assert!(
        read_tabulated(&hf)
            .unwrap()
            .description
            .contains("heightfield 4x4")
    );
    // A Gaussian (Beckmann-slope) surface of mirrors; a bad α is refused by name.
    let mirror = r#"<bsdf type="conductor"/>"#;
    let gauss = d.join("gauss.txt");
    let args = |alpha: &'static str| {
        vec![
            "measure",
            mirror,
            "-o",
            gauss.to_str().unwrap(),
            "--heightfield",
            "64",
            "--alpha",
            alpha,
            "--incident",
            "2",
            "--outgoing",
            "2",
            "--azimuths",
            "3",
            "--photons",
            "20000",
        ]
    };
    let o = gonio(&args("0.3"));
    assert!(o.status.success(), "{:?}", text(&o));
    assert!(
        read_tabulated(&gauss)
            .unwrap()
            .description
            .contains("heightfield 64x64")
    );
    let o = gonio(&args("0"));
    assert!(!o.status.success());
    assert!(text(&o).1.contains("--alpha 0"), "{:?}", text(&o));
    let _ = std::fs::remove_dir_all(d);
}

/// A synthetic Stokes EXR, written by the repository's own EXR writer with Mitsuba's channel
/// names: four pixels of known Stokes vectors (equal in R, G, B) → known colours in each view.
#[test]
fn plot_stokes_false_colours_and_missing_layer() {
    use gonio_render::image::{ChannelImage, Encoding, RgbImage};
    let d = tmpdir("stokes");
    // (S0, S1, S2, S3): horizontal; −45°; half right-circular; no light.
    let pixels = [
        [1.0f32, 1.0, 0.0, 0.0],
        [2.0, 0.0, -2.0, 0.0],
        [4.0, 0.0, 0.0, 2.0],
        [0.0, 0.0, 0.0, 0.0],
    ];
    let write = |skip: Option<&str>, file: &str| {
        let mut names: Vec<String> = ["R", "G", "B"].map(String::from).to_vec();
        for k in 0..4 {
            for c in ["R", "G", "B"] {
                names.push(format!("S{k}.{c}"));
            }
        }
        names.retain(|n| Some(n.as_str()) != skip);
        let mut data = vec![];
        for p in &pixels {
            for n in &names {
                data.push(match n.strip_prefix('S') {
                    Some(rest) => p[rest[..1].parse::<usize>().unwrap()],
                    None => p[0],
                });
            }
        }
        let img = ChannelImage {
            width: 4,
            height: 1,
            names,
            data,
        };
        let path = d.join(file);
        img.write_exr(&path).unwrap();
        path
    };
    let path = write(None, "stokes.exr");
    let o = gonio(&["plot", "stokes", path.to_str().unwrap()]);
    assert!(o.status.success(), "{:?}", text(&o));
    assert_eq!(text(&o).0.lines().count(), 6, "six files listed");
    let read = |suffix: &str| -> Vec<[u8; 3]> {
        let img = RgbImage::read_with(d.join(format!("stokes_{suffix}.png")), Encoding::Raw).unwrap();
        assert_eq!((img.width, img.height), (4, 1));
        img.data
            .iter()
            .map(|p| p.map(|v| (v * 255.0).round() as u8))
            .collect()
    };
    const BLACK: [u8; 3] = [0, 0, 0];
    const RED_END: [u8; 3] = [180, 4, 38]; // diverging +1
    const BLUE_END: [u8; 3] = [59, 76, 192]; // diverging −1
    const GREY: [u8; 3] = [221, 221, 221]; // diverging 0
    assert_eq!(read("s1"), [RED_END, GREY, GREY, BLACK]);
    assert_eq!(read("s2"), [GREY, BLUE_END, GREY, BLACK]);
    // S3/S0 = 0.5: halfway from grey to the red end.
    assert_eq!(read("s3"), [GREY, GREY, [200, 112, 129], BLACK]);
    // viridis: 1 → yellow, 0 → purple, 0.5 → teal.
    assert_eq!(read("dolp"), [[253, 231, 37], [253, 231, 37], [68, 1, 84], BLACK]);
    assert_eq!(
        read("dop"),
        [[253, 231, 37], [253, 231, 37], [33, 145, 140], BLACK]
    );
    // Hue circle over 180°: 0° red, −45° a quarter turn back (violet); no linear part: 0°.
    assert_eq!(read("aolp"), [[255, 0, 0], [128, 0, 255], [255, 0, 0], BLACK]);

    let broken = write(Some("S2.G"), "broken.exr");
    let o = gonio(&["plot", "stokes", broken.to_str().unwrap()]);
    assert!(!o.status.success());
    let err = text(&o).1;
    assert!(
        err.contains("broken.exr") && err.contains("no channel S2.G"),
        "the error names the file and the layer: {err}"
    );
    let _ = std::fs::remove_dir_all(d);
}
