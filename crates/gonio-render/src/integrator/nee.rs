//! Next-event estimation from a camera-path vertex and the shadow rays it traces: where lights
//! are sampled from ([`PathTracer::light_ref`]), one light sample with its MIS weight
//! ([`PathTracer::next_event`], shared by `path` and `direct`), and visibility through
//! `thindielectric` sheets ([`PathTracer::visibility`], one sheet at a time by
//! [`PathTracer::pass_sheet`], which the walk through glass of [`super::refracted`] uses too).

use super::{MAX_NULL_CROSSINGS, PathTracer, Vertex, refracted};
use crate::accel::Intersect;
use crate::emitter::{LightRef, LightSample};
use crate::geometry::{Ray, SurfaceInteraction};
use crate::material::ShadingPoint;
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::weight::{BsdfWeight, Weight};
use gonio_core::{Bsdf, BsdfContext, BsdfFlags, SampledWavelengths};

impl PathTracer<'_> {
    /// Where lights are sampled from at vertex `v` (its side of the shading normal; a whole
    /// sphere of directions when the BSDF transmits); `mis` when the BSDF is sampled there too
    /// ([`LightRef::mis`]), with the lights BSDF sampling resolves alone there
    /// ([`LightRef::resolved_density`]) where they may be left to it (`narrow_lobes`).
    pub(super) fn light_ref(&self, v: &Vertex, flags: BsdfFlags, mis: bool) -> LightRef {
        let n_side = if v.wi.z >= 0.0 {
            v.si.shading.n
        } else {
            -v.si.shading.n
        };
        LightRef {
            p: v.si.p,
            n: n_side,
            hemisphere: !flags.is_transmission(),
            mis,
            resolved_density: if mis && self.narrow_lobes {
                v.bsdf.resolved_light_density(v.wi)
            } else {
                0.0
            },
            resampled: false,
        }
    }

    /// Next-event estimation from `v`: β·f·|cos|·Lᵢ·T/p·w for one light sample (`u_sel` picks
    /// the light, `u` the point), w the power heuristic against the BSDF density. `counts`
    /// (light samples, BSDF samples) scale the two densities in the heuristic (`(1, 1)` for the
    /// path tracer; `direct` takes several of each). With `path` (the camera path's state at
    /// `v`, given where refracted next-event estimation takes part), a sample whose shadow ray
    /// meets glass is followed through it ([`refracted`]).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn next_event<W: Weight>(
        &self,
        v: &Vertex,
        r: &LightRef,
        beta: W,
        u_sel: f32,
        u: Vec2,
        wl: &SampledWavelengths,
        counts: (f32, f32),
        path: Option<&refracted::PathContext>,
    ) -> W
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        if r.resampled {
            return self.resampled_next_events(v, r, beta, (u_sel, u), wl, counts, path);
        }
        let mut sum = W::ZERO;
        self.lights
            .for_each_sample(self.accel.shapes(), r, (u_sel, u), wl, |li, ls| {
                sum += self.light_contribution(v, beta, (li, ls), wl, counts, path);
            });
        sum
    }

    /// [`Self::next_event`] where resampled next-event estimation takes the map's turn
    /// ([`LightRef::resampled`]): the map's light by [`Self::resampled_next_event`] (divided by
    /// the probability of choosing the map, when one light is chosen), every other light's by
    /// its own light sample, as at any vertex.
    #[allow(clippy::too_many_arguments)]
    fn resampled_next_events<W: Weight>(
        &self,
        v: &Vertex,
        r: &LightRef,
        beta: W,
        (u_sel, u): (f32, Vec2),
        wl: &SampledWavelengths,
        counts: (f32, f32),
        path: Option<&refracted::PathContext>,
    ) -> W
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        let Some(map) = self.lights.sole_envmap() else {
            return W::ZERO;
        };
        let (mut own, mut others) = (W::ZERO, W::ZERO);
        self.lights.for_each_sample_but(
            self.accel.shapes(),
            r,
            (u_sel, u),
            wl,
            map,
            |p_turn, u_rest| own += self.resampled_next_event(v, beta, u_rest, u, wl) * (1.0 / p_turn),
            |li, ls| others += self.light_contribution(v, beta, (li, ls), wl, counts, path),
        );
        own + others
    }

    /// One light sample `ls` of light `li` (density `ls.pdf`, selection included) at `v`:
    /// β·f·|cos|·Lᵢ·T/p·w (see [`Self::next_event`]).
    fn light_contribution<W: Weight>(
        &self,
        v: &Vertex,
        beta: W,
        (li, ls): (usize, &LightSample),
        wl: &SampledWavelengths,
        counts: (f32, f32),
        path: Option<&refracted::PathContext>,
    ) -> W
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        let wo = v.si.shading.to_local(ls.wi);
        let ctx = BsdfContext::radiance();
        let (f, bsdf_pdf): (W, f32) = (
            v.bsdf
                .eval_weight(&ctx, v.wi, wo, wl)
                .local_to_world(&v.si.shading),
            v.bsdf.pdf(&ctx, v.wi, wo, wl),
        );
        if f.is_black() {
            return W::ZERO;
        }
        let t = match path {
            // Through glass too ([`refracted`]).
            Some(c) => match self.trace_light_sample::<W>(v, c, li, ls, bsdf_pdf, wl) {
                refracted::LightPath::Straight(t) => t,
                refracted::LightPath::Refracted(tr, le, w) => {
                    return (beta * f).through_then_source(tr, le) * (wo.z.abs() * w / ls.pdf);
                }
                refracted::LightPath::Blocked => return W::ZERO,
            },
            _ => self.transmittance(v.si, ls, wl),
        };
        if t.is_black() {
            return W::ZERO;
        }
        let w = if ls.delta {
            1.0
        } else {
            self.mis(ls.pdf * counts.0, bsdf_pdf * counts.1)
        };
        // Light order: the source, the sheets the shadow ray crossed, then f (a polarized path
        // does not commute).
        (beta * f).through_then_source(t, ls.li) * (wo.z.abs() * w / ls.pdf)
    }

    /// Visibility of a light sample from `si`: 0/1, or with thin shadows the transmittance of the
    /// sheets crossed.
    fn transmittance<W: Weight>(
        &self,
        si: &SurfaceInteraction,
        ls: &LightSample,
        wl: &SampledWavelengths,
    ) -> W
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        let ray = if ls.dist.is_finite() {
            si.spawn_ray_to(si.p + ls.wi * ls.dist, ls.normal)
        } else {
            si.spawn_ray(ls.wi)
        };
        self.visibility(ray, wl, false)
    }

    /// Visibility along a shadow ray: 0/1, or with thin shadows the transmittance of the sheets
    /// crossed, for light travelling towards the ray's origin, or along the ray when
    /// `light_along_ray` (a light vertex's connection to the camera). The direction matters only
    /// for the Stokes bases of a polarized transmittance.
    pub(super) fn visibility<W: Weight>(&self, ray: Ray, wl: &SampledWavelengths, light_along_ray: bool) -> W
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        if !(self.thin_shadows && self.any_thin) {
            return if self.accel.occluded(&ray) {
                W::ZERO
            } else {
                W::ONE
            };
        }
        let dir = ray.d;
        let mut ray = ray;
        let mut tr = W::ONE;
        // As many sheets as a path's segment crosses ([`MAX_NULL_CROSSINGS`]), then the light.
        for crossed in 0..=MAX_NULL_CROSSINGS {
            let Some(h) = self.accel.intersect(&ray) else {
                return tr;
            };
            if !self.is_thin(h.shape) || crossed == MAX_NULL_CROSSINGS {
                return W::ZERO;
            }
            let Some((t, next)) = self.pass_sheet::<W>(&h, &ray, dir, wl, light_along_ray) else {
                return W::ZERO;
            };
            // Light order: a sheet nearer the light first.
            tr = if light_along_ray { t * tr } else { tr * t };
            if tr.is_black() {
                return tr;
            }
            match next {
                Some(r) => ray = r,
                None => return tr,
            }
        }
        W::ZERO
    }

    /// A shadow ray's straight pass through the sheet it hit at `h`: the sheet's transmittance
    /// (for light travelling towards the ray's origin, or along the ray when `light_along_ray`)
    /// and the ray on towards the same end point, `None` once that is reached; `None` when the
    /// sheet lets nothing through.
    pub(super) fn pass_sheet<W: Weight>(
        &self,
        h: &SurfaceInteraction,
        ray: &Ray,
        dir: Vec3,
        wl: &SampledWavelengths,
        light_along_ray: bool,
    ) -> Option<(W, Option<Ray>)>
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        // The transmittance along the segment's own direction `dir`, the same at every sheet of
        // it (the ray's, below, is re-aimed at each: a polarized path's Stokes bases follow
        // `dir`).
        let wi = h.shading.to_local(if light_along_ray { dir } else { -dir });
        let t = self
            .bsdf_at(h.shape, &ShadingPoint::from(h), wl, |bsdf: &SurfaceBsdf<'_>| {
                bsdf.null_transmission_weight(wi, wl)
                    .map(|t| t.local_to_world(&h.shading))
            })
            .flatten()?;
        // On from the sheet towards the same end point (already offset off the light), aimed at
        // it: the origin's offset off the sheet is along the sheet's normal, and a ray kept
        // parallel would end that much beside the point; past a few oblique sheets its end
        // reached the light's own surface, which then blocked the shadow ray (a floor under an
        // area light, lit through ten null sheets, came out 0.71 of its brightness).
        let o = crate::geometry::offset_ray_origin(h.p, h.n, ray.d);
        let next = if ray.tmax.is_finite() {
            let to_end = ray.o + ray.d * ray.tmax - o;
            let (along, length) = (to_end.dot(ray.d), to_end.length());
            // A segment too long (a far clip of 1e20) or too short to square stays parallel.
            (along > 0.0).then(|| {
                if length.is_finite() && length > 0.0 {
                    Ray {
                        o,
                        d: to_end / length,
                        tmax: length,
                    }
                } else {
                    Ray {
                        o,
                        d: ray.d,
                        tmax: along,
                    }
                }
            })
        } else {
            Some(Ray {
                o,
                d: ray.d,
                tmax: f32::INFINITY,
            })
        };
        Some((t, next))
    }
}
