//! Tracing one light subpath (see the parent module for the strategy and its MIS weights), in
//! named steps: [`PathTracer::emit_light_path`] starts it on an area light, and each surface hit
//! goes through [`PathTracer::light_path_vertex`]: keep a smooth vertex and connect it to the
//! camera ([`PathTracer::keep_light_vertex`]), sample the BSDF in importance mode, then
//! [`PathTracer::advance_light_walk`] (shading-normal correction, sheets, MIS densities, Russian
//! roulette).
//!
//! Generic over what the subpath carries (`L`): a spectrum, or in polarized mode a Mueller
//! matrix. The emitter is unpolarized (a depolarizer), and each vertex's importance-mode matrix
//! (light arriving along −ωᵢ, leaving along ωₒ: [`gonio_core::bsdf::light_directions`]) is
//! mapped to the implicit world bases of its beams and applied after what came before:
//! β ← M·β, so β's first column is the Stokes vector of the light travelling along the walk.

use super::super::{MAX_NULL_CROSSINGS, PathSampler, PathTracer};
use super::{EmissionSampler, LightSubpath, LightVertex, MAX_CHAIN, RefractedDensity};
use crate::accel::Intersect;
use crate::camera::Camera;
use crate::emitter::Light;
use crate::geometry::sampling::sample_area;
use crate::geometry::{Ray, SurfaceInteraction, offset_ray_origin, spawn_ray_between};
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::weight::{BsdfWeight, Weight};
use gonio_core::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, SampledWavelengths};

/// A light subpath being traced: where it goes and what it carries.
#[derive(Clone, Copy, Debug)]
struct LightWalk<L> {
    /// Index of the light it started from.
    light: usize,
    ray: Ray,
    /// Emitted radiance over the sampling densities, times the vertices' weights.
    beta: L,
    /// The vertices' weights alone (Russian roulette looks at their intensity).
    throughput: L,
    /// Product of the relative indices crossed since the light.
    eta: f32,
    /// The light-side density of the MIS ratio ([`LightVertex`]'s `light_density`).
    light_density: f32,
    /// Delta vertices so far.
    deltas: u32,
    /// Segments from the light so far.
    segments: u32,
    /// True when the last vertex (or the light itself) was smooth: the next must be a delta.
    after_smooth: bool,
    /// Straight passes through sheets since the last real scattering event.
    null_crossings: u32,
    /// True while refracted next-event estimation could produce the path so far in reverse: the
    /// light is one it ends on and every delta vertex was a refraction at a refractor.
    refracted_ok: bool,
    /// At the first smooth vertex: its [`RefractedDensity::Here`] numerators; after it, the
    /// ratio `s` there ([`RefractedDensity::Earlier`]); `None` while no smooth vertex was met.
    refracted: Option<RefractedDensity>,
}

/// What a light subpath needs besides its state: the emission sampler, the camera, and where
/// its vertices and camera connections go.
struct LightPathSink<'c, F, L> {
    emission: &'c EmissionSampler,
    camera: &'c dyn Camera,
    splat: &'c mut F,
    out: &'c mut LightSubpath<L>,
}

/// A surface hit of a light subpath.
struct LightHit<'h> {
    si: &'h SurfaceInteraction,
    /// Direction back towards the light, in the shading frame.
    wi: Vec3,
    /// |ω_in·n_g|.
    cos_in_g: f32,
}

impl PathTracer<'_> {
    /// Traces one light subpath with the camera sample's wavelengths `wl`: keeps its vertices in
    /// `out` (cleared first) for [`PathTracer::li`] and hands each connection to the camera to
    /// `splat` as (film position, unnormalized pixel estimate, wavelengths); the caller sums
    /// those into an image and divides by the number of light subpaths. Does nothing unless
    /// [`PathTracer::traces_caustics`]. In polarized mode (`L = Mueller`) a splatted matrix's
    /// output basis is the implicit basis of the beam towards the camera and its first column
    /// the Stokes vector that arrives.
    pub fn trace_light_path<L: Weight>(
        &self,
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
        splat: &mut impl FnMut(Vec2, L, &SampledWavelengths),
        out: &mut LightSubpath<L>,
    ) where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<L>,
    {
        out.clear();
        let (Some(emission), Some(camera)) = (&self.caustics, self.camera) else {
            return;
        };
        let Some(mut walk) = self.emit_light_path(emission, sampler, wl) else {
            return;
        };
        let mut sink = LightPathSink {
            emission,
            camera,
            splat,
            out,
        };
        while let Some(si) = self.accel.intersect(&walk.ray) {
            if !self.light_path_vertex(&mut sink, &mut walk, &si, sampler, wl) {
                break;
            }
        }
    }

    /// The start of a light subpath: a light chosen by power (for a fraction `rate` of the
    /// camera samples), a uniform point on it, a direction aimed at the delta shapes;
    /// `β = Lₑ·cos θ_l/(p_sel·p_A·p_ω)`. `None` when this sample traces no light subpath.
    fn emit_light_path<L: Weight>(
        &self,
        emission: &EmissionSampler,
        sampler: &mut impl PathSampler,
        wl: &SampledWavelengths,
    ) -> Option<LightWalk<L>> {
        let u_sel = sampler.next_1d();
        let u_pos = sampler.next_2d();
        let u_dir = sampler.next_2d();
        // The shortest such path has three segments: light, delta vertex, y, and one more to x.
        if self.max_depth < 3 {
            return None;
        }
        // A light subpath for a fraction `rate` of the camera samples: the rate acts as part of
        // the light's selection probability.
        if !(u_sel < emission.rate) {
            return None;
        }
        let (k, p_sel, u_pick) = emission.selection.sample_discrete(u_sel / emission.rate);
        let p_sel = p_sel * emission.rate;
        let li = emission.lights[k];
        let Light::Area(area) = &self.lights.lights()[li] else {
            return None;
        };
        let shape = self.accel.shapes().get(area.shape)?;
        let s = sample_area(shape, u_pos);
        let (dir, dir_pdf) = emission.targets.sample(s.p, s.n, u_pick, u_dir)?;
        let cos_l = s.n.dot(dir);
        let le = area.le(&(&s).into(), dir, wl);
        if le.is_black() || !(s.pdf > 0.0 && p_sel > 0.0 && cos_l > 0.0) {
            return None;
        }
        Some(LightWalk {
            light: li,
            ray: Ray::new(offset_ray_origin(s.p, s.n, dir), dir),
            // Emitters are unpolarized: a depolarizer.
            beta: L::from_spectrum(le * (cos_l / (p_sel * s.pdf * dir_pdf))),
            throughput: L::ONE,
            eta: 1.0,
            light_density: p_sel * s.pdf * dir_pdf / cos_l,
            deltas: 0,
            segments: 1,
            // The light itself counts as a smooth vertex: the next one must be a delta.
            after_smooth: true,
            null_crossings: 0,
            refracted_ok: self.refracted_nee && self.refracted_light.get(li).copied().unwrap_or(false),
            refracted: None,
        })
    }

    /// One surface hit `si` of the light subpath: false when the subpath ends there.
    fn light_path_vertex<L: Weight, F: FnMut(Vec2, L, &SampledWavelengths)>(
        &self,
        sink: &mut LightPathSink<'_, F, L>,
        walk: &mut LightWalk<L>,
        si: &SurfaceInteraction,
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
    ) -> bool
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<L>,
    {
        let Some(&m) = self.shape_material.get(si.shape as usize) else {
            return false;
        };
        if walk.after_smooth && !sink.emission.delta.get(m).copied().unwrap_or(false) {
            // Two smooth vertices in a row (or light reaching a smooth surface directly): the
            // path tracer's alone. Decided before the BSDF is built: most light subpaths end here.
            return false;
        }
        let u_lobe = sampler.next_1d();
        let u_bsdf = sampler.next_2d();
        let u_rr = sampler.next_1d();
        let wi_world = -walk.ray.d;
        let hit = LightHit {
            si,
            wi: si.shading.to_local(wi_world),
            cos_in_g: si.n.dot(wi_world).abs(),
        };
        let sample = self.bsdf_at(
            si.shape,
            &crate::material::ShadingPoint::from(si),
            &{ *wl },
            |bsdf: &SurfaceBsdf<'_>| {
                let flags = bsdf.flags();
                if walk.after_smooth && !flags.is_delta() {
                    // Two smooth vertices in a row (or light reaching a smooth surface directly):
                    // the path tracer's alone.
                    return None;
                }
                // At the first smooth vertex, refracted next-event estimation's numerators.
                let here = match walk.refracted {
                    None if walk.refracted_ok && flags.has_smooth() => {
                        RefractedDensity::Here(self.refracted_density_at(si, flags, wi_world, walk.light, wl))
                    }
                    None => RefractedDensity::None,
                    Some(d) => d,
                };
                if !walk.after_smooth && flags.has_smooth() && hit.cos_in_g > 0.0 {
                    self.keep_light_vertex(sink, walk, &hit, bsdf, here, wl);
                }
                let bs: BsdfSample<L> =
                    bsdf.sample_weight(&BsdfContext::importance(), hit.wi, u_lobe, u_bsdf, wl)?;
                // For a smooth bounce, the path tracer's density of the reverse direction.
                let eye_pdf = if bs.flags.is_delta() {
                    0.0
                } else {
                    bsdf.pdf(&BsdfContext::radiance(), bs.wo, hit.wi, wl)
                };
                Some((bs, eye_pdf, here))
            },
        );
        let Some(Some((bs, eye_pdf, here))) = sample else {
            return false;
        };
        self.advance_light_walk(walk, &hit, &bs, eye_pdf, here, u_rr)
    }

    /// Keeps the smooth vertex `hit` (BSDF `bsdf`) for the camera path's connections and
    /// connects it to the camera.
    fn keep_light_vertex<L: Weight, F: FnMut(Vec2, L, &SampledWavelengths)>(
        &self,
        sink: &mut LightPathSink<'_, F, L>,
        walk: &LightWalk<L>,
        hit: &LightHit,
        bsdf: &SurfaceBsdf<'_>,
        refracted: RefractedDensity,
        wl: &SampledWavelengths,
    ) where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<L>,
    {
        let si = hit.si;
        let vertex = LightVertex {
            p: si.p,
            n: si.n,
            shading: si.shading,
            at: crate::material::ShadingPoint::from(si),
            shape: si.shape,
            wi: hit.wi,
            cos_chain: hit.cos_in_g,
            beta: walk.beta,
            light_density: walk.light_density,
            eta2: 1.0 / (walk.eta * walk.eta),
            segments: walk.segments,
            refracted,
        };
        sink.out.push(vertex);
        self.splat_to_camera(sink.camera, bsdf, &vertex, wl, &mut *sink.splat);
    }

    /// After a BSDF sample at `hit`: the weight with the shading-normal correction, sheets
    /// crossed, the light-side MIS densities, the chain bounds and Russian roulette. False when
    /// the subpath ends. `here`: refracted next-event estimation's density at this vertex.
    fn advance_light_walk<L: Weight>(
        &self,
        walk: &mut LightWalk<L>,
        hit: &LightHit,
        bs: &BsdfSample<L>,
        eye_pdf: f32,
        here: RefractedDensity,
        u_rr: f32,
    ) -> bool {
        let smooth = !bs.flags.is_delta();
        if smooth && walk.after_smooth {
            return false;
        }
        let si = hit.si;
        let wo_world = si.shading.to_world(bs.wo);
        let cos_out_g = si.n.dot(wo_world).abs();
        let denom = hit.cos_in_g * bs.wo.z.abs();
        let correction = if denom > 0.0 {
            hit.wi.z.abs() * cos_out_g / denom
        } else {
            0.0
        };
        let weight = bs.weight.local_to_world(&si.shading) * correction;
        if !weight.intensity().is_finite() || weight.is_black() {
            return false;
        }
        // Light order: this vertex acts after everything before it.
        walk.beta = weight * walk.beta;
        walk.throughput = weight * walk.throughput;
        walk.ray = si.spawn_ray(wo_world);

        if self.thin_shadows && bs.flags.contains(BsdfFlags::NULL) {
            walk.null_crossings += 1;
            return walk.null_crossings <= MAX_NULL_CROSSINGS;
        }
        walk.segments += 1;
        walk.null_crossings = 0;
        if smooth {
            let d = eye_pdf * cos_out_g;
            if !(d > 0.0) {
                return false;
            }
            walk.light_density *= bs.pdf * hit.cos_in_g / d;
            walk.after_smooth = true;
            if walk.refracted.is_none() {
                // Leaving the first smooth vertex towards the camera side: `s` there is fixed.
                walk.refracted = Some(match here {
                    RefractedDensity::Here(num) => {
                        RefractedDensity::Earlier(num[usize::from(bs.wo.z < 0.0)] / eye_pdf)
                    }
                    other => other,
                });
            }
        } else {
            walk.refracted_ok &=
                self.is_refractor(si.shape) && bs.flags.contains(BsdfFlags::DELTA_TRANSMISSION);
            walk.eta *= bs.eta;
            walk.deltas += 1;
            walk.after_smooth = false;
        }
        // A connection adds at least one more segment (from the next vertex to the camera).
        if walk.deltas > MAX_CHAIN || walk.segments.saturating_add(1) > self.max_depth {
            return false;
        }
        if walk.segments > self.rr_depth {
            let q = walk.throughput.intensity().max_component().min(0.95);
            if !(u_rr < q) {
                return false;
            }
            walk.beta /= q;
            walk.throughput /= q;
        }
        true
    }

    /// The connection of light vertex `y` (BSDF `bsdf`) to the camera.
    fn splat_to_camera<L: Weight>(
        &self,
        camera: &dyn Camera,
        bsdf: &SurfaceBsdf<'_>,
        y: &LightVertex<L>,
        wl: &SampledWavelengths,
        splat: &mut impl FnMut(Vec2, L, &SampledWavelengths),
    ) where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<L>,
    {
        let Some(c) = camera.connect(y.p) else {
            return;
        };
        let wo_cam = y.shading.to_local(c.dir);
        // Radiance mode with wi towards the camera: light arrives along −y.wi, leaves to the camera.
        let (f, pdf_y): (L, f32) = bsdf.eval_pdf_weight(&BsdfContext::radiance(), wo_cam, y.wi, wl);
        if f.is_black() {
            return;
        }
        let f = f.local_to_world(&y.shading);
        let cos_cam = y.n.dot(c.dir).abs();
        let g = y.wi.z.abs() / y.cos_chain * cos_cam / c.dist2;
        let value = f * y.beta * (g * c.importance);
        if value.is_black() || !value.intensity().is_finite() {
            return;
        }
        let w = y.connection_weight(c.film_pdf * cos_cam / c.dist2, pdf_y, wo_cam);
        if !(w > 0.0) {
            return;
        }
        // The shadow ray leaves y and light travels along it, towards the camera.
        let v: L = self.visibility(spawn_ray_between(y.p, y.n, c.near_point, None), wl, true);
        if !v.is_black() {
            splat(c.film, v * value * w, wl);
        }
    }
}
