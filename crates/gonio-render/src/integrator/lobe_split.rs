//! Lobe splitting at rough glass (beyond Mitsuba): where the reflection or the refraction of a
//! `roughdielectric` vertex leaves the scene, it is added whole, and the path follows the other.
//!
//! # Why
//!
//! At a rough dielectric vertex the path tracer draws a facet normal `m` and then one lobe,
//! reflection with probability F(m), refraction with 1 − F(m). The lobe not taken is left to the
//! paths that take it. Two kinds of light pay for that coin: the environment reflected by the
//! glass the camera sees (taken with F ≈ 0.04–0.1, so each find is 10–25× too bright), and light
//! bouncing inside a glass object, which leaves at whichever bounce the coin first says
//! "refract": where it leaves, and so which part of the environment it brings back, is decided
//! by a run of coin flips (Mitsuba's `bsdf_roughdielectric_glass` preview: 30 % of its error).
//!
//! # The estimator
//!
//! The facet `m` is the path tracer's (`u_dir`), and both directions about it are made
//! ([`RoughDielectric::sample_split`](gonio_core::bsdfs::roughdielectric::RoughDielectric::sample_split)),
//! each weighted as its lobe sampled alone, `w = f·|cos θo|/p_lobe`. The lobe that points to the
//! *outside* of the surface (ωo·n > 0: the reflection on the outside, the refraction from
//! inside; only there can light leave a closed object) is traced first.
//!
//! * If its ray leaves the scene, it adds `β·w·L_∞(ω)` whole (weighted against next-event
//!   estimation as a BSDF sample that escapes) and the path follows the inward lobe with its
//!   whole weight `w`: no coin.
//! * Otherwise the step is the path tracer's own: the lobe `u_lobe` takes (probability c = F or
//!   1 − F) is followed with `w/c`, reusing the outward ray's hit when it is that one.
//!
//! Given the facet, which case applies is fixed (the outward ray either leaves or does not), and
//! in each case every lobe's integral is estimated without bias: whole, or followed with a
//! probability its weight divides out. The cost is the outward ray where the path goes on
//! inwards, and the inward paths that go on where the path tracer's would have left; the gain
//! is that light leaving the glass no longer waits for the coin (relMSE −29 % at +11 % CPU time
//! on the preview, `bench/RESULTS.md`; following the inward lobe there with the coin's
//! probability instead gave −27 % at +13 %, and under a uniform sky 0.96× the pixel variance
//! against 0.85×).
//!
//! # MIS
//!
//! The weights stay the path tracer's functions of the path: a branch's direction carries the
//! full BSDF's density (F·p_r or (1 − F)·p_t) as its `pdf`, for the power heuristic against
//! next-event estimation and for the ratios of the other strategies, which see the same density
//! whichever way the direction was reached. Weights that sum to one over the strategies for every
//! path need the same function on every side, not the density a sample was actually drawn with.
//!
//! Not split: scenes without a light at infinity (an escape there carries nothing), delta
//! interfaces (measured with this rule and not kept: smooth glass gained 4–9 % in error for
//! 10 % more time, `bench/RESULTS.md`), trees of several BSDFs, multiple-scattering or
//! dispersive glass, and polarized renders.

use super::{PathState, PathTracer, PrevVertex, Vertex};
use crate::accel::Intersect;
use crate::emitter::LightRef;
use crate::geometry::SurfaceInteraction;
use glam::Vec2;
use gonio_core::weight::Weight;
use gonio_core::{Bsdf, BsdfContext, BsdfSample, SampledWavelengths};

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
}

/// The lobe a split vertex's path follows: its sample (weight divided by the probability of
/// following it), the surface its ray hits, and its reverse density.
pub(super) struct Followed<W> {
    pub sample: BsdfSample<W>,
    pub hit: SurfaceInteraction,
    pub reverse_pdf: f32,
}

impl PathTracer<'_> {
    /// Both lobes of `v` when it splits them (`split_escapes`, spectral renders, a
    /// single-scattering, non-dispersive `roughdielectric`); `None` to sample `v` as usual.
    pub(super) fn lobe_pair<W: Weight>(
        &self,
        v: &Vertex,
        u_lobe: f32,
        u_dir: Vec2,
        wl: &mut SampledWavelengths,
        want_reverse: bool,
    ) -> Option<LobePair<W>> {
        // Escapes carry light only where a light at infinity exists; elsewhere the outward
        // ray would be traced for nothing.
        if !self.split_escapes || self.polarized || self.lights.infinite().is_empty() {
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
        })
    }

    /// Traces the lobes of `pair` from `v` as the module's rule says: adds what leaves the scene
    /// to `l` and returns the lobe the path follows (`None`: the path ends).
    pub(super) fn follow_pair<W: Weight>(
        &self,
        pair: LobePair<W>,
        v: &Vertex,
        state: &PathState<W>,
        light_ref: LightRef,
        l: &mut W,
        wl: &SampledWavelengths,
    ) -> Option<Followed<W>> {
        let si = v.si;
        // A lobe whose ray leaves the scene: the escape its next vertex would have added.
        let escape = |l: &mut W, bs: &BsdfSample<W>, weight: W, dir| {
            let escaped = PathState {
                beta: state.beta * weight,
                prev: Some(PrevVertex {
                    light_ref,
                    bsdf_pdf: bs.pdf,
                    delta: false,
                }),
                ..*state
            };
            self.add_escaped(l, &escaped, dir, wl);
        };
        // Follows `lobe` with probability `q` (already decided), or adds its escape.
        let follow = |l: &mut W, lobe: Lobe<W>, hit: Option<SurfaceInteraction>, q: f32| {
            let dir = si.shading.to_world(lobe.sample.wo);
            let weight = lobe.sample.weight * (1.0 / q);
            let hit = match hit {
                Some(hit) => Some(hit),
                None => self.accel.intersect(&si.spawn_ray(dir)),
            };
            match hit {
                Some(hit) => Some(Followed {
                    sample: BsdfSample {
                        weight,
                        ..lobe.sample
                    },
                    hit,
                    reverse_pdf: if pair.want_reverse {
                        v.bsdf.pdf(&BsdfContext::importance(), lobe.sample.wo, v.wi, wl)
                    } else {
                        0.0
                    },
                }),
                None => {
                    escape(l, &lobe.sample, weight, dir);
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
            return follow(l, i, None, i.c);
        };
        let dir = si.shading.to_world(o.sample.wo);
        let ray = si.spawn_ray(dir);
        // The outward ray's hit is needed only where the path may follow it.
        let (leaves, out_hit) = if out_taken {
            let hit = self.accel.intersect(&ray);
            (hit.is_none(), hit)
        } else {
            (!self.accel.occluded(&ray), None)
        };
        if leaves {
            // Both whole.
            escape(l, &o.sample, o.sample.weight, dir);
            return follow(l, inn?, None, 1.0);
        }
        // The path tracer's step.
        if out_taken {
            follow(l, o, out_hit, o.c)
        } else {
            let i = inn?;
            follow(l, i, None, i.c)
        }
    }
}
