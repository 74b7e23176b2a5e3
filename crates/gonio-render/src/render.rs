//! The render loop: a [`Scene`] prepared once ([`PreparedScene`]: world shapes, BVH, lights,
//! camera), then rendered in passes over 16 × 16 tiles in parallel with rayon.
//!
//! # Determinism
//!
//! Every sample is a pure function of (seed, pixel, sample index): the sampler is seeded from
//! them, never from a thread. Each tile accumulates its samples into its own buffer, in sample
//! order; the tiles of a pass are collected in tile order and merged into the film sequentially.
//! The floating-point sums are therefore the same whatever the number of threads, and so is the
//! image, bit for bit.
//!
//! # Passes, progress and cancellation
//!
//! The samples of a pixel are split into passes of at most [`PASS_SPP`] samples; the progress
//! callback receives (samples done, samples total) after every tile; a set cancellation flag stops
//! the render at the next tile, and the image of everything finished so far is returned (each
//! pixel normalized by its own filter-weight sum, so a pixel that got fewer samples is only
//! noisier).
//!
//! # Film
//!
//! Mitsuba's `hdrfilm` ([`crate::film`]): each sample is splatted with the reconstruction filter's
//! weight to every pixel whose centre lies within the filter radius, and a pixel is Σ w·rgb / Σ w.
//! The radiance estimate becomes linear sRGB through
//! [`gonio_core::color::linear_srgb_from_sampled`], the estimator that divides by the wavelength
//! pdfs (terminated wavelengths count for nothing).
//!
//! # Sampling
//!
//! Dimensions 0–1 place the sample in its pixel, dimension 2 draws the hero wavelength (visible
//! pdf, through [`VisibleWavelengthTable`]), the path takes the rest; see [`STRUCTURED_DIMS`]
//! for where the structured pattern hands over to independent numbers.

use crate::accel::Accel;
use crate::camera::Camera;
use crate::emitter::{
    AreaLight, ConstantLight, DirectionalLight, EnvMapLight, Light, Lights, PointLight, SpotLight,
};
use crate::film::{Film, FilmTile, SplatFilm};
use crate::geometry::WorldShape;
use crate::image::RgbImage;
use crate::integrator::caustics::LightSubpath;
use crate::integrator::{PathSampler, PathTracer, bounding_sphere};
use crate::sampler::{Pattern, Pcg32, Sampler, sample_key};
use crate::scene::{Emitter, Scene};
use glam::{UVec2, Vec2, Vec3};
use gonio_core::SampledWavelengths;
use gonio_core::color::linear_srgb_from_sampled;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// The embedded default scene: a gallery of the lecture's materials (`gonio render` with no
/// arguments).
pub const DEFAULT_SCENE: &str = include_str!("default_scene.xml");

/// Tile edge, pixels.
pub const TILE: u32 = 16;
/// Largest number of samples per pixel in one pass.
pub const PASS_SPP: u32 = 16;

/// Errors while preparing a scene for rendering.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A shape could not be placed in the world (bad transform, empty mesh...).
    #[error("shape {index}: {message}")]
    Shape {
        /// Index of the shape in the scene.
        index: usize,
        /// What went wrong.
        message: String,
    },
    /// A shape refers to a material that does not exist.
    #[error("shape {index} refers to material {material}, but the scene has {count}")]
    Material {
        /// Index of the shape.
        index: usize,
        /// The material index it names.
        material: usize,
        /// Number of materials.
        count: usize,
    },
    /// An emitter's parameters cannot be used.
    #[error("emitter {index}: {message}")]
    Emitter {
        /// Index of the emitter among the scene's emitters.
        index: usize,
        /// What went wrong.
        message: String,
    },
    /// The film has no pixels.
    #[error("the film has no pixels ({width} x {height})")]
    EmptyFilm {
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
}

/// A scene ready to render: shapes in world space inside a BVH, lights with their selection
/// distribution, the camera.
pub struct PreparedScene {
    /// The scene as read.
    pub scene: Scene,
    accel: Accel,
    lights: Lights,
    shape_material: Vec<usize>,
    camera: Camera,
}

impl std::fmt::Debug for PreparedScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PreparedScene")
            .field("shapes", &self.scene.shapes.len())
            .field("lights", &self.lights.lights().len())
            .finish()
    }
}

impl PreparedScene {
    /// Places the shapes, builds the BVH and the lights.
    pub fn new(scene: Scene) -> Result<Self, RenderError> {
        let film = &scene.sensor.film;
        if film.width == 0 || film.height == 0 {
            return Err(RenderError::EmptyFilm {
                width: film.width,
                height: film.height,
            });
        }
        let mut world = Vec::with_capacity(scene.shapes.len());
        let mut shape_material = Vec::with_capacity(scene.shapes.len());
        for (index, shape) in scene.shapes.iter().enumerate() {
            let name = shape.id.clone().unwrap_or_else(|| format!("#{index}"));
            let w = WorldShape::from_scene(shape, &name).map_err(|e| RenderError::Shape {
                index,
                message: e.to_string(),
            })?;
            if shape.material >= scene.materials.len() {
                return Err(RenderError::Material {
                    index,
                    material: shape.material,
                    count: scene.materials.len(),
                });
            }
            world.push(w);
            shape_material.push(shape.material);
        }
        let scene_area: f32 = world.iter().map(|s| s.area()).filter(|a| a.is_finite()).sum();
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for s in &world {
            for prim in 0..s.prim_count() {
                let (a, b) = s.prim_bounds(prim);
                lo = lo.min(a);
                hi = hi.max(b);
            }
        }
        let bounds = bounding_sphere(lo, hi);

        let mut lights = Vec::new();
        for (index, shape) in scene.shapes.iter().enumerate() {
            if let Some(em) = &shape.emitter {
                let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
                for prim in 0..world[index].prim_count() {
                    let (a, b) = world[index].prim_bounds(prim);
                    lo = lo.min(a);
                    hi = hi.max(b);
                }
                let sphere = bounding_sphere(lo, hi);
                lights.push(Light::Area(AreaLight {
                    shape: index,
                    radiance: em.radiance.clone(),
                    area: world[index].area(),
                    mean_radiance: em.radiance.mean(),
                    center: sphere.center,
                    radius: sphere.radius,
                }));
            }
        }
        for (index, e) in scene.emitters.iter().enumerate() {
            let light = match e {
                Emitter::Point { position, intensity } => Light::Point(PointLight {
                    position: *position,
                    intensity: intensity.clone(),
                }),
                Emitter::Spot {
                    to_world,
                    intensity,
                    cutoff_angle_deg,
                    beam_width_deg,
                } => {
                    if to_world.matrix3.determinant() == 0.0 {
                        return Err(RenderError::Emitter {
                            index,
                            message: "singular to_world".into(),
                        });
                    }
                    Light::Spot(SpotLight::new(
                        *to_world,
                        intensity.clone(),
                        *cutoff_angle_deg,
                        *beam_width_deg,
                    ))
                }
                Emitter::Directional {
                    direction,
                    irradiance,
                } => {
                    let d = direction.normalize_or_zero();
                    if d == Vec3::ZERO {
                        return Err(RenderError::Emitter {
                            index,
                            message: "zero direction".into(),
                        });
                    }
                    Light::Directional(DirectionalLight {
                        direction: d,
                        irradiance: irradiance.clone(),
                    })
                }
                Emitter::Constant { radiance } => Light::Constant(ConstantLight {
                    radiance: radiance.clone(),
                }),
                Emitter::EnvMap {
                    image,
                    scale,
                    to_world,
                } => {
                    let env = EnvMapLight::new(
                        image.width,
                        image.height,
                        image.data.clone(),
                        *scale,
                        *to_world,
                        gonio_core::Spectrum::rgb_illuminant,
                    )
                    .ok_or_else(|| RenderError::Emitter {
                        index,
                        message: "empty environment image or singular to_world".into(),
                    })?;
                    Light::EnvMap(env)
                }
            };
            lights.push(light);
        }
        let lights = Lights::new(lights, world.len(), scene_area, bounds);
        let camera = Camera::new(&scene.sensor);
        let accel = Accel::new(world);
        Ok(Self {
            scene,
            accel,
            lights,
            shape_material,
            camera,
        })
    }

    /// The lights.
    pub fn lights(&self) -> &Lights {
        &self.lights
    }

    /// The accelerator.
    pub fn accel(&self) -> &Accel {
        &self.accel
    }

    /// Film size (width, height).
    pub fn size(&self) -> (u32, u32) {
        (self.scene.sensor.film.width, self.scene.sensor.film.height)
    }
}

/// What to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Samples per pixel.
    pub spp: u32,
    /// Seed of the sample sequences.
    pub seed: u64,
    /// Sample pattern.
    pub pattern: Pattern,
}

impl RenderOptions {
    /// The scene's own sampler settings, except that Mitsuba's `independent` sampler is replaced
    /// by our Owen-scrambled Sobol pattern, which gives the same expected image with less noise
    /// (set [`RenderOptions::pattern`] to [`Pattern::Independent`] for Mitsuba's exact sampler).
    pub fn from_scene(scene: &Scene) -> Self {
        let s = &scene.sensor.sampler;
        let pattern = match Pattern::from(s.kind) {
            Pattern::Independent => Pattern::Sobol,
            p => p,
        };
        Self {
            spp: s.sample_count.max(1),
            seed: s.seed,
            pattern,
        }
    }

    /// Exactly the scene's sampler (Mitsuba's `independent` stays independent).
    pub fn exact_from_scene(scene: &Scene) -> Self {
        let s = &scene.sensor.sampler;
        Self {
            spp: s.sample_count.max(1),
            seed: s.seed,
            pattern: s.kind.into(),
        }
    }
}

/// The result of [`render`].
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Linear sRGB image.
    pub image: RgbImage,
    /// Samples per pixel every pixel received (the requested count unless cancelled).
    pub complete_spp: u32,
    /// True when the cancellation flag stopped the render early.
    pub cancelled: bool,
}

/// Dimensions drawn from the structured pattern before switching to independent numbers: the
/// camera (3) and two vertices with a smooth lobe (6 each: light choice, light point, lobe,
/// direction; a purely delta vertex takes one, its lobe choice, and roulette numbers start at
/// `rr_depth`). Stratification matters most for the first bounces; beyond them a scrambled Sobol
/// point costs more than it gains, so deeper dimensions come from a PCG32 stream keyed by
/// (seed, pixel, sample index) — still a pure function of the sample, as determinism requires.
const STRUCTURED_DIMS: u32 = 3 + 2 * 6;

/// Adapter from the render sampler to the integrator's interface (with the padding above).
struct Dims<'s> {
    sampler: &'s mut Sampler,
    used: u32,
    limit: u32,
    key: u64,
    rng: Option<Pcg32>,
}

impl<'s> Dims<'s> {
    fn new(sampler: &'s mut Sampler, used: u32, pattern: Pattern, key: u64) -> Self {
        let limit = if pattern == Pattern::Independent {
            u32::MAX
        } else {
            STRUCTURED_DIMS
        };
        Self {
            sampler,
            used,
            limit,
            key,
            rng: None,
        }
    }

    #[inline]
    fn rng(&mut self) -> &mut Pcg32 {
        let key = self.key;
        self.rng
            .get_or_insert_with(|| Pcg32::new(key, key.rotate_left(17) ^ 0x9e37_79b9_7f4a_7c15))
    }
}

impl PathSampler for Dims<'_> {
    #[inline]
    fn next_1d(&mut self) -> f32 {
        if self.used < self.limit {
            self.used += 1;
            self.sampler.next_1d()
        } else {
            self.rng().next_f32()
        }
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        if self.used + 1 < self.limit {
            self.used += 2;
            self.sampler.next_2d()
        } else {
            let r = self.rng();
            let x = r.next_f32();
            Vec2::new(x, r.next_f32())
        }
    }
}

/// Mixed into a sample's key to seed its light path's random numbers.
const LIGHT_PATH_KEY: u64 = 0x6c69_6768_745f_7061;

/// Renders the scene. `progress(done, total)` counts samples; `cancel` stops early.
pub fn render(
    prepared: &PreparedScene,
    options: &RenderOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> RenderOutput {
    let scene = &prepared.scene;
    let (width, height) = prepared.size();
    let tracer = PathTracer::new(
        &scene.integrator,
        &prepared.accel,
        &prepared.lights,
        &scene.materials,
        &prepared.shape_material,
    )
    .with_camera(&prepared.camera);
    let spp = options.spp.max(1);
    let mut film = Film::new(width, height, scene.sensor.film.filter);
    // Light tracing of the caustics seen directly (`integrator::caustics`): one light path per
    // camera sample, splatted anywhere on the film.
    let splats = tracer
        .traces_caustics()
        .then(|| SplatFilm::new(width, height, scene.sensor.film.filter));
    // One light-subpath slot per camera sample; splats arrive divided by their total (the
    // light tracer estimates the image with N = spp·pixels subpaths).
    let light_paths = AtomicU64::new(0);
    let blocks: Vec<(UVec2, UVec2)> = film.tiles(TILE).iter().map(|t| t.block()).collect();
    let total = width as u64 * height as u64 * spp as u64;
    let inv_light_paths = 1.0 / total as f32;
    let done = AtomicU64::new(0);
    let mut complete_spp = 0;
    let wavelengths = VisibleWavelengthTable::new();
    let mut cancelled = false;

    let mut start = 0;
    while start < spp {
        let count = PASS_SPP.min(spp - start);
        let tiles: Vec<Option<FilmTile>> = blocks
            .par_iter()
            .map(|&(lo, hi)| {
                if cancel.load(Ordering::Relaxed) {
                    return None;
                }
                let mut tile = film.tile(lo, hi);
                let mut sampler = Sampler::new(options.pattern, spp, options.seed);
                let mut light = LightSubpath::EMPTY;
                for py in lo.y..hi.y {
                    for px in lo.x..hi.x {
                        for s in start..start + count {
                            sampler.start_pixel_sample(UVec2::new(px, py), s);
                            let pos = Vec2::new(px as f32, py as f32) + sampler.next_2d();
                            let mut wl = wavelengths.sample(sampler.next_1d());
                            let ray = prepared.camera.generate_ray(pos);
                            let key = sample_key(options.seed, px, py, s);
                            // The light subpath first: it shares the wavelengths (and may
                            // terminate the secondary ones).
                            if let Some(splats) = &splats {
                                let mut rng = Pcg32::new(key ^ LIGHT_PATH_KEY, key.rotate_left(29));
                                let mut splat = |p, value, wl: &SampledWavelengths| {
                                    let rgb = linear_srgb_from_sampled(value, wl) * inv_light_paths;
                                    splats.splat(p, rgb.to_array())
                                };
                                tracer.trace_light_path(&mut rng, &mut wl, &mut splat, &mut light);
                            }
                            let mut dims = Dims::new(&mut sampler, 3, options.pattern, key);
                            let l = tracer.li(ray, &mut dims, &mut wl, &light);
                            tile.add_sample(pos, linear_srgb_from_sampled(l, &wl).to_array());
                        }
                    }
                }
                let n = ((hi.x - lo.x) * (hi.y - lo.y) * count) as u64;
                light_paths.fetch_add(n, Ordering::Relaxed);
                progress(done.fetch_add(n, Ordering::Relaxed) + n, total);
                Some(tile)
            })
            .collect();
        // Merge in tile order: the same sums whatever thread rendered which tile.
        let mut pass_complete = true;
        for tile in &tiles {
            match tile {
                Some(t) => film.merge(t),
                None => pass_complete = false,
            }
        }
        if !pass_complete {
            cancelled = true;
            break;
        }
        complete_spp = start + count;
        start += count;
        if cancel.load(Ordering::Relaxed) && start < spp {
            cancelled = true;
            break;
        }
    }

    let mut image = film.to_image();
    let traced = light_paths.load(Ordering::Relaxed);
    if let Some(splats) = &splats
        && traced > 0
    {
        // A cancelled render traced fewer.
        splats.add_to(&mut image, total as f64 / traced as f64);
    }
    RenderOutput {
        image,
        complete_spp,
        cancelled,
    }
}

/// Hero-wavelength sampling from the visible pdf through a table: the inverse CDF of
/// [`gonio_core::spectrum::sample_visible_wavelength`] (Radziszewski's sech² fit, as in pbrt and
/// Mitsuba) tabulated at 4096 points and interpolated linearly. Linear interpolation of the inverse
/// CDF samples the piecewise-constant density p = (1/N)/(λᵢ₊₁ − λᵢ) on each interval, which is
/// returned with each wavelength, so the estimator stays exactly unbiased; the density differs
/// from the sech² curve by less than 1 % (at the far tails, where few samples land). It replaces four `f64` atanh and cosh per camera
/// sample (a fifth of the render time) by table lookups. The four wavelengths are the hero and
/// its rotations by ¼, ½ and ¾ in sample space, as in `SampledWavelengths::sample_visible`.
struct VisibleWavelengthTable {
    lambda: Vec<f32>,
}

impl VisibleWavelengthTable {
    const N: usize = 4096;

    fn new() -> Self {
        let lambda = (0..=Self::N)
            .map(|i| gonio_core::spectrum::sample_visible_wavelength(i as f32 / Self::N as f32))
            .collect();
        Self { lambda }
    }

    #[inline]
    fn one(&self, u: f32) -> (f32, f32) {
        let x = (u * Self::N as f32).clamp(0.0, Self::N as f32 - 1e-3);
        let i = (x as usize).min(Self::N - 1);
        let (a, b) = (self.lambda[i], self.lambda[i + 1]);
        let t = x - i as f32;
        (a + t * (b - a), 1.0 / (Self::N as f32 * (b - a)))
    }

    #[inline]
    fn sample(&self, u: f32) -> SampledWavelengths {
        let mut lambda = [0.0; 4];
        let mut pdf = [0.0; 4];
        for k in 0..4 {
            let mut uk = u + k as f32 * 0.25;
            if uk >= 1.0 {
                uk -= 1.0;
            }
            (lambda[k], pdf[k]) = self.one(uk);
        }
        SampledWavelengths::from_parts(lambda, pdf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gonio_core::spectrum::visible_wavelength_pdf;

    #[test]
    fn wavelength_table_density_is_exact_and_close_to_the_visible_pdf() {
        let t = VisibleWavelengthTable::new();
        let n = 100_000;
        // The returned density integrates to one over [360, 830] (Σ p·Δλ per interval = 1/N).
        let mut worst = 0.0f32;
        let mut y_est = 0.0f64;
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            let (l, p) = t.one(u);
            assert!((360.0..=830.0).contains(&l));
            worst = worst.max((p / visible_wavelength_pdf(l) - 1.0).abs());
            y_est += (gonio_core::color::cie_y(l) / p) as f64;
        }
        assert!(
            worst < 1e-2,
            "table density departs from the sech² pdf by {worst}"
        );
        // Unbiased: the estimate of ∫ȳ dλ with the table's density matches CIE_Y_INTEGRAL.
        let y = y_est / n as f64;
        assert!(
            (y / gonio_core::color::CIE_Y_INTEGRAL as f64 - 1.0).abs() < 2e-4,
            "∫ȳ = {y}"
        );
        // The four wavelengths are the hero and its rotations by ¼ in sample space.
        let wl = t.sample(0.1);
        for k in 0..4 {
            assert!((wl.lambda(k) - t.one(0.1 + 0.25 * k as f32).0).abs() < 1e-3);
        }
    }
}
