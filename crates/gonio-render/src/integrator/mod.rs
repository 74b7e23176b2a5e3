//! The `path` integrator: a unidirectional spectral path tracer with next-event estimation and
//! multiple importance sampling, after Mitsuba 3's `path` (`src/integrators/path.cpp`).
//!
//! # Algorithm
//!
//! For a camera ray carrying four wavelengths (hero + three rotated, [`SampledWavelengths`]):
//!
//! 1. **Emission.** A hit on an area light (or an escaped ray, for the lights at infinity) adds
//!    β·Lₑ·w. After the camera or a delta lobe w = 1; after a smooth lobe w is the power heuristic
//!    (β = 2) between the BSDF density and the light density (selection probability × the
//!    light's solid-angle density from the previous vertex). `hide_emitters` drops what the
//!    camera sees directly.
//! 2. **Next-event estimation**, only when the BSDF has a smooth (diffuse or glossy) lobe: pick a
//!    light ([`Lights::select_at`]), draw a direction on it (solid angle for spheres, and for
//!    rectangles that subtend more than [`SPHERICAL_RECTANGLE_MIN_SOLID_ANGLE`]; area otherwise), add β·f·|cos|·Lᵢ·T/(p_sel·p_dir)·w, with w the power heuristic against the
//!    BSDF density (w = 1 for delta lights). T is the visibility: 0 or 1, or, with
//!    `thin_shadows`, the product of the straight-through transmittances
//!    ([`gonio_core::Bsdf::null_transmission`]) of the `thindielectric` sheets crossed.
//! 3. **BSDF sampling**: β ← β·weight, η_path ← η_path·η (the relative index crossed). A
//!    dispersive refraction terminates the secondary wavelengths inside the BSDF; the estimator
//!    that turns the result into colour divides by the pdfs, so nothing else changes here.
//! 4. **Russian roulette** from `rr_depth` on: continue with q = min(max(β)·η_path², 0.95), then
//!    β ← β/q. The η² undoes the radiance compression of refraction, so a path inside glass is
//!    not killed more often than outside it.
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
//! estimate the same integral and MIS stays unbiased. With `thin_shadows = false` a null
//! transmission is an ordinary delta event and sheets block shadow rays: Mitsuba's exact
//! behaviour (the light behind a window then arrives only through BSDF sampling).
//!
//! # Caustic light paths (beyond Mitsuba)
//!
//! With `caustic_paths` (the default; active when the scene has an area light and a delta lobe),
//! each camera sample also traces a light subpath through delta chains ([`caustics`]), whose
//! smooth vertices are connected to the camera (splatted) and to every smooth vertex of this
//! path. The paths both can produce (an area light reached through a delta chain) are weighted
//! by the power heuristic between the two; see that module for the densities.
//!
//! # Shading normals
//!
//! BSDFs are evaluated in the shading frame (interpolated normals), as in Mitsuba; rays leave
//! from the side of the geometric normal that their direction points to.

pub mod caustics;

use crate::accel::{Accel, Intersect};
use crate::emitter::AreaLight;
use crate::emitter::{BoundingSphere, Light, LightRef, LightSample, Lights};
use crate::geometry::sampling::{pdf_solid_angle, sample_area, sample_solid_angle};
use crate::geometry::{Ray, SurfaceInteraction};
use crate::geometry::{ShapeKind, WorldShape};
use crate::material::Material;
use crate::scene::Integrator as IntegratorSettings;
use glam::{Vec2, Vec3};
use gonio_core::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, SampledSpectrum, SampledWavelengths};

/// The random numbers a path consumes, in a fixed order (so stratified and low-discrepancy
/// samplers keep their dimensions aligned).
pub trait PathSampler {
    /// One number in [0, 1).
    fn next_1d(&mut self) -> f32;
    /// Two numbers in [0, 1)².
    fn next_2d(&mut self) -> Vec2;
}

/// Independent numbers from a PCG32 stream (light paths, tests).
impl PathSampler for gonio_core::rng::Pcg32 {
    #[inline]
    fn next_1d(&mut self) -> f32 {
        self.next_f32()
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        self.next_vec2()
    }
}

/// Power heuristic with exponent 2 for two strategies with densities `a` (the one used) and `b`.
#[inline]
pub fn mis_power(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 && a2.is_finite() {
        a2 / (a2 + b2)
    } else if a2.is_finite() {
        0.0
    } else {
        1.0
    }
}

/// Largest number of sheets a path or a shadow ray crosses before giving up (a bound against
/// stacks of coincident sheets; never reached in sensible scenes).
const MAX_NULL_CROSSINGS: u32 = 64;

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
    max_depth: u32,
    rr_depth: u32,
    hide_emitters: bool,
    thin_shadows: bool,
    /// Light tracing of the caustics, when enabled and useful.
    caustics: Option<caustics::EmissionSampler>,
    /// The camera light paths connect to (light tracing needs it).
    camera: Option<&'a crate::camera::Camera>,
}

/// What happened at one surface vertex (computed while the per-hit BSDF exists).
struct VertexOutcome {
    nee: SampledSpectrum,
    sample: Option<BsdfSample>,
    light_ref: LightRef,
    /// Density of the light tracer sampling the reverse of a smooth sample (when asked for).
    reverse_pdf: f32,
}

impl<'a> PathTracer<'a> {
    /// A path tracer over prepared scene data. `shape_material[i]` is the material of shape `i`
    /// of the accelerator.
    pub fn new(
        settings: &IntegratorSettings,
        accel: &'a Accel,
        lights: &'a Lights,
        materials: &'a [Material],
        shape_material: &'a [usize],
    ) -> Self {
        let thin: Vec<bool> = materials.iter().map(Material::has_null_transmission).collect();
        let any_thin = thin.iter().any(|&t| t);
        let caustics = if settings.caustic_paths {
            caustics::EmissionSampler::new(lights, materials, shape_material, accel.shapes())
        } else {
            None
        };
        Self {
            accel,
            lights,
            materials,
            shape_material,
            thin,
            any_thin,
            max_depth: if settings.max_depth < 0 {
                u32::MAX
            } else {
                settings.max_depth as u32
            },
            rr_depth: settings.rr_depth,
            hide_emitters: settings.hide_emitters,
            thin_shadows: settings.thin_shadows,
            caustics,
            camera: None,
        }
    }

    /// The camera, which enables light tracing of caustics (when the settings ask for it and the
    /// scene has an area light and a delta lobe).
    pub fn with_camera(mut self, camera: &'a crate::camera::Camera) -> Self {
        self.camera = Some(camera);
        self
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
    pub fn li(
        &self,
        mut ray: Ray,
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
        light: &caustics::LightSubpath,
    ) -> SampledSpectrum {
        if self.max_depth == 0 {
            // Mitsuba: max_depth 0 renders nothing, not even emitters.
            return SampledSpectrum::ZERO;
        }
        let ctx = BsdfContext::radiance();
        let mut l = SampledSpectrum::ZERO;
        let mut beta = SampledSpectrum::ONE;
        let mut eta_path = 1.0f32;
        let mut depth = 0u32;
        // The last real scattering vertex: where a light would have been sampled from, the BSDF
        // density of the direction taken, and whether that lobe was a delta. None = the camera.
        let mut prev: Option<(LightRef, f32, bool)> = None;
        let mut null_crossings = 0u32;
        // The last smooth vertex and the delta chain after it, for the MIS weight against the
        // light-path connections ([`caustics`]).
        let mut chain: Option<caustics::ChainState> = None;

        loop {
            let hit = self.accel.intersect(&ray);
            let show = !(self.hide_emitters && depth == 0);
            let Some(si) = hit else {
                if show {
                    for &i in self.lights.infinite() {
                        let light = &self.lights.lights()[i as usize];
                        let le = light.le_infinite(ray.d, wl);
                        if le.is_black() {
                            continue;
                        }
                        let w = match prev {
                            Some((r, bsdf_pdf, false)) => mis_power(
                                bsdf_pdf,
                                self.lights.pmf_at(&r, i as usize) * light.pdf_li_infinite(&r, ray.d),
                            ),
                            _ => 1.0,
                        };
                        l += beta * le * w;
                    }
                }
                break;
            };

            // Emission of an area light hit from its front side.
            if show && let Some(li) = self.lights.shape_light(si.shape as usize) {
                if let Light::Area(area) = &self.lights.lights()[li] {
                    let le = area.le(si.n, si.uv, -ray.d, wl);
                    if !le.is_black() {
                        let w = match prev {
                            Some((r, bsdf_pdf, false)) => {
                                let shape = &self.accel.shapes()[si.shape as usize];
                                let dir_pdf = if by_area(area, shape, r.p) {
                                    area_pdf_to_solid_angle(1.0 / area.area, r.p, si.p, si.n)
                                } else {
                                    pdf_solid_angle(shape, r.p, &si)
                                };
                                let light_pdf = self.lights.pmf_at(&r, li) * dir_pdf;
                                mis_power(bsdf_pdf, light_pdf)
                            }
                            // After a delta lobe: light paths may have found this path too.
                            _ => self.caustic_path_weight(chain.as_ref(), li, area, si.p, si.n, -ray.d),
                        };
                        l += beta * le * w;
                    }
                }
            }

            if depth.saturating_add(1) >= self.max_depth {
                break;
            }
            let Some(material) = self.material_of(si.shape) else {
                break;
            };

            let wi_world = -ray.d;
            let wi = si.shading.to_local(wi_world);
            // How this point was reached, for the MIS weight against light-subpath connections.
            let arrival = Self::arrival(
                prev.as_ref().map(|(r, pdf, delta)| (r.p, *pdf, *delta)),
                &si,
                ray.d,
            );
            // After a delta lobe, a smooth sample here needs the light tracer's density of the
            // reverse direction for the MIS ratio.
            let want_reverse = self.traces_caustics() && matches!(prev, Some((_, _, true)));
            let outcome = material.with_bsdf_at(si.uv, *wl, |bsdf: &dyn Bsdf| {
                self.scatter(bsdf, &ctx, &si, wi, beta, depth, light, want_reverse, sampler, wl)
            });
            l += outcome.nee;

            let Some(bs) = outcome.sample else { break };
            beta *= bs.weight;
            let dir = si.shading.to_world(bs.wo);
            ray = si.spawn_ray(dir);

            if self.thin_shadows && bs.flags.contains(BsdfFlags::NULL) {
                // Straight through a sheet: keep the previous vertex's MIS state and depth.
                null_crossings += 1;
                if null_crossings > MAX_NULL_CROSSINGS || beta.is_black() {
                    break;
                }
                continue;
            }

            eta_path *= bs.eta;
            if self.traces_caustics() {
                chain = caustics::ChainState::after_sample(
                    chain,
                    &bs,
                    arrival,
                    si.n.dot(wi_world).abs(),
                    si.n.dot(dir).abs(),
                    outcome.reverse_pdf,
                );
            }
            prev = Some((outcome.light_ref, bs.pdf, bs.flags.is_delta()));
            depth += 1;

            // Russian roulette, from `rr_depth` on (its number is drawn only there: a function of
            // the depth, so the dimensions of paths of the same shape stay aligned).
            let beta_max = beta.max_component();
            if depth >= self.rr_depth {
                let u_rr = sampler.next_1d();
                let q = (beta_max * eta_path * eta_path).min(0.95);
                if !(u_rr < q) {
                    break;
                }
                beta /= q;
            }
            if !(beta_max > 0.0) || !beta.is_finite() {
                break;
            }
        }
        if l.is_finite() { l } else { SampledSpectrum::ZERO }
    }

    /// Next-event estimation and BSDF sampling at one vertex, while the BSDF exists.
    #[allow(clippy::too_many_arguments)]
    fn scatter(
        &self,
        bsdf: &dyn Bsdf,
        ctx: &BsdfContext,
        si: &SurfaceInteraction,
        wi: Vec3,
        beta: SampledSpectrum,
        depth: u32,
        light: &caustics::LightSubpath,
        want_reverse: bool,
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
    ) -> VertexOutcome {
        let flags = bsdf.flags();
        let n_side = if wi.z >= 0.0 { si.shading.n } else { -si.shading.n };
        let light_ref = LightRef {
            p: si.p,
            n: n_side,
            hemisphere: !flags.is_transmission(),
        };

        // Random numbers: a vertex with a smooth lobe takes five (light choice, light point,
        // lobe, direction), a purely delta one only its lobe choice (it samples no light and
        // needs no direction), so the sampler's structured dimensions reach the smooth vertices
        // behind glass and mirrors. The count is a function of the path, as it must be.
        let smooth = flags.has_smooth();
        let (u_sel, u_light) = if smooth {
            (sampler.next_1d(), sampler.next_2d())
        } else {
            (0.5, Vec2::splat(0.5))
        };
        let mut nee = SampledSpectrum::ZERO;
        if flags.has_smooth()
            && let Some((li, p_sel)) = self.lights.select_at(&light_ref, u_sel)
            && let Some(ls) = self.sample_light(li, &light_ref, u_light, wl)
        {
            let wo = si.shading.to_local(ls.wi);
            let (f, bsdf_pdf) = bsdf.eval_pdf(ctx, wi, wo, wl);
            if !f.is_black() {
                let t = self.transmittance(si, &ls, wl);
                if !t.is_black() {
                    let light_pdf = p_sel * ls.pdf;
                    let w = if ls.delta {
                        1.0
                    } else {
                        mis_power(light_pdf, bsdf_pdf)
                    };
                    nee = beta * f * ls.li * t * (wo.z.abs() * w / light_pdf);
                }
            }
        }

        if flags.has_smooth() && !light.is_empty() {
            nee += beta * self.connect_light_vertices(bsdf, si, wi, depth, light, wl);
        }

        let u_lobe = sampler.next_1d();
        let u_dir = if smooth {
            sampler.next_2d()
        } else {
            Vec2::splat(0.5)
        };
        let sample = bsdf.sample(ctx, wi, u_lobe, u_dir, wl).filter(|bs| {
            bs.weight.is_finite() && !bs.weight.is_black() && (bs.flags.is_delta() || bs.pdf > 0.0)
        });
        let reverse_pdf = match &sample {
            Some(bs) if want_reverse && !bs.flags.is_delta() => {
                bsdf.pdf(&BsdfContext::importance(), bs.wo, wi, wl)
            }
            _ => 0.0,
        };
        VertexOutcome {
            nee,
            sample,
            light_ref,
            reverse_pdf,
        }
    }

    fn sample_light(&self, li: usize, r: &LightRef, u: Vec2, wl: &SampledWavelengths) -> Option<LightSample> {
        match &self.lights.lights()[li] {
            Light::Area(area) => {
                let shape = self.accel.shapes().get(area.shape)?;
                if by_area(area, shape, r.p) {
                    let s = sample_area(shape, u);
                    let pdf = area_pdf_to_solid_angle(s.pdf, r.p, s.p, s.n);
                    area.sample_from_point(r.p, s.p, s.n, s.uv, pdf, wl)
                } else {
                    let s = sample_solid_angle(shape, r.p, u)?;
                    area.sample_from_point(r.p, s.p, s.n, s.uv, s.pdf, wl)
                }
            }
            light => light.sample_li_nonarea(r, u, wl),
        }
    }

    /// Visibility of a light sample from `si`: 0/1, or with thin shadows the transmittance of the
    /// sheets crossed.
    fn transmittance(
        &self,
        si: &SurfaceInteraction,
        ls: &LightSample,
        wl: &SampledWavelengths,
    ) -> SampledSpectrum {
        let ray = if ls.dist.is_finite() {
            si.spawn_ray_to(si.p + ls.wi * ls.dist, ls.normal)
        } else {
            si.spawn_ray(ls.wi)
        };
        self.visibility(ray, wl)
    }

    /// Visibility along a shadow ray: 0/1, or with thin shadows the transmittance of the sheets
    /// crossed.
    fn visibility(&self, ray: Ray, wl: &SampledWavelengths) -> SampledSpectrum {
        if !(self.thin_shadows && self.any_thin) {
            return if self.accel.occluded(&ray) {
                SampledSpectrum::ZERO
            } else {
                SampledSpectrum::ONE
            };
        }
        let mut ray = ray;
        let mut tr = SampledSpectrum::ONE;
        for _ in 0..MAX_NULL_CROSSINGS {
            let Some(h) = self.accel.intersect(&ray) else {
                return tr;
            };
            if !self.is_thin(h.shape) {
                return SampledSpectrum::ZERO;
            }
            let Some(material) = self.material_of(h.shape) else {
                return SampledSpectrum::ZERO;
            };
            let wi = h.shading.to_local(-ray.d);
            let t = material.with_bsdf_at(h.uv, *wl, |bsdf: &dyn Bsdf| bsdf.null_transmission(wi, wl));
            match t {
                Some(t) => tr *= t,
                None => return SampledSpectrum::ZERO,
            }
            if tr.is_black() {
                return tr;
            }
            // Continue from the sheet towards the same end point (already offset off the light).
            let o = crate::geometry::offset_ray_origin(h.p, h.n, ray.d);
            let remaining = if ray.tmax.is_finite() {
                (ray.o + ray.d * ray.tmax - o).dot(ray.d)
            } else {
                f32::INFINITY
            };
            if !(remaining > 0.0) {
                return tr;
            }
            ray = Ray {
                o,
                d: ray.d,
                tmax: remaining,
            };
        }
        SampledSpectrum::ZERO
    }
}

/// Below this solid angle (estimated as A/d² from the light's bounding-sphere centre) a rectangle
/// light is sampled uniformly by area: spherical-rectangle sampling (Ureña et al. 2013) costs a
/// dozen transcendental functions and gains little when the light subtends a small angle, where
/// the area density is nearly proportional to solid angle anyway. Measured (`bench/RESULTS.md`):
/// 0.5 sr saves 28 % of thin-vs-thick's time at equal error and costs materials 8 % more error at
/// equal time.
pub const SPHERICAL_RECTANGLE_MIN_SOLID_ANGLE: f32 = 0.5;

/// True when the area light is sampled by area from `p` (rectangles subtending a small angle).
/// A function of the light and the point only, so light sampling and the MIS density agree.
#[inline]
fn by_area(light: &AreaLight, shape: &WorldShape, p: Vec3) -> bool {
    matches!(shape.kind, ShapeKind::Rectangle { .. })
        && light.area < SPHERICAL_RECTANGLE_MIN_SOLID_ANGLE * (light.center - p).length_squared()
}

/// An area density at `p` (normal `n`) seen from `r`, per unit solid angle: p_A·d²/|cos|.
#[inline]
fn area_pdf_to_solid_angle(pdf_area: f32, r: Vec3, p: Vec3, n: Vec3) -> f32 {
    let v = p - r;
    let d2 = v.length_squared();
    let cos = (n.dot(v) / d2.sqrt()).abs();
    if cos > 0.0 && d2 > 0.0 {
        pdf_area * d2 / cos
    } else {
        0.0
    }
}

/// The bounding sphere of a set of points' axis-aligned box (a unit sphere at the origin when
/// empty).
pub fn bounding_sphere(min: Vec3, max: Vec3) -> BoundingSphere {
    if !(min.is_finite() && max.is_finite()) || min.cmpgt(max).any() {
        return BoundingSphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
    }
    let center = 0.5 * (min + max);
    BoundingSphere {
        center,
        radius: (0.5 * (max - min).length()).max(1e-3),
    }
}
