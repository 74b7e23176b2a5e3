//! The state a camera path carries from one vertex to the next, and what a step does to it: the
//! next state along a sampled (or split) lobe ([`PathTracer::advance`] in place,
//! [`PathTracer::advanced`] as a copy), Russian roulette, and the emission the path meets,
//! weighted by MIS against every strategy that could have found it
//! ([`PathTracer::add_escaped`], [`PathTracer::add_emitted`]). The loop (`PathTracer::trace`) and
//! lobe splitting ([`super::lobe_split`]) both go through these, so a path's MIS weights are the
//! same functions whichever way it was reached.

use super::{PathTracer, Vertex, caustics, manifold, refracted};
use crate::accel::Intersect;
use crate::emitter::{Light, LightRef};
use crate::geometry::{Ray, SurfaceInteraction};
use crate::sampler::PathSampler;
use glam::Vec3;
use gonio_core::weight::Weight;
use gonio_core::{BsdfSample, SampledSpectrum, SampledWavelengths};

/// The last real scattering vertex of a camera path, for the MIS weight of a light that the
/// direction sampled there finds.
#[derive(Clone, Copy, Debug)]
pub(super) struct PrevVertex {
    /// Where a light would have been sampled from.
    pub(super) light_ref: LightRef,
    /// BSDF density of the direction taken.
    pub(super) bsdf_pdf: f32,
    /// True when that direction came from a delta lobe.
    pub(super) delta: bool,
}

/// The state a camera path carries from one vertex to the next.
///
/// Generic over what the path carries ([`Weight`]): a spectrum today, a Mueller matrix for a
/// polarized renderer (Mitsuba 3's design: throughput and radiance are the same type, emitters
/// depolarized; the film observes [`Weight::intensity`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct PathState<W: Weight = SampledSpectrum> {
    /// Throughput β.
    pub(super) beta: W,
    /// Product of the relative indices of refraction crossed (for Russian roulette).
    pub(super) eta: f32,
    /// Real scattering events so far (straight passes through sheets do not count).
    pub(super) depth: u32,
    /// Straight passes through sheets since the last real scattering event (each segment may
    /// cross [`super::MAX_NULL_CROSSINGS`], as each shadow ray may).
    pub(super) null_crossings: u32,
    /// The last real scattering vertex; `None` at the camera.
    pub(super) prev: Option<PrevVertex>,
    /// The last smooth vertex and the delta chain after it, for the MIS weight against the
    /// light-path connections ([`caustics`]).
    pub(super) chain: Option<caustics::ChainState>,
    /// The last smooth vertex and the refractions after it, for the MIS weight against refracted
    /// next-event estimation ([`refracted`]).
    pub(super) refr: Option<refracted::RefractedStart>,
    /// The last smooth vertex after a delta one and the mirror sphere after it, for the MIS
    /// weight against manifold next-event estimation ([`manifold`]).
    pub(super) mnee: Option<manifold::Start>,
}

impl<W: Weight> PathState<W> {
    pub(super) const CAMERA: Self = Self {
        beta: W::ONE,
        eta: 1.0,
        depth: 0,
        null_crossings: 0,
        prev: None,
        chain: None,
        refr: None,
        mnee: None,
    };

    /// The previous vertex when it sampled a smooth lobe: a light found from there is weighted
    /// against light sampling.
    #[inline]
    pub(super) fn smooth_prev(&self) -> Option<&PrevVertex> {
        self.prev.as_ref().filter(|p| !p.delta)
    }

    /// True right after a delta lobe.
    #[inline]
    pub(super) fn after_delta(&self) -> bool {
        matches!(self.prev, Some(PrevVertex { delta: true, .. }))
    }

    /// A straight pass through a sheet (`thin_shadows`): the throughput times the sheet's
    /// transmission `w`, the depth and the previous vertex's MIS state kept. False when the path
    /// ends there (more than [`super::MAX_NULL_CROSSINGS`] sheets on this segment, or no
    /// throughput left).
    #[inline]
    pub(super) fn cross_sheet(&mut self, w: W) -> bool {
        self.beta *= w;
        self.null_crossings += 1;
        self.null_crossings <= super::MAX_NULL_CROSSINGS && !self.beta.is_black()
    }
}

/// What a vertex's continuation carries into the path's next state (besides the BSDF sample):
/// see [`PathTracer::advanced`].
pub(super) struct StepFrom {
    pub(super) light_ref: LightRef,
    /// Manifold next-event estimation took part at the vertex.
    pub(super) manifold_here: bool,
    /// How the vertex was reached, for the light subpaths' MIS.
    pub(super) arrival: caustics::Arrival,
    /// |cos| between the geometric normal and the direction the path arrived from.
    pub(super) cos_in: f32,
}

impl PathTracer<'_> {
    /// Russian roulette, from `rr_depth` on (its number is drawn only there: a function of the
    /// depth, so the dimensions of paths of the same shape stay aligned): false when the path
    /// ends.
    #[inline]
    pub(super) fn russian_roulette<W: Weight>(
        &self,
        state: &mut PathState<W>,
        sampler: &mut impl PathSampler,
    ) -> bool {
        let beta_max = state.beta.intensity().max_component();
        if state.depth >= self.rr_depth {
            let u_rr = sampler.next_1d();
            let q = (self.rr_scale * beta_max * state.eta * state.eta).min(self.rr_survival);
            if !(u_rr < q) {
                return false;
            }
            state.beta /= q;
        }
        beta_max > 0.0 && state.beta.intensity().is_finite()
    }

    /// Adds the lights at infinity seen along `d` by a ray that left the scene.
    pub(super) fn add_escaped<W: Weight>(
        &self,
        l: &mut W,
        state: &PathState<W>,
        d: Vec3,
        wl: &SampledWavelengths,
    ) {
        let prev = state.smooth_prev();
        for &i in self.lights.infinite() {
            let (le, pdf_light) = self
                .lights
                .le_escaped(prev.map(|p| &p.light_ref), i as usize, d, wl);
            if le.is_black() {
                continue;
            }
            let w = match prev {
                Some(p) => self.mis(p.bsdf_pdf, pdf_light),
                // From the camera or after a delta lobe: refracted next-event estimation may
                // have found this path too.
                None => refracted::shares(
                    f32::INFINITY,
                    self.refracted_ratio(state.refr.as_ref(), i as usize, wl),
                )[0],
            };
            *l += state.beta * W::from_spectrum(le) * w;
        }
    }

    /// Adds the emission of an area light hit at `si` (along `d`) from its front side.
    pub(super) fn add_emitted<W: Weight>(
        &self,
        l: &mut W,
        state: &PathState<W>,
        si: &SurfaceInteraction,
        d: Vec3,
        wl: &SampledWavelengths,
    ) {
        let Some(li) = self.lights.shape_light(si.shape as usize) else {
            return;
        };
        let Light::Area(area) = &self.lights.lights()[li] else {
            return;
        };
        let le = area.le(&si.into(), -d, wl);
        if le.is_black() {
            return;
        }
        let w = match state.smooth_prev() {
            Some(p) => self.mis(
                p.bsdf_pdf,
                self.lights.pdf_li_hit(self.accel.shapes(), &p.light_ref, li, si),
            ),
            // From the camera or after a delta lobe: light paths, refracted and manifold
            // next-event estimation may have found this path too (the last only where the first
            // two cannot: a path through a mirror sphere from a vertex after a delta one).
            None => {
                let r = self.caustic_ratio(state.chain.as_ref(), li, area, si.p, si.n, -d);
                let s = self.refracted_ratio(state.refr.as_ref(), li, wl);
                let m = self.manifold_ratio(state.mnee.as_ref(), li, si);
                refracted::shares(r, s)[0] * self.mis(1.0, m)
            }
        };
        *l += state.beta * W::from_spectrum(le) * w;
    }

    /// The path's state after it follows `bs` (its weight already divided by any choice) from
    /// vertex `v` along `ray`: the throughput, and what the next vertex's emission and MIS
    /// weights read of this one (`reverse_pdf`: the light tracer's density of the reverse
    /// direction, where the caustics need it).
    pub(super) fn advanced<W: Weight>(
        &self,
        state: &PathState<W>,
        bs: &BsdfSample<W>,
        v: &Vertex,
        ray: &Ray,
        from: &StepFrom,
        reverse_pdf: f32,
    ) -> PathState<W> {
        let mut next = *state;
        self.advance(&mut next, bs, v, ray, from, reverse_pdf);
        next
    }

    /// [`Self::advanced`] in place (the path loop's step: the state is a few hundred bytes).
    pub(super) fn advance<W: Weight>(
        &self,
        state: &mut PathState<W>,
        bs: &BsdfSample<W>,
        v: &Vertex,
        ray: &Ray,
        from: &StepFrom,
        reverse_pdf: f32,
    ) {
        let si = v.si;
        let dir = ray.d;
        state.beta *= bs.weight;
        state.eta *= bs.eta;
        state.mnee = self.manifold_after_sample(state.mnee, from.manifold_here, (si, dir), bs);
        if self.refracted_nee {
            state.refr = if bs.flags.is_delta() {
                self.refracted_after_delta(state.refr, si.shape, bs)
            } else {
                Some(refracted::RefractedStart::new(from.light_ref, *ray, bs.pdf))
            };
        }
        if self.traces_caustics() {
            state.chain = caustics::ChainState::after_sample(
                state.chain,
                bs,
                from.arrival,
                from.cos_in,
                si.n.dot(dir).abs(),
                reverse_pdf,
            );
        }
        state.prev = Some(PrevVertex {
            light_ref: from.light_ref,
            bsdf_pdf: bs.pdf,
            delta: bs.flags.is_delta(),
        });
        state.depth += 1;
        state.null_crossings = 0;
    }
}
