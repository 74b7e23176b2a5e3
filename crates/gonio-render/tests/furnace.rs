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

/// Heitz et al. 2016 multiple scattering (`multiple_scattering = true`): a white rough
/// conductor and a closed rough glass sphere lose no energy, so they vanish in the furnace. Their
/// `eval` is a stochastic estimate and their `pdf` an approximation used only in the MIS
/// weights; the path tracer stays unbiased only if it takes BSDF-sample contributions from
/// `sample().weight` and uses the same `pdf` in both strategies' weights. Per 8 × 8 block and
/// channel, |mean − 1| is compared with the block's standard error (from its 64 pixels) at a
/// Šidák-corrected 1 % over all blocks and channels, beyond an allowance of 0.2 % (the walks cut
/// at 16 bounces lose < 1.5·10⁻⁵ each: `microsurface`'s docs). Measured (seed 3, 128 spp): every
/// block within the allowance, image mean 0.99994; a 1 % bias fails.
#[test]
fn multiple_scattering_spheres_vanish_in_the_furnace() {
    let xml = r#"<scene version="3.0.0">
        <integrator type="path">
            <integer name="max_depth" value="-1"/>
            <integer name="rr_depth" value="1000"/>
        </integrator>
        <sensor type="perspective">
            <float name="fov" value="45"/>
            <string name="fov_axis" value="x"/>
            <transform name="to_world"><lookat origin="0, 0, 6" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="128"/></sampler>
            <film type="hdrfilm">
                <integer name="width" value="96"/><integer name="height" value="48"/>
                <rfilter type="box"/>
            </film>
        </sensor>
        <shape type="sphere">
            <point name="center" x="-1.1" y="0" z="0"/><float name="radius" value="1"/>
            <bsdf type="roughconductor">
                <string name="distribution" value="ggx"/><float name="alpha" value="0.8"/>
                <boolean name="multiple_scattering" value="true"/>
            </bsdf>
        </shape>
        <shape type="sphere">
            <point name="center" x="1.1" y="0" z="0"/><float name="radius" value="1"/>
            <bsdf type="roughdielectric">
                <string name="distribution" value="ggx"/><float name="alpha" value="0.5"/>
                <float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/>
                <boolean name="multiple_scattering" value="true"/>
            </bsdf>
        </shape>
        <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    </scene>"#;
    let scene = gonio_render::xml::load_scene_str(xml, ".", &[]).expect("scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let mut options = RenderOptions::from_scene(&prepared.scene);
    options.seed = 3;
    let img = render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false)).image;
    let blocks = (img.width / 8) * (img.height / 8) * 3;
    let z = gonio_core::check::z_quantile(gonio_core::check::sidak(0.01, blocks));
    let (mut worst, mut at, mut sum, mut n) = (0.0f64, String::new(), 0.0f64, 0usize);
    for by in 0..img.height / 8 {
        for bx in 0..img.width / 8 {
            for k in 0..3 {
                let v: Vec<f64> = (0..64)
                    .map(|i| img.get(bx * 8 + i % 8, by * 8 + i / 8)[k] as f64)
                    .collect();
                let mean = v.iter().sum::<f64>() / 64.0;
                let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 63.0;
                let se = (var / 64.0).sqrt();
                let excess = ((mean - 1.0).abs() - 0.002).max(0.0) / se.max(1e-12);
                sum += mean;
                n += 1;
                if excess > worst {
                    worst = excess;
                    at = format!("block ({bx}, {by}) channel {k}: {mean:.5} ± {se:.5}");
                }
            }
        }
    }
    eprintln!(
        "multiple-scattering furnace: image mean {:.5}; worst {at}",
        sum / n as f64
    );
    assert!(
        worst <= z,
        "{at} deviates from 1 by {worst:.2} standard errors (limit {z:.2})"
    );
}

/// The built-in `lambertian-furnace` scene (`gonio render --builtin lambertian-furnace`) at a
/// reduced film: white rough conductors and rough glass with multiple scattering, Lambert,
/// white diffuse microfacets and white Lambertian spheres under a uniform sky of radiance 1.
fn render_builtin_furnace(ms: bool, spp: u32, seed: u64) -> RgbImage {
    let text = gonio_render::render::builtin_scene("lambertian-furnace").expect("built in");
    let defines = [
        ("width", "80"),
        ("height", "40"),
        ("ms", if ms { "true" } else { "false" }),
    ]
    .map(|(k, v)| (k.to_string(), v.to_string()));
    let scene = gonio_render::xml::load_scene_str(text, ".", &defines).expect("scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let mut options = RenderOptions::from_scene(&prepared.scene);
    (options.spp, options.seed) = (spp, seed);
    render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false)).image
}

/// Spp of the built-in furnace test (`BUILTIN_FURNACE_SPP` overrides it for measurements).
fn builtin_furnace_spp() -> u32 {
    std::env::var("BUILTIN_FURNACE_SPP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(BUILTIN_FURNACE_SPP)
}

const BUILTIN_FURNACE_SPP: u32 = 512;

#[test]
fn the_builtin_lambertian_furnace_is_white_within_half_a_percent() {
    // With multiple scattering every sphere of the scene is lossless: every 8 × 8 block within
    // 0.5 % of 1, each channel. Measured at 80 × 40 and 512 spp, seeds 1, 2, 3: worst blocks
    // 0.35 %, 0.19 %, 0.21 % (1024 spp, seed 1: 0.28 %), all on the diffuse-microfacet sphere,
    // whose `eval` estimates its facet term with one sampled normal.
    let t = std::time::Instant::now();
    let seed = std::env::var("BUILTIN_FURNACE_SEED").map_or(1, |s| s.parse().unwrap_or(1));
    let img = render_builtin_furnace(true, builtin_furnace_spp(), seed);
    let (dev, bx, by) = worst_block_deviation(&img);
    eprintln!(
        "builtin furnace, {} spp: worst block ({bx}, {by}) {:.3} % ({:.1} s)",
        builtin_furnace_spp(),
        dev * 100.0,
        t.elapsed().as_secs_f64()
    );
    assert!(
        dev < 0.005,
        "block ({bx}, {by}) deviates by {:.3} % from 1",
        dev * 100.0
    );
}

#[test]
fn the_builtin_furnace_shows_what_single_scattering_loses() {
    // The same scene with `ms=false`: the single-scattering rough conductors and glass lose the
    // light that meets the microsurface twice or more, so their spheres darken (the white GGX
    // α = 1 conductor's albedo is 1 − ln 2 ≈ 0.31 at normal incidence).
    let img = render_builtin_furnace(false, 32, 1);
    let (dev, bx, by) = worst_block_deviation(&img);
    assert!(
        dev > 0.3,
        "darkest block ({bx}, {by}) only {:.1} % below 1",
        dev * 100.0
    );
}
