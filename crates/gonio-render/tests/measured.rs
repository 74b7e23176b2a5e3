//! `measured` (RGL's measured BRDFs) against Mitsuba 3.9.1 `scalar_spectral`
//! (`testdata/measured/mitsuba-values.json`, made by `testdata/measured/make_reference.py` from
//! its synthetic files `iso.bsdf` and `aniso.bsdf`: GGX-like tables of uneven grid sizes,
//! 6 incidences, 8 wavelengths over 360–1000 nm, the anisotropic one over φi ∈ [−π, −π/2] with
//! Mitsuba's four-fold mirroring).
//!
//! Mitsuba's `eval` is f cos θo (the RGL tables hold that); gonio's is f, so the rows compare
//! eval · cos θo. Tolerances: eval values and pdfs within 2e-5 relative; sample rows (f32 warps
//! through two CDF inversions each way, where the script's float64 model of Mitsuba's formulas
//! differs from Mitsuba itself by up to 3.9e-5) within 1e-4, directions within 1e-4, except at
//! the corners of the unit square, where Mitsuba's own f32 round-off moves ωo by 1e-3.
//!
//! Where gonio's contract differs from Mitsuba's, and is checked as such: a sample below the
//! horizon or with a pdf ≤ 0 (an interpolated visible-normal density can put a little mass on
//! back-facing normals) is returned by Mitsuba with weight 0 or a negative pdf, by gonio as
//! `None`.

use crate::mitsuba_json::{context, vec3};
use glam::{Vec2, Vec3};
use gonio_core::{BsdfContext, SampledWavelengths};
use gonio_render::material::Material;
use gonio_render::xml::load_bsdf_str;
use serde_json::Value;

const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../testdata/measured");

fn load(xml: &str) -> Material {
    let xml = xml.replace("value=\"", &format!("value=\"{DIR}/"));
    load_bsdf_str(&xml).unwrap_or_else(|e| panic!("{xml}: {e}"))
}

fn close(got: f32, want: f64, tol: f64) -> bool {
    (got as f64 - want).abs() <= tol * want.abs().max(1e-3)
}

#[test]
fn measured_agrees_with_mitsuba() {
    let data: Value =
        serde_json::from_str(include_str!("../../../testdata/measured/mitsuba-values.json")).unwrap();
    let (mut evals, mut samples, mut refused) = (0, 0, 0);
    for config in data["configs"].as_array().unwrap() {
        let name = config["name"].as_str().unwrap();
        let material = load(config["xml"].as_str().unwrap());
        for q in config["rows"].as_array().unwrap() {
            let ctx = context(q);
            let wi = vec3(&q["wi"]);
            let wl = SampledWavelengths::fixed(q["lambda_nm"].as_f64().unwrap() as f32);
            let (want, want_pdf) = (q["value"].as_f64().unwrap(), q["pdf"].as_f64().unwrap());
            let what = format!(
                "{name} {} {} wi {wi} λ {} ({})",
                q["kind"], q["mode"], q["lambda_nm"], q["note"]
            );
            if q["kind"] == "eval" {
                let wo = vec3(&q["wo"]);
                let (f, pdf) = material.with_bsdf(Vec2::ZERO, |b| {
                    (b.eval(&ctx, wi, wo, &wl), b.pdf(&ctx, wi, wo, &wl))
                });
                let f_cos = f[0] * wo.z.max(0.0);
                assert!(
                    close(f_cos, want, 2e-5),
                    "{what} wo {wo}: f cos {f_cos} vs Mitsuba {want}"
                );
                assert!(
                    close(pdf, want_pdf.max(0.0), 2e-5),
                    "{what} wo {wo}: pdf {pdf} vs Mitsuba {want_pdf}"
                );
                evals += 1;
                continue;
            }
            let u1 = q["sample1"].as_f64().unwrap() as f32;
            let u2 = vec3(&serde_json::json!([q["sample2"][0], q["sample2"][1], 0.0])).truncate();
            let s = material.with_bsdf(Vec2::ZERO, |b| b.sample(&ctx, wi, u1, u2, &mut wl.clone()));
            let wo = vec3(&q["wo"]);
            if want_pdf <= 0.0 || wo.z <= 0.0 || wi.z <= 0.0 {
                assert!(
                    s.is_none(),
                    "{what}: Mitsuba pdf {want_pdf}, wo {wo}: gonio sampled {s:?}"
                );
                refused += 1;
                continue;
            }
            let s = s.unwrap_or_else(|| panic!("{what}: no sample (Mitsuba wo {wo} pdf {want_pdf})"));
            let corner = u2.x.min(u2.y) < 1e-3 || u2.x.max(u2.y) > 0.999;
            let (tol_dir, tol) = if corner { (5e-3, 5e-3) } else { (1e-4, 1e-4) };
            assert!(
                (s.wo - wo).length() < tol_dir,
                "{what}: wo {} vs Mitsuba {wo}",
                s.wo
            );
            assert!(
                close(s.pdf, want_pdf, tol),
                "{what}: pdf {} vs Mitsuba {want_pdf}",
                s.pdf
            );
            assert!(
                close(s.weight[0], want, tol),
                "{what}: weight {} vs Mitsuba {want}",
                s.weight[0]
            );
            samples += 1;
        }
    }
    assert!(
        evals >= 60 && samples >= 30 && refused >= 2,
        "{evals} eval, {samples} sample, {refused} refused rows"
    );
}

/// The battery on both synthetic tables: every row but `reciprocity` and `adjoint`, which these
/// tables break (each incidence's spectra were filled on their own, as a measurement is;
/// Mitsuba's `measured` evaluates the same table in both transport modes, and so does gonio), so
/// sampling, pdf, weights, energy and (an)isotropy are checked, and the asymmetry is seen; and
/// the χ² row at normal incidence, replaced by the next test. The battery's quick sizes (10×
/// fewer samples: a full run of both tables takes 80 s, the model's sampling two warps and their
/// inverses).
#[test]
fn measured_tables_pass_the_battery_but_reciprocity() {
    use gonio_core::check::{CheckConfig, all_passed, battery, failures};
    for (file, anisotropic) in [("iso.bsdf", false), ("aniso.bsdf", true)] {
        let m = gonio_render::material::measured::read_rgl(std::path::Path::new(&format!("{DIR}/{file}")))
            .unwrap();
        assert_eq!(
            gonio_core::Bsdf::flags(&m).contains(gonio_core::BsdfFlags::ANISOTROPIC),
            anisotropic
        );
        let rows = battery(&m, &CheckConfig::quick());
        // The χ² row at normal incidence: see the next test.
        let normal = |r: &gonio_core::check::CheckResult| {
            r.name == "chi2" && r.detail.starts_with("wi=(0.000,0.000,1.000)")
        };
        let rows: Vec<_> = rows.into_iter().filter(|r| !normal(r)).collect();
        let (asym, rest): (Vec<_>, Vec<_>) = rows
            .into_iter()
            .partition(|r| r.name == "reciprocity" || r.name == "adjoint");
        assert!(all_passed(&rest), "{file}:\n{}", failures(&rest));
        assert!(
            rest.iter().filter(|r| r.name == "chi2").count() >= 2,
            "{file}: chi2 rows"
        );
        assert!(
            asym.iter().all(|r| !r.passed),
            "{file}: the synthetic table's asymmetry is not seen"
        );
    }
}

/// At normal incidence an RGL table's density has an integrable 1/θ spike at the mirror direction
/// (the visible-normal table vanishes on its first column, u_θ = 0, and is linear in u_θ next to
/// it, while the Jacobian of u ↦ ωo goes as u_θ sin θh; Mitsuba's too), at the pole of the
/// battery's (cos θ, φ) grid, where its Simpson quadrature misjudges the pole cells (expected
/// 0.9185 of the samples above the horizon against 0.9097 drawn, 2 × 10⁶ samples). So that χ²
/// row is replaced by this one: the fraction of 10⁶ stratified samples within 9° of the normal
/// against the pdf integrated in θ (where the spike is θ · 1/θ, smooth), within 4 standard
/// errors.
#[test]
fn the_mirror_spike_at_normal_incidence_holds_the_sampled_mass() {
    use gonio_core::Bsdf;
    let m =
        gonio_render::material::measured::read_rgl(std::path::Path::new(&format!("{DIR}/iso.bsdf"))).unwrap();
    let ctx = BsdfContext::radiance();
    let mut wl = SampledWavelengths::fixed(550.0);
    let theta_max = std::f64::consts::FRAC_PI_2 / 10.0;
    let n = 1000;
    let mut inside = 0usize;
    for i in 0..n {
        for j in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            if let Some(s) = m.sample(&ctx, Vec3::Z, 0.5, u, &mut wl) {
                inside += ((s.wo.z as f64).acos() < theta_max) as usize;
            }
        }
    }
    let drawn = inside as f64 / (n * n) as f64;
    let (nt, np) = (20_000, 64);
    let (dt, dp) = (theta_max / nt as f64, std::f64::consts::TAU / np as f64);
    let mut mass = 0.0f64;
    for i in 0..nt {
        let t = (i as f64 + 0.5) * dt;
        for j in 0..np {
            let phi = (j as f64 + 0.5) * dp;
            let wo = Vec3::new(
                (t.sin() * phi.cos()) as f32,
                (t.sin() * phi.sin()) as f32,
                t.cos() as f32,
            );
            mass += m.pdf(&ctx, Vec3::Z, wo, &wl) as f64 * t.sin() * dt * dp;
        }
    }
    let se = (mass * (1.0 - mass) / (n * n) as f64).sqrt();
    assert!(
        (drawn - mass).abs() < 4.0 * se,
        "drawn {drawn:.5} vs ∫pdf {mass:.5} (σ {se:.1e})"
    );
    assert!(mass > 0.05, "the spike holds {mass}");
}

/// A field's new name and shape.
type Renamed = Option<(String, Vec<usize>)>;

#[test]
fn broken_rgl_files_are_located_errors() {
    use gonio_render::tensor_file::{Dtype, TensorFile, write_tensor_file};
    let iso = std::fs::read(format!("{DIR}/iso.bsdf")).unwrap();
    let t = TensorFile::parse(&iso).unwrap();
    let dir = tempfile::tempdir().unwrap();
    // The iso file's fields, with `change` applied to one of them (None: dropped).
    let rewrite = |file: &str, change: &dyn Fn(&str) -> Renamed| {
        let mut fields: Vec<(String, Dtype, Vec<usize>, Vec<u8>)> = Vec::new();
        for name in t.names() {
            let f = t.field(name).unwrap();
            match change(name) {
                Some((n, shape)) => fields.push((n, f.dtype, shape, f.as_bytes().to_vec())),
                None if ["wavelengths", "spectra"].contains(&name) => {}
                None => fields.push((name.to_string(), f.dtype, f.shape.clone(), f.as_bytes().to_vec())),
            }
        }
        let refs: Vec<(&str, Dtype, &[usize], &[u8])> = fields
            .iter()
            .map(|(n, d, s, b)| (n.as_str(), *d, s.as_slice(), b.as_slice()))
            .collect();
        let path = dir.path().join(file);
        std::fs::write(&path, write_tensor_file(&refs)).unwrap();
        let xml = format!(
            "<bsdf version=\"3.0.0\" type=\"measured\">\n  <string name=\"filename\" value=\"{}\"/>\n</bsdf>",
            path.display()
        );
        match load_bsdf_str(&xml) {
            Ok(_) => panic!("{file} loaded"),
            Err(e) => e.to_string(),
        }
    };
    let shape = |name: &str| t.field(name).unwrap().shape.clone();
    // An RGB file: `rgb` instead of `spectra` and `wavelengths`.
    let e = rewrite("rgb.bsdf", &|n| {
        (n == "spectra").then(|| ("rgb".to_string(), shape("spectra")))
    });
    assert!(e.contains(":2:") && e.contains("an RGB file"), "{e}");
    // Spectra over a grid other than the luminance's.
    let e = rewrite("grid.bsdf", &|n| match n {
        "spectra" => {
            let s = shape("spectra");
            Some(("spectra".into(), vec![s[0], s[1], s[2], s[3] / 2, s[4] * 2]))
        }
        "wavelengths" => Some(("wavelengths".into(), shape("wavelengths"))),
        _ => None,
    });
    assert!(e.contains(":2:") && e.contains("must agree"), "{e}");
    let e = rewrite("vndf.bsdf", &|n| match n {
        "vndf" => {
            let s = shape("vndf");
            Some(("vndf".into(), vec![s[0] * s[1], s[2], s[3]]))
        }
        "spectra" | "wavelengths" => Some((n.into(), shape(n))),
        _ => None,
    });
    assert!(
        e.contains("field \"vndf\" has shape") && e.contains("expected [1, 6, h, w]"),
        "{e}"
    );
}

/// Hostile files: 800 random corruptions of each synthetic table (bytes flipped in the header
/// or the data, truncations) either load, and then evaluate and sample (intensity and Mueller
/// matrix, both transport modes, four wavelengths) without a panic and without a NaN or
/// negative value, or are refused with an error. Seeded: deterministic.
#[test]
fn corrupted_tables_never_panic_nor_give_nan() {
    use gonio_core::Bsdf;
    use gonio_core::rng::Pcg32;
    let pbsdf = format!("{DIR}/../measured_polarized/synthetic.pbsdf");
    let dir = tempfile::tempdir().unwrap();
    let ctx = BsdfContext::radiance();
    let (mut loaded, mut refused) = (0, 0);
    for (k, file) in [format!("{DIR}/iso.bsdf"), format!("{DIR}/aniso.bsdf"), pbsdf]
        .iter()
        .enumerate()
    {
        let original = std::fs::read(file).unwrap();
        let mut rng = Pcg32::new(20261207, k as u64);
        for case in 0..800 {
            let mut bytes = original.clone();
            match case % 4 {
                // The header (names, types, offsets, shapes).
                0 => {
                    let i = (rng.next_f32() * 400.0) as usize % bytes.len();
                    bytes[i] ^= 1 << (rng.next_f32() * 8.0) as u32;
                }
                // A data byte anywhere.
                1 | 2 => {
                    let i = (rng.next_f32() * bytes.len() as f32) as usize % bytes.len();
                    bytes[i] = (rng.next_f32() * 256.0) as u8;
                }
                _ => bytes.truncate((rng.next_f32() * bytes.len() as f32) as usize),
            }
            let path = dir.path().join("t");
            std::fs::write(&path, &bytes).unwrap();
            let model: Box<dyn Bsdf> = if k < 2 {
                match gonio_render::material::measured::read_rgl(&path) {
                    Ok(m) => Box::new(m),
                    Err(_) => {
                        refused += 1;
                        continue;
                    }
                }
            } else {
                match gonio_render::material::measured_polarized::read_pbsdf(&path) {
                    Ok(t) => Box::new(gonio_core::bsdfs::MeasuredPolarized::new(t, 0.1, None)),
                    Err(_) => {
                        refused += 1;
                        continue;
                    }
                }
            };
            loaded += 1;
            let mut wl = SampledWavelengths::sample_visible(0.37);
            for q in 0..8 {
                let ctx = if q % 2 == 0 {
                    ctx
                } else {
                    BsdfContext::importance()
                };
                let a = 0.3 + 0.8 * q as f32;
                let wi = Vec3::new(a.cos() * 0.6, a.sin() * 0.6, 0.8);
                let wo = Vec3::new(-a.sin() * 0.3, a.cos() * 0.3, 0.954);
                let (f, pdf) = model.eval_pdf(&ctx, wi, wo, &wl);
                let ok = |x: f32| x.is_finite() && x >= 0.0;
                assert!(
                    (0..4).all(|i| ok(f[i])) && ok(pdf),
                    "case {case} of {file}: f {f:?} pdf {pdf}"
                );
                let m = model.eval_mueller(&ctx, wi, wo, &wl);
                assert!(
                    (0..16).all(|e| m.get(e / 4, e % 4).is_finite()),
                    "case {case} of {file}: {m:?}"
                );
                let u = Vec2::new(0.1 * q as f32 + 0.05, 0.37);
                if let Some(s) = model.sample(&ctx, wi, 0.5, u, &mut wl) {
                    assert!(
                        (0..4).all(|i| ok(s.weight[i])) && ok(s.pdf),
                        "case {case} of {file}: {s:?}"
                    );
                }
                if let Some(s) = model.sample_mueller(&ctx, wi, 0.5, u, &mut wl) {
                    assert!(
                        (0..16).all(|e| s.weight.get(e / 4, e % 4).is_finite()),
                        "case {case} of {file}: {s:?}"
                    );
                }
            }
        }
    }
    eprintln!("{loaded} loaded, {refused} refused");
    assert!(
        loaded > 600 && refused > 300,
        "{loaded} loaded, {refused} refused"
    );
}
