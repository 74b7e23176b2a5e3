//! The `direct` and `depth` integrators, on the path tracer's light sampling and MIS.
//!
//! `direct` (Mitsuba 3 `src/integrators/direct.cpp`): at the first hit, n_L light samples
//! ([`PathTracer::next_event`]) and n_B BSDF samples whose rays are followed to the first
//! surface, where an area light (or, escaping, a light at infinity) adds its emission
//! ([`PathTracer::add_emitted`], [`PathTracer::add_escaped`]). Each estimate is weighted by the
//! power heuristic over the densities scaled by the sample counts, (n p)², and divided by its own
//! count. A delta light or a delta lobe has weight 1 (the other strategy cannot produce it).
//! Mitsuba gives a delta light's samples weight 1 each, without the 1/n_L; we divide by n_L, so
//! that `emitter_samples` changes the noise and not the brightness (both agree for n_L = 1, the
//! default).
//!
//! `depth` (Mitsuba 3 `src/integrators/depth.cpp`): t of the first hit along the unit camera
//! ray, 0 where it escapes.

use super::{PathState, PathTracer, PrevVertex, Vertex};
use crate::accel::Intersect;
use crate::geometry::Ray;
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::weight::{BsdfWeight, Weight};
use gonio_core::{Bsdf, BsdfContext};

use super::{CameraSample, PathSampler};

impl PathTracer<'_> {
    /// The `direct` estimate for one camera sample (see the module documentation), carrying `W`
    /// (a spectrum, or a Mueller matrix when polarized).
    pub(super) fn li_direct<W: Weight>(
        &self,
        sample: &mut CameraSample<'_>,
        emitter_samples: u32,
        bsdf_samples: u32,
    ) -> W
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        let CameraSample {
            ray: camera_ray,
            wavelengths: wl,
            sampler,
            ..
        } = sample;
        let camera = PathState::<W>::CAMERA;
        let mut l = W::ZERO;
        let Some(si) = self.accel.intersect(camera_ray) else {
            if !self.hide_emitters {
                self.add_escaped(&mut l, &camera, camera_ray.d, wl);
            }
            return l;
        };
        if !self.hide_emitters {
            self.add_emitted(&mut l, &camera, &si, camera_ray.d, wl);
        }
        let Some(material) = self.material_of(si.shape) else {
            return l;
        };
        let mut bsdf = SurfaceBsdf::new();
        material.fill_bsdf_at(&crate::material::ShadingPoint::from(&si), wl, &mut bsdf);
        let v = Vertex {
            bsdf: &bsdf,
            si: &si,
            wi: si.shading.to_local(-camera_ray.d),
        };
        let flags = bsdf.flags();
        let light_ref = self.light_ref(&v, flags, bsdf_samples > 0);
        let (n_l, n_b) = (emitter_samples as f32, bsdf_samples as f32);

        if flags.has_smooth() && emitter_samples > 0 {
            let mut sum = W::ZERO;
            for _ in 0..emitter_samples {
                let u_sel = sampler.next_1d();
                let u = sampler.next_2d();
                sum += self.next_event(&v, &light_ref, W::ONE, u_sel, u, wl, (n_l, n_b), None);
            }
            l += sum / n_l;
        }

        let ctx = BsdfContext::radiance();
        let mut sum = W::ZERO;
        for _ in 0..bsdf_samples {
            let u_lobe = sampler.next_1d();
            let u_dir = sampler.next_2d();
            let Some(bs) = bsdf.sample_weight(&ctx, v.wi, u_lobe, u_dir, &mut *wl) else {
                continue;
            };
            if bs.weight.is_black()
                || !bs.weight.intensity().is_finite()
                || !(bs.flags.is_delta() || bs.pdf > 0.0)
            {
                continue;
            }
            // The light density is compared with the BSDF density scaled by n_B / n_L (the power
            // heuristic only sees the ratio); with no light samples the BSDF sample has weight 1.
            let bsdf_pdf = if emitter_samples == 0 {
                f32::INFINITY
            } else {
                bs.pdf * n_b / n_l
            };
            let state = PathState {
                beta: bs.weight.local_to_world(&si.shading),
                prev: Some(PrevVertex {
                    light_ref,
                    bsdf_pdf,
                    delta: bs.flags.is_delta(),
                }),
                ..camera
            };
            let dir = si.shading.to_world(bs.wo);
            let ray = si.spawn_ray(dir);
            match self.accel.intersect(&ray) {
                Some(hit) => self.add_emitted(&mut sum, &state, &hit, dir, wl),
                None => self.add_escaped(&mut sum, &state, dir, wl),
            }
        }
        if bsdf_samples > 0 {
            l += sum / n_b;
        }
        if l.intensity().is_finite() { l } else { W::ZERO }
    }

    /// The `depth` value of a camera ray: the hit distance, 0 on a miss.
    pub(super) fn depth(&self, ray: &Ray) -> f32 {
        self.accel.intersect(ray).map_or(0.0, |si| si.t * ray.d.length())
    }
}
