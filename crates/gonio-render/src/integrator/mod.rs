//! Integrators: the [`Integrator`] trait the render loop calls once per camera sample, and the
//! `path` integrator ([`PathTracer`]): a unidirectional spectral path tracer with next-event
//! estimation and multiple importance sampling, after Mitsuba 3's `path`
//! (`src/integrators/path.cpp`).
//!
//! # The `Integrator` trait
//!
//! The render loop ([`crate::render`]) places a sample on the film, draws its wavelengths and
//! generates the camera ray; the integrator gets that [`CameraSample`] with the rest of the
//! sample's random numbers and writes the sample's value, one number per film channel
//! ([`Integrator::channels`]), and may splat contributions anywhere on the film
//! ([`Integrator::splats`]). What future integrators need of it:
//!
//! * `direct` (Mitsuba's direct-illumination integrator): the same as `path` with one bounce;
//!   channels `R`, `G`, `B`.
//! * `aov` ([`layers`]): nested integrators' images as layers `name.R` … `name.A`, and values
//!   read at the first hit (`depth.T`, `nn.X`, ...).
//! * `moment` ([`layers`]): nested integrators' values in XYZ and their squares (`p.X`,
//!   `m2_p.X`, ...), so the film gives the per-pixel variance.
//! * `ptracer` (light tracing): splats every light-path vertex's connection to the camera
//!   ([`crate::camera::Camera::connect`]) and writes nothing in place; the loop divides splats by
//!   the number of camera samples, which is the number of light paths.
//! * `stokes` (polarization): four spectral values S0..S3, each turned into colour by the same
//!   wavelength estimator, in channels `S0.R` … `S3.B`.
//!
//! # The `path` integrator
//!
//! For a camera ray carrying four wavelengths (hero + three rotated, [`SampledWavelengths`]):
//!
//! 1. **Emission.** A hit on an area light (or an escaped ray, for the lights at infinity) adds
//!    β·Lₑ·w. After the camera or a delta lobe w = 1; after a smooth lobe w is the power heuristic
//!    (β = 2) between the BSDF density and the light density (selection probability × the
//!    light's solid-angle density from the previous vertex). `hide_emitters` drops what the
//!    camera sees directly.
//! 2. **Next-event estimation**, only when the BSDF has a smooth (diffuse or glossy) lobe: pick a
//!    light (or each light, `split_lights`) and draw a direction on it
//!    ([`Lights::for_each_sample`]; each light kind has its own
//!    policy, e.g. [`crate::emitter::area`]), add β·f·|cos|·Lᵢ·T/(p_sel·p_dir)·w, with w the
//!    power heuristic against the BSDF density (w = 1 for delta lights). T is the visibility: 0 or 1, or, with
//!    `thin_shadows`, the product of the straight-through transmittances
//!    ([`gonio_core::Bsdf::null_transmission`]) of the `thindielectric` sheets crossed.
//! 3. **BSDF sampling**: β ← β·weight, η_path ← η_path·η (the relative index crossed). A
//!    dispersive refraction terminates the secondary wavelengths inside the BSDF; the estimator
//!    that turns the result into colour divides by the pdfs, so nothing else changes here.
//! 4. **Russian roulette** from `rr_depth` on: continue with q = min(s·max(β)·η_path², q_max),
//!    then β ← β/q. The η² undoes the radiance compression of refraction, so a path inside glass
//!    is not killed more often than outside it. `q_max` is `rr_survival` (ours, 0.99; Mitsuba's
//!    fixed 0.95): where β stays near 1 for many bounces (light trapped in glass by total
//!    internal reflection, a white furnace) a path that survives n capped roulettes carries
//!    q_max⁻ⁿ, and at 0.95 the rare survivors of 50 bounces are fireflies 13× too bright
//!    (`tests/russian_roulette.rs`). `s` is `rr_scale` (ours, 4; Mitsuba's and pbrt-v4's
//!    rule is s = 1). Roulette trades variance for time: a path killed with probability 1 − q
//!    adds (1/q − 1)·E\[F²\] to the variance of its future contribution F and saves (1 − q) of its
//!    cost, so q should follow F relative to the pixel's value (Vorba and Křivánek 2016's
//!    adjoint-driven roulette), and s = 1 assumes F is of the order of the pixel. But a pixel's
//!    value is its first surface's albedo times the light arriving there, and with albedos of
//!    ¼ to ½ the light a path still gathers is 2–4 times the pixel's: s = 4 continues every path
//!    whose throughput is above ¼. Measured on the bench scenes (64 spp against 16384-spp
//!    references): relMSE −23 % to −45 % at +0–7 % time where surfaces are dark or glass traps
//!    light; the `roughplastic` preview's image barely changes.
//!
//! `max_depth` counts path segments as Mitsuba does: −1 = unbounded, 0 = black, 1 = only emitters
//! seen directly, 2 = direct lighting.
//!
//! # Thin sheets (beyond Mitsuba)
//!
//! With `thin_shadows` (the default), a BSDF sample that passes straight through a sheet (a
//! `NULL` transmission) is transparent to the bookkeeping: the depth, the MIS state (previous
//! vertex and BSDF density) and Russian roulette are those of the last real scattering event.
//! Shadow rays cross the same sheets attenuated by the same transmittance, so the two strategies
//! estimate the same integral and MIS stays unbiased; so a sheet met by the last segment
//! `max_depth` allows is crossed too (its straight transmittance taken whole), or the light
//! beyond it, which next-event estimation from the vertex before counted on this strategy
//! for, would be lost. With `thin_shadows = false` a null
//! transmission is an ordinary delta event and sheets block shadow rays: Mitsuba's exact
//! behaviour (the light behind a window then arrives only through BSDF sampling).
//!
//! # Refracted next-event estimation (beyond Mitsuba)
//!
//! With `refracted_nee` (the default), a light sample whose shadow ray meets smooth glass is
//! followed through it, refracting, and counts if it still reaches the light it was drawn on;
//! the path tracer, the light subpaths below and this strategy share such paths by MIS
//! (`integrator/refracted.rs`). Without it, glass blocks shadow rays as in Mitsuba.
//!
//! # Manifold next-event estimation (beyond Mitsuba)
//!
//! With `manifold_nee` (the default), a vertex whose camera-side neighbour is delta also joins a
//! point drawn on an area light through the one point of a mirror sphere that reflects it there
//! (`integrator/manifold.rs`); the path tracer evaluates that strategy's density for the same
//! paths and the two share them by the power heuristic.
//!
//! # Resampled next-event estimation (beyond Mitsuba)
//!
//! With `ris_candidates` (default 8), at a single-scattering `roughconductor` of narrow lobe in a
//! scene with one `envmap`, the map's light sample is replaced by one direction resampled from
//! that many candidates drawn from the lobe (Talbot et al. 2005), weighed by the lobe times a
//! coarse table of the map; it alone adds the map's direct light there, so the BSDF sample
//! from that vertex adds none of the map's when it escapes (`integrator/resampled.rs`).
//!
//! # Caustic light paths (beyond Mitsuba)
//!
//! With `caustic_paths` (the default; active when the scene has an area light and a delta lobe),
//! each camera sample also traces a light subpath through delta chains ([`caustics`]), whose
//! smooth vertices are connected to the camera (splatted) and to every smooth vertex of this
//! path. The paths both can produce (an area light reached through a delta chain) are weighted
//! by the power heuristic between the two; see that module for the densities.
//!
//! # Polarization
//!
//! In polarized mode (a `stokes` integrator, a polarizing BSDF, `gonio render --polarized`) the
//! same estimators run with Mueller matrices ([`polarized`]): every BSDF weight is mapped to
//! world space in the implicit bases of its beams, and the camera reads S0 (and, for `stokes`,
//! S0..S3). The caustic light subpaths carry Mueller matrices as well (importance mode, light
//! order).
//!
//! # Shading normals
//!
//! BSDFs are evaluated in the shading frame (interpolated normals), as in Mitsuba; rays leave
//! from the side of the geometric normal that their direction points to.

pub mod caustics;
mod direct;
pub mod layers;
mod lobe_split;
mod manifold;
mod nee;
mod path_state;
pub mod polarized;
mod ptracer;
mod record;
mod refracted;
mod resampled;
mod scatter;
pub use resampled::MAX_CANDIDATES as MAX_RIS_CANDIDATES;
mod volpath;

use path_state::{PathState, PrevVertex, StepFrom};

use crate::accel::{Accel, Intersect};
use crate::camera::Camera;
use crate::emitter::{LightRef, Lights};
use crate::film::Channels;
use crate::geometry::{Ray, SurfaceInteraction};
use crate::material::{Material, ShadingPoint};
pub use crate::sampler::PathSampler;
use crate::sampler::{PaddedSampler, Pcg32};
use crate::scene::{IntegratorDesc, IntegratorKind};
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::sensor_response::SensorResponse;
use gonio_core::weight::{BsdfWeight, Weight};
use gonio_core::{BsdfFlags, BsdfSample, SampledSpectrum, SampledWavelengths};

/// One camera sample, as the render loop hands it to an [`Integrator`].
#[derive(Debug)]
pub struct CameraSample<'s> {
    /// Film position (pixels).
    pub film: Vec2,
    /// The camera ray through `film`.
    pub ray: Ray,
    /// The sample's wavelengths (a dispersive refraction may terminate the secondary ones).
    pub wavelengths: SampledWavelengths,
    /// The rest of the sample's random numbers (its key, [`PaddedSampler::key`], seeds any
    /// independent stream the integrator needs, such as a light path's).
    pub sampler: PaddedSampler<'s>,
}

/// A light-transport algorithm, called by the render loop once per camera sample (see the
/// module documentation for what each planned integrator needs of it).
///
/// Every sample must be a pure function of the [`CameraSample`] (its random numbers included):
/// the loop relies on that for images that do not depend on the thread count.
pub trait Integrator: Sync {
    /// The film channels a sample writes, in order (EXR names: `R`, `G`, `B`, `layer.R`...).
    fn channels(&self) -> Channels;

    /// True when [`Integrator::sample`] splats (light tracing): the loop then keeps a splat film
    /// with the same channels.
    fn splats(&self) -> bool {
        false
    }

    /// Evaluates one camera sample: writes its value, one number per channel, into `value`, and
    /// hands contributions that land elsewhere on the film to `splat` as (film position, one
    /// number per channel); the loop sums splats and divides them by the number of camera
    /// samples.
    fn sample(&self, sample: &mut CameraSample<'_>, value: &mut [f32], splat: &mut dyn FnMut(Vec2, &[f32]));
}

/// Power heuristic with exponent `beta` (≥ 1) for two strategies with densities `a` (the one
/// used) and `b`: aᵝ/(aᵝ + bᵝ), computed from the ratio b/a so that neither power overflows
/// or underflows; 0 where only `b` can produce the sample (a = 0, or b infinite), 1 where only
/// `a` can (b = 0, or a infinite).
#[inline]
pub fn mis_power(a: f32, b: f32, beta: f32) -> f32 {
    if !a.is_finite() {
        return 1.0;
    }
    if !(a > 0.0) {
        return 0.0;
    }
    let t = b / a;
    // The default exponent and Mitsuba's without `powf`.
    let tb = if beta == 1.25 {
        t * t.sqrt().sqrt()
    } else if beta == 2.0 {
        t * t
    } else {
        t.powf(beta)
    };
    if tb.is_nan() { 0.0 } else { 1.0 / (1.0 + tb) }
}

/// Largest number of sheets one segment of a path, or a shadow ray, crosses before giving up (a
/// bound against stacks of coincident sheets). Per segment, not per path: a path through
/// foliage of masked leaves may cross many over its bounces.
const MAX_NULL_CROSSINGS: u32 = 64;

/// Mixed into a sample's key to seed its light path's random numbers.
const LIGHT_PATH_KEY: u64 = 0x6c69_6768_745f_7061;

/// Everything the path tracer reads: the scene's materials, the accelerator and the lights.
pub struct PathTracer<'a> {
    accel: &'a Accel,
    lights: &'a Lights,
    materials: &'a [Material],
    /// Material index of each shape.
    shape_material: &'a [usize],
    /// Per material: true when its BSDF can pass light straight through (`thindielectric`).
    thin: Vec<bool>,
    any_thin: bool,
    /// Per material: a refractor ([`refracted`]).
    refractor: Vec<bool>,
    /// Per light: refracted next-event estimation may end on it.
    refracted_light: Vec<bool>,
    /// Next-event estimation through refraction ([`refracted`]) takes part.
    refracted_nee: bool,
    /// Glass and plastic split their lobes where one leaves the scene or meets an area light
    /// ([`lobe_split`]).
    split_escapes: bool,
    /// The first surface the camera sees, if smooth glass, has both its lobes followed
    /// ([`PathTracer::visible_glass_split`]).
    split_visible_glass: bool,
    /// Lights at infinity without features as narrow as a rough lobe are left to BSDF sampling
    /// there ([`crate::emitter::Lights::left_to_bsdf`]).
    narrow_lobes: bool,
    /// Candidates of resampled next-event estimation where it applies ([`resampled`]; 0: off).
    ris_candidates: u32,
    /// Exponent of the power heuristic between next-event estimation and BSDF sampling
    /// ([`PathTracer::mis`]).
    mis_exponent: f32,
    /// The area lights' shapes, for the glints of lobe splitting ([`lobe_split`]).
    light_shapes: Option<lobe_split::LightShapes>,
    /// Manifold next-event estimation through mirror spheres ([`manifold`]), where it takes part.
    manifold: Option<manifold::Setup>,
    max_depth: u32,
    rr_depth: u32,
    /// Highest probability of continuing a path at Russian roulette (`rr_survival`).
    rr_survival: f32,
    /// The factor of the throughput in Russian roulette's probability (`rr_scale`).
    rr_scale: f32,
    hide_emitters: bool,
    thin_shadows: bool,
    /// Light tracing of the caustics, when enabled and useful.
    caustics: Option<caustics::EmissionSampler>,
    /// The camera light paths connect to (light tracing needs it).
    camera: Option<&'a dyn Camera>,
    /// `path`, or `direct` and `depth` ([`direct`]), which reuse its light sampling and MIS.
    kind: IntegratorKind,
    /// Paths carry Mueller matrices ([`polarized`]).
    polarized: bool,
    /// Also write the Stokes vector (Mitsuba's `stokes` integrator) as the layers `S0` … `S3`.
    stokes: bool,
    /// The sensor's up direction in world space: the Stokes vectors' x-axis is d × up.
    sensor_up: Vec3,
    /// What the film records of a path's radiance: linear sRGB or spectral bands.
    response: SensorResponse,
    /// The integrator is volumetric (`volpath`): media take part where the scene has them.
    volumetric: bool,
    /// The scene's participating media, when they take part ([`volpath`]).
    media: Option<volpath::Media<'a>>,
}

/// A camera-path vertex while its BSDF exists.
struct Vertex<'v> {
    bsdf: &'v SurfaceBsdf<'v>,
    si: &'v SurfaceInteraction,
    /// Direction back along the path, in the shading frame.
    wi: Vec3,
}

/// What happened at one surface vertex (computed while the per-hit BSDF exists).
struct VertexOutcome<W: Weight> {
    /// Next-event estimation and light-subpath connections, throughput included.
    nee: W,
    light_ref: LightRef,
    /// Manifold next-event estimation took part here ([`manifold`]).
    manifold_here: bool,
    /// Where the path goes next.
    step: Step<W>,
}

/// The continuation a vertex drew.
enum Step<W: Weight> {
    /// One BSDF sample (`None`: the path ends) and the light tracer's density of its reverse
    /// (when asked for).
    Sampled {
        sample: Option<BsdfSample<W>>,
        reverse_pdf: f32,
    },
    /// Both lobes of glass or plastic ([`lobe_split`]).
    Split(lobe_split::LobePair<W>),
}

impl<'a> PathTracer<'a> {
    /// A path tracer over prepared scene data. `shape_material[i]` is the material of shape `i`
    /// of the accelerator.
    pub fn new(
        settings: &IntegratorDesc,
        accel: &'a Accel,
        lights: &'a Lights,
        materials: &'a [Material],
        shape_material: &'a [usize],
    ) -> Self {
        let thin: Vec<bool> = materials.iter().map(Material::has_null_transmission).collect();
        let any_thin = thin.iter().any(|&t| t);
        // `ptracer`'s light paths are spectral.
        let polarized = (settings.polarized || settings.stokes) && settings.kind != IntegratorKind::PTracer;
        // In polarized mode the light subpaths carry Mueller matrices ([`polarized`]).
        let caustics = if settings.caustic_paths {
            caustics::EmissionSampler::new(lights, materials, shape_material, accel.shapes())
        } else {
            None
        };
        let refractor = refracted::refractors(materials);
        let mut tracer = Self {
            accel,
            lights,
            materials,
            shape_material,
            thin,
            any_thin,
            refractor,
            refracted_light: Vec::new(),
            refracted_nee: false,
            split_escapes: settings.split_escapes,
            // Spectral renders only (the split lobes' weights are spectra).
            split_visible_glass: settings.split_visible_glass && !polarized,
            narrow_lobes: settings.narrow_lobes,
            // The path tracer's spectral renders only (the estimator is the path tracer's
            // strategy, [`resampled`]).
            ris_candidates: if settings.kind == IntegratorKind::Path && !polarized {
                settings.ris_candidates
            } else {
                0
            },
            mis_exponent: settings.mis_exponent,
            light_shapes: if settings.split_escapes {
                lobe_split::LightShapes::new(lights, accel.shapes())
            } else {
                None
            },
            manifold: None,
            max_depth: if settings.max_depth < 0 {
                u32::MAX
            } else {
                settings.max_depth as u32
            },
            rr_depth: settings.rr_depth,
            rr_survival: settings.rr_survival,
            rr_scale: settings.rr_scale,
            hide_emitters: settings.hide_emitters,
            thin_shadows: settings.thin_shadows,
            caustics,
            camera: None,
            kind: settings.kind,
            polarized,
            stokes: settings.stokes,
            sensor_up: Vec3::Y,
            response: SensorResponse::Srgb,
            volumetric: settings.volumetric,
            media: None,
        };
        tracer.refracted_light = tracer.refracted_lights();
        tracer.refracted_nee = settings.refracted_nee
            && settings.kind == IntegratorKind::Path
            && tracer.refractor.iter().any(|&r| r)
            && tracer.refracted_light.iter().any(|&l| l);
        if settings.manifold_nee && settings.kind == IntegratorKind::Path && !polarized && !any_thin {
            tracer.manifold = manifold::Setup::new(&tracer);
        }
        tracer.prepare_resampling(materials);
        tracer
    }

    /// The camera, which enables light tracing of caustics (when the settings ask for it and the
    /// scene has an area light and a delta lobe).
    pub fn with_camera(mut self, camera: &'a dyn Camera) -> Self {
        self.camera = Some(camera);
        self
    }

    /// [`PathTracer::with_camera`] when the camera can join points to its film
    /// ([`Camera::connects`]); otherwise no light tracing.
    pub fn with_camera_if_it_connects(self, camera: &'a dyn Camera) -> Self {
        if camera.connects() || self.kind == IntegratorKind::PTracer {
            self.with_camera(camera)
        } else {
            self
        }
    }

    /// The sensor's up direction in world space (its +y axis), which orients the Stokes vectors
    /// of the `stokes` layers as Mitsuba does (x-axis d × up for a camera ray d).
    pub fn with_sensor_up(mut self, up: Vec3) -> Self {
        self.sensor_up = up;
        self
    }

    /// The scene's participating media, the media each shape separates and the sensor's
    /// medium: a volumetric integrator (`volpath`) then renders with them (the module
    /// `integrator/volpath.rs`); other integrators ignore media, as Mitsuba's do.
    pub fn with_media(
        mut self,
        media: &'a [crate::medium::Medium],
        shape_media: &'a [crate::medium::MediumInterface],
        sensor_medium: Option<crate::medium::MediumId>,
    ) -> Self {
        let any = sensor_medium.is_some() || shape_media.iter().any(|m| m.is_transition());
        if self.volumetric && any && self.kind == IntegratorKind::Path && !self.polarized {
            self.media = Some(volpath::Media {
                media,
                shape_media,
                sensor_medium,
            });
            // Mitsuba's estimator: the path tracer's own strategies do not see the media.
            self.caustics = None;
        }
        self
    }

    /// True when paths carry Mueller matrices (the scene's `polarized`, or `stokes`).
    pub fn is_polarized(&self) -> bool {
        self.polarized
    }

    /// True when light subpaths ([`PathTracer::trace_light_path`]) take part: each camera sample
    /// then traces one and passes it to [`PathTracer::li`].
    pub fn traces_caustics(&self) -> bool {
        self.caustics.is_some() && self.camera.is_some()
    }

    fn material_of(&self, shape: u32) -> Option<&'a Material> {
        self.shape_material
            .get(shape as usize)
            .and_then(|&m| self.materials.get(m))
    }

    /// Calls `f` with the BSDF of shape `shape`'s material at the hit `at` (`None` when the
    /// shape has no material).
    #[inline]
    fn bsdf_at<R>(
        &self,
        shape: u32,
        at: &ShadingPoint,
        wl: &SampledWavelengths,
        f: impl FnOnce(&SurfaceBsdf<'_>) -> R,
    ) -> Option<R> {
        Some(f(&self.material_of(shape)?.bsdf_at_point(at, wl)))
    }

    /// The weight of a sample drawn with density `a` against a second strategy of density `b`:
    /// the power heuristic with the integrator's exponent (`mis_exponent`). Next-event estimation
    /// and BSDF sampling, and manifold next-event estimation against the path tracer, weigh
    /// their samples by it; three-way shares ([`refracted::shares`]) keep the exponent 2.
    #[inline]
    pub(crate) fn mis(&self, a: f32, b: f32) -> f32 {
        mis_power(a, b, self.mis_exponent)
    }

    fn is_thin(&self, shape: u32) -> bool {
        self.shape_material
            .get(shape as usize)
            .and_then(|&m| self.thin.get(m))
            .copied()
            .unwrap_or(false)
    }

    /// Radiance arriving along `ray` at the wavelengths `wl` (which a dispersive refraction may
    /// reduce to the hero wavelength). `light` is the light subpath traced for this camera sample
    /// by [`PathTracer::trace_light_path`] with the same wavelengths (empty when
    /// [`PathTracer::traces_caustics`] is false).
    ///
    /// Generic over the [`Weight`] the path carries (`SampledSpectrum` for the spectral
    /// renderer, `Mueller` in polarized mode: see [`polarized`]); the light subpath carries `L`
    /// (the same Mueller matrices in polarized mode; a spectral subpath enters any path
    /// depolarized, [`caustics::LightWeight`]).
    pub fn li<W: Weight, L: caustics::LightWeight<W>>(
        &self,
        ray: Ray,
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
        light: &caustics::LightSubpath<L>,
    ) -> W
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        if self.max_depth == 0 {
            // Mitsuba: max_depth 0 renders nothing, not even emitters.
            return W::ZERO;
        }
        let mut l = W::ZERO;
        let mut bsdf = SurfaceBsdf::new();
        self.trace(ray, PathState::<W>::CAMERA, sampler, wl, light, &mut bsdf, &mut l);
        if l.intensity().is_finite() { l } else { W::ZERO }
    }

    /// The path loop of [`Self::li`] from `ray` with `state`, adding what it finds to `l`;
    /// `bsdf` is the path's one BSDF buffer, refilled at each vertex.
    #[allow(clippy::too_many_arguments)]
    fn trace<'s, W: Weight, L: caustics::LightWeight<W>>(
        &'s self,
        mut ray: Ray,
        mut state: PathState<W>,
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
        light: &caustics::LightSubpath<L>,
        bsdf: &mut SurfaceBsdf<'s>,
        l: &mut W,
    ) where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        // The hit of `ray` when a lobe split traced it already, and whether the split added
        // its emission.
        let mut traced: Option<SurfaceInteraction> = None;
        let mut emission_added = false;
        loop {
            let hit = match traced.take() {
                Some(si) => Some(si),
                None => self.accel.intersect(&ray),
            };
            let show = !(self.hide_emitters && state.depth == 0);
            let Some(si) = hit else {
                if show {
                    self.add_escaped(l, &state, ray.d, wl);
                }
                break;
            };
            // A lobe split added this hit's emission already (`lobe_split`).
            let counted = std::mem::take(&mut emission_added);
            if show && !counted {
                self.add_emitted(l, &state, &si, ray.d, wl);
            }
            if state.depth.saturating_add(1) >= self.max_depth {
                // At the last segment, a sheet (`thin_shadows`) is still crossed straight, its
                // transmittance taken whole: the pass is no segment, and next-event estimation
                // from the previous vertex counted on this strategy for the light beyond it.
                if self.thin_shadows
                    && self.is_thin(si.shape)
                    && let Some((t, Some(next))) = self.pass_sheet::<W>(&si, &ray, ray.d, wl, false)
                    && state.cross_sheet(t)
                {
                    ray = next;
                    continue;
                }
                break;
            }

            let wi_world = -ray.d;
            // How this point was reached, for the MIS weight against light-subpath connections.
            let arrival = Self::arrival(
                state.prev.as_ref().map(|p| (p.light_ref.p, p.bsdf_pdf, p.delta)),
                &si,
                ray.d,
            );
            // The path's one BSDF buffer, refilled at each vertex (no per-hit initialization).
            let Some(material) = self.material_of(si.shape) else {
                break;
            };
            material.fill_bsdf_at(&ShadingPoint::from(&si), wl, bsdf);
            let v = Vertex {
                bsdf,
                si: &si,
                wi: si.shading.to_local(wi_world),
            };
            let cos_in = si.n.dot(wi_world).abs();
            // The glass the camera sees: both lobes followed, each by a loop of its own (whose
            // depth or sheet count is then past 0: no second split).
            if self.split_visible_glass
                && state.depth == 0
                && state.null_crossings == 0
                && let Some(starts) = self.visible_glass_split(&v, &state, (arrival, cos_in), sampler, wl)
            {
                // Both paths take the same numbers: each is the coin path's with its lobe.
                let mark = sampler.mark();
                for (ray, state) in starts.into_iter().flatten() {
                    sampler.rewind(mark);
                    self.trace(ray, state, sampler, wl, light, bsdf, l);
                }
                break;
            }
            let outcome = self.scatter(&v, &state, arrival, light, sampler, wl);
            *l += outcome.nee;

            let from = StepFrom {
                light_ref: outcome.light_ref,
                manifold_here: outcome.manifold_here,
                arrival,
                cos_in,
            };
            let (bs, reverse_pdf) = match outcome.step {
                Step::Split(pair) => {
                    let followed = self.follow_pair(pair, &v, &state, &from, l, wl);
                    let Some(f) = followed else { break };
                    traced = Some(f.hit);
                    emission_added = f.emitted;
                    (f.sample, f.reverse_pdf)
                }
                Step::Sampled {
                    sample: Some(bs),
                    reverse_pdf,
                } => (bs, reverse_pdf),
                Step::Sampled { sample: None, .. } => break,
            };
            let dir = si.shading.to_world(bs.wo);
            ray = si.spawn_ray(dir);

            if self.thin_shadows && bs.flags.contains(BsdfFlags::NULL) {
                // Straight through a sheet: keep the previous vertex's MIS state and depth.
                if !state.cross_sheet(bs.weight) {
                    break;
                }
                continue;
            }

            self.advance(&mut state, &bs, &v, &ray, &from, reverse_pdf);
            if !self.russian_roulette(&mut state, sampler) {
                break;
            }
        }
    }
}

/// The `path` integrator: channels `R`, `G`, `B` (linear sRGB through the wavelength estimator
/// [`gonio_core::color::linear_srgb_from_sampled`]) or a spectral film's bands
/// ([`SensorResponse`]); with caustic light paths it splats their connections to the camera.
impl Integrator for PathTracer<'_> {
    fn channels(&self) -> Channels {
        if self.stokes {
            polarized::stokes_channels(&self.response)
        } else {
            Channels::for_response(&self.response)
        }
    }

    fn splats(&self) -> bool {
        self.traces_caustics() || self.kind == IntegratorKind::PTracer
    }

    fn sample(&self, sample: &mut CameraSample<'_>, value: &mut [f32], splat: &mut dyn FnMut(Vec2, &[f32])) {
        if self.polarized {
            self.sample_polarized(sample, value, splat);
            return;
        }
        match self.kind {
            IntegratorKind::Path => {}
            IntegratorKind::Direct {
                emitter_samples,
                bsdf_samples,
            } => {
                let l = self.li_direct(sample, emitter_samples, bsdf_samples);
                self.record(l, &sample.wavelengths, value);
                return;
            }
            IntegratorKind::Depth => {
                let l = SampledSpectrum::splat(self.depth(&sample.ray));
                self.record(l, &sample.wavelengths, value);
                return;
            }
            IntegratorKind::PTracer => {
                value.fill(0.0);
                return self.sample_ptracer(sample, splat);
            }
        }
        if let Some(media) = &self.media {
            let l = self.li_volumetric(media, sample.ray, &mut sample.sampler, &mut sample.wavelengths);
            self.record(l, &sample.wavelengths, value);
            return;
        }
        let mut light = caustics::LightSubpath::new();
        if self.traces_caustics() {
            // The light subpath first: it shares the wavelengths (and may terminate the
            // secondary ones). Its random numbers are an independent stream keyed by the sample.
            let key = sample.sampler.key();
            let mut rng = Pcg32::new(key ^ LIGHT_PATH_KEY, key.rotate_left(29));
            let mut to_film =
                |p: Vec2, v: SampledSpectrum, wl: &SampledWavelengths| self.splat_radiance(splat, p, v, wl);
            self.trace_light_path(&mut rng, &mut sample.wavelengths, &mut to_film, &mut light);
        }
        let l: SampledSpectrum = self.li(sample.ray, &mut sample.sampler, &mut sample.wavelengths, &light);
        self.record(l, &sample.wavelengths, value);
    }
}
