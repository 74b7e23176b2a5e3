//! The gonioreflectometer round trip (issue 4): measure an analytic BSDF with `gonio measure`,
//! render the measured table (`<bsdf type="tabulated">`) and the analytic BSDF with
//! `gonio render`, and `gonio compare` says they agree within noise. The noise level is measured,
//! not assumed: two renders of the analytic BSDF with different seeds. A table measured from a
//! different reflectance must fail the same threshold (the test can fail).

use std::path::{Path, PathBuf};
use std::process::Command;

fn gonio(args: &[&str], dir: &Path) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_gonio"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("gonio runs");
    let text = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    (out.status.code().unwrap_or(-1), text)
}

fn block_relmse(report: &str) -> f64 {
    let line = report
        .lines()
        .find(|l| l.starts_with("relMSE 8x8"))
        .expect("block relMSE line");
    line.split_whitespace().nth(2).unwrap().parse().unwrap()
}

const SCENE: &str = r#"<scene version="3.0.0">
    <default name="bsdf" value="analytic.xml"/>
    <integrator type="path"><integer name="max_depth" value="4"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/><rfilter type="box"/></film>
    </sensor>
    <include filename="$bsdf"/>
    <shape type="sphere"><float name="radius" value="1"/><ref id="mat"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.8"/><rotate x="1" angle="120"/><translate x="1" y="3" z="2"/></transform>
        <emitter type="area"><rgb name="radiance" value="5"/></emitter>
    </shape>
    <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
</scene>"#;

fn workdir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gonio-tabulated-roundtrip-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn measured_lambertian_table_renders_like_the_analytic_bsdf() {
    let dir = workdir();
    let write = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
    write("scene.xml", SCENE);
    write(
        "analytic.xml",
        r#"<scene version="3.0.0"><bsdf type="diffuse" id="mat"><float name="reflectance" value="0.6"/></bsdf></scene>"#,
    );
    for (table, file) in [("lambert.table", "table.xml"), ("wrong.table", "wrong.xml")] {
        write(
            file,
            &format!(
                r#"<scene version="3.0.0"><bsdf type="tabulated" id="mat"><string name="filename" value="{table}"/></bsdf></scene>"#
            ),
        );
    }
    // The table's own measurement error must lie well below the render noise for "within noise"
    // to hold. Block relMSE of table against analytic renders, three seed pairs each, against
    // 0.62e-6 between analytic renders: 1.14e-6 from 2·10⁵ photons (the table's error as large
    // as the noise: the test passed or failed with the seeds), 0.89e-6 from 8·10⁵, 0.71e-6 from
    // 3.2·10⁶. The wrong table fails by orders of magnitude from any count.
    for (rho, table, photons) in [
        ("0.6", "lambert.table", "3200000"),
        ("0.5", "wrong.table", "200000"),
    ] {
        let bsdf = format!(r#"<bsdf type="diffuse"><float name="reflectance" value="{rho}"/></bsdf>"#);
        let (code, out) = gonio(&["measure", &bsdf, "-o", table, "--photons", photons], &dir);
        assert_eq!(code, 0, "{out}");
    }
    for (name, seed, bsdf) in [
        ("a1.exr", "1", "analytic.xml"),
        ("a2.exr", "2", "analytic.xml"),
        ("t.exr", "3", "table.xml"),
        ("w.exr", "4", "wrong.xml"),
    ] {
        let (code, out) = gonio(
            &[
                "render",
                "scene.xml",
                "-o",
                name,
                "--seed",
                seed,
                "-D",
                &format!("bsdf={bsdf}"),
            ],
            &dir,
        );
        assert_eq!(code, 0, "{out}");
    }
    // The noise level: two analytic renders. With 48 blocks the relMSE of block means fluctuates
    // by ≈ sqrt(2/48) ≈ 20 % around its expectation, so twice the measured level is ≈ 5σ.
    let (_, noise) = gonio(&["compare", "a1.exr", "a2.exr"], &dir);
    let threshold = 2.0 * block_relmse(&noise);
    let limit = format!("{threshold:e}");
    let (code, out) = gonio(
        &["compare", "t.exr", "a2.exr", "--max-block-relmse", &limit],
        &dir,
    );
    assert_eq!(code, 0, "measured table vs analytic, threshold {limit}:\n{out}");
    let (code, out) = gonio(
        &["compare", "w.exr", "a2.exr", "--max-block-relmse", &limit],
        &dir,
    );
    assert_eq!(code, 1, "a table of ρ = 0.5 must not pass for ρ = 0.6:\n{out}");
    let _ = std::fs::remove_dir_all(&dir);
}
