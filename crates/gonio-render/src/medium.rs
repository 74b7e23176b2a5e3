//! Participating media as the renderer holds them: the `homogeneous` medium (Mitsuba 3
//! `src/media/homogeneous.cpp`) and the interface a shape's surface makes between two media.
//!
//! A homogeneous medium has one extinction σt(λ) = `scale`·`sigma_t`(λ) everywhere (a number or
//! a spectrum), a single-scattering albedo α(λ) (a reflectance-like spectrum, or a `gridvolume`
//! read at the scattering point: Mitsuba's albedo is a volume), so σs = α·σt, and a phase
//! function ([`Phase`]: a model of [`gonio_core::phase`], a `blendphase` of two, or `sggx`
//! microflakes, whose projected area σ(ω) multiplies σt along ω); its free flights are drawn exactly
//! ([`gonio_core::medium::sample_free_flight`]) unless the microflakes' matrix varies in space.
//! A heterogeneous medium (Mitsuba 3 `src/media/heterogeneous.cpp`) reads σt from a
//! `gridvolume` too: it is tracked under the majorant σ̄ = `scale`·max σt (times a bound of the
//! projected area for `sggx`), by delta tracking along paths and ratio tracking along shadow
//! rays ([`gonio_core::medium::null_collision_event`]), and only inside the grid's box, the
//! world-axis-aligned bounds of its unit cube under `to_world` (outside it the medium is empty;
//! inside, a turned grid is read through its wrap mode, as in Mitsuba). Given a constant instead, it is that constant inside
//! the axis-aligned bounds of its `constvolume`'s unit cube under `to_world`, whose free
//! flights are drawn exactly there ([`Medium::box_sigma_t`]). The integrator is `volpath`
//! (`crate::integrator::volpath`).
//!
//! A shape takes media with `<ref name="interior" id="..."/>` and `name="exterior"`: the side its
//! normal points to is the exterior. A ray that leaves such a surface enters the medium on the
//! side its direction points to (Mitsuba's `SurfaceInteraction::target_medium`); surfaces that
//! name no medium leave the ray in the medium it was in. A sensor nesting a medium starts its
//! rays in it.

use crate::plugins::phase::blendphase::BlendPhase;
use crate::plugins::phase::sggx::SggxPhase;
use crate::texture::volume::GridVolume;
use glam::{Affine3A, Vec2, Vec3};
use gonio_core::phase::{PhaseFunction, PhaseSample};
use gonio_core::{SampledSpectrum, SampledWavelengths, Spectrum};
use std::sync::Arc;

/// Index of a medium in [`crate::scene::Scene::media`].
pub type MediumId = u32;

/// The media on the two sides of a shape's surface (`None`: vacuum).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumInterface {
    /// The medium inside (against the normal).
    pub interior: Option<MediumId>,
    /// The medium outside (the side the normal points to).
    pub exterior: Option<MediumId>,
}

impl MediumInterface {
    /// The interface between `interior` and `exterior`.
    pub fn new(interior: Option<MediumId>, exterior: Option<MediumId>) -> Self {
        Self { interior, exterior }
    }

    /// True when the shape names a medium on either side: crossing it changes the ray's medium.
    #[inline]
    pub fn is_transition(&self) -> bool {
        self.interior.is_some() || self.exterior.is_some()
    }

    /// The medium a ray leaving the surface along `d` is in, given the geometric normal `n` and
    /// the medium `current` the ray arrived in (kept where the surface is no transition).
    #[inline]
    pub fn target(&self, d: Vec3, n: Vec3, current: Option<MediumId>) -> Option<MediumId> {
        if !self.is_transition() {
            current
        } else if d.dot(n) > 0.0 {
            self.exterior
        } else {
            self.interior
        }
    }
}

/// A medium's phase function: one of the models, a blend of two whose weight may vary in space,
/// or SGGX microflakes whose matrix may (so all take the scattering point).
#[derive(Clone, Debug, PartialEq)]
pub enum Phase {
    /// `isotropic`, `hg`, `rayleigh`, `tabphase`.
    Model(PhaseFunction),
    /// `blendphase`.
    Blend(Box<BlendPhase>),
    /// `sggx`: microflakes, whose projected area also scales the medium's extinction.
    Sggx(Box<SggxPhase>),
}

impl Phase {
    /// p(ωi, ωo) at world point `p`.
    #[inline]
    pub fn eval(&self, p: Vec3, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Phase::Model(m) => m.eval(wi, wo),
            Phase::Blend(b) => b.eval(p, wi, wo),
            Phase::Sggx(s) => s.eval(p, wi, wo),
        }
    }

    /// Draws ωo at world point `p` from two uniform numbers; the sample's density is
    /// [`Phase::eval`] (its weight p/pdf is 1).
    #[inline]
    pub fn sample(&self, p: Vec3, wi: Vec3, u: Vec2) -> PhaseSample {
        match self {
            Phase::Model(m) => m.sample(wi, u),
            Phase::Blend(b) => b.sample(p, wi, u),
            Phase::Sggx(s) => s.sample(p, wi, u),
        }
    }

    /// The factor of the extinction at `p` along ±`d`: microflakes' projected area σ(d), 1 for
    /// the other phase functions.
    #[inline]
    pub fn projected_area(&self, p: Vec3, d: Vec3) -> f32 {
        match self {
            Phase::Sggx(s) => s.projected_area(p, d),
            _ => 1.0,
        }
    }

    /// [`Phase::projected_area`] where it is the same at every point (`None` where it varies).
    #[inline]
    fn uniform_projected_area(&self, d: Vec3) -> Option<f32> {
        match self {
            Phase::Sggx(s) => s.uniform_projected_area(d),
            _ => Some(1.0),
        }
    }

    /// A bound of [`Phase::projected_area`] over every point and direction.
    fn max_projected_area(&self) -> f32 {
        match self {
            Phase::Sggx(s) => s.max_projected_area(),
            _ => 1.0,
        }
    }
}

/// A medium's single-scattering albedo.
#[derive(Clone, Debug, PartialEq)]
pub enum Albedo {
    /// The same everywhere.
    Spectrum(Spectrum),
    /// A grid read at the scattering point (one channel, or linear RGB as Mitsuba's spectral
    /// `gridvolume` reads it), clamped to [0, 1] per wavelength unless `unclamped`.
    Volume {
        /// The grid.
        grid: Arc<GridVolume>,
        /// Mitsuba's reading (`--mitsuba-estimators`): the stored form of a saturated colour
        /// above 1 kept, an albedo that creates energy.
        unclamped: bool,
    },
}

/// A medium's extinction before `scale` (1/length).
#[derive(Clone, Debug, PartialEq)]
pub enum Extinction {
    /// The same everywhere (the homogeneous medium).
    Spectrum(Spectrum),
    /// The same inside a box, zero outside: a heterogeneous medium given a number or a
    /// `constvolume` (Mitsuba's: the medium is where its extinction volume is, for a constant
    /// the axis-aligned bounds of the unit cube under the volume's `to_world`), given as the
    /// world → [0, 1]³ transform of the box.
    Box(Spectrum, Affine3A),
    /// A grid (one channel, or linear RGB as Mitsuba's spectral `gridvolume` reads it), zero
    /// outside its box.
    Volume(Arc<GridVolume>),
}

/// A participating medium: homogeneous, or heterogeneous when its extinction is a grid.
#[derive(Clone, Debug)]
pub struct Medium {
    /// Extinction before `scale` (1/length).
    pub sigma_t: Extinction,
    /// Single-scattering albedo.
    pub albedo: Albedo,
    /// Multiplier of σt (Mitsuba's `scale`).
    pub scale: f32,
    /// The phase function.
    pub phase: Phase,
    /// Next-event estimation at scattering events in this medium (Mitsuba's `sample_emitters`).
    pub sample_emitters: bool,
    /// [`Medium::majorant`], computed once (a grid's maximum is a scan of the grid).
    majorant: f32,
    /// World → [0, 1]³ of the box the medium fills (a grid's or a constant's), `None` when it
    /// fills everything (the homogeneous medium).
    bounds: Option<Affine3A>,
}

/// The world → [0, 1]³ transform of the world-axis-aligned bounds of the unit cube under
/// `to_world` (Mitsuba's `Volume::bbox`, where its heterogeneous medium exists); `None` for a
/// flat or non-finite box.
pub fn unit_cube_bounds(to_world: &Affine3A) -> Option<Affine3A> {
    let corners = (0..8).map(|i| {
        to_world.transform_point3(Vec3::new(
            (i & 1) as f32,
            (i >> 1 & 1) as f32,
            (i >> 2 & 1) as f32,
        ))
    });
    let (lo, hi) = corners.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), c| {
        (lo.min(c), hi.max(c))
    });
    let size = hi - lo;
    (size.min_element() > 0.0 && size.is_finite())
        .then(|| Affine3A::from_scale_rotation_translation(size.recip(), glam::Quat::IDENTITY, -lo / size))
}

impl Medium {
    /// The medium of these parts.
    pub fn new(sigma_t: Extinction, albedo: Albedo, scale: f32, phase: Phase, sample_emitters: bool) -> Self {
        let majorant = scale
            * phase.max_projected_area()
            * match &sigma_t {
                Extinction::Spectrum(s) | Extinction::Box(s, _) => s.max_value(),
                Extinction::Volume(g) if g.channels == 1 => g.max(),
                Extinction::Volume(g) => 2.0 * g.max(),
            };
        let bounds = match &sigma_t {
            Extinction::Spectrum(_) => None,
            Extinction::Box(_, to_local) => Some(*to_local),
            // A grid's `to_world` was checked invertible when it was read.
            Extinction::Volume(g) => unit_cube_bounds(&g.to_local.inverse()),
        };
        Self {
            sigma_t,
            albedo,
            scale,
            phase,
            sample_emitters,
            majorant,
            bounds,
        }
    }

    /// The extinction σt along direction `d` at the sample's wavelengths where it is the same
    /// at every point; `None` where it varies (a grid of σt, or of a microflake phase
    /// function's matrix).
    #[inline]
    pub fn uniform_sigma_t(&self, d: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        match &self.sigma_t {
            Extinction::Spectrum(s) => {
                let area = self.phase.uniform_projected_area(d)?;
                Some(s.sample(wl) * (self.scale * area))
            }
            Extinction::Box(..) | Extinction::Volume(_) => None,
        }
    }

    /// The extinction along direction `d` of a medium that is the same everywhere inside its box
    /// and empty outside (a heterogeneous medium given a constant, [`Extinction::Box`]); `None`
    /// for others (and where a microflake matrix varies in space). Its free flights are drawn
    /// exactly inside [`Medium::extent`].
    #[inline]
    pub fn box_sigma_t(&self, d: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        match &self.sigma_t {
            Extinction::Box(s, _) => {
                let area = self.phase.uniform_projected_area(d)?;
                Some(s.sample(wl) * (self.scale * area))
            }
            _ => None,
        }
    }

    /// σt at world point `p` along direction `d` (0 outside a grid's box): the density times
    /// the phase function's projected area ([`Phase::projected_area`]).
    pub fn sigma_t_at(&self, p: Vec3, d: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let area = self.phase.projected_area(p, d);
        self.density_at(p, wl) * area
    }

    /// σt at world point `p` before the projected area.
    fn density_at(&self, p: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        // Outside its box the medium is empty; inside, a grid is read through its wrap mode
        // (a turned grid's box holds more than the grid: Mitsuba's clamped lookups there).
        if let Some(to_local) = &self.bounds {
            let x = to_local.transform_point3(p);
            if !(x.cmpge(Vec3::ZERO).all() && x.cmple(Vec3::ONE).all()) {
                return SampledSpectrum::splat(0.0);
            }
        }
        match &self.sigma_t {
            Extinction::Spectrum(s) | Extinction::Box(s, _) => s.sample(wl) * self.scale,
            Extinction::Volume(g) => {
                let x = g.to_local.transform_point3(p);
                // Negative extinction reads as 0 (one channel; colour samples are uplifted
                // from non-negative values).
                let s = g.spectrum_local(x, wl);
                SampledSpectrum(s.0.max(glam::Vec4::ZERO)) * self.scale
            }
        }
    }

    /// A grey bound σ̄ ≥ σt(λ, p, ω) everywhere (an uplifted RGB colour stays below twice its
    /// largest component; microflakes' projected area below its bound).
    #[inline]
    pub fn majorant(&self) -> f32 {
        self.majorant
    }

    /// The part [t0, t1] of the ray `o + t·d`, t in [0, `t_max`], where the medium may have
    /// extinction: all of it, or the part inside a grid's or a box's box (`None`: it misses
    /// the box).
    pub fn extent(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let Some(to_local) = &self.bounds else {
            return Some((0.0, t_max));
        };
        // The box [0, 1]³ in the grid's space, where the ray keeps its parameter t.
        let (o, d) = (to_local.transform_point3(o), to_local.transform_vector3(d));
        let (mut t0, mut t1) = (0.0f32, t_max);
        for a in 0..3 {
            let inv = 1.0 / d[a];
            let (near, far) = ((0.0 - o[a]) * inv, (1.0 - o[a]) * inv);
            let (near, far) = if near <= far { (near, far) } else { (far, near) };
            // NaN (a ray in the slab's plane) leaves the bound as it is.
            t0 = if near > t0 { near } else { t0 };
            t1 = if far < t1 { far } else { t1 };
        }
        (t0 <= t1).then_some((t0, t1))
    }

    /// True when the medium only absorbs (α given as the number 0): a path then crosses it
    /// with the transmittance exp(−σt·d) instead of a free-flight sample (the same expectation,
    /// without the variance of a path that survives with probability T).
    #[inline]
    pub fn absorbs_only(&self) -> bool {
        matches!(&self.albedo, Albedo::Spectrum(Spectrum::Constant(a)) if *a == 0.0)
    }

    /// α at world point `p`.
    pub fn albedo(&self, p: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        match &self.albedo {
            Albedo::Spectrum(s) => s.sample(wl),
            Albedo::Volume { grid: g, unclamped } => {
                // Mitsuba's colour samples (2·max(rgb) times the sigmoid of rgb/(2·max)) can
                // exceed 1 at some wavelengths for saturated colours; an albedo above 1 creates
                // energy, so it is clamped to [0, 1] per wavelength (equal to Mitsuba's wherever
                // Mitsuba's is at most 1), except under Mitsuba's estimators.
                let a = g.spectrum_local(g.to_local.transform_point3(p), wl);
                let top = if *unclamped { f32::INFINITY } else { 1.0 };
                SampledSpectrum(a.0.clamp(glam::Vec4::ZERO, glam::Vec4::splat(top)))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::WrapMode;
    use crate::texture::volume::spectral_samples;
    use glam::Affine3A;

    /// Mitsuba 3.9.1 reads the saturated colour (0.8, 0.1, 0) of a `gridvolume` as 1.313 at
    /// 680 nm (2·max(rgb) times the sigmoid of rgb/(2·max)): as an albedo that creates energy at
    /// every scattering. The medium's albedo is clamped to 1 there (below 1 it is Mitsuba's);
    /// Mitsuba's estimators keep 1.313.
    #[test]
    fn an_albedo_grid_of_a_saturated_colour_stays_at_most_one() {
        let data = vec![0.8, 0.1, 0.0];
        let grid = GridVolume {
            res: [1, 1, 1],
            channels: 3,
            spectra: spectral_samples(&data, 3, false),
            data,
            trilinear: true,
            wrap: WrapMode::Clamp,
            raw: false,
            to_local: Affine3A::IDENTITY,
        };
        let grid = Arc::new(grid);
        let wl = SampledWavelengths::from_parts([450.0, 520.0, 600.0, 680.0], [1.0; 4]);
        // Ours, then Mitsuba's (`--mitsuba-estimators`): 0.021224, 0.067321, 0.453848, 1.313242.
        for (unclamped, top) in [(false, 1.0f32), (true, 1.313242)] {
            let medium = Medium::new(
                Extinction::Spectrum(Spectrum::Constant(1.0)),
                Albedo::Volume {
                    grid: grid.clone(),
                    unclamped,
                },
                1.0,
                Phase::Model(PhaseFunction::Isotropic),
                true,
            );
            let a = medium.albedo(Vec3::splat(0.5), &wl);
            for (k, want) in [0.021224f32, 0.067321, 0.453848, top].into_iter().enumerate() {
                let (got, lambda) = (a[k], wl.lambda(k));
                assert!((got - want).abs() < 2e-3 * want.max(0.05), "λ {lambda}: {got}");
            }
        }
    }
}
