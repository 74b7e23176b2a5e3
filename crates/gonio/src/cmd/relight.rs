//! `gonio relight SCENE --lights N --env MAP.exr -o out.exr`: the light stage (lecture slides
//! "The Light Stage", "Leveraging BRDF Linearity: Relighting").
//!
//! The reflection equation is linear in the incident light, so an object photographed under N
//! lights one at a time can be shown under any lighting that is a combination of them:
//!
//! 1. N directions d_k spread evenly over the sphere (a Fibonacci lattice);
//! 2. one basis image I_k per direction: the scene's own emitters removed, a single directional
//!    light from d_k of unit irradiance (D65, i.e. white);
//! 3. the weights w_k = ∫ L_env dω over the directions closer to d_k than to any other (the
//!    environment's radiance gathered into its Voronoi cell), per RGB channel;
//! 4. the relit image Σ_k w_k I_k, compared with a direct render of the scene under the
//!    environment map (relMSE), for a series of N. Both hide directly visible emitters: the
//!    stage relights the object, not its background.
//!
//! The error has two parts: the discretization of the environment into N lights, which falls as
//! N grows, and the Monte Carlo noise of the renders. Ideal specular surfaces (mirrors, glass)
//! are invisible to directional lights (a delta BSDF never meets a delta light), so their
//! reflections of the environment are missing from the relit image at any N: the light stage
//! captures them only in the limit of infinitely many lights.

use anyhow::{Context, anyhow, bail};
use clap::Args as ClapArgs;
use glam::{Affine3A, Vec3};
use gonio_core::Spectrum;
use gonio_render::compare::relmse;
use gonio_render::image::RgbImage;
use gonio_render::render::{PreparedScene, RenderOptions, render};
use gonio_render::scene::{EmitterDesc, Scene};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Arguments of `gonio relight`.
#[derive(ClapArgs)]
pub struct Args {
    /// The scene (Mitsuba 3 XML); its emitters are replaced by the light stage's.
    scene: PathBuf,
    /// Number of directional lights over the sphere.
    #[arg(long, default_value_t = 64)]
    lights: usize,
    /// The environment map (lat-long, linear RGB: EXR, HDR, or PNG).
    #[arg(long)]
    env: PathBuf,
    /// The relit image (.exr or .png).
    #[arg(short, long)]
    output: PathBuf,
    /// Also write the direct render under the environment map here.
    #[arg(long)]
    direct: Option<PathBuf>,
    /// Samples per pixel of every render (default: the scene's).
    #[arg(long)]
    spp: Option<u32>,
    /// Also relight with these smaller light counts and report how the error falls
    /// (comma-separated; default N/64, N/16, N/4 where ≥ 1).
    #[arg(long, value_delimiter = ',')]
    series: Vec<usize>,
}

/// N directions evenly spread over the unit sphere (spherical Fibonacci lattice).
pub fn fibonacci_sphere(n: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|k| {
            let z = 1.0 - (2.0 * k as f32 + 1.0) / n as f32;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * k as f32;
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// The world direction of lat-long pixel centre (i, j), Mitsuba's `envmap` convention with an
/// identity `to_world` (+y up, u = 0 looking down −z).
fn env_direction(i: usize, j: usize, w: usize, h: usize) -> (Vec3, f32) {
    let u = (i as f32 + 0.5) / w as f32;
    let v = (j as f32 + 0.5) / h as f32;
    let (st, ct) = (std::f32::consts::PI * v).sin_cos();
    let (sp, cp) = (std::f32::consts::TAU * u).sin_cos();
    let d_omega = st * (std::f32::consts::TAU / w as f32) * (std::f32::consts::PI / h as f32);
    (Vec3::new(st * sp, ct, -st * cp), d_omega)
}

/// The light-stage weights: the environment's radiance integrated over each light's Voronoi cell
/// (RGB, i.e. the irradiance each directional light must have).
pub fn light_weights(env: &RgbImage, dirs: &[Vec3]) -> Vec<[f64; 3]> {
    let mut w = vec![[0.0f64; 3]; dirs.len()];
    for j in 0..env.height {
        for i in 0..env.width {
            let (d, d_omega) = env_direction(i, j, env.width, env.height);
            let k = dirs
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.dot(d).total_cmp(&b.1.dot(d)))
                .map(|(k, _)| k)
                .unwrap_or(0);
            let c = env.data[j * env.width + i];
            for ch in 0..3 {
                let v = if c[ch].is_finite() { c[ch].max(0.0) } else { 0.0 };
                w[k][ch] += (v * d_omega) as f64;
            }
        }
    }
    w
}

fn render_with(
    scene: &Scene,
    emitters: Vec<EmitterDesc>,
    options: &RenderOptions,
) -> anyhow::Result<RgbImage> {
    let mut s = scene.clone();
    s.emitters = emitters;
    // The stage photographs the object, not the lights: the environment seen directly (the
    // background) has no counterpart in the basis images.
    s.integrator.hide_emitters = true;
    for shape in &mut s.shapes {
        shape.emitter = None;
    }
    let prepared = PreparedScene::new(s).map_err(|e| anyhow!("{e}"))?;
    Ok(render(&prepared, options, &|_, _| {}, &AtomicBool::new(false)).image)
}

/// Relights with `n` lights: Σ w_k I_k.
fn relight(scene: &Scene, env: &RgbImage, n: usize, options: &RenderOptions) -> anyhow::Result<RgbImage> {
    let dirs = fibonacci_sphere(n);
    let weights = light_weights(env, &dirs);
    let (w, h) = (
        scene.sensor.film.width as usize,
        scene.sensor.film.height as usize,
    );
    let mut acc = vec![[0.0f64; 3]; w * h];
    for (d, wk) in dirs.iter().zip(&weights) {
        if wk.iter().all(|&x| x == 0.0) {
            continue; // a black part of the environment: its basis image does not contribute
        }
        let light = EmitterDesc::Directional {
            direction: -*d,
            irradiance: Spectrum::d65(),
        };
        let basis = render_with(scene, vec![light], options)?;
        for (a, p) in acc.iter_mut().zip(&basis.data) {
            for ch in 0..3 {
                a[ch] += wk[ch] * p[ch] as f64;
            }
        }
    }
    let mut out = RgbImage::new(w, h);
    for (o, a) in out.data.iter_mut().zip(&acc) {
        *o = a.map(|x| x as f32);
    }
    Ok(out)
}

/// Runs `gonio relight`.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    if !(1..=4096).contains(&a.lights) {
        bail!("--lights {}: must be within [1, 4096]", a.lights);
    }
    if let Some(&bad) = a.series.iter().find(|&&n| n == 0 || n > 4096) {
        bail!("--series {bad}: light counts must be within [1, 4096]");
    }
    let scene = gonio_render::xml::load_scene_file(&a.scene, &[])
        .with_context(|| format!("loading {}", a.scene.display()))?;
    // The environment's weights are RGB: the images must be the film's plain colour.
    if scene.sensor.film.response != gonio_core::sensor_response::SensorResponse::Srgb {
        bail!(
            "{}: relighting weighs colour images; this sensor records spectral bands (specfilm) or filters by an srf",
            a.scene.display()
        );
    }
    let env =
        RgbImage::read(&a.env).with_context(|| format!("reading the environment map {}", a.env.display()))?;
    if env.width == 0 || env.height == 0 {
        bail!("{}: empty environment map", a.env.display());
    }
    let mut options = RenderOptions::from_scene(&scene);
    if let Some(spp) = a.spp {
        if spp == 0 {
            bail!("--spp 0: need at least one sample per pixel");
        }
        options.spp = spp;
    }
    let t = Instant::now();
    let env_emitter = EmitterDesc::EnvMap {
        image: Arc::new(env.clone()),
        scale: 1.0,
        to_world: Affine3A::IDENTITY,
        mitsuba_lookup: false,
        mis_compensation: true,
        product_sampling: true,
    };
    let direct = render_with(&scene, vec![env_emitter], &options)?;
    eprintln!(
        "direct render under the environment: {:.1} s",
        t.elapsed().as_secs_f32()
    );
    if let Some(p) = &a.direct {
        direct
            .write(p)
            .with_context(|| format!("writing {}", p.display()))?;
    }
    let mut counts: Vec<usize> = if a.series.is_empty() {
        [64, 16, 4]
            .iter()
            .map(|d| a.lights / d)
            .filter(|&n| n >= 1 && n < a.lights)
            .collect()
    } else {
        a.series.clone()
    };
    counts.retain(|&n| n != a.lights);
    counts.sort_unstable();
    counts.dedup();
    counts.push(a.lights);
    let mut out = std::io::stdout().lock();
    writeln!(out, "{:>7} {:>12} {:>9}", "lights", "relMSE", "seconds")?;
    for &n in &counts {
        let t = Instant::now();
        let img = relight(&scene, &env, n, &options)?;
        let e = relmse(&img, &direct).map_err(|e| anyhow!("{e}"))?;
        writeln!(out, "{n:>7} {e:>12.6} {:>9.1}", t.elapsed().as_secs_f32())?;
        if n == a.lights {
            img.write(&a.output)
                .with_context(|| format!("writing {}", a.output.display()))?;
        }
    }
    writeln!(out, "relit image ({} lights): {}", a.lights, a.output.display())?;
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fibonacci_directions_are_unit_and_balanced() {
        let d = fibonacci_sphere(200);
        assert!(d.iter().all(|v| (v.length() - 1.0).abs() < 1e-5));
        let mean = d.iter().fold(Vec3::ZERO, |a, v| a + *v) / 200.0;
        assert!(mean.length() < 0.02, "{mean}");
    }

    #[test]
    fn weights_of_a_uniform_environment_sum_to_its_radiance_times_4pi() {
        let env = RgbImage::from_fn(64, 32, |_, _| [1.0, 0.5, 0.25]);
        let w = light_weights(&env, &fibonacci_sphere(12));
        let sum: f64 = w.iter().map(|c| c[0]).sum();
        assert!((sum - 4.0 * std::f64::consts::PI).abs() < 1e-2, "{sum}");
        assert!(
            w.iter()
                .all(|c| (c[0] - 4.0 * std::f64::consts::PI / 12.0).abs() < 0.35),
            "cells are about equal"
        );
        assert!((w[0][1] / w[0][0] - 0.5).abs() < 1e-6);
    }
}
