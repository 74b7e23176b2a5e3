//! `diffuse`: the ideal diffuse (Lambertian) reflector.
//!
//! Lecture, slide "Ideal Diffuse Reflection": light is equally likely to leave in any
//! direction, so f is a constant c, and the reflectance ρ_d = π c gives
//!
//! ```text
//!     f_r = ρ / π
//! ```
//!
//! Sampling: cosine-weighted hemisphere, pdf = cos θo/π, so the weight is ρ exactly.
//!
//! Mitsuba 3 plugin `diffuse` (`src/bsdfs/diffuse.cpp`), one-sided (zero unless both directions
//! are above the surface; wrap it in `twosided` for back faces).
//!
//! | parameter     | type     | default |
//! |---------------|----------|---------|
//! | `reflectance` | spectrum | 0.5     |

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// The Lambertian BRDF f = ρ/π.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse<S = Spectrum> {
    /// ρ, the directional (and hemispherical) reflectance.
    pub reflectance: S,
}

impl Default for Diffuse {
    /// Mitsuba's default, ρ = 0.5.
    fn default() -> Self {
        Self {
            reflectance: Spectrum::Constant(0.5),
        }
    }
}

impl Diffuse {
    /// A Lambertian reflector of reflectance ρ.
    pub fn new(reflectance: Spectrum) -> Self {
        Self { reflectance }
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> Diffuse<SampledSpectrum> {
        Diffuse {
            reflectance: self.reflectance.sample(wl),
        }
    }
}

impl<S: SpectralValue> Bsdf for Diffuse<S> {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.reflectance.sample(wl) * FRAC_1_PI
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> f32 {
        if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 {
            return 0.0;
        }
        square_to_cosine_hemisphere_pdf(wo)
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 {
            return None;
        }
        let wo = square_to_cosine_hemisphere(u2);
        let pdf = square_to_cosine_hemisphere_pdf(wo);
        let weight = self.reflectance.sample(wl);
        (pdf > 0.0).then_some(BsdfSample {
            wo,
            weight,
            pdf,
            flags: BsdfFlags::DIFFUSE_REFLECTION,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_values_match_mitsuba() {
        // Mitsuba 3 src/bsdfs/diffuse.cpp: eval = ρ cos θo/π (its convention), i.e. f = ρ/π here.
        let d = Diffuse::default();
        let wl = SampledWavelengths::fixed(550.0);
        let ctx = BsdfContext::radiance();
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let f = d.eval(&ctx, Vec3::Z, wo, &wl);
        assert!((f[0] - 0.5 * FRAC_1_PI).abs() < 1e-7);
        assert!((d.pdf(&ctx, Vec3::Z, wo, &wl) - 0.8 * FRAC_1_PI).abs() < 1e-7);
        let mut wl2 = wl;
        let s = d
            .sample(&ctx, Vec3::Z, 0.5, Vec2::new(0.3, 0.7), &mut wl2)
            .unwrap();
        assert!((s.wo - Vec3::new(-0.282843, 0.282843, 0.916515)).length() < 1e-5);
        assert!((s.weight[0] - 0.5).abs() < 1e-7);
        assert_eq!(
            d.eval(&ctx, -Vec3::Z, wo, &wl),
            SampledSpectrum::ZERO,
            "one-sided"
        );
    }
}
