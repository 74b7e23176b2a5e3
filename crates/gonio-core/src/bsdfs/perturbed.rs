//! A BSDF evaluated in a perturbed shading frame: the adapter behind `normalmap` and `bumpmap`.
//!
//! Given a nested BSDF f' and an orthonormal frame F = (s, t, n) expressed in the **local
//! coordinates of the unperturbed shading frame** (n is the mapped normal), Mitsuba 3
//! (`src/bsdfs/normalmap.cpp`, `src/bsdfs/bumpmap.cpp`) defines
//!
//! ```text
//!     f(ωi, ωo)   = f'(F⁻¹ωi, F⁻¹ωo)         if cos θo · cos θ'o > 0, else 0
//!     pdf(ωi, ωo) = pdf'(F⁻¹ωi, F⁻¹ωo)       (same condition)
//!     sample:  ω'o ~ f'(F⁻¹ωi, ·),  ωo = F ω'o,  rejected unless cos θ'o · cos θo > 0
//! ```
//!
//! where θo is measured from the unperturbed normal and θ'o from the perturbed one. Only ωo is
//! tested: a direction that the mapped normal sees above its surface but the shading normal sees
//! below (or the reverse) gets no light, which darkens grazing views of strongly tilted normals
//! (Mitsuba's black fringes); ωi is not tested, so light may leak where the mapped normal tilts
//! past the viewer. The cosine the integrator multiplies by is the unperturbed |cos θo|, as in
//! Mitsuba (the adapter does not correct it).
//!
//! The frame comes from the plugin at each hit (`normalmap`: n = 2·rgb − 1 of the map;
//! `bumpmap`: the normal of the displaced surface p + scale·h(u, v)·n).
//!
//! **Polarization** (Mitsuba 3's polarized variants do the same through `to_world_mueller`): the
//! nested BSDF's Mueller matrix answers between the implicit Stokes bases of the directions in
//! the perturbed frame; its bases are carried by F (a rotation) into the unperturbed local frame
//! and re-expressed in the implicit bases there, `M = R_out · M'(F⁻¹ωi, F⁻¹ωo) · R_inᵀ`
//! ([`Weight::local_to_world`] with F), so a polarizing nested model stays polarizing.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::frame::Frame;
use crate::mueller::Mueller;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::weight::Weight;
use glam::{Vec2, Vec3};

/// `bsdf` seen through the perturbed shading frame `frame` (local coordinates of the shading
/// frame). See the module docs.
#[derive(Clone, Copy)]
pub struct PerturbedFrame<'a> {
    /// The perturbed frame, its vectors in the unperturbed local frame.
    pub frame: Frame,
    /// The nested BSDF, evaluated in `frame`.
    pub bsdf: &'a dyn Bsdf,
}

impl std::fmt::Debug for PerturbedFrame<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PerturbedFrame")
            .field("frame", &self.frame)
            .finish_non_exhaustive()
    }
}

impl<'a> PerturbedFrame<'a> {
    /// `bsdf` in the frame `frame`.
    pub fn new(frame: Frame, bsdf: &'a dyn Bsdf) -> Self {
        Self { frame, bsdf }
    }

    /// `wo` in the perturbed frame, when it lies on the same side of both normals.
    #[inline]
    fn wo_local(&self, wo: Vec3) -> Option<Vec3> {
        let p = self.frame.to_local(wo);
        (wo.z * p.z > 0.0).then_some(p)
    }
}

impl Bsdf for PerturbedFrame<'_> {
    fn flags(&self) -> BsdfFlags {
        self.bsdf.flags()
    }

    fn pdf_is_exact(&self) -> bool {
        self.bsdf.pdf_is_exact()
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        match self.wo_local(wo) {
            Some(p) => self.bsdf.eval(ctx, self.frame.to_local(wi), p, wl),
            None => SampledSpectrum::ZERO,
        }
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        match self.wo_local(wo) {
            Some(p) => self.bsdf.pdf(ctx, self.frame.to_local(wi), p, wl),
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
        match self.wo_local(wo) {
            Some(p) => self.bsdf.eval_pdf(ctx, self.frame.to_local(wi), p, wl),
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
        let mut s = self.bsdf.sample(ctx, self.frame.to_local(wi), u1, u2, wl)?;
        let wo = self.frame.to_world(s.wo);
        if !(s.wo.z * wo.z > 0.0) {
            return None;
        }
        s.wo = wo;
        Some(s)
    }

    fn null_transmission(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        self.bsdf.null_transmission(self.frame.to_local(wi), wl)
    }

    /// The nested matrix, its bases carried from the perturbed frame to the shading frame.
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        match self.wo_local(wo) {
            Some(p) => self
                .bsdf
                .eval_mueller(ctx, self.frame.to_local(wi), p, wl)
                .local_to_world(&self.frame),
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
        let mut s = self
            .bsdf
            .sample_mueller(ctx, self.frame.to_local(wi), u1, u2, wl)?;
        let wo = self.frame.to_world(s.wo);
        if !(s.wo.z * wo.z > 0.0) {
            return None;
        }
        s.wo = wo;
        s.weight = s.weight.local_to_world(&self.frame);
        Some(s)
    }

    fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        self.bsdf
            .null_transmission_mueller(self.frame.to_local(wi), wl)
            .map(|m| m.local_to_world(&self.frame))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::{Conductor, Diffuse};
    use crate::spectra::Spectrum;

    #[test]
    fn the_identity_frame_changes_nothing() {
        let d = Diffuse::new(Spectrum::Constant(0.7));
        let p = PerturbedFrame::new(Frame::from_normal(Vec3::Z), &d);
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
        // Normal tilted by 20° about y: a mirror reflects wi about it.
        let a = 20f32.to_radians();
        let n = Vec3::new(a.sin(), 0.0, a.cos());
        let frame = Frame::from_normal_tangent(n, Vec3::X);
        let m = Conductor::mirror();
        let p = PerturbedFrame::new(frame, &m);
        let wi = Vec3::new(-0.2, 0.1, 0.97).normalize();
        let mut wl = SampledWavelengths::fixed(550.0);
        let s = p
            .sample(&BsdfContext::radiance(), wi, 0.5, Vec2::splat(0.5), &mut wl)
            .unwrap();
        let expected = 2.0 * wi.dot(n) * n - wi;
        assert!((s.wo - expected).length() < 1e-5, "{:?} vs {expected:?}", s.wo);
    }

    #[test]
    fn directions_on_opposite_sides_of_the_two_normals_get_nothing() {
        // Normal tilted by 60° about y: wo just above the surface on the far side lies below
        // the mapped normal's horizon (Mitsuba's black fringe).
        let a = 60f32.to_radians();
        let frame = Frame::from_normal_tangent(Vec3::new(a.sin(), 0.0, a.cos()), Vec3::X);
        let d = Diffuse::new(Spectrum::Constant(0.7));
        let p = PerturbedFrame::new(frame, &d);
        let (ctx, wl) = (BsdfContext::radiance(), SampledWavelengths::fixed(550.0));
        let wi = Vec3::new(0.5, 0.0, 0.8).normalize();
        let wo = Vec3::new(-0.95, 0.0, 0.1).normalize();
        assert!(frame.to_local(wo).z < 0.0);
        assert_eq!(p.eval(&ctx, wi, wo, &wl), SampledSpectrum::ZERO);
        assert_eq!(p.pdf(&ctx, wi, wo, &wl), 0.0);
        // On the near side: the diffuse value ρ/π.
        let wo = Vec3::new(0.6, 0.0, 0.8).normalize();
        assert!((p.eval(&ctx, wi, wo, &wl)[0] - 0.7 / std::f32::consts::PI).abs() < 1e-6);
    }
}
