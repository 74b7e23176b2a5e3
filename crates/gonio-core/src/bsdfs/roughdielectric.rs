//! `roughdielectric`: a rough interface between two dielectrics (ground or etched glass), single
//! scattering from a microfacet surface of smooth dielectric facets: reflection and refraction.
//!
//! Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces" (eqs. 20–21),
//! as Mitsuba 3 `src/bsdfs/roughdielectric.cpp`. With η the relative index seen from ωi's side
//! (η_it = n_int/n_ext when cos θi > 0, its reciprocal from inside), the distribution D and Smith
//! G of [`crate::microfacet`] and the dielectric Fresnel reflectance F(ωi·m):
//!
//! ```text
//!   reflection (cos θi cos θo > 0):   m = normalize(ωi + ωo)
//!       f_r = F D(m) G(ωi, ωo, m) / (4 |cos θi| |cos θo|)
//!   transmission (opposite sides):    m = normalize(ωi + η ωo)      (the generalized half vector)
//!       f_t = s (1 − F) D(m) G(ωi, ωo, m) η² |ωi·m| |ωo·m| / (|cos θi| |cos θo| (ωi·m + η ωo·m)²)
//! ```
//!
//! m is flipped to the upper hemisphere, and configurations where a facet and the macro surface
//! disagree on a side (ωi·m cos θi ≤ 0 or ωo·m cos θo ≤ 0) are discarded. s = 1/η² in radiance
//! transport, 1 in importance transport (the solid-angle compression of radiance, the "missing
//! term" Mitsuba adds to Walter's f_t; Veach 1997, §5.2): f_rad(a, b)/η_a² = f_rad(b, a)/η_b².
//!
//! Sampling draws a facet normal m for ωi flipped to the upper side (visible normals by default),
//! then reflects with probability F(ωi·m), refracting otherwise (pbrt-v4 and Mitsuba). With the
//! Jacobians dωm/dωo = 1/(4 |ωo·m|) and η² |ωo·m|/(ωi·m + η ωo·m)²,
//!
//! ```text
//!     pdf(ωo) = pdf_m(m) · (F or 1 − F) · dωm/dωo
//!     weight  = G1(ωo, m) · (1 or 1/η²)           (visible normals)
//!     weight  = G (ωi·m)/(cos θi cos θm) · (…)     (all normals)
//! ```
//!
//! With all normals (`sample_visible = false`) the sampling distribution's α is scaled by
//! 1.2 − 0.2 √|cos θi| (Walter et al. 2007, §5.3), which lowers the weights' variance; eval is
//! unaffected. The weight is f·|cos θo|/pdf, which then includes D(m)/D_widened(m): Mitsuba
//! 3.9.1's `sample` omits that ratio (its weight G (ωi·m)/(cos θi cos θm) is the unwidened
//! one), so its mean weight differs from the integral of its own `eval` there (the test
//! `mitsuba_roughdielectric_values` shows it); gonio keeps weight = f·|cos θo|/pdf. Below
//! α = 10⁻² the widening is not applied (`WIDENING_MIN_ALPHA`).
//!
//! **Zero roughness.** α is clamped to 10⁻⁴ (Mitsuba): the lobes then hold within 10⁻³ rad of
//! the mirror and refraction directions with the smooth `dielectric`'s weights (1 and 1/η²).
//!
//! **Dispersion** (ours). With a wavelength-dependent index, each wavelength has its own
//! refraction lobe: `eval` gives every wavelength its own generalized half vector (a rough prism
//! disperses light seen through it), reflections its own F. `pdf` and `sample` follow the hero
//! wavelength, as the smooth [`super::Dielectric`] does: a reflection keeps all four wavelengths
//! (weights F(λᵢ)/F(λ₀)), a refraction takes its scalar η from [`relative_hero_eta`], which
//! terminates the secondary wavelengths.
//!
//! **Multiple scattering** (`multiple_scattering`, ours; Heitz et al. 2016): the random walk of
//! [`crate::microsurface`] across the interface, in `roughdielectric_ms.rs`; `pdf` is then for
//! MIS only ([`Bsdf::pdf_is_exact`]).
//!
//! Mitsuba 3 plugin `roughdielectric`, two-sided:
//!
//! | parameter                | type             | default                  |
//! |--------------------------|------------------|--------------------------|
//! | `int_ior`                | float, name      | `bk7` 1.5046             |
//! | `ext_ior`                | float, name      | `air` 1.000277 (≠ int)   |
//! | `specular_reflectance`   | spectrum         | 1 (tint; not physical)   |
//! | `specular_transmittance` | spectrum         | 1 (tint; not physical)   |
//! | `distribution`           | string           | `beckmann` (or `ggx`)    |
//! | `alpha` / `alpha_u`, `alpha_v` | float or texture | 0.1                |
//! | `sample_visible`         | boolean          | true                     |
//! | `multiple_scattering`    | boolean (ours)   | false                    |
//!
//! gonio additionally accepts a spectrum (Sellmeier, table) for either index.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, TransportMode};
use crate::fresnel::{fresnel_dielectric, fresnel_dielectric_spectrum};
use crate::fresnel_polarized::{dielectric_reflection, dielectric_transmission, facet_mueller};
use crate::ior::{Ior, IorValue, SampledIor, relative_eta, relative_hero_eta};
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
use crate::mueller::Mueller;
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// A rough dielectric interface: microfacet reflection and refraction (Walter et al. 2007).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric<S = Spectrum, I = Ior> {
    /// Index of the interior (the side the normal points away from).
    pub int_ior: I,
    /// Index of the exterior (the side the normal points to).
    pub ext_ior: I,
    /// Tint of the reflection (default 1).
    pub specular_reflectance: S,
    /// Tint of the refraction (default 1).
    pub specular_transmittance: S,
    /// Normal distribution and roughness (α_u along the shading frame's x, the surface tangent).
    pub distribution: MicrofacetDistribution,
    /// Follow the scattering between facets (Heitz et al. 2016); false: single scattering.
    pub multiple_scattering: bool,
}

/// Below this roughness all-normal sampling draws from the model's own distribution, without
/// Walter et al.'s widening: the all-normal sampler computes cos θm = 1/√(1 + tan²θm) in `f32`,
/// which rounds to 1 once tan²θm < 6·10⁻⁸, so at α ≈ 10⁻⁴ every normal lands on the pole where
/// the weight f·|cos θo|/pdf = D(z)/D_widened(z) = s² (up to 1.12 at 60°) instead of averaging
/// to 1. At α ≥ 10⁻² the sampled tilt is resolved to 0.1 % and the widening is Mitsuba's.
const WIDENING_MIN_ALPHA: f32 = 1e-2;

/// The lobe flags of the rough refraction.
const TRANSMISSION: BsdfFlags = BsdfFlags(BsdfFlags::GLOSSY_TRANSMISSION.0 | BsdfFlags::NON_SYMMETRIC.0);

impl Default for RoughDielectric {
    /// Mitsuba's defaults: bk7 (1.5046) inside, air (1.000277) outside, Beckmann α = 0.1,
    /// visible normals.
    fn default() -> Self {
        Self::new(
            Ior::Constant(1.5046),
            Ior::Constant(1.000277),
            MicrofacetDistribution::isotropic(MicrofacetKind::Beckmann, 0.1),
        )
    }
}

impl RoughDielectric {
    /// The lobe flags of the refraction.
    pub const TRANSMISSION_FLAGS: BsdfFlags = TRANSMISSION;

    /// An untinted rough interface between `int_ior` (inside) and `ext_ior` (outside).
    pub fn new(int_ior: Ior, ext_ior: Ior, distribution: MicrofacetDistribution) -> Self {
        Self {
            int_ior,
            ext_ior,
            specular_reflectance: Spectrum::Constant(1.0),
            specular_transmittance: Spectrum::Constant(1.0),
            distribution,
            multiple_scattering: false,
        }
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> RoughDielectric<SampledSpectrum, SampledIor> {
        RoughDielectric {
            int_ior: self.int_ior.at(wl),
            ext_ior: self.ext_ior.at(wl),
            specular_reflectance: self.specular_reflectance.sample(wl),
            specular_transmittance: self.specular_transmittance.sample(wl),
            distribution: self.distribution,
            multiple_scattering: self.multiple_scattering,
        }
    }
}

/// The microfacet terms of one (ωi, ωo) query at one relative index.
#[derive(Clone, Copy, Debug)]
struct Facet {
    /// The signed cosine with m at which F is evaluated (positive on the exterior side, as
    /// [`fresnel_dielectric`] takes it): ωi·m for a reflection; for a refraction the cosine on
    /// the side of the smaller index, where F is well conditioned (1 − F → 0 linearly at
    /// grazing) and no total internal reflection can occur. The two sides give the same F in
    /// exact arithmetic (Snell holds about the generalized half vector); computed from the denser
    /// side near its critical angle, 1 − F would carry a relative rounding error of O(1) and
    /// break the reciprocity of f_t in `f32`.
    cos_fresnel: f32,
    /// f without the Fresnel factor and the tint (1/sr).
    value: f32,
    /// The density of ωo given the lobe: pdf_m(m)·|dωm/dωo|.
    pdf: f32,
}

impl<S: SpectralValue, I: IorValue> RoughDielectric<S, I> {
    /// The distribution that `sample` draws facet normals from: the model's, or with all normals
    /// its α scaled by 1.2 − 0.2 √|cos θi| (Walter et al.'s trick).
    #[inline]
    fn sampling_distribution(&self, cos_theta_i: f32) -> MicrofacetDistribution {
        let d = self.distribution;
        if d.sample_visible || d.alpha_u.min(d.alpha_v) < WIDENING_MIN_ALPHA {
            return d;
        }
        let scale = 1.2 - 0.2 * cos_theta_i.abs().sqrt();
        MicrofacetDistribution {
            alpha_u: d.alpha_u * scale,
            alpha_v: d.alpha_v * scale,
            ..d
        }
    }

    /// The facet terms at relative index `eta` (n_int/n_ext), or `None` where f and the pdf
    /// vanish (grazing wi, a facet facing away from either direction, D = 0).
    #[inline]
    fn facet(&self, wi: Vec3, wo: Vec3, eta: f32, mode: TransportMode) -> Option<Facet> {
        let (cos_i, cos_o) = (wi.z, wo.z);
        if cos_i == 0.0 || cos_o == 0.0 {
            return None;
        }
        let reflect = cos_i * cos_o > 0.0;
        let outside = cos_i > 0.0;
        // The generalized half vector ∝ ωi + η_it ωo, written as ω_ext + η ω_int (ω_ext the
        // direction on the exterior side) so that (a, b) and (b, a) give the same bits: the
        // reciprocity of f is then exact in f32, as a reflection's normalize(ωi + ωo) is.
        let (w_ext, w_int) = if outside { (wi, wo) } else { (wo, wi) };
        let m = if reflect {
            (wi + wo).normalize_or_zero()
        } else {
            (w_ext + eta * w_int).normalize_or_zero()
        };
        if m.z == 0.0 {
            return None;
        }
        let m = if m.z < 0.0 { -m } else { m };
        let (cos_im, cos_om) = (wi.dot(m), wo.dot(m));
        if cos_im * cos_i <= 0.0 || cos_om * cos_o <= 0.0 {
            return None;
        }
        let distr = &self.distribution;
        let d = distr.d(m);
        if d == 0.0 {
            return None;
        }
        let g = distr.g(wi, wo, m);
        let pdf_m = self.sampling_distribution(cos_i).pdf(wi * cos_i.signum(), m);
        let (value, jacobian) = if reflect {
            (d * g / (4.0 * cos_i * cos_o), 1.0 / (4.0 * cos_om.abs()))
        } else {
            // With (ωi·m + η_it ωo·m) = (ω_ext·m + η ω_int·m)/(1 or η), η_it²/(…)² becomes
            // η²/denom² for ωi outside and 1/denom² from inside; the radiance scale 1/η_it²
            // leaves 1/denom² and η²/denom².
            let (ext_m, int_m) = if outside {
                (cos_im, cos_om)
            } else {
                (cos_om, cos_im)
            };
            let denom = ext_m + eta * int_m;
            let base = (d * g * (cos_im * cos_om) / ((cos_i * cos_o) * (denom * denom))).abs();
            let eta2 = eta * eta;
            let scale = match (mode, outside) {
                (TransportMode::Radiance, true) | (TransportMode::Importance, false) => 1.0,
                (TransportMode::Radiance, false) | (TransportMode::Importance, true) => eta2,
            };
            let jacobian = (cos_om / (denom * denom)).abs() * if outside { eta2 } else { 1.0 };
            (base * scale, jacobian)
        };
        let pdf = pdf_m * jacobian;
        let pdf = if pdf.is_finite() { pdf } else { 0.0 };
        let value = if value.is_finite() { value } else { 0.0 };
        let cos_fresnel = match (reflect, eta >= 1.0) {
            (true, _) => cos_im,
            (false, true) => w_ext.dot(m),
            (false, false) => w_int.dot(m),
        };
        Some(Facet {
            cos_fresnel,
            value,
            pdf,
        })
    }

    /// True when the per-wavelength values differ (a dispersive index, secondaries alive).
    #[inline]
    fn disperses(&self, wl: &SampledWavelengths) -> bool {
        (self.int_ior.is_dispersive() || self.ext_ior.is_dispersive()) && !wl.secondary_terminated()
    }

    /// (f, pdf) at (wi, wo) for the lobes enabled in `ctx`; `sample` uses it too, so that its
    /// weight and pdf are exactly eval's and pdf's (see `RoughConductor`).
    fn eval_pdf_lobes(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        let has_r = ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION);
        let has_t = ctx.is_enabled(BsdfFlags::GLOSSY_TRANSMISSION);
        let reflect = wi.z * wo.z > 0.0;
        if (reflect && !has_r) || (!reflect && !has_t) {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let eta = relative_eta(&self.int_ior, &self.ext_ior, wl);
        let hero = self.facet(wi, wo, eta[0], ctx.mode);
        let pdf = hero.map_or(0.0, |h| {
            let f = fresnel_dielectric(h.cos_fresnel, eta[0]).reflectance;
            let p_lobe = match (has_r && has_t, reflect) {
                (false, _) => 1.0,
                (true, true) => f,
                (true, false) => 1.0 - f,
            };
            h.pdf * p_lobe
        });
        let dispersive = self.disperses(wl);
        let value = if reflect {
            // The half vector does not depend on λ; only F does.
            let Some(h) = hero else {
                return (SampledSpectrum::ZERO, pdf);
            };
            let f = if dispersive {
                fresnel_dielectric_spectrum(h.cos_fresnel, eta)
            } else {
                SampledSpectrum::splat(fresnel_dielectric(h.cos_fresnel, eta[0]).reflectance)
            };
            f * h.value * self.specular_reflectance.sample(wl)
        } else {
            let transmitted = |facet: Option<Facet>, eta: f32| {
                facet.map_or(0.0, |h| {
                    (1.0 - fresnel_dielectric(h.cos_fresnel, eta).reflectance) * h.value
                })
            };
            let t = if dispersive {
                // Each wavelength refracts about its own generalized half vector.
                SampledSpectrum::from_fn(|i| {
                    let facet = if i == 0 {
                        hero
                    } else {
                        self.facet(wi, wo, eta[i], ctx.mode)
                    };
                    transmitted(facet, eta[i])
                })
            } else {
                SampledSpectrum::splat(transmitted(hero, eta[0]))
            };
            t * self.specular_transmittance.sample(wl)
        };
        (value, pdf)
    }
}

impl<S: SpectralValue, I: IorValue> Bsdf for RoughDielectric<S, I> {
    fn flags(&self) -> BsdfFlags {
        let flags = BsdfFlags::GLOSSY_REFLECTION | TRANSMISSION;
        if self.distribution.is_anisotropic() {
            flags | BsdfFlags::ANISOTROPIC
        } else {
            flags
        }
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.eval_pdf(ctx, wi, wo, wl).0
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        if self.multiple_scattering {
            return self.pdf_ms(ctx, wi, wo, wl);
        }
        self.eval_pdf_lobes(ctx, wi, wo, wl).1
    }

    fn pdf_is_exact(&self) -> bool {
        !self.multiple_scattering
    }

    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        if self.multiple_scattering {
            return self.eval_pdf_ms(ctx, wi, wo, wl);
        }
        self.eval_pdf_lobes(ctx, wi, wo, wl)
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let has_r = ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION);
        let has_t = ctx.is_enabled(BsdfFlags::GLOSSY_TRANSMISSION);
        let cos_i = wi.z;
        if cos_i == 0.0 || !(has_r || has_t) {
            return None;
        }
        if self.multiple_scattering {
            return self.sample_ms(ctx, wi, u1, u2, wl);
        }
        // A facet normal seen from wi's side.
        let (m, pdf_m) = self.sampling_distribution(cos_i).sample(wi * cos_i.signum(), u2);
        let cos_im = wi.dot(m);
        if !(pdf_m > 0.0) || cos_im * cos_i <= 0.0 {
            return None;
        }
        // The lobe is chosen with the hero wavelength's F (no direction yet: no termination).
        let eta0 = relative_eta(&self.int_ior, &self.ext_ior, wl)[0];
        let f_hero = fresnel_dielectric(cos_im, eta0).reflectance;
        let reflect = if has_r && has_t { u1 < f_hero } else { has_r };
        let (wo, eta_crossed) = if reflect {
            (2.0 * cos_im * m - wi, 1.0)
        } else {
            if f_hero >= 1.0 {
                return None; // total internal reflection at this facet
            }
            // The one scalar η the direction needs; terminates the secondaries if dispersive.
            let fr = fresnel_dielectric(cos_im, relative_hero_eta(&self.int_ior, &self.ext_ior, wl));
            (
                m * (cos_im * fr.eta_ti + fr.cos_theta_t) - wi * fr.eta_ti,
                fr.eta_it,
            )
        };
        let wo = wo.normalize_or_zero();
        // A direction on the wrong side for its lobe is a failed sample (its weight would be 0:
        // G1(ωo, m) vanishes there).
        if wo.z == 0.0 || (wo.z * cos_i > 0.0) != reflect {
            return None;
        }
        let (f, pdf) = self.eval_pdf_lobes(ctx, wi, wo, wl);
        if !(pdf > 0.0) {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: f * (wo.z.abs() / pdf),
            pdf,
            flags: if reflect {
                BsdfFlags::GLOSSY_REFLECTION
            } else {
                TRANSMISSION
            },
            eta: eta_crossed,
        })
    }

    /// `eval` with the dielectric's Fresnel reflection or transmission Mueller matrix at the
    /// (generalized) half vector (polarizing).
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        self.polarize(self.eval(ctx, wi, wo, wl), ctx, wi, wo, wl)
    }

    /// `sample` with the Fresnel Mueller matrix of the sampled lobe at its half vector.
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        let s = self.sample(ctx, wi, u1, u2, wl)?;
        Some(s.with_weight(self.polarize(s.weight, ctx, wi, s.wo, wl)))
    }
}

impl<S: SpectralValue, I: IorValue> RoughDielectric<S, I> {
    /// The unpolarized value `f` at (wi, wo) as a Mueller matrix: the Fresnel reflection or
    /// transmission at the hero wavelength's (generalized) half vector, in its s/p frames
    /// (Mitsuba's polarized `roughdielectric`).
    fn polarize(
        &self,
        f: SampledSpectrum,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> Mueller {
        if self.multiple_scattering {
            // Heitz et al. 2016's walk mixes every order of scattering into one value; one
            // facet's Fresnel matrix does not describe it. Depolarized (the unpolarized value
            // unchanged), until the walk carries Mueller matrices itself.
            return Mueller::depolarizer(f);
        }
        let eta = relative_eta(&self.int_ior, &self.ext_ior, wl);
        let reflect = wi.z * wo.z > 0.0;
        let (w_ext, w_int) = if wi.z > 0.0 { (wi, wo) } else { (wo, wi) };
        let m = if reflect {
            (wi + wo).normalize_or_zero()
        } else {
            (w_ext + eta[0] * w_int).normalize_or_zero()
        };
        let m = if m.z < 0.0 { -m } else { m };
        let fresnel = if reflect {
            dielectric_reflection(wi.dot(m), eta)
        } else {
            dielectric_transmission(wi.dot(m), eta)
        };
        facet_mueller(f, &fresnel, m, ctx, wi, wo)
    }
}

#[path = "roughdielectric_ms.rs"]
mod ms;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::albedo::directional_albedo;
    use crate::bsdfs::Dielectric;
    use crate::microfacet::MicrofacetKind::{Beckmann, Ggx};
    use crate::microfacet::{rough_reflectance, rough_transmittance};
    use crate::spectra::{Extrapolation, PiecewiseLinear};
    use std::sync::Arc;

    fn dir(theta_deg: f32, phi_deg: f32, side: f32) -> Vec3 {
        let (st, ct) = theta_deg.to_radians().sin_cos();
        let (sp, cp) = phi_deg.to_radians().sin_cos();
        Vec3::new(st * cp, st * sp, side * ct)
    }

    fn glass(distribution: MicrofacetDistribution) -> RoughDielectric {
        RoughDielectric::new(Ior::Constant(1.5), Ior::Constant(1.0), distribution)
    }

    /// The importance-mode albedo split (R, T) from the visible-normal quadratures of
    /// [`crate::microfacet`], for wi on either side of an interface of relative index `eta`.
    fn vndf_albedo(d: &MicrofacetDistribution, wi: Vec3, eta: f32) -> (f32, f32) {
        let (up, eta) = if wi.z > 0.0 { (wi, eta) } else { (-wi, 1.0 / eta) };
        (rough_reflectance(d, up, eta), rough_transmittance(d, up, eta))
    }

    #[test]
    fn importance_albedo_is_the_vndf_average_and_at_most_one() {
        // Two independent integrations of the same physics: quadrature of eval over directions,
        // and E_{m∼D_wi}[F G1(ωo, m)], E[(1 − F) G1(ωt, m)] over the visible-normal sampler. For
        // Beckmann, eval's G1(ωi) is Mitsuba's rational approximation (< 0.35 %) where the
        // sampler is exact, hence the relative term of the tolerance.
        let wl = SampledWavelengths::fixed(550.0);
        for kind in [Beckmann, Ggx] {
            for alpha in [0.3f32, 1.0] {
                let d = MicrofacetDistribution::isotropic(kind, alpha);
                let m = glass(d);
                for (theta, side) in [
                    (0.0f32, 1.0f32),
                    (45.0, 1.0),
                    (80.0, 1.0),
                    (30.0, -1.0),
                    (60.0, -1.0),
                ] {
                    let wi = dir(theta, 20.0, side);
                    let quad = directional_albedo(&m, TransportMode::Importance, wi, &wl, 1_000_000);
                    let (r, t) = vndf_albedo(&d, wi, 1.5);
                    let tol = |x: f32| 1e-3 + if kind == Beckmann { 3.5e-3 * x } else { 0.0 };
                    let at = format!("{kind:?} α={alpha} θ={theta} side={side}");
                    assert!((quad.r[0] - r).abs() < tol(r), "{at}: R {} vs {r}", quad.r[0]);
                    assert!((quad.t[0] - t).abs() < tol(t), "{at}: T {} vs {t}", quad.t[0]);
                    assert!(r + t <= 1.0 + 1e-4, "{at}: R + T = {}", r + t);
                }
            }
        }
    }

    #[test]
    fn single_scattering_loses_energy_as_roughness_grows() {
        // Mitsuba's default glass (bk7/air, Beckmann), importance mode, from outside: R + T ≤ 1,
        // lower the rougher and the more grazing. In radiance mode a transmission carries 1/η²,
        // so at small α the albedo is the smooth interface's F + (1 − F)/η².
        let eta = 1.5046f32 / 1.000277;
        for theta in [0.0f32, 45.0, 80.0] {
            let wi = dir(theta, 0.0, 1.0);
            let mut previous = 1.0 + 1e-4;
            for alpha in [0.01f32, 0.1, 0.5, 1.0] {
                let d = MicrofacetDistribution::isotropic(Beckmann, alpha);
                let (r, t) = vndf_albedo(&d, wi, eta);
                assert!(r + t <= previous, "θ={theta} α={alpha}: {}", r + t);
                previous = r + t;
            }
            assert!(previous < 0.97, "θ={theta}: α = 1 loses energy ({previous})");
        }
        let d = MicrofacetDistribution::isotropic(Beckmann, 0.1);
        let (r, t) = vndf_albedo(&d, Vec3::Z, eta);
        let f = fresnel_dielectric(1.0, eta).reflectance;
        let (rough, smooth) = (r + t / (eta * eta), f + (1.0 - f) / (eta * eta));
        assert!((rough - smooth).abs() < 1e-3, "{rough} vs {smooth}");
    }

    #[test]
    fn sampling_weight_is_eval_over_pdf_for_both_samplers_sides_and_modes() {
        for kind in [Beckmann, Ggx] {
            for visible in [true, false] {
                let m = glass(MicrofacetDistribution::new(kind, 0.2, 0.5, visible));
                for ctx in [BsdfContext::radiance(), BsdfContext::importance()] {
                    for wi in [
                        dir(0.0, 0.0, 1.0),
                        dir(50.0, 20.0, 1.0),
                        dir(85.0, 200.0, 1.0),
                        dir(30.0, 70.0, -1.0),
                        dir(60.0, 10.0, -1.0),
                    ] {
                        let mut seen = [false; 2];
                        for j in 0..32 {
                            let u = Vec2::new((j as f32 + 0.3) / 32.0, ((j * 7) % 32) as f32 / 32.0 + 0.01);
                            let mut wl = SampledWavelengths::fixed(600.0);
                            let Some(s) = m.sample(&ctx, wi, (j as f32 + 0.5) / 32.0, u, &mut wl) else {
                                continue;
                            };
                            let refl = s.wo.z * wi.z > 0.0;
                            assert_eq!(refl, s.flags.is_reflection());
                            seen[refl as usize] = true;
                            let (f, pdf) = (m.eval(&ctx, wi, s.wo, &wl)[0], m.pdf(&ctx, wi, s.wo, &wl));
                            assert!((pdf / s.pdf - 1.0).abs() < 1e-5, "pdf {pdf} vs {}", s.pdf);
                            let w = f * s.wo.z.abs() / pdf;
                            assert!(
                                (w - s.weight[0]).abs() < 1e-5 * w.max(1e-3),
                                "{w} vs {}",
                                s.weight[0]
                            );
                            // Mitsuba's weight: G1(ωo, m) (× 1/η² for a radiance refraction);
                            // Beckmann's rational G1 peaks at 1.00003 (a = 1.6).
                            if visible && refl {
                                assert!(s.weight[0] <= 1.0 + 4e-5, "{kind:?} wi={wi} {s}");
                            }
                        }
                        assert!(seen[0] || wi.z < 0.0, "{kind:?} wi={wi}: no transmission sampled");
                    }
                }
            }
        }
    }

    #[test]
    fn radiance_and_importance_differ_by_eta_squared_on_transmission() {
        let m = glass(MicrofacetDistribution::isotropic(Ggx, 0.3));
        let wl = SampledWavelengths::fixed(550.0);
        let (rad, imp) = (BsdfContext::radiance(), BsdfContext::importance());
        let (a, b) = (dir(30.0, 10.0, 1.0), dir(25.0, 170.0, -1.0));
        let (fr, fi) = (m.eval(&rad, a, b, &wl)[0], m.eval(&imp, a, b, &wl)[0]);
        assert!(fr > 0.0 && (fi / fr - 2.25).abs() < 1e-5, "{fi} / {fr}");
        // Veach's law: f_rad(a, b)/η_a² = f_rad(b, a)/η_b²; importance is the transpose.
        let back = m.eval(&rad, b, a, &wl)[0];
        assert!((fr * 2.25 / back - 1.0).abs() < 1e-5, "{fr} {back}");
        assert!((m.eval(&imp, b, a, &wl)[0] / fr - 1.0).abs() < 1e-5);
        // Reflection is symmetric and mode-independent.
        let c = dir(40.0, 200.0, 1.0);
        let (x, y) = (m.eval(&rad, a, c, &wl)[0], m.eval(&imp, c, a, &wl)[0]);
        assert!(x > 0.0 && (x / y - 1.0).abs() < 1e-5);
    }

    #[test]
    fn zero_roughness_behaves_like_the_smooth_dielectric() {
        // α = 0 (clamped to 1e-4) and 1e-4: the same lobe choice, directions near the smooth
        // interface's (the median within 1e-3 rad; GGX's long tail, amplified by refraction near
        // the critical angle, reaches ~1e-2 at the grid's edge), the same weights (1, and 1/η² for a radiance refraction, η²
        // from inside), never NaN, never black; total internal reflection beyond 41.8° inside.
        let smooth = Dielectric::new(Ior::Constant(1.5), Ior::Constant(1.0));
        let ctx = BsdfContext::radiance();
        for kind in [Beckmann, Ggx] {
            for visible in [true, false] {
                for alpha in [0.0f32, 1e-4] {
                    let rough = glass(MicrofacetDistribution::new(kind, alpha, alpha, visible));
                    for (theta, side) in [
                        (0.0f32, 1.0f32),
                        (30.0, 1.0),
                        (75.0, 1.0),
                        (89.0, 1.0),
                        (20.0, -1.0),
                        (40.0, -1.0),
                        (60.0, -1.0),
                    ] {
                        let wi = dir(theta, 40.0, side);
                        for u1 in [0.001f32, 0.5, 0.999] {
                            let mut wl = SampledWavelengths::fixed(550.0);
                            let s0 = smooth.sample(&ctx, wi, u1, Vec2::ZERO, &mut wl).unwrap();
                            // Visible normals: each weight is the smooth one (G1 → 1). All normals:
                            // Walter's widened sampling α makes each weight D/D_sampled (mean 1);
                            // their midpoint-rule mean over a 64 × 64 grid of u is the smooth weight.
                            let (n, mut sum, mut far) = (64usize, 0.0f64, 0usize);
                            for k in 0..n * n {
                                let u = Vec2::new(
                                    ((k % n) as f32 + 0.5) / n as f32,
                                    ((k / n) as f32 + 0.5) / n as f32,
                                );
                                let at = format!(
                                    "{kind:?} α={alpha} visible={visible} θ={theta} side={side} u1={u1} u={u}"
                                );
                                let s = rough.sample(&ctx, wi, u1, u, &mut wl).expect(&at);
                                assert_eq!(s.flags.is_reflection(), s0.flags.is_reflection(), "{at}");
                                assert!(s.wo.distance(s0.wo) < 5e-2, "{at}: {} vs {}", s.wo, s0.wo);
                                far += usize::from(s.wo.distance(s0.wo) > 1e-3);
                                assert!(s.weight.is_finite() && s.pdf.is_finite() && s.pdf > 0.0, "{at}");
                                assert!((s.eta - s0.eta).abs() < 1e-6, "{at}");
                                let ratio = s.weight[0] / s0.weight[0];
                                if visible {
                                    assert!(
                                        (ratio - 1.0).abs() < 1e-3,
                                        "{at}: {} vs {}",
                                        s.weight[0],
                                        s0.weight[0]
                                    );
                                }
                                sum += ratio as f64;
                            }
                            let mean = sum / (n * n) as f64;
                            assert!(
                                far * 2 < n * n,
                                "{kind:?} α={alpha} θ={theta}: {far} directions beyond 1e-3 rad"
                            );
                            assert!(
                                (mean - 1.0).abs() < 1e-2,
                                "{kind:?} α={alpha} visible={visible} θ={theta}: mean weight ratio {mean}"
                            );
                        }
                    }
                }
            }
        }
    }

    fn dispersive(distribution: MicrofacetDistribution) -> RoughDielectric {
        let table = PiecewiseLinear::new(vec![400.0, 700.0], vec![1.53, 1.51], Extrapolation::Clamp).unwrap();
        RoughDielectric::new(
            Ior::from_spectrum(Spectrum::PiecewiseLinear(Arc::new(table))),
            Ior::Constant(1.0),
            distribution,
        )
    }

    #[test]
    fn a_rough_prism_disperses_and_refraction_terminates_the_secondaries() {
        let d = MicrofacetDistribution::isotropic(Ggx, 0.05);
        let prism = dispersive(d);
        let lambdas = [420.0f32, 500.0, 580.0, 660.0];
        let wl = SampledWavelengths::from_parts(lambdas, [1.0; 4]);
        let ctx = BsdfContext::radiance();
        let (wi, wo) = (dir(60.0, 0.0, 1.0), dir(33.0, 180.0, -1.0));
        // eval: each wavelength is the constant-index model at its own index; pdf is the hero's.
        let f = prism.eval(&ctx, wi, wo, &wl);
        for (i, &l) in lambdas.iter().enumerate() {
            let fixed = glass(d);
            let at_l = RoughDielectric {
                int_ior: Ior::Constant(prism.int_ior.eval(l)),
                ..fixed
            };
            let expect = at_l.eval(&ctx, wi, wo, &wl)[0];
            assert!(
                expect > 0.0 && (f[i] / expect - 1.0).abs() < 1e-6,
                "λ {l}: {} vs {expect}",
                f[i]
            );
            if i == 0 {
                assert_eq!(prism.pdf(&ctx, wi, wo, &wl), at_l.pdf(&ctx, wi, wo, &wl));
            }
        }
        assert!(f[0] != f[3], "the lobes of blue and red differ");
        // A reflection keeps every wavelength, a refraction keeps the hero only.
        let mut w = wl;
        let s = prism.sample(&ctx, wi, 0.0, Vec2::new(0.3, 0.6), &mut w).unwrap();
        assert!(s.flags.is_reflection() && !w.secondary_terminated());
        assert!(s.weight[0] != s.weight[3], "F(λ) differs per wavelength");
        let s = prism.sample(&ctx, wi, 0.99, Vec2::new(0.3, 0.6), &mut w).unwrap();
        assert!(s.flags.is_transmission() && w.secondary_terminated());
        // The same facet refracts blue more than red.
        let refracted = |l: f32| {
            let mut w = SampledWavelengths::from_parts([l, 500.0, 600.0, 650.0], [1.0; 4]);
            prism
                .sample(&ctx, wi, 0.99, Vec2::new(0.3, 0.6), &mut w)
                .unwrap()
                .wo
        };
        assert!(
            refracted(400.0).x.abs() < refracted(700.0).x.abs(),
            "blue bends more"
        );
    }

    #[test]
    fn anisotropy_follows_the_tangent() {
        // α_u (along x) small, α_v (along y) large: leaving the refraction direction along y costs
        // less than along x, in reflection and in transmission.
        let m = glass(MicrofacetDistribution::new(Ggx, 0.05, 0.3, true));
        assert!(m.flags().contains(BsdfFlags::ANISOTROPIC));
        assert!(
            !glass(MicrofacetDistribution::isotropic(Ggx, 0.3))
                .flags()
                .contains(BsdfFlags::ANISOTROPIC)
        );
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(550.0);
        for side in [1.0f32, -1.0] {
            let along_x = m.eval(&ctx, Vec3::Z, dir(10.0, 0.0, side), &wl)[0];
            let along_y = m.eval(&ctx, Vec3::Z, dir(10.0, 90.0, side), &wl)[0];
            assert!(along_y > 10.0 * along_x, "side {side}: {along_y} vs {along_x}");
        }
    }

    #[test]
    fn lobes_masked_by_the_context() {
        let m = RoughDielectric::default();
        let wl = SampledWavelengths::fixed(550.0);
        let (a, r, t) = (dir(30.0, 0.0, 1.0), dir(30.0, 180.0, 1.0), dir(19.4, 180.0, -1.0));
        let refl_only = BsdfContext::radiance().with_lobes(BsdfFlags::GLOSSY_REFLECTION);
        let trans_only = BsdfContext::radiance().with_lobes(BsdfFlags::GLOSSY_TRANSMISSION);
        assert!(m.eval(&refl_only, a, r, &wl)[0] > 0.0 && m.eval(&refl_only, a, t, &wl)[0] == 0.0);
        assert!(m.eval(&trans_only, a, t, &wl)[0] > 0.0 && m.pdf(&trans_only, a, r, &wl) == 0.0);
        // One lobe enabled: it is sampled with probability 1 (the pdf has no F or 1 − F).
        let both = BsdfContext::radiance();
        let f = fresnel_dielectric(a.dot((a + r).normalize()), 1.5046 / 1.000277).reflectance;
        let ratio = m.pdf(&refl_only, a, r, &wl) / m.pdf(&both, a, r, &wl);
        assert!((ratio * f - 1.0).abs() < 1e-5, "{ratio} vs 1/{f}");
        let mut wl2 = wl;
        for u1 in [0.0f32, 0.5, 0.999] {
            let s = m
                .sample(&trans_only, a, u1, Vec2::new(0.4, 0.4), &mut wl2)
                .unwrap();
            assert!(s.flags.is_transmission());
        }
        assert!(
            m.sample(
                &both.with_lobes(BsdfFlags::DELTA_REFLECTION),
                a,
                0.5,
                Vec2::splat(0.5),
                &mut wl2
            )
            .is_none()
        );
    }
}
