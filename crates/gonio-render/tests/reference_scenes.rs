//! The shared Mitsuba scenes agree with their Mitsuba 3.9.1 references (`scalar_spectral`,
//! 4096 spp, box filter) within Monte Carlo noise.
//!
//! # Measure
//!
//! relMSE of 8 × 8-block means: the image is cut into 8 × 8-pixel blocks, each block's mean colour
//! is compared per channel, relMSE = mean over blocks and channels of (a − b)²/(b² + 10⁻²).
//! Block means average out pixel noise, so a systematic difference (a wrong BSDF, a missing light
//! path, a mirrored camera) stands out against the noise.
//!
//! # CI size
//!
//! Each scene is rendered at half resolution: with a box filter a half-resolution pixel integrates
//! exactly the 2 × 2 full-resolution pixels it covers, so the reference is downsampled 2 × 2 and
//! compared with 4 × 4 blocks (= 8 × 8 blocks of the original image). The sample count is
//! [`CI_SPP`] per half-resolution pixel (4 × that per original block area).
//!
//! # Thresholds
//!
//! The threshold of each scene is the level two independent gonio renders at the same size and
//! spp show against each other (seeds 1 and 2), measured with `cargo test --release --test
//! reference_scenes -- --ignored --nocapture measure` (the Mitsuba-vs-Mitsuba level, measured with
//! Mitsuba 3.9.1 itself, is listed beside it below). Two independent renders carry twice the
//! variance of one render against a converged reference, so a correct renderer sits near half of
//! that level (plus the reference's own small noise); a systematic error pushes it above.

use gonio_render::image::RgbImage;
use gonio_render::render::{PreparedScene, RenderOptions, render};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// Samples per half-resolution pixel in CI.
const CI_SPP: u32 = 16;

fn testdata() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mitsuba")
}

fn render_scene(name: &str, scale_down: u32, spp: u32, seed: u64) -> RgbImage {
    let path = testdata().join("scenes").join(format!("{name}.xml"));
    let full = gonio_render::xml::load_scene_file(&path, &[]).expect("scene loads");
    let (w, h) = (
        full.sensor.film.width / scale_down,
        full.sensor.film.height / scale_down,
    );
    let defines = vec![
        ("width".to_string(), w.to_string()),
        ("height".to_string(), h.to_string()),
    ];
    let scene = gonio_render::xml::load_scene_file(&path, &defines).expect("scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let mut options = RenderOptions::from_scene(&prepared.scene);
    options.spp = spp;
    options.seed = seed;
    render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false)).image
}

fn reference(name: &str, scale_down: usize) -> RgbImage {
    let r =
        RgbImage::read(testdata().join("reference").join(format!("{name}.exr"))).expect("reference reads");
    downsample(&r, scale_down)
}

fn downsample(img: &RgbImage, k: usize) -> RgbImage {
    if k == 1 {
        return img.clone();
    }
    RgbImage::from_fn(img.width / k, img.height / k, |x, y| {
        let mut s = [0.0f64; 3];
        for j in 0..k {
            for i in 0..k {
                let c = img.get(x * k + i, y * k + j);
                for ch in 0..3 {
                    s[ch] += c[ch] as f64;
                }
            }
        }
        s.map(|v| (v / (k * k) as f64) as f32)
    })
}

/// relMSE of `block` × `block` means of `a` against `b` (see the module docs; the same metric as
/// `gonio compare`).
fn block_relmse(a: &RgbImage, b: &RgbImage, block: usize) -> f64 {
    gonio_render::compare::block_relmse(a, b, block).expect("images of the same size")
}

/// gonio-vs-gonio relMSE at CI size, seeds 1 and 2 (printed by `measure`; see the module docs).
fn check(name: &str, threshold: f64) {
    let img = render_scene(name, 2, CI_SPP, 0);
    let r = reference(name, 2);
    let e = block_relmse(&img, &r, 4);
    println!("{name}: relMSE vs reference {e:.3e} (threshold {threshold:.3e})");
    assert!(
        e < threshold,
        "{name}: 8x8-block relMSE against Mitsuba {e:.3e} ≥ noise level {threshold:.3e}"
    );
}

#[test]
#[ignore = "measurement, run by hand: prints the noise levels the thresholds come from"]
fn measure() {
    for name in ["furnace", "materials", "cornell-spheres", "thin-vs-thick"] {
        let a = render_scene(name, 2, CI_SPP, 1);
        let b = render_scene(name, 2, CI_SPP, 2);
        let c = render_scene(name, 2, CI_SPP, 0);
        let r = reference(name, 2);
        println!(
            "{name}: gonio-vs-gonio {:.3e}, gonio-vs-reference {:.3e} / {:.3e} / {:.3e}",
            block_relmse(&a, &b, 4),
            block_relmse(&a, &r, 4),
            block_relmse(&b, &r, 4),
            block_relmse(&c, &r, 4)
        );
        if let Ok(dir) = std::env::var("GONIO_TEST_OUT") {
            let dir = PathBuf::from(dir);
            a.write(dir.join(format!("{name}-gonio.png"))).unwrap();
            r.write(dir.join(format!("{name}-ref.png"))).unwrap();
        }
    }
}

// Measured with `measure` (CI size, 16 spp, Sobol pattern): the gonio-vs-gonio level, then
// gonio-vs-reference for seeds 1, 2, 0 (about half the level, as it should be), then the level two
// Mitsuba 3.9.1 `scalar_spectral` renders (seeds 1 and 2, its `independent` sampler) show against
// each other at the same size and spp:
//   scene            gonio-gonio  gonio-reference               Mitsuba-Mitsuba
//   furnace          6.80e-5      3.43e-5  3.55e-5  3.25e-5     9.52e-4
//   materials        1.06e-3      5.59e-4  5.35e-4  6.08e-4     3.20e-3
//   cornell-spheres  2.98e-2      1.78e-2  1.79e-2  1.71e-2     3.56e-2
//   thin-vs-thick    1.75e-3      9.15e-4  9.21e-4  9.02e-4     4.96e-3
// The thresholds are the gonio-vs-gonio levels: stricter than Mitsuba's own (gonio's Sobol pattern
// is less noisy at equal spp), and still about twice what a correct render scores.

#[test]
fn furnace_matches_mitsuba() {
    check("furnace", 6.80e-5);
}

#[test]
fn materials_matches_mitsuba() {
    check("materials", 1.06e-3);
}

#[test]
fn cornell_spheres_matches_mitsuba() {
    check("cornell-spheres", 2.98e-2);
}

#[test]
fn thin_vs_thick_matches_mitsuba() {
    check("thin-vs-thick", 1.75e-3);
}
