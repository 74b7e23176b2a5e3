//! `principled`: the Disney BSDF (Burley 2012, "Physically Based Shading at Disney"; Burley 2015,
//! "Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering") as Mitsuba 3
//! implements it (`src/bsdfs/principled.cpp`, helpers in `principledhelpers.h`; the shared
//! pieces are in [`super::principled_common`]).
//!
//! With the lobe weights w_brdf = (1 − metallic)(1 − spec_trans), w_bsdf = (1 − metallic)
//! spec_trans, the GGX distribution D, G of roughness (α_x, α_y) =
//! [`ggx_alphas`]`(roughness, anisotropic)`, the half vector h (of the reflection, or of the
//! refraction ωi + η ωo, turned to +z), the dielectric Fresnel F of η at ωi·h, and c the
//! base colour:
//!
//! ```text
//!   f = F_p D G / (4 |cos θi| |cos θo|)                                   main specular
//!     + w_bsdf √c (1 − F) D G η² |ωi·h| |ωo·h| s / (|cos θi| |cos θo| (ωi·h + η ωo·h)²)
//!                                                   main transmission, s = 1/η² (radiance), 1
//!     + clearcoat/4 · F_s(0.04) D_GTR1 G_cc                                 clearcoat
//!     + w_brdf c/π · lerp(f_diffuse + f_retro, f_ss, flatness)             diffuse, retro, "subsurface"
//!     + (1 − metallic) f_sheen                                             sheen (where w_brdf > 0)
//! ```
//!
//! F_p, outside: (1 − metallic)(1 − spec_tint) F + metallic F_s(c) + (1 − metallic) spec_tint
//! F_s(C_tint R0(η)), with F_s Schlick's approximation; inside: w_bsdf F. The clearcoat, diffuse
//! and sheen lobes exist outside only; inside, light meets the main specular reflection and
//! transmission. The clearcoat keeps Mitsuba's form: its value has no 1/(4 cos θi cos θo).
//!
//! Sampling picks a lobe with probability ∝ (w_brdf r_d, clearcoat r_c/4, r_s w_bsdf (1 − F),
//! r_s (1 − w_bsdf (1 − F))) outside (diffuse, clearcoat, transmission, reflection; r the
//! sampling rates) and (0, 0, 1 − F, F) inside, with F at the sampled visible GGX normal; the
//! diffuse lobe is sampled cosine-weighted, the clearcoat by GTR1 normals; pdf is the mixture.
//! Inside a material with no transmission (w_bsdf = 0: `spec_trans` 0 or `metallic` 1) f is
//! zero and so is our pdf, where Mitsuba 3.9.1's `pdf` keeps the reflection's density
//! D_vis/(4 |wo·h|): it samples nothing there either (no image differs), but its pdf is not 0.
//!
//! Energy: not conserved (Burley's model is artistic). Inside, the reflection is scaled by w_bsdf
//! and the transmission by w_bsdf √c, so light inside a part-metallic or part-diffuse material
//! loses energy at each crossing (Mitsuba issue 465); the figures are stated in the tests.
//!
//! Mitsuba 3 plugin `principled` (every parameter a float or a texture unless stated; the
//! documented range of all but `eta` and the rates is [0, 1]):
//!
//! | parameter            | default | meaning                                                   |
//! |----------------------|---------|-----------------------------------------------------------|
//! | `base_color`         | 0.5     | c (spectrum or texture)                                   |
//! | `roughness`          | 0.5     | r of the main lobes (α = r²) and of the retro-reflection  |
//! | `anisotropic`        | 0       | aspect of α_x/α_y                                         |
//! | `metallic`           | 0       | blend towards a Schlick metal of colour c                 |
//! | `spec_trans`         | 0       | blend of the BRDF towards the rough dielectric BSDF       |
//! | `eta`                | 1.5     | η = n_int/n_ext (float; exclusive with `specular`)        |
//! | `specular`           | 0.5     | η = 2/(1 − √(0.08 specular)) − 1 (float)                  |
//! | `spec_tint`          | 0       | tint of the dielectric reflection towards c               |
//! | `sheen`, `sheen_tint`| 0, 0    | the sheen lobe and its tint                               |
//! | `flatness`           | 0       | blend of diffuse + retro towards the fake subsurface      |
//! | `clearcoat`          | 0       | weight of the clearcoat                                   |
//! | `clearcoat_gloss`    | 0       | its gloss: α_cc = 0.1 … 0.001                             |
//! | `main_specular_sampling_rate` | 1 | r_s (float)                                           |
//! | `clearcoat_sampling_rate`     | 1 | r_c (float; Mitsuba's docs say 0, its code uses 1)    |
//! | `diffuse_reflectance_sampling_rate` | 1 | r_d (float)                                     |
//!
//! With `spec_trans` present, η = 1 becomes 1.001 and `specular` = 0 becomes 10⁻³ (Mitsuba).

use super::principled_common::{
    Gtr1, choose_lobe, diffuse_shape, facet_compatible, ggx_alphas, reflect_about, refract_through,
    schlick_fresnel, schlick_fresnel_spectrum, schlick_r0, sheen_shape, smith_ggx1, tint_color,
    tint_luminance,
};
use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, TransportMode};
use crate::fresnel::fresnel_dielectric;
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// The lobe-selection rates of `principled` (Mitsuba's `*_sampling_rate`; 1 each by default).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipledRates {
    /// `diffuse_reflectance_sampling_rate`.
    pub diffuse: f32,
    /// `main_specular_sampling_rate`.
    pub main_specular: f32,
    /// `clearcoat_sampling_rate`.
    pub clearcoat: f32,
}

impl Default for PrincipledRates {
    fn default() -> Self {
        Self {
            diffuse: 1.0,
            main_specular: 1.0,
            clearcoat: 1.0,
        }
    }
}

/// The Disney principled BSDF (see the module docs for the formula and parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principled<S = Spectrum> {
    /// c, the base colour.
    pub base_color: S,
    /// r ∈ [0, 1].
    pub roughness: f32,
    /// Anisotropy ∈ [0, 1] (α_x along the shading frame's x, the tangent, is the larger).
    pub anisotropic: f32,
    /// Metallic blend ∈ [0, 1].
    pub metallic: f32,
    /// Transmission blend ∈ [0, 1].
    pub spec_trans: f32,
    /// η = n_int/n_ext (> 0, ≠ 1 with transmission).
    pub eta: f32,
    /// Tint of the dielectric reflection ∈ [0, 1].
    pub spec_tint: f32,
    /// Sheen weight.
    pub sheen: f32,
    /// Sheen tint ∈ [0, 1].
    pub sheen_tint: f32,
    /// Fake-subsurface blend ∈ [0, 1].
    pub flatness: f32,
    /// Clearcoat weight.
    pub clearcoat: f32,
    /// Clearcoat gloss ∈ [0, 1].
    pub clearcoat_gloss: f32,
    /// Lobe-selection rates.
    pub rates: PrincipledRates,
}

impl Default for Principled {
    /// Mitsuba's defaults: c = 0.5, r = 0.5, `specular` 0.5 (η = 1.5), everything else 0.
    fn default() -> Self {
        Self::new(Spectrum::Constant(0.5))
    }
}

impl Principled {
    /// Mitsuba's defaults with base colour `base_color`.
    pub fn new(base_color: Spectrum) -> Self {
        Self {
            base_color,
            roughness: 0.5,
            anisotropic: 0.0,
            metallic: 0.0,
            spec_trans: 0.0,
            eta: eta_from_specular(0.5),
            spec_tint: 0.0,
            sheen: 0.0,
            sheen_tint: 0.0,
            flatness: 0.0,
            clearcoat: 0.0,
            clearcoat_gloss: 0.0,
            rates: PrincipledRates::default(),
        }
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> Principled<SampledSpectrum> {
        Principled {
            base_color: self.base_color.sample(wl),
            roughness: self.roughness,
            anisotropic: self.anisotropic,
            metallic: self.metallic,
            spec_trans: self.spec_trans,
            eta: self.eta,
            spec_tint: self.spec_tint,
            sheen: self.sheen,
            sheen_tint: self.sheen_tint,
            flatness: self.flatness,
            clearcoat: self.clearcoat,
            clearcoat_gloss: self.clearcoat_gloss,
            rates: self.rates,
        }
    }
}

/// η of Mitsuba's `specular` parameter: 2/(1 − √(0.08 specular)) − 1 (the inverse of
/// specular = R0(η)/0.08).
pub fn eta_from_specular(specular: f32) -> f32 {
    2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
}

/// The unnormalized lobe probabilities (diffuse, clearcoat, transmission, reflection) for a
/// query from side `front` with dielectric reflectance `f` at the facet, only the lobes `ctx`
/// enables.
#[inline]
fn lobe_probs(
    rates: &PrincipledRates,
    ctx: &BsdfContext,
    front: bool,
    f: f32,
    w_brdf: f32,
    w_bsdf: f32,
    clearcoat: f32,
) -> [f32; 4] {
    let en = |l: BsdfFlags| if ctx.is_enabled(l) { 1.0 } else { 0.0 };
    let (g_r, g_t, d_r) = (
        en(BsdfFlags::GLOSSY_REFLECTION),
        en(BsdfFlags::GLOSSY_TRANSMISSION),
        en(BsdfFlags::DIFFUSE_REFLECTION),
    );
    if front {
        [
            d_r * w_brdf * rates.diffuse,
            g_r * 0.25 * clearcoat * rates.clearcoat,
            g_t * rates.main_specular * w_bsdf * (1.0 - f),
            g_r * rates.main_specular * (1.0 - w_bsdf * (1.0 - f)),
        ]
    } else if w_bsdf > 0.0 {
        [0.0, 0.0, g_t * (1.0 - f), g_r * f]
    } else {
        [0.0; 4]
    }
}

impl<S: SpectralValue> Principled<S> {
    /// The main lobes' GGX distribution (visible normals).
    #[inline]
    fn spec_distribution(&self) -> MicrofacetDistribution {
        let (ax, ay) = ggx_alphas(self.roughness, self.anisotropic);
        MicrofacetDistribution::new(MicrofacetKind::Ggx, ax, ay, true)
    }

    /// (w_brdf, w_bsdf).
    #[inline]
    fn weights(&self) -> (f32, f32) {
        let dm = 1.0 - self.metallic;
        (dm * (1.0 - self.spec_trans), dm * self.spec_trans)
    }

    /// The half vector of (wi, wo), of the reflection (ωi + ωo) or the refraction (ω_ext +
    /// η ω_int, the same direction as Mitsuba's ωi + η_path ωo, written so that (wi, wo) and
    /// (wo, wi) round alike), turned to +z; and |ωi + η_path ωo|² for a refraction.
    #[inline]
    fn half_vector(&self, wi: Vec3, wo: Vec3, reflect: bool) -> (Vec3, f32) {
        if reflect {
            let h = (wi + wo).normalize();
            return (if h.z < 0.0 { -h } else { h }, 0.0);
        }
        let (ext, int) = if wi.z > 0.0 { (wi, wo) } else { (wo, wi) };
        let sum = ext + int * self.eta;
        let len2 = sum.length_squared();
        let h = sum / len2.sqrt();
        let denom2 = if wi.z > 0.0 {
            len2
        } else {
            len2 / (self.eta * self.eta)
        };
        (if h.z < 0.0 { -h } else { h }, denom2)
    }

    /// f·|cos θo| (Mitsuba's `eval`) and the pdf, the lobes of `ctx`.
    fn eval_pdf_cos(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        let (ci, co) = (wi.z, wo.z);
        let (reflect, refract) = (ci * co > 0.0, ci * co < 0.0);
        if ci == 0.0 || !(reflect || refract) {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let front = ci > 0.0;
        let (w_brdf, w_bsdf) = self.weights();
        let eta_path = if front { self.eta } else { 1.0 / self.eta };
        let (h, denom2) = self.half_vector(wi, wo, reflect);
        if !h.is_finite() {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let (cos_ih, cos_oh) = (wi.dot(h), wo.dot(h));
        // Mitsuba's F at ωi·h, written symmetrically in (ωi, ωo), so that rounding keeps values
        // reciprocal and the pdf isotropic near total internal reflection, where F is steep: a
        // reflection at the mean of ωi·h and ωo·h (equal but for rounding), a refraction at the
        // facet cosine on the exterior side (the same F from either side).
        let cos_f = if reflect {
            0.5 * (cos_ih + cos_oh)
        } else if front {
            cos_ih
        } else {
            cos_oh
        };
        let f_val = fresnel_dielectric(cos_f, self.eta).reflectance;
        // denom2 = (ωi·h + η_path ωo·h)² = |ωi + η_path ωo|² for a refraction, without cancellation.
        let refl_ok = reflect && facet_compatible(h, wi, wo, ci, true);
        let refr_ok = refract && facet_compatible(h, wi, wo, ci, false);
        let distr = self.spec_distribution();
        let (d, g) = (distr.d(h), distr.g(wi, wo, h));
        let c = self.base_color.sample(wl);
        let (en_gr, en_gt, en_dr) = (
            ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION),
            ctx.is_enabled(BsdfFlags::GLOSSY_TRANSMISSION),
            ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION),
        );
        let mut value = SampledSpectrum::ZERO;
        let lum = if self.spec_tint != 0.0 || self.sheen_tint != 0.0 {
            tint_luminance(c, wl)
        } else {
            1.0
        };

        // Main specular reflection.
        if en_gr && refl_ok && f_val > 0.0 {
            let fp = if front {
                let outside = cos_f >= 0.0;
                let eta_it = if outside { self.eta } else { 1.0 / self.eta };
                let mut f_s = SampledSpectrum::ZERO;
                if self.metallic != 0.0 {
                    f_s += schlick_fresnel_spectrum(c, cos_f, self.eta) * self.metallic;
                }
                if self.spec_tint != 0.0 {
                    let r0 = tint_color(c, lum) * schlick_r0(eta_it);
                    f_s += schlick_fresnel_spectrum(r0, cos_f, self.eta)
                        * ((1.0 - self.metallic) * self.spec_tint);
                }
                f_s + SampledSpectrum::splat((1.0 - self.metallic) * (1.0 - self.spec_tint) * f_val)
            } else {
                SampledSpectrum::splat(w_bsdf * f_val)
            };
            value += fp * (d * g / (4.0 * ci.abs()));
        }
        // Main specular transmission.
        if en_gt && w_bsdf > 0.0 && refr_ok && f_val < 1.0 {
            let scale = match ctx.mode {
                TransportMode::Radiance => 1.0 / (eta_path * eta_path),
                TransportMode::Importance => 1.0,
            };
            let t =
                (scale * (1.0 - f_val) * d * g * eta_path * eta_path * cos_ih * cos_oh / (ci * denom2)).abs();
            value += c.sqrt() * (w_bsdf * t);
        }
        if front && reflect {
            // Clearcoat.
            if en_gr && self.clearcoat > 0.0 && refl_ok {
                let fcc = schlick_fresnel(0.04, cos_f, self.eta);
                let dcc = Gtr1::from_gloss(self.clearcoat_gloss).d(h);
                let gcc = smith_ggx1(wi, h, 0.25) * smith_ggx1(wo, h, 0.25);
                value += SampledSpectrum::splat(self.clearcoat * 0.25 * fcc * dcc * gcc * co.abs());
            }
            // Diffuse, retro-reflection, fake subsurface, sheen.
            if en_dr && w_brdf > 0.0 {
                let shape = diffuse_shape(ci, co, cos_oh, self.roughness, self.flatness);
                value += c * (w_brdf * co.abs() * FRAC_1_PI * shape);
                if self.sheen > 0.0 && 1.0 - self.metallic > 0.0 {
                    let tint = if self.sheen_tint != 0.0 {
                        tint_color(c, lum)
                    } else {
                        SampledSpectrum::ONE
                    };
                    value += sheen_shape(cos_oh, self.sheen_tint, tint)
                        * (self.sheen * (1.0 - self.metallic) * co.abs());
                }
            }
        }

        // The pdf of `sample`.
        let probs = lobe_probs(&self.rates, ctx, front, f_val, w_brdf, w_bsdf, self.clearcoat);
        let total: f32 = probs.iter().sum();
        if total.is_nan() || total <= 0.0 {
            return (value, 0.0);
        }
        let [p_d, p_cc, p_t, p_r] = probs.map(|p| p / total);
        let dwh_dwo = if reflect {
            (1.0 / (4.0 * cos_oh)).abs()
        } else {
            (eta_path * eta_path * cos_oh / denom2).abs()
        };
        let wi_up = if front { wi } else { -wi };
        let mut pdf = 0.0;
        if refl_ok {
            pdf += p_r * distr.pdf(wi_up, h) * dwh_dwo;
            if p_cc > 0.0 {
                pdf += p_cc * Gtr1::from_gloss(self.clearcoat_gloss).pdf(h) * dwh_dwo;
            }
        }
        if reflect {
            pdf += p_d * square_to_cosine_hemisphere_pdf(wo);
        }
        if refr_ok {
            pdf += p_t * distr.pdf(wi_up, h) * dwh_dwo;
        }
        (value, if pdf.is_finite() { pdf } else { 0.0 })
    }
}

impl<S: SpectralValue> Bsdf for Principled<S> {
    fn flags(&self) -> BsdfFlags {
        let mut f = BsdfFlags::DIFFUSE_REFLECTION | BsdfFlags::GLOSSY_REFLECTION;
        if self.spec_trans > 0.0 {
            f = f | BsdfFlags::GLOSSY_TRANSMISSION | BsdfFlags::NON_SYMMETRIC;
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
        let ci = wi.z;
        if ci == 0.0 {
            return None;
        }
        let front = ci > 0.0;
        let (w_brdf, w_bsdf) = self.weights();
        let distr = self.spec_distribution();
        let wi_up = if front { wi } else { -wi };
        let (m, _) = distr.sample(wi_up, u2);
        let fres = fresnel_dielectric(wi.dot(m), self.eta);
        let probs = lobe_probs(
            &self.rates,
            ctx,
            front,
            fres.reflectance,
            w_brdf,
            w_bsdf,
            self.clearcoat,
        );
        let lobe = choose_lobe(probs, u1)?;
        let (wo, flags, eta) = match lobe {
            0 => {
                let wo = square_to_cosine_hemisphere(u2);
                (wo, BsdfFlags::DIFFUSE_REFLECTION, 1.0)
            }
            1 => {
                let m_cc = Gtr1::from_gloss(self.clearcoat_gloss).sample(u2);
                let wo = reflect_about(wi, m_cc).normalize();
                if !facet_compatible(m_cc, wi, wo, ci, true) {
                    return None;
                }
                (wo, BsdfFlags::GLOSSY_REFLECTION, 1.0)
            }
            2 => {
                let wo = refract_through(wi, m, fres.cos_theta_t, fres.eta_ti).normalize();
                if !facet_compatible(m, wi, wo, ci, false) || ci * wo.z >= 0.0 {
                    return None;
                }
                (wo, BsdfFlags::GLOSSY_TRANSMISSION, fres.eta_it)
            }
            _ => {
                let wo = reflect_about(wi, m).normalize();
                if !facet_compatible(m, wi, wo, ci, true) {
                    return None;
                }
                (wo, BsdfFlags::GLOSSY_REFLECTION, 1.0)
            }
        };
        if ci * wo.z == 0.0 || (flags.is_reflection() && ci * wo.z < 0.0) {
            return None;
        }
        let (v, pdf) = self.eval_pdf_cos(ctx, wi, wo, wl);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: v / pdf,
            pdf,
            flags,
            eta,
        })
    }
}

#[path = "principled_lanes.rs"]
mod lanes;
pub use lanes::PrincipledLanes;

#[cfg(test)]
#[path = "principled_tests.rs"]
mod tests;
