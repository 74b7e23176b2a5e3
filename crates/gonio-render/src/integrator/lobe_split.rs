//! Lobe splitting at glass (beyond Mitsuba): where the reflection or the refraction of a
//! `roughdielectric` vertex leaves the scene, it is added whole, and the path follows the other;
//! where the outward lobe of a `dielectric` or `roughdielectric` vertex, or the coat's mirror
//! reflection of a `plastic` one, meets an area light (a glint), that light's emission is added
//! whole.
//!
//! # Why
//!
//! At a glass vertex the path tracer takes one lobe, reflection with probability F, refraction
//! with 1 − F (about a facet normal `m` it draws first, at rough glass). The lobe not taken is
//! left to the paths that take it. Three kinds of light pay for that coin: the environment
//! reflected by the glass the camera sees (taken with F ≈ 0.04–0.1, so each find is 10–25× too
//! bright), light bouncing inside a glass object, which leaves at whichever bounce the coin
//! first says "refract" (Mitsuba's `bsdf_roughdielectric_glass` preview: 30 % of its error), and
//! the reflections of lamps in glass (glints), which next-event estimation cannot find behind a
//! delta lobe and which the coin finds 10–25× too bright. `plastic` flips the same kind of coin
//! between its coat's mirror (probability P_spec) and its diffuse base: its lamp reflections are
//! glints too (its two lobes take the places of reflection and refraction below; both point
//! outwards, and the mirror is the one looked at).
//!
//! # The estimator
//!
//! The lobe choice's numbers are the path tracer's (at rough glass `u_dir` draws the facet), and
//! both directions are made
//! ([`RoughDielectric::sample_split`](gonio_core::bsdfs::roughdielectric::RoughDielectric::sample_split),
//! [`Dielectric::sample_split`](gonio_core::bsdfs::dielectric::Dielectric::sample_split),
//! [`Plastic::sample_split`](gonio_core::bsdfs::plastic::Plastic::sample_split)),
//! each weighted as its lobe sampled alone, `w = f·|cos θo|/p_lobe` (F or 1 − F, times tints and
//! η², for smooth glass). The lobe that points to the *outside* of the surface (ωo·n > 0: the
//! reflection on the outside, the refraction from inside; only there can light leave a closed
//! object) is looked at first.
//!
//! * Rough glass in a scene with a light at infinity: the outward ray is traced. If it leaves
//!   the scene, it adds `β·w·L_∞(ω)` whole (weighted against next-event estimation as a BSDF
//!   sample that escapes) and the path follows the inward lobe with its whole weight `w`: no
//!   coin.
//! * Smooth or rough glass, or plastic, in a scene with area lights: where the outward ray may
//!   meet one ([`LightShapes`]: the lights' analytic shapes exactly, others by their bounding
//!   boxes), it is traced, and if its hit is an area light, `β·w·L_e` is added whole, with the MIS weight
//!   the path tracer gives that emission (the path's state along the lobe,
//!   [`PathTracer::advanced`]); then the coin below, and a path that follows the outward lobe
//!   does not add that emission again.
//! * Otherwise the step is the path tracer's own: the lobe `u_lobe` takes (probability c = F or
//!   1 − F) is followed with `w/c`, reusing the outward ray's hit when it was traced.
//!
//! Given the lobe numbers, which case applies is fixed (a function of the outward ray), and in
//! each case every lobe's integral is estimated without bias: whole, or followed with a
//! probability its weight divides out (the emission at the outward hit whole, what lies beyond
//! it by the coin). The cost is the outward ray where the path goes on inwards; the escapes
//! took the preview's relMSE −29 % at +11 % CPU time (following the inward lobe there with the
//! coin's probability instead gave −27 % at +13 %, and under a uniform sky 0.96× the pixel
//! variance against 0.85×), the glints materials' −17 % at +2 % CPU time, cornell-spheres' −12 % at +3 % and
//! thin-vs-thick's −9 % at +5 % (`bench/RESULTS.md`).
//!
//! # MIS
//!
//! The weights stay the path tracer's functions of the path: a branch's direction carries the
//! full BSDF's density (F·p_r or (1 − F)·p_t; F or 1 − F for a delta lobe) as its `pdf`, for the
//! power heuristic against next-event estimation and for the ratios of the other strategies,
//! which see the same density whichever way the direction was reached. Weights that sum to one
//! over the strategies for every path need the same function on every side, not the density a
//! sample was actually drawn with.
//!
//! Where the camera sees smooth glass directly, both lobes are followed whole instead
//! (`split_visible_glass`, [`PathTracer::visible_glass_split`]); the rule here applies where
//! that one does not: deeper vertices, glass seen through a sheet, rough glass.
//!
//! Not split: escapes at smooth glass (measured with the rule above and not kept: 4–9 % less
//! error for 10 % more time, `bench/RESULTS.md`), `thindielectric` sheets by this rule (a
//! sheet's transmission crosses straight, keeping the previous vertex's MIS state, which the
//! emission added whole would have to follow), trees of several BSDFs, multiple-scattering
//! glass, dispersive glass while the path's secondary wavelengths live (a refraction would end
//! them for both lobes), and polarized renders.

use super::{PathState, PathTracer, StepFrom, Vertex, caustics};
use crate::accel::Intersect;
use crate::emitter::{Light, Lights};
use crate::geometry::shape::TriRay;
use crate::geometry::{Ray, ShapeKind, SurfaceInteraction, WorldShape};
use crate::sampler::PathSampler;
use glam::{Vec2, Vec3};
use gonio_core::weight::Weight;
use gonio_core::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, SampledWavelengths};

/// One lobe of a split vertex: world-space weight `w` (`pdf` the full density) and the
/// probability `c` with which the path tracer takes it.
#[derive(Clone, Copy)]
struct Lobe<W> {
    sample: BsdfSample<W>,
    c: f32,
}

/// Both lobes of a split vertex, and the number that chooses between them.
#[derive(Clone, Copy)]
pub(super) struct LobePair<W> {
    /// Reflection, refraction.
    lobes: [Option<Lobe<W>>; 2],
    /// The probability F of taking the reflection.
    reflectance: f32,
    u_lobe: f32,
    /// The lobe followed needs the light tracer's density of its reverse (for the caustics).
    want_reverse: bool,
    /// An outward lobe that leaves the scene is added whole (rough glass under a light at
    /// infinity).
    escapes: bool,
}

/// The lobe a split vertex's path follows: its sample (weight divided by the probability of
/// following it), the surface its ray hits, and its reverse density.
pub(super) struct Followed<W> {
    pub sample: BsdfSample<W>,
    pub hit: SurfaceInteraction,
    pub reverse_pdf: f32,
    /// The emission at `hit` was added already (a glint, added whole).
    pub emitted: bool,
}

/// Which rays may meet an area light, tested before a lobe's ray is traced through the whole
/// scene: the lights' analytic shapes exactly, the others by their bounding boxes. A ray it
/// misses is never an area light's (a false alarm costs one traced ray, nothing else).
#[derive(Clone, Debug)]
pub(super) struct LightShapes {
    /// Spheres, rectangles and disks that emit, by shape index.
    analytic: Vec<u32>,
    /// Bounding boxes of the other emitting shapes (meshes, instances, SDF grids).
    boxes: Vec<(Vec3, Vec3)>,
}

impl LightShapes {
    /// The area lights' shapes; `None` when there is no area light.
    pub(super) fn new(lights: &Lights, shapes: &[WorldShape]) -> Option<Self> {
        let mut out = Self {
            analytic: Vec::new(),
            boxes: Vec::new(),
        };
        for light in lights.lights() {
            let Light::Area(a) = light else { continue };
            let Some(shape) = shapes.get(a.shape) else {
                continue;
            };
            match &shape.kind {
                ShapeKind::Sphere { .. } | ShapeKind::Rectangle { .. } | ShapeKind::Disk { .. } => {
                    out.analytic.push(a.shape as u32)
                }
                // A mesh without triangles emits nothing a ray could meet.
                ShapeKind::Mesh(m) if m.indices.is_empty() => {}
                ShapeKind::Mesh(m) => out.boxes.push(
                    (0..m.indices.len())
                        .map(|i| shape.prim_bounds(i))
                        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (a, b)| {
                            (lo.min(a), hi.max(b))
                        }),
                ),
                _ => out.boxes.push(shape.prim_bounds(0)),
            }
        }
        (!out.analytic.is_empty() || !out.boxes.is_empty()).then_some(out)
    }

    /// Whether `ray` may meet an area light within `ray.tmax`.
    pub(super) fn may_hit(&self, shapes: &[WorldShape], ray: &Ray) -> bool {
        let tri = TriRay::none(ray);
        self.analytic
            .iter()
            .any(|&s| shapes[s as usize].intersect_prim(0, ray, &tri).is_some())
            || self.boxes.iter().any(|&(lo, hi)| slab_hit(ray, lo, hi))
    }
}

/// Whether `ray` meets the box `[lo, hi]` within `(0, ray.tmax]` (with a few ulps of slack on
/// the far side). An axis the ray runs parallel to is a test of its origin between the two
/// planes, not a division by zero.
fn slab_hit(ray: &Ray, lo: Vec3, hi: Vec3) -> bool {
    let (mut near, mut far) = (0.0f32, ray.tmax);
    for k in 0..3 {
        let (o, d) = (ray.o[k], ray.d[k]);
        if d == 0.0 {
            if !(lo[k] <= o && o <= hi[k]) {
                return false;
            }
            continue;
        }
        let (a, b) = ((lo[k] - o) / d, (hi[k] - o) / d);
        near = near.max(a.min(b));
        far = far.min(a.max(b));
    }
    near <= far * (1.0 + 4.0 * f32::EPSILON)
}

impl PathTracer<'_> {
    /// Both lobes of `v` when it splits them (`split_escapes`, spectral renders, one
    /// single-scattering `roughdielectric`, `dielectric` or `plastic` whose index does not
    /// disperse the path's live wavelengths, and a light the rule can use); `None` to sample `v`
    /// as usual.
    pub(super) fn lobe_pair<W: Weight>(
        &self,
        v: &Vertex,
        u_lobe: f32,
        u_dir: Vec2,
        wl: &mut SampledWavelengths,
        want_reverse: bool,
    ) -> Option<LobePair<W>> {
        // Sheets (`thindielectric`) cross straight, keeping the previous vertex's MIS state,
        // which the rule's emission would have to follow: not split here.
        if !self.split_escapes || self.polarized || v.bsdf.flags().contains(BsdfFlags::NULL) {
            return None;
        }
        // Escapes carry light only where a light at infinity exists (and are split where no
        // lobe is delta: rough glass); glints only where an area light does.
        let escapes = !v.bsdf.flags().is_delta() && !self.lights.infinite().is_empty();
        if !escapes && self.light_shapes.is_none() {
            return None;
        }
        let split = v.bsdf.sample_split(&BsdfContext::radiance(), v.wi, u_dir, wl)?;
        let lobe = |l: Option<(BsdfSample, f32)>| {
            let (bs, c) = l?;
            if !(bs.weight.is_finite() && !bs.weight.is_black() && c > 0.0) {
                return None;
            }
            Some(Lobe {
                sample: BsdfSample {
                    weight: W::from_spectrum(bs.weight).local_to_world(&v.si.shading),
                    pdf: bs.pdf,
                    wo: bs.wo,
                    flags: bs.flags,
                    eta: bs.eta,
                },
                c,
            })
        };
        Some(LobePair {
            lobes: [lobe(split.reflection), lobe(split.refraction)],
            reflectance: split.reflectance,
            u_lobe,
            want_reverse,
            escapes,
        })
    }

    /// Traces the lobes of `pair` from `v` as the module's rule says: adds what leaves the scene
    /// and the glints to `l` and returns the lobe the path follows (`None`: the path ends).
    pub(super) fn follow_pair<W: Weight>(
        &self,
        pair: LobePair<W>,
        v: &Vertex,
        state: &PathState<W>,
        from: &StepFrom,
        l: &mut W,
        wl: &SampledWavelengths,
    ) -> Option<Followed<W>> {
        let si = v.si;
        // The light tracer's density of a lobe's reverse, where the caustics need it.
        let reverse_pdf = |bs: &BsdfSample<W>| {
            if pair.want_reverse && !bs.flags.is_delta() {
                v.bsdf.pdf(&BsdfContext::importance(), bs.wo, v.wi, wl)
            } else {
                0.0
            }
        };
        // The path's state along a lobe (its weight as given), for the emission it meets.
        let along = |bs: &BsdfSample<W>, weight: W, ray: &Ray| {
            let sample = BsdfSample { weight, ..*bs };
            self.advanced(state, &sample, v, ray, from, reverse_pdf(bs))
        };
        // Follows `lobe` with probability `q` (already decided): its ray's hit (`traced`, when
        // the outward ray was traced already), or the escape it adds.
        let follow =
            |l: &mut W, lobe: Lobe<W>, traced: Option<Option<SurfaceInteraction>>, q: f32, emitted| {
                let dir = si.shading.to_world(lobe.sample.wo);
                let ray = si.spawn_ray(dir);
                let weight = lobe.sample.weight * (1.0 / q);
                match traced.unwrap_or_else(|| self.accel.intersect(&ray)) {
                    Some(hit) => Some(Followed {
                        sample: BsdfSample {
                            weight,
                            ..lobe.sample
                        },
                        hit,
                        reverse_pdf: reverse_pdf(&lobe.sample),
                        emitted,
                    }),
                    None => {
                        self.add_escaped(l, &along(&lobe.sample, weight, &ray), dir, wl);
                        None
                    }
                }
            };
        // Which lobe points outwards (ωo·n > 0: the reflection when ωi is on the outside, the
        // refraction from inside), which inwards, and which the coin takes.
        let [r, t] = pair.lobes;
        let outside = v.wi.z > 0.0;
        let (out, inn) = if outside { (r, t) } else { (t, r) };
        let out_taken = (pair.u_lobe < pair.reflectance) == outside;
        let Some(o) = out else {
            // No outward lobe (total internal reflection, or its direction failed): the coin,
            // which ends the path where it takes the missing lobe (as `sample` does).
            let i = if out_taken { None } else { inn }?;
            return follow(l, i, None, i.c, false);
        };
        let dir = si.shading.to_world(o.sample.wo);
        let ray = si.spawn_ray(dir);
        // The outward ray is traced where the path may follow it and where it may meet an area
        // light; otherwise, for the escape rule, only asked whether it leaves.
        let glint = self
            .light_shapes
            .as_ref()
            .is_some_and(|s| s.may_hit(self.accel.shapes(), &ray));
        let (leaves, out_hit) = if out_taken || glint {
            let hit = self.accel.intersect(&ray);
            (hit.is_none(), Some(hit))
        } else if pair.escapes {
            (!self.accel.occluded(&ray), None)
        } else {
            (false, None)
        };
        if leaves && pair.escapes {
            // Both whole.
            self.add_escaped(l, &along(&o.sample, o.sample.weight, &ray), dir, wl);
            return follow(l, inn?, None, 1.0, false);
        }
        // An area light the outward ray meets: its emission whole, and the coin for the rest.
        let mut emitted = false;
        if glint
            && let Some(Some(hit)) = &out_hit
            && self.lights.shape_light(hit.shape as usize).is_some()
        {
            self.add_emitted(l, &along(&o.sample, o.sample.weight, &ray), hit, dir, wl);
            emitted = true;
        }
        // The path tracer's step.
        if out_taken {
            follow(l, o, out_hit, o.c, emitted)
        } else {
            let i = inn?;
            follow(l, i, None, i.c, false)
        }
    }
}

/// Where a path loop starts (`PathTracer::trace`): its ray and its state.
type PathStart<W> = (Ray, PathState<W>);

impl PathTracer<'_> {
    /// At the first surface the camera sees, smooth glass (one `dielectric` whose index does
    /// not disperse the live wavelengths, or one `thindielectric`) has both lobes followed, each
    /// whole (weight F·tint, or (1 − F)·tint, × 1/η² for a `dielectric`'s refraction; the
    /// BSDF's density F or 1 − F in the MIS weights, as on a coin's path): the starts of the
    /// two paths, refraction first; `None` to take the coin. The coin's variance is at its
    /// worst there: through a pane, every pixel mixes what lies behind it with a reflection
    /// that is often much brighter, and a pixel's few reflected samples decide its value.
    /// Deeper, the coin's noise is averaged with the rest of the path's. `cos_in` is |cos|
    /// between the geometric normal and the direction the path arrived from. Both paths take
    /// the same random numbers from here on (the caller rewinds the sampler): each is the path
    /// the coin would have made with its lobe, with its stratification (unbiased: each path
    /// estimates its lobe's share alone, and the sum of two estimates is one of the sum,
    /// correlated or not).
    ///
    /// Both paths share the sample's wavelengths: a dispersive refraction on the first ends the
    /// secondary wavelengths for the whole sample, the second path's light included, as it
    /// does for the light a path found before such a refraction (and for the caustic light
    /// subpath, which shares them too).
    pub(super) fn visible_glass_split<W: Weight>(
        &self,
        v: &Vertex,
        state: &PathState<W>,
        (arrival, cos_in): (caustics::Arrival, f32),
        sampler: &mut impl PathSampler,
        wl: &mut SampledWavelengths,
    ) -> Option<[Option<PathStart<W>>; 2]> {
        let flags = v.bsdf.flags();
        if !flags.is_delta() || flags.has_smooth() {
            return None;
        }
        let split = v
            .bsdf
            .sample_split(&BsdfContext::radiance(), v.wi, Vec2::splat(0.5), wl)?;
        // The coin's number, drawn all the same: both paths take the dimensions behind it, as
        // the coin's path would (the sampler is rewound for the second, `PathTracer::trace`),
        // but for Russian roulette's, drawn for both here when `rr_depth` ≤ 1.
        let _ = sampler.next_1d();
        let from = StepFrom {
            light_ref: self.light_ref(v, flags, true),
            manifold_here: self.manifold_applies(state),
            arrival,
            cos_in,
        };
        let mut start = |lobe: Option<(BsdfSample, f32)>| {
            let (bs, c) = lobe?;
            if !(c > 0.0 && bs.weight.is_finite() && !bs.weight.is_black()) {
                return None;
            }
            let bs = BsdfSample {
                weight: W::from_spectrum(bs.weight).local_to_world(&v.si.shading),
                pdf: bs.pdf,
                wo: bs.wo,
                flags: bs.flags,
                eta: bs.eta,
            };
            let ray = v.si.spawn_ray(v.si.shading.to_world(bs.wo));
            let mut next = *state;
            if self.thin_shadows && bs.flags.contains(BsdfFlags::NULL) {
                // Straight through a sheet: the previous vertex's MIS state and depth.
                next.cross_sheet(bs.weight).then_some((ray, next))
            } else {
                self.advance(&mut next, &bs, v, &ray, &from, 0.0);
                self.russian_roulette(&mut next, sampler).then_some((ray, next))
            }
        };
        let refraction = start(split.refraction);
        Some([refraction, start(split.reflection)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The light-box test: rays parallel to an axis, also from a point on a face (where the
    /// division form gives ∞ − ∞), along the face, beyond `tmax`, and pointing away.
    #[test]
    fn slab_hit_handles_rays_parallel_to_an_axis() {
        let (lo, hi) = (Vec3::new(-1.0, 2.0, -1.0), Vec3::new(1.0, 2.0, 1.0));
        let ray = |o: Vec3, d: Vec3, tmax: f32| Ray { o, d, tmax };
        // Straight up into a flat (zero-height) lamp, and along its plane from its edge.
        assert!(slab_hit(&ray(Vec3::ZERO, Vec3::Y, f32::INFINITY), lo, hi));
        assert!(slab_hit(
            &ray(Vec3::new(-1.0, 2.0, 0.0), Vec3::X, f32::INFINITY),
            lo,
            hi
        ));
        assert!(!slab_hit(
            &ray(Vec3::new(-1.0, 2.5, 0.0), Vec3::X, f32::INFINITY),
            lo,
            hi
        ));
        // Too short, pointing away, and an oblique hit.
        assert!(!slab_hit(&ray(Vec3::ZERO, Vec3::Y, 1.5), lo, hi));
        assert!(!slab_hit(&ray(Vec3::ZERO, -Vec3::Y, f32::INFINITY), lo, hi));
        let d = Vec3::new(0.3, 1.0, -0.2).normalize();
        assert!(slab_hit(&ray(Vec3::ZERO, d, f32::INFINITY), lo, hi));
    }
}
