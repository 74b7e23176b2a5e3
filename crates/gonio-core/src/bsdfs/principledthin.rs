//! `principledthin`: the thin-surface variant of the Disney BSDF (Burley 2015, "Extending the
//! Disney BRDF to a BSDF with Integrated Subsurface Scattering", §4) as Mitsuba 3 implements it
//! (`src/bsdfs/principledthin.cpp`; shared pieces in [`super::principled_common`]).
//!
//! A sheet with no inside: both sides behave alike (ωi is turned to +z, ωo with it), light
//! leaves without bending (η of the sheet only shapes F and the transmission roughness). With
//! s = spec_trans, t = diff_trans/2, c the base colour, the half vector h of ωi and ωo mirrored
//! to ωi's side, and F the dielectric Fresnel of η at ωi·h:
//!
//! ```text
//!   f = s F_t D G / (4 cos θi cos θo)                         specular reflection (GGX, r)
//!     + s c (1 − F) D' G' / (4 cos θi |cos θo|)                specular transmission (GGX, r')
//!     + (1 − s)(1 − t) c/π lerp(f_diffuse + f_retro, f_ss, flatness)    diffuse reflection
//!     + (1 − s)(1 − t) f_sheen                                 sheen
//!     + (1 − s) t c/π                                          diffuse transmission
//! ```
//!
//! F_t = lerp(F, F_s(C_tint R0(η)), spec_tint) (Schlick); the transmission's roughness is scaled
//! by the index, r' = (0.65 η − 0.35) r (Burley 2015, fig. 15); the diffuse family and sheen
//! are [`super::principled_common`]'s. Sampling picks a lobe with probability ∝ (s r_sr/2,
//! s r_st/2, (1 − s)(1 − t) r_dr, (1 − s) t r_dt): visible GGX normals, reflected (and mirrored
//! through the sheet for the transmission), or cosine-weighted on either side.
//!
//! Mitsuba 3 plugin `principledthin` (floats or textures unless stated; all but `eta`,
//! `diff_trans` and the rates in [0, 1]):
//!
//! | parameter            | default | meaning                                                   |
//! |----------------------|---------|-----------------------------------------------------------|
//! | `base_color`         | 0.5     | c (spectrum or texture)                                   |
//! | `roughness`          | 0.5     | r (α = r², at least 10⁻³)                                 |
//! | `anisotropic`        | 0       | aspect of α_x/α_y                                         |
//! | `spec_trans`         | 0       | s, blend of the diffuse towards the specular response     |
//! | `eta`                | 1.5     | η of the sheet                                            |
//! | `spec_tint`          | 0       | tint of the specular reflection towards c                 |
//! | `sheen`, `sheen_tint`| 0, 0    | the sheen lobe and its tint                               |
//! | `flatness`           | 0       | blend of diffuse + retro towards the fake subsurface      |
//! | `diff_trans`         | 0       | ∈ [0, 2]: share of the diffuse response transmitted (2 t) |
//! | `diffuse_reflectance_sampling_rate`    | 1 | r_dr (float)                             |
//! | `specular_reflectance_sampling_rate`   | 1 | r_sr (float)                             |
//! | `specular_transmittance_sampling_rate` | 1 | r_st (float)                             |
//! | `diffuse_transmittance_sampling_rate`  | 1 | r_dt (float)                             |

use super::principled_common::{
    choose_lobe, diffuse_shape, facet_compatible, ggx_alphas, reflect_about, schlick_fresnel_spectrum,
    schlick_r0, sheen_shape, tint_color, tint_luminance,
};
use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::fresnel::fresnel_dielectric;
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// The lobe-selection rates of `principledthin` (1 each by default).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipledThinRates {
    /// `diffuse_reflectance_sampling_rate`.
    pub diffuse_reflectance: f32,
    /// `specular_reflectance_sampling_rate`.
    pub specular_reflectance: f32,
    /// `specular_transmittance_sampling_rate`.
    pub specular_transmittance: f32,
    /// `diffuse_transmittance_sampling_rate`.
    pub diffuse_transmittance: f32,
}

impl Default for PrincipledThinRates {
    fn default() -> Self {
        Self {
            diffuse_reflectance: 1.0,
            specular_reflectance: 1.0,
            specular_transmittance: 1.0,
            diffuse_transmittance: 1.0,
        }
    }
}

/// The thin Disney BSDF (see the module docs for the formula and parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipledThin<S = Spectrum> {
    /// c, the base colour.
    pub base_color: S,
    /// r ∈ [0, 1].
    pub roughness: f32,
    /// Anisotropy ∈ [0, 1].
    pub anisotropic: f32,
    /// s ∈ [0, 1].
    pub spec_trans: f32,
    /// η of the sheet (> 0).
    pub eta: f32,
    /// Specular tint ∈ [0, 1].
    pub spec_tint: f32,
    /// Sheen weight.
    pub sheen: f32,
    /// Sheen tint ∈ [0, 1].
    pub sheen_tint: f32,
    /// Fake-subsurface blend ∈ [0, 1].
    pub flatness: f32,
    /// Mitsuba's `diff_trans` ∈ [0, 2] (t = diff_trans/2 of the diffuse response is transmitted).
    pub diff_trans: f32,
    /// Lobe-selection rates.
    pub rates: PrincipledThinRates,
}

impl Default for PrincipledThin {
    /// Mitsuba's defaults: c = 0.5, r = 0.5, η = 1.5, everything else 0.
    fn default() -> Self {
        Self::new(Spectrum::Constant(0.5))
    }
}

impl PrincipledThin {
    /// Mitsuba's defaults with base colour `base_color`.
    pub fn new(base_color: Spectrum) -> Self {
        Self {
            base_color,
            roughness: 0.5,
            anisotropic: 0.0,
            spec_trans: 0.0,
            eta: 1.5,
            spec_tint: 0.0,
            sheen: 0.0,
            sheen_tint: 0.0,
            flatness: 0.0,
            diff_trans: 0.0,
            rates: PrincipledThinRates::default(),
        }
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> PrincipledThin<SampledSpectrum> {
        PrincipledThin {
            base_color: self.base_color.sample(wl),
            roughness: self.roughness,
            anisotropic: self.anisotropic,
            spec_trans: self.spec_trans,
            eta: self.eta,
            spec_tint: self.spec_tint,
            sheen: self.sheen,
            sheen_tint: self.sheen_tint,
            flatness: self.flatness,
            diff_trans: self.diff_trans,
            rates: self.rates,
        }
    }
}

impl<S: SpectralValue> PrincipledThin<S> {
    /// The reflection's GGX and the transmission's, of roughness (0.65 η − 0.35) r.
    #[inline]
    fn distributions(&self) -> (MicrofacetDistribution, MicrofacetDistribution) {
        let (ax, ay) = ggx_alphas(self.roughness, self.anisotropic);
        let r_t = (0.65 * self.eta - 0.35) * self.roughness;
        let (tx, ty) = ggx_alphas(r_t, self.anisotropic);
        (
            MicrofacetDistribution::new(MicrofacetKind::Ggx, ax, ay, true),
            MicrofacetDistribution::new(MicrofacetKind::Ggx, tx, ty, true),
        )
    }

    /// The unnormalized probabilities (specular reflection, specular transmission, diffuse
    /// reflection, diffuse transmission) of the lobes `ctx` enables.
    #[inline]
    fn probs(&self, ctx: &BsdfContext) -> [f32; 4] {
        let en = |l: BsdfFlags| if ctx.is_enabled(l) { 1.0 } else { 0.0 };
        let (s, t, r) = (self.spec_trans, 0.5 * self.diff_trans, &self.rates);
        [
            en(BsdfFlags::GLOSSY_REFLECTION) * s * r.specular_reflectance * 0.5,
            en(BsdfFlags::GLOSSY_TRANSMISSION) * s * r.specular_transmittance * 0.5,
            en(BsdfFlags::DIFFUSE_REFLECTION) * r.diffuse_reflectance * (1.0 - s) * (1.0 - t),
            en(BsdfFlags::DIFFUSE_TRANSMISSION) * r.diffuse_transmittance * (1.0 - s) * t,
        ]
    }

    /// f·|cos θo| (Mitsuba's `eval`) and the pdf, the lobes of `ctx`.
    fn eval_pdf_cos(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        if wi.z == 0.0 || wo.z == 0.0 {
            return (SampledSpectrum::ZERO, 0.0);
        }
        // The sheet is the same from both sides: turn ωi to +z and ωo with it.
        let flip = if wi.z < 0.0 { -1.0 } else { 1.0 };
        let (wi, wo) = (wi * flip, wo * flip);
        let (ci, co) = (wi.z, wo.z);
        let reflect = co > 0.0;
        let wo_r = Vec3::new(wo.x, wo.y, co.abs());
        let h = (wi + wo_r).normalize();
        if !h.is_finite() {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let (s, t) = (self.spec_trans, 0.5 * self.diff_trans);
        let (distr_r, distr_t) = self.distributions();
        let refl_ok = reflect && facet_compatible(h, wi, wo, ci, true);
        let refr_ok = !reflect && facet_compatible(h, wi, wo, ci, false);
        let c = self.base_color.sample(wl);
        let lum = if self.spec_tint != 0.0 || self.sheen_tint != 0.0 {
            tint_luminance(c, wl)
        } else {
            1.0
        };
        let cos_ih = wi.dot(h);
        let mut value = SampledSpectrum::ZERO;
        if s > 0.0 && (refl_ok || refr_ok) {
            let fr = fresnel_dielectric(cos_ih, self.eta).reflectance;
            if refl_ok && ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) {
                let mut f_t = SampledSpectrum::splat(fr);
                if self.spec_tint != 0.0 {
                    let r0 = tint_color(c, lum) * schlick_r0(self.eta);
                    let f_s = schlick_fresnel_spectrum(r0, cos_ih, self.eta);
                    f_t = f_t + (f_s - f_t) * self.spec_tint;
                }
                let dg = distr_r.d(h) * distr_r.g(wi, wo, h);
                value += f_t * (s * dg / (4.0 * ci));
            }
            if refr_ok && ctx.is_enabled(BsdfFlags::GLOSSY_TRANSMISSION) {
                let dg = distr_t.d(h) * distr_t.g(wi, wo, h);
                value += c * (s * (1.0 - fr) * dg / (4.0 * ci));
            }
        }
        let cos_d = h.dot(wo);
        if reflect && s < 1.0 && t < 1.0 && ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) {
            let shape = diffuse_shape(ci, co, cos_d, self.roughness, self.flatness);
            value += c * ((1.0 - s) * co * FRAC_1_PI * (1.0 - t) * shape);
            if self.sheen > 0.0 {
                let tint = if self.sheen_tint != 0.0 {
                    tint_color(c, lum)
                } else {
                    SampledSpectrum::ONE
                };
                value +=
                    sheen_shape(cos_d, self.sheen_tint, tint) * (self.sheen * (1.0 - s) * (1.0 - t) * co);
            }
        }
        if !reflect && s < 1.0 && t > 0.0 && ctx.is_enabled(BsdfFlags::DIFFUSE_TRANSMISSION) {
            value += c * ((1.0 - s) * t * FRAC_1_PI * co.abs());
        }

        let probs = self.probs(ctx);
        let total: f32 = probs.iter().sum();
        if total.is_nan() || total <= 0.0 {
            return (value, 0.0);
        }
        let [p_sr, p_st, p_dr, p_dt] = probs.map(|p| p / total);
        let dwh_dwo = (1.0 / (4.0 * wo_r.dot(h))).abs();
        let mut pdf = 0.0;
        if refl_ok && p_sr > 0.0 {
            pdf += p_sr * distr_r.pdf(wi, h) * dwh_dwo;
        }
        if refr_ok && p_st > 0.0 {
            pdf += p_st * distr_t.pdf(wi, h) * dwh_dwo;
        }
        if reflect {
            pdf += p_dr * square_to_cosine_hemisphere_pdf(wo);
        } else {
            pdf += p_dt * square_to_cosine_hemisphere_pdf(-wo);
        }
        (value, if pdf.is_finite() { pdf } else { 0.0 })
    }
}

impl<S: SpectralValue> Bsdf for PrincipledThin<S> {
    fn flags(&self) -> BsdfFlags {
        let mut f = BsdfFlags::DIFFUSE_REFLECTION | BsdfFlags::GLOSSY_REFLECTION;
        if self.spec_trans > 0.0 {
            f = f | BsdfFlags::GLOSSY_TRANSMISSION;
        }
        if self.diff_trans > 0.0 {
            f = f | BsdfFlags::DIFFUSE_TRANSMISSION;
        }
        if self.anisotropic != 0.0 {
            f = f | BsdfFlags::ANISOTROPIC;
        }
        f
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
        let (v, pdf) = self.eval_pdf_cos(ctx, wi, wo, wl);
        if v.is_black() {
            return (SampledSpectrum::ZERO, pdf);
        }
        (v / wo.z.abs(), pdf)
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let flip = if wi.z < 0.0 { -1.0 } else { 1.0 };
        let wi_f = wi * flip;
        let lobe = choose_lobe(self.probs(ctx), u1)?;
        let (distr_r, distr_t) = self.distributions();
        let (wo_f, flags) = match lobe {
            0 | 1 => {
                let distr = if lobe == 0 { distr_r } else { distr_t };
                let (m, _) = distr.sample(wi_f, u2);
                let mut wo = reflect_about(wi_f, m).normalize();
                if lobe == 1 {
                    wo.z = -wo.z;
                }
                let reflection = lobe == 0;
                if !facet_compatible(m, wi_f, wo, wi_f.z, reflection) || (wo.z > 0.0) != reflection {
                    return None;
                }
                let kind = if reflection {
                    BsdfFlags::GLOSSY_REFLECTION
                } else {
                    BsdfFlags::GLOSSY_TRANSMISSION
                };
                (wo, kind)
            }
            2 => (square_to_cosine_hemisphere(u2), BsdfFlags::DIFFUSE_REFLECTION),
            _ => (-square_to_cosine_hemisphere(u2), BsdfFlags::DIFFUSE_TRANSMISSION),
        };
        let wo = wo_f * flip;
        let (v, pdf) = self.eval_pdf_cos(ctx, wi, wo, wl);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: v / pdf,
            pdf,
            flags,
            eta: 1.0,
        })
    }
}

#[path = "principledthin_lanes.rs"]
mod lanes;
pub use lanes::PrincipledThinLanes;

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
        let (st, ct) = theta_deg.to_radians().sin_cos();
        let (sp, cp) = phi_deg.to_radians().sin_cos();
        Vec3::new(st * cp, st * sp, ct)
    }

    fn sheet() -> PrincipledThin {
        let mut p = PrincipledThin::new(Spectrum::Constant(0.7));
        p.roughness = 0.3;
        p.anisotropic = 0.4;
        p.spec_trans = 0.6;
        p.eta = 1.33;
        p.spec_tint = 0.2;
        p.sheen = 0.5;
        p.flatness = 0.3;
        p.diff_trans = 0.8;
        p
    }

    #[test]
    fn both_sides_are_alike_and_weights_are_eval_over_pdf() {
        let ctx = BsdfContext::radiance();
        let m = sheet();
        let wl = SampledWavelengths::fixed(550.0);
        let (a, b) = (dir(35.0, 20.0), dir(50.0, 210.0));
        for (wi, wo) in [(a, b), (a, -b)] {
            let front = m.eval_pdf(&ctx, wi, wo, &wl);
            let back = m.eval_pdf(&ctx, -wi, -wo, &wl);
            assert_eq!(front, back);
        }
        let mut kinds = BsdfFlags::NONE;
        for wi in [dir(0.0, 0.0), dir(60.0, 30.0), -dir(45.0, 100.0)] {
            for j in 0..128 {
                let mut wl = wl;
                let u2 = Vec2::new((j as f32 + 0.5) / 128.0, ((j * 53) % 128) as f32 / 128.0 + 0.003);
                let Some(s) = m.sample(&ctx, wi, ((j * 7) % 128) as f32 / 128.0, u2, &mut wl) else {
                    continue;
                };
                kinds = kinds | s.flags;
                let (f, pdf) = m.eval_pdf(&ctx, wi, s.wo, &wl);
                assert!((pdf / s.pdf - 1.0).abs() < 1e-5);
                let w = f[0] * s.wo.z.abs() / pdf;
                assert!(
                    (w - s.weight[0]).abs() <= 1e-4 * w.max(1e-3),
                    "{w} vs {}",
                    s.weight[0]
                );
                assert_eq!(s.eta, 1.0, "a thin sheet does not bend light");
            }
        }
        assert!(kinds.contains(
            BsdfFlags::GLOSSY_TRANSMISSION | BsdfFlags::DIFFUSE_TRANSMISSION | BsdfFlags::DIFFUSE_REFLECTION
        ));
    }

    #[test]
    fn zero_roughness_is_finite_and_not_black() {
        let ctx = BsdfContext::radiance();
        let mut m = sheet();
        m.roughness = 0.0;
        m.anisotropic = 0.0;
        for wi in [dir(0.0, 0.0), dir(60.0, 0.0), dir(89.0, 0.0), -dir(30.0, 0.0)] {
            let mut sum = 0.0;
            for j in 0..256 {
                let mut wl = SampledWavelengths::fixed(550.0);
                let u = Vec2::new((j as f32 + 0.5) / 256.0, ((j * 97) % 256) as f32 / 256.0 + 0.001);
                if let Some(s) = m.sample(&ctx, wi, ((j * 13) % 256) as f32 / 256.0, u, &mut wl) {
                    assert!(s.weight.is_finite() && s.pdf.is_finite(), "{s}");
                    sum += s.weight[0];
                }
            }
            assert!(sum > 0.0);
        }
    }

    #[test]
    fn pure_diffuse_transmission_is_lambertian() {
        // spec_trans 0, diff_trans 2 (t = 1): f = c/π on the far side, nothing on the near one.
        let mut m = PrincipledThin::new(Spectrum::Constant(0.6));
        m.diff_trans = 2.0;
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(550.0);
        let f = m.eval(&ctx, dir(30.0, 0.0), -dir(70.0, 120.0), &wl)[0];
        assert!((f - 0.6 * FRAC_1_PI).abs() < 1e-6, "{f}");
        assert_eq!(m.eval(&ctx, dir(30.0, 0.0), dir(70.0, 120.0), &wl)[0], 0.0);
    }
}
