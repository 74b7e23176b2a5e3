//! `ptracer`: light tracing (Mitsuba 3 `src/integrators/ptracer.cpp`; Veach 1997 §10.2,
//! "particle tracing"). Paths start at the lights and every surface vertex is joined to the
//! camera; nothing is written where the camera sample lies, everything is splatted.
//!
//! Per camera sample (so `spp` is light paths per pixel, as in Mitsuba; the render loop divides
//! the splats by the number of camera samples):
//!
//! 1. **Emitters seen directly** (unless `hide_emitters` or `max_depth = 0`): a light chosen by
//!    power; on an area light a point uniform by area joined to the camera,
//!    `Lₑ(ω_cam)·cos θ_l/d²·W/(p_sel·p_A)`; from a light at infinity a direction sampled from the
//!    camera position, `L(ω)·W/(p_sel·p(ω))` (W the camera importance,
//!    [`Camera::connect_lens`]); delta lights add nothing, as Mitsuba's.
//! 2. **The light path**: a light chosen by power emits a ray ([`Light::sample_ray`],
//!    `β = weight/p_sel`). At each surface hit with a smooth lobe, the vertex is joined to the
//!    camera: `β·f(ω_cam, ω_in)·|ω_in·n_s|/|ω_in·n_g|·|ω_cam·n_g|/d²·W·V` (f in radiance mode
//!    with ω_cam as its incident direction, the shading-normal correction of Veach 1997 §5.3).
//!    Then the BSDF is sampled in importance mode, β ×= weight × the same correction; directions
//!    on the wrong side of the geometric normal end the path (Mitsuba's light-leak test).
//!
//! `max_depth` counts segments of the whole path, camera segment included (1: emitters seen
//! directly, 2: direct lighting); Russian roulette from `rr_depth` on with
//! q = min(max(Π weights), q_max) on the vertex weights, q_max Mitsuba's 0.95 (the plugin's
//! `rr_survival`; Mitsuba uses β including the emission, which makes q = 0.95 almost always:
//! the same expectation). A dispersive refraction leaves the
//! hero wavelength alone for the rest of the path (connections before it used all four).
//! Paths are spectral (a polarizing material is rendered without polarization). Null surfaces
//! and thin sheets are delta vertices of the light paths; a connection to the camera crosses
//! them, attenuated by their transmittance (`thin_shadows`, ours, as the path tracer's shadow
//! rays: no other strategy of the light tracer makes a path whose last segment passes through
//! one, so without it whatever lies behind a null surface or a pane renders black), and a
//! light path's straight pass through one is not a segment of `max_depth` nor a step of the
//! roulette, as in the path tracer. Mitsuba's connections stop at them; `thin_shadows = false`
//! (the default under `--mitsuba-estimators`) does the same, and counts every pass. The light
//! tracer renders no participating media (a scene's media are left out, with a warning).

use super::{CameraSample, MAX_NULL_CROSSINGS, PathSampler, PathTracer};
use crate::accel::Intersect;
use crate::camera::Camera;
use crate::emitter::{Light, LightRef};
use crate::geometry::sampling::sample_area;
use crate::geometry::{Ray, SurfaceInteraction, spawn_ray_between};
use crate::material::ShadingPoint;
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::{Bsdf, BsdfContext, BsdfFlags, SampledSpectrum, SampledWavelengths};

/// Where a light path's connections go: the camera and the film.
struct Splatter<'s, 'p> {
    camera: &'s dyn Camera,
    splat: &'s mut dyn FnMut(Vec2, &[f32]),
    tracer: &'s PathTracer<'p>,
}

impl Splatter<'_, '_> {
    fn add(&mut self, film: Vec2, v: SampledSpectrum, wl: &SampledWavelengths) {
        if v.is_finite() && !v.is_black() {
            self.tracer.splat_radiance(self.splat, film, v, wl);
        }
    }
}

impl PathTracer<'_> {
    /// One camera sample of `ptracer`: splats only.
    pub(super) fn sample_ptracer(&self, sample: &mut CameraSample<'_>, splat: &mut dyn FnMut(Vec2, &[f32])) {
        let Some(camera) = self.camera else {
            return;
        };
        if self.max_depth == 0 {
            return;
        }
        let mut out = Splatter {
            camera,
            splat,
            tracer: self,
        };
        let sampler = &mut sample.sampler;
        let wl = &mut sample.wavelengths;
        // A fixed count of numbers before the light path, whatever happens here.
        let u_sel = sampler.next_1d();
        let u_pos = sampler.next_2d();
        let u_lens = sampler.next_2d();
        if !self.hide_emitters {
            self.splat_visible_emitter(&mut out, u_sel, u_pos, u_lens, wl);
        }
        self.trace_ptracer_path(&mut out, sampler, wl);
    }

    /// Step 1 of the module docs: one emitter sample joined to the camera.
    fn splat_visible_emitter(
        &self,
        out: &mut Splatter<'_, '_>,
        u_sel: f32,
        u_pos: Vec2,
        u_lens: Vec2,
        wl: &SampledWavelengths,
    ) {
        let Some((li, p_sel)) = self.lights.select(u_sel) else {
            return;
        };
        match &self.lights.lights()[li] {
            Light::Area(area) => {
                let Some(shape) = self.accel.shapes().get(area.shape) else {
                    return;
                };
                let s = sample_area(shape, u_pos);
                let Some(c) = out.camera.connect_lens(s.p, u_lens) else {
                    return;
                };
                let cos = s.n.dot(c.dir);
                let le = area.le(&(&s).into(), c.dir, wl);
                if !(cos > 0.0 && s.pdf > 0.0) || le.is_black() {
                    return;
                }
                let v = le * (cos / c.dist2 * c.importance / (p_sel * s.pdf));
                let seen: SampledSpectrum =
                    self.visibility(spawn_ray_between(s.p, s.n, c.near_point, None), wl, true);
                if !seen.is_black() {
                    out.add(c.film, v * seen, wl);
                }
            }
            light if light.is_infinite() => {
                let cam = out.camera.position();
                let r = LightRef {
                    p: cam,
                    n: Vec3::Z,
                    hemisphere: false,
                    // The camera's view of the light: no BSDF sampling covers it.
                    mis: false,
                    resolved_density: 0.0,
                    resampled: false,
                };
                let Some(ls) = light.sample_li_nonarea(&r, u_pos, wl) else {
                    return;
                };
                // A point beyond the scene along the direction, for the film position and W.
                let b = self.lights.bounds();
                let far = 2.0 * (b.radius + (b.center - cam).length()) + 1.0;
                let Some(c) = out.camera.connect_lens(cam + ls.wi * far, u_lens) else {
                    return;
                };
                // Area density p(ω)/d² of a point facing the camera: L·(d²/p(ω))·W/d².
                let v = ls.li * (c.importance / (p_sel * ls.pdf));
                let seen: SampledSpectrum = self.visibility(Ray::new(c.near_point, -c.dir), wl, false);
                if !seen.is_black() {
                    out.add(c.film, v * seen, wl);
                }
            }
            _ => {}
        }
    }

    /// Step 2 of the module docs: a light path and its connections to the camera.
    fn trace_ptracer_path(
        &self,
        out: &mut Splatter<'_, '_>,
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
    ) {
        let u_sel = sampler.next_1d();
        let u_pos = sampler.next_2d();
        let u_dir = sampler.next_2d();
        let Some((li, p_sel)) = self.lights.select(u_sel) else {
            return;
        };
        let light = &self.lights.lights()[li];
        let bounds = self.lights.bounds();
        let Some(e) = light.sample_ray(self.accel.shapes(), &bounds, u_pos, u_dir, wl) else {
            return;
        };
        let mut beta = e.weight / p_sel;
        let mut throughput = SampledSpectrum::ONE;
        let mut ray = e.ray;
        // Segments so far (the emitted one), and straight passes through sheets, which count
        // as none when the joins cross sheets (as the path tracer counts them).
        let mut depth = 1u32;
        let mut crossings = 0u32;
        while depth < self.max_depth {
            let Some(si) = self.accel.intersect(&ray) else {
                break;
            };
            let u_lens = sampler.next_2d();
            let u_lobe = sampler.next_1d();
            let u_bsdf = sampler.next_2d();
            let wi_world = -ray.d;
            let wi = si.shading.to_local(wi_world);
            let cos_in_g = si.n.dot(wi_world);
            let sampled = self.bsdf_at(
                si.shape,
                &ShadingPoint::from(&si),
                &{ *wl },
                |bsdf: &SurfaceBsdf<'_>| {
                    if bsdf.flags().has_smooth() {
                        self.ptracer_connect(out, bsdf, &si, wi, cos_in_g, beta, u_lens, wl);
                    }
                    bsdf.sample(&BsdfContext::importance(), wi, u_lobe, u_bsdf, wl)
                },
            );
            let Some(Some(bs)) = sampled else {
                break;
            };
            let wo_world = si.shading.to_world(bs.wo);
            let cos_out_g = si.n.dot(wo_world);
            // Mitsuba's light-leak test and the adjoint shading-normal correction.
            if !(cos_in_g * wi.z > 0.0 && cos_out_g * bs.wo.z > 0.0) {
                break;
            }
            let correction = (wi.z * cos_out_g / (bs.wo.z * cos_in_g)).abs();
            let w = bs.weight * correction;
            beta *= w;
            throughput *= w;
            if !beta.is_finite() || beta.is_black() {
                break;
            }
            ray = si.spawn_ray(wo_world);
            if self.thin_shadows && bs.flags.contains(BsdfFlags::NULL) {
                crossings += 1;
                if crossings > MAX_NULL_CROSSINGS {
                    break;
                }
                continue;
            }
            depth += 1;
            crossings = 0;
            if depth > self.rr_depth {
                let q = throughput.max_component().min(self.rr_survival);
                if !(sampler.next_1d() < q) {
                    break;
                }
                beta /= q;
                throughput /= q;
            }
        }
    }

    /// The connection of the light-path vertex `si` (BSDF `bsdf`, `wi` towards the light in
    /// the shading frame, `cos_in_g` = ω_in·n_g) to the camera.
    #[allow(clippy::too_many_arguments)]
    fn ptracer_connect(
        &self,
        out: &mut Splatter<'_, '_>,
        bsdf: &SurfaceBsdf<'_>,
        si: &SurfaceInteraction,
        wi: Vec3,
        cos_in_g: f32,
        beta: SampledSpectrum,
        u_lens: Vec2,
        wl: &SampledWavelengths,
    ) {
        let Some(c) = out.camera.connect_lens(si.p, u_lens) else {
            return;
        };
        let wo = si.shading.to_local(c.dir);
        let cos_cam_g = si.n.dot(c.dir);
        if !(cos_in_g * wi.z > 0.0 && cos_cam_g * wo.z > 0.0) {
            return;
        }
        let f = bsdf.eval(&BsdfContext::radiance(), wo, wi, wl);
        if f.is_black() {
            return;
        }
        let g = (wi.z / cos_in_g).abs() * cos_cam_g.abs() / c.dist2 * c.importance;
        let v = beta * f * g;
        if v.is_black() || !v.is_finite() {
            return;
        }
        let seen: SampledSpectrum =
            self.visibility(spawn_ray_between(si.p, si.n, c.near_point, None), wl, true);
        if !seen.is_black() {
            out.add(c.film, v * seen, wl);
        }
    }
}
