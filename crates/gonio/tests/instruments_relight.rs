//! `gonio relight`: the light stage reproduces a direct render under an environment map, and its
//! error falls as the number of lights grows.

use gonio_render::image::RgbImage;
use std::path::{Path, PathBuf};
use std::process::Command;

fn gonio() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gonio"))
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gonio-test-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

const SCENE: &str = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="4"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <transform name="to_world"><lookat origin="0, 0, 6" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/></film>
    </sensor>
    <shape type="sphere">
        <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.4, 0.2"/></bsdf>
    </shape>
    <emitter type="constant"/>
</scene>"#;

/// A sky: dim blue above, darker below, and a warm bright patch (a "sun") up and to the side.
fn write_env(path: &Path) {
    let img = RgbImage::from_fn(64, 32, |i, j| {
        let v = (j as f32 + 0.5) / 32.0;
        let u = (i as f32 + 0.5) / 64.0;
        let sky = if v < 0.5 {
            [0.3, 0.4, 0.6]
        } else {
            [0.08, 0.06, 0.05]
        };
        let sun = if (u - 0.3).abs() < 0.06 && (v - 0.3).abs() < 0.08 {
            [8.0, 6.0, 3.0]
        } else {
            [0.0; 3]
        };
        [sky[0] + sun[0], sky[1] + sun[1], sky[2] + sun[2]]
    });
    img.write_exr(path).unwrap();
}

#[test]
fn relighting_error_falls_as_the_number_of_lights_grows() {
    let dir = tmpdir("relight");
    let scene = dir.join("scene.xml");
    std::fs::write(&scene, SCENE).unwrap();
    let env = dir.join("env.exr");
    write_env(&env);
    let out = dir.join("relit.exr");
    let direct = dir.join("direct.exr");
    let o = gonio()
        .args([
            "relight",
            scene.to_str().unwrap(),
            "--lights",
            "256",
            "--series",
            "4,16,64",
            "--env",
        ])
        .arg(&env)
        .arg("-o")
        .arg(&out)
        .arg("--direct")
        .arg(&direct)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    eprintln!("{stdout}");
    let errors: Vec<(usize, f64)> = stdout
        .lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() == 3)
                .then(|| Some((f[0].parse().ok()?, f[1].parse().ok()?)))
                .flatten()
        })
        .collect();
    assert_eq!(
        errors.iter().map(|e| e.0).collect::<Vec<_>>(),
        vec![4, 16, 64, 256],
        "{stdout}"
    );
    // The discretization error falls with N until the Monte Carlo noise of the renders is
    // reached (measured: 0.088, 0.0040, 0.0012, 0.0011).
    assert!(
        errors[1].1 < errors[0].1 && errors[2].1 < errors[1].1,
        "error must fall: {errors:?}"
    );
    assert!(errors[3].1 < 1.1 * errors[2].1, "{errors:?}");
    assert!(errors[3].1 < 0.25 * errors[0].1, "{errors:?}");
    assert!(
        errors[3].1 < 0.05,
        "256 lights reproduce the environment render: {errors:?}"
    );
    let relit = RgbImage::read(&out).unwrap();
    let d = RgbImage::read(&direct).unwrap();
    assert_eq!((relit.width, relit.height), (d.width, d.height));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_relight_input_is_reported() {
    let o = gonio()
        .args([
            "relight",
            "/nonexistent/scene.xml",
            "--env",
            "x.exr",
            "-o",
            "y.exr",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("/nonexistent/scene.xml"));
    let o = gonio()
        .args([
            "relight", "s.xml", "--lights", "0", "--env", "x.exr", "-o", "y.exr",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--lights 0"));
    // A spectral film records bands, which the RGB weights cannot relight.
    let bands =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/specfilm/bands.xml");
    let o = gonio()
        .args([
            "relight",
            bands.to_str().unwrap(),
            "--env",
            "x.exr",
            "-o",
            "y.exr",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("specfilm"));
}
