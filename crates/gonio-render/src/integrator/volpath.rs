//! The volumetric path tracer: Mitsuba 3's `volpath` (`src/integrators/volpath.cpp`) on scenes
//! with participating media ([`crate::medium`]), run by the `volpath`, `volpathmis` and
//! `prbvolpath` integrators when the scene declares a medium.
//!
//! The path carries the medium it is in (the sensor's at the camera). In a medium each segment
//! first draws a free-flight distance ([`gonio_core::medium::sample_free_flight`], spectral MIS
//! over the sample's wavelengths):
//!
//! * **a collision** before the next surface is a scattering event: β ← β·σs·T/p, then
//!   next-event estimation with the phase function (where the medium's `sample_emitters` asks
//!   for it) and a phase-function sample (weight 1);
//! * otherwise the ray reaches the surface with β ← β·T/P, and the surface is handled as by the
//!   path tracer: emission, next-event estimation, BSDF sampling.
//!
//! A medium that only absorbs (albedo 0: tinted glass, ink) is crossed with β ← β·T, no
//! distance drawn (beyond Mitsuba, whose paths there survive with probability T: the same
//! mean, with a relative variance of 1/T − 1 per path).
//!
//! In a heterogeneous medium (σt from a grid) the flight is delta tracking under the grid's
//! majorant σ̄ inside its box ([`gonio_core::medium::null_collision_event`]: tentative
//! collisions at rate σ̄, each real or null by the mean σt over the live wavelengths), and
//! shadow rays (and flights through a grid that only absorbs) take ratio tracking's estimate
//! of T, the product of σn/σ̄ over the tentative collisions (Mitsuba's shadow rays stop at the
//! first: 0 or 1, the same mean).
//!
//! Shadow rays cross media (T = exp(−σt·d) per segment, exact for homogeneous media, where
//! Mitsuba's delta tracking is an unbiased 0/1 estimate of it) and surfaces that let light
//! straight through (`null`, `thindielectric`: their null transmission); any other surface
//! blocks them. A ray leaving a surface that separates media enters the medium on the side it
//! leaves to ([`crate::medium::MediumInterface::target`]).
//!
//! Bookkeeping as Mitsuba's: a scattering event in a medium or at a surface counts one segment
//! of `max_depth` (a straight pass through a `null` surface none, nor does it change the MIS
//! state); emission found by BSDF or phase sampling is weighted by the power heuristic against
//! light sampling from the last scattering event (1 after the camera, a delta lobe or a medium
//! that samples no emitters), with the path tracer's exponent. Russian roulette is the path
//! tracer's. gonio's further path-tracer estimators (light subpaths, lobe splitting, refracted
//! and manifold next-event estimation) do not take part here: this is Mitsuba's estimator.
//! Polarized renders ignore media.

use super::path_state::{PathState, PrevVertex};
use super::{MAX_NULL_CROSSINGS, PathTracer};
use crate::accel::{Intersect, LazyHit};
use crate::emitter::LightRef;
use crate::geometry::{Ray, SurfaceInteraction, spawn_ray_between};
use crate::material::ShadingPoint;
use crate::medium::{Medium, MediumId, MediumInterface};
use crate::sampler::PathSampler;
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::medium::{Tracking, flight_weight, null_collision_event, sample_distance, transmittance};
use gonio_core::{Bsdf, BsdfContext, BsdfFlags, SampledSpectrum, SampledWavelengths};

/// Largest number of tentative collisions a flight through a grid takes (a bound against a
/// majorant far above the grid's values; never reached in sensible scenes).
const MAX_TRACKING_STEPS: u32 = 1 << 16;

/// What the volumetric path tracer reads besides the path tracer's scene data.
pub(crate) struct Media<'a> {
    /// The scene's media.
    pub(crate) media: &'a [Medium],
    /// The media on the two sides of each shape.
    pub(crate) shape_media: &'a [MediumInterface],
    /// The medium the camera rays start in.
    pub(crate) sensor_medium: Option<MediumId>,
}

impl Media<'_> {
    fn interface(&self, shape: u32) -> MediumInterface {
        self.shape_media.get(shape as usize).copied().unwrap_or_default()
    }

    fn medium(&self, id: Option<MediumId>) -> Option<&Medium> {
        id.and_then(|m| self.media.get(m as usize))
    }
}

impl PathTracer<'_> {
    /// Radiance arriving along the camera ray `ray` in a scene with participating media (see the
    /// module documentation).
    pub(super) fn li_volumetric(
        &self,
        media: &Media<'_>,
        mut ray: Ray,
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
    ) -> SampledSpectrum {
        let mut l = SampledSpectrum::splat(0.0);
        if self.max_depth == 0 {
            return l;
        }
        let mut state = PathState::<SampledSpectrum>::CAMERA;
        let mut medium = media.sensor_medium;
        let mut bsdf = SurfaceBsdf::new();
        loop {
            let mut lazy = None;
            if let Some(m) = media.medium(medium) {
                let (surface, collision, weight) = self.fly(m, &ray, sampler, wl);
                lazy = surface;
                state.beta *= weight;
                if let Some(p) = collision {
                    if state.depth.saturating_add(1) >= self.max_depth {
                        break;
                    }
                    let wi = -ray.d;
                    let r = LightRef {
                        p,
                        n: wi,
                        hemisphere: false,
                        mis: true,
                        resolved_density: 0.0,
                        resampled: false,
                    };
                    if m.sample_emitters {
                        let u = (sampler.next_1d(), sampler.next_2d());
                        l += state.beta * self.phase_next_event(media, m, medium, &r, wi, u, sampler, wl);
                    }
                    let ps = m.phase.sample(p, wi, sampler.next_2d());
                    if !(ps.pdf > 0.0) {
                        break;
                    }
                    state.prev = Some(PrevVertex {
                        light_ref: r,
                        bsdf_pdf: ps.pdf,
                        // Without light samples here, the emission BSDF sampling finds counts
                        // whole.
                        delta: !m.sample_emitters,
                    });
                    state.depth += 1;
                    state.null_crossings = 0;
                    ray = Ray::new(p, ps.wo);
                    if !self.russian_roulette(&mut state, sampler) {
                        break;
                    }
                    continue;
                }
                if state.beta.is_black() {
                    break;
                }
            }
            // The surface is reached: its interaction now.
            let hit = match media.medium(medium) {
                Some(_) => lazy.map(|h| self.accel.complete(&ray, h)),
                None => self.accel.intersect(&ray),
            };
            let show = !(self.hide_emitters && state.depth == 0);
            let Some(si) = hit else {
                if show {
                    self.add_escaped(&mut l, &state, ray.d, wl);
                }
                break;
            };
            if show {
                self.add_emitted(&mut l, &state, &si, ray.d, wl);
            }
            let Some(material) = self.material_of(si.shape) else {
                break;
            };
            material.fill_bsdf_at(&ShadingPoint::from(&si), wl, &mut bsdf);
            let flags = bsdf.flags();
            let wi = si.shading.to_local(-ray.d);
            let smooth = flags.has_smooth();
            // At the last segment only a straight pass (a `null` or `thindielectric` surface's
            // NULL lobe, no scattering event) may go on, as in Mitsuba.
            let at_limit = state.depth.saturating_add(1) >= self.max_depth;
            if at_limit && !flags.contains(BsdfFlags::NULL) {
                break;
            }
            let interface = media.interface(si.shape);
            if smooth && !at_limit {
                let (u_sel, u) = (sampler.next_1d(), sampler.next_2d());
                let r = self.surface_light_ref(&si, wi, flags);
                l += state.beta
                    * self.surface_next_event(
                        media,
                        &bsdf,
                        &si,
                        wi,
                        interface,
                        medium,
                        &r,
                        (u_sel, u),
                        sampler,
                        wl,
                    );
            }
            let ctx = BsdfContext::radiance();
            let Some(bs) = bsdf
                .sample(&ctx, wi, sampler.next_1d(), sampler.next_2d(), wl)
                .filter(|bs| {
                    bs.weight.is_finite() && !bs.weight.is_black() && (bs.flags.is_delta() || bs.pdf > 0.0)
                })
            else {
                break;
            };
            let dir = si.shading.to_world(bs.wo);
            ray = si.spawn_ray(dir);
            medium = interface.target(dir, si.n, medium);
            if bs.flags.contains(BsdfFlags::NULL) {
                // Straight through: the MIS state and depth of the last scattering event stay.
                if !state.cross_sheet(bs.weight) {
                    break;
                }
                continue;
            }
            if at_limit {
                break;
            }
            state.beta *= bs.weight;
            state.eta *= bs.eta;
            state.prev = Some(PrevVertex {
                light_ref: self.surface_light_ref(&si, wi, flags),
                bsdf_pdf: bs.pdf,
                delta: bs.flags.is_delta(),
            });
            state.depth += 1;
            // The bound on sheets counts those between two scattering events (a path in and
            // out of a fog box crosses many in all).
            state.null_crossings = 0;
            if !self.russian_roulette(&mut state, sampler) {
                break;
            }
        }
        if l.is_finite() {
            l
        } else {
            SampledSpectrum::splat(0.0)
        }
    }

    /// The flight of `ray` through medium `m`: the surface it reaches (`None` where it escapes
    /// or scatters first), the scattering event's point (`None` when the ray reaches a surface or
    /// escapes) and the throughput's factor (σs included at a scattering event). In a homogeneous
    /// medium the distance is drawn first and the surface looked for only up to it (Mitsuba's
    /// order: in a dense medium most queries are short).
    fn fly(
        &self,
        m: &Medium,
        ray: &Ray,
        sampler: &mut impl PathSampler,
        wl: &SampledWavelengths,
    ) -> (Option<LazyHit>, Option<Vec3>, SampledSpectrum) {
        match m.uniform_sigma_t(ray.d, wl) {
            // Only absorption: the transmittance, nothing drawn.
            Some(sigma_t) if m.absorbs_only() => {
                let hit = self.accel.intersect_lazy(ray);
                let t_max = hit.as_ref().map_or(ray.tmax, LazyHit::t);
                (hit, None, transmittance(sigma_t, t_max))
            }
            Some(sigma_t) => {
                let t = sample_distance(sigma_t, sampler.next_1d(), wl);
                let hit = self.accel.intersect_lazy(&Ray {
                    tmax: ray.tmax.min(t),
                    ..*ray
                });
                match hit {
                    None if t < ray.tmax => {
                        let p = ray.at(t);
                        let w = flight_weight(sigma_t, t, true, wl) * m.albedo(p, wl) * sigma_t;
                        (None, Some(p), w)
                    }
                    _ => {
                        let t_max = hit.as_ref().map_or(ray.tmax, LazyHit::t);
                        (hit, None, flight_weight(sigma_t, t_max, false, wl))
                    }
                }
            }
            None => {
                let hit = self.accel.intersect_lazy(ray);
                let t_max = hit.as_ref().map_or(ray.tmax, LazyHit::t);
                if let Some(sigma_t) = m.box_sigma_t(ray.d, wl) {
                    // A constant inside a box: drawn exactly over the part inside.
                    let Some((t0, t1)) = m.extent(ray.o, ray.d, t_max) else {
                        return (hit, None, SampledSpectrum::splat(1.0));
                    };
                    let len = t1 - t0;
                    if m.absorbs_only() {
                        return (hit, None, transmittance(sigma_t, len));
                    }
                    let t = sample_distance(sigma_t, sampler.next_1d(), wl);
                    if t < len {
                        let p = ray.at(t0 + t);
                        let w = flight_weight(sigma_t, t, true, wl) * m.albedo(p, wl) * sigma_t;
                        return (None, Some(p), w);
                    }
                    return (hit, None, flight_weight(sigma_t, len, false, wl));
                }
                let (collision, w) = self.track(m, ray, t_max, sampler, wl);
                (if collision.is_some() { None } else { hit }, collision, w)
            }
        }
    }

    /// Delta tracking through a grid medium up to the surface at `t_max` (see [`Self::fly`]):
    /// the scattering event's point, if any, and the throughput's factor; a grid that only
    /// absorbs takes its transmittance.
    fn track(
        &self,
        m: &Medium,
        ray: &Ray,
        t_max: f32,
        sampler: &mut impl PathSampler,
        wl: &SampledWavelengths,
    ) -> (Option<Vec3>, SampledSpectrum) {
        if m.absorbs_only() {
            return (None, self.medium_transmittance(m, ray, t_max, sampler, wl));
        }
        let one = SampledSpectrum::splat(1.0);
        let bar = m.majorant();
        let Some((t0, t1)) = m.extent(ray.o, ray.d, t_max).filter(|_| bar > 0.0) else {
            return (None, one);
        };
        let (mut t, mut w) = (t0, one);
        for _ in 0..MAX_TRACKING_STEPS {
            t += -(1.0 - sampler.next_1d()).ln() / bar;
            if t >= t1 {
                return (None, w);
            }
            let p = ray.at(t);
            let sigma_t = m.sigma_t_at(p, ray.d, wl);
            match null_collision_event(sigma_t, bar, sampler.next_1d(), wl) {
                Tracking::Real(f) => return (Some(p), w * f * m.albedo(p, wl) * sigma_t),
                Tracking::Null(f) => {
                    w *= f;
                    if w.is_black() {
                        return (None, w);
                    }
                }
            }
        }
        (None, SampledSpectrum::splat(0.0))
    }

    /// The transmittance of medium `m` along `ray` up to `t_max`: exact where σt is constant,
    /// by ratio tracking in a grid (each tentative collision multiplies by σn/σ̄).
    fn medium_transmittance(
        &self,
        m: &Medium,
        ray: &Ray,
        t_max: f32,
        sampler: &mut impl PathSampler,
        wl: &SampledWavelengths,
    ) -> SampledSpectrum {
        if let Some(sigma_t) = m.uniform_sigma_t(ray.d, wl) {
            return transmittance(sigma_t, t_max);
        }
        if let Some(sigma_t) = m.box_sigma_t(ray.d, wl) {
            return match m.extent(ray.o, ray.d, t_max) {
                Some((t0, t1)) => transmittance(sigma_t, t1 - t0),
                None => SampledSpectrum::splat(1.0),
            };
        }
        let bar = m.majorant();
        let one = SampledSpectrum::splat(1.0);
        let Some((t0, t1)) = m.extent(ray.o, ray.d, t_max).filter(|_| bar > 0.0) else {
            return one;
        };
        let (mut t, mut tr) = (t0, one);
        for _ in 0..MAX_TRACKING_STEPS {
            t += -(1.0 - sampler.next_1d()).ln() / bar;
            if t >= t1 {
                return tr;
            }
            tr *= (1.0 - m.sigma_t_at(ray.at(t), ray.d, wl) * (1.0 / bar)).clamp_zero();
            if tr.is_black() {
                return tr;
            }
        }
        SampledSpectrum::splat(0.0)
    }

    /// Where lights are sampled from at a surface (as the path tracer's [`PathTracer::light_ref`]).
    fn surface_light_ref(&self, si: &SurfaceInteraction, wi: Vec3, flags: BsdfFlags) -> LightRef {
        LightRef {
            p: si.p,
            n: if wi.z >= 0.0 { si.shading.n } else { -si.shading.n },
            hemisphere: !flags.is_transmission(),
            mis: true,
            resolved_density: 0.0,
            resampled: false,
        }
    }

    /// Next-event estimation at a scattering event in medium `m` (id `id`) at `r.p`:
    /// p·Lᵢ·T/p_light·w, w the power heuristic against the phase function's density.
    #[allow(clippy::too_many_arguments)]
    fn phase_next_event(
        &self,
        media: &Media<'_>,
        m: &Medium,
        id: Option<MediumId>,
        r: &LightRef,
        wi: Vec3,
        u: (f32, Vec2),
        sampler: &mut impl PathSampler,
        wl: &SampledWavelengths,
    ) -> SampledSpectrum {
        let mut sum = SampledSpectrum::splat(0.0);
        self.lights
            .for_each_sample(self.accel.shapes(), r, u, wl, |_, ls| {
                let f = m.phase.eval(r.p, wi, ls.wi);
                if !(f > 0.0) {
                    return;
                }
                let ray = match ls.dist.is_finite() {
                    true => spawn_ray_between(r.p, Vec3::ZERO, r.p + ls.wi * ls.dist, ls.normal),
                    false => Ray::new(r.p, ls.wi),
                };
                let t = self.transmittance_through(media, ray, id, sampler, wl);
                if t.is_black() {
                    return;
                }
                let w = if ls.delta { 1.0 } else { self.mis(ls.pdf, f) };
                sum += ls.li * t * (f * w / ls.pdf);
            });
        sum
    }

    /// Next-event estimation at a surface vertex: f·|cos|·Lᵢ·T/p·w, the shadow ray starting in
    /// the medium on the side it leaves to.
    #[allow(clippy::too_many_arguments)]
    fn surface_next_event(
        &self,
        media: &Media<'_>,
        bsdf: &SurfaceBsdf<'_>,
        si: &SurfaceInteraction,
        wi: Vec3,
        interface: MediumInterface,
        medium: Option<MediumId>,
        r: &LightRef,
        u: (f32, Vec2),
        sampler: &mut impl PathSampler,
        wl: &SampledWavelengths,
    ) -> SampledSpectrum {
        let mut sum = SampledSpectrum::splat(0.0);
        let ctx = BsdfContext::radiance();
        self.lights
            .for_each_sample(self.accel.shapes(), r, u, wl, |_, ls| {
                let wo = si.shading.to_local(ls.wi);
                let (f, pdf) = bsdf.eval_pdf(&ctx, wi, wo, wl);
                if f.is_black() {
                    return;
                }
                let ray = if ls.dist.is_finite() {
                    si.spawn_ray_to(si.p + ls.wi * ls.dist, ls.normal)
                } else {
                    si.spawn_ray(ls.wi)
                };
                let start = interface.target(ls.wi, si.n, medium);
                let t = self.transmittance_through(media, ray, start, sampler, wl);
                if t.is_black() {
                    return;
                }
                let w = if ls.delta { 1.0 } else { self.mis(ls.pdf, pdf) };
                sum += f * ls.li * t * (wo.z.abs() * w / ls.pdf);
            });
        sum
    }

    /// The transmittance along the shadow ray `ray` that starts in medium `medium`: the media's
    /// exp(−σt·d) over its segments and the null transmission of the surfaces it crosses (0 at
    /// any other surface).
    fn transmittance_through(
        &self,
        media: &Media<'_>,
        mut ray: Ray,
        mut medium: Option<MediumId>,
        sampler: &mut impl PathSampler,
        wl: &SampledWavelengths,
    ) -> SampledSpectrum {
        let mut tr = SampledSpectrum::splat(1.0);
        let dir = ray.d;
        // As many sheets as a segment of the path crosses ([`MAX_NULL_CROSSINGS`]), then the end.
        for crossed in 0..=MAX_NULL_CROSSINGS {
            let hit = self.accel.intersect(&ray);
            if let Some(m) = media.medium(medium) {
                let t_max = hit.as_ref().map_or(ray.tmax, |h| h.t);
                tr *= self.medium_transmittance(m, &ray, t_max, sampler, wl);
            }
            let Some(h) = hit else {
                return tr;
            };
            if tr.is_black() {
                return tr;
            }
            if crossed == MAX_NULL_CROSSINGS {
                return SampledSpectrum::splat(0.0);
            }
            let Some((t, next)) = self.pass_sheet::<SampledSpectrum>(&h, &ray, dir, wl, false) else {
                return SampledSpectrum::splat(0.0);
            };
            tr *= t;
            medium = media.interface(h.shape).target(ray.d, h.n, medium);
            match next {
                Some(r) if !tr.is_black() => ray = r,
                _ => return tr,
            }
        }
        SampledSpectrum::splat(0.0)
    }
}
