//! `dielectric`: a smooth interface between two dielectrics (glass, water), ideal specular
//! reflection plus ideal refraction.
//!
//! Lecture, slides "Ideal Specular Reflection", "Ideal Specular Refraction" and "Fresnel
//! Equations": with F = F(cos θi, η) the dielectric Fresnel reflectance and η = n_int/n_ext,
//!
//! ```text
//!     f(ωi, ωo) = F δ(ωo − ωr)/|cos θo|  +  (η_ti)² (1 − F) δ(ωo − ωt)/|cos θo|
//!     ωr = (−ωi.x, −ωi.y, ωi.z),   ωt = (−η_ti ωi.x, −η_ti ωi.y, cos θt)     (Snell)
//! ```
//!
//! where the (η_ti)² = (n_i/n_t)² radiance compression applies in radiance transport mode only
//! (importance transport is the adjoint, without the factor). Sampling follows the lecture's
//! "p_r = F_r": reflect with probability F, refract otherwise, so both weights are 1 (times the
//! tints and the η² factor). With only one lobe enabled the lobe is taken with probability 1 and
//! weighted by F or 1 − F. Total internal reflection makes F = 1: reflection always.
//!
//! **Dispersion.** With a wavelength-dependent `int_ior` or `ext_ior` the lobe is chosen with the
//! hero wavelength's F₀. A reflection does not depend on λ, so all four wavelengths continue
//! with weights F(λᵢ)/F₀ (each wavelength's expected weight is P·F(λᵢ)/F₀ = F(λᵢ): unbiased). A
//! refraction direction does depend on λ: its scalar η comes from
//! [`crate::ior::relative_hero_eta`], which terminates the secondary wavelengths; the hero carries
//! on. (A hero exactly index-matched, F₀ = 0, never reflects; the secondaries' tiny reflectance is
//! then lost, a measure-zero event.)
//!
//! Mitsuba 3 plugin `dielectric` (`src/bsdfs/dielectric.cpp`), two-sided:
//!
//! | parameter                | type              | default                |
//! |--------------------------|-------------------|------------------------|
//! | `int_ior`                | float, name       | `bk7` 1.5046           |
//! | `ext_ior`                | float, name       | `air` 1.000277         |
//! | `specular_reflectance`   | spectrum          | 1 (tint; not physical) |
//! | `specular_transmittance` | spectrum          | 1 (tint; not physical) |
//!
//! gonio additionally accepts a spectrum (Sellmeier, table) for either index.

use crate::bsdf::{
    Bsdf, BsdfContext, BsdfFlags, BsdfSample, LobeSplit, TransportMode, choose_delta_lobe, light_directions,
    reflect,
};
use crate::fresnel::{FresnelDielectric, fresnel_dielectric, fresnel_dielectric_spectrum, refract};
use crate::fresnel_polarized::{
    dielectric_reflection, dielectric_transmission, interface_mueller, normalized,
};
use crate::ior::{Ior, IorValue, SampledIor, relative_eta, relative_hero_eta};
use crate::mueller::Mueller;
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// A smooth dielectric interface: Fresnel-weighted delta reflection and refraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric<S = Spectrum, I = Ior> {
    /// Index of the interior (the side the normal points away from).
    pub int_ior: I,
    /// Index of the exterior (the side the normal points to).
    pub ext_ior: I,
    /// Tint of the reflection (default 1).
    pub specular_reflectance: S,
    /// Tint of the refraction (default 1).
    pub specular_transmittance: S,
}

impl Default for Dielectric {
    /// Mitsuba's defaults: bk7 (1.5046) inside, air (1.000277) outside, η = 1.504183.
    fn default() -> Self {
        Self::new(Ior::Constant(1.5046), Ior::Constant(1.000277))
    }
}

/// The lobe flags of the refraction.
const TRANSMISSION: BsdfFlags = BsdfFlags(BsdfFlags::DELTA_TRANSMISSION.0 | BsdfFlags::NON_SYMMETRIC.0);

impl Dielectric {
    /// The lobe flags of the refraction.
    pub const TRANSMISSION_FLAGS: BsdfFlags = TRANSMISSION;

    /// An untinted interface between `int_ior` (inside) and `ext_ior` (outside).
    pub fn new(int_ior: Ior, ext_ior: Ior) -> Self {
        Self {
            int_ior,
            ext_ior,
            specular_reflectance: Spectrum::Constant(1.0),
            specular_transmittance: Spectrum::Constant(1.0),
        }
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> Dielectric<SampledSpectrum, SampledIor> {
        Dielectric {
            int_ior: self.int_ior.at(wl),
            ext_ior: self.ext_ior.at(wl),
            specular_reflectance: self.specular_reflectance.sample(wl),
            specular_transmittance: self.specular_transmittance.sample(wl),
        }
    }
}

impl<S: SpectralValue, I: IorValue> Dielectric<S, I> {
    /// Both lobes [`Bsdf::sample`] chooses between with the coin `u1 < F` ([`LobeSplit`]): the
    /// reflection weighted F·tint, the refraction (1 − F)·η²·tint, each with the probability
    /// `sample` takes it as its `pdf`. `None` for a dispersive index while the secondary wavelengths
    /// live (a refraction would end them for both lobes) and grazing ωi; no refraction under
    /// total internal reflection. The lobes of `ctx` are replaced by each lobe alone.
    pub fn sample_split(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wl: &mut SampledWavelengths,
    ) -> Option<LobeSplit> {
        let dispersive = self.int_ior.is_dispersive() || self.ext_ior.is_dispersive();
        if wi.z == 0.0 || (dispersive && !wl.secondary_terminated()) {
            return None;
        }
        let f_hero = fresnel_dielectric(wi.z, relative_eta(&self.int_ior, &self.ext_ior, wl)[0]).reflectance;
        Some(LobeSplit::of_delta_lobes(
            f_hero,
            BsdfFlags::DELTA_TRANSMISSION,
            wl,
            |lobe, wl| self.sample(&ctx.with_lobes(lobe), wi, 0.5, Vec2::ZERO, wl),
        ))
    }
}

impl<S: SpectralValue, I: IorValue> Bsdf for Dielectric<S, I> {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DELTA_REFLECTION | TRANSMISSION
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
        u1: f32,
        _u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let dispersive = self.int_ior.is_dispersive() || self.ext_ior.is_dispersive();
        // Per-wavelength η for amplitudes; [0] is the hero's.
        let eta = relative_eta(&self.int_ior, &self.ext_ior, wl);
        let f_hero = fresnel_dielectric(wi.z, eta[0]).reflectance;
        // Total internal reflection with the reflection masked: no transmission (probability 0).
        let (reflect_chosen, pdf) = choose_delta_lobe(ctx, u1, f_hero)?;
        if !reflect_chosen && f_hero >= 1.0 {
            return None;
        }

        if reflect_chosen {
            let f = if dispersive {
                fresnel_dielectric_spectrum(wi.z, eta)
            } else {
                SampledSpectrum::splat(f_hero)
            };
            let weight = f / pdf * self.specular_reflectance.sample(wl);
            return (pdf > 0.0 && !weight.is_black()).then_some(BsdfSample {
                wo: reflect(wi),
                weight,
                pdf,
                flags: BsdfFlags::DELTA_REFLECTION,
                eta: 1.0,
            });
        }

        let base = (1.0 - f_hero) / pdf;
        // The one scalar η the direction needs; terminates the secondaries if dispersive.
        let eta_hero = relative_hero_eta(&self.int_ior, &self.ext_ior, wl);
        let FresnelDielectric {
            cos_theta_t,
            eta_it,
            eta_ti,
            ..
        } = fresnel_dielectric(wi.z, eta_hero);
        let mut weight = self.specular_transmittance.sample(wl) * base;
        if ctx.mode == TransportMode::Radiance {
            weight *= eta_ti * eta_ti;
        }
        (!weight.is_black()).then_some(BsdfSample {
            wo: refract(wi, cos_theta_t, eta_ti),
            weight,
            pdf,
            flags: TRANSMISSION,
            eta: eta_it,
        })
    }

    /// [`Bsdf::sample`]'s lobe and weight times the Fresnel reflection or transmission Mueller
    /// matrix (with the phase of total internal reflection), normalized so that M00 is the
    /// spectral weight.
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        let s = self.sample(ctx, wi, u1, u2, wl)?;
        let eta = relative_eta(&self.int_ior, &self.ext_ior, wl);
        let m = if s.flags.is_reflection() {
            dielectric_reflection(wi.z, eta)
        } else {
            dielectric_transmission(wi.z, eta)
        };
        let (light_in, light_out) = light_directions(ctx, wi, s.wo);
        Some(s.with_weight(interface_mueller(
            normalized(&m).scaled(s.weight),
            Vec3::Z,
            light_in,
            light_out,
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectra::{Extrapolation, PiecewiseLinear};
    use std::sync::Arc;

    fn dir(theta_deg: f32) -> Vec3 {
        let t = theta_deg.to_radians();
        Vec3::new(t.sin(), 0.0, t.cos())
    }

    fn close(a: f32, b: f32, tol: f32) -> bool {
        (a - b).abs() <= tol
    }

    /// Fixed-seed uniforms in [0, 1) (the core's Weyl sequence hashed by `mix64`).
    fn uniforms(seed: u64) -> impl FnMut() -> f32 {
        let mut r = crate::hash::WeylHash(seed);
        move || r.next_f32()
    }

    /// The exact directional albedo of a delta BSDF: Σ over its (at most two) outcomes of
    /// P(outcome)·weight, found by sampling with u1 at both ends.
    fn exact_albedo(b: &dyn Bsdf, ctx: &BsdfContext, wi: Vec3) -> f32 {
        let mut total = 0.0;
        let mut seen = BsdfFlags::NONE;
        for u1 in [0.0, 1.0 - f32::EPSILON] {
            let mut wl = SampledWavelengths::fixed(550.0);
            if let Some(s) = b.sample(ctx, wi, u1, Vec2::splat(0.5), &mut wl)
                && s.flags != seen
            {
                total += s.pdf * s.weight[0];
                seen = s.flags;
            }
        }
        total
    }

    fn tinted_15() -> Dielectric {
        let mut d = Dielectric::new(Ior::Constant(1.5), Ior::Constant(1.0));
        d.specular_reflectance = Spectrum::Constant(0.3);
        d.specular_transmittance = Spectrum::Constant(0.6);
        d
    }

    /// Lobe splitting: the lobe `sample` takes with `u1` is one of the two (same direction,
    /// flags and pdf, weight times the probability of taking it), the probabilities are F and
    /// 1 − F, and each lobe's weight is its whole expected value (F·tint, (1 − F)·η²·tint);
    /// under total internal reflection the refraction is missing; no split where the index
    /// disperses.
    #[test]
    fn split_lobes_are_the_coin_outcomes_of_sample_weighted_whole() {
        let d = tinted_15().at(&SampledWavelengths::fixed(550.0));
        let ctx = BsdfContext::radiance();
        for wi in [dir(0.0), dir(40.0), dir(85.0), -dir(20.0), -dir(30.0), -dir(60.0)] {
            let mut wl = SampledWavelengths::fixed(550.0);
            let split = d.sample_split(&ctx, wi, &mut wl).unwrap();
            let eta = if wi.z > 0.0 { 1.5 } else { 1.0 / 1.5 };
            let f = fresnel_dielectric(wi.z, 1.5).reflectance;
            assert!(close(split.reflectance, f, 1e-7));
            let (r, c_r) = split.reflection.unwrap();
            assert!(close(r.weight[0], 0.3 * f, 1e-6) && close(c_r, f, 1e-7) && r.pdf == c_r);
            match split.refraction {
                Some((t, c_t)) => {
                    assert!(f < 1.0 && close(c_r + c_t, 1.0, 1e-6) && t.pdf == c_t);
                    assert!(close(t.weight[0], 0.6 * (1.0 - f) / (eta * eta), 1e-5), "{t:?}");
                }
                None => assert!(f >= 1.0, "refraction missing at {wi}"),
            }
            for u1 in [0.001f32, 0.02, 0.1, 0.5, 0.9, 0.999] {
                let plain = d.sample(&ctx, wi, u1, Vec2::splat(0.5), &mut wl);
                let taken = if u1 < split.reflectance {
                    split.reflection
                } else {
                    split.refraction
                };
                match (plain, taken) {
                    (None, None) => {}
                    (Some(p), Some((t, c))) => {
                        assert!((p.wo - t.wo).length() < 1e-6 && p.flags == t.flags && p.pdf == t.pdf);
                        assert!(close(t.weight[0] / c, p.weight[0], 1e-5), "{t:?} / {c} vs {p:?}");
                    }
                    (p, t) => panic!("wi={wi} u1={u1}: sample {p:?}, split {t:?}"),
                }
            }
        }
        let mut wl = SampledWavelengths::from_parts([450.0, 520.0, 590.0, 660.0], [1.0; 4]);
        assert!(
            dispersive_glass()
                .at(&wl)
                .sample_split(&ctx, dir(30.0), &mut wl)
                .is_none()
        );
    }

    #[test]
    fn mitsuba_unit_test_values() {
        // Mitsuba 3 src/bsdfs/tests/test_dielectric.py: η = 1.5, tints 0.3 / 0.6, ωi = +z.
        let d = tinted_15();
        let rad = BsdfContext::radiance();
        let imp = BsdfContext::importance();
        let mut wl = SampledWavelengths::fixed(550.0);
        let u2 = Vec2::new(0.3, 0.7);
        let s = d.sample(&rad, Vec3::Z, 0.0, u2, &mut wl).unwrap();
        assert!(close(s.weight[0], 0.3, 1e-6) && close(s.pdf, 0.04, 1e-6) && s.eta == 1.0);
        assert_eq!((s.wo, s.flags), (Vec3::Z, BsdfFlags::DELTA_REFLECTION));
        let s = d.sample(&imp, Vec3::Z, 0.05, u2, &mut wl).unwrap();
        assert!(close(s.weight[0], 0.6, 1e-6) && close(s.pdf, 0.96, 1e-6) && s.eta == 1.5);
        assert_eq!(s.wo, -Vec3::Z);
        assert!(
            s.flags
                .contains(BsdfFlags::DELTA_TRANSMISSION | BsdfFlags::NON_SYMMETRIC)
        );
        let s = d.sample(&rad, Vec3::Z, 0.05, u2, &mut wl).unwrap();
        assert!(close(s.weight[0], 0.6 / 2.25, 1e-6));
        let s = d.sample(&rad, -Vec3::Z, 0.05, u2, &mut wl).unwrap();
        assert!(close(s.weight[0], 0.6 * 2.25, 1e-5) && close(s.eta, 1.0 / 1.5, 1e-7) && s.wo == Vec3::Z);
        // Only the reflection lobe: pdf 1, weight 0.3·0.04, whatever u1.
        let refl_only = rad.with_lobes(BsdfFlags::DELTA_REFLECTION);
        for u1 in [0.0, 0.5, 0.99] {
            let s = d.sample(&refl_only, Vec3::Z, u1, u2, &mut wl).unwrap();
            assert!(close(s.weight[0], 0.3 * 0.04, 1e-7) && s.pdf == 1.0);
        }
        let trans_only = imp.with_lobes(BsdfFlags::DELTA_TRANSMISSION);
        let s = d.sample(&trans_only, Vec3::Z, 0.0, u2, &mut wl).unwrap();
        assert!(close(s.weight[0], 0.6 * 0.96, 1e-6) && s.pdf == 1.0);
        assert!(
            d.sample(
                &rad.with_lobes(BsdfFlags::DIFFUSE_REFLECTION),
                Vec3::Z,
                0.5,
                u2,
                &mut wl
            )
            .is_none()
        );
    }

    #[test]
    fn default_sampling_table() {
        // Measured with Mitsuba 3.9.1, defaults η = 1.504183, radiance mode, ξ2 = (0.3, 0.7).
        let d = Dielectric::default();
        let ctx = BsdfContext::radiance();
        let u2 = Vec2::new(0.3, 0.7);
        let mut wl = SampledWavelengths::sample_visible(0.5);
        let s = d.sample(&ctx, Vec3::Z, 0.01, u2, &mut wl).unwrap();
        assert!(close(s.pdf, 0.040536, 1e-6) && close(s.weight[0], 1.0, 1e-6) && s.wo == Vec3::Z);
        let s = d.sample(&ctx, Vec3::Z, 0.99, u2, &mut wl).unwrap();
        assert!((s.wo - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert!(
            close(s.pdf, 0.959464, 1e-6) && close(s.eta, 1.50418, 1e-5) && close(s.weight[0], 0.441976, 1e-6)
        );
        let wi = Vec3::new(60f32.to_radians().sin(), 0.0, 0.5);
        let s = d.sample(&ctx, wi, 0.01, u2, &mut wl).unwrap();
        assert!(close(s.pdf, 0.089880, 1e-6) && s.flags == BsdfFlags::DELTA_REFLECTION);
        let s = d.sample(&ctx, wi, 0.99, u2, &mut wl).unwrap();
        assert!(
            (s.wo - Vec3::new(-0.575745, 0.0, -0.81763)).length() < 1e-5,
            "{}",
            s.wo
        );
        assert!(close(s.pdf, 0.910120, 1e-6) && close(s.weight[0], 0.441976, 1e-6));
        assert!(!wl.secondary_terminated(), "constant IOR never terminates");
        assert_eq!(d.eval(&ctx, wi, s.wo, &wl), SampledSpectrum::ZERO);
        assert_eq!(d.pdf(&ctx, wi, s.wo, &wl), 0.0);
    }

    #[test]
    fn refraction_obeys_snell_reverses_and_radiance_weights_cancel() {
        let d = Dielectric::new(Ior::Constant(1.5), Ior::Constant(1.0));
        let ctx = BsdfContext::radiance();
        for deg in [0.0f32, 15.0, 40.0, 65.0, 85.0] {
            for az in [0.0f32, 2.0] {
                let t = deg.to_radians();
                let wi = Vec3::new(t.sin() * az.cos(), t.sin() * az.sin(), t.cos());
                let mut wl = SampledWavelengths::fixed(550.0);
                let s = d.sample(&ctx, wi, 0.9999, Vec2::ZERO, &mut wl).unwrap();
                assert!(s.flags.is_transmission() && close(s.wo.length(), 1.0, 1e-6));
                // Snell: n_i sin θi = n_t sin θt, and the plane of incidence is kept.
                let sin_i = (wi.x * wi.x + wi.y * wi.y).sqrt();
                let sin_t = (s.wo.x * s.wo.x + s.wo.y * s.wo.y).sqrt();
                assert!(close(sin_i, 1.5 * sin_t, 1e-6), "θ {deg}");
                assert!(wi.truncate().perp_dot(s.wo.truncate()).abs() < 1e-6 && s.wo.z < 0.0);
                // Back through the interface from inside: the reversed path.
                let back = d.sample(&ctx, s.wo, 0.9999, Vec2::ZERO, &mut wl).unwrap();
                assert!(back.flags.is_transmission());
                assert!((back.wo - wi).length() < 1e-5, "refract(refract(ω)) = ω");
                assert!(
                    close(s.weight[0] * back.weight[0], 1.0, 1e-5),
                    "η² factors cancel"
                );
                assert!(close(s.eta * back.eta, 1.0, 1e-6));
            }
        }
    }

    #[test]
    fn total_internal_reflection_always_reflects() {
        let d = Dielectric::new(Ior::Constant(1.5), Ior::Constant(1.0));
        let ctx = BsdfContext::radiance();
        let wi = -dir(45.0); // inside, beyond the critical angle 41.8°
        for u1 in [0.0, 0.3, 0.999_999] {
            let mut wl = SampledWavelengths::fixed(550.0);
            let s = d.sample(&ctx, wi, u1, Vec2::ZERO, &mut wl).unwrap();
            assert_eq!(
                (s.flags, s.pdf, s.weight[0]),
                (BsdfFlags::DELTA_REFLECTION, 1.0, 1.0)
            );
            assert_eq!(s.wo, Vec3::new(-wi.x, -wi.y, wi.z));
        }
        let mut wl = SampledWavelengths::fixed(550.0);
        let trans_only = ctx.with_lobes(BsdfFlags::DELTA_TRANSMISSION);
        assert!(d.sample(&trans_only, wi, 0.5, Vec2::ZERO, &mut wl).is_none());
        // Just inside the critical angle refraction is still possible.
        let wi = -dir(41.0);
        assert!(d.sample(&trans_only, wi, 0.5, Vec2::ZERO, &mut wl).is_some());
    }

    #[test]
    fn reflection_frequency_is_fresnel_binomial() {
        let d = Dielectric::default();
        let ctx = BsdfContext::radiance();
        let eta = 1.5046f32 / 1.000277;
        let n = 200_000;
        let mut u = uniforms(7);
        for wi in [dir(0.0), dir(60.0), dir(80.0), -dir(30.0)] {
            let f = fresnel_dielectric(wi.z, eta).reflectance as f64;
            let mut hits = 0usize;
            for _ in 0..n {
                let mut wl = SampledWavelengths::fixed(550.0);
                let s = d.sample(&ctx, wi, u(), Vec2::ZERO, &mut wl).unwrap();
                hits += s.flags.is_reflection() as usize;
            }
            let sigma = (f * (1.0 - f) / n as f64).sqrt();
            let freq = hits as f64 / n as f64;
            assert!(
                (freq - f).abs() < 5.0 * sigma,
                "θ {}: {freq} vs F {f} (σ {sigma})",
                wi.z.acos()
            );
        }
    }

    #[test]
    fn energy_importance_is_one_radiance_is_f_plus_t_over_eta2() {
        let d = Dielectric::default();
        let eta = 1.5046f32 / 1.000277;
        let imp = BsdfContext::importance();
        let rad = BsdfContext::radiance();
        for deg in [0.0f32, 20.0, 45.0, 60.0, 80.0, 89.0] {
            for wi in [dir(deg), -dir(deg)] {
                assert!(close(exact_albedo(&d, &imp, wi), 1.0, 1e-6), "importance θ {deg}");
                let f = fresnel_dielectric(wi.z, eta).reflectance;
                let eta_ti = if wi.z > 0.0 { 1.0 / eta } else { eta };
                let expect = if f == 1.0 {
                    1.0
                } else {
                    f + (1.0 - f) * eta_ti * eta_ti
                };
                assert!(close(exact_albedo(&d, &rad, wi), expect, 1e-5));
            }
        }
        // F + (1 − F)/η² computed from the Fresnel equations (Mitsuba 3.9.1 measures 0.4647, 0.4704,
        // 0.6588).
        for (deg, a) in [(0.0, 0.464596), (45.0, 0.470337), (80.0, 0.658714)] {
            assert!(close(exact_albedo(&d, &rad, dir(deg)), a, 2e-6), "{deg}");
        }
        assert!(close(exact_albedo(&d, &rad, -Vec3::Z), 2.211388, 5e-6));
        assert!(close(exact_albedo(&d, &rad, -dir(45.0)), 1.0, 1e-7), "TIR");
    }

    #[test]
    fn index_matched_interface_is_invisible() {
        let d = Dielectric::new(Ior::Constant(1.33), Ior::Constant(1.33));
        let wi = Vec3::new(0.3, -0.4, 0.5).normalize();
        let mut wl = SampledWavelengths::fixed(500.0);
        for u1 in [0.0, 0.5] {
            let s = d
                .sample(&BsdfContext::radiance(), wi, u1, Vec2::ZERO, &mut wl)
                .unwrap();
            assert!((s.wo + wi).length() < 1e-6 && close(s.weight[0], 1.0, 1e-6) && s.pdf == 1.0);
        }
    }

    fn dispersive_glass() -> Dielectric {
        let table = PiecewiseLinear::new(vec![400.0, 700.0], vec![1.53, 1.51], Extrapolation::Clamp).unwrap();
        Dielectric::new(
            Ior::from_spectrum(Spectrum::PiecewiseLinear(Arc::new(table))),
            Ior::Constant(1.0),
        )
    }

    #[test]
    fn dispersion_reflection_keeps_wavelengths_unbiased_refraction_terminates() {
        let d = dispersive_glass();
        let ctx = BsdfContext::radiance();
        let wi = dir(70.0);
        let lambdas = [420.0f32, 500.0, 580.0, 660.0];
        let f: Vec<f32> = lambdas
            .iter()
            .map(|&l| fresnel_dielectric(wi.z, d.int_ior.eval(l)).reflectance)
            .collect();
        // Stratified u1: the mean reflected weight per wavelength must be F(λᵢ).
        let n = 100_000;
        let mut mean = [0.0f64; 4];
        for j in 0..n {
            let u1 = (j as f32 + 0.5) / n as f32;
            let mut wl = SampledWavelengths::from_parts(lambdas, [1.0; 4]);
            let s = d.sample(&ctx, wi, u1, Vec2::ZERO, &mut wl).unwrap();
            if s.flags.is_reflection() {
                assert!(!wl.secondary_terminated(), "a reflection does not disperse");
                assert_eq!(s.wo, reflect(wi));
                for i in 0..4 {
                    mean[i] += s.weight[i] as f64 / n as f64;
                }
            } else {
                assert!(wl.secondary_terminated(), "a refraction disperses");
                // The direction follows the hero's index.
                let sin_t = (1.0 - s.wo.z * s.wo.z).sqrt();
                assert!(close(wi.x, d.int_ior.eval(lambdas[0]) * sin_t, 1e-6));
            }
        }
        for i in 0..4 {
            assert!(
                (mean[i] - f[i] as f64).abs() < 2e-5,
                "λ {}: {} vs F {}",
                lambdas[i],
                mean[i],
                f[i]
            );
        }
        // Blue and red refract to different directions.
        let refr = |l: f32| {
            let mut wl = SampledWavelengths::from_parts([l, 500.0, 600.0, 650.0], [1.0; 4]);
            d.sample(&ctx, wi, 0.99, Vec2::ZERO, &mut wl).unwrap().wo
        };
        assert!(refr(400.0).x.abs() < refr(700.0).x.abs(), "blue bends more");
    }
}
