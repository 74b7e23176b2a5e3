//! `conductor`: a smooth metal, or the ideal mirror.
//!
//! Lecture, slide "Ideal Specular Reflection": all light leaves in the mirror direction
//! ωr = (−ωi.x, −ωi.y, ωi.z), scaled by the conductor Fresnel reflectance of the complex index
//! η̃ = n + ik:
//!
//! ```text
//!     f_r(ωi, ωo) = F(cos θi, η̃) δ(ωo − ωr) / |cos θo|
//! ```
//!
//! Sampling is deterministic: ωo = ωr, pdf 1 (a discrete probability), weight = tint · F per
//! wavelength. The direction does not depend on λ, so the secondary wavelengths survive.
//!
//! Mitsuba 3 plugin `conductor` (`src/bsdfs/conductor.cpp`), one-sided (nothing unless
//! cos θi > 0):
//!
//! | parameter              | type     | default                                   |
//! |------------------------|----------|-------------------------------------------|
//! | `material`             | string   | `none` (η = 0, k = 1: F ≡ 1, ideal mirror) |
//! | `eta`, `k`             | spectrum | 0, 1 (from `material`)                    |
//! | `specular_reflectance` | spectrum | 1                                         |
//!
//! Addition over Mitsuba: `ext_ior`, the index of a dielectric exterior (a metal under water);
//! Fresnel then uses the relative complex index (n + ik)/n_ext. A dispersive exterior changes
//! amplitudes only and terminates nothing.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, light_directions, reflect};
use crate::fresnel::fresnel_conductor_exterior;
use crate::fresnel_polarized::{conductor_reflection, interface_mueller, normalized};
use crate::ior::{Ior, IorValue, SampledIor};
use crate::mueller::Mueller;
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// A smooth conductor: delta reflection weighted by the complex-index Fresnel reflectance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor<S = Spectrum, I = Ior> {
    /// Real part n of the complex index of refraction.
    pub eta: S,
    /// Imaginary part k (extinction coefficient).
    pub k: S,
    /// Index of the dielectric the metal is immersed in (1 = vacuum; Mitsuba has no such
    /// parameter and assumes 1).
    pub ext_ior: I,
    /// Tint multiplying the Fresnel term (not physically based; default 1).
    pub specular_reflectance: S,
}

impl Default for Conductor {
    /// Mitsuba's default, `material="none"`: the ideal mirror.
    fn default() -> Self {
        Self::mirror()
    }
}

impl Conductor {
    /// A conductor of complex index `eta` + i`k` in vacuum, untinted.
    pub fn new(eta: Spectrum, k: Spectrum) -> Self {
        Self {
            eta,
            k,
            ext_ior: Ior::Constant(1.0),
            specular_reflectance: Spectrum::Constant(1.0),
        }
    }

    /// The ideal mirror, η = 0, k = 1, which makes F ≡ 1 at every angle (Mitsuba
    /// `material="none"`).
    pub fn mirror() -> Self {
        Self::new(Spectrum::Constant(0.0), Spectrum::Constant(1.0))
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> Conductor<SampledSpectrum, SampledIor> {
        Conductor {
            eta: self.eta.sample(wl),
            k: self.k.sample(wl),
            ext_ior: self.ext_ior.at(wl),
            specular_reflectance: self.specular_reflectance.sample(wl),
        }
    }
}

impl<S: SpectralValue, I: IorValue> Conductor<S, I> {
    /// Fresnel reflectance times the tint at incidence cosine `cos_theta_i` (> 0), per
    /// wavelength.
    pub fn reflectance(&self, cos_theta_i: f32, wl: &SampledWavelengths) -> SampledSpectrum {
        let f = fresnel_conductor_exterior(
            cos_theta_i,
            self.eta.sample(wl),
            self.k.sample(wl),
            self.ext_ior.sample(wl),
        );
        f * self.specular_reflectance.sample(wl)
    }
}

impl<S: SpectralValue, I: IorValue> Bsdf for Conductor<S, I> {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DELTA_REFLECTION
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
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !ctx.is_enabled(BsdfFlags::DELTA_REFLECTION) || wi.z <= 0.0 {
            return None;
        }
        let weight = self.reflectance(wi.z, wl);
        (!weight.is_black()).then_some(BsdfSample {
            wo: reflect(wi),
            weight,
            pdf: 1.0,
            flags: BsdfFlags::DELTA_REFLECTION,
            eta: 1.0,
        })
    }

    /// The mirror's weight times the conductor's Fresnel reflection Mueller matrix (complex
    /// index, with its retardance), normalized so that M00 is [`Bsdf::sample`]'s weight.
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        let s = self.sample(ctx, wi, u1, u2, wl)?;
        let m = conductor_reflection(
            wi.z,
            self.eta.sample(wl),
            self.k.sample(wl),
            self.ext_ior.sample(wl),
        );
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

    #[test]
    fn mirror_reflects_everything_exactly() {
        // Mitsuba 3 src/bsdfs/conductor.cpp, material "none": weight 1 at all angles, pdf 1,
        // eval = pdf = 0.
        let m = Conductor::default();
        let ctx = BsdfContext::radiance();
        for deg in [0.0f32, 30.0, 60.0, 80.0, 89.9] {
            let wi = Vec3::new(0.3, 0.4, 0.0).normalize() * dir(deg).x + Vec3::Z * dir(deg).z;
            let mut wl = SampledWavelengths::sample_visible(0.37);
            let s = m.sample(&ctx, wi, 0.5, Vec2::new(0.2, 0.9), &mut wl).unwrap();
            assert_eq!(s.wo, Vec3::new(-wi.x, -wi.y, wi.z), "exact mirror direction");
            assert!(
                (s.weight - SampledSpectrum::ONE).0.abs().max_element() < 1e-6,
                "{:?}",
                s.weight
            );
            assert_eq!((s.pdf, s.eta, s.flags), (1.0, 1.0, BsdfFlags::DELTA_REFLECTION));
            assert!(!wl.secondary_terminated());
            assert_eq!(m.eval(&ctx, wi, s.wo, &wl), SampledSpectrum::ZERO);
            assert_eq!(m.pdf(&ctx, wi, s.wo, &wl), 0.0);
        }
    }

    #[test]
    fn one_sided_and_lobe_masked() {
        let m = Conductor::mirror();
        let mut wl = SampledWavelengths::fixed(550.0);
        let u2 = Vec2::new(0.5, 0.5);
        assert!(
            m.sample(&BsdfContext::radiance(), -dir(20.0), 0.5, u2, &mut wl)
                .is_none(),
            "back side"
        );
        let diffuse_only = BsdfContext::radiance().with_lobes(BsdfFlags::DIFFUSE_REFLECTION);
        assert!(m.sample(&diffuse_only, dir(20.0), 0.5, u2, &mut wl).is_none());
    }

    #[test]
    fn gold_weight_is_fresnel_of_complex_index() {
        // Gold at 400 nm and 550 nm (n, k of pbrt-v4's metal-Au tables; R from the complex Fresnel
        // equations): R(0°) 0.391 / 0.848, R(60°) 0.416 / 0.843.
        let n = PiecewiseLinear::new(vec![400.0, 550.0], vec![1.6579, 0.3504], Extrapolation::Clamp).unwrap();
        let k = PiecewiseLinear::new(vec![400.0, 550.0], vec![1.9560, 2.7141], Extrapolation::Clamp).unwrap();
        let au = Conductor::new(
            Spectrum::PiecewiseLinear(Arc::new(n)),
            Spectrum::PiecewiseLinear(Arc::new(k)),
        );
        let ctx = BsdfContext::radiance();
        for (deg, r400, r550) in [(0.0f32, 0.391f32, 0.848f32), (60.0, 0.416, 0.843)] {
            let mut wl = SampledWavelengths::from_parts([400.0, 550.0, 400.0, 550.0], [1.0; 4]);
            let s = au.sample(&ctx, dir(deg), 0.5, Vec2::ZERO, &mut wl).unwrap();
            assert!(
                (s.weight[0] - r400).abs() < 1e-3 && (s.weight[2] - r400).abs() < 1e-3,
                "{:?}",
                s.weight
            );
            assert!((s.weight[1] - r550).abs() < 1e-3 && (s.weight[3] - r550).abs() < 1e-3);
            assert!(!wl.secondary_terminated(), "reflection keeps all wavelengths");
        }
        // F0 formula through the model, with a tint.
        let (n, k) = (0.2f32, 3.9f32);
        let mut c = Conductor::new(Spectrum::Constant(n), Spectrum::Constant(k));
        c.specular_reflectance = Spectrum::Constant(0.5);
        let f0 = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        let mut wl = SampledWavelengths::fixed(600.0);
        let s = c.sample(&ctx, Vec3::Z, 0.5, Vec2::ZERO, &mut wl).unwrap();
        assert!((s.weight[0] - 0.5 * f0).abs() < 1e-6);
        assert_eq!(s.wo, Vec3::Z);
    }

    #[test]
    fn out_of_range_table_gives_no_nan() {
        // n = k = 0 outside the table (Mitsuba's AlSb at 650 nm gives NaN).
        let n = PiecewiseLinear::new(vec![300.0, 590.0], vec![4.0, 4.5], Extrapolation::Zero).unwrap();
        let k = PiecewiseLinear::new(vec![300.0, 590.0], vec![1.0, 0.2], Extrapolation::Zero).unwrap();
        let c = Conductor::new(
            Spectrum::PiecewiseLinear(Arc::new(n)),
            Spectrum::PiecewiseLinear(Arc::new(k)),
        );
        for deg in [0.0f32, 45.0, 85.0] {
            let mut wl = SampledWavelengths::from_parts([650.0, 750.0, 500.0, 700.0], [1.0; 4]);
            let s = c
                .sample(&BsdfContext::radiance(), dir(deg), 0.5, Vec2::ZERO, &mut wl)
                .unwrap();
            assert!(s.weight.is_finite(), "{:?}", s.weight);
        }
    }

    #[test]
    fn metal_under_water_reflects_less_and_mirror_stays_perfect() {
        let mut au = Conductor::new(Spectrum::Constant(0.3504), Spectrum::Constant(2.7141));
        let mut wl = SampledWavelengths::fixed(550.0);
        let ctx = BsdfContext::radiance();
        let in_air = au.sample(&ctx, Vec3::Z, 0.5, Vec2::ZERO, &mut wl).unwrap().weight[0];
        au.ext_ior = Ior::Constant(1.333);
        let in_water = au.sample(&ctx, Vec3::Z, 0.5, Vec2::ZERO, &mut wl).unwrap().weight[0];
        let (n, k, w) = (0.3504f32, 2.7141f32, 1.333f32);
        let f0 = ((n - w).powi(2) + k * k) / ((n + w).powi(2) + k * k);
        assert!((in_water - f0).abs() < 1e-6 && in_water < in_air);
        let mut m = Conductor::mirror();
        m.ext_ior = Ior::Constant(1.333);
        let s = m.sample(&ctx, dir(70.0), 0.5, Vec2::ZERO, &mut wl).unwrap();
        assert!(
            (s.weight[0] - 1.0).abs() < 1e-6,
            "η = 0 stays a perfect mirror under water"
        );
    }
}
