//! White furnace: under a uniform environment of radiance 1, lossless materials (a white
//! Lambertian sphere, a closed glass sphere, a thin-glass sphere) are invisible, so every pixel
//! is 1. Checked per 8 × 8 block (block means), in each channel, within 0.5 %.
//!
//! What remains in a correct renderer is Monte Carlo noise: the colour noise of the spectral
//! estimator (a D65 spectrum seen through four wavelengths per sample) everywhere, and on the
//! spheres the noise of light arriving by different paths (a diffuse point lit through the glass
//! sphere only by BSDF sampling). A biased path (the η² factor of refraction not undone, a lost
//! Fresnel branch, a wrong MIS weight on the environment) shifts a sphere's blocks by per cents.
//!
//! Noise level (`furnace_noise_level`, full 256 × 128 film, Sobol pattern, seeds 0–3): the worst of
//! the 512 blocks deviates from 1 by 0.47–0.68 % at 64 spp, 0.21–0.49 % at 256 spp and
//! 0.17–0.33 % at 512 spp (noise falls as 1/√spp). The noisiest blocks are on the diffuse
//! sphere's rim facing the glass sphere, lit through the glass only by BSDF sampling. At 512 spp
//! the 0.5 % bound keeps a margin of 1.5× over the worst measured block, while a 1 % bias fails.

use gonio_render::image::RgbImage;
use gonio_render::render::{PreparedScene, RenderOptions, render};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

const SPP: u32 = 512;

fn render_furnace(seed: u64, width: u32, height: u32, spp: u32) -> RgbImage {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mitsuba/scenes/furnace.xml");
    let defines = vec![
        ("width".to_string(), width.to_string()),
        ("height".to_string(), height.to_string()),
    ];
    let scene = gonio_render::xml::load_scene_file(&path, &defines).expect("furnace scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let mut options = RenderOptions::from_scene(&prepared.scene);
    options.spp = spp;
    options.seed = seed;
    render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false)).image
}

/// Largest |block mean − 1| over 8 × 8 blocks and channels.
fn worst_block_deviation(img: &RgbImage) -> (f64, usize, usize) {
    let mut worst = (0.0f64, 0, 0);
    for by in 0..img.height / 8 {
        for bx in 0..img.width / 8 {
            let mut m = [0.0f64; 3];
            for y in 0..8 {
                for x in 0..8 {
                    let c = img.get(bx * 8 + x, by * 8 + y);
                    for k in 0..3 {
                        m[k] += c[k] as f64 / 64.0;
                    }
                }
            }
            for v in m {
                if (v - 1.0).abs() > worst.0 {
                    worst = ((v - 1.0).abs(), bx, by);
                }
            }
        }
    }
    worst
}

#[test]
fn furnace_is_white_within_half_a_percent() {
    // The full 256 × 128 film at 512 spp (see the module docs for the measured noise).
    let img = render_furnace(0, 256, 128, SPP);
    let (dev, bx, by) = worst_block_deviation(&img);
    assert!(
        dev < 0.005,
        "block ({bx}, {by}) deviates by {:.3} % from 1",
        dev * 100.0
    );
}

#[test]
#[ignore = "measurement, run by hand: worst block per seed and spp (FURNACE_SPP, default 512)"]
fn furnace_noise_level() {
    let spp = std::env::var("FURNACE_SPP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(SPP);
    for seed in 0..4 {
        let (dev, bx, by) = worst_block_deviation(&render_furnace(seed, 256, 128, spp));
        println!(
            "spp {spp}, seed {seed}: worst block ({bx}, {by}) {:.4} %",
            dev * 100.0
        );
    }
}
