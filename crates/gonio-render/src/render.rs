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
//! Mitsuba's `hdrfilm`: each sample is splatted with the reconstruction filter's weight to every
//! pixel whose centre lies within the filter radius, and a pixel is Σ w·rgb / Σ w. The radiance
//! estimate becomes linear sRGB through [`gonio_core::color::linear_srgb_from_sampled`], the
//! estimator that divides by the wavelength pdfs (terminated wavelengths count for nothing).

use crate::accel::Accel;
use crate::camera::Camera;
use crate::emitter::{
    AreaLight, ConstantLight, DirectionalLight, EnvMapLight, Light, Lights, PointLight, SpotLight,
};
use crate::geometry::WorldShape;
use crate::image::RgbImage;
use crate::integrator::{PathSampler, PathTracer, bounding_sphere};
use crate::sampler::{Pattern, Sampler};
use crate::scene::{Emitter, Filter, Scene};
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
                lights.push(Light::Area(AreaLight {
                    shape: index,
                    radiance: em.radiance.clone(),
                    area: world[index].area(),
                    mean_radiance: em.radiance.mean(),
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

/// The reconstruction filter's 1D weight at offset `x` pixels (separable; Mitsuba's definitions).
fn filter_weight(f: &Filter, x: f32) -> f32 {
    let x = x.abs();
    match *f {
        Filter::Box { radius } => {
            if x <= radius {
                1.0
            } else {
                0.0
            }
        }
        Filter::Tent { radius } => (1.0 - x / radius).max(0.0),
        Filter::Gaussian { stddev } => {
            let r = 4.0 * stddev;
            if x > r {
                0.0
            } else {
                let a = -1.0 / (2.0 * stddev * stddev);
                ((a * x * x).exp() - (a * r * r).exp()).max(0.0)
            }
        }
    }
}

/// A tile's accumulation buffer including the filter border: Σ w·rgb and Σ w per pixel.
struct TileBuffer {
    x0: i64,
    y0: i64,
    w: usize,
    h: usize,
    sum: Vec<[f32; 4]>,
}

/// Adapter from the render sampler to the integrator's interface.
struct Dims<'s>(&'s mut Sampler);
impl PathSampler for Dims<'_> {
    #[inline]
    fn next_1d(&mut self) -> f32 {
        self.0.next_1d()
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        self.0.next_2d()
    }
}

/// Renders the scene. `progress(done, total)` counts samples; `cancel` stops early.
pub fn render(
    prepared: &PreparedScene,
    options: &RenderOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> RenderOutput {
    let scene = &prepared.scene;
    let (width, height) = prepared.size();
    let filter = scene.sensor.film.filter;
    let radius = filter.radius().max(0.5);
    let border = (radius - 0.5).ceil().max(0.0) as i64;
    let tracer = PathTracer::new(
        &scene.integrator,
        &prepared.accel,
        &prepared.lights,
        &scene.materials,
        &prepared.shape_material,
    );
    let spp = options.spp.max(1);
    let tiles_x = width.div_ceil(TILE);
    let tiles_y = height.div_ceil(TILE);
    let tiles: Vec<(u32, u32)> = (0..tiles_y)
        .flat_map(|ty| (0..tiles_x).map(move |tx| (tx, ty)))
        .collect();
    let total = width as u64 * height as u64 * spp as u64;
    let done = AtomicU64::new(0);
    let mut film = vec![[0.0f64; 4]; (width * height) as usize];
    let mut complete_spp = 0;
    let mut cancelled = false;

    let mut start = 0;
    while start < spp {
        let count = PASS_SPP.min(spp - start);
        let buffers: Vec<Option<TileBuffer>> = tiles
            .par_iter()
            .map(|&(tx, ty)| {
                if cancel.load(Ordering::Relaxed) {
                    return None;
                }
                let (px0, py0) = (tx * TILE, ty * TILE);
                let (px1, py1) = ((px0 + TILE).min(width), (py0 + TILE).min(height));
                let x0 = px0 as i64 - border;
                let y0 = py0 as i64 - border;
                let w = (px1 - px0) as usize + 2 * border as usize;
                let h = (py1 - py0) as usize + 2 * border as usize;
                let mut buf = TileBuffer {
                    x0,
                    y0,
                    w,
                    h,
                    sum: vec![[0.0; 4]; w * h],
                };
                let mut sampler = Sampler::new(options.pattern, spp, options.seed);
                for py in py0..py1 {
                    for px in px0..px1 {
                        for s in start..start + count {
                            sampler.start_pixel_sample(UVec2::new(px, py), s);
                            let pos = Vec2::new(px as f32, py as f32) + sampler.next_2d();
                            let mut wl = SampledWavelengths::sample_visible(sampler.next_1d());
                            let ray = prepared.camera.generate_ray(pos);
                            let l = tracer.li(ray, &mut Dims(&mut sampler), &mut wl);
                            let rgb = linear_srgb_from_sampled(l, &wl);
                            let rgb = if rgb.is_finite() { rgb } else { Vec3::ZERO };
                            splat(&mut buf, &filter, radius, pos, rgb);
                        }
                    }
                }
                let n = done.fetch_add(((px1 - px0) * (py1 - py0) * count) as u64, Ordering::Relaxed);
                progress(n + ((px1 - px0) * (py1 - py0) * count) as u64, total);
                Some(buf)
            })
            .collect();
        let mut pass_complete = true;
        for buf in buffers {
            let Some(buf) = buf else {
                pass_complete = false;
                continue;
            };
            for j in 0..buf.h {
                let y = buf.y0 + j as i64;
                if y < 0 || y >= height as i64 {
                    continue;
                }
                for i in 0..buf.w {
                    let x = buf.x0 + i as i64;
                    if x < 0 || x >= width as i64 {
                        continue;
                    }
                    let src = buf.sum[j * buf.w + i];
                    let dst = &mut film[(y as usize) * width as usize + x as usize];
                    for k in 0..4 {
                        dst[k] += src[k] as f64;
                    }
                }
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

    let image = RgbImage::from_fn(width as usize, height as usize, |x, y| {
        let s = film[y * width as usize + x];
        if s[3] > 0.0 {
            [(s[0] / s[3]) as f32, (s[1] / s[3]) as f32, (s[2] / s[3]) as f32]
        } else {
            [0.0; 3]
        }
    });
    RenderOutput {
        image,
        complete_spp,
        cancelled,
    }
}

/// Adds one sample at film position `pos` (pixels) to every pixel of the tile buffer whose
/// centre lies within the filter radius.
#[inline]
fn splat(buf: &mut TileBuffer, filter: &Filter, radius: f32, pos: Vec2, rgb: Vec3) {
    if let Filter::Box { radius: r } = filter
        && *r <= 0.5
    {
        // Each sample lands in its own pixel only.
        let (i, j) = (pos.x.floor() as i64 - buf.x0, pos.y.floor() as i64 - buf.y0);
        if i >= 0 && j >= 0 && (i as usize) < buf.w && (j as usize) < buf.h {
            let d = &mut buf.sum[j as usize * buf.w + i as usize];
            d[0] += rgb.x;
            d[1] += rgb.y;
            d[2] += rgb.z;
            d[3] += 1.0;
        }
        return;
    }
    let xa = (pos.x - 0.5 - radius).ceil() as i64;
    let xb = (pos.x - 0.5 + radius).floor() as i64;
    let ya = (pos.y - 0.5 - radius).ceil() as i64;
    let yb = (pos.y - 0.5 + radius).floor() as i64;
    for y in ya..=yb {
        let j = y - buf.y0;
        if j < 0 || j as usize >= buf.h {
            continue;
        }
        let wy = filter_weight(filter, y as f32 + 0.5 - pos.y);
        if wy == 0.0 {
            continue;
        }
        for x in xa..=xb {
            let i = x - buf.x0;
            if i < 0 || i as usize >= buf.w {
                continue;
            }
            let w = wy * filter_weight(filter, x as f32 + 0.5 - pos.x);
            if w == 0.0 {
                continue;
            }
            let d = &mut buf.sum[j as usize * buf.w + i as usize];
            d[0] += w * rgb.x;
            d[1] += w * rgb.y;
            d[2] += w * rgb.z;
            d[3] += w;
        }
    }
}
