//! `gonio compare` end to end: output, exit codes 0/1/2, the difference image.

use gonio_render::image::RgbImage;
use std::process::Command;

/// A fresh temporary folder, removed when the handle drops.
fn dir() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("gonio-compare-cli-")
        .tempdir()
        .unwrap()
}

fn run(args: &[&std::ffi::OsStr]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_gonio"))
        .arg("compare")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn exit_codes_and_report() {
    let d = dir();
    let d = d.path();
    let reference = RgbImage::from_fn(16, 16, |x, y| [0.5 + 0.01 * x as f32, 0.25, 0.1 * y as f32]);
    let mut close = reference.clone();
    close.set(3, 3, [0.52, 0.25, 0.3]);
    let far = RgbImage::from_fn(16, 16, |x, y| {
        let p = reference.get(x, y);
        [p[0] * 2.0, p[1], p[2]]
    });
    let (rp, cp, fp) = (d.join("ref.exr"), d.join("close.exr"), d.join("far.exr"));
    reference.write_exr(&rp).unwrap();
    close.write_exr(&cp).unwrap();
    far.write_exr(&fp).unwrap();
    let diff = d.join("diff.png");

    let (code, out, err) = run(&[
        cp.as_os_str(),
        rp.as_os_str(),
        "--max-relmse".as_ref(),
        "1e-3".as_ref(),
        "--diff".as_ref(),
        diff.as_os_str(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    for key in [
        "relMSE",
        "RMSE",
        "MAE",
        "mean a",
        "mean b",
        "worst block   x 0 y 0",
    ] {
        assert!(out.contains(key), "missing {key:?} in\n{out}");
    }
    let png = RgbImage::read(&diff).unwrap();
    assert_eq!((png.width, png.height), (16, 16));
    assert!(png.get(3, 3).iter().sum::<f32>() > png.get(10, 10).iter().sum::<f32>());

    let (code, out, _) = run(&[
        fp.as_os_str(),
        rp.as_os_str(),
        "--max-relmse".as_ref(),
        "1e-3".as_ref(),
    ]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("FAIL"), "{out}");
    let (code, _, _) = run(&[
        fp.as_os_str(),
        rp.as_os_str(),
        "--max-block-relmse".as_ref(),
        "1e-3".as_ref(),
    ]);
    assert_eq!(code, 1);
    // No threshold: report only, success.
    let (code, _, _) = run(&[fp.as_os_str(), rp.as_os_str()]);
    assert_eq!(code, 0);
}

#[test]
fn bad_input_exits_2_naming_the_file() {
    let d = dir();
    let d = d.path();
    let good = d.join("good.exr");
    RgbImage::new(4, 4).write_exr(&good).unwrap();
    let junk = d.join("junk.exr");
    std::fs::write(&junk, b"not an image").unwrap();
    let (code, _, err) = run(&[junk.as_os_str(), good.as_os_str()]);
    assert_eq!(code, 2);
    assert!(err.contains("junk.exr"), "{err}");
    let missing = d.join("missing.exr");
    let (code, _, err) = run(&[good.as_os_str(), missing.as_os_str()]);
    assert_eq!(code, 2);
    assert!(err.contains("missing.exr"), "{err}");
    let other = d.join("other.exr");
    RgbImage::new(5, 4).write_exr(&other).unwrap();
    let (code, _, err) = run(&[
        good.as_os_str(),
        other.as_os_str(),
        "--max-relmse".as_ref(),
        "1".as_ref(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("sizes differ"), "{err}");
}
