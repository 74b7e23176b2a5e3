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
//! `mitsuba_roughdielectric_values` shows it); gonio keeps weight = f·|cos θo|/pdf. When both
//! α are below 10⁻² the widening is not applied (`WIDENING_MIN_ALPHA`).
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

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, LobeSplit, TransportMode};
use crate::fresnel::{fresnel_dielectric, fresnel_dielectric_spectrum};
use crate::fresnel_polarized::{dielectric_reflection, dielectric_transmission, facet_mueller};
use crate::ior::{Ior, IorValue, SampledIor, relative_eta, relative_hero_eta};
use crate::lanes::fresnel::fresnel_dielectric as fresnel_dielectric_lanes;
use crate::lanes::{BsdfSamples, F32s, Isa, Mask, MicrofacetLanes, Portable, SampledSpectra, Vec3s};
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
/// to 1. At α ≥ 10⁻² the sampled tilt is resolved to 0.1 % and the widening is Mitsuba's. The
/// test is on the larger α: tan²θm sums both axes' slopes, so one rough axis resolves the tilt
/// however smooth the other is (an anisotropic surface with α = (0.5, 0.005) is widened, as in
/// Mitsuba).
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
        if d.sample_visible || d.alpha_u.max(d.alpha_v) < WIDENING_MIN_ALPHA {
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

    /// The sample of lobe `reflect` about the facet `m` (hero F there `f_hero`), with the
    /// weight f·|cos θo|/pdf and the pdf of `ctx`'s lobes (with both, the Fresnel choice is in
    /// the pdf); `None` for total internal reflection of a refraction or a direction on the wrong
    /// side of the surface for its lobe.
    fn sample_about(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        m: Vec3,
        f_hero: f32,
        reflect: bool,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let cos_i = wi.z;
        let cos_im = wi.dot(m);
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

    /// Both lobes of one facet, for the path tracer's lobe splitting (`split_escapes`): the
    /// reflection and the refraction about the facet [`Bsdf::sample`] draws with `u2` (all lobes
    /// enabled), each weighted as its lobe sampled alone, f·|cos θo|/p_lobe, while its `pdf`
    /// stays the full model's (p_lobe times the probability F or 1 − F with which `sample` takes
    /// the lobe, given beside it), so that MIS weights are the same function of the direction
    /// as for `sample`. `None` for multiple scattering (whose lobes are not one facet's), a
    /// dispersive index (a refraction would end the secondary wavelengths of both) and grazing
    /// ωi.
    pub fn sample_split(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<LobeSplit> {
        let cos_i = wi.z;
        if self.multiple_scattering || cos_i == 0.0 || self.disperses(wl) {
            return None;
        }
        let mut split = LobeSplit::NONE;
        let (m, pdf_m) = self.sampling_distribution(cos_i).sample(wi * cos_i.signum(), u2);
        let cos_im = wi.dot(m);
        if !(pdf_m > 0.0) || cos_im * cos_i <= 0.0 {
            return Some(split);
        }
        let eta0 = relative_eta(&self.int_ior, &self.ext_ior, wl)[0];
        let f_hero = fresnel_dielectric(cos_im, eta0).reflectance;
        let lobe = |reflect: bool, wl: &mut SampledWavelengths| {
            let (flags, choice) = if reflect {
                (BsdfFlags::GLOSSY_REFLECTION, f_hero)
            } else {
                (BsdfFlags::GLOSSY_TRANSMISSION, 1.0 - f_hero)
            };
            let alone = ctx.with_lobes(flags);
            self.sample_about(&alone, wi, m, f_hero, reflect, wl)
                .map(|bs| {
                    (
                        BsdfSample {
                            pdf: bs.pdf * choice,
                            ..bs
                        },
                        choice,
                    )
                })
                .filter(|(bs, _)| bs.pdf > 0.0)
        };
        split.reflection = lobe(true, wl);
        split.refraction = lobe(false, wl);
        split.reflectance = f_hero;
        Some(split)
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
        self.sample_about(ctx, wi, m, f_hero, reflect, wl)
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

/// [`RoughDielectric`] (single scattering, non-dispersive indices) for `N` lanes, each with its
/// own relative index, tints and roughness. Lane `k` agrees with the scalar model to rounding
/// (`tests/lanes/`).
#[derive(Clone, Copy, Debug)]
pub struct RoughDielectricLanes<const N: usize, X: Isa = Portable> {
    /// η = n_int/n_ext per lane.
    pub eta: F32s<N, X>,
    /// Tint of the reflection.
    pub specular_reflectance: SampledSpectra<N, X>,
    /// Tint of the refraction.
    pub specular_transmittance: SampledSpectra<N, X>,
    /// Distribution and per-lane roughness.
    pub distribution: MicrofacetLanes<N, X>,
}

impl RoughDielectric {
    /// This model at each lane's wavelengths; `None` for a dispersive index (a refraction there
    /// terminates a lane's secondary wavelengths and gives each wavelength its own half vector)
    /// and for `multiple_scattering` (a random walk): those stay with the scalar model.
    #[inline(always)]
    pub fn lanes<const N: usize, X: Isa>(
        &self,
        wl: &[SampledWavelengths; N],
    ) -> Option<RoughDielectricLanes<N, X>> {
        // Constant indices: η = n_int/n_ext is the same in every lane (`relative_eta`'s value
        // at any wavelength, the same division), one splat instead of two spectra per lane.
        let (Ior::Constant(n_int), Ior::Constant(n_ext)) = (&self.int_ior, &self.ext_ior) else {
            return None;
        };
        if self.multiple_scattering {
            return None;
        }
        Some(RoughDielectricLanes {
            eta: F32s::splat(n_int / n_ext),
            specular_reflectance: self.specular_reflectance.sample_lanes(wl),
            specular_transmittance: self.specular_transmittance.sample_lanes(wl),
            distribution: self.distribution.lanes(),
        })
    }
}

/// The facet terms of `N` queries ([`Facet`] per lane) and the lanes where they exist.
struct Facets<const N: usize, X: Isa> {
    valid: Mask<N, X>,
    cos_fresnel: F32s<N, X>,
    value: F32s<N, X>,
    pdf: F32s<N, X>,
}

impl<const N: usize, X: Isa> RoughDielectricLanes<N, X> {
    /// The sampling distribution per lane (Walter et al.'s widening for all-normal sampling).
    #[inline(always)]
    fn sampling_distribution(&self, cos_theta_i: F32s<N, X>) -> MicrofacetLanes<N, X> {
        let d = self.distribution;
        if d.sample_visible {
            return d;
        }
        let narrow = d.alpha_u.max(d.alpha_v).lt(WIDENING_MIN_ALPHA);
        let scale = narrow.select(F32s::ONE, 1.2 - 0.2 * cos_theta_i.abs().sqrt());
        MicrofacetLanes {
            alpha_u: d.alpha_u * scale,
            alpha_v: d.alpha_v * scale,
            ..d
        }
    }

    /// The scalar `facet`, lane by lane.
    #[inline(always)]
    fn facet(&self, wi: Vec3s<N, X>, wo: Vec3s<N, X>, mode: TransportMode) -> Facets<N, X> {
        let eta = self.eta;
        let (cos_i, cos_o) = (wi.z, wo.z);
        let reflect = (cos_i * cos_o).gt(0.0);
        let outside = cos_i.gt(0.0);
        let w_ext = outside.select3(wi, wo);
        let w_int = outside.select3(wo, wi);
        let m = reflect
            .select3(wi + wo, w_ext + w_int * eta)
            .normalize_or(Vec3::ZERO);
        let m = m.z.lt(0.0).select3(-m, m);
        let (cos_im, cos_om) = (wi.dot(m), wo.dot(m));
        let distr = &self.distribution;
        let d = distr.d(m);
        let valid = cos_i.ne(0.0)
            & cos_o.ne(0.0)
            & m.z.ne(0.0)
            & (cos_im * cos_i).gt(0.0)
            & (cos_om * cos_o).gt(0.0)
            & d.ne(0.0);
        let g = distr.g(wi, wo, m);
        let sign = F32s::ONE.copysign(cos_i);
        let pdf_m = self.sampling_distribution(cos_i).pdf(wi * sign, m);
        // Reflection.
        let value_r = d * g / (4.0 * cos_i * cos_o);
        let jacobian_r = (4.0 * cos_om.abs()).recip();
        // Refraction (see the scalar `facet` for the factors).
        let ext_m = outside.select(cos_im, cos_om);
        let int_m = outside.select(cos_om, cos_im);
        let denom = ext_m + eta * int_m;
        let denom2 = denom * denom;
        let base = (d * g * (cos_im * cos_om) / ((cos_i * cos_o) * denom2)).abs();
        let eta2 = eta * eta;
        let scaled = match mode {
            TransportMode::Radiance => !outside,
            TransportMode::Importance => outside,
        };
        let value_t = scaled.select(base * eta2, base);
        let jacobian_t = (cos_om / denom2).abs() * outside.select(eta2, F32s::ONE);
        let value = reflect.select(value_r, value_t);
        let pdf = pdf_m * reflect.select(jacobian_r, jacobian_t);
        let cos_fresnel = reflect.select(cos_im, eta.ge(1.0).select(w_ext.dot(m), w_int.dot(m)));
        Facets {
            valid,
            cos_fresnel,
            value: (valid & value.is_finite()).and_then(value),
            pdf: (valid & pdf.is_finite()).and_then(pdf),
        }
    }

    /// (f, pdf) per lane for the lobes enabled in `ctx`, as the scalar `eval_pdf_lobes`.
    #[inline(always)]
    fn eval_pdf_lobes(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        wo: Vec3s<N, X>,
    ) -> (SampledSpectra<N, X>, F32s<N, X>) {
        let has_r = ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION);
        let has_t = ctx.is_enabled(BsdfFlags::GLOSSY_TRANSMISSION);
        let reflect = (wi.z * wo.z).gt(0.0);
        let enabled = (reflect & Mask::splat(has_r)) | (!reflect & Mask::splat(has_t));
        let facet = self.facet(wi, wo, ctx.mode);
        let f = fresnel_dielectric_lanes(facet.cos_fresnel, self.eta).reflectance;
        let p_lobe = if has_r && has_t {
            reflect.select(f, 1.0 - f)
        } else {
            F32s::ONE
        };
        let ok = enabled & facet.valid;
        let pdf = ok.and_then(facet.pdf * p_lobe);
        let r = self.specular_reflectance * (f * facet.value);
        let t = self.specular_transmittance * ((1.0 - f) * facet.value);
        (SampledSpectra::select(reflect, r, t).masked(ok), pdf)
    }

    /// f(wi, wo) per lane (the scalar [`Bsdf::eval`]): [`Self::eval_pdf`]'s value; the pdf's
    /// arithmetic, unused, is dropped by the compiler once this is inlined.
    #[inline(always)]
    pub fn eval(&self, ctx: &BsdfContext, wi: Vec3s<N, X>, wo: Vec3s<N, X>) -> SampledSpectra<N, X> {
        self.eval_pdf(ctx, wi, wo).0
    }

    /// f(wi, wo) and the pdf of `sample` per lane ([`Bsdf::eval_pdf`]).
    #[inline(always)]
    pub fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        wo: Vec3s<N, X>,
    ) -> (SampledSpectra<N, X>, F32s<N, X>) {
        self.eval_pdf_lobes(ctx, wi, wo)
    }

    /// A direction per lane ([`Bsdf::sample`]): a facet normal seen from wi's side, then
    /// reflection with probability F, refraction otherwise.
    #[inline(always)]
    pub fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        u1: F32s<N, X>,
        u2: [F32s<N, X>; 2],
    ) -> BsdfSamples<N, X> {
        let has_r = ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION);
        let has_t = ctx.is_enabled(BsdfFlags::GLOSSY_TRANSMISSION);
        let cos_i = wi.z;
        let sign = F32s::ONE.copysign(cos_i);
        let (m, pdf_m) = self.sampling_distribution(cos_i).sample(wi * sign, u2);
        let cos_im = wi.dot(m);
        let fr = fresnel_dielectric_lanes(cos_im, self.eta);
        let reflect = if has_r && has_t {
            u1.lt(fr.reflectance)
        } else {
            Mask::splat(has_r)
        };
        let wo_r = wi.reflect_about(m);
        let wo_t = m * (cos_im * fr.eta_ti + fr.cos_theta_t) - wi * fr.eta_ti;
        let wo = reflect.select3(wo_r, wo_t).normalize_or(Vec3::ZERO);
        let on_its_side = (wo.z * cos_i).gt(0.0);
        let (f, pdf) = self.eval_pdf_lobes(ctx, wi, wo);
        let valid = Mask::splat(has_r || has_t)
            & cos_i.ne(0.0)
            & pdf_m.gt(0.0)
            & (cos_im * cos_i).gt(0.0)
            & (reflect | fr.reflectance.lt(1.0))
            & wo.z.ne(0.0)
            & ((on_its_side & reflect) | (!on_its_side & !reflect))
            & pdf.gt(0.0);
        BsdfSamples {
            valid,
            wo,
            weight: (f * (wo.z.abs() / pdf)).masked(valid),
            pdf,
            eta: reflect.select(F32s::ONE, fr.eta_it),
            flags: std::array::from_fn(|k| {
                if reflect.test(k) {
                    BsdfFlags::GLOSSY_REFLECTION
                } else {
                    TRANSMISSION
                }
            }),
        }
    }
}

#[path = "roughdielectric_ms.rs"]
mod ms;

#[cfg(test)]
#[path = "roughdielectric_tests.rs"]
mod tests;
