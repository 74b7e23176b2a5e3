//! The render loop: a [`Scene`] prepared once ([`PreparedScene`]: world shapes, BVH, lights,
//! camera), then rendered in passes over 16 × 16 tiles in parallel with rayon by any
//! [`Integrator`] ([`render_with`]; [`render`] uses the scene's own, the `path` integrator).
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
//! Mitsuba's `hdrfilm` ([`crate::film`]) with the integrator's channels
//! ([`Integrator::channels`]): each sample is splatted with the reconstruction filter's weight to
//! every pixel whose centre lies within the filter radius, and a pixel is Σ w·value / Σ w.
//! Integrators splat what lands elsewhere (light tracing) into a [`SplatFilm`] with the same
//! channels, divided by the number of camera samples.
//!
//! # Sampling
//!
//! Dimensions 0–1 place the sample in its pixel, dimension 2 draws the hero wavelength (the
//! visible sech² pdf blended with the colour matching functions,
//! [`gonio_core::spectrum::render_wavelength_pdf`], through
//! [`gonio_core::spectrum::VisibleWavelengthTable`]), the integrator takes the rest
//! ([`Sampler::padded`]; see [`crate::sampler::STRUCTURED_DIMS`] for where the structured
//! pattern hands over to independent numbers).

use crate::accel::Accel;
use crate::accel::Intersect;
use crate::camera::Camera;
use crate::emitter::Lights;
use crate::film::{Film, FilmTile, SplatFilm};
use crate::geometry::WorldShape;
use crate::image::{ChannelImage, RgbImage};
use crate::integrator::layers::Layered;
use crate::integrator::{CameraSample, Integrator, PathTracer};
use crate::sampler::{Pattern, Sampler};
use crate::scene::{IntegratorDesc, Scene};
use glam::{UVec2, Vec2};
use gonio_core::spectrum::VisibleWavelengthTable;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// The embedded default scene: a gallery of the lecture's materials (`gonio render` with no
/// arguments).
pub const DEFAULT_SCENE: &str = include_str!("default_scene.xml");

/// The embedded scenes by name (`gonio render --builtin NAME`): `gallery` (the default scene),
/// `lambertian` (the lecture's generalizations of Lambert: Oren–Nayar, diffuse microfacets,
/// Lambertian spheres, and single against multiple scattering on rough gold and glass) and
/// `lambertian-furnace` (the same models in white under a uniform sky, where every lossless one
/// vanishes; `-D ms=false` shows the single-scattering microfacet models instead).
pub const BUILTIN_SCENES: [(&str, &str); 3] = [
    ("gallery", DEFAULT_SCENE),
    ("lambertian", include_str!("scenes/lambertian.xml")),
    (
        "lambertian-furnace",
        include_str!("scenes/lambertian-furnace.xml"),
    ),
];

/// The embedded scene called `name` (see [`BUILTIN_SCENES`]).
pub fn builtin_scene(name: &str) -> Option<&'static str> {
    BUILTIN_SCENES.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

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
    /// The scene as read, except the vertex data of meshes nothing else shared: it has moved
    /// into the world-space shapes of [`PreparedScene::accel`], leaving their descriptions
    /// with empty meshes.
    pub scene: Scene,
    accel: Accel,
    lights: Lights,
    shape_material: Vec<usize>,
    /// The media on the two sides of each shape.
    shape_media: Vec<crate::medium::MediumInterface>,
    camera: Box<dyn Camera>,
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
    pub fn new(mut scene: Scene) -> Result<Self, RenderError> {
        let film = &scene.sensor.film;
        if film.width == 0 || film.height == 0 {
            return Err(RenderError::EmptyFilm {
                width: film.width,
                height: film.height,
            });
        }
        let mut world = Vec::with_capacity(scene.shapes.len());
        let mut shape_material = Vec::with_capacity(scene.shapes.len());
        let mut shape_media = Vec::with_capacity(scene.shapes.len());
        for (index, shape) in scene.shapes.iter_mut().enumerate() {
            let name = shape.id.clone().unwrap_or_else(|| format!("#{index}"));
            let mut w = WorldShape::from_scene_moving_mesh(shape, &name).map_err(|e| RenderError::Shape {
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
            // A sphere's uv costs two inverse trigonometric functions per hit: only where a
            // texture or an AOV reads it.
            w.uv = scene.materials[shape.material].is_textured()
                || shape.emitter.as_ref().is_some_and(|e| e.radiance.is_textured())
                || scene.integrator.layers.is_some();
            world.push(w);
            shape_material.push(shape.material);
            shape_media.push(shape.media);
        }
        let lights = Lights::from_scene(&scene, &world).map_err(|e| RenderError::Emitter {
            index: e.index,
            message: e.message,
        })?;
        let mut camera = crate::camera::from_sensor(&scene.sensor, &world, lights.bounds());
        if let Some(crop) = film.crop {
            let full_pixels = film.width as f32 * film.height as f32;
            camera = Box::new(CroppedCamera {
                full: camera,
                offset: Vec2::new(crop.offset.0 as f32, crop.offset.1 as f32),
                size: Vec2::new(crop.size.0 as f32, crop.size.1 as f32),
                area_ratio: full_pixels / (crop.size.0 as f32 * crop.size.1 as f32),
            });
        }
        let accel = Accel::new(world);
        Ok(Self {
            scene,
            accel,
            lights,
            shape_material,
            shape_media,
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

    /// The camera.
    pub fn camera(&self) -> &dyn Camera {
        self.camera.as_ref()
    }

    /// Size (width, height) of the rendered image: the film's, or its crop window's.
    pub fn size(&self) -> (u32, u32) {
        self.scene.sensor.film.image_size()
    }

    /// The scene's integrator (`path`, with its settings), over this scene. It renders
    /// polarized when the settings ask for it (`polarized`, `stokes`) or when the scene has a
    /// polarizing material ([`Scene::asks_for_polarization`]).
    pub fn integrator(&self) -> PathTracer<'_> {
        self.integrator_for(&self.scene.integrator)
    }

    /// The path tracer (`path`, `direct` or `depth`) with the settings `desc` over this scene,
    /// polarized as [`PreparedScene::integrator`] decides (used for the integrators nested in
    /// `aov` and `moment`).
    pub fn integrator_for(&self, desc: &IntegratorDesc) -> PathTracer<'_> {
        let mut settings = desc.clone();
        settings.polarized |= self.scene.asks_for_polarization();
        PathTracer::new(
            &settings,
            &self.accel,
            &self.lights,
            &self.scene.materials,
            &self.shape_material,
        )
        .with_camera_if_it_connects(self.camera.as_ref())
        .with_media(&self.scene.media, &self.shape_media, self.scene.sensor_medium)
        .with_sensor_up(self.scene.sensor.to_world.transform_vector3(glam::Vec3::Y))
        .with_response(self.scene.sensor.film.response.clone())
    }

    /// An empty film of the sensor's size and filter with an integrator's channels, and `A`
    /// after them when the film's `pixel_format` has alpha.
    pub fn film(&self, integrator: &(impl Integrator + ?Sized)) -> Film {
        let (width, height) = self.size();
        let mut channels = integrator.channels();
        if self.scene.sensor.film.output.pixel_format.has_alpha() {
            channels = channels.with_channel("A");
        }
        Film::with_channels(width, height, self.scene.sensor.film.filter, channels)
    }

    /// A camera sample's alpha, as Mitsuba defines it: 1 when the ray hits a surface or an
    /// environment emitter is visible behind everything (and not hidden), else 0.
    fn alpha(&self, ray: &crate::geometry::Ray) -> f32 {
        let sees_environment = !self.lights.infinite().is_empty() && !self.scene.integrator.hide_emitters;
        if sees_environment || self.accel.occluded(ray) {
            1.0
        } else {
            0.0
        }
    }
}

/// A camera seen through a crop window of its film (`hdrfilm`'s `crop_*`): film positions are
/// the window's, `offset` pixels from the full film's top-left corner.
#[derive(Debug)]
struct CroppedCamera {
    full: Box<dyn Camera>,
    offset: Vec2,
    size: Vec2,
    /// Full film area / window area: camera samples spread over the window only, so the density
    /// of a camera direction is this much higher than over the whole film.
    area_ratio: f32,
}

impl CroppedCamera {
    /// A connection of the full film seen through the window (`None` outside it).
    fn crop(&self, mut c: crate::camera::CameraConnection) -> Option<crate::camera::CameraConnection> {
        c.film -= self.offset;
        c.film_pdf *= self.area_ratio;
        let inside = c.film.x >= 0.0 && c.film.y >= 0.0 && c.film.x < self.size.x && c.film.y < self.size.y;
        inside.then_some(c)
    }
}

impl Camera for CroppedCamera {
    fn generate_ray(&self, film: Vec2) -> crate::geometry::Ray {
        self.full.generate_ray(film + self.offset)
    }

    fn project(&self, p: glam::Vec3) -> Option<Vec2> {
        self.full.project(p).map(|f| f - self.offset)
    }

    fn position(&self) -> glam::Vec3 {
        self.full.position()
    }

    fn connect(&self, p: glam::Vec3) -> Option<crate::camera::CameraConnection> {
        self.crop(self.full.connect(p)?)
    }

    fn connect_lens(&self, p: glam::Vec3, u_lens: Vec2) -> Option<crate::camera::CameraConnection> {
        self.crop(self.full.connect_lens(p, u_lens)?)
    }

    fn connects(&self) -> bool {
        self.full.connects()
    }

    fn needs_lens_sample(&self) -> bool {
        self.full.needs_lens_sample()
    }

    fn generate_ray_lens(&self, film: Vec2, u_lens: Vec2) -> crate::geometry::Ray {
        self.full.generate_ray_lens(film + self.offset, u_lens)
    }

    fn needs_ray_samples(&self) -> bool {
        self.full.needs_ray_samples()
    }

    fn generate_ray_sampled(&self, film: Vec2, u_pos: Vec2, u_dir: Vec2) -> (crate::geometry::Ray, f32) {
        self.full.generate_ray_sampled(film + self.offset, u_pos, u_dir)
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
    /// Linear sRGB image (the channels `R`, `G`, `B`).
    pub image: RgbImage,
    /// Every channel the integrator wrote, by name (the same `R`, `G`, `B` values as `image`).
    pub channels: ChannelImage,
    /// Samples per pixel every pixel received (the requested count unless cancelled).
    pub complete_spp: u32,
    /// True when the cancellation flag stopped the render early.
    pub cancelled: bool,
}

/// Renders the scene with its own integrator (`path`, `direct`, `depth`, or the `aov` and
/// `moment` wrappers of [`Layered`] around them). `progress(done, total)` counts samples;
/// `cancel` stops early.
pub fn render(
    prepared: &PreparedScene,
    options: &RenderOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> RenderOutput {
    match &prepared.scene.integrator.layers {
        None => render_with(prepared, &prepared.integrator(), options, progress, cancel),
        Some(layers) => {
            let layered = Layered::new(prepared, layers, options.spp);
            render_with(prepared, &layered, options, progress, cancel)
        }
    }
}

/// Renders the scene with `integrator`. `progress(done, total)` counts samples; `cancel` stops
/// early.
pub fn render_with<I: Integrator + ?Sized>(
    prepared: &PreparedScene,
    integrator: &I,
    options: &RenderOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> RenderOutput {
    let (width, height) = prepared.size();
    let crop_offset = prepared
        .scene
        .sensor
        .film
        .crop
        .map_or(UVec2::ZERO, |c| UVec2::new(c.offset.0, c.offset.1));
    let crop_shift = Vec2::new(crop_offset.x as f32, crop_offset.y as f32);
    let spp = options.spp.max(1);
    let mut film = prepared.film(integrator);
    let n_channels = film.channels().len();
    // The film's alpha channel, if any, comes after the integrator's.
    let n_integrator = integrator.channels().len();
    let with_alpha = n_channels > n_integrator;
    // What the integrator splats anywhere on the film (light tracing), one slot per camera
    // sample: splats arrive divided by their total (the light tracer estimates the image with
    // N = spp·pixels subpaths).
    let splats = integrator
        .splats()
        .then(|| SplatFilm::with_channels(width, height, prepared.scene.sensor.film.filter, n_channels));
    let light_paths = AtomicU64::new(0);
    let blocks: Vec<(UVec2, UVec2)> = film.tiles(TILE).iter().map(|t| t.block()).collect();
    // `sample_border`: the pixels within the filter's reach outside the image are sampled too
    // (by the tiles at the image's edges), their samples reaching the edge pixels through the
    // filter, as in Mitsuba's `SamplingIntegrator::render`.
    let border = if prepared.scene.sensor.film.sample_border {
        film.border() as i64
    } else {
        0
    };
    let sampled = |lo: u32, hi: u32, size: u32| -> (i64, i64) {
        (
            if lo == 0 { -border } else { lo as i64 },
            if hi == size { hi as i64 + border } else { hi as i64 },
        )
    };
    let total = (width as i64 + 2 * border) as u64 * (height as i64 + 2 * border) as u64 * spp as u64;
    let inv_light_paths = 1.0 / total as f32;
    let done = AtomicU64::new(0);
    let mut complete_spp = 0;
    // The wavelengths: the visible density for a colour film, the bands' for a spectral one
    // (or the sensor's response function's).
    let visible = VisibleWavelengthTable::get();
    let bands = prepared.scene.sensor.film.response.wavelength_bands();
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
                // Pixels share nets where the filter shares samples (`Sampler::z_ordered`).
                let mut sampler =
                    Sampler::new(options.pattern, spp, options.seed).z_ordered(film.border() > 0);
                let mut value = vec![0.0f32; n_channels];
                let mut scaled = vec![0.0f32; n_channels];
                let mut splat = |p: Vec2, v: &[f32]| {
                    if let Some(splats) = &splats {
                        for (s, &x) in scaled.iter_mut().zip(v) {
                            *s = x * inv_light_paths;
                        }
                        splats.splat(p, &scaled);
                    }
                };
                let (y0, y1) = sampled(lo.y, hi.y, height);
                let (x0, x1) = sampled(lo.x, hi.x, width);
                for py in y0..y1 {
                    for px in x0..x1 {
                        for s in start..start + count {
                            // Keyed by the full film's pixel: a crop window renders exactly
                            // those pixels of the full image (light paths aside). The film
                            // position is the window's, computed from the full film's (exact:
                            // the cropped camera adds the offset back bit for bit). A border
                            // pixel left of or above the film is keyed by its coordinate
                            // wrapped to 32 bits.
                            let (fx, fy) = (px + crop_offset.x as i64, py + crop_offset.y as i64);
                            sampler.start_pixel_sample(UVec2::new(fx as u32, fy as u32), s);
                            let film_pos = Vec2::new(fx as f32, fy as f32) + sampler.next_2d() - crop_shift;
                            let u_lambda = sampler.next_1d();
                            let wl = bands.map_or_else(|| visible.sample(u_lambda), |b| b.sample(u_lambda));
                            let (ray, ray_weight) = if prepared.camera.needs_ray_samples() {
                                let u_pos = sampler.next_2d();
                                prepared
                                    .camera
                                    .generate_ray_sampled(film_pos, u_pos, sampler.next_2d())
                            } else if prepared.camera.needs_lens_sample() {
                                (
                                    prepared.camera.generate_ray_lens(film_pos, sampler.next_2d()),
                                    1.0,
                                )
                            } else {
                                (prepared.camera.generate_ray(film_pos), 1.0)
                            };
                            let mut sample = CameraSample {
                                film: film_pos,
                                ray,
                                wavelengths: wl,
                                sampler: sampler.padded(),
                            };
                            integrator.sample(&mut sample, &mut value[..n_integrator], &mut splat);
                            if ray_weight != 1.0 {
                                for v in &mut value[..n_integrator] {
                                    *v *= ray_weight;
                                }
                            }
                            if with_alpha {
                                value[n_integrator] = prepared.alpha(&ray);
                            }
                            tile.add_sample(film_pos, &value);
                        }
                    }
                }
                let n = ((x1 - x0) * (y1 - y0)) as u64 * count as u64;
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

    let mut channels = film.to_channels();
    let traced = light_paths.load(Ordering::Relaxed);
    if let Some(splats) = &splats
        && traced > 0
    {
        // A cancelled render traced fewer.
        splats.add_to_channels(&mut channels, total as f64 / traced as f64);
    }
    RenderOutput {
        image: channels.rgb(),
        channels,
        complete_spp,
        cancelled,
    }
}
