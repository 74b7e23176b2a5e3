//! `measured_polarized` against Mitsuba 3.9.1 (`testdata/measured_polarized/mitsuba-values.json`,
//! made by `testdata/measured_polarized/make_reference.py` from its synthetic `.pbsdf` table:
//! 9 φd × 7 θd × 7 θh nodes, 5 wavelengths, NaN and negative-M00 nodes, every element distinct).
//!
//! Bases and rows as in `mitsuba_polarized` (eval rows are f without the cosine, in Mitsuba's
//! implicit Stokes bases of −ω̂o and ω̂i). Tolerance: every element within 1e-4 of the largest
//! element of Mitsuba's matrix; pdfs within 1e-4 relative.
//!
//! Deliberate differences, checked here as such:
//! - at the exact mirror configuration (h = n) Mitsuba normalizes a zero vector, its φd is NaN
//!   and its matrix 0; gonio returns the table's limit there (the value 1e-5 away); where
//!   ω̂i ∥ ω̂o (retro-reflection) Mitsuba's frames are NaN, gonio's the implicit bases;
//! - Mitsuba's unpolarized variant lets a NaN node through as NaN; gonio gives 0, as Mitsuba's
//!   polarized variant does;
//! - gonio's GGX visible-normal sampler maps the unit square differently from Mitsuba's (see
//!   `mitsuba_polarized`), so the glossy sample rows compare the pdf and weight at Mitsuba's
//!   direction; the cosine-lobe rows compare the direction too.

use crate::mitsuba_json::{
    assert_implicit_bases, context as ctx_of, mueller_matrix as matrix, mueller_rel_diff, vec3,
};
use glam::{Vec2, Vec3};
use gonio_core::SampledWavelengths;
use gonio_core::bsdf::light_directions;
use gonio_render::material::Material;
use gonio_render::xml::load_bsdf_str;
use serde_json::Value;

const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../testdata/measured_polarized");

fn reference() -> Value {
    let text = include_str!("../../../testdata/measured_polarized/mitsuba-values.json");
    serde_json::from_str(text).expect("reference JSON parses")
}

fn load(xml: &str) -> Material {
    let xml = xml.replace(
        "value=\"synthetic.pbsdf\"",
        &format!("value=\"{DIR}/synthetic.pbsdf\""),
    );
    load_bsdf_str(&xml).unwrap_or_else(|e| panic!("{xml}: {e}"))
}

#[test]
fn measured_polarized_agrees_with_mitsuba() {
    let data = reference();
    let (mut evals, mut samples, mut unpolarized) = (0, 0, 0);
    for config in data["configs"].as_array().unwrap() {
        let name = config["name"].as_str().unwrap();
        let material = load(config["xml"].as_str().unwrap());
        let mut worst = 0.0f64;
        for q in config["rows"].as_array().unwrap() {
            let ctx = ctx_of(q);
            let wi = vec3(&q["wi"]);
            let wl = SampledWavelengths::fixed(q["lambda_nm"].as_f64().unwrap() as f32);
            let want = matrix(&q["M"]);
            let wo = vec3(&q["wo"]);
            let what = format!(
                "{name} {} {} wi {wi} wo {wo} λ {}",
                q["kind"], q["mode"], q["lambda_nm"]
            );
            let (m, pdf, f) = material.with_bsdf(Vec2::splat(0.5), |b| {
                (
                    b.eval_mueller(&ctx, wi, wo, &wl),
                    b.pdf(&ctx, wi, wo, &wl),
                    b.eval(&ctx, wi, wo, &wl),
                )
            });
            let (light_in, light_out) = light_directions(&ctx, wi, wo);
            assert_implicit_bases(&m, light_in, light_out, &what);
            assert_eq!(m.get(0, 0)[0], f[0], "{what}: M00 is not eval's value");
            let want_pdf = q["pdf"].as_f64().unwrap();
            assert!(
                (pdf as f64 - want_pdf).abs() <= 1e-4 * want_pdf.max(1e-3),
                "{what}: pdf {pdf} vs Mitsuba {want_pdf}"
            );
            if q["kind"] == "eval" && q["note"].as_str().unwrap().starts_with("exact-mirror") {
                // Mitsuba: 0 (its φd is NaN here). gonio: the limit.
                assert!(want.iter().flatten().all(|&x| x == 0.0));
                let near = (wo + Vec3::new(1e-5, -1e-5, 0.0)).normalize();
                let m_near = material.with_bsdf(Vec2::splat(0.5), |b| b.eval_mueller(&ctx, wi, near, &wl));
                let scale = m_near.get(0, 0)[0];
                assert!(
                    scale > 0.0,
                    "{what}: the table is positive near the mirror direction"
                );
                for k in 0..16 {
                    let (g, n) = (m.get(k / 4, k % 4)[0], m_near.get(k / 4, k % 4)[0]);
                    assert!(
                        (g - n).abs() <= 1e-3 * scale,
                        "{what}: element {k} {g} vs {n} 1e-5 away"
                    );
                }
                continue;
            }
            let got = if q["kind"] == "eval" {
                evals += 1;
                m
            } else {
                samples += 1;
                let u1 = q["sample1"].as_f64().unwrap() as f32;
                let u2 = Vec2::new(
                    q["sample2"][0].as_f64().unwrap() as f32,
                    q["sample2"][1].as_f64().unwrap() as f32,
                );
                let s = material
                    .with_bsdf(Vec2::splat(0.5), |b| {
                        b.sample_mueller(&ctx, wi, u1, u2, &mut wl.clone())
                    })
                    .unwrap_or_else(|| panic!("{what}: no sample"));
                if u1 < 0.1 {
                    // The cosine lobe: the same warp as Mitsuba's.
                    assert!(
                        (s.wo - wo).length() < 1e-5,
                        "{what}: sampled {} vs Mitsuba {wo}",
                        s.wo
                    );
                    assert!(
                        (s.pdf as f64 - want_pdf).abs() <= 1e-4 * want_pdf,
                        "{what}: pdf {}",
                        s.pdf
                    );
                    s.weight
                } else {
                    m * (wo.z / pdf)
                }
            };
            let d = mueller_rel_diff(&got, &want, false);
            assert!(
                d <= 1e-4,
                "{what}: relative difference {d:.2e}\n gonio {:?}\n Mitsuba {want:?}",
                got.matrix()
            );
            worst = worst.max(d);
        }
        for q in config["unpolarized_rows"].as_array().unwrap() {
            let ctx = ctx_of(q);
            let (wi, wo) = (vec3(&q["wi"]), vec3(&q["wo"]));
            let wl = SampledWavelengths::fixed(q["lambda_nm"].as_f64().unwrap() as f32);
            let f = material.with_bsdf(Vec2::splat(0.5), |b| b.eval(&ctx, wi, wo, &wl))[0] as f64;
            let what = format!("{name} unpolarized {} wi {wi} wo {wo}", q["mode"]);
            match q["value"].as_f64() {
                Some(want) => assert!(
                    (f - want).abs() <= 1e-4 * want.abs().max(1e-2),
                    "{what}: {f} vs Mitsuba {want}"
                ),
                // Mitsuba's NaN (a NaN node, or its exact-mirror NaN): gonio gives 0 at a NaN
                // node and the limit at the mirror.
                None => assert!(f.is_finite() && f >= 0.0, "{what}: {f}"),
            }
            unpolarized += 1;
        }
        eprintln!("measured_polarized {name}: largest relative element difference {worst:.2e}");
    }
    assert!(
        evals >= 100 && samples >= 40 && unpolarized >= 60,
        "{evals} eval, {samples} sample, {unpolarized} unpolarized rows"
    );
}

#[test]
fn a_broken_pbsdf_is_a_located_error() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(format!("{DIR}/synthetic.pbsdf")).unwrap();
    let cases: [(&str, Vec<u8>, &str); 3] = [
        ("truncated.pbsdf", bytes[..bytes.len() / 2].to_vec(), "do not fit"),
        ("text.pbsdf", b"hello".to_vec(), "not a tensor file"),
        // (The OS's message is not checked: it depends on the locale.)
        ("missing.pbsdf", Vec::new(), "missing.pbsdf"),
    ];
    for (file, content, needle) in cases {
        if !content.is_empty() {
            std::fs::write(dir.path().join(file), content).unwrap();
        }
        let path = dir.path().join(file);
        let xml = format!(
            "<bsdf version=\"3.0.0\" type=\"measured_polarized\">\n  <string name=\"filename\" value=\"{}\"/>\n</bsdf>",
            path.display()
        );
        let e = load_bsdf_str(&xml).unwrap_err().to_string();
        assert!(
            e.contains(":2:") && e.contains(file) && e.contains(needle),
            "{file}: {e}"
        );
    }
    for (param, value) in [
        ("alpha_sample", "0"),
        ("alpha_sample", "nan"),
        ("wavelength", "-2"),
    ] {
        let xml = format!(
            "<bsdf version=\"3.0.0\" type=\"measured_polarized\">\n  <string name=\"filename\" value=\"{DIR}/synthetic.pbsdf\"/>\n  <float name=\"{param}\" value=\"{value}\"/>\n</bsdf>"
        );
        let e = load_bsdf_str(&xml).unwrap_err().to_string();
        assert!(e.contains(":3:") && e.contains(param), "{param}={value}: {e}");
    }
}

#[test]
fn a_pbsdf_without_a_field_or_with_a_wrong_shape_names_it() {
    use gonio_render::tensor_file::{Dtype, write_tensor_file};
    let f32s = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let axis = f32s(&[0.0, 1.0]);
    let wvls: Vec<u8> = [500u16].iter().flat_map(|x| x.to_le_bytes()).collect();
    let m = f32s(&[0.1; 2 * 2 * 2 * 16]);
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, fields: &[(&str, Dtype, &[usize], &[u8])]| {
        let path = dir.path().join(name);
        std::fs::write(&path, write_tensor_file(fields)).unwrap();
        gonio_render::material::measured_polarized::read_pbsdf(&path)
    };
    let ok = write(
        "ok.pbsdf",
        &[
            ("phi_d", Dtype::F32, &[1, 2], &axis),
            ("theta_d", Dtype::F32, &[1, 2], &axis),
            ("theta_h", Dtype::F32, &[1, 2], &axis),
            ("wvls", Dtype::U16, &[1], &wvls),
            ("M", Dtype::F32, &[2, 2, 2, 1, 4, 4], &m),
        ],
    );
    assert!(ok.is_ok(), "{ok:?}");
    let e = write(
        "no-m.pbsdf",
        &[
            ("phi_d", Dtype::F32, &[1, 2], &axis),
            ("theta_d", Dtype::F32, &[1, 2], &axis),
            ("theta_h", Dtype::F32, &[1, 2], &axis),
            ("wvls", Dtype::U16, &[1], &wvls),
        ],
    )
    .unwrap_err();
    assert!(
        e.contains("no field \"M\"") && e.contains("phi_d, theta_d, theta_h, wvls"),
        "{e}"
    );
    let e = write(
        "shape.pbsdf",
        &[
            ("phi_d", Dtype::F32, &[1, 2], &axis),
            ("theta_d", Dtype::F32, &[1, 2], &axis),
            ("theta_h", Dtype::F32, &[1, 2], &axis),
            ("wvls", Dtype::U16, &[1], &wvls),
            ("M", Dtype::F32, &[2, 2, 2, 1, 16], &m),
        ],
    )
    .unwrap_err();
    assert!(
        e.contains("shape [2, 2, 2, 1, 16]") && e.contains("[2, 2, 2, 1, 4, 4]"),
        "{e}"
    );
    let descending = f32s(&[1.0, 0.0]);
    let e = write(
        "axis.pbsdf",
        &[
            ("phi_d", Dtype::F32, &[1, 2], &axis),
            ("theta_d", Dtype::F32, &[1, 2], &descending),
            ("theta_h", Dtype::F32, &[1, 2], &axis),
            ("wvls", Dtype::U16, &[1], &wvls),
            ("M", Dtype::F32, &[2, 2, 2, 1, 4, 4], &m),
        ],
    )
    .unwrap_err();
    assert!(e.contains("theta_d") && e.contains("index 1"), "{e}");
}
