//! Light subpaths through specular chains (`caustic_paths`, `integrator::caustics`) against a
//! closed form and against the path tracer alone.
//!
//! * A grey Lambertian floor (ρ = 0.5) lit by a spherical light and by its image in a vertical
//!   mirror, `max_depth` = 3 (direct light and one mirror bounce, nothing else): each floor point
//!   receives E = π·Lₑ·(r/d)²·cos θ from the light and the same from the mirror image, so every
//!   pixel has a closed-form value. With and without light subpaths the image mean matches it;
//!   with them, the noise is lower (the mirror image of a small light is what BSDF sampling
//!   rarely finds).
//! * A glass ball and a mirror ball in a box under a small light: the full path space (floor
//!   caustic, caustics lighting the walls, the floor caustic seen through the ball…) with and
//!   without light subpaths: the same expectation, much less noise with them.
//!
//! Tolerances come from the standard error of the image mean (pixel variance / pixel count), at
//! four standard errors, plus the 0.5 % spectral-uplifting allowance of the other integrator
//! tests for the closed form.

use glam::Vec2;
use gonio_render::camera::{Camera, PerspectiveCamera};
use gonio_render::image::RgbImage;
use gonio_render::render::{PreparedScene, RenderOptions, render};
use std::sync::atomic::AtomicBool;

fn prepare(xml: &str) -> PreparedScene {
    let scene = gonio_render::xml::load_scene_str(xml, ".", &[]).expect("test scene loads");
    PreparedScene::new(scene).expect("test scene prepares")
}

fn render_prepared(p: &PreparedScene, spp: u32, seed: u64) -> RgbImage {
    let mut options = RenderOptions::from_scene(&p.scene);
    options.spp = spp;
    options.seed = seed;
    render(p, &options, &|_, _| {}, &AtomicBool::new(false)).image
}

/// Mean and variance over pixels of the green channel.
fn mean_var(img: &RgbImage) -> (f64, f64) {
    let n = img.data.len() as f64;
    let m = img.data.iter().map(|c| c[1] as f64).sum::<f64>() / n;
    let v = img.data.iter().map(|c| (c[1] as f64 - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, v)
}

fn mirror_scene(caustics: bool) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path">
        <integer name="max_depth" value="3"/>
        <boolean name="caustic_paths" value="{caustics}"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="22"/>
        <transform name="to_world"><lookat origin="-0.5, 4, 0" target="-0.5, 0, 0" up="0, 0, -1"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="32"/><integer name="height" value="32"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="100"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale x="2" y="1.5"/><rotate y="1" angle="-90"/><translate x="1"/></transform>
        <bsdf type="conductor"><string name="material" value="none"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="0.3, 1, 0"/><float name="radius" value="0.1"/>
        <emitter type="area"><rgb name="radiance" value="10"/></emitter>
    </shape>
</scene>"#
    )
}

/// Irradiance at floor point (x, 0, z) from a sphere of radiance `le`, radius `r`, centre `c`
/// fully above the horizon: E = π·Lₑ·(r/d)²·cos θ.
fn sphere_irradiance(x: f64, z: f64, c: [f64; 3], r: f64, le: f64) -> f64 {
    let v = [c[0] - x, c[1], c[2] - z];
    let d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let cos = v[1] / d2.sqrt();
    std::f64::consts::PI * le * r * r / d2 * cos
}

#[test]
fn mirror_image_of_a_light_matches_the_closed_form_with_and_without_light_subpaths() {
    let on = prepare(&mirror_scene(true));
    let off = prepare(&mirror_scene(false));
    // The closed form at every pixel centre (the irradiance is smooth: the pixel mean differs
    // from the centre value by far less than the tolerance).
    let camera = PerspectiveCamera::new(&on.scene.sensor);
    let (w, h) = on.size();
    let mut exact = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let ray = camera.generate_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            let t = -ray.o.y as f64 / ray.d.y as f64;
            let px = ray.o.x as f64 + t * ray.d.x as f64;
            let pz = ray.o.z as f64 + t * ray.d.z as f64;
            assert!(px < 1.0, "the camera must see the floor in front of the mirror");
            let e = sphere_irradiance(px, pz, [0.3, 1.0, 0.0], 0.1, 10.0)
                + sphere_irradiance(px, pz, [1.7, 1.0, 0.0], 0.1, 10.0);
            exact.push(0.5 / std::f64::consts::PI * e);
        }
    }
    let n = exact.len() as f64;
    let expected = exact.iter().sum::<f64>() / n;
    // Noise variance: squared deviation from the closed form, pixel by pixel.
    let noise = |img: &RgbImage| {
        img.data
            .iter()
            .zip(&exact)
            .map(|(c, e)| (c[1] as f64 - e).powi(2))
            .sum::<f64>()
            / n
    };

    let img_on = render_prepared(&on, 64, 1);
    let img_off = render_prepared(&off, 64, 1);
    let (m_on, v_on) = (mean_var(&img_on).0, noise(&img_on));
    let (m_off, v_off) = (mean_var(&img_off).0, noise(&img_off));
    println!(
        "expected {expected:.6}; with light subpaths {m_on:.6} (pixel noise sd {:.5}), without {m_off:.6} (pixel noise sd {:.5})",
        v_on.sqrt(),
        v_off.sqrt()
    );
    for (what, m, v) in [("with", m_on, v_on), ("without", m_off, v_off)] {
        let tol = 4.0 * (v / n).sqrt() + 0.005 * expected;
        assert!(
            (m - expected).abs() < tol,
            "{what} light subpaths: mean {m}, expected {expected} (± {tol})"
        );
    }
    assert!(
        v_on < 0.5 * v_off,
        "light subpaths should lower the noise: pixel variance {v_on} vs {v_off}"
    );
}

fn balls_scene(caustics: bool) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path"><boolean name="caustic_paths" value="{caustics}"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0.2, 3.2" target="0, -0.3, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.7"/></bsdf>
    <shape type="rectangle">
        <transform name="to_world"><rotate x="1" angle="-90"/><translate y="-1"/></transform>
        <ref id="white"/>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><translate z="-1"/></transform>
        <ref id="white"/>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><rotate x="1" angle="90"/><translate y="1"/></transform>
        <ref id="white"/>
    </shape>
    <shape type="sphere">
        <point name="center" value="0.4, -0.6, 0"/><float name="radius" value="0.4"/>
        <bsdf type="dielectric"/>
    </shape>
    <shape type="sphere">
        <point name="center" value="-0.45, -0.65, -0.3"/><float name="radius" value="0.35"/>
        <bsdf type="conductor"><string name="material" value="none"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.15"/><rotate x="1" angle="90"/><translate y="0.99"/></transform>
        <emitter type="area"><rgb name="radiance" value="20"/></emitter>
    </shape>
</scene>"#
    )
}

#[test]
fn light_subpaths_keep_the_expectation_of_a_glass_and_mirror_ball_box() {
    let on = prepare(&balls_scene(true));
    let off = prepare(&balls_scene(false));
    // Several independent renders of each: their means are the samples of the test, so heavy
    // pixel tails (the path tracer's fireflies) do not distort the standard error.
    let runs = 6;
    let stats = |p: &PreparedScene, seed0: u64| -> (f64, f64, f64) {
        let means: Vec<f64> = (0..runs)
            .map(|k| mean_var(&render_prepared(p, 32, seed0 + k)).0)
            .collect();
        let m = means.iter().sum::<f64>() / runs as f64;
        let var_of_mean = means.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (runs as f64 - 1.0);
        (m, var_of_mean, var_of_mean.sqrt())
    };
    let (m_on, var_on, sd_on) = stats(&on, 100);
    let (m_off, var_off, sd_off) = stats(&off, 200);
    let se = ((var_on + var_off) / runs as f64).sqrt();
    println!(
        "balls: with {m_on:.6} (sd of a render {sd_on:.2e}), without {m_off:.6} (sd {sd_off:.2e}), se {se:.2e}"
    );
    assert!(
        (m_on - m_off).abs() < 4.0 * se,
        "means differ: {m_on} with light subpaths, {m_off} without (se {se})"
    );
    assert!(
        var_on < 0.5 * var_off,
        "light subpaths should lower the noise of the image mean: variance {var_on} vs {var_off}"
    );
}
