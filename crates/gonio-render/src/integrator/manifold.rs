//! Manifold next-event estimation through a mirror sphere (beyond Mitsuba; Hanika, Droske and
//! Fascione 2015, "Manifold Next Event Estimation", for one reflection on an analytic sphere).
//!
//! # The paths
//!
//! A floor lit by a small light's reflection in a mirror sphere (`L S D`) is a caustic: next-event
//! estimation cannot reach the light through the mirror, and BSDF sampling finds it only when the
//! sampled direction happens to reflect into the light (a firefly for a small light). Seen
//! directly, such a caustic is the light subpaths' business ([`super::caustics`]); seen through
//! another delta surface (the floor's caustic reflected in a second mirror sphere, `E S D S L`)
//! no light subpath can join the camera path, whose vertex before the floor is delta. There
//! this strategy connects the floor point `x` to a point `l` drawn on the light through the one
//! point `s` of a mirror sphere where light from `l` reflects towards `x`.
//!
//! # The estimator
//!
//! At a smooth vertex `x` whose camera-side neighbour is delta: a mirror sphere `k` with
//! probability `1/K` (the spheres whose material is a pure delta reflection, [`Setup`]), an
//! area light `j` on a rectangle, disk or sphere by power (`p_j`), a point `l` on it uniformly
//! (`1/A_j`). The reflection point `s` lies in the plane through the sphere's centre `c`, `x`
//! and `l`, on the arc between the directions of `x` and `l` seen from `c`, where the normal
//! bisects the directions towards `x` and `l` (Alhazen's problem on a circle; on that arc the
//! difference of the two cosines decreases monotonically, so bisection finds the one solution
//! from which both points are in front of the mirror). With ω = (s − x)/|s − x| the sample adds
//!
//! `β · f_x(ωᵢ, ω) · |cos θ| · F_s · Lₑ(l, −ω′) / p_M(ω) · w`,
//!
//! where `F_s` is the mirror's weight for the reflection (its BSDF sample's), ω′ the reflected
//! direction, and `p_M(ω) = (1/K) · p_j · (1/A_j) · |dA_l/dω|` the density of ω: the light
//! point's area density carried to directions at `x` by the Jacobian of the map ω ↦ l (trace
//! ω to the sphere, reflect, meet the light's tangent plane at `l`), computed by central
//! differences in `f64` ([`area_per_solid_angle`]). The segments must be unoccluded: ω's first
//! hit is the sphere at `s`, the reflected ray's first hit the light at `l`.
//!
//! # MIS
//!
//! The path tracer produces the same path when BSDF sampling at `x` takes ω, the sphere
//! reflects it and the reflected ray hits light `j`, with density `p_x(ω)` (the BSDF's). No
//! light subpath can (the vertex before `x` is delta), nor refracted next-event estimation (the
//! chain reflects), so the two share such paths by the power heuristic: this strategy
//! `p_M²/(p_M² + p_x²)`, the path tracer the rest. The path tracer keeps its start ([`Start`])
//! from `x` through the sphere and evaluates `p_M` for the light it hits, with the same
//! function; both strategies apply the same conditions ([`PathTracer::manifold_applies`]): a
//! `path` integrator, not polarized, no `thindielectric` sheet in the scene (a sheet on a
//! segment would be a vertex for one strategy and not the other), and `max_depth` leaving room
//! for the two more segments.

use super::{PathState, PathTracer, Vertex};
use crate::accel::Intersect;
use crate::emitter::{Distribution1D, Light, LightPoint};
use crate::geometry::sampling::sample_area;
use crate::geometry::triangle::TriRay;
use crate::geometry::{ShapeKind, SurfaceInteraction, WorldShape};
use crate::material::ShadingPoint;
use glam::{DVec3, Vec2, Vec3};
use gonio_core::weight::Weight;
use gonio_core::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, SampledSpectrum, SampledWavelengths};

/// The mirror spheres and the lights the strategy connects through and to.
#[derive(Clone, Debug)]
pub(super) struct Setup {
    /// Shape index, centre and radius of each sphere whose material is a pure delta reflection.
    spheres: Vec<(u32, DVec3, f64)>,
    /// Per shape: its index in `spheres`.
    sphere_of_shape: Vec<Option<u32>>,
    /// Light index of each area light on a rectangle, disk or sphere.
    lights: Vec<usize>,
    /// Per light index: its index in `lights`.
    light_slot: Vec<Option<u32>>,
    /// The lights' choice, by power.
    selection: Distribution1D,
}

impl Setup {
    /// The set-up for a scene, or `None` when it has no mirror sphere or no such light.
    pub(super) fn new(tracer: &PathTracer<'_>) -> Option<Self> {
        let shapes = tracer.accel.shapes();
        let mut spheres = Vec::new();
        let mut sphere_of_shape = vec![None; shapes.len()];
        for (i, shape) in shapes.iter().enumerate() {
            let ShapeKind::Sphere { center, radius, .. } = shape.kind else {
                continue;
            };
            // Exactly a delta reflection: a material whose frame is perturbed (`normalmap`,
            // `bumpmap`) also says ANISOTROPIC | NON_SYMMETRIC and is left out, since it does
            // not reflect about the sphere's normal.
            let mirror = tracer
                .material_of(i as u32)
                .is_some_and(|m| m.flags() == BsdfFlags::DELTA_REFLECTION);
            if mirror && tracer.lights.shape_light(i).is_none() && radius > 0.0 {
                sphere_of_shape[i] = Some(spheres.len() as u32);
                spheres.push((i as u32, center.as_dvec3(), radius as f64));
            }
        }
        let mut lights = Vec::new();
        let mut power = Vec::new();
        let mut light_slot = vec![None; tracer.lights.lights().len()];
        for (li, light) in tracer.lights.lights().iter().enumerate() {
            let Light::Area(area) = light else { continue };
            let planar_or_sphere = matches!(
                shapes.get(area.shape).map(|s| &s.kind),
                Some(ShapeKind::Rectangle { .. } | ShapeKind::Disk { .. } | ShapeKind::Sphere { .. })
            );
            if planar_or_sphere && sphere_of_shape[area.shape].is_none() && area.power() > 0.0 {
                light_slot[li] = Some(lights.len() as u32);
                lights.push(li);
                power.push(area.power());
            }
        }
        (!spheres.is_empty() && !lights.is_empty()).then(|| Self {
            spheres,
            sphere_of_shape,
            lights,
            light_slot,
            selection: Distribution1D::new(&power),
        })
    }

    /// `p_M(ω)` from `x` along `omega` through sphere `k` to light `li` hit at `at_light` (point
    /// and geometric normal): zero where the strategy does not produce the path.
    fn density(
        &self,
        tracer: &PathTracer<'_>,
        (x, omega): (Vec3, Vec3),
        k: u32,
        li: usize,
        at_light: &LightPoint,
    ) -> f32 {
        let Some(slot) = self.light_slot.get(li).copied().flatten() else {
            return 0.0;
        };
        let Light::Area(area) = &tracer.lights.lights()[li] else {
            return 0.0;
        };
        let (_, c, radius) = self.spheres[k as usize];
        let (l, n_l) = (at_light.p, at_light.n);
        let jacobian = area_per_solid_angle(
            x.as_dvec3(),
            omega.as_dvec3(),
            c,
            radius,
            l.as_dvec3(),
            n_l.as_dvec3(),
        );
        let p = self.selection.pmf(slot as usize) as f64 / self.spheres.len() as f64 / area.area as f64
            * jacobian;
        if p.is_finite() { p as f32 } else { 0.0 }
    }
}

/// The smooth vertex a camera path left (where the strategy applies) and the mirror sphere its
/// direction reflected on, for `p_M` when the path tracer hits a light next.
#[derive(Clone, Copy, Debug)]
pub(super) struct Start {
    x: Vec3,
    omega: Vec3,
    bsdf_pdf: f32,
    /// The sphere (index in [`Setup`]) once the direction reflected on one.
    sphere: Option<u32>,
}

impl PathTracer<'_> {
    /// True when the strategy applies at a vertex of a path in `state`: the vertex before is
    /// delta and two more segments fit in `max_depth` (see the module docs for the rest, fixed
    /// per render in [`Self::manifold`]).
    #[inline]
    pub(super) fn manifold_applies<W: Weight>(&self, state: &PathState<W>) -> bool {
        self.manifold.is_some() && state.after_delta() && state.depth.saturating_add(2) < self.max_depth
    }

    /// The path tracer's record after the vertex at `si` sampled `bs` (world direction `dir`),
    /// given the record before it and whether the strategy applied there. (No sheet can lie on
    /// the segments: the strategy is off in scenes with a material that passes light straight
    /// through, [`Self::new`].)
    pub(super) fn manifold_after_sample<W>(
        &self,
        start: Option<Start>,
        applies_here: bool,
        (si, dir): (&SurfaceInteraction, Vec3),
        bs: &BsdfSample<W>,
    ) -> Option<Start> {
        let setup = self.manifold.as_ref()?;
        if !bs.flags.is_delta() {
            return applies_here.then_some(Start {
                x: si.p,
                omega: dir,
                bsdf_pdf: bs.pdf,
                sphere: None,
            });
        }
        let s = start?;
        let k = setup.sphere_of_shape.get(si.shape as usize).copied().flatten()?;
        (s.sphere.is_none() && bs.flags.contains(BsdfFlags::DELTA_REFLECTION))
            .then_some(Start { sphere: Some(k), ..s })
    }

    /// The ratio `p_M/p_x` for a path the path tracer traced from `start` that hit area light
    /// `li` at `hit` (zero where the strategy cannot produce it).
    pub(super) fn manifold_ratio(&self, start: Option<&Start>, li: usize, hit: &SurfaceInteraction) -> f32 {
        let (Some(setup), Some(s)) = (self.manifold.as_ref(), start) else {
            return 0.0;
        };
        let Some(k) = s.sphere else { return 0.0 };
        if !(s.bsdf_pdf > 0.0) {
            return 0.0;
        }
        setup.density(self, (s.x, s.omega), k, li, &LightPoint::from(hit)) / s.bsdf_pdf
    }

    /// One manifold sample at `v` (the module docs): `u_sel` picks the sphere and the light,
    /// `u` the point on the light. Spectral paths only.
    pub(super) fn manifold_next_event(
        &self,
        v: &Vertex,
        u_sel: f32,
        u: Vec2,
        wl: &SampledWavelengths,
    ) -> SampledSpectrum {
        self.manifold_sample(v, u_sel, u, wl)
            .unwrap_or(SampledSpectrum::ZERO)
    }

    fn manifold_sample(
        &self,
        v: &Vertex,
        u_sel: f32,
        u: Vec2,
        wl: &SampledWavelengths,
    ) -> Option<SampledSpectrum> {
        let setup = self.manifold.as_ref()?;
        let n_spheres = setup.spheres.len();
        let pick = (u_sel * n_spheres as f32).min(n_spheres as f32 - 1.0);
        let k = pick as usize;
        let (slot, _, _) = setup.selection.sample_discrete(pick - k as f32);
        let li = setup.lights[slot];
        let Light::Area(area) = &self.lights.lights()[li] else {
            return None;
        };
        let light_shape = &self.accel.shapes()[area.shape];
        let on_light = sample_area(light_shape, u);
        let (sphere_shape, c, radius) = setup.spheres[k];
        let x = v.si.p;
        let s = reflection_point(c, radius, x.as_dvec3(), on_light.p.as_dvec3())?.as_vec3();
        let omega = (s - x).normalize_or_zero();
        let local = v.si.shading.to_local(omega);
        let ctx = BsdfContext::radiance();
        let f = v.bsdf.eval(&ctx, v.wi, local, wl);
        if f.is_black() {
            return None;
        }
        // The light must face s (it emits from its front only).
        if (s - on_light.p).dot(on_light.n) <= 0.0 {
            return None;
        }
        let pdf_x = v.bsdf.pdf(&ctx, v.wi, local, wl);
        // x → s: nothing in between (the sphere itself is not: x is in front of its tangent
        // plane at s), and the sphere's record at s.
        let sphere = &self.accel.shapes()[sphere_shape as usize];
        let at_s = hit_on(sphere, sphere_shape, &v.si.spawn_ray(omega))?;
        if (at_s.p - s).length() > 1e-3 * radius as f32
            || self.accel.occluded(&v.si.spawn_ray_to(at_s.p, Some(at_s.n)))
        {
            return None;
        }
        // The mirror's reflection there, and s → l.
        let wi_s = at_s.shading.to_local(-omega);
        let bs = self.bsdf_at(at_s.shape, &ShadingPoint::from(&at_s), wl, |bsdf| {
            bsdf.sample(&ctx, wi_s, 0.5, Vec2::splat(0.5), &mut wl.clone())
        })??;
        if !bs.flags.contains(BsdfFlags::DELTA_REFLECTION) || bs.weight.is_black() {
            return None;
        }
        let reflected = at_s.shading.to_world(bs.wo);
        let at_l = hit_on(light_shape, area.shape as u32, &at_s.spawn_ray(reflected))?;
        if (at_l.p - on_light.p).length() > 1e-3 * (radius as f32).max(1.0)
            || self.accel.occluded(&at_s.spawn_ray_to(at_l.p, Some(at_l.n)))
        {
            return None;
        }
        let at_light = LightPoint::from(&at_l);
        let le = area.le(&at_light, -reflected, wl);
        if le.is_black() {
            return None;
        }
        let p_m = setup.density(self, (x, omega), k as u32, li, &at_light);
        if !(p_m > 0.0) {
            return None;
        }
        let w = self.mis(p_m, pdf_x);
        let contribution = f * bs.weight * le * (local.z.abs() * w / p_m);
        contribution.is_finite().then_some(contribution)
    }
}

/// The record of `ray`'s nearest hit on `shape` alone (index `index`; a sphere, rectangle or disk).
fn hit_on(shape: &WorldShape, index: u32, ray: &crate::geometry::Ray) -> Option<SurfaceInteraction> {
    let tri = TriRay::new(ray);
    let hit = shape.intersect_prim(0, ray, &tri)?;
    Some(shape.interaction(index, 0, ray, hit))
}

/// The point of the sphere (centre `c`, radius `radius`) where light from `l` reflects towards
/// `x` (both outside it), or `None` (a point inside, or `x`, `l` and `c` on one line).
///
/// By symmetry the normal `n` at the reflection point lies in the plane of `c`, `x` and `l`, on
/// the arc from the direction `e₁` of `x` to the direction `e_l` of `l` (seen from `c`):
/// `n(t) = normalize((1 − t)·e₁ + t·e_l)`, t ∈ [0, 1]. There `g = n·(x − s)/|x − s| −
/// n·(l − s)/|l − s|` falls from positive (t = 0) to negative (t = 1) monotonically, and its
/// root (kept bracketed, to 10⁻⁹ in t) is where the normal bisects the two directions: the law
/// of reflection.
pub(super) fn reflection_point(c: DVec3, radius: f64, x: DVec3, l: DVec3) -> Option<DVec3> {
    let (dx, dl) = (x - c, l - c);
    if !(dx.length() > radius && dl.length() > radius) {
        return None;
    }
    let e1 = dx.normalize();
    let across = dl - e1 * dl.dot(e1);
    if !(across.length() > 1e-9 * dl.length()) {
        return None;
    }
    // Only where the caps of the sphere that x and l see overlap can a point face both: the
    // angle between them below the sum of the caps' half-angles (compared by cosines).
    let e_l = dl.normalize();
    let (a, b) = (radius / dx.length(), radius / dl.length());
    if e1.dot(e_l) <= a * b - ((1.0 - a * a) * (1.0 - b * b)).sqrt() {
        return None;
    }
    // The arc from e₁ to the direction of l, without trigonometry: n(t) = normalize((1 − t)·e₁
    // + t·e_l) turns monotonically from one to the other as t goes from 0 to 1.
    let normal = |t: f64| (e1 + (e_l - e1) * t).normalize();
    let g = |t: f64| {
        let n = normal(t);
        let s = c + n * radius;
        n.dot((x - s).normalize()) - n.dot((l - s).normalize())
    };
    // Regula falsi with the Illinois modification: superlinear, and the bracket always holds
    // the root.
    // The bisector of e₁ and e_l (t = ½) is the answer when x and l are equally far from c:
    // start from the half of [0, 1] it brackets.
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let (mut g_lo, mut g_hi) = (g(lo), g(hi));
    if !(g_lo > 0.0 && g_hi < 0.0) {
        return None;
    }
    let g_half = g(0.5);
    if g_half > 0.0 {
        (lo, g_lo) = (0.5, g_half);
    } else {
        (hi, g_hi) = (0.5, g_half);
    }
    let tolerance = 1e-9;
    let mut side = 0i8;
    let mut theta = 0.5 * (lo + hi);
    for _ in 0..60 {
        theta = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
        if !(theta > lo && theta < hi) {
            theta = 0.5 * (lo + hi);
        }
        let g_theta = g(theta);
        if g_theta > 0.0 {
            lo = theta;
            g_lo = g_theta;
            if side == 1 {
                g_hi *= 0.5;
            }
            side = 1;
        } else {
            hi = theta;
            g_hi = g_theta;
            if side == -1 {
                g_lo *= 0.5;
            }
            side = -1;
        }
        if hi - lo < tolerance || g_theta == 0.0 {
            break;
        }
    }
    let n = normal(theta);
    let s = c + n * radius;
    (n.dot(x - s) > 0.0 && n.dot(l - s) > 0.0).then_some(s)
}

/// |dA_l/dω| at `x` for the direction `omega`: how much area of the light's tangent plane at `l`
/// (normal `n_l`) a unit solid angle of directions from `x` covers after reflecting on the
/// sphere (centre `c`, radius `radius`). Central differences over ±10⁻⁵ rad in two orthogonal
/// directions; 0 where a perturbed ray misses the sphere or the plane.
pub(super) fn area_per_solid_angle(
    x: DVec3,
    omega: DVec3,
    c: DVec3,
    radius: f64,
    l: DVec3,
    n_l: DVec3,
) -> f64 {
    let omega = omega.normalize();
    let (t1, t2) = omega.any_orthonormal_pair();
    let land = |d: DVec3| -> Option<DVec3> {
        let d = d.normalize();
        // The nearer intersection with the sphere.
        let oc = x - c;
        let b = oc.dot(d);
        let disc = b * b - (oc.length_squared() - radius * radius);
        if !(disc >= 0.0) {
            return None;
        }
        let t = -b - disc.sqrt();
        if !(t > 0.0) {
            return None;
        }
        let s = x + d * t;
        let n = (s - c) / radius;
        let r = d - n * (2.0 * d.dot(n));
        let denom = r.dot(n_l);
        if denom == 0.0 {
            return None;
        }
        let t2 = (l - s).dot(n_l) / denom;
        (t2 > 0.0).then(|| s + r * t2)
    };
    const H: f64 = 1e-5;
    let diff =
        |t: DVec3| -> Option<DVec3> { Some((land(omega + t * H)? - land(omega - t * H)?) / (2.0 * H)) };
    match (diff(t1), diff(t2)) {
        (Some(a), Some(b)) => a.cross(b).dot(n_l).abs(),
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_point_obeys_the_law_of_reflection() {
        let c = DVec3::new(0.3, -0.2, 0.1);
        let radius = 0.7;
        let cases = [
            (DVec3::new(2.0, 0.5, -1.0), DVec3::new(-1.0, 3.0, 2.0)),
            (DVec3::new(0.0, -3.0, 0.0), DVec3::new(2.5, -1.0, 0.5)),
            (DVec3::new(5.0, 5.0, 5.0), DVec3::new(1.5, 0.0, 0.0)),
        ];
        for (x, l) in cases {
            let s = reflection_point(c, radius, x, l).expect("a reflection point");
            let n = (s - c).normalize();
            assert!(((s - c).length() - radius).abs() < 1e-9);
            let (to_x, to_l) = ((x - s).normalize(), (l - s).normalize());
            // Equal angles, and the mirror image of one direction is the other.
            assert!((n.dot(to_x) - n.dot(to_l)).abs() < 1e-9, "{x} {l}");
            let mirrored = n * (2.0 * n.dot(to_x)) - to_x;
            assert!((mirrored - to_l).length() < 1e-8, "{x} {l}");
        }
        // A point inside the sphere, on the line through the centre, or the two points on
        // nearly opposite sides (no point of the sphere is in front of both): none.
        assert!(reflection_point(c, radius, c, DVec3::X * 3.0).is_none());
        assert!(reflection_point(c, radius, DVec3::new(0.0, -3.0, 0.0), DVec3::new(0.1, 4.0, 0.2)).is_none());
        assert!(reflection_point(DVec3::ZERO, 1.0, DVec3::X * 2.0, DVec3::X * 3.0).is_none());
    }

    #[test]
    fn area_per_solid_angle_matches_a_flat_mirror_limit_and_finite_areas() {
        // A huge sphere is locally a plane mirror: the reflected ray is a straight line from the
        // mirror image of x, so |dA/dω| = d²/|cos θ_l| with d the unfolded distance.
        let radius = 1e6;
        let c = DVec3::new(0.0, -radius, 0.0);
        let x = DVec3::new(0.0, 1.0, 0.0);
        let l = DVec3::new(2.0, 1.5, 0.0);
        let n_l = DVec3::new(-1.0, -1.0, 0.0).normalize();
        let s = reflection_point(c, radius, x, l).unwrap();
        let omega = (s - x).normalize();
        let j = area_per_solid_angle(x, omega, c, radius, l, n_l);
        let d = (s - x).length() + (l - s).length();
        let cos_l = (l - s).normalize().dot(n_l).abs();
        let expected = d * d / cos_l;
        assert!((j / expected - 1.0).abs() < 1e-3, "{j} vs {expected}");
        // A convex mirror spreads the light: finite and larger than the unfolded-distance value.
        let (c, radius) = (DVec3::ZERO, 1.0);
        let x = DVec3::new(0.0, 3.0, 0.0);
        let l = DVec3::new(3.0, 0.5, 0.0);
        let s = reflection_point(c, radius, x, l).unwrap();
        let j = area_per_solid_angle(x, (s - x).normalize(), c, radius, l, DVec3::NEG_X);
        let d = (s - x).length() + (l - s).length();
        let flat = d * d / (l - s).normalize().dot(DVec3::NEG_X).abs();
        assert!(j.is_finite() && j > flat, "{j} vs {flat}");
    }
}
