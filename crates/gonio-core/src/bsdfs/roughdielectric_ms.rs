//! `roughdielectric` with `multiple_scattering`: Heitz et al. 2016's random walk across a rough
//! dielectric interface ([`crate::microsurface`]), wrapped in gonio's BSDF conventions.
//!
//! * **Sides.** The walk is run in the frame where ωi is above, with η = n(other side)/n(ωi's
//!   side); ωo on ωi's side is the reflection lobe (tinted by `specular_reflectance`), on the
//!   other side the transmission lobe (`specular_transmittance`), whatever path the walk took.
//! * **Transport.** The walk and its estimator are the importance-transport BSDF (a refraction
//!   keeps the flux); radiance transport multiplies the transmission by (η_ωi/η_ωo)² = 1/η², the
//!   net crossing (a walk that crosses twice comes back unscaled).
//! * **Dispersion.** The geometry of a walk follows the hero wavelength's η. A walk that never
//!   crosses the interface keeps all four wavelengths (weights Π F(λᵢ)/F(λ₀) over its
//!   reflections, exact since its directions do not depend on λ); a walk that crosses terminates
//!   the secondary wavelengths, as the single-scattering refraction does. `eval` runs one walk
//!   per wavelength with its own η while the secondaries are alive (four times the cost).
//! * **Lobes.** With one lobe disabled in the context, `sample` drops the walks that leave on its
//!   side (an unbiased estimate of the enabled lobe) and `eval` returns 0 there.
//! * `pdf` is the MIS-only approximation of [`Microsurface::pdf_dielectric`] at the hero η.

use super::RoughDielectric;
use crate::bsdf::{BsdfContext, BsdfFlags, BsdfSample, TransportMode};
use crate::ior::{IorValue, relative_eta};
use crate::microsurface::{Microsurface, eval_rng, sample_rng};
use crate::spectra::SpectralValue;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

impl<S: SpectralValue, I: IorValue> RoughDielectric<S, I> {
    /// The sign that takes ωi above, and η = n(other side)/n(ωi's side) per wavelength.
    #[inline]
    fn ms_side(&self, wi: Vec3, wl: &SampledWavelengths) -> (f32, SampledSpectrum) {
        let eta = relative_eta(&self.int_ior, &self.ext_ior, wl);
        if wi.z > 0.0 {
            (1.0, eta)
        } else {
            (-1.0, SampledSpectrum::splat(1.0) / eta)
        }
    }

    /// True when the lobe ωo falls in (reflection: same side as ωi) is enabled in `ctx`.
    #[inline]
    fn ms_lobe_enabled(ctx: &BsdfContext, reflect: bool) -> bool {
        if reflect {
            ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION)
        } else {
            ctx.is_enabled(BsdfFlags::GLOSSY_TRANSMISSION)
        }
    }

    /// The lobe's tint and, for a transmission in radiance transport, 1/η².
    #[inline]
    fn ms_scale(
        &self,
        ctx: &BsdfContext,
        reflect: bool,
        etas: SampledSpectrum,
        wl: &SampledWavelengths,
    ) -> SampledSpectrum {
        if reflect {
            self.specular_reflectance.sample(wl)
        } else if ctx.mode == TransportMode::Radiance {
            self.specular_transmittance.sample(wl) / (etas * etas)
        } else {
            self.specular_transmittance.sample(wl)
        }
    }

    /// (f, MIS-only pdf) of the multiple-scattering interface.
    pub(super) fn eval_pdf_ms(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        let reflect = wi.z * wo.z > 0.0;
        if wi.z == 0.0 || wo.z == 0.0 || !Self::ms_lobe_enabled(ctx, reflect) {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let (s, etas) = self.ms_side(wi, wl);
        let (a, b) = (wi * s, wo * s);
        let ms = Microsurface::new(self.distribution);
        let mut rng = eval_rng(wi, wo, wl);
        let f_cos = if self.disperses(wl) {
            SampledSpectrum::from_fn(|i| ms.eval_dielectric(a, b, etas[i], &mut rng))
        } else {
            SampledSpectrum::splat(ms.eval_dielectric(a, b, etas[0], &mut rng))
        };
        let f = f_cos * self.ms_scale(ctx, reflect, etas, wl) / wo.z.abs();
        (f, ms.pdf_dielectric(a, b, etas[0]))
    }

    /// The MIS-only pdf of the multiple-scattering interface.
    pub(super) fn pdf_ms(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        let reflect = wi.z * wo.z > 0.0;
        if wi.z == 0.0 || wo.z == 0.0 || !Self::ms_lobe_enabled(ctx, reflect) {
            return 0.0;
        }
        let (s, etas) = self.ms_side(wi, wl);
        Microsurface::new(self.distribution).pdf_dielectric(wi * s, wo * s, etas[0])
    }

    /// The random walk (see the module docs for sides, transport and dispersion).
    pub(super) fn sample_ms(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (s, etas) = self.ms_side(wi, wl);
        let dispersive = self.disperses(wl);
        let walk_etas = if dispersive {
            etas
        } else {
            SampledSpectrum::splat(etas[0])
        };
        let ms = Microsurface::new(self.distribution);
        let walk = ms.sample_dielectric(wi * s, walk_etas, &mut sample_rng(wi, u1, u2))?;
        let wo = walk.wo * s;
        let reflect = wo.z * wi.z > 0.0;
        if wo.z == 0.0 || !Self::ms_lobe_enabled(ctx, reflect) {
            return None;
        }
        let pdf = ms.pdf_dielectric(wi * s, walk.wo, etas[0]);
        if !(pdf > 0.0) {
            return None;
        }
        if dispersive && walk.crossings > 0 {
            wl.terminate_secondary();
        }
        Some(BsdfSample {
            wo,
            weight: walk.weight * self.ms_scale(ctx, reflect, etas, wl),
            pdf,
            flags: if reflect {
                BsdfFlags::GLOSSY_REFLECTION
            } else {
                RoughDielectric::TRANSMISSION_FLAGS
            },
            eta: if reflect { 1.0 } else { etas[0] },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::Bsdf;
    use crate::ior::Ior;
    use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
    use crate::spectra::{Extrapolation, PiecewiseLinear, Spectrum};
    use std::sync::Arc;

    fn dispersive_ms() -> RoughDielectric {
        // BK7-like: n falls from 1.53 at 400 nm to 1.51 at 700 nm.
        let table = PiecewiseLinear::new(vec![400.0, 700.0], vec![1.53, 1.51], Extrapolation::Clamp).unwrap();
        let d = MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.5);
        let mut r = RoughDielectric::new(
            Ior::from_spectrum(Spectrum::PiecewiseLinear(Arc::new(table))),
            Ior::Constant(1.0),
            d,
        );
        r.multiple_scattering = true;
        r
    }

    #[test]
    fn a_crossing_walk_terminates_the_secondaries_and_a_reflecting_one_keeps_them() {
        let r = dispersive_ms();
        let ctx = BsdfContext::importance();
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let (mut kept, mut refracted, mut differs) = (0, 0, false);
        for k in 0..4000u32 {
            let mut wl = SampledWavelengths::sample_visible(0.37);
            let u = Vec2::new((k % 64) as f32 / 64.0 + 0.007, (k / 64) as f32 / 64.0 + 0.003);
            let Some(s) = r.sample(&ctx, wi, (k as f32 * 0.618).fract(), u, &mut wl) else {
                continue;
            };
            if s.flags.is_transmission() {
                refracted += 1;
                assert!(
                    wl.secondary_terminated(),
                    "a refraction keeps the secondaries: {s:?}"
                );
                assert!((s.eta - r.int_ior.eval(wl.hero())).abs() < 1e-6);
            } else if !wl.secondary_terminated() {
                // A walk that only reflected: the secondaries carry Π F(λᵢ)/F(λ₀), near 1 (the
                // index changes by 1.3 %, F ∝ ((n − 1)/(n + 1))² at normal incidence by ~5 %) but
                // not 1.
                kept += 1;
                assert_eq!(s.weight[0], 1.0);
                for i in 1..4 {
                    assert!(s.weight[i] > 0.8 && s.weight[i] < 1.25, "{s:?}");
                }
                differs |= s.weight[1] != 1.0;
            }
        }
        assert!(
            kept > 50 && refracted > 1000 && differs,
            "kept {kept}, refracted {refracted}"
        );
    }

    #[test]
    fn eval_gives_every_wavelength_its_own_walk() {
        // Through a rough prism each wavelength refracts about its own half vector: the four
        // values differ; with the secondaries terminated only the hero is evaluated.
        let r = dispersive_ms();
        let ctx = BsdfContext::importance();
        let (wi, wo) = (Vec3::new(0.6, 0.0, 0.8), Vec3::new(-0.2, 0.1, -0.97).normalize());
        let wl = SampledWavelengths::sample_visible(0.2);
        let f = r.eval(&ctx, wi, wo, &wl);
        assert!(
            f.min_component() > 0.0 && f.max_component() > f.min_component(),
            "{f:?}"
        );
        let mut hero = wl;
        hero.terminate_secondary();
        let g = r.eval(&ctx, wi, wo, &hero);
        assert!(g[0] > 0.0 && g[1] == g[0] && g[3] == g[0], "{g:?}");
    }
}
