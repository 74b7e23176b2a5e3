//! Emitters: area and directional-area lights on shapes, point, spot, directional, constant,
//! envmap and sunsky, and the choice of one light per next-event estimate, with probability proportional
//! to power.
//!
//! Every light answers the same questions (see [`Light`]): draw a direction towards it from a
//! reference point ([`LightSample`]: unit direction, distance, arriving radiance, solid-angle
//! density), give the density of that strategy for a direction found by BSDF sampling (for MIS),
//! and give a scalar power for light selection. [`Lights`] adds the choice of a light: the
//! integrators ask it for light samples from a reference point ([`Lights::for_each_sample`]:
//! one light chosen, or every light in a scene of few, `split_lights`) and for
//! the density of a light found by BSDF sampling ([`Lights::pdf_li_hit`],
//! [`Lights::le_escaped`]), selection included; the sampling policy of each light kind
//! (solid angle, area, spherical rectangle) lives with the light. Parameters and defaults of
//! each Mitsuba plugin are documented in the submodules.
//!
//! # Light selection
//!
//! Lights are chosen with probability ∝ an estimate of the power they deliver to the scene:
//! area π·A·mean(L), directional area A·mean(L), point 4π·mean(I), spot mean(I)·∫falloff dω, directional π r²·mean(E) and
//! infinite lights π·mean(L)·(half the total surface area of the scene) (the irradiance πL of an
//! unoccluded surface over the area that can face it), with r the bounding-sphere radius used
//! when the scene has no surfaces. Lights of zero power are never chosen; if every light has
//! zero power the choice is uniform.
//!
//! With a few lights ([`MAX_LOCAL_LIGHTS`] or fewer) the choice also looks at the shading point
//! ([`Lights::select_at`]): each light gets a cheap bound of the irradiance it can deliver there
//! (area: mean radiance × min(A/d², 2π) × the cosine towards its bounding sphere, widened by the
//! sphere's angular radius; point and spot: I/d² × cosine; directional: E × cosine; directional
//! area: mean L times the beams' concentration where they reach the point, else 0; constant and
//! envmap: π × mean radiance; sunsky: the sun's irradiance × the cosine towards its disk plus
//! π × the sky's mean radiance × the share of the sky the surface sees), and the probability is 90 % ∝ that bound plus 10 % ∝ power, so a
//! light the bound undervalues (it ignores occlusion) keeps a share. The integrator recomputes the
//! same probability at the previous vertex for MIS when a BSDF sample hits a light.

pub mod area;
pub mod delta;
pub mod directional_area;
mod emission;
pub mod envmap_product;
mod from_scene;
pub mod infinite;
pub mod projector;
pub mod sunsky;

pub use area::{AreaLight, LightPoint, SPHERICAL_RECTANGLE_MIN_SOLID_ANGLE};
pub use delta::{DirectionalLight, PointLight, SpotLight};
pub use directional_area::DirectionalAreaLight;
pub use emission::EmittedRay;
pub use from_scene::EmitterError;
pub use gonio_core::sampling::{Distribution1D, Distribution2D};
pub use infinite::{ConstantLight, EnvMapLight, ResamplingLookup};
pub use projector::ProjectorLight;
pub use sunsky::SunSkyLight;

use crate::geometry::{SurfaceInteraction, WorldShape};
use glam::{Vec2, Vec3};
use gonio_core::{SampledSpectrum, SampledWavelengths};

/// A sphere bounding the scene (centre, radius), for lights at infinity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (> 0).
    pub radius: f32,
}

/// The point a light is sampled from, and what the BSDF there can use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightRef {
    /// World position.
    pub p: Vec3,
    /// Unit shading normal, oriented to the side the path arrived from.
    pub n: Vec3,
    /// True when the BSDF there only reflects (to the side of `n`): a light may then restrict
    /// its sampling to that hemisphere (the constant environment does).
    pub hemisphere: bool,
    /// True when the caller also samples the BSDF there and weighs both strategies by MIS: a
    /// light may then leave to BSDF sampling the directions where it is dimmer than its mean
    /// (the environment map's MIS compensation). False where the light's samples must cover
    /// everything it lights (no BSDF samples, the particle tracer).
    pub mis: bool,
    /// The largest density max L/∫L dω of a light at infinity that BSDF sampling resolves alone
    /// here (`SurfaceBsdf::resolved_light_density`, with `mis`; 0 where none is): such lights are
    /// left to BSDF sampling from here ([`Lights::left_to_bsdf`]).
    pub resolved_density: f32,
    /// True when resampled next-event estimation lights this point with the scene's environment
    /// map ([`Lights::sole_envmap`], at a single-scattering `roughconductor`;
    /// `integrator/resampled.rs`): that estimator alone adds the map's light arriving straight
    /// from it, so a BSDF sample leaving from here that escapes adds none of the map's
    /// ([`Lights::le_escaped`]). It takes the map's turn of next-event estimation (the map's
    /// selection probability is unchanged), so the other lights' densities ([`Lights::pmf_at`])
    /// need not know.
    pub resampled: bool,
}

impl LightRef {
    /// No surface to light: the light's plain density over everything it lights (emission
    /// sampling).
    pub const EMISSION: Self = Self {
        p: Vec3::ZERO,
        n: Vec3::Z,
        hemisphere: false,
        mis: false,
        resolved_density: 0.0,
        resampled: false,
    };
}

/// A direction towards a light, drawn from a reference point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit world direction from the reference point towards the light.
    pub wi: Vec3,
    /// Distance to the light point (`f32::INFINITY` for lights at infinity).
    pub dist: f32,
    /// Radiance arriving along −`wi` (for delta lights: irradiance on a surface facing the light,
    /// I/d² or E), before visibility.
    pub li: SampledSpectrum,
    /// Solid-angle density of the direction (excluding light selection); 1 for delta lights.
    pub pdf: f32,
    /// True for point, spot and directional lights: no BSDF sample can find them.
    pub delta: bool,
    /// Surface normal at the light point (area lights), so a shadow ray can stop short of it.
    pub normal: Option<Vec3>,
}

impl LightSample {
    /// A light at infinity's sample: (direction towards it, density, radiance arriving).
    pub fn at_infinity((wi, pdf, li): (Vec3, f32, SampledSpectrum)) -> Self {
        Self {
            wi,
            dist: f32::INFINITY,
            li,
            pdf,
            delta: false,
            normal: None,
        }
    }
}

/// One emitter.
///
/// Unboxed although the variants differ in size: the list holds a few lights, read on every
/// light sample, and an indirection would cost a cache miss there.
#[derive(Clone, Debug)]
#[allow(clippy::large_enum_variant)]
pub enum Light {
    /// `area`, attached to a shape.
    Area(AreaLight),
    /// `directionalarea`, attached to a shape.
    DirectionalArea(DirectionalAreaLight),
    /// `point`.
    Point(PointLight),
    /// `spot`.
    Spot(SpotLight),
    /// `directional`.
    Directional(DirectionalLight),
    /// `constant`.
    Constant(ConstantLight),
    /// `envmap`.
    EnvMap(EnvMapLight),
    /// `projector`.
    Projector(ProjectorLight),
    /// `sunsky`.
    SunSky(SunSkyLight),
}

impl Light {
    /// True for lights that rays never hit (point, spot, directional, projector) or never hit
    /// in the one direction they emit (directional area).
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Light::Point(_)
                | Light::Spot(_)
                | Light::Directional(_)
                | Light::Projector(_)
                | Light::DirectionalArea(_)
        )
    }

    /// True for lights at infinity (constant, envmap, sunsky), seen by rays that escape the scene.
    pub fn is_infinite(&self) -> bool {
        matches!(self, Light::Constant(_) | Light::EnvMap(_) | Light::SunSky(_))
    }

    /// Radiance from an infinite light arriving along −`dir` (`dir` points away from the scene);
    /// zero for other lights.
    pub fn le_infinite(&self, dir: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Light::Constant(c) => c.le(wl),
            Light::EnvMap(e) => e.le(dir, wl),
            Light::SunSky(s) => s.le(dir, wl),
            _ => SampledSpectrum::ZERO,
        }
    }

    /// Draws a direction towards the light from `r` (solid-angle density, selection not
    /// included); `shapes` are the scene's shapes in the world, which area lights sample.
    #[inline]
    pub fn sample_li(
        &self,
        shapes: &[WorldShape],
        r: &LightRef,
        u: Vec2,
        wl: &SampledWavelengths,
    ) -> Option<LightSample> {
        match self {
            Light::Area(area) => area.sample_li(shapes.get(area.shape)?, r, u, wl),
            Light::DirectionalArea(l) => l.sample_li(shapes.get(l.surface.shape)?, r, u.x, wl),
            light => light.sample_li_nonarea(r, u, wl),
        }
    }

    /// Draws a direction towards a non-area light from `r`. Area lights are sampled through
    /// [`AreaLight::sample_li`], which needs the shape's geometry.
    pub fn sample_li_nonarea(&self, r: &LightRef, u: Vec2, wl: &SampledWavelengths) -> Option<LightSample> {
        let s = match self {
            Light::Area(_) | Light::DirectionalArea(_) => return None,
            Light::Point(l) => {
                let d = l.position - r.p;
                let d2 = d.length_squared();
                if d2 == 0.0 {
                    return None;
                }
                let dist = d2.sqrt();
                LightSample {
                    wi: d / dist,
                    dist,
                    li: l.intensity.sample(wl) / d2,
                    pdf: 1.0,
                    delta: true,
                    normal: None,
                }
            }
            Light::Spot(l) => {
                let d = l.position() - r.p;
                let d2 = d.length_squared();
                if d2 == 0.0 {
                    return None;
                }
                let dist = d2.sqrt();
                let wi = d / dist;
                let li = l.intensity_towards(-wi, wl) / d2;
                LightSample {
                    wi,
                    dist,
                    li,
                    pdf: 1.0,
                    delta: true,
                    normal: None,
                }
            }
            Light::Projector(l) => {
                let d = l.position() - r.p;
                let dist = d.length();
                if !(dist > 0.0) {
                    return None;
                }
                LightSample {
                    wi: d / dist,
                    dist,
                    li: l.li_at(r.p, wl),
                    pdf: 1.0,
                    delta: true,
                    normal: None,
                }
            }
            Light::Directional(l) => LightSample {
                wi: -l.direction,
                dist: f32::INFINITY,
                li: l.irradiance.sample(wl),
                pdf: 1.0,
                delta: true,
                normal: None,
            },
            Light::Constant(c) => {
                let (wi, pdf) = c.sample_dir(r, u);
                LightSample::at_infinity((wi, pdf, c.le(wl)))
            }
            Light::EnvMap(e) => LightSample::at_infinity(e.sample_dir_le(u, wl, r)?),
            Light::SunSky(s) => LightSample::at_infinity(s.sample_dir_le(u, wl)?),
        };
        (s.pdf > 0.0 && !s.li.is_black()).then_some(s)
    }

    /// [`Self::le_infinite`] and [`Self::pdf_li_infinite`] from `r` together: an environment
    /// map maps `dir` to its image once for both.
    #[inline]
    pub fn le_pdf_infinite(
        &self,
        r: &LightRef,
        dir: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        match self {
            Light::EnvMap(e) => e.le_pdf(dir, wl, r),
            Light::SunSky(s) => s.le_pdf(dir, wl),
            _ => (self.le_infinite(dir, wl), self.pdf_li_infinite(r, dir)),
        }
    }

    /// Density with which [`Self::sample_li_nonarea`] from `r` produces `dir`, for an infinite
    /// light (0 for others).
    pub fn pdf_li_infinite(&self, r: &LightRef, dir: Vec3) -> f32 {
        match self {
            Light::Constant(c) => c.pdf_dir(r, dir),
            Light::EnvMap(e) => e.pdf_dir(dir, r),
            Light::SunSky(s) => s.pdf_dir(dir),
            _ => 0.0,
        }
    }

    /// The largest solid-angle density of the light's radiance over the directions it lights,
    /// max L/∫L dω (1/sr): how narrow its finest feature can be. Finite for lights at infinity
    /// (a constant 1/4π, an environment map [`EnvMapLight::feature_density`]); infinite for the
    /// others (an area light's subtended solid angle shrinks with distance, delta lights have
    /// none).
    pub fn feature_density(&self) -> f32 {
        match self {
            Light::Constant(_) => 0.25 * std::f32::consts::FRAC_1_PI,
            Light::EnvMap(e) => e.feature_density(),
            Light::SunSky(s) => s.feature_density(),
            _ => f32::INFINITY,
        }
    }

    /// The scalar emission used by [`Self::local_importance`]: mean radiance, intensity or
    /// irradiance over 360–830 nm (computed once per light: a spectrum's mean is a 471-point sum).
    pub fn mean_emission(&self) -> f32 {
        match self {
            Light::Area(a) => a.mean_radiance,
            Light::DirectionalArea(l) => l.surface.mean_radiance,
            Light::Point(l) => l.intensity.mean(),
            Light::Spot(l) => l.intensity.mean(),
            Light::Projector(l) => l.mean_emission(),
            Light::Directional(l) => l.irradiance.mean(),
            Light::Constant(c) => c.mean_radiance(),
            Light::EnvMap(e) => e.mean_radiance(),
            Light::SunSky(s) => s.mean_radiance(),
        }
    }

    /// A cheap bound of the irradiance this light can deliver at `r` (see the module docs);
    /// `mean` is [`Self::mean_emission`].
    pub fn local_importance(&self, r: &LightRef, mean: f32) -> f32 {
        let cos_towards = |d: Vec3, half_angle_sin: f32| -> f32 {
            if !r.hemisphere {
                return 1.0;
            }
            let len = d.length();
            if len == 0.0 {
                return 1.0;
            }
            let cos_n = (r.n.dot(d) / len).clamp(-1.0, 1.0);
            if half_angle_sin >= 1.0 {
                return 1.0;
            }
            // cos of (angle to the normal − angular radius of the light's bounding sphere),
            // clamped to [0, 1], without inverse trigonometric functions.
            let cos_b = (1.0 - half_angle_sin * half_angle_sin).max(0.0).sqrt();
            if cos_n >= cos_b {
                return 1.0;
            }
            let sin_n = (1.0 - cos_n * cos_n).max(0.0).sqrt();
            (cos_n * cos_b + sin_n * half_angle_sin).max(0.0)
        };
        let v = match self {
            Light::Area(a) => {
                let d = a.center - r.p;
                let d2 = d.length_squared().max(1e-12);
                let sin_half = (a.radius / d2.sqrt()).min(1.0);
                let solid = (a.area / d2).min(2.0 * std::f32::consts::PI);
                mean * solid * cos_towards(d, sin_half)
            }
            Light::Point(l) => {
                let d = l.position - r.p;
                mean / d.length_squared().max(1e-12) * cos_towards(d, 0.0)
            }
            Light::Spot(l) => {
                let d = l.position() - r.p;
                mean / d.length_squared().max(1e-12) * cos_towards(d, 0.0)
            }
            Light::Projector(l) => {
                let d = l.position() - r.p;
                mean / d.length_squared().max(1e-12) * cos_towards(d, 0.0)
            }
            Light::Directional(l) => mean * cos_towards(-l.direction, 0.0),
            Light::DirectionalArea(l) => l.local_importance(r, mean),
            Light::Constant(_) | Light::EnvMap(_) => std::f32::consts::PI * mean,
            Light::SunSky(s) => {
                let sky_view = if r.hemisphere {
                    0.5 * (1.0 + r.n.dot(s.zenith()))
                } else {
                    1.0
                };
                s.local_importance(cos_towards(s.sun_direction(), s.sin_alpha()), sky_view)
            }
        };
        if v.is_finite() { v.max(0.0) } else { 0.0 }
    }

    /// Scalar power estimate for light selection (see the module docs). `scene_area` is the
    /// total surface area of the scene's shapes, `bounds` the bounding sphere.
    pub fn power(&self, scene_area: f32, bounds: &BoundingSphere) -> f32 {
        let infinite_area = if scene_area > 0.0 {
            0.5 * scene_area
        } else {
            std::f32::consts::PI * bounds.radius * bounds.radius
        };
        let p = match self {
            Light::Area(a) => a.power(),
            Light::DirectionalArea(l) => l.power(),
            Light::Point(l) => l.power(),
            Light::Spot(l) => l.power(),
            Light::Projector(l) => l.power(),
            Light::Directional(l) => l.power(bounds.radius),
            Light::Constant(c) => std::f32::consts::PI * c.mean_radiance() * infinite_area,
            Light::EnvMap(e) => std::f32::consts::PI * e.mean_radiance() * infinite_area,
            Light::SunSky(s) => std::f32::consts::PI * s.mean_radiance() * infinite_area,
        };
        if p.is_finite() { p.max(0.0) } else { 0.0 }
    }
}

/// Lights per scene up to which the choice depends on the shading point.
pub const MAX_LOCAL_LIGHTS: usize = 8;

/// All the lights of a scene and the distribution that picks one.
#[derive(Clone, Debug)]
pub struct Lights {
    lights: Vec<Light>,
    selection: Distribution1D,
    /// Light index of each shape's area emitter.
    shape_light: Vec<Option<u32>>,
    infinite: Vec<u32>,
    bounds: BoundingSphere,
    /// [`Light::mean_emission`] of each light.
    means: Vec<f32>,
    /// Every light sampled at each vertex ([`Self::with_split`]).
    split: bool,
    /// [`Light::feature_density`] of each light.
    feature_density: Vec<f32>,
    /// The index of the scene's environment map when it has exactly one.
    sole_envmap: Option<u32>,
}

impl Lights {
    /// Builds the selection distribution. `shape_count` is the number of shapes (area lights refer
    /// to them by index), `scene_area` their total area.
    pub fn new(lights: Vec<Light>, shape_count: usize, scene_area: f32, bounds: BoundingSphere) -> Self {
        let powers: Vec<f32> = lights.iter().map(|l| l.power(scene_area, &bounds)).collect();
        let selection = Distribution1D::new(&powers);
        let mut shape_light = vec![None; shape_count];
        let mut infinite = Vec::new();
        for (i, l) in lights.iter().enumerate() {
            match l {
                Light::Area(a) if a.shape < shape_count => shape_light[a.shape] = Some(i as u32),
                l if l.is_infinite() => infinite.push(i as u32),
                _ => {}
            }
        }
        let means = lights.iter().map(Light::mean_emission).collect();
        let feature_density = lights.iter().map(Light::feature_density).collect();
        let mut maps = (0..lights.len()).filter(|&i| matches!(lights[i], Light::EnvMap(_)));
        let sole_envmap = match (maps.next(), maps.next()) {
            (Some(i), None) => Some(i as u32),
            _ => None,
        };
        Self {
            lights,
            selection,
            shape_light,
            infinite,
            bounds,
            means,
            split: false,
            feature_density,
            sole_envmap,
        }
    }

    /// The index of the scene's environment map (`envmap`), when it has exactly one (resampled
    /// next-event estimation samples it).
    #[inline]
    pub fn sole_envmap(&self) -> Option<usize> {
        self.sole_envmap.map(|i| i as usize)
    }

    /// True when next-event estimation from `r` leaves light `i` to BSDF sampling: the BSDF
    /// there is sampled too and resolves the light alone, its radiance having no feature as
    /// narrow as the BSDF's lobe ([`Light::feature_density`] at most
    /// [`LightRef::resolved_density`]; see `MicrofacetDistribution::resolved_light_density`).
    /// A light sample would then add little to the BSDF samples and cost a light sample, a BSDF
    /// evaluation and a shadow ray; left out, the light's density from `r` is 0
    /// ([`Self::pmf_at`]), so the BSDF samples that find it take its whole weight and the
    /// estimate stays unbiased.
    #[inline]
    pub fn left_to_bsdf(&self, r: &LightRef, i: usize) -> bool {
        r.resolved_density > 0.0
            && self
                .feature_density
                .get(i)
                .is_some_and(|&f| f <= r.resolved_density)
    }

    /// The lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// True when the scene has no light.
    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// Picks a light: (index, probability).
    #[inline]
    pub fn select(&self, u: f32) -> Option<(usize, f32)> {
        if self.lights.is_empty() {
            return None;
        }
        let (i, p, _) = self.selection.sample_discrete(u);
        (p > 0.0).then_some((i, p))
    }

    /// Probability that [`Self::select`] picks light `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        if self.lights.is_empty() {
            0.0
        } else {
            self.selection.pmf(i)
        }
    }

    /// Per-light probabilities at `r` (position-aware when there are few lights), written into
    /// `out` (length ≥ the number of lights); returns false when the global distribution applies.
    #[inline]
    fn local_pmf(&self, r: &LightRef, out: &mut [f32; MAX_LOCAL_LIGHTS]) -> bool {
        let n = self.lights.len();
        if n <= 1 || n > MAX_LOCAL_LIGHTS {
            return false;
        }
        let mut total = 0.0f32;
        for (i, l) in self.lights.iter().enumerate() {
            out[i] = l.local_importance(r, self.means[i]);
            total += out[i];
        }
        for i in 0..n {
            let local = if total > 0.0 { out[i] / total } else { 0.0 };
            let global = self.selection.pmf(i);
            out[i] = if total > 0.0 {
                0.9 * local + 0.1 * global
            } else {
                global
            };
        }
        true
    }

    /// Picks a light for next-event estimation from `r`: (index, probability).
    #[inline]
    pub fn select_at(&self, r: &LightRef, u: f32) -> Option<(usize, f32)> {
        self.select_at_remapped(r, u).map(|(i, p, _)| (i, p))
    }

    /// [`Self::select_at`], with `u` remapped into [0, 1) within the light's share: a number
    /// independent of the choice, for the sampling that follows it.
    #[inline]
    pub fn select_at_remapped(&self, r: &LightRef, u: f32) -> Option<(usize, f32, f32)> {
        let mut p = [0.0f32; MAX_LOCAL_LIGHTS];
        if !self.local_pmf(r, &mut p) {
            if self.lights.is_empty() {
                return None;
            }
            let (i, p, ur) = self.selection.sample_discrete(u);
            return (p > 0.0).then_some((i, p, ur));
        }
        let n = self.lights.len();
        let mut acc = 0.0f32;
        let mut last = None;
        // As `Distribution1D::sample_discrete` rescales (the global branch above).
        let remap = |u: f32, start: f32, pi: f32| ((u - start) / pi).clamp(0.0, 1.0 - f32::EPSILON);
        for (i, &pi) in p.iter().enumerate().take(n) {
            if pi <= 0.0 {
                continue;
            }
            let start = acc;
            acc += pi;
            last = Some((i, pi, remap(u, start, pi)));
            if u < acc {
                return last;
            }
        }
        last
    }

    /// True when next-event estimation samples every light at each vertex instead of choosing
    /// one ([`Self::with_split`]); [`Self::pmf_at`] is then 1 for every light.
    #[inline]
    pub fn split(&self) -> bool {
        self.split
    }

    /// The same lights, sampled each at every vertex when the scene has between two and
    /// `max_lights` of them (the `path` integrator's `split_lights`): no noise from choosing
    /// between a sun and a sky, or a lamp and a sky, at the cost of a shadow ray per light.
    pub fn with_split(mut self, max_lights: u32) -> Self {
        self.split = (2..=max_lights as usize).contains(&self.lights.len());
        self
    }

    /// Probability that next-event estimation from `r` samples light `i`: that
    /// [`Self::select_at`] picks it, or 1 when every light is sampled ([`Self::with_split`]);
    /// 0 when it is left to BSDF sampling there ([`Self::left_to_bsdf`]: a pick of it then draws
    /// no sample).
    #[inline]
    pub fn pmf_at(&self, r: &LightRef, i: usize) -> f32 {
        if self.left_to_bsdf(r, i) {
            return 0.0;
        }
        if self.split() {
            return 1.0;
        }
        let mut p = [0.0f32; MAX_LOCAL_LIGHTS];
        if !self.local_pmf(r, &mut p) {
            return self.pmf(i);
        }
        p.get(i).copied().unwrap_or(0.0)
    }

    /// Next-event estimation's light samples from `r`, each handed to `f` with its light's
    /// index: the light [`Self::select_at`] picks with `u_sel`, or every light when they are
    /// split ([`Self::with_split`]), all drawn with `u`. Each sample's `pdf` includes the
    /// probability of sampling its light ([`Self::pmf_at`]). `shapes` are the scene's shapes in
    /// the world (area lights sample them).
    #[inline]
    pub fn for_each_sample(
        &self,
        shapes: &[WorldShape],
        r: &LightRef,
        (u_sel, u): (f32, Vec2),
        wl: &SampledWavelengths,
        mut f: impl FnMut(usize, &LightSample),
    ) {
        if self.split {
            for (li, light) in self.lights.iter().enumerate() {
                if self.left_to_bsdf(r, li) {
                    continue;
                }
                if let Some(ls) = light.sample_li(shapes, r, u, wl) {
                    f(li, &ls);
                }
            }
        } else if let Some((li, ls)) = self.sample_li_indexed(shapes, r, u_sel, u, wl) {
            f(li, &ls);
        }
    }

    /// [`Self::for_each_sample`] with light `own`'s turn handed to `own_turn` instead of a light
    /// sample of it: called with the probability of that turn (1 where every light is sampled,
    /// else the probability of choosing `own`) and the number for what follows (`u_sel`, or
    /// what is left of it once `own` is chosen). Resampled next-event estimation takes the
    /// environment map's turn this way.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn for_each_sample_but(
        &self,
        shapes: &[WorldShape],
        r: &LightRef,
        (u_sel, u): (f32, Vec2),
        wl: &SampledWavelengths,
        own: usize,
        mut own_turn: impl FnMut(f32, f32),
        mut f: impl FnMut(usize, &LightSample),
    ) {
        if self.split {
            for (li, light) in self.lights.iter().enumerate() {
                if self.left_to_bsdf(r, li) {
                    continue;
                }
                if li == own {
                    own_turn(1.0, u_sel);
                } else if let Some(ls) = light.sample_li(shapes, r, u, wl) {
                    f(li, &ls);
                }
            }
        } else if let Some((li, p_sel, u_rest)) = self.select_at_remapped(r, u_sel) {
            if li == own {
                own_turn(p_sel, u_rest);
            } else if !self.left_to_bsdf(r, li)
                && let Some(ls) = self.lights[li].sample_li(shapes, r, u, wl)
            {
                f(
                    li,
                    &LightSample {
                        pdf: p_sel * ls.pdf,
                        ..ls
                    },
                );
            }
        }
    }

    /// One light picked by [`Self::select_at`] with `u_sel` and a direction towards it drawn with
    /// `u`, with the light's index; the sample's `pdf` includes the selection probability.
    #[inline]
    pub fn sample_li_indexed(
        &self,
        shapes: &[WorldShape],
        r: &LightRef,
        u_sel: f32,
        u: Vec2,
        wl: &SampledWavelengths,
    ) -> Option<(usize, LightSample)> {
        let (li, p_sel) = self.select_at(r, u_sel)?;
        if self.left_to_bsdf(r, li) {
            return None;
        }
        let ls = self.lights[li].sample_li(shapes, r, u, wl)?;
        Some((
            li,
            LightSample {
                pdf: p_sel * ls.pdf,
                ..ls
            },
        ))
    }

    /// The density with which [`Self::for_each_sample`] from `r` produces the point of `hit` on area
    /// light `li` (selection × solid angle), for the MIS weight of a light found by BSDF
    /// sampling; 0 when `li` is not an area light.
    #[inline]
    pub fn pdf_li_hit(
        &self,
        shapes: &[WorldShape],
        r: &LightRef,
        li: usize,
        hit: &SurfaceInteraction,
    ) -> f32 {
        let Some(Light::Area(area)) = self.lights.get(li) else {
            return 0.0;
        };
        let Some(shape) = shapes.get(hit.shape as usize) else {
            return 0.0;
        };
        let dir_pdf = area.pdf_li(shape, r.p, hit);
        self.pmf_at(r, li) * dir_pdf
    }

    /// The radiance of the light at infinity `li` arriving along −`dir` (a ray that left the
    /// scene) and, when `r` is the vertex that drew `dir` by its BSDF, the density with which
    /// [`Self::for_each_sample`] from `r` produces `dir` (selection × solid angle; 0 without `r` or
    /// where the light is black, which nothing then weighs). Nothing at all of the map that
    /// resampled next-event estimation lit `r` with ([`LightRef::resampled`]).
    #[inline]
    pub fn le_escaped(
        &self,
        r: Option<&LightRef>,
        li: usize,
        dir: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        let light = &self.lights[li];
        let Some(r) = r else {
            return (light.le_infinite(dir, wl), 0.0);
        };
        if r.resampled && self.sole_envmap() == Some(li) {
            // Resampled next-event estimation at `r` added this light whole.
            return (SampledSpectrum::ZERO, 0.0);
        }
        let (le, pdf_dir) = light.le_pdf_infinite(r, dir, wl);
        if le.is_black() {
            return (le, 0.0);
        }
        (le, self.pmf_at(r, li) * pdf_dir)
    }

    /// The area light on shape `shape`, if it emits.
    #[inline]
    pub fn shape_light(&self, shape: usize) -> Option<usize> {
        self.shape_light.get(shape).copied().flatten().map(|i| i as usize)
    }

    /// Indices of the lights at infinity.
    #[inline]
    pub fn infinite(&self) -> &[u32] {
        &self.infinite
    }

    /// The scene's bounding sphere.
    pub fn bounds(&self) -> BoundingSphere {
        self.bounds
    }
}
