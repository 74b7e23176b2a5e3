//! `sunsky`: the Hosek–Wilkie sky and sun against Mitsuba 3.9.1's `eval`
//! (`testdata/sunsky/mitsuba-values.json`, made by `make_reference.py` there) and the sun's
//! place from the date and time; the light's sampling (its density integrates to one, and
//! next-event samples average to the quadrature of its radiance); a render against Mitsuba's;
//! the edges (720 nm, degenerate directions, bad parameters). Emission sampling is checked with
//! the other lights' (`emitter::emission`).

use crate::mitsuba_json::{floats, parse, vec3};
use glam::{Vec2, Vec3};
use gonio_core::SampledWavelengths;
use gonio_core::rng::Pcg32;
use gonio_render::compare::block_relmse;
use gonio_render::emitter::{Light, LightRef, SunSkyLight};
use gonio_render::image::RgbImage;
use gonio_render::render::PreparedScene;
use gonio_render::xml::{LoadOptions, load_scene_file_with, load_scene_str};
use std::path::{Path, PathBuf};

const VALUES: &str = include_str!("../../../testdata/sunsky/mitsuba-values.json");

fn scene_with(body: &str) -> String {
    format!(
        "<scene version=\"3.0.0\">\n    <emitter type=\"sunsky\">\n        {body}\n    </emitter>\n</scene>\n"
    )
}

pub(crate) fn light_of(body: &str) -> Light {
    let scene = load_scene_str(&scene_with(body), Path::new("."), &[]).expect("scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let lights = prepared.lights().lights();
    assert_eq!(lights.len(), 1);
    lights[0].clone()
}

fn sunsky(l: &Light) -> &SunSkyLight {
    match l {
        Light::SunSky(s) => s,
        _ => panic!("not a sunsky light"),
    }
}

/// Every radiance Mitsuba evaluated, to 1e-4 relative (f32 rounding in the Bézier weights, the
/// exponentials and the spectral interpolation; 5e-4 for an RGB albedo), in the sun's disk plus the rounding of
/// Mitsuba's 1 − cos α (up to 0.55 %: gonio's is exact), skipping 1 % of the disk's 1 − cos α
/// about its rim (where Mitsuba's cosine test and gonio's chord test may disagree), and the sun
/// where Mitsuba puts it (given, to 2e-6; from the date and time, to 5e-5 rad).
#[test]
fn radiance_matches_mitsuba() {
    let v = parse(VALUES);
    let mut checked = 0;
    for cfg in v["configs"].as_array().unwrap() {
        let name = cfg["name"].as_str().unwrap();
        let light = light_of(cfg["xml"].as_str().unwrap());
        let s = sunsky(&light);
        let sun_world = vec3(&cfg["sun_direction"]);
        let complex = cfg["xml"].as_str().unwrap().contains("complex_sun");
        // An `<rgb>` albedo goes through each renderer's own RGB uplift (gonio's sigmoid table
        // is its own): 2.4e-4 measured.
        let base_tol = if cfg["xml"].as_str().unwrap().contains("<rgb") {
            5e-4
        } else {
            1e-4
        };
        for row in cfg["rows"].as_array().unwrap() {
            let d = vec3(&row["d"]);
            let lambda: [f32; 4] = floats(&row["lambda"]).try_into().unwrap();
            // null: Mitsuba's NaN at exactly 720 nm (make_reference.py).
            let want: Vec<Option<f32>> = row["value"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().map(|x| x as f32))
                .collect();
            // The disk's rim: Mitsuba's dot ≥ cos α and gonio's chord test may differ there.
            let cos = d.normalize().dot(sun_world.normalize());
            let half = (1.0 - cos).max(0.0);
            let disk = s.model().one_minus_cos_aperture();
            if (half - disk).abs() < 0.01 * disk + 1e-7 {
                continue;
            }
            let wl = SampledWavelengths::from_parts(lambda, [1.0; 4]);
            let got = light.le_infinite(d, &wl).to_array();
            // In the disk Mitsuba's `f32` 1 − cos α (and, for the complex sun, 1 − cos α₀ of its
            // area ratio) may be off by an ulp of the cosine, 2⁻²⁴, where gonio's is exact.
            let ulp = 2f32.powi(-24);
            let sun_tol = if half < disk {
                let alpha0 = gonio_core::sunsky::one_minus_cos(gonio_core::sunsky::SUN_HALF_APERTURE);
                ulp / disk + if complex { ulp / alpha0 } else { 0.0 }
            } else {
                0.0
            };
            for k in 0..4 {
                let Some(want) = want[k] else {
                    assert_eq!(lambda[k], 720.0, "{name}: Mitsuba's NaN away from 720 nm");
                    continue;
                };
                let tol = (base_tol + sun_tol) * want.abs() + 1e-9;
                assert!(
                    (got[k] - want).abs() <= tol,
                    "{name}: d {d} λ {} nm: gonio {} Mitsuba {want}",
                    lambda[k],
                    got[k],
                );
                checked += 1;
            }
        }
        // From the date and time: the same `f32` algorithm, but sines of arguments near 150 rad
        // (the ecliptic terms, ulp 1.5e-5) round differently in Rust's and Dr.Jit's libraries;
        // 2e-5 measured, 5e-5 rad allowed (the algorithm itself is good to about 1.7e-4).
        let tol = if cfg["xml"].as_str().unwrap().contains("sun_direction") {
            2e-6
        } else {
            5e-5
        };
        let got = s.sun_direction();
        assert!(
            (got - sun_world).length() < tol,
            "{name}: the sun at {got}, Mitsuba's at {sun_world}"
        );
    }
    assert!(checked > 2000, "{checked} values checked");
}

/// ∫ f(ω) dω over the sphere of world directions for a sunsky light: the midpoint rule in
/// (φ, cos θ) outside the sun's disk, and over the disk a polar midpoint rule in its cone
/// (a rotation `to_world` there: the disk's solid angle is the local one).
pub(crate) fn sphere_integral(s: &SunSkyLight, f: impl Fn(Vec3) -> [f32; 4]) -> [f64; 4] {
    let (n_cos, n_phi) = (1024, 2048);
    let mut acc = [0.0f64; 4];
    let cell = 2.0 * std::f64::consts::TAU / (n_phi * n_cos) as f64;
    for j in 0..n_cos {
        let z = -1.0 + 2.0 * (j as f32 + 0.5) / n_cos as f32;
        let r = (1.0 - z * z).max(0.0).sqrt();
        for i in 0..n_phi {
            let phi = std::f32::consts::TAU * (i as f32 + 0.5) / n_phi as f32;
            let d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
            if s.model().hits_sun(s.local_direction(d)) {
                continue;
            }
            let v = f(d);
            for k in 0..4 {
                acc[k] += v[k] as f64 * cell;
            }
        }
    }
    // The disk: (φ, 1 − cos θ) about the sun, equal solid angles.
    let omc = s.model().one_minus_cos_aperture();
    let sun = s.sun_direction();
    let frame = gonio_core::Frame::from_normal(sun);
    let (m_r, m_phi) = (64, 64);
    let disk_cell = std::f64::consts::TAU * omc as f64 / (m_r * m_phi) as f64;
    for a in 0..m_r {
        let one_minus = omc * (a as f32 + 0.5) / m_r as f32;
        let sin = (one_minus * (2.0 - one_minus)).sqrt();
        for b in 0..m_phi {
            let phi = std::f32::consts::TAU * (b as f32 + 0.5) / m_phi as f32;
            let d = frame
                .to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), 1.0 - one_minus))
                .normalize();
            if !s.model().hits_sun(s.local_direction(d)) {
                continue;
            }
            let v = f(d);
            for k in 0..4 {
                acc[k] += v[k] as f64 * disk_cell;
            }
        }
    }
    acc
}

/// Next-event samples from the sky's table and the sun's cone: L/p averages to ∫ L dω within
/// four standard errors (so the densities the light reports are those of its draws, wherever
/// it shines); `pdf_li_infinite`, which MIS asks for BSDF-sampled directions, integrates to one
/// over the sphere; a sun alone costs no variance; a sun below the horizon draws nothing.
/// The cases: a sky alone, sky and sun, a sun alone, the limb-darkened sun, a wide disk cut by
/// the horizon, and a sky under a scaled and sheared `to_world` (the Jacobian of its densities).
#[test]
fn next_event_samples_integrate_the_sky_and_sun() {
    let r = LightRef {
        p: Vec3::ZERO,
        n: Vec3::Y,
        hemisphere: false,
        mis: true,
        resolved_density: 0.0,
        resampled: false,
    };
    let y_up = "<transform name=\"to_world\"><rotate x=\"1\" angle=\"-90\"/></transform>";
    let sheared = "<transform name=\"to_world\"><matrix value=\"1.5 0.4 0 0  0 0.8 0.3 0  0.2 0 1.1 0  0 0 0 1\"/></transform>";
    let cases = [
        ("sky", format!("<float name=\"hour\" value=\"8.5\"/><float name=\"sun_scale\" value=\"0\"/>{y_up}")),
        ("sky_and_sun", format!("<float name=\"hour\" value=\"13\"/><float name=\"turbidity\" value=\"7\"/>{y_up}")),
        ("sun", "<vector name=\"sun_direction\" x=\"0.3\" y=\"-0.2\" z=\"0.7\"/><float name=\"sky_scale\" value=\"0\"/>".into()),
        (
            "complex_sun",
            "<vector name=\"sun_direction\" x=\"-0.3\" y=\"0.5\" z=\"0.6\"/><boolean name=\"complex_sun\" value=\"true\"/><float name=\"sun_aperture\" value=\"3\"/>".into(),
        ),
        (
            "disk_cut_by_the_horizon",
            "<vector name=\"sun_direction\" x=\"0.9\" y=\"0.1\" z=\"0.05\"/><float name=\"sun_aperture\" value=\"12\"/>".into(),
        ),
        ("sheared_sky", format!("<float name=\"hour\" value=\"16\"/><float name=\"sun_scale\" value=\"0\"/>{sheared}")),
    ];
    let wl = SampledWavelengths::from_parts([420.0, 505.0, 590.0, 675.0], [1.0; 4]);
    for (name, body) in cases {
        let light = light_of(&body);
        let s = sunsky(&light);
        let want = sphere_integral(s, |d| light.le_infinite(d, &wl).to_array());
        let pdf_total = sphere_integral(s, |d| [light.pdf_li_infinite(&r, d); 4])[0];
        assert!(
            (pdf_total - 1.0).abs() < 2e-3,
            "{name}: the density integrates to {pdf_total}"
        );

        let n = 200_000;
        let mut rng = Pcg32::new(20261207, 1);
        let (mut sum, mut sum2) = ([0.0f64; 4], [0.0f64; 4]);
        for _ in 0..n {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let Some(ls) = light.sample_li_nonarea(&r, u, &wl) else {
                continue;
            };
            assert!(
                ls.pdf.is_finite() && ls.li.is_finite(),
                "{name}: {} {:?}",
                ls.pdf,
                ls.li
            );
            let v = ls.li.to_array();
            for k in 0..4 {
                let x = (v[k] / ls.pdf) as f64;
                sum[k] += x;
                sum2[k] += x * x;
            }
        }
        for k in 0..4 {
            let mean = sum[k] / n as f64;
            let se = ((sum2[k] / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
            // The quadrature's own error: 3e-4 (the disk's rim, the circumsolar sky).
            let tol = 4.0 * se + 3e-4 * want[k].abs();
            assert!(
                (mean - want[k]).abs() <= tol,
                "{name} λ {} nm: mean of L/p {mean} (± {se}) but ∫L dω {}",
                wl.lambda(k),
                want[k]
            );
            if name == "sun" {
                assert!(
                    se <= 1e-4 * mean,
                    "{name}: a sun alone should cost no variance (± {se})"
                );
            }
        }
    }
    // The sun set: black everywhere, no samples.
    let light = light_of("<float name=\"hour\" value=\"23\"/>");
    let mut rng = Pcg32::new(3, 3);
    for _ in 0..1000 {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        assert!(light.sample_li_nonarea(&r, u, &wl).is_none());
    }
    assert!(light.le_infinite(Vec3::Z, &wl).is_black());
}

/// At exactly 720 nm (the model's last wavelength, where Mitsuba reads past its table and
/// returns NaN) the radiance is the table's last value, continuous from below; a zero or NaN
/// direction lights nothing.
#[test]
fn the_last_wavelength_and_degenerate_directions() {
    let light = light_of("<vector name=\"sun_direction\" x=\"0.2\" y=\"0.1\" z=\"0.8\"/>");
    let d = Vec3::new(-0.4, 0.3, 0.5).normalize();
    let at = |l: f32| {
        light
            .le_infinite(d, &SampledWavelengths::from_parts([l; 4], [1.0; 4]))
            .to_array()[0]
    };
    let (edge, below) = (at(720.0), at(719.99));
    assert!(
        edge > 0.0 && (edge - below).abs() < 1e-3 * edge,
        "{edge} at 720 nm, {below} just below"
    );
    assert_eq!(at(720.5), 0.0);
    let wl = SampledWavelengths::from_parts([500.0; 4], [1.0; 4]);
    assert!(light.le_infinite(Vec3::ZERO, &wl).is_black());
    assert!(light.le_infinite(Vec3::new(f32::NAN, 0.0, 1.0), &wl).is_black());
}

fn render_scene(spp: u32, seed: u64, mitsuba_estimators: bool) -> RgbImage {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/sunsky");
    let options = LoadOptions {
        defines: vec![],
        mitsuba_estimators,
    };
    let scene = load_scene_file_with(dir.join("scene.xml"), &options)
        .expect("scene loads")
        .scene;
    crate::integrator::render_scene(scene, spp, seed).image
}

/// `testdata/sunsky/scene.xml` (a y-up world, the sun at 10:30 in Tokyo, a floor, a white and a
/// rough copper sphere) against Mitsuba 3.9.1's `llvm_ad_spectral` at 4096 spp: gonio at 64 spp
/// with its own estimators and with Mitsuba's, block relMSE (8 × 8) under twice what two gonio
/// renders show against each other, and the image means within 0.5 % (the sun's radiance
/// differs by Mitsuba's 0.22 % rounding of 1 − cos α).
#[test]
fn scene_matches_mitsuba() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/sunsky");
    let reference = RgbImage::read(dir.join("mitsuba-scene-4096spp.exr")).expect("reference reads");
    for mitsuba_estimators in [false, true] {
        let a = render_scene(64, 1, mitsuba_estimators);
        let b = render_scene(64, 2, mitsuba_estimators);
        let noise = block_relmse(&a, &b, 8).unwrap();
        let err = block_relmse(&a, &reference, 8).unwrap();
        assert!(
            err < 2.0 * noise,
            "mitsuba_estimators {mitsuba_estimators}: block relMSE {err:e} against Mitsuba, {noise:e} between two seeds"
        );
        for c in 0..3 {
            let mean =
                |img: &RgbImage| img.data.iter().map(|p| p[c] as f64).sum::<f64>() / img.data.len() as f64;
            let (m, r) = (mean(&a), mean(&reference));
            assert!(
                (m - r).abs() < 5e-3 * r,
                "channel {c}: mean {m} against Mitsuba's {r}"
            );
        }
    }
}

/// Bad parameters name the line and the value: a turbidity beyond the tables, an albedo above
/// one, a negative scale, an aperture of 180° or too small for a float's 1 − cos, a zero or NaN
/// sun direction, a sun direction given with a time, a month 13, a latitude beyond the pole;
/// a date out of any range and an overflowing `to_world` at the emitter's line.
#[test]
fn bad_parameters_are_refused_with_their_line() {
    let cases = [
        ("<float name=\"turbidity\" value=\"11\"/>", "11", 3),
        ("<float name=\"albedo\" value=\"1.5\"/>", "1.5", 3),
        ("<rgb name=\"albedo\" value=\"0.2, 0.4, 1.7\"/>", "albedo", 3),
        ("<float name=\"sun_scale\" value=\"-1\"/>", "-1", 3),
        ("<float name=\"sky_scale\" value=\"nan\"/>", "NaN", 3),
        ("<float name=\"sun_aperture\" value=\"180\"/>", "180", 3),
        ("<float name=\"sun_aperture\" value=\"1e-9\"/>", "sun_aperture", 3),
        (
            "<vector name=\"sun_direction\" x=\"0\" y=\"0\" z=\"0\"/>",
            "sun_direction",
            3,
        ),
        (
            "<vector name=\"sun_direction\" x=\"nan\" y=\"0\" z=\"1\"/>",
            "sun_direction",
            3,
        ),
        (
            "<vector name=\"sun_direction\" x=\"0\" y=\"0\" z=\"1\"/><float name=\"hour\" value=\"12\"/>",
            "hour",
            3,
        ),
        ("<integer name=\"month\" value=\"13\"/>", "13", 3),
        ("<float name=\"latitude\" value=\"91\"/>", "91", 3),
        ("<float name=\"hour\" value=\"1e38\"/>", "out of range", 2),
        (
            "<transform name=\"to_world\"><scale value=\"1e20\"/></transform>",
            "to_world",
            2,
        ),
    ];
    for (body, quote, line) in cases {
        let text = scene_with(body);
        let e = match load_scene_str(&text, Path::new("."), &[]) {
            Ok(_) => panic!("{body}: loaded"),
            Err(e) => e,
        };
        let msg = e.to_string();
        assert_eq!(e.location.line, line, "{body}: {msg}");
        assert!(msg.contains(quote), "{body}: {msg:?} should mention {quote:?}");
    }
}

/// Light selection's estimate at a shading point, the sun at the zenith: a surface facing up
/// gets π × the sky's hemisphere mean plus the sun's irradiance (4π × the difference of the
/// lights' mean radiances over the sphere), one facing down nothing, an upright one half the
/// sky and the sun × the sine of the disk's radius (the cosine widened by it), and a surface
/// that transmits the whole of both.
#[test]
fn selection_estimate_follows_the_sun_and_the_sky() {
    let light = light_of("<vector name=\"sun_direction\" x=\"0\" y=\"0\" z=\"1\"/>");
    let sky = light_of(
        "<vector name=\"sun_direction\" x=\"0\" y=\"0\" z=\"1\"/><float name=\"sun_scale\" value=\"0\"/>",
    );
    let at = |n: Vec3, hemisphere: bool| {
        let r = LightRef {
            p: Vec3::ZERO,
            n,
            hemisphere,
            mis: true,
            resolved_density: 0.0,
            resampled: false,
        };
        light.local_importance(&r, light.mean_emission())
    };
    let pi = std::f32::consts::PI;
    // Means over the sphere: the sky's is half its hemisphere's.
    let sky_part = pi * 2.0 * sky.mean_emission();
    let sun = 4.0 * pi * (light.mean_emission() - sky.mean_emission());
    let sin_alpha = sunsky(&light).sin_alpha();
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * b.abs().max(1e-6);
    let (up, down, upright, through) = (
        at(Vec3::Z, true),
        at(-Vec3::Z, true),
        at(Vec3::X, true),
        at(-Vec3::Z, false),
    );
    assert!(close(up, sky_part + sun), "facing up: {up} vs {}", sky_part + sun);
    assert_eq!(down, 0.0, "facing down");
    assert!(
        close(upright, 0.5 * sky_part + sun * sin_alpha),
        "upright: {upright}"
    );
    assert!(close(through, sky_part + sun), "transmitting: {through}");
    // Turbidity 3 at noon: the sun's irradiance 3.0 × the sky's (0.82 and 0.28 W m⁻² nm⁻¹).
    assert!(
        sun > 2.0 * sky_part,
        "the noon sun outshines the sky: {sun} vs {sky_part}"
    );
}
