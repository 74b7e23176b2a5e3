//! `pplastic`: polarized plastic, a rough specular reflection added to a diffuse lobe that enters
//! and leaves through a smooth interface (Baek et al. 2018, "Simultaneous acquisition of
//! polarimetric SVBRDF and normals", ACM TOG 37(6); as Mitsuba 3.9.1 implements it in
//! `src/bsdfs/pplastic.cpp`).
//!
//! Unlike `plastic`/`roughplastic` the two lobes are added without modelling the layer: the
//! specular lobe is the microfacet reflection of the dielectric interface (Walter et al. 2007) and
//! the diffuse lobe is Lambertian light that refracted in through a smooth interface, was
//! depolarized by subsurface scattering, and refracted out again. With h the half vector,
//! μ = cos θ, F the dielectric Fresnel reflectance of η = int_ior/ext_ior and D, G of
//! [`crate::microfacet`]:
//!
//! ```text
//!     f(ωi, ωo) = tint F(ωi·h, η) D(h) G(ωi, ωo, h) / (4 μi μo)
//!               + (1 − F(μi, η)) ρ/π (1 − F(μo, η))
//! ```
//!
//! Neither lobe accounts for the other's energy; the sum is not energy conserving in general
//! (Mitsuba's documentation says as much) but stays below 1 for ρ ≤ 1, since the rough reflection
//! returns less than the two refractions take away.
//!
//! **Polarization** (`eval_mueller`): the specular lobe is f_s times the Fresnel reflection
//! matrix at h in the s/p frames of the plane through h (as `roughconductor`); the diffuse lobe is
//! T_out · diag(ρ, 0, 0, 0) · T_in · (1/π) with T_in, T_out the Fresnel transmission matrices of
//! the macro-surface (normal +z) at the light's entry and exit, in the s/p frames of the plane
//! through +z. Since the middle factor depolarizes, the diffuse matrix is of rank one: with
//! t(μ) = (T_s − T_p)/(T_s + T_p) at incidence μ (a reciprocal quantity, so the exit refraction
//! from inside has the t of its outside direction),
//!
//! ```text
//!     M_diffuse = f_d [1 t_in 0 0; t_out t_out·t_in 0 0; 0 0 0 0; 0 0 0 0]    (s/p frames)
//! ```
//!
//! so diffuse light leaves partly p-polarized, weaker than the specular lobe's s-polarization and
//! turned by 90 degrees (the cue of shape from polarization). Both terms are then expressed in
//! Mitsuba's implicit Stokes bases of the incident and outgoing beams ([`crate::bsdf::light_directions`]).
//! M00 is [`Bsdf::eval`]'s value exactly.
//!
//! **Sampling** (Mitsuba's): the specular lobe with probability s = mean(tint)/(mean(ρ) +
//! mean(tint)) (a microfacet normal, visible normals by default, ωo reflected about it), else a
//! cosine-weighted direction; pdf = s D_ωi(h)/(4 ωo·h) + (1 − s) μo/π; weight f μo / pdf.
//! One-sided: nothing unless μi > 0 and μo > 0.
//!
//! Mitsuba 3 plugin `pplastic`:
//!
//! | parameter              | type        | default                                   |
//! |------------------------|-------------|-------------------------------------------|
//! | `diffuse_reflectance`  | spectrum    | 0.5                                       |
//! | `specular_reflectance` | spectrum    | 1 (tint; not physical)                    |
//! | `int_ior`, `ext_ior`   | float, name | `polypropylene` 1.49, `air` 1.000277 (must differ) |
//! | `distribution`         | string      | `beckmann` (or `ggx`)                     |
//! | `alpha` (or `alpha_u`, `alpha_v`) | float | 0.1 (numbers; anisotropic allowed) |
//! | `sample_visible`       | boolean     | true                                      |

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, light_directions};
use crate::fresnel::fresnel_dielectric;
use crate::fresnel_polarized::{
    dielectric_reflection, dielectric_transmission, facet_mueller, interface_mueller,
};
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
use crate::mueller::{Mueller, MuellerMatrix};
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Polarized plastic (Mitsuba `pplastic`); see the module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PPlastic<S = Spectrum> {
    /// ρ, the albedo of the diffuse lobe.
    pub diffuse_reflectance: S,
    /// Tint of the specular lobe (default 1).
    pub specular_reflectance: S,
    /// The microfacet distribution of the specular lobe.
    pub distribution: MicrofacetDistribution,
    /// Relative index η = int_ior/ext_ior (≠ 1).
    pub eta: f32,
    specular_sampling_weight: f32,
}

impl Default for PPlastic {
    /// Mitsuba's defaults: ρ = 0.5, tint 1, polypropylene (1.49) in air (1.000277), Beckmann
    /// α = 0.1, visible normals.
    fn default() -> Self {
        Self::new(
            Spectrum::Constant(0.5),
            Spectrum::Constant(1.0),
            MicrofacetDistribution::isotropic(MicrofacetKind::Beckmann, 0.1),
            1.49 / 1.000277,
        )
    }
}

impl PPlastic {
    /// The model; the specular sampling weight is s = mean(tint)/(mean(ρ) + mean(tint)).
    pub fn new(
        diffuse_reflectance: Spectrum,
        specular_reflectance: Spectrum,
        distribution: MicrofacetDistribution,
        eta: f32,
    ) -> Self {
        let (d, s) = (diffuse_reflectance.mean(), specular_reflectance.mean());
        let specular_sampling_weight = if d + s > 0.0 { s / (d + s) } else { 0.5 };
        Self {
            diffuse_reflectance,
            specular_reflectance,
            distribution,
            eta,
            specular_sampling_weight,
        }
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> PPlastic<SampledSpectrum> {
        PPlastic {
            diffuse_reflectance: self.diffuse_reflectance.sample(wl),
            specular_reflectance: self.specular_reflectance.sample(wl),
            distribution: self.distribution,
            eta: self.eta,
            specular_sampling_weight: self.specular_sampling_weight,
        }
    }
}

impl<S: SpectralValue> PPlastic<S> {
    /// Replaces the specular sampling weight s ∈ [0, 1] (a textured material keeps the weight of
    /// its texture means). Changes the variance only.
    pub fn with_specular_sampling_weight(mut self, s: f32) -> Self {
        self.specular_sampling_weight = s.clamp(0.0, 1.0);
        self
    }

    /// s, the probability of sampling the specular lobe when both lobes are enabled.
    pub fn specular_sampling_weight(&self) -> f32 {
        self.specular_sampling_weight
    }

    fn prob_specular(&self, ctx: &BsdfContext) -> f32 {
        let has_spec = ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION);
        let has_diff = ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION);
        if has_spec != has_diff {
            return if has_spec { 1.0 } else { 0.0 };
        }
        self.specular_sampling_weight
    }

    /// (f_specular, f_diffuse, pdf) for μi, μo > 0.
    #[inline]
    fn lobes(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, SampledSpectrum, f32) {
        let distr = &self.distribution;
        let p_spec = self.prob_specular(ctx);
        let h = (wi + wo).normalize_or_zero();
        let mut f_s = SampledSpectrum::ZERO;
        let mut f_d = SampledSpectrum::ZERO;
        let mut pdf = 0.0;
        if h.z > 0.0 && wi.dot(h) > 0.0 && wo.dot(h) > 0.0 {
            if ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) {
                let fr = fresnel_dielectric(wi.dot(h), self.eta).reflectance;
                let value = fr * distr.d(h) * distr.g(wi, wo, h) / (4.0 * wi.z * wo.z);
                if value.is_finite() && value > 0.0 {
                    f_s = self.specular_reflectance.sample(wl) * value;
                }
            }
            let p = distr.pdf(wi, h) / (4.0 * wo.dot(h));
            if p.is_finite() {
                pdf = p_spec * p;
            }
        }
        if ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) {
            let t_i = 1.0 - fresnel_dielectric(wi.z, self.eta).reflectance;
            let t_o = 1.0 - fresnel_dielectric(wo.z, self.eta).reflectance;
            f_d = self.diffuse_reflectance.sample(wl) * (t_i * t_o * FRAC_1_PI);
            pdf += (1.0 - p_spec) * square_to_cosine_hemisphere_pdf(wo);
        }
        (f_s, f_d, pdf)
    }

    fn any_lobe(ctx: &BsdfContext) -> bool {
        ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) || ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION)
    }

    /// The two lobes' values as one Mueller matrix between the implicit bases of the query.
    fn polarize(
        &self,
        f_s: SampledSpectrum,
        f_d: SampledSpectrum,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
    ) -> Mueller {
        let (light_in, light_out) = light_directions(ctx, wi, wo);
        let eta = SampledSpectrum::splat(self.eta);
        let h = (wi + wo).normalize_or_zero();
        // Fresnel reflection at h, for light arriving along light_in.
        let spec = facet_mueller(
            f_s,
            &dielectric_reflection((-light_in).dot(h), eta),
            h,
            ctx,
            wi,
            wo,
        );
        // t = (T_s − T_p)/(T_s + T_p) at the entry and the exit (module docs).
        let t = |mu: f32| {
            let m = dielectric_transmission(mu.abs(), eta);
            let (a, b) = (m.get(0, 0)[0], m.get(0, 1)[0]);
            if a > 0.0 { b / a } else { 0.0 }
        };
        let (t_in, t_out) = (t(light_in.z), t(light_out.z));
        let mut m = MuellerMatrix::ZERO;
        m.0[0][0] = f_d;
        m.0[0][1] = f_d * t_in;
        m.0[1][0] = f_d * t_out;
        m.0[1][1] = f_d * (t_out * t_in);
        let diffuse = interface_mueller(m, Vec3::Z, light_in, light_out);
        spec + diffuse
    }
}

impl<S: SpectralValue> Bsdf for PPlastic<S> {
    fn flags(&self) -> BsdfFlags {
        let f = BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::DIFFUSE_REFLECTION;
        if self.distribution.is_anisotropic() {
            f | BsdfFlags::ANISOTROPIC
        } else {
            f
        }
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.eval_pdf(ctx, wi, wo, wl).0
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        self.eval_pdf(ctx, wi, wo, wl).1
    }

    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        if !Self::any_lobe(ctx) || wi.z <= 0.0 || wo.z <= 0.0 {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let (f_s, f_d, pdf) = self.lobes(ctx, wi, wo, wl);
        (f_s + f_d, pdf)
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, flags) = self.sample_direction(ctx, wi, u1, u2)?;
        let (f_s, f_d, pdf) = self.lobes(ctx, wi, wo, wl);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: (f_s + f_d) * (wo.z / pdf),
            pdf,
            flags,
            eta: 1.0,
        })
    }

    /// `eval` with the Fresnel matrices of both lobes (polarizing).
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        if !Self::any_lobe(ctx) || wi.z <= 0.0 || wo.z <= 0.0 {
            return Mueller::depolarizer(SampledSpectrum::ZERO);
        }
        let (f_s, f_d, _) = self.lobes(ctx, wi, wo, wl);
        self.polarize(f_s, f_d, ctx, wi, wo)
    }

    /// `sample` with the Mueller weight of `eval_mueller` · μo / pdf.
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        let (wo, flags) = self.sample_direction(ctx, wi, u1, u2)?;
        let (f_s, f_d, pdf) = self.lobes(ctx, wi, wo, wl);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: self.polarize(f_s, f_d, ctx, wi, wo) * (wo.z / pdf),
            pdf,
            flags,
            eta: 1.0,
        })
    }
}

impl<S: SpectralValue> PPlastic<S> {
    /// The direction `sample` draws and its lobe, before evaluation.
    fn sample_direction(&self, ctx: &BsdfContext, wi: Vec3, u1: f32, u2: Vec2) -> Option<(Vec3, BsdfFlags)> {
        if !Self::any_lobe(ctx) || wi.z <= 0.0 {
            return None;
        }
        let (wo, flags) = if u1 < self.prob_specular(ctx) {
            let (m, pdf_m) = self.distribution.sample(wi, u2);
            let cos_im = wi.dot(m);
            if pdf_m <= 0.0 || cos_im <= 0.0 {
                return None;
            }
            ((2.0 * cos_im * m - wi).normalize(), BsdfFlags::GLOSSY_REFLECTION)
        } else {
            (square_to_cosine_hemisphere(u2), BsdfFlags::DIFFUSE_REFLECTION)
        };
        (wo.z > 0.0).then_some((wo, flags))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::TransportMode;
    use crate::mueller::StokesBasis;

    fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
        let (st, ct) = theta_deg.to_radians().sin_cos();
        let (sp, cp) = phi_deg.to_radians().sin_cos();
        Vec3::new(st * cp, st * sp, ct)
    }

    #[test]
    fn m00_is_eval_bit_for_bit_in_both_modes() {
        let wl = SampledWavelengths::fixed(550.0);
        let m = PPlastic::default();
        for mode in [TransportMode::Radiance, TransportMode::Importance] {
            let ctx = BsdfContext {
                mode,
                ..BsdfContext::radiance()
            };
            for (a, b) in [(10.0, 20.0), (60.0, 55.0), (0.0, 80.0), (75.0, 3.0)] {
                let (wi, wo) = (dir(a, 15.0), dir(b, 200.0));
                let f = m.eval(&ctx, wi, wo, &wl);
                let mm = m.eval_mueller(&ctx, wi, wo, &wl);
                assert_eq!(mm.get(0, 0), f);
                let (li, lo) = light_directions(&ctx, wi, wo);
                let (i, o) = mm.frames().expect("polarizing");
                assert!(i.same_as(&StokesBasis::implicit(li)) && o.same_as(&StokesBasis::implicit(lo)));
            }
        }
    }

    /// The diffuse lobe alone, in the plane of incidence (φ = 0, so the implicit and s/p bases
    /// coincide up to sign): unpolarized light leaves with the degree of polarization
    /// |t(μo)| = (T_p − T_s)/(T_p + T_s), p-polarized, as the closed form says.
    #[test]
    fn diffuse_lobe_leaves_p_polarized_by_the_exit_refraction() {
        let wl = SampledWavelengths::fixed(550.0);
        let eta = 1.5;
        let m = PPlastic::new(
            Spectrum::Constant(0.8),
            Spectrum::Constant(1.0),
            MicrofacetDistribution::isotropic(MicrofacetKind::Beckmann, 0.1),
            eta,
        );
        let ctx = BsdfContext::radiance().with_lobes(BsdfFlags::DIFFUSE_REFLECTION);
        let (wi, wo) = (dir(70.0, 0.0), dir(20.0, 180.0));
        let mm = m.eval_mueller(&ctx, wi, wo, &wl);
        let dop = |m: &Mueller| {
            let (s0, s1, s2) = (m.get(0, 0)[0], m.get(1, 0)[0], m.get(2, 0)[0]);
            (s1 * s1 + s2 * s2).sqrt() / s0
        };
        // Closed form of the Fresnel transmittances at the exit (light leaves along wi, θ = 70°).
        let (ci, si) = (70f32.to_radians().cos(), 70f32.to_radians().sin());
        let ct = (1.0 - si * si / (eta * eta)).sqrt();
        let rs = ((ci - eta * ct) / (ci + eta * ct)).powi(2);
        let rp = ((eta * ci - ct) / (eta * ci + ct)).powi(2);
        let want = ((1.0 - rp) - (1.0 - rs)) / ((1.0 - rp) + (1.0 - rs));
        assert!((dop(&mm) - want).abs() < 1e-5, "{} vs {want}", dop(&mm));
        // And the p-direction: in the s/p basis of the exit the Stokes S1 is negative.
        let sp = mm.in_bases(
            StokesBasis::perpendicular_to_plane(-wo, Vec3::Z, Vec3::X),
            StokesBasis::perpendicular_to_plane(wi, Vec3::Z, Vec3::X),
        );
        assert!(sp.get(1, 0)[0] < 0.0 && (sp.get(1, 0)[0] / sp.get(0, 0)[0] + want).abs() < 1e-5);
        // At normal exit the diffuse light is unpolarized.
        let n = m.eval_mueller(&ctx, Vec3::Z, wo, &wl);
        assert!(n.get(1, 0)[0].abs() < 1e-6 && n.get(2, 0)[0].abs() < 1e-6);
    }

    /// The specular lobe alone at the Brewster configuration (ωi·h at Brewster's angle): the
    /// reflected light of unpolarized input is fully s-polarized.
    #[test]
    fn specular_lobe_at_brewster_is_fully_polarized() {
        let wl = SampledWavelengths::fixed(550.0);
        let eta = 1.5f32;
        let m = PPlastic::new(
            Spectrum::Constant(0.5),
            Spectrum::Constant(1.0),
            MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.2),
            eta,
        );
        let ctx = BsdfContext::radiance().with_lobes(BsdfFlags::GLOSSY_REFLECTION);
        let b = eta.atan().to_degrees();
        let (wi, wo) = (dir(b, 0.0), dir(b, 180.0));
        let mm = m.eval_mueller(&ctx, wi, wo, &wl);
        let (s0, s1, s2) = (mm.get(0, 0)[0], mm.get(1, 0)[0], mm.get(2, 0)[0]);
        assert!(s0 > 0.0);
        assert!(
            ((s1 * s1 + s2 * s2).sqrt() / s0 - 1.0).abs() < 1e-4,
            "{s0} {s1} {s2}"
        );
    }

    #[test]
    fn sample_mueller_matches_sample() {
        let m = PPlastic::default();
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(600.0);
        for (k, u1) in [0.1f32, 0.5, 0.9].into_iter().enumerate() {
            let wi = dir(20.0 + 20.0 * k as f32, 40.0);
            let u2 = Vec2::new(0.3, 0.7);
            let s = m.sample(&ctx, wi, u1, u2, &mut wl.clone()).unwrap();
            let p = m.sample_mueller(&ctx, wi, u1, u2, &mut wl.clone()).unwrap();
            assert_eq!((s.wo, s.pdf, s.flags), (p.wo, p.pdf, p.flags));
            assert_eq!(p.weight.get(0, 0), s.weight);
        }
    }
}
