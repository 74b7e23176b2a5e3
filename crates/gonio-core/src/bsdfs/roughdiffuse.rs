//! `roughdiffuse`: a rough diffuse surface, Oren and Nayar's V-cavity model (M. Oren, S. K.
//! Nayar, "Generalization of Lambert's Reflectance Model", SIGGRAPH 1994), with Mitsuba 0.6's
//! plugin name and parameters (`src/bsdfs/roughdiffuse.cpp`; Mitsuba 3 and pbrt-v4 have no such
//! plugin).
//!
//! The surface is made of long symmetric V-grooves whose facets are ideal diffuse reflectors of
//! albedo ρ, with facet slopes normally distributed with standard deviation σ (radians).
//! Mitsuba's `alpha` is an RMS slope like the microfacet plugins' Beckmann α and is mapped to
//! σ = α/√2. With α = max(θi, θo), β = min(θi, θo) and φ the azimuth between ωi and ωo
//! (cos φ = 0 when either direction is within sin θ < 10⁻⁴ of the normal):
//!
//! ```text
//!     C1 = 1 − σ²/(2(σ² + 0.33))
//!     C2 = 0.45 σ²/(σ² + 0.09) · sin α                     if cos φ > 0
//!          0.45 σ²/(σ² + 0.09) · (sin α − (2β/π)³)          otherwise
//!     C3 = 0.125 σ²/(σ² + 0.09) · (4αβ/π²)²
//!     f  = ρ/π [C1 + cos φ C2 tan β + (1 − |cos φ|) C3 tan((α + β)/2)]       (direct light)
//!        + 0.17 ρ²/π · σ²/(σ² + 0.13) · (1 − cos φ (2β/π)²)                  (interreflections)
//! ```
//!
//! (the bracket of the direct term clamped at 0: for σ ≳ 1.4 rad the fit goes negative when a
//! grazing direction looks back against the other),
//!
//! the paper's full model (its Eqs. 30 and 31: the single-bounce fit plus the two-bounce
//! interreflection term), and, with `useFastApprox`, its "qualitative" model
//!
//! ```text
//!     f = ρ/π (A + B max(0, cos φ) sin α tan β),   A = 1 − σ²/(2(σ² + 0.33)),   B = 0.45 σ²/(σ² + 0.09)
//! ```
//!
//! The default is the full model, as in Mitsuba 0.6 (`useFastApprox` false): it keeps the
//! interreflections, whose ρ² makes bright rough surfaces lighter and colours more saturated,
//! and the C3 term that flattens the forward side; the qualitative form drops both for speed.
//! σ = 0 (α = 0) is Lambert's ρ/π exactly in both forms. Both are reciprocal (symmetric in θi,
//! θo and even in φ) but neither conserves energy exactly: at ρ = 1 the directional albedo is
//! below 1 at normal incidence and, for small α, above 1 at grazing incidence (1.04 for the full
//! model at α = 0.5, cos θi = 0.01).
//!
//! Sampling: cosine-weighted, exact pdf cos θo/π (as in Mitsuba 0.6).
//!
//! `model="microfacet"` (ours) replaces the V-grooves by the Smith microsurface of a microfacet
//! distribution (`distribution`, Beckmann by default, α the same RMS slope as above) with
//! Lambertian facets, and follows light through every bounce between facets: Heitz, Hanika,
//! d'Eon and Dachsbacher 2016, "Multiple-Scattering Microfacet BSDFs with the Smith Model"
//! (ACM TOG 35(4)), the random walk of [`crate::microsurface`]. There is no closed form:
//!
//! ```text
//!     f cos θo = E[ Σₖ ρᵏ p_k(ωo) G1(ωo, hₖ) ]     (walk from ωi; p the facets' phase function)
//! ```
//!
//! `sample` is the walk itself (weight ρ^order, exact), `eval` the paper's unbiased estimator,
//! seeded from its arguments so it is a deterministic function of them, and `pdf` is cos θo/π,
//! an approximation for MIS weights only ([`Bsdf::pdf_is_exact`] is false). A white surface
//! (ρ = 1) reflects all the light at every roughness; ρ < 1 loses ρᵏ per bounce, so roughness
//! darkens and saturates colours (at ρ = 0.8, GGX α = 1 reflects 0.674 at normal incidence).
//! Beckmann is the default because Mitsuba's `alpha` means a Beckmann RMS slope (in
//! `roughdiffuse` as in `roughconductor`, whose default distribution is Beckmann too), and a
//! Gaussian heightfield, the surface Oren–Nayar's σ describes, has Beckmann slopes.
//!
//! One-sided (nothing unless cos θi > 0 and cos θo > 0).
//!
//! | parameter       | type                | default                                        |
//! |-----------------|---------------------|------------------------------------------------|
//! | `reflectance`   | spectrum or texture | 0.5                                            |
//! | `alpha`         | float or texture    | 0.2 (RMS slope; σ = α/√2)                      |
//! | `useFastApprox` | boolean             | false (the full Oren–Nayar model)              |
//! | `model`         | string              | `orennayar` (or `microfacet`)                  |
//! | `distribution`  | string              | `beckmann` (or `ggx`; `model="microfacet"`)    |

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
use crate::microsurface::{Microsurface, eval_rng, sample_rng};
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_1_SQRT_2};

/// Below this sin θ a direction counts as normal and cos φ is taken as 0 (Mitsuba's `Epsilon`).
const MIN_SIN_THETA: f32 = 1e-4;

/// Which scattering model `roughdiffuse` evaluates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RoughDiffuseModel {
    /// Oren–Nayar's full model with the interreflection term (Mitsuba 0.6's default).
    #[default]
    OrenNayar,
    /// Oren–Nayar's qualitative model, A + B max(0, cos φ) sin α tan β (`useFastApprox`).
    OrenNayarFast,
    /// Lambertian facets on the Smith microsurface of this distribution, all bounces (Heitz
    /// et al. 2016; stochastic `eval`, MIS-only `pdf`).
    Microfacet(MicrofacetKind),
}

/// A rough diffuse BRDF (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDiffuse<S = Spectrum> {
    /// ρ, the facets' albedo.
    pub reflectance: S,
    /// α, the RMS slope of the facets (Oren–Nayar's σ = α/√2).
    pub alpha: f32,
    /// The model evaluated.
    pub model: RoughDiffuseModel,
}

impl Default for RoughDiffuse {
    /// Mitsuba 0.6's defaults: ρ = 0.5, α = 0.2, the full Oren–Nayar model.
    fn default() -> Self {
        Self {
            reflectance: Spectrum::Constant(0.5),
            alpha: 0.2,
            model: RoughDiffuseModel::OrenNayar,
        }
    }
}

impl RoughDiffuse {
    /// A rough diffuse surface of albedo ρ, RMS slope α and the given model (α clamped to ≥ 0).
    pub fn new(reflectance: Spectrum, alpha: f32, model: RoughDiffuseModel) -> Self {
        Self {
            reflectance,
            alpha: alpha.max(0.0),
            model,
        }
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> RoughDiffuse<SampledSpectrum> {
        RoughDiffuse {
            reflectance: self.reflectance.sample(wl),
            alpha: self.alpha,
            model: self.model,
        }
    }
}

/// The angles of a pair of directions in Oren–Nayar's terms.
struct Angles {
    /// cos(φi − φo), 0 when either direction is (nearly) normal.
    cos_phi: f32,
    /// sin α, α = max(θi, θo).
    sin_alpha: f32,
    /// sin β, β = min(θi, θo).
    sin_beta: f32,
    /// tan β.
    tan_beta: f32,
    /// cos α.
    cos_alpha: f32,
    /// cos β.
    cos_beta: f32,
}

impl Angles {
    #[inline]
    fn new(wi: Vec3, wo: Vec3) -> Self {
        let sin_i = (1.0 - wi.z * wi.z).max(0.0).sqrt();
        let sin_o = (1.0 - wo.z * wo.z).max(0.0).sqrt();
        let cos_phi = if sin_i > MIN_SIN_THETA && sin_o > MIN_SIN_THETA {
            ((wi.x * wo.x + wi.y * wo.y) / (sin_i * sin_o)).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        // β is the angle of the direction nearer the normal (the larger cosine).
        let (sin_alpha, cos_alpha, sin_beta, cos_beta) = if wi.z > wo.z {
            (sin_o, wo.z, sin_i, wi.z)
        } else {
            (sin_i, wi.z, sin_o, wo.z)
        };
        Self {
            cos_phi,
            sin_alpha,
            sin_beta,
            tan_beta: sin_beta / cos_beta,
            cos_alpha,
            cos_beta,
        }
    }
}

impl<S: SpectralValue> RoughDiffuse<S> {
    /// σ², Oren–Nayar's slope variance (σ = α/√2).
    #[inline]
    fn sigma2(&self) -> f32 {
        let sigma = self.alpha * FRAC_1_SQRT_2;
        sigma * sigma
    }

    /// The Smith microsurface of the facets (isotropic α; visible normals are always sampled).
    #[inline]
    pub fn microsurface(&self, kind: MicrofacetKind) -> Microsurface {
        Microsurface::new(MicrofacetDistribution::new(kind, self.alpha, self.alpha, true))
    }

    /// f (no cosine), both directions above the surface.
    fn value(&self, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let rho = self.reflectance.sample(wl);
        let s2 = self.sigma2();
        let g = Angles::new(wi, wo);
        match self.model {
            RoughDiffuseModel::OrenNayarFast => {
                let a = 1.0 - 0.5 * s2 / (s2 + 0.33);
                let b = 0.45 * s2 / (s2 + 0.09);
                rho * (FRAC_1_PI * (a + b * g.cos_phi.max(0.0) * g.sin_alpha * g.tan_beta))
            }
            RoughDiffuseModel::OrenNayar => {
                let alpha = g.cos_alpha.clamp(-1.0, 1.0).acos();
                let beta = g.cos_beta.clamp(-1.0, 1.0).acos();
                let t = s2 / (s2 + 0.09);
                let ab = 4.0 * FRAC_1_PI * FRAC_1_PI * alpha * beta;
                let b2 = 2.0 * beta * FRAC_1_PI;
                let c1 = 1.0 - 0.5 * s2 / (s2 + 0.33);
                let c2 = 0.45
                    * t
                    * if g.cos_phi > 0.0 {
                        g.sin_alpha
                    } else {
                        g.sin_alpha - b2 * b2 * b2
                    };
                let c3 = 0.125 * t * ab * ab;
                let c4 = 0.17 * s2 / (s2 + 0.13);
                // tan((α + β)/2) from the half-angle identity.
                let tan_half = (g.sin_alpha + g.sin_beta) / (g.cos_alpha + g.cos_beta);
                // The fit goes negative for very rough surfaces seen backwards near grazing
                // (σ ≳ 1.4 rad: C1 + cos φ C2 tan β < 0): a radiance is never negative.
                let single =
                    (c1 + g.cos_phi * c2 * g.tan_beta + (1.0 - g.cos_phi.abs()) * c3 * tan_half).max(0.0);
                let double = c4 * (1.0 - g.cos_phi * b2 * b2);
                (rho * single + rho * rho * double) * FRAC_1_PI
            }
            RoughDiffuseModel::Microfacet(kind) => {
                let f_cos = self
                    .microsurface(kind)
                    .eval_diffuse(wi, wo, rho, &mut eval_rng(wi, wo, wl));
                let f = f_cos * (1.0 / wo.z);
                if f.is_finite() { f } else { SampledSpectrum::ZERO }
            }
        }
    }
}

impl<S: SpectralValue> Bsdf for RoughDiffuse<S> {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.value(wi, wo, wl)
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> f32 {
        if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        // The microfacet walk's density is unknown: cos θo/π stands in for MIS weights.
        square_to_cosine_hemisphere_pdf(wo)
    }

    fn pdf_is_exact(&self) -> bool {
        !matches!(self.model, RoughDiffuseModel::Microfacet(_))
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 {
            return None;
        }
        if let RoughDiffuseModel::Microfacet(kind) = self.model {
            let rho = self.reflectance.sample(wl);
            let walk = self
                .microsurface(kind)
                .sample_diffuse(wi, rho, &mut sample_rng(wi, u1, u2))?;
            let pdf = square_to_cosine_hemisphere_pdf(walk.wo);
            return (pdf > 0.0 && walk.wo.z > 0.0).then_some(BsdfSample {
                wo: walk.wo,
                weight: walk.weight,
                pdf,
                flags: BsdfFlags::DIFFUSE_REFLECTION,
                eta: 1.0,
            });
        }
        let wo = square_to_cosine_hemisphere(u2);
        let pdf = square_to_cosine_hemisphere_pdf(wo);
        if !(pdf > 0.0 && wo.z > 0.0) {
            return None;
        }
        // f cos θo/pdf = π f.
        let weight = self.value(wi, wo, wl) * std::f32::consts::PI;
        Some(BsdfSample {
            wo,
            weight,
            pdf,
            flags: BsdfFlags::DIFFUSE_REFLECTION,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
#[path = "roughdiffuse_tests.rs"]
mod tests;
