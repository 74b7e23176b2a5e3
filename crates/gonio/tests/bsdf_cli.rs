//! `gonio bsdf`: the scriptable query interface, driven as a user would, through stdin.

use std::io::Write;
use std::process::{Command, Stdio};

fn gonio_bsdf(args: &[&str], stdin: &str) -> (i32, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gonio"))
        .arg("bsdf")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("gonio runs");
    child.stdin.take().unwrap().write_all(stdin.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

fn numbers(line: &str) -> Vec<f64> {
    line.split_whitespace().filter_map(|t| t.parse().ok()).collect()
}

const GLASS: &str = r#"<bsdf version="3.0.0" type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>"#;

#[test]
fn albedo_of_glass_is_fresnel_and_eta_squared_exactly() {
    // Normal incidence, η = 1.5: R = 0.04; radiance T = 0.96/η² from outside, 0.96·η² from
    // inside; importance T = 0.96 (as Mitsuba 3 src/bsdfs/dielectric.cpp).
    let (code, out, _) = gonio_bsdf(&["albedo", GLASS], "0 0 1 550\n0 0 -1 550\n");
    assert_eq!(code, 0);
    let rows: Vec<Vec<f64>> = out.lines().map(numbers).collect();
    assert!(
        (rows[0][0] - 0.04).abs() < 1e-6 && (rows[0][1] - 0.96 / 2.25).abs() < 1e-6,
        "{out}"
    );
    assert!(
        (rows[1][0] - 0.04).abs() < 1e-6 && (rows[1][1] - 0.96 * 2.25).abs() < 1e-5,
        "{out}"
    );
    let (_, out, _) = gonio_bsdf(&["albedo", "--mode", "importance", GLASS], "0 0 1 550\n");
    let r = numbers(out.trim());
    assert!(
        (r[0] + r[1] - 1.0).abs() < 1e-6,
        "lossless in importance mode: {out}"
    );
}

#[test]
fn eval_and_sample_answer_one_line_per_query() {
    let diffuse = r#"<bsdf type="diffuse"><float name="reflectance" value="0.3"/></bsdf>"#;
    let (code, out, _) = gonio_bsdf(
        &["eval", diffuse],
        "0 0 1 0.6 0 0.8 500\n# skip\n0 0 1 0 0 -1 500\n",
    );
    assert_eq!(code, 0);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2);
    let v = numbers(lines[0]);
    assert!(
        (v[0] - 0.3 / std::f64::consts::PI).abs() < 1e-7 && (v[1] - 0.8 / std::f64::consts::PI).abs() < 1e-7
    );
    let (code, out, _) = gonio_bsdf(
        &["sample", GLASS],
        "0 0 1 550 0.01 0.3 0.7\n0 0 1 550 0.99 0.3 0.7\n",
    );
    assert_eq!(code, 0);
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].starts_with("0 0 1 1 0.04") && lines[0].ends_with("reflection|delta"),
        "{}",
        lines[0]
    );
    assert!(
        lines[1].starts_with("0 0 -1 ") && lines[1].contains("transmission|delta"),
        "{}",
        lines[1]
    );
}

#[test]
fn bad_input_names_the_line_and_exits_with_two() {
    let (code, out, err) = gonio_bsdf(
        &["eval", "<bsdf type=\"diffuse\"/>"],
        "0 0 1 0 0 1 550\n0 0 1 nan? 0 1 550\n",
    );
    assert_eq!(code, 2);
    assert_eq!(out.lines().count(), 1);
    assert!(err.contains("line 2") && err.contains("nan?"), "{err}");
    let (code, _, err) = gonio_bsdf(&["eval", "<bsdf type=\"difuse\"/>"], "");
    assert_eq!(code, 2);
    assert!(err.contains("difuse") && err.contains(":1:"), "{err}");
    let (code, _, err) = gonio_bsdf(
        &[
            "eval",
            "<bsdf type=\"dielectric\"><float name=\"int_ior\" value=\"-1\"/></bsdf>",
        ],
        "",
    );
    assert_eq!(code, 2, "negative IOR: {err}");
    let (code, _, err) = gonio_bsdf(&["eval", "no/such/file.xml"], "");
    assert_eq!(code, 2);
    assert!(err.contains("no/such/file.xml"), "{err}");
}

#[test]
fn closed_stdout_ends_quietly_without_a_panic() {
    // `gonio compare a.exr b.exr | head -0`: the reader is gone before gonio prints. Without the
    // default SIGPIPE action, `println!` panics on EPIPE ("failed printing to stdout").
    let reference = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/mitsuba/reference/furnace.exr"
    );
    let mut child = Command::new(env!("CARGO_BIN_EXE_gonio"))
        .args(["compare", reference, reference])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // close the read end while the images are still loading
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        assert_eq!(
            out.status.signal(),
            Some(13),
            "ended by SIGPIPE, as cat or grep would be"
        );
    }
}
