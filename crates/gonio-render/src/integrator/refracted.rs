//! Next-event estimation through refraction (beyond Mitsuba): a light sample whose shadow ray
//! meets smooth glass is followed through the glass instead of being dropped.
//!
//! # The estimator
//!
//! Light behind a pane or a slab of glass reaches a smooth surface `x` only through refraction:
//! the shadow ray of ordinary next-event estimation is blocked and only BSDF sampling, leaving
//! `x` through the glass and happening to hit the light, finds it (a firefly for a small light).
//! Yet a parallel slab only shifts a ray sideways: most directions that point at the light still
//! reach it after two refractions. So the light sample is taken as a *direction* ω from `x`
//! (drawn exactly as next-event estimation draws it: light `j` with probability `p_sel(j)`, a
//! point on it, solid-angle density `p_j(ω)`), and the ray along ω is traced through the
//! interfaces it meets, refracting at each (delta transmission only, weighted by its Fresnel
//! transmittance and tints, as the path tracer's radiance-mode weight), until it reaches a
//! surface that is not glass. If that is light `j` (the one drawn), the sample adds
//!
//! `β · f(ωᵢ, ω) · |cos θ| · T_chain · Lₑ(y′, −ω′) / (p_sel(j)·p_j(ω)) · w₃`,
//!
//! with `y′` where the refracted ray lands and ω′ its last direction. `p_sel·p_j(ω)` is the
//! density of ω, a function of `x` and ω alone (the "straight-line" density: of the point where
//! the *unrefracted* ray along ω meets light `j`), so the path tracer can evaluate it for any
//! path that leaves a smooth vertex along ω, refracts through the same interfaces and hits `j`.
//! The straight case (no glass in the way) is ordinary next-event estimation, and a straight
//! pass through a `thindielectric` sheet (`thin_shadows`) is crossed as a shadow ray crosses it;
//! with glass in between this generalizes the thin sheets to glass of any thickness.
//!
//! # Which paths, and their MIS weights
//!
//! A path `… x → (refractions)⁺ → y′` ending on area light `j` (or leaving the scene towards a
//! light at infinity) is produced by this strategy iff
//! every delta vertex between `x` (its last smooth vertex) and the light is a refraction through a
//! non-dispersive `dielectric` (the "refractors"), there are at most [`MAX_CHAIN`] of them, the
//! light is an area light on a rectangle, disk or sphere whose own material is not a refractor
//! (one crossing of its surface per straight line, so the straight-line density is the
//! density), and the straight line from `x` along ω meets the light's front at a point where it
//! emits. Those conditions are functions of the path, checked identically by the three
//! strategies that can produce it:
//!
//! 1. the path tracer (BSDF sampling at `x`, then the delta lobes), density `p₁`;
//! 2. a light-subpath connection ([`super::caustics`]), when the vertex before the chain's
//!    smooth vertices is smooth or the camera, `p₂ = p₁/r`;
//! 3. this strategy, `p₃ = s·p₁` with `s = p_sel(j)·p_j(ω) / p_x(ω)` (the BSDF density at
//!    `x`; the Fresnel choices of the path tracer's delta lobes are left out of `s`, as the
//!    caustic ratio leaves them out: the weights below only need to be the same function of the
//!    path for all three).
//!
//! The power heuristic over the three ([`shares`]) gives `1 : 1/r² : s²` in proportion. The path
//! tracer keeps the chain's start (`RefractedStart`) to compute `s` when it hits a light; a light
//! subpath computes it at its first smooth vertex (for the camera side the connection or its
//! next sample picks); this strategy computes `r` by extending the path tracer's chain record
//! through the refractions it traced.
//!
//! Lights at infinity take part too: their sample is a direction already, and the refracted ray
//! that leaves the scene adds the radiance along its own last direction (the density is the one
//! of the drawn direction, which the path tracer evaluates for the direction it left `x` along).
//! No light subpath starts at infinity, so there two strategies share the paths.
//!
//! Not followed: reflections (a mirror's light is the caustic subpaths' business), dispersive
//! glass (the refracted direction differs per wavelength). `direct` does not use it (Mitsuba's
//! direct illumination stops at glass).

use super::caustics::{Arrival, ChainState, MAX_CHAIN};
use super::{MAX_NULL_CROSSINGS, PathTracer, Vertex};
use crate::accel::Intersect;
use crate::emitter::{Light, LightRef, LightSample};
use crate::geometry::triangle::TriRay;
use crate::geometry::{Ray, ShapeKind, SurfaceInteraction};
use crate::material::{Material, ShadingPoint, dielectric::DielectricMaterial};
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::weight::{BsdfWeight, Weight};
use gonio_core::{
    Bsdf, BsdfContext, BsdfFlags, BsdfSample, SampledSpectrum, SampledWavelengths, TransportMode,
};

/// The power heuristic's shares of (path tracer, light-subpath connection, refracted next-event
/// estimation) for a path whose densities are `p₁`, `p₂ = p₁/r` and `p₃ = s·p₁`.
///
/// `r = ∞` or NaN (0/0: neither density exists) means the connection cannot produce the path,
/// `s = 0` or NaN that refracted next-event estimation cannot. Every strategy evaluates this same
/// function of the same `(r, s)`, so the shares sum to one for every path.
pub fn shares(r: f32, s: f32) -> [f32; 3] {
    let (r, s) = (r as f64, s as f64);
    let q2 = if r.is_nan() { 0.0 } else { 1.0 / (r * r) };
    let q3 = if s.is_nan() { 0.0 } else { s * s };
    match (q2.is_finite(), q3.is_finite()) {
        (true, true) => {
            let total = 1.0 + q2 + q3;
            [(1.0 / total) as f32, (q2 / total) as f32, (q3 / total) as f32]
        }
        // p₁ is negligible beside p₂ (and p₃, when both overflow: the connection keeps it).
        (false, _) => [0.0, 1.0, 0.0],
        (true, false) => [0.0, 0.0, 1.0],
    }
}

/// The smooth vertex a camera path last left and the refractions since, for `s` when the path
/// tracer reaches a light through them.
#[derive(Clone, Copy, Debug)]
pub(super) struct RefractedStart {
    /// Where lights were sampled from at the smooth vertex.
    light_ref: LightRef,
    /// The ray that left it (origin offset off the surface, direction ω).
    ray: Ray,
    /// BSDF density of ω there.
    bsdf_pdf: f32,
    /// Refractions since.
    deltas: u32,
}

impl RefractedStart {
    /// The start at a smooth vertex that sampled `ray.d` with density `bsdf_pdf`.
    pub(super) fn new(light_ref: LightRef, ray: Ray, bsdf_pdf: f32) -> Self {
        Self {
            light_ref,
            ray,
            bsdf_pdf,
            deltas: 0,
        }
    }
}

/// What the refracted strategy needs of the camera path at the vertex it starts from.
#[derive(Clone, Copy, Debug)]
pub(super) struct PathContext {
    /// Real scattering events before the vertex.
    pub depth: u32,
    /// How the vertex was reached (for the caustic ratio).
    pub arrival: Arrival,
    /// The path's caustic record before the vertex.
    pub chain: Option<ChainState>,
}

/// The context that keeps only a lobe of delta transmission: at a `dielectric` the refraction,
/// chosen with probability one, so the sample's weight is its value.
const REFRACTION_ONLY: BsdfContext = BsdfContext {
    mode: TransportMode::Radiance,
    lobes: BsdfFlags::DELTA_TRANSMISSION,
};

/// Per material: true for a non-dispersive smooth `dielectric` (the interfaces refracted
/// next-event estimation passes).
pub(super) fn refractors(materials: &[Material]) -> Vec<bool> {
    materials
        .iter()
        .map(|m| {
            m.get::<DielectricMaterial>()
                .is_some_and(|d| !d.model.int_ior.is_dispersive() && !d.model.ext_ior.is_dispersive())
        })
        .collect()
}

impl PathTracer<'_> {
    /// Per light: true when refracted next-event estimation may end on it (an area light on a
    /// rectangle, disk or sphere that is not itself a refractor, or a light at infinity).
    pub(super) fn refracted_lights(&self) -> Vec<bool> {
        self.lights
            .lights()
            .iter()
            .map(|l| match l {
                Light::Area(a) => {
                    let simple = self.accel.shapes().get(a.shape).is_some_and(|s| {
                        matches!(
                            s.kind,
                            ShapeKind::Rectangle { .. } | ShapeKind::Disk { .. } | ShapeKind::Sphere { .. }
                        )
                    });
                    simple && !self.is_refractor(a.shape as u32)
                }
                Light::Constant(_) | Light::EnvMap(_) | Light::SunSky(_) => true,
                _ => false,
            })
            .collect()
    }

    /// True when shape `shape`'s material is a refractor.
    #[inline]
    pub(super) fn is_refractor(&self, shape: u32) -> bool {
        self.shape_material
            .get(shape as usize)
            .and_then(|&m| self.refractor.get(m))
            .copied()
            .unwrap_or(false)
    }

    /// True when refracted next-event estimation may end on light `li`.
    #[inline]
    fn refracted_light(&self, li: usize) -> bool {
        self.refracted_nee && self.refracted_light.get(li).copied().unwrap_or(false)
    }

    /// `p_sel(li)·p_li(ω)` from `r` for the direction of `ray`: the density with which
    /// refracted next-event estimation draws it, from the point where the straight line meets
    /// the light; zero where it misses the light, meets its back or a point that does not emit,
    /// or the strategy cannot end on `li`.
    pub(super) fn straight_light_pdf(
        &self,
        r: &LightRef,
        ray: &Ray,
        li: usize,
        wl: &SampledWavelengths,
    ) -> f32 {
        match self.lights.lights().get(li) {
            Some(Light::Area(_)) => {
                let dir_pdf = self.straight_area_pdf(r.p, ray, li, wl);
                if dir_pdf == 0.0 {
                    0.0
                } else {
                    self.lights.pmf_at(r, li) * dir_pdf
                }
            }
            // At infinity: the direction's own density (zero where the light is black).
            Some(_) if self.refracted_light(li) => self.lights.le_escaped(Some(r), li, ray.d, wl).1,
            _ => 0.0,
        }
    }

    /// The solid-angle density from `p` (selection excluded) with which area light `li`'s
    /// sampling produces the point where `ray` (from `p`) meets it; zero as in
    /// [`PathTracer::straight_light_pdf`].
    fn straight_area_pdf(&self, p: Vec3, ray: &Ray, li: usize, wl: &SampledWavelengths) -> f32 {
        if !self.refracted_light(li) {
            return 0.0;
        }
        let Some(Light::Area(area)) = self.lights.lights().get(li) else {
            return 0.0;
        };
        let Some(shape) = self.accel.shapes().get(area.shape) else {
            return 0.0;
        };
        let ray = Ray::new(ray.o, ray.d);
        let Some(hit) = shape.intersect_prim(0, &ray, &TriRay::new(&ray)) else {
            return 0.0;
        };
        let si = shape.interaction(area.shape as u32, 0, &ray, hit);
        if area.le(&(&si).into(), -ray.d, wl).is_black() {
            return 0.0;
        }
        area.pdf_li(shape, p, &si)
    }

    /// The path tracer's record after a delta vertex on shape `shape` that sampled `bs`: kept
    /// through a refraction at a refractor, dropped otherwise.
    pub(super) fn refracted_after_delta<W>(
        &self,
        start: Option<RefractedStart>,
        shape: u32,
        bs: &BsdfSample<W>,
    ) -> Option<RefractedStart> {
        let s = start?;
        (self.is_refractor(shape) && bs.flags.contains(BsdfFlags::DELTA_TRANSMISSION) && s.deltas < MAX_CHAIN)
            .then_some(RefractedStart {
                deltas: s.deltas + 1,
                ..s
            })
    }

    /// `s = p₃/p₁` for a path the path tracer traced from `start` and that hit light `li`
    /// (zero when refracted next-event estimation cannot produce it).
    pub(super) fn refracted_ratio(
        &self,
        start: Option<&RefractedStart>,
        li: usize,
        wl: &SampledWavelengths,
    ) -> f32 {
        match start {
            Some(s) if s.deltas > 0 => self.straight_light_pdf(&s.light_ref, &s.ray, li, wl) / s.bsdf_pdf,
            _ => 0.0,
        }
    }

    /// The light-side factor of `s` at a light subpath's first smooth vertex `si` (lobes
    /// `flags`) on area light `li`'s subpath, reached along `−to_chain`: `p_sel·p(ω)` for ω = `to_chain` with the camera side
    /// along +n_s ([0]) and −n_s ([1]) of its shading normal.
    pub(super) fn refracted_density_at(
        &self,
        si: &SurfaceInteraction,
        flags: BsdfFlags,
        to_chain: Vec3,
        li: usize,
        wl: &SampledWavelengths,
    ) -> [f32; 2] {
        // One straight line for both sides; only the light selection depends on the side.
        let dir_pdf = self.straight_area_pdf(si.p, &si.spawn_ray(to_chain), li, wl);
        if dir_pdf == 0.0 {
            return [0.0; 2];
        }
        let selected = |n: Vec3| {
            let r = LightRef {
                p: si.p,
                n,
                hemisphere: !flags.is_transmission(),
                mis: true,
                // Area lights only, which are never left to BSDF sampling.
                resolved_density: 0.0,
                resampled: false,
            };
            self.lights.pmf_at(&r, li) * dir_pdf
        };
        [selected(si.shading.n), selected(-si.shading.n)]
    }

    /// The shadow ray of the light sample `ls` of light `li` drawn at `v`, followed through the
    /// sheets and the glass it meets: [`LightPath::Straight`] with the sheets' transmittance
    /// when it reaches the light unrefracted (the same as [`PathTracer::visibility`]),
    /// [`LightPath::Refracted`] when refracted next-event estimation counts it, or `Blocked`.
    /// `bsdf_pdf` is the BSDF density of `ls.wi` at `v`. One closest-hit query per surface met,
    /// so a blocked ray costs what an occlusion query costs and the glass is entered where the
    /// query found it.
    pub(super) fn trace_light_sample<W: Weight>(
        &self,
        v: &Vertex,
        c: &PathContext,
        li: usize,
        ls: &LightSample,
        bsdf_pdf: f32,
        wl: &SampledWavelengths,
    ) -> LightPath<W>
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        // At least one refraction: the path has depth + 3 segments or more.
        let may_refract = !ls.delta
            && !ls.li.is_black()
            && self.refracted_light(li)
            && c.depth as u64 + 3 <= self.max_depth as u64;
        let sheets = self.thin_shadows && self.any_thin;
        let mut ray = if ls.dist.is_finite() {
            v.si.spawn_ray_to(v.si.p + ls.wi * ls.dist, ls.normal)
        } else {
            v.si.spawn_ray(ls.wi)
        };
        let mut tr = W::ONE;
        let mut deltas = 0u32;
        let mut eta = 1.0f32;
        let mut crossed = 0u32;
        let mut wl_chain = *wl;
        // The direction of the chain's current segment (its sheets' transmittances use it).
        let mut dir = ray.d;
        let hit = loop {
            let Some(h) = self.accel.intersect(&ray) else {
                if deltas == 0 {
                    return LightPath::Straight(tr);
                }
                // Left the scene: a light at infinity, seen along the refracted direction. No
                // light subpath starts there, so two strategies share the path.
                if !self.lights.infinite().contains(&(li as u32)) {
                    return LightPath::Blocked;
                }
                let le = self.lights.le_escaped(None, li, ray.d, wl).0;
                let w = shares(f32::INFINITY, ls.pdf / bsdf_pdf)[2];
                return LightPath::refracted(tr, le, w);
            };
            if sheets && self.is_thin(h.shape) {
                // Straight through a sheet, as a shadow ray crosses it (at most as many as
                // `visibility` crosses).
                crossed += 1;
                if crossed > MAX_NULL_CROSSINGS {
                    return LightPath::Blocked;
                }
                let Some((t, next)) = self.pass_sheet::<W>(&h, &ray, dir, wl, false) else {
                    return LightPath::Blocked;
                };
                tr *= t;
                match next {
                    _ if tr.is_black() => return LightPath::Blocked,
                    Some(r) => ray = r,
                    None if deltas == 0 => return LightPath::Straight(tr),
                    None => return LightPath::Blocked,
                }
                continue;
            }
            if !may_refract || !self.is_refractor(h.shape) {
                break h;
            }
            deltas += 1;
            // Each refraction starts a segment: its own count of sheets, as the path's.
            crossed = 0;
            if deltas > MAX_CHAIN || c.depth as u64 + deltas as u64 + 2 > self.max_depth as u64 {
                return LightPath::Blocked;
            }
            let wi = h.shading.to_local(-ray.d);
            let Some(bs) = self
                .bsdf_at(h.shape, &ShadingPoint::from(&h), wl, |b: &SurfaceBsdf<'_>| {
                    b.sample_weight(&REFRACTION_ONLY, wi, 0.5, Vec2::splat(0.5), &mut wl_chain)
                })
                .flatten()
                .filter(|bs: &BsdfSample<W>| {
                    !bs.weight.is_black() && bs.flags.contains(BsdfFlags::DELTA_TRANSMISSION)
                })
            else {
                return LightPath::Blocked;
            };
            tr *= bs.weight.local_to_world(&h.shading);
            eta *= bs.eta;
            // Refracted: the light point drawn is no longer the target.
            ray = h.spawn_ray(h.shading.to_world(bs.wo));
            dir = ray.d;
        };
        if deltas == 0 || self.lights.shape_light(hit.shape as usize) != Some(li) {
            return LightPath::Blocked;
        }
        let Light::Area(area) = &self.lights.lights()[li] else {
            return LightPath::Blocked;
        };
        let le = area.le(&(&hit).into(), -ray.d, wl);
        // The caustic ratio of the same path, from the path tracer's record extended by the
        // smooth sample at v and the refractions.
        let r = if self.traces_caustics() {
            let cos_out = v.si.n.dot(ls.wi).abs();
            let reverse_pdf = if matches!(c.arrival, Arrival::Delta) {
                let wo = v.si.shading.to_local(ls.wi);
                v.bsdf.pdf(&BsdfContext::importance(), wo, v.wi, wl)
            } else {
                0.0
            };
            let cos_in = v.si.n.dot(v.si.shading.to_world(v.wi)).abs();
            let chain = ChainState::after_smooth(c.chain, bsdf_pdf, c.arrival, cos_in, cos_out, reverse_pdf)
                .map(|ch| ch.after_deltas(deltas, eta));
            self.caustic_ratio(chain.as_ref(), li, area, hit.p, hit.n, -ray.d)
        } else {
            f32::INFINITY
        };
        LightPath::refracted(tr, le, shares(r, ls.pdf / bsdf_pdf)[2])
    }
}

/// Where a light sample's shadow ray went ([`PathTracer::trace_light_sample`]).
pub(super) enum LightPath<W> {
    /// Blocked, or refracted and then missing the light.
    Blocked,
    /// To the light unrefracted, through sheets of this transmittance.
    Straight(W),
    /// Refracted on the way: the transmittance, the radiance arriving along the last direction,
    /// and the MIS weight `w₃`.
    Refracted(W, SampledSpectrum, f32),
}

impl<W: Weight> LightPath<W> {
    fn refracted(tr: W, le: SampledSpectrum, w: f32) -> Self {
        if le.is_black() || tr.is_black() || !(w > 0.0) {
            Self::Blocked
        } else {
            Self::Refracted(tr, le, w)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::shares;

    /// The three shares are the power heuristic's for densities (1, 1/r, s), numbers in [0, 1]
    /// that sum to one for every pair, including the limits where a strategy cannot produce the
    /// path (r = ∞ or NaN: no connection; s = 0 or NaN: no refracted sample) and where the path
    /// tracer cannot (r = 0 or s = ∞).
    #[test]
    fn shares_are_the_power_heuristic_and_sum_to_one() {
        let values = [
            0.0,
            1e-20,
            1e-3,
            0.5,
            1.0,
            3.0,
            1e4,
            1e30,
            f32::MAX,
            f32::INFINITY,
            f32::NAN,
        ];
        for r in values {
            for s in values {
                let w = shares(r, s);
                let sum: f32 = w.iter().sum();
                assert!(
                    w.iter().all(|x| (0.0..=1.0).contains(x)),
                    "r = {r}, s = {s}: {w:?}"
                );
                assert!((sum - 1.0).abs() < 1e-6, "r = {r}, s = {s}: {w:?} sums to {sum}");
            }
        }
        let (r, s) = (2.0f64, 0.5f64);
        let (p1, p2, p3) = (1.0, 1.0 / r, s);
        let total = p1 * p1 + p2 * p2 + p3 * p3;
        let w = shares(r as f32, s as f32);
        for (got, want) in w.iter().zip([p1 * p1 / total, p2 * p2 / total, p3 * p3 / total]) {
            assert!((*got as f64 - want).abs() < 1e-6, "{w:?}");
        }
        assert_eq!(shares(f32::INFINITY, 0.0), [1.0, 0.0, 0.0]);
        assert_eq!(shares(0.0, 1.0), [0.0, 1.0, 0.0]);
        assert_eq!(shares(f32::INFINITY, f32::INFINITY), [0.0, 0.0, 1.0]);
        assert_eq!(shares(f32::INFINITY, 1.0), [0.5, 0.0, 0.5]);
    }
}
