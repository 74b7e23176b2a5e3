//! Statistics over independent renders, shared by the tests that compare two estimators of the
//! same image (`refracted.rs`, `manifold.rs`, `light_splitting.rs`): the green channel of a
//! render; the mean, the variance of the mean and the mean pixel variance over several seeds;
//! and the comparison itself (the same mean, less noise).

use gonio_render::image::RgbImage;
use gonio_render::render::{PreparedScene, RenderOptions, render};
use std::sync::atomic::AtomicBool;

/// Mitsuba's material-preview environment (`museum.exr`) with +y up, as the statistical tests'
/// scenes light their glass and metal (a soft map: its largest density is 5.2 per sr).
pub const MUSEUM: &str = r#"<emitter type="envmap">
        <string name="filename" value="../../testdata/mitsuba-corpus/common/textures/museum.exr"/>
        <transform name="to_world"><rotate x="1" angle="-90"/></transform>
    </emitter>"#;

/// A diffuse floor (8 × 8 in y = 0) and a small bright lamp above it, beside the statistical
/// scenes' objects.
pub const FLOOR_AND_LAMP: &str = r#"<shape type="rectangle">
        <transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"/>
    </shape>
    <shape type="sphere">
        <point name="center" value="1.2, 1.6, 0.8"/><float name="radius" value="0.1"/>
        <emitter type="area"><rgb name="radiance" value="20"/></emitter>
    </shape>"#;

/// The camera of the statistical scenes: 24 × 24 pixels, box filter, looking down at objects of
/// about unit size at the origin.
pub const SENSOR: &str = r#"<sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 1.6, 3" target="0, 0.5, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/>
        </film>
    </sensor>"#;

/// The scene from text (relative paths against the working directory), rendered polarized
/// (Mueller matrices along the paths) when `polarized`.
pub fn prepare(xml: &str, polarized: bool) -> PreparedScene {
    let mut scene = gonio_render::xml::load_scene_str(xml, ".", &[]).expect("test scene loads");
    scene.integrator.polarized |= polarized;
    PreparedScene::new(scene).expect("test scene prepares")
}

/// The green channel of a render.
pub fn green(p: &PreparedScene, spp: u32, seed: u64) -> Vec<f64> {
    let mut options = RenderOptions::from_scene(&p.scene);
    options.spp = spp;
    options.seed = seed;
    let img: RgbImage = render(p, &options, &|_, _| {}, &AtomicBool::new(false)).image;
    img.data.iter().map(|c| c[1] as f64).collect()
}

/// Over `runs` independent renders (seeds `seed0`, `seed0 + 1`, …): (mean of the image means,
/// variance of one render's image mean, variance of one render's pixel averaged over the
/// pixels).
fn stats(p: &PreparedScene, runs: u64, spp: u32, seed0: u64) -> (f64, f64, f64) {
    let images: Vec<Vec<f64>> = (0..runs).map(|k| green(p, spp, seed0 + k)).collect();
    let n = runs as f64;
    let means: Vec<f64> = images
        .iter()
        .map(|g| g.iter().sum::<f64>() / g.len() as f64)
        .collect();
    let m = means.iter().sum::<f64>() / n;
    let var = means.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    let pixels = images[0].len();
    let pixel_var = (0..pixels)
        .map(|i| {
            let mi = images.iter().map(|g| g[i]).sum::<f64>() / n;
            images.iter().map(|g| (g[i] - mi).powi(2)).sum::<f64>() / (n - 1.0)
        })
        .sum::<f64>()
        / pixels as f64;
    (m, var, pixel_var)
}

/// Two estimators of one image, `with` (the strategy under test) and `without`: over 16 renders
/// of `spp` samples each (seeds 100… and 200…), the same mean within four standard errors of the
/// difference, and `with`'s pixel variance at most `gain` times `without`'s. Returns `with`'s
/// mean.
pub fn same_mean_less_noise(
    with: &PreparedScene,
    without: &PreparedScene,
    spp: u32,
    what: &str,
    gain: f64,
) -> f64 {
    let runs = 16;
    let (m_on, var_on, px_on) = stats(with, runs, spp, 100);
    let (m_off, var_off, px_off) = stats(without, runs, spp, 200);
    let se = ((var_on + var_off) / runs as f64).sqrt();
    println!(
        "{what}: with {m_on:.6} (sd of a render {:.2e}, pixel variance {px_on:.3e}), without {m_off:.6} (sd {:.2e}, pixel variance {px_off:.3e}), se {se:.2e}",
        var_on.sqrt(),
        var_off.sqrt()
    );
    assert!(
        (m_on - m_off).abs() < 4.0 * se,
        "{what}: means differ: {m_on} with, {m_off} without (se {se})"
    );
    assert!(
        px_on < gain * px_off,
        "{what}: pixel variance {px_on} with the strategy, above {gain} × the {px_off} without"
    );
    m_on
}
