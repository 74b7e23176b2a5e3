//! `roughplastic`: a Lambertian base under a rough dielectric coat, the rough counterpart of
//! [`super::Plastic`].
//!
//! Mitsuba 3 `src/bsdfs/roughplastic.cpp` (after Weidlich & Wilkie 2007, "Arbitrarily Layered
//! Micro-Facet Surfaces", and Kelemen & Szirmay-Kalos 2001): the coat reflects like a rough
//! dielectric interface (Walter et al. 2007, the microfacet BRDF of `roughconductor` with the
//! dielectric Fresnel term); the light it transmits reaches the base and escapes as in `plastic`,
//! the smooth coat's 1 − F replaced by the rough interface's directional transmittance T(μ). With
//! h the half vector, F = F(ωi·h, η), D and G of [`crate::microfacet`], μ = cos θ:
//!
//! ```text
//!     f(ωi, ωo) = tint F D(h) G(ωi, ωo, h) / (4 μi μo)
//!               + T(μi) T(μo) (1/η²) (ρ/π) / (1 − D′)
//!     D′ = ρ R̄_int   (nonlinear = true: the series of internal reflections)
//!     D′ = R̄_int     (nonlinear = false, Mitsuba's default: colours stay linear in ρ)
//!     T(μ)   = E_{m∼D_ωi}[(1 − F(ωi·m, η)) G1(ωt, m)]        (light entering from outside)
//!     R̄_int = 2 ∫₀¹ R(μ, 1/η) μ dμ,  R(μ, 1/η) = E_{m∼D_ωi}[F(ωi·m, 1/η) G1(ωr, m)]
//! ```
//!
//! T and R are the single-scattering directional albedos of the interface
//! ([`crate::microfacet::rough_transmittance`], [`crate::microfacet::rough_reflectance`]). The
//! diffuse lobe integrates to T(μi) ρ/(1 − D′) · T̄/η² with T̄ = 2∫T μ dμ, and reciprocity of the
//! interface makes T̄/η² the internal escape fraction T̄_int ≤ 1 − R̄_int: at ρ = 1 the albedo is
//! R(μi) + T(μi) T̄_int/(1 − R̄_int) ≤ R(μi) + T(μi) ≤ 1, with equality for a smooth coat (as in
//! `plastic`) and a loss growing with α (single scattering drops the light masked by facets).
//!
//! **The averages.** T and R are expectations over the visible normals by Gauss–Legendre
//! quadrature (32² nodes, 128² from the denser side); T is tabulated once at construction on a
//! uniform grid in μ and linearly interpolated (no allocation in eval or sample).
//! [`CoatAverages::Exact`] (gonio's default): 256 nodes, and R̄_int by Gauss–Legendre in μ
//! (2 × 24 nodes) split at the critical cosine, where total internal reflection puts a kink.
//! [`CoatAverages::Mitsuba`] reproduces Mitsuba 3.9.1's tables for comparisons: 64 nodes (the
//! first at μ = 10⁻⁶), Mitsuba's visible-normal map for the quadrature, and R̄_int = 2·mean over
//! those 64 nodes of R μ, which weighs the end points like interior ones and misses the kink. Its
//! R̄_int is too small (Beckmann α = 0.1: 0.5747 where the exact value is 0.5832), so a white base
//! loses up to 2 % more energy than single scattering does (0.968 instead of 0.987 at normal
//! incidence); the tests `exact_averages_keep_more_energy_than_mitsubas_tables` (below) and
//! `white_coat_energy_exact_vs_mitsuba` (`crates/gonio-render/tests/mitsuba_roughplastic_values.rs`)
//! state the figures. Mitsuba's eval and pdf are reproduced to 3e-6 with its tables; the exact
//! default differs from them by up to 2 % (diffuse lobe) and 0.1 % (pdf).
//!
//! **Sampling** (Mitsuba's): with s = mean(tint)/(mean(ρ) + mean(tint)), the coat's lobe is chosen
//! with probability P_s = (1 − T(μi)) s / ((1 − T(μi)) s + T(μi)(1 − s)) (a microfacet normal, visible
//! normals by default, and ωo reflected about it), else a cosine-weighted direction; the pdf is
//! the mixture P_s D_ωi(h)/(4 ωo·h) + (1 − P_s) μo/π and the weight f μo / pdf (one-sample MIS
//! over both lobes). One-sided: nothing unless μi > 0 and μo > 0.
//!
//! α = 0 is clamped to 10⁻⁴ (as Mitsuba): the coat's lobe becomes a mirror of weight ≈ F and T
//! becomes 1 − F, so the model behaves like `plastic` (with the same exact R̄_int = Fdr(1/η)).
//!
//! Mitsuba 3 plugin `roughplastic`:
//!
//! | parameter              | type        | default                                   |
//! |------------------------|-------------|-------------------------------------------|
//! | `diffuse_reflectance`  | spectrum    | 0.5                                       |
//! | `nonlinear`            | boolean     | false                                     |
//! | `int_ior`, `ext_ior`   | float, name | `polypropylene` 1.49, `air` 1.000277 (must differ) |
//! | `specular_reflectance` | spectrum    | 1 (tint; not physical)                    |
//! | `distribution`         | string      | `beckmann` (or `ggx`)                     |
//! | `alpha`                | float       | 0.1 (no texture, isotropic only)          |
//! | `sample_visible`       | boolean     | true                                      |

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::fresnel::{fresnel_dielectric, refract_about};
use crate::lanes::fresnel::fresnel_dielectric as fresnel_dielectric_lanes;
use crate::lanes::warp::square_to_cosine_hemisphere as square_to_cosine_hemisphere_lanes;
use crate::lanes::{BsdfSamples, F32s, Isa, Mask, Portable, SampledSpectra, Vec3s};
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind, rough_reflectance, rough_transmittance};
use crate::quadrature::gauss_legendre;
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::warp::{
    square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf, square_to_uniform_disk_concentric,
};
use glam::{Vec2, Vec3};
use std::borrow::Borrow;
use std::f32::consts::FRAC_1_PI;

/// How the coat's averages T(μ) and R̄_int are computed (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CoatAverages {
    /// gonio's default: T on 256 nodes, R̄_int by Gauss–Legendre split at the critical angle.
    #[default]
    Exact,
    /// Mitsuba 3.9.1's tables: T on 64 nodes, R̄_int by a 64-node mean.
    Mitsuba,
}

/// Nodes of T(μ) in [`CoatAverages::Exact`].
const EXACT_NODES: usize = 256;
/// Nodes of T(μ) in [`CoatAverages::Mitsuba`] (`MI_ROUGH_TRANSMITTANCE_RES`).
const MITSUBA_NODES: usize = 64;
/// Gauss–Legendre nodes in μ on each side of the critical cosine for the exact R̄_int.
const R_INT_NODES: usize = 24;

/// The rough coat: its microfacet distribution, relative index and precomputed averages. Built
/// once (a few hundred thousand visible-normal evaluations); a per-hit model borrows it.
#[derive(Clone, Debug, PartialEq)]
pub struct RoughCoat {
    distribution: MicrofacetDistribution,
    eta: f32,
    inv_eta2: f32,
    averages: CoatAverages,
    nodes: usize,
    transmittance: [f32; EXACT_NODES],
    internal_reflectance: f32,
}

impl RoughCoat {
    /// A coat of relative index `eta` (interior over exterior, ≠ 1) with an isotropic
    /// distribution (α_v is ignored; the plugin rejects anisotropy as Mitsuba does).
    pub fn new(distribution: MicrofacetDistribution, eta: f32, averages: CoatAverages) -> Self {
        let distribution = MicrofacetDistribution::new(
            distribution.kind,
            distribution.alpha_u,
            distribution.alpha_u,
            distribution.sample_visible,
        );
        let nodes = match averages {
            CoatAverages::Exact => EXACT_NODES,
            CoatAverages::Mitsuba => MITSUBA_NODES,
        };
        let mu_at = |i: usize| {
            let mu = i as f32 / (nodes - 1) as f32;
            match averages {
                CoatAverages::Mitsuba => mu.max(1e-6),
                CoatAverages::Exact => mu,
            }
        };
        let dir = |mu: f32| Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
        let mut transmittance = [0.0f32; EXACT_NODES];
        for (i, t) in transmittance.iter_mut().enumerate().take(nodes) {
            *t = match averages {
                CoatAverages::Exact => rough_transmittance(&distribution, dir(mu_at(i)), eta),
                CoatAverages::Mitsuba => mitsuba_albedo(&distribution, dir(mu_at(i)), eta, false),
            };
        }
        let internal_reflectance = match averages {
            CoatAverages::Mitsuba => {
                let sum: f64 = (0..nodes)
                    .map(|i| {
                        let mu = mu_at(i);
                        mitsuba_albedo(&distribution, dir(mu), 1.0 / eta, true) as f64 * mu as f64
                    })
                    .sum();
                (2.0 * sum / nodes as f64) as f32
            }
            CoatAverages::Exact => {
                // 2∫₀¹ R(μ, 1/η) μ dμ; R has a kink at the critical cosine (for η > 1 seen from
                // inside; for η < 1 the exterior is the denser side and there is none).
                let crit = if eta > 1.0 {
                    (1.0 - 1.0 / (eta as f64 * eta as f64)).sqrt()
                } else {
                    0.5
                };
                let mut sum = 0.0f64;
                for (a, b) in [(0.0, crit), (crit, 1.0)] {
                    for (mu, w) in gauss_legendre(R_INT_NODES, a, b) {
                        sum += w * mu * rough_reflectance(&distribution, dir(mu as f32), 1.0 / eta) as f64;
                    }
                }
                (2.0 * sum) as f32
            }
        };
        Self {
            distribution,
            eta,
            inv_eta2: 1.0 / (eta * eta),
            averages,
            nodes,
            transmittance,
            internal_reflectance,
        }
    }

    /// The microfacet distribution (isotropic).
    pub fn distribution(&self) -> &MicrofacetDistribution {
        &self.distribution
    }
    /// Relative index η = int_ior/ext_ior.
    pub fn eta(&self) -> f32 {
        self.eta
    }
    /// How the averages were computed.
    pub fn averages(&self) -> CoatAverages {
        self.averages
    }
    /// R̄_int, the cosine-weighted average reflectance of the coat seen from inside.
    pub fn internal_reflectance(&self) -> f32 {
        self.internal_reflectance
    }

    /// T(μ), the coat's directional transmittance from outside (the table, linearly
    /// interpolated as Mitsuba's `lerp_gather`).
    #[inline]
    pub fn transmittance(&self, mu: f32) -> f32 {
        let n = self.nodes;
        let x = mu.clamp(0.0, 1.0) * (n - 1) as f32;
        let i = (x as usize).min(n - 2);
        let w = x - i as f32;
        let t = &self.transmittance[..n];
        (1.0 - w) * t[i] + w * t[i + 1]
    }

    /// 2∫₀¹ T(μ) μ dμ of the interpolated table (exact for the piecewise-linear T): the
    /// hemispherical transmittance from outside; T̄/η² is the escape fraction from inside.
    pub fn mean_transmittance(&self) -> f64 {
        let n = self.nodes;
        let h = 1.0 / (n - 1) as f64;
        let mut sum = 0.0;
        for i in 0..n - 1 {
            let (a, b) = (i as f64 * h, (i + 1) as f64 * h);
            let (ta, tb) = (self.transmittance[i] as f64, self.transmittance[i + 1] as f64);
            // ∫ (ta (b − μ) + tb (μ − a))/h · μ dμ over [a, b].
            sum += ta * (b * (b * b - a * a) / 2.0 - (b * b * b - a * a * a) / 3.0) / h
                + tb * ((b * b * b - a * a * a) / 3.0 - a * (b * b - a * a) / 2.0) / h;
        }
        2.0 * sum
    }
}

/// The rough interface's directional reflectance (`reflect`) or transmittance as Mitsuba 3.9.1
/// computes them for its tables (`eval_reflectance`, `eval_transmittance` in
/// `include/mitsuba/render/microfacet.h`): the same expectation over visible normals as
/// [`rough_reflectance`] and [`rough_transmittance`], with Mitsuba's Gauss–Legendre grid pushed
/// through Mitsuba's own visible-normal map. For GGX that map starts from the concentric disk
/// (ours, Heitz 2018's, from polar coordinates), whose kinks along the diagonals move the 32²-node
/// quadrature by ~3e-4; reproducing it is what makes the tables Mitsuba's.
fn mitsuba_albedo(distr: &MicrofacetDistribution, wi: Vec3, eta: f32, reflect: bool) -> f32 {
    let integrand = |m: Vec3| -> f64 {
        let cos_im = wi.dot(m);
        let f = fresnel_dielectric(cos_im, eta).reflectance;
        if reflect {
            let wo = 2.0 * cos_im * m - wi;
            if wo.z <= 0.0 {
                0.0
            } else {
                (f * distr.g1(wo, m)) as f64
            }
        } else {
            match refract_about(wi, m, eta) {
                Some((wt, _)) if wt.z * wi.z < 0.0 => ((1.0 - f) * distr.g1(wt, m)) as f64,
                _ => 0.0,
            }
        }
    };
    let n = if eta > 1.0 { 32 } else { 128 };
    if distr.kind == MicrofacetKind::Beckmann {
        // Mitsuba's Beckmann map is the same inversion (three Newton steps where ours converges).
        return distr.vndf_expectation(wi, n, integrand) as f32;
    }
    let alpha = distr.alpha_u;
    let wh = Vec3::new(alpha * wi.x, alpha * wi.y, wi.z).normalize();
    let cos_theta = wh.z;
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let r = (wh.x * wh.x + wh.y * wh.y).sqrt();
    let (sin_phi, cos_phi) = if r > 0.0 { (wh.y / r, wh.x / r) } else { (0.0, 1.0) };
    let rule = gauss_legendre(n, 0.0, 1.0);
    let mut sum = 0.0;
    for &(x, wx) in &rule {
        for &(y, wy) in &rule {
            // Project a point of the disk onto the visible hemisphere, as slopes (α = 1).
            let mut p = square_to_uniform_disk_concentric(Vec2::new(x as f32, y as f32));
            let s = 0.5 * (1.0 + cos_theta);
            p.y = (1.0 - s) * (1.0 - p.x * p.x).max(0.0).sqrt() + s * p.y;
            let z = (1.0 - p.length_squared()).max(0.0).sqrt();
            let norm = 1.0 / (sin_theta * p.y + cos_theta * z);
            let (sx, sy) = ((cos_theta * p.y - sin_theta * z) * norm, p.x * norm);
            // Rotate back to wi's azimuth and unstretch.
            let slope_x = (cos_phi * sx - sin_phi * sy) * alpha;
            let slope_y = (sin_phi * sx + cos_phi * sy) * alpha;
            let m = Vec3::new(-slope_x, -slope_y, 1.0).normalize();
            sum += wx * wy * integrand(m);
        }
    }
    sum as f32
}

/// A rough dielectric coat over a Lambertian base (Mitsuba `roughplastic`); `C` is the coat,
/// owned ([`RoughCoat`]) or borrowed from the scene at a hit (`&RoughCoat`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughPlastic<S = Spectrum, C = RoughCoat> {
    /// ρ, the albedo of the Lambertian base.
    pub diffuse_reflectance: S,
    /// Tint of the coat's reflection (default 1).
    pub specular_reflectance: S,
    /// true: the physical series 1/(1 − ρ R̄_int); false (default): 1/(1 − R̄_int).
    pub nonlinear: bool,
    /// The coat and its precomputed averages.
    pub coat: C,
    specular_sampling_weight: f32,
}

impl Default for RoughPlastic {
    /// Mitsuba's defaults: ρ = 0.5, polypropylene (1.49) in air (1.000277), linear, tint 1,
    /// Beckmann α = 0.1, visible normals; exact averages.
    fn default() -> Self {
        Self::new(
            Spectrum::Constant(0.5),
            Spectrum::Constant(1.0),
            false,
            RoughCoat::new(
                MicrofacetDistribution::isotropic(MicrofacetKind::Beckmann, 0.1),
                1.49 / 1.000277,
                CoatAverages::Exact,
            ),
        )
    }
}

impl RoughPlastic {
    /// The model; the specular sampling weight is s = mean(tint)/(mean(ρ) + mean(tint)).
    pub fn new(
        diffuse_reflectance: Spectrum,
        specular_reflectance: Spectrum,
        nonlinear: bool,
        coat: RoughCoat,
    ) -> Self {
        let (d, s) = (diffuse_reflectance.mean(), specular_reflectance.mean());
        let specular_sampling_weight = if d + s > 0.0 { s / (d + s) } else { 0.5 };
        Self {
            diffuse_reflectance,
            specular_reflectance,
            nonlinear,
            coat,
            specular_sampling_weight,
        }
    }

    /// This model at the four wavelengths of a path, borrowing the coat (the per-hit `Copy`
    /// value).
    pub fn at(&self, wl: &SampledWavelengths) -> RoughPlastic<SampledSpectrum, &RoughCoat> {
        RoughPlastic {
            diffuse_reflectance: self.diffuse_reflectance.sample(wl),
            specular_reflectance: self.specular_reflectance.sample(wl),
            nonlinear: self.nonlinear,
            coat: &self.coat,
            specular_sampling_weight: self.specular_sampling_weight,
        }
    }
}

impl RoughPlastic {
    /// This model with the coat borrowed, for any wavelengths (a copy whose spectra a textured
    /// material replaces at a point without rebuilding the coat).
    pub fn borrowed(&self) -> RoughPlastic<Spectrum, &RoughCoat> {
        RoughPlastic {
            diffuse_reflectance: self.diffuse_reflectance.clone(),
            specular_reflectance: self.specular_reflectance.clone(),
            nonlinear: self.nonlinear,
            coat: &self.coat,
            specular_sampling_weight: self.specular_sampling_weight,
        }
    }
}

impl<S: SpectralValue, C: Borrow<RoughCoat>> RoughPlastic<S, C> {
    /// Replaces the specular sampling weight s ∈ [0, 1]. Changes the variance only.
    pub fn with_specular_sampling_weight(mut self, s: f32) -> Self {
        self.specular_sampling_weight = s.clamp(0.0, 1.0);
        self
    }

    /// s, the weight of the coat's lobe in lobe selection.
    pub fn specular_sampling_weight(&self) -> f32 {
        self.specular_sampling_weight
    }

    /// Probability of sampling the coat's lobe at incidence `mu_i`.
    #[inline]
    fn prob_specular(&self, ctx: &BsdfContext, mu_i: f32) -> f32 {
        let has_spec = ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION);
        let has_diff = ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION);
        if has_spec != has_diff {
            return if has_spec { 1.0 } else { 0.0 };
        }
        let t_i = self.coat.borrow().transmittance(mu_i);
        let s = self.specular_sampling_weight;
        let (ps, pd) = ((1.0 - t_i) * s, t_i * (1.0 - s));
        if ps + pd > 0.0 { ps / (ps + pd) } else { 0.0 }
    }

    /// (f, pdf) for μi, μo > 0 and at least one lobe enabled.
    #[inline]
    fn eval_pdf_lobes(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        let coat = self.coat.borrow();
        let distr = &coat.distribution;
        let p_spec = self.prob_specular(ctx, wi.z);
        let h = (wi + wo).normalize_or_zero();
        let mut f = SampledSpectrum::ZERO;
        let mut pdf = 0.0;
        let d = if h.z > 0.0 { distr.d(h) } else { 0.0 };
        if d > 0.0 {
            if ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) {
                let fr = fresnel_dielectric(wi.dot(h), coat.eta).reflectance;
                let value = fr * d * distr.g(wi, wo, h) / (4.0 * wi.z * wo.z);
                if value.is_finite() && value > 0.0 {
                    f = self.specular_reflectance.sample(wl) * value;
                }
            }
            let p = distr.pdf(wi, h) / (4.0 * wo.dot(h));
            if p.is_finite() {
                pdf = p_spec * p;
            }
        }
        if ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) {
            let rho = self.diffuse_reflectance.sample(wl);
            let denom = if self.nonlinear {
                1.0 - rho * coat.internal_reflectance
            } else {
                SampledSpectrum::splat(1.0 - coat.internal_reflectance)
            };
            let t = coat.transmittance(wi.z) * coat.transmittance(wo.z);
            f += rho.safe_div(denom) * (coat.inv_eta2 * t * FRAC_1_PI);
            pdf += (1.0 - p_spec) * square_to_cosine_hemisphere_pdf(wo);
        }
        (f, pdf)
    }
}

impl<S: SpectralValue, C: Borrow<RoughCoat> + Send + Sync> Bsdf for RoughPlastic<S, C> {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::DIFFUSE_REFLECTION
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
        let any =
            ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) || ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION);
        if !any || wi.z <= 0.0 || wo.z <= 0.0 {
            return (SampledSpectrum::ZERO, 0.0);
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
        let any =
            ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) || ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION);
        if !any || wi.z <= 0.0 {
            return None;
        }
        let p_spec = self.prob_specular(ctx, wi.z);
        let (wo, flags) = if u1 < p_spec {
            let (m, pdf_m) = self.coat.borrow().distribution.sample(wi, u2);
            let cos_im = wi.dot(m);
            if pdf_m <= 0.0 || cos_im <= 0.0 {
                return None;
            }
            ((2.0 * cos_im * m - wi).normalize(), BsdfFlags::GLOSSY_REFLECTION)
        } else {
            (square_to_cosine_hemisphere(u2), BsdfFlags::DIFFUSE_REFLECTION)
        };
        if wo.z <= 0.0 {
            return None;
        }
        let (f, pdf) = self.eval_pdf_lobes(ctx, wi, wo, wl);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: f * (wo.z / pdf),
            pdf,
            flags,
            eta: 1.0,
        })
    }
}

/// [`RoughPlastic`] for `N` lanes, each at its own wavelengths (the coat, whose roughness
/// Mitsuba does not texture, is shared). Lane `k` agrees with the scalar model to rounding
/// (`tests/lanes/`).
#[derive(Clone, Copy, Debug)]
pub struct RoughPlasticLanes<'a, const N: usize, X: Isa = Portable> {
    /// ρ per lane and wavelength.
    pub diffuse_reflectance: SampledSpectra<N, X>,
    /// The coat's tint per lane and wavelength.
    pub specular_reflectance: SampledSpectra<N, X>,
    /// The physical series 1/(1 − ρ R̄_int) (true) or Mitsuba's 1/(1 − R̄_int).
    pub nonlinear: bool,
    /// The coat and its averages.
    pub coat: &'a RoughCoat,
    specular_sampling_weight: f32,
}

impl RoughPlastic {
    /// This model at each lane's wavelengths.
    #[inline(always)]
    pub fn lanes<const N: usize, X: Isa>(&self, wl: &[SampledWavelengths; N]) -> RoughPlasticLanes<'_, N, X> {
        RoughPlasticLanes {
            diffuse_reflectance: self.diffuse_reflectance.sample_lanes(wl),
            specular_reflectance: self.specular_reflectance.sample_lanes(wl),
            nonlinear: self.nonlinear,
            coat: &self.coat,
            specular_sampling_weight: self.specular_sampling_weight,
        }
    }
}

impl<const N: usize, X: Isa> RoughPlasticLanes<'_, N, X> {
    /// T(μ) per lane (the table, linearly interpolated).
    #[inline(always)]
    fn transmittance(&self, mu: F32s<N, X>) -> F32s<N, X> {
        let n = self.coat.nodes;
        (mu.clamp(0.0, 1.0) * (n - 1) as f32).lerp_table(&self.coat.transmittance[..n])
    }

    /// The probability of sampling the coat's lobe at incidence `mu_i`, per lane.
    #[inline(always)]
    fn prob_specular(&self, ctx: &BsdfContext, mu_i: F32s<N, X>) -> F32s<N, X> {
        let has_spec = ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION);
        let has_diff = ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION);
        if has_spec != has_diff {
            return F32s::splat(if has_spec { 1.0 } else { 0.0 });
        }
        let t_i = self.transmittance(mu_i);
        let s = self.specular_sampling_weight;
        let (ps, pd) = ((1.0 - t_i) * s, t_i * (1.0 - s));
        (ps + pd).gt(0.0).and_then(ps / (ps + pd))
    }

    /// (f, pdf) per lane for μi, μo > 0, as the scalar `eval_pdf_lobes`.
    #[inline(always)]
    fn eval_pdf_lobes(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        wo: Vec3s<N, X>,
    ) -> (SampledSpectra<N, X>, F32s<N, X>) {
        let coat = self.coat;
        let distr = coat.distribution.lanes::<N, X>();
        let p_spec = self.prob_specular(ctx, wi.z);
        let h = (wi + wo).normalize_or(Vec3::ZERO);
        let d = distr.d(h);
        let g1_wi = distr.g1(wi, h);
        let has_d = d.gt(0.0);
        let mut f = SampledSpectra::ZERO;
        if ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) {
            let fr = fresnel_dielectric_lanes(wi.dot(h), F32s::splat(coat.eta)).reflectance;
            let value = fr * d * (g1_wi * distr.g1(wo, h)) / (4.0 * wi.z * wo.z);
            let ok = has_d & value.is_finite() & value.gt(0.0);
            f = self.specular_reflectance * ok.and_then(value);
        }
        let p = distr.pdf_from(wi, h, d, g1_wi) / (4.0 * wo.dot(h));
        let mut pdf = (has_d & p.is_finite()).and_then(p_spec * p);
        if ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) {
            let rho = self.diffuse_reflectance;
            let denom = if self.nonlinear {
                rho.one_minus_scaled(coat.internal_reflectance)
            } else {
                SampledSpectra::splat(1.0 - coat.internal_reflectance)
            };
            let t = self.transmittance(wi.z) * self.transmittance(wo.z);
            f = f + rho.safe_div(denom) * (coat.inv_eta2 * t * FRAC_1_PI);
            pdf += (1.0 - p_spec) * wo.z.gt(0.0).and_then(wo.z * FRAC_1_PI);
        }
        (f, pdf)
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
        let any =
            ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) || ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION);
        if !any {
            return (SampledSpectra::ZERO, F32s::ZERO);
        }
        let ok = wi.z.gt(0.0) & wo.z.gt(0.0);
        let (f, pdf) = self.eval_pdf_lobes(ctx, wi, wo);
        (f.masked(ok), ok.and_then(pdf))
    }

    /// A direction per lane ([`Bsdf::sample`]): the coat's lobe where `u1` < P_s, else the base's.
    #[inline(always)]
    pub fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        u1: F32s<N, X>,
        u2: [F32s<N, X>; 2],
    ) -> BsdfSamples<N, X> {
        let any =
            ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) || ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION);
        let p_spec = self.prob_specular(ctx, wi.z);
        let specular = u1.lt(p_spec);
        let mut wo = Vec3s::default();
        let mut ok = Mask::splat(any) & wi.z.gt(0.0);
        // Each strategy only where some lane takes it.
        if specular.any() {
            let (m, pdf_m) = self.coat.distribution.lanes::<N, X>().sample(wi, u2);
            let cos_im = wi.dot(m);
            wo = wi.reflect_about(m).normalize();
            ok = ok & (!specular | (pdf_m.gt(0.0) & cos_im.gt(0.0)));
        }
        if !specular.all() {
            wo = specular.select3(wo, square_to_cosine_hemisphere_lanes(u2));
        }
        let (f, pdf) = self.eval_pdf_lobes(ctx, wi, wo);
        let valid = ok & wo.z.gt(0.0) & pdf.gt(0.0) & pdf.is_finite();
        BsdfSamples {
            valid,
            wo,
            weight: (f * (wo.z / pdf)).masked(valid),
            pdf,
            eta: F32s::ONE,
            flags: std::array::from_fn(|k| {
                if specular.test(k) {
                    BsdfFlags::GLOSSY_REFLECTION
                } else {
                    BsdfFlags::DIFFUSE_REFLECTION
                }
            }),
        }
    }
}

#[cfg(test)]
#[path = "roughplastic_tests.rs"]
mod tests;
