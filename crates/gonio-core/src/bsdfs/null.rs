//! `null`: a surface that does not interact with light; every ray passes straight through.
//!
//! ```text
//!     f(ωi, ωo) = δ(ωo + ωi) / |cos θo|,      null transmittance T = 1
//! ```
//!
//! The single lobe is a forward Dirac delta: `sample` returns ωo = −ωi with weight 1, pdf 1
//! (a discrete choice), η = 1 and flags `DELTA | TRANSMISSION | NULL`; `eval` and `pdf` are 0
//! (no smooth lobe). [`Bsdf::null_transmission`] is 1, so that shadow rays cross the surface
//! unattenuated, and an opacity `mask` is `blendbsdf`-like: (1 − α)·null + α·nested (Mitsuba 3
//! `src/bsdfs/mask.cpp`: eval α·f, pdf α·p, null transmittance 1 − α·(1 − T_nested)).
//! The same lobe bounds a participating medium in Mitsuba; here it is a shape that only emits,
//! or a shape made invisible.
//!
//! Mitsuba 3 plugin `null` (`src/bsdfs/null.cpp`): no parameters; two-sided.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// The pass-through BSDF: light continues along its direction, unchanged.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NullBsdf;

impl NullBsdf {
    /// The lobe flags: a delta transmission that changes nothing (`NULL`).
    pub const FLAGS: BsdfFlags = BsdfFlags(BsdfFlags::DELTA_TRANSMISSION.0 | BsdfFlags::NULL.0);
}

impl Bsdf for NullBsdf {
    fn flags(&self) -> BsdfFlags {
        Self::FLAGS
    }

    fn eval(&self, _ctx: &BsdfContext, _wi: Vec3, _wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::ZERO
    }

    fn pdf(&self, _ctx: &BsdfContext, _wi: Vec3, _wo: Vec3, _wl: &SampledWavelengths) -> f32 {
        0.0
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        _u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !ctx.is_enabled(BsdfFlags::DELTA_TRANSMISSION) || wi.z == 0.0 {
            return None;
        }
        Some(BsdfSample {
            wo: -wi,
            weight: SampledSpectrum::ONE,
            pdf: 1.0,
            flags: Self::FLAGS,
            eta: 1.0,
        })
    }

    fn null_transmission(&self, _wi: Vec3, _wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        Some(SampledSpectrum::ONE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::{BlendBsdf, Diffuse};
    use crate::spectra::Spectrum;

    fn wl() -> SampledWavelengths {
        SampledWavelengths::sample_visible(0.3)
    }

    #[test]
    fn passes_straight_through_from_both_sides() {
        let ctx = BsdfContext::radiance();
        for wi in [
            Vec3::new(0.3, -0.2, 0.9).normalize(),
            Vec3::new(-0.5, 0.1, -0.7).normalize(),
        ] {
            let s = NullBsdf
                .sample(&ctx, wi, 0.7, Vec2::new(0.2, 0.9), &mut wl())
                .unwrap();
            assert_eq!(s.wo, -wi);
            assert_eq!(s.weight, SampledSpectrum::ONE);
            assert_eq!((s.pdf, s.eta), (1.0, 1.0));
            assert!(s.flags.contains(BsdfFlags::NULL) && s.flags.is_delta());
            assert_eq!(NullBsdf.eval(&ctx, wi, -wi, &wl()), SampledSpectrum::ZERO);
            assert_eq!(NullBsdf.pdf(&ctx, wi, -wi, &wl()), 0.0);
            assert_eq!(NullBsdf.null_transmission(wi, &wl()), Some(SampledSpectrum::ONE));
        }
    }

    #[test]
    fn a_mask_is_a_blend_with_null_as_mitsuba_defines_it() {
        // mask(α) = (1 − α)·null + α·nested: eval α·f, pdf α·p, T = 1 − α.
        let alpha = 0.3;
        let d = Diffuse::new(Spectrum::Constant(0.5));
        let m = BlendBsdf::new(1.0 - alpha, &d, &NullBsdf);
        let (ctx, wl) = (BsdfContext::radiance(), wl());
        let (wi, wo) = (
            Vec3::new(0.1, 0.2, 0.97).normalize(),
            Vec3::new(-0.4, 0.1, 0.9).normalize(),
        );
        let f = m.eval(&ctx, wi, wo, &wl);
        let fd = d.eval(&ctx, wi, wo, &wl);
        assert!((f[0] - alpha * fd[0]).abs() < 1e-6);
        assert!((m.pdf(&ctx, wi, wo, &wl) - alpha * d.pdf(&ctx, wi, wo, &wl)).abs() < 1e-6);
        let t = m.null_transmission(wi, &wl).unwrap();
        assert!((t[0] - (1.0 - alpha)).abs() < 1e-6);
        // u1 below 1 − α: the pass-through, with probability 1 − α and weight 1.
        let s = m
            .sample(&ctx, wi, 0.5, Vec2::splat(0.5), &mut wl.clone())
            .unwrap();
        assert_eq!(s.wo, -wi);
        assert!((s.pdf - (1.0 - alpha)).abs() < 1e-6 && (s.weight[0] - 1.0).abs() < 1e-6);
        // Above: the diffuse lobe with its own weight (α·f·cos/(α·p) = ρ).
        let s = m
            .sample(&ctx, wi, 0.9, Vec2::new(0.3, 0.6), &mut wl.clone())
            .unwrap();
        assert!(s.wo.z > 0.0 && (s.weight[0] - 0.5).abs() < 1e-5);
    }
}
