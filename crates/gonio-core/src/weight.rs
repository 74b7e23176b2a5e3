//! What a path carries and a BSDF multiplies it by: one type parameter, so that polarization can
//! replace the spectrum by a Mueller matrix (and the film's value by a Stokes vector) without
//! touching the estimators.
//!
//! Two [`Weight`]s exist: [`SampledSpectrum`] (four spectral values) and
//! [`crate::mueller::Mueller`] (a Mueller matrix per wavelength with its Stokes bases). A polarized renderer (Mitsuba 3's `*_polarized` variants; Wilkie & Weidlich 2012,
//! "Polarised light in computer graphics") carries 4×4 Mueller matrices per wavelength whose
//! products are taken in path order, and observes the Stokes vector's first component S0 where
//! an unpolarized renderer observes the spectrum: [`Weight::intensity`] is that observation,
//! [`Weight::from_spectrum`] the depolarizing embedding of a scalar weight (diag(f, 0, 0, 0) for
//! a Mueller matrix).
//!
//! BSDFs return their weights through [`BsdfWeight`]: every [`Bsdf`] does so for spectra; a
//! polarizing model adds its own implementation for Mueller matrices.

use crate::bsdf::{Bsdf, BsdfContext, BsdfSample};
use crate::frame::Frame;
use crate::mueller::Mueller;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};
use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign};

/// A path throughput or BSDF weight at the path's wavelengths.
pub trait Weight:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Mul<Output = Self>
    + MulAssign
    + Mul<f32, Output = Self>
    + MulAssign<f32>
    + Div<f32, Output = Self>
    + DivAssign<f32>
    + Add<Output = Self>
    + AddAssign
{
    /// Nothing passes.
    const ZERO: Self;
    /// Everything passes unchanged.
    const ONE: Self;
    /// The depolarizing weight of a spectral value.
    fn from_spectrum(s: SampledSpectrum) -> Self;
    /// What an intensity-only observer sees (the spectrum itself; S0 for polarized light).
    fn intensity(self) -> SampledSpectrum;
    /// True when nothing passes at any wavelength.
    fn is_black(self) -> bool {
        self.intensity().is_black()
    }
    /// A BSDF's weight, given in its local shading `frame` (normal = +z), as a renderer needs
    /// it in world space. A weight without reference frames is unchanged (the default); a
    /// Mueller matrix has its bases mapped to world and re-expressed in the implicit bases of
    /// its own directions, so that consecutive vertices of a path share their bases.
    #[inline]
    fn local_to_world(self, _frame: &Frame) -> Self {
        self
    }
    /// `self · t · Lₑ`: light of radiance `le` from an unpolarized source that crosses `t`
    /// first and then `self`, in that order (next-event estimation: β·f, then the sheets a
    /// shadow ray crossed, then the light). The default `self · Lₑ · t` is the same value for
    /// weights that commute (spectra), multiplied in the order the spectral renderer always has.
    #[inline]
    fn through_then_source(self, t: Self, le: SampledSpectrum) -> Self {
        self * Self::from_spectrum(le) * t
    }
}

impl Weight for SampledSpectrum {
    const ZERO: Self = SampledSpectrum::ZERO;
    const ONE: Self = SampledSpectrum::ONE;
    #[inline]
    fn from_spectrum(s: SampledSpectrum) -> Self {
        s
    }
    #[inline]
    fn intensity(self) -> SampledSpectrum {
        self
    }
    #[inline]
    fn is_black(self) -> bool {
        SampledSpectrum::is_black(self)
    }
}

/// A BSDF's values as weights of type `W` (see the module docs). Every [`Bsdf`] implements it
/// for [`SampledSpectrum`]; a renderer generic over `W` asks for `BsdfWeight<W>`.
pub trait BsdfWeight<W: Weight> {
    /// f(wi, wo) without the cosine, as a `W` ([`Bsdf::eval`]).
    fn eval_weight(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> W;
    /// [`Bsdf::sample`] with its weight as a `W`.
    fn sample_weight(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<W>>;
    /// [`Bsdf::null_transmission`] as a `W`.
    fn null_transmission_weight(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<W>;
    /// [`BsdfWeight::eval_weight`] and [`Bsdf::pdf`] together ([`Bsdf::eval_pdf`] for spectra,
    /// where models share work).
    #[inline]
    fn eval_pdf_weight(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> (W, f32)
    where
        Self: Sized + Bsdf,
    {
        (self.eval_weight(ctx, wi, wo, wl), self.pdf(ctx, wi, wo, wl))
    }
}

impl<B: Bsdf + ?Sized> BsdfWeight<SampledSpectrum> for B {
    #[inline]
    fn eval_weight(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.eval(ctx, wi, wo, wl)
    }
    #[inline]
    fn sample_weight(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        self.sample(ctx, wi, u1, u2, wl)
    }
    #[inline]
    fn null_transmission_weight(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        self.null_transmission(wi, wl)
    }
    #[inline]
    fn eval_pdf_weight(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32)
    where
        Self: Sized + Bsdf,
    {
        self.eval_pdf(ctx, wi, wo, wl)
    }
}

/// Every [`Bsdf`] gives Mueller matrices through its polarized methods ([`Bsdf::eval_mueller`],
/// [`Bsdf::sample_mueller`], [`Bsdf::null_transmission_mueller`]; depolarizing by default).
impl<B: Bsdf + ?Sized> BsdfWeight<Mueller> for B {
    #[inline]
    fn eval_weight(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        self.eval_mueller(ctx, wi, wo, wl)
    }
    #[inline]
    fn sample_weight(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        self.sample_mueller(ctx, wi, u1, u2, wl)
    }
    #[inline]
    fn null_transmission_weight(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        self.null_transmission_mueller(wi, wl)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::Diffuse;

    /// The spectral weight is the BSDF's own value, unchanged (an unpolarized caller sees exactly
    /// what it saw before the type parameter existed).
    #[test]
    fn spectral_weights_are_the_bsdf_values() {
        let d = Diffuse::default();
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(550.0);
        let (wi, wo) = (Vec3::Z, Vec3::new(0.6, 0.0, 0.8));
        let spectral: &dyn BsdfWeight<SampledSpectrum> = &d;
        assert_eq!(spectral.eval_weight(&ctx, wi, wo, &wl), d.eval(&ctx, wi, wo, &wl));
        let (mut a, mut b) = (wl, wl);
        let u2 = Vec2::new(0.3, 0.7);
        assert_eq!(
            spectral.sample_weight(&ctx, wi, 0.5, u2, &mut a),
            d.sample(&ctx, wi, 0.5, u2, &mut b)
        );
        assert_eq!(
            SampledSpectrum::from_spectrum(SampledSpectrum::ONE).intensity(),
            SampledSpectrum::ONE
        );
        assert!(<SampledSpectrum as Weight>::ZERO.is_black());
    }

    /// The Mueller weight of a depolarizing BSDF is diag(f, 0, 0, 0) with f the spectral value,
    /// frame-free; its intensity is M00, and ONE/ZERO behave as identity and nothing.
    #[test]
    fn mueller_weights_of_a_depolarizing_bsdf() {
        let d = Diffuse::default();
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(550.0);
        let (wi, wo) = (Vec3::Z, Vec3::new(0.6, 0.0, 0.8));
        let polarized: &dyn BsdfWeight<Mueller> = &d;
        let m = polarized.eval_weight(&ctx, wi, wo, &wl);
        assert_eq!(m, Mueller::depolarizer(d.eval(&ctx, wi, wo, &wl)));
        assert_eq!(m.intensity(), d.eval(&ctx, wi, wo, &wl));
        assert!(m.frames().is_none());
        assert_eq!(Mueller::ONE * m, m);
        assert!((Mueller::ZERO * m).is_black());
        assert_eq!(
            Mueller::from_spectrum(SampledSpectrum::splat(0.3)).intensity(),
            SampledSpectrum::splat(0.3)
        );
    }
}
