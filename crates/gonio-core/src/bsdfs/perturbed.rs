//! A BSDF evaluated in a perturbed shading frame: the adapter behind `normalmap` and `bumpmap`
//! (Mitsuba 3.9.1 `src/bsdfs/normalmap.cpp`, `bumpmap.cpp`, the shared perturbation and
//! `eval_shadow_terminator`).
//!
//! A plugin gives, at each hit, the perturbed normal n (unnormalized) in the **local coordinates
//! of the unperturbed shading frame** (`normalmap`: n = 2·rgb − 1 of the map; `bumpmap`: the
//! normal of the displaced surface p + scale·h(u, v)·n). For an incident direction ωi the frame
//! F = (s', t', n') is, as in Mitsuba:
//!
//! ```text
//!     n  ← (−n_x, −n_y, n_z)  if flip_invalid_normals and cos θi·(ωi·n) ≤ 0
//!     n' = normalize(n)                    (z when n is 0 or not finite)
//!     s' = normalize(x − n'·n'_x),  t' = n' × s'    (x the unperturbed tangent; y if degenerate)
//! ```
//!
//! The flip (Schüssler et al. 2017) keeps the mapped normal on the side of the viewer, so that
//! a tilted normal does not turn the surface black where the viewer sees it at a grazing angle.
//! With θo measured from the unperturbed normal and θ'o from n':
//!
//! ```text
//!     f(ωi, ωo)·|cos θo| = f'(F⁻¹ωi, F⁻¹ωo)·|cos θ'o| · G(n', ωo)   if cos θo · cos θ'o > 0, else 0
//!     pdf(ωi, ωo)        = pdf'(F⁻¹ωi, F⁻¹ωo)                       (same condition)
//!     sample:  ω'o ~ f'(F⁻¹ωi, ·),  ωo = F ω'o,  rejected unless cos θ'o · cos θo > 0,
//!              weight = the nested sample's (f'·|cos θ'o|/pdf') · G(n', ωo)
//!     G(n', ωo) = 2/(1 + √(1 + α² tan²θo)),  α² = min(tan²θ(n')/8, 1)    (use_shadowing_function)
//! ```
//!
//! G is the microfacet-based shadowing of Conty Estevez et al. 2019 ("A Microfacet-Based
//! Shadowing Function to Solve the Bump Terminator Problem"): a perturbed normal tilted by θ(n')
//! shadows grazing ωo as a GGX surface of roughness α would, which softens the terminator.
//! Mitsuba's BSDFs return f·cos θo with the cosine taken in their own (here the perturbed) frame;
//! gonio's integrators multiply [`Bsdf::eval`] by the unperturbed |cos θo|, so the adapter
//! returns the value above divided by it: next-event estimation and BSDF sampling then
//! estimate the same integrand, Mitsuba's. Only ωo is tested against both normals: a direction
//! that the mapped normal sees above its surface but the shading normal sees below (or the
//! reverse) gets no light (Mitsuba's black fringes).
//!
//! **Importance** (paths from the lights: `ptracer`, the caustic light subpaths). The value
//! above is not reciprocal (the flip depends on ωi, the cosine ratio and G on ωo), so the adjoint
//! is not the radiance value: f*(ωi, ωo) = f(ωo, ωi), evaluated as the nested model's importance
//! value in the frame of ωo with the factor of ωi,
//!
//! ```text
//!     f*(ωi, ωo) = f'_imp(F_o⁻¹ωi, F_o⁻¹ωo) · (cos θ'i / cos θi) · G(n'_o, ωi),   F_o the frame for ωo
//! ```
//!
//! and sampling keeps the radiance frame F (that of ωi, the only one known before ωo), weighting
//! the sample by f*·|cos θo|/pdf. Mitsuba passes the mode through unchanged, so its `ptracer`
//! and its path tracer disagree on normal maps; here both estimate the same image.
//!
//! **Polarization** (Mitsuba 3's polarized variants do the same through `to_world_mueller`): the
//! nested BSDF's Mueller matrix answers between the implicit Stokes bases of the directions in
//! the perturbed frame; its bases are carried by F (a rotation) into the unperturbed local frame
//! and re-expressed in the implicit bases there, `M = R_out · M'(F⁻¹ωi, F⁻¹ωo) · R_inᵀ`
//! ([`Weight::local_to_world`] with F), so a polarizing nested model stays polarizing.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, TransportMode};
use crate::frame::Frame;
use crate::mueller::Mueller;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::weight::Weight;
use glam::{Vec2, Vec3};

/// A perturbed normal and how the adapter treats it (see the module docs): a small `Copy`
/// value a material makes at each hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perturbation {
    /// The perturbed normal, unnormalized, in the local coordinates of the shading frame.
    pub n: Vec3,
    /// Mitsuba's `flip_invalid_normals` (default true): mirror the normal's tangential part
    /// where the viewer would see the surface from behind it.
    pub flip_invalid_normals: bool,
    /// Mitsuba's `use_shadowing_function` (default true): the terminator's shadowing G.
    pub use_shadowing_function: bool,
}

impl Perturbation {
    /// The normal `n` with Mitsuba's defaults (flip and shadowing on).
    pub fn new(n: Vec3) -> Self {
        Self {
            n,
            flip_invalid_normals: true,
            use_shadowing_function: true,
        }
    }

    /// Whether the normal leans away from the shading normal: a normal along +z (or one the
    /// frame replaces by +z: zero or not finite) leaves the frame, and the value, unchanged.
    pub fn is_tilted(&self) -> bool {
        unit(self.n).is_some_and(|n| n.x != 0.0 || n.y != 0.0)
    }

    /// The perturbed frame F for incident direction `wi` (local): n' flipped towards the viewer
    /// where asked, s' the unperturbed tangent x made orthogonal to n'.
    #[inline]
    pub fn frame(&self, wi: Vec3) -> Frame {
        let mut n = self.n;
        if self.flip_invalid_normals && wi.z * wi.dot(n) <= 0.0 {
            n = Vec3::new(-n.x, -n.y, n.z);
        }
        let n = unit(n).unwrap_or(Vec3::Z);
        let s = Vec3::X - n * n.x;
        let s_len2 = s.length_squared();
        let s = if s_len2 > 0.0 && s_len2.is_finite() {
            s / s_len2.sqrt()
        } else {
            Vec3::Y
        };
        Frame { s, t: n.cross(s), n }
    }
}

/// `n` normalized; `None` when |n|² is 0 or not finite (the frame then keeps the shading normal).
#[inline]
fn unit(n: Vec3) -> Option<Vec3> {
    let len2 = n.length_squared();
    (len2 > 0.0 && len2.is_finite()).then(|| n / len2.sqrt())
}

/// Conty Estevez et al.'s shadowing of a perturbed normal `n` (unit, local) for direction `wo`
/// (local to the unperturbed frame): 2/(1 + √(1 + α² tan²θo)), α² = min(tan²θn/8, 1); 0 at
/// grazing `wo`.
#[inline]
pub fn shadow_terminator(n: Vec3, wo: Vec3) -> f32 {
    let tan2 = |v: Vec3| {
        let c2 = v.z * v.z;
        (1.0 - c2).max(0.0) / c2
    };
    let alpha2 = (0.125 * tan2(n)).min(1.0);
    let g = 2.0 / (1.0 + (1.0 + alpha2 * tan2(wo)).sqrt());
    if g.is_finite() { g } else { 0.0 }
}

/// `bsdf` seen through a perturbed normal. See the module docs.
#[derive(Clone, Copy)]
pub struct PerturbedFrame<'a> {
    /// The perturbed normal and its options.
    pub perturbation: Perturbation,
    /// The nested BSDF, evaluated in the perturbed frame.
    pub bsdf: &'a dyn Bsdf,
}

impl std::fmt::Debug for PerturbedFrame<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PerturbedFrame")
            .field("perturbation", &self.perturbation)
            .finish_non_exhaustive()
    }
}

impl<'a> PerturbedFrame<'a> {
    /// `bsdf` seen through `perturbation`.
    pub fn new(perturbation: Perturbation, bsdf: &'a dyn Bsdf) -> Self {
        Self { perturbation, bsdf }
    }

    /// The frame for `wi`, `wi` and `wo` in it, and the factor that turns the nested value
    /// into this adapter's, when `wo` lies on the same side of both normals.
    #[inline]
    fn local(&self, wi: Vec3, wo: Vec3) -> Option<(Frame, Vec3, Vec3, f32)> {
        let frame = self.perturbation.frame(wi);
        let p = frame.to_local(wo);
        let factor = self.factor(frame.n, wo, p);
        (wo.z * p.z > 0.0 && factor.is_finite()).then(|| (frame, frame.to_local(wi), p, factor))
    }

    /// For the adjoint (importance mode): [`Self::local`] with the roles of `wi` and `wo`
    /// exchanged (the frame for `wo`, the factor of `wi`), `wi` and `wo` in that frame.
    #[inline]
    fn local_adjoint(&self, wi: Vec3, wo: Vec3) -> Option<(Frame, Vec3, Vec3, f32)> {
        self.local(wo, wi)
            .map(|(frame, wo, wi, factor)| (frame, wi, wo, factor))
    }

    /// The factor (cos θ'/cos θ)·G(n', w) of direction `w`, `p` being `w` in the frame of `n`.
    #[inline]
    fn factor(&self, n: Vec3, w: Vec3, p: Vec3) -> f32 {
        p.z / w.z * self.shadowing(n, w)
    }

    /// The terminator's shadowing G(n, w), 1 when it is off.
    #[inline]
    fn shadowing(&self, n: Vec3, w: Vec3) -> f32 {
        if self.perturbation.use_shadowing_function {
            shadow_terminator(n, w)
        } else {
            1.0
        }
    }

    /// The sampled direction back in the unperturbed frame and its weight factor (the
    /// terminator's shadowing), unless it changed sides.
    #[inline]
    fn back(&self, frame: &Frame, wo_perturbed: Vec3) -> Option<(Vec3, f32)> {
        let wo = frame.to_world(wo_perturbed);
        (wo_perturbed.z * wo.z > 0.0).then(|| (wo, self.shadowing(frame.n, wo)))
    }
}

/// How a nested sample becomes the adjoint's (importance mode).
enum Adjoint {
    /// The nested weight times this factor.
    Scale(f32),
    /// The sample lies off the adjoint's support.
    Reject,
    /// Weigh it by the adjoint's value, f*·|cos θo|/pdf (ωo's frame differs from the sampling one).
    Evaluate,
}

impl PerturbedFrame<'_> {
    /// Importance mode: how the nested sample's weight (f'·|cos θ'o|/pdf' in the sampling frame
    /// of `wi`) becomes the adjoint's, f*·|cos θo|/pdf'. Where ωo's frame is the sampling frame
    /// (the flip agrees), f* is the nested importance value times the factor of ωi: the weight
    /// scales by (cos θ'i/cos θi)·G(n', ωi)·|cos θo/cos θ'o|. Otherwise a smooth sample is
    /// weighted by f* evaluated in ωo's frame, and a delta one lies off the adjoint's support.
    #[inline]
    fn adjoint(&self, frame: &Frame, wi: Vec3, p_i: Vec3, wo: Vec3, p_o: Vec3, delta: bool) -> Adjoint {
        if self.perturbation.frame(wo).n == frame.n {
            let ratio = self.factor(frame.n, wi, p_i) * (wo.z / p_o.z).abs();
            if wi.z * p_i.z > 0.0 && ratio.is_finite() {
                Adjoint::Scale(ratio)
            } else {
                Adjoint::Reject
            }
        } else if delta {
            Adjoint::Reject
        } else {
            Adjoint::Evaluate
        }
    }
}

impl Bsdf for PerturbedFrame<'_> {
    /// The nested model's lobes; where the normal is tilted, also [`BsdfFlags::NON_SYMMETRIC`]
    /// (the importance value is the adjoint, not the radiance value) and
    /// [`BsdfFlags::ANISOTROPIC`] (the tilt picks an azimuth), so that the checks hold the
    /// adapter to what it is.
    fn flags(&self) -> BsdfFlags {
        let flags = self.bsdf.flags();
        if self.perturbation.is_tilted() {
            flags | BsdfFlags::NON_SYMMETRIC | BsdfFlags::ANISOTROPIC
        } else {
            flags
        }
    }

    fn pdf_is_exact(&self) -> bool {
        self.bsdf.pdf_is_exact()
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let local = match ctx.mode {
            TransportMode::Radiance => self.local(wi, wo),
            TransportMode::Importance => self.local_adjoint(wi, wo),
        };
        match local {
            Some((_, wi, wo, factor)) => self.bsdf.eval(ctx, wi, wo, wl) * factor,
            None => SampledSpectrum::ZERO,
        }
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        match self.local(wi, wo) {
            Some((_, wi, p, _)) => self.bsdf.pdf(ctx, wi, p, wl),
            None => 0.0,
        }
    }

    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        if ctx.mode == TransportMode::Importance {
            // The value in the frame of wo, the density in the sampling frame of wi.
            return (self.eval(ctx, wi, wo, wl), self.pdf(ctx, wi, wo, wl));
        }
        match self.local(wi, wo) {
            Some((_, wi, p, factor)) => {
                let (f, pdf) = self.bsdf.eval_pdf(ctx, wi, p, wl);
                (f * factor, pdf)
            }
            None => (SampledSpectrum::ZERO, 0.0),
        }
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let frame = self.perturbation.frame(wi);
        let p_i = frame.to_local(wi);
        let mut s = self.bsdf.sample(ctx, p_i, u1, u2, wl)?;
        let p_o = s.wo;
        let (wo, g) = self.back(&frame, p_o)?;
        s.wo = wo;
        if ctx.mode == TransportMode::Radiance {
            s.weight *= g;
            return Some(s);
        }
        match self.adjoint(&frame, wi, p_i, wo, p_o, s.flags.is_delta()) {
            Adjoint::Scale(r) => s.weight *= r,
            Adjoint::Reject => return None,
            Adjoint::Evaluate => s.weight = self.eval(ctx, wi, wo, wl) * (wo.z.abs() / s.pdf),
        }
        Some(s)
    }

    fn null_transmission(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        self.bsdf
            .null_transmission(self.perturbation.frame(wi).to_local(wi), wl)
    }

    /// The nested matrix, its bases carried from the perturbed frame to the shading frame.
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        let local = match ctx.mode {
            TransportMode::Radiance => self.local(wi, wo),
            TransportMode::Importance => self.local_adjoint(wi, wo),
        };
        match local {
            Some((frame, wi, p, factor)) => {
                self.bsdf.eval_mueller(ctx, wi, p, wl).local_to_world(&frame) * factor
            }
            None => Mueller::ZERO,
        }
    }

    /// [`Bsdf::sample`] with the nested Mueller weight, bases carried as in `eval_mueller`.
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        let frame = self.perturbation.frame(wi);
        let p_i = frame.to_local(wi);
        let mut s = self.bsdf.sample_mueller(ctx, p_i, u1, u2, wl)?;
        let p_o = s.wo;
        let (wo, g) = self.back(&frame, p_o)?;
        s.wo = wo;
        if ctx.mode == TransportMode::Radiance {
            s.weight = s.weight.local_to_world(&frame) * g;
            return Some(s);
        }
        match self.adjoint(&frame, wi, p_i, wo, p_o, s.flags.is_delta()) {
            Adjoint::Scale(r) => s.weight = s.weight.local_to_world(&frame) * r,
            Adjoint::Reject => return None,
            Adjoint::Evaluate => s.weight = self.eval_mueller(ctx, wi, wo, wl) * (wo.z.abs() / s.pdf),
        }
        Some(s)
    }

    fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        let frame = self.perturbation.frame(wi);
        self.bsdf
            .null_transmission_mueller(frame.to_local(wi), wl)
            .map(|m| m.local_to_world(&frame))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::{Conductor, Diffuse};
    use crate::spectra::Spectrum;
    use std::f32::consts::PI;

    fn tilted(degrees: f32) -> Vec3 {
        let a = degrees.to_radians();
        Vec3::new(a.sin(), 0.0, a.cos())
    }

    fn plain(n: Vec3) -> Perturbation {
        Perturbation {
            n,
            flip_invalid_normals: false,
            use_shadowing_function: false,
        }
    }

    #[test]
    fn the_identity_perturbation_changes_nothing() {
        let d = Diffuse::new(Spectrum::Constant(0.7));
        let p = PerturbedFrame::new(Perturbation::new(Vec3::Z), &d);
        let (ctx, wl) = (BsdfContext::radiance(), SampledWavelengths::fixed(550.0));
        let (wi, wo) = (
            Vec3::new(0.3, 0.1, 0.9).normalize(),
            Vec3::new(-0.2, 0.5, 0.8).normalize(),
        );
        assert_eq!(p.eval(&ctx, wi, wo, &wl), d.eval(&ctx, wi, wo, &wl));
        assert_eq!(p.pdf(&ctx, wi, wo, &wl), d.pdf(&ctx, wi, wo, &wl));
    }

    #[test]
    fn a_tilted_mirror_reflects_about_the_mapped_normal() {
        // Normal tilted by 20° about y: a mirror reflects wi about it, its weight the shadowing.
        let n = tilted(20.0);
        let m = Conductor::mirror();
        let p = PerturbedFrame::new(Perturbation::new(n), &m);
        let wi = Vec3::new(-0.2, 0.1, 0.97).normalize();
        let mut wl = SampledWavelengths::fixed(550.0);
        let s = p
            .sample(&BsdfContext::radiance(), wi, 0.5, Vec2::splat(0.5), &mut wl)
            .unwrap();
        let expected = 2.0 * wi.dot(n) * n - wi;
        assert!((s.wo - expected).length() < 1e-5, "{:?} vs {expected:?}", s.wo);
        let g = shadow_terminator(n, s.wo);
        assert!(g < 1.0 && (s.weight[0] - g).abs() < 1e-5, "{:?} vs {g}", s.weight);
    }

    #[test]
    fn eval_carries_the_cosine_of_the_perturbed_frame() {
        // Mitsuba's value f'·|cos θ'o| divided by the |cos θo| the integrators multiply by.
        let n = tilted(30.0);
        let d = Diffuse::new(Spectrum::Constant(0.7));
        let p = PerturbedFrame::new(plain(n), &d);
        let (ctx, wl) = (BsdfContext::radiance(), SampledWavelengths::fixed(550.0));
        let wi = Vec3::new(0.1, 0.2, 0.9).normalize();
        let wo = Vec3::new(0.6, -0.1, 0.5).normalize();
        let expected = 0.7 / PI * wo.dot(n) / wo.z;
        assert!((p.eval(&ctx, wi, wo, &wl)[0] - expected).abs() < 1e-6);
        // The pdf is the nested one, in the nested frame.
        assert!((p.pdf(&ctx, wi, wo, &wl) - wo.dot(n) / PI).abs() < 1e-6);
    }

    #[test]
    fn directions_on_opposite_sides_of_the_two_normals_get_nothing() {
        // Normal tilted by 60° about y: wo just above the surface on the far side lies below
        // the mapped normal's horizon (Mitsuba's black fringe).
        let n = tilted(60.0);
        let d = Diffuse::new(Spectrum::Constant(0.7));
        let p = PerturbedFrame::new(plain(n), &d);
        let (ctx, wl) = (BsdfContext::radiance(), SampledWavelengths::fixed(550.0));
        let wi = Vec3::new(0.5, 0.0, 0.8).normalize();
        let wo = Vec3::new(-0.95, 0.0, 0.1).normalize();
        assert!(wo.dot(n) < 0.0);
        assert_eq!(p.eval(&ctx, wi, wo, &wl), SampledSpectrum::ZERO);
        assert_eq!(p.pdf(&ctx, wi, wo, &wl), 0.0);
        // On the near side: the diffuse value.
        let wo = Vec3::new(0.6, 0.0, 0.8).normalize();
        let expected = 0.7 / PI * wo.dot(n) / wo.z;
        assert!((p.eval(&ctx, wi, wo, &wl)[0] - expected).abs() < 1e-6);
    }

    #[test]
    fn an_invalid_normal_is_flipped_towards_the_viewer() {
        // Tilted by 60° towards +x, seen at a grazing angle from −x: the viewer is behind the
        // mapped normal's surface, so its tangential part is mirrored.
        let n = tilted(60.0);
        let wi = Vec3::new(-0.95, 0.0, 0.1).normalize();
        assert!(wi.dot(n) < 0.0);
        let flipped = Perturbation::new(n).frame(wi);
        assert!(
            (flipped.n - Vec3::new(-n.x, 0.0, n.z)).length() < 1e-6,
            "{flipped:?}"
        );
        assert!(flipped.s.dot(flipped.n).abs() < 1e-6 && flipped.s.x > 0.0);
        // Without the flip, and for a viewer in front of it, it stays.
        assert!((plain(n).frame(wi).n - n).length() < 1e-6);
        assert!((Perturbation::new(n).frame(Vec3::Z).n - n).length() < 1e-6);
        // The flip is what lights that view: without it the nested diffuse sees wi from behind.
        let d = Diffuse::new(Spectrum::Constant(0.7));
        let (ctx, wl) = (BsdfContext::radiance(), SampledWavelengths::fixed(550.0));
        let wo = Vec3::new(-0.3, 0.2, 0.9).normalize();
        let with = PerturbedFrame::new(Perturbation::new(n), &d).eval(&ctx, wi, wo, &wl)[0];
        let without = PerturbedFrame::new(plain(n), &d).eval(&ctx, wi, wo, &wl)[0];
        assert!(with > 0.1 && without == 0.0, "{with} {without}");
    }

    #[test]
    fn the_terminator_shadowing_has_its_closed_form() {
        // No tilt, no shadowing; α² = min(tan²θn/8, 1) and G = 2/(1 + √(1 + α² tan²θo)).
        assert_eq!(shadow_terminator(Vec3::Z, tilted(80.0)), 1.0);
        let n = tilted(30.0);
        let wo = tilted(-45.0);
        let alpha2 = (30f32.to_radians().tan().powi(2) / 8.0) as f64;
        let expected = 2.0 / (1.0 + (1.0 + alpha2).sqrt());
        assert!((shadow_terminator(n, wo) as f64 - expected).abs() < 1e-6);
        // α² saturates at 1 for tilts beyond atan √8 ≈ 70.5°.
        let expected = 2.0 / (1.0 + 2f64.sqrt());
        assert!((shadow_terminator(tilted(80.0), wo) as f64 - expected).abs() < 1e-6);
        // Grazing directions are fully shadowed, never NaN.
        assert_eq!(shadow_terminator(n, Vec3::X), 0.0);
    }

    /// Random unit directions, a quarter of them grazing, on both sides.
    fn directions(n: usize) -> Vec<Vec3> {
        let mut rng = crate::rng::Pcg32::new(7, 3);
        (0..n)
            .map(|k| {
                let z = if k % 4 == 0 {
                    0.02 + 0.1 * rng.next_f32()
                } else {
                    rng.next_f32()
                };
                let phi = std::f32::consts::TAU * rng.next_f32();
                let r = (1.0 - z * z).sqrt();
                let sign = if k % 7 == 3 { -1.0 } else { 1.0 };
                Vec3::new(r * phi.cos(), r * phi.sin(), sign * z)
            })
            .collect()
    }

    /// The nested models of the adjoint tests: diffuse, anisotropic GGX metal, rough glass.
    fn nested_models() -> Vec<Box<dyn Bsdf>> {
        use crate::bsdfs::{RoughConductor, RoughDielectric};
        use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
        let ggx = MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.25, 0.05, true);
        let beckmann = MicrofacetDistribution::new(MicrofacetKind::Beckmann, 0.3, 0.3, true);
        vec![
            Box::new(Diffuse::new(Spectrum::Constant(0.7))),
            Box::new(RoughConductor::mirror(ggx)),
            Box::new(RoughDielectric::new(
                crate::Ior::Constant(1.5),
                crate::Ior::Constant(1.0),
                beckmann,
            )),
        ]
    }

    #[test]
    fn importance_mode_is_the_adjoint() {
        // f*(a, b) = f(b, a): Mitsuba's flip and shadowing make f non-reciprocal, and paths from
        // the lights must see its transpose.
        let dirs = directions(64);
        let wl = SampledWavelengths::fixed(550.0);
        let (rad, imp) = (BsdfContext::radiance(), BsdfContext::importance());
        let mut lit = 0;
        for nested in nested_models() {
            for n in [tilted(35.0), Vec3::new(-0.3, 0.5, 0.7), tilted(75.0)] {
                let p = PerturbedFrame::new(Perturbation::new(n), nested.as_ref());
                for (k, &a) in dirs.iter().enumerate() {
                    for &b in &dirs[k + 1..] {
                        let (f_ab, f_ba) = (p.eval(&imp, a, b, &wl)[0], p.eval(&rad, b, a, &wl)[0]);
                        assert!(
                            (f_ab - f_ba).abs() <= 1e-4 * f_ab.abs().max(f_ba.abs()).max(1e-6),
                            "n {n} a {a} b {b}: importance {f_ab} vs radiance transposed {f_ba}"
                        );
                        lit += usize::from(f_ab > 1e-3);
                    }
                }
            }
        }
        assert!(lit > 2000, "{lit} lit pairs");
        // And the radiance value itself is not reciprocal (else this test would prove nothing).
        let d = Diffuse::new(Spectrum::Constant(0.7));
        let p = PerturbedFrame::new(Perturbation::new(tilted(35.0)), &d);
        let (a, b) = (
            Vec3::new(0.1, 0.2, 0.97).normalize(),
            Vec3::new(0.8, 0.0, 0.3).normalize(),
        );
        assert!((p.eval(&rad, a, b, &wl)[0] / p.eval(&rad, b, a, &wl)[0] - 1.0).abs() > 0.1);
    }

    #[test]
    fn importance_samples_are_weighted_by_the_adjoint() {
        let dirs = directions(24);
        let wl0 = SampledWavelengths::fixed(550.0);
        let imp = BsdfContext::importance();
        let mut taken = 0;
        for nested in nested_models() {
            for n in [tilted(35.0), Vec3::new(-0.3, 0.5, 0.7), tilted(75.0)] {
                let p = PerturbedFrame::new(Perturbation::new(n), nested.as_ref());
                for &wi in &dirs {
                    for k in 0..16 {
                        let u = Vec2::new((k % 4) as f32 / 4.0 + 0.1, (k / 4) as f32 / 4.0 + 0.05);
                        let mut wl = wl0;
                        let Some(s) = p.sample(&imp, wi, (k as f32 + 0.5) / 16.0, u, &mut wl) else {
                            continue;
                        };
                        let (f, pdf) = p.eval_pdf(&imp, wi, s.wo, &wl0);
                        assert!((pdf - s.pdf).abs() <= 1e-4 * pdf, "{pdf} vs {}", s.pdf);
                        let w = f[0] * s.wo.z.abs() / pdf;
                        assert!(
                            (w - s.weight[0]).abs() <= 1e-4 * w.max(1e-3),
                            "n {n} wi {wi} wo {}: adjoint weight {w} vs sampled {}",
                            s.wo,
                            s.weight[0]
                        );
                        taken += 1;
                    }
                }
            }
        }
        assert!(taken > 1500, "{taken} samples");
    }

    #[test]
    fn sample_weights_agree_with_eval_over_pdf() {
        let d = Diffuse::new(Spectrum::Constant(0.7));
        let ctx = BsdfContext::radiance();
        let wl0 = SampledWavelengths::fixed(550.0);
        for (n, wi) in [
            (tilted(25.0), Vec3::new(0.2, -0.3, 0.9).normalize()),
            (tilted(60.0), Vec3::new(-0.95, 0.0, 0.1).normalize()),
            (Vec3::new(0.3, -0.4, 0.8), Vec3::new(0.5, 0.5, 0.3).normalize()),
        ] {
            let p = PerturbedFrame::new(Perturbation::new(n), &d);
            let mut taken = 0;
            for k in 0..64 {
                let u = Vec2::new((k % 8) as f32 / 8.0 + 0.06, (k / 8) as f32 / 8.0 + 0.03);
                let mut wl = wl0;
                let Some(s) = p.sample(&ctx, wi, 0.5, u, &mut wl) else {
                    continue;
                };
                let (f, pdf) = p.eval_pdf(&ctx, wi, s.wo, &wl0);
                assert!((pdf - s.pdf).abs() <= 1e-5 * pdf, "{pdf} vs {}", s.pdf);
                let w = f[0] * s.wo.z.abs() / pdf;
                assert!(
                    (w - s.weight[0]).abs() < 1e-5,
                    "n {n} wi {wi}: {w} vs {:?}",
                    s.weight
                );
                taken += 1;
            }
            assert!(taken > 32, "{taken} samples kept of 64");
        }
    }

    #[test]
    fn the_checks_see_a_tilted_normal_as_anisotropic_and_not_reciprocal() {
        // `gonio check` on a normal map: the flags say what the adapter is, so the isotropy row
        // holds it to being anisotropic and the adjoint row to its transposed value, while the
        // reciprocity row reports the asymmetry of Mitsuba's frame (the flip and G).
        use crate::bsdfs::RoughConductor;
        use crate::check::{CheckConfig, isotropy::isotropy, reciprocity::reciprocity};
        let m = RoughConductor::default();
        let config = CheckConfig::quick();
        let flat = PerturbedFrame::new(Perturbation::new(Vec3::Z), &m);
        assert_eq!(flat.flags(), m.flags());
        assert!(isotropy(&flat, &config).passed);
        let p = PerturbedFrame::new(Perturbation::new(tilted(25.0)), &m);
        assert!(
            p.flags()
                .contains(BsdfFlags::ANISOTROPIC | BsdfFlags::NON_SYMMETRIC)
        );
        let iso = isotropy(&p, &config);
        assert!(iso.passed && iso.figure > 0.1, "{iso:?}");
        let rows = reciprocity(&p, &config);
        let row = |name: &str| rows.iter().find(|r| r.name == name).unwrap();
        assert!(row("adjoint").passed, "{:?}", row("adjoint"));
        assert!(!row("reciprocity").passed, "{:?}", row("reciprocity"));
    }
}
