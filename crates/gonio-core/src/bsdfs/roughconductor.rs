//! `roughconductor`: a rough metal, single scattering from a microfacet surface of mirrors.
//!
//! Cook & Torrance 1982 with Walter et al. 2007's normalization ("Microfacet Models for
//! Refraction through Rough Surfaces", eq. 20), as Mitsuba 3 `src/bsdfs/roughconductor.cpp`.
//! With the half vector h = (ωi + ωo)/|ωi + ωo|, the complex-index Fresnel reflectance F and the
//! distribution D, Smith G of [`crate::microfacet`]:
//!
//! ```text
//!     f_r(ωi, ωo) = F(ωi·h) D(h) G1(ωi, h) G1(ωo, h) / (4 cos θi cos θo)
//! ```
//!
//! Sampling draws a microfacet normal m (visible normals by default) and reflects ωi about it;
//! the reflection Jacobian is dωh/dωo = 1/(4 ωo·h), so
//!
//! ```text
//!     pdf(ωo) = D_ωi(h)/(4 ωo·h) = D(h) G1(ωi, h)/(4 cos θi)     (visible normals)
//!     pdf(ωo) = D(h) cos θh/(4 ωo·h)                              (all normals)
//!     weight  = F G1(ωo, m)   or   F G (ωi·m)/(cos θi cos θm)
//! ```
//!
//! Single scattering loses the light that would leave after bouncing between facets: a white
//! (F ≡ 1) surface reflects less than 1, the more so the rougher it is and the more grazing the
//! light (Heitz et al. 2016, "Multiple-Scattering Microfacet BSDFs with the Smith Model").
//!
//! **Multiple scattering** (`multiple_scattering = true`, ours; Heitz et al. 2016): the facets'
//! inter-reflections are followed by the random walk of [`crate::microsurface`]. `sample` is the
//! walk (weight: the product of F over its bounces, per wavelength; the walk's geometry does not
//! depend on the wavelength); `eval` is its unbiased stochastic estimate, a deterministic function
//! of (ωi, ωo, λ) through a seeded generator; `pdf` is an approximation for MIS weights only
//! ([`Bsdf::pdf_is_exact`] is false). A white surface then reflects all the light.
//!
//! Mitsuba 3 plugin `roughconductor`, one-sided (nothing unless cos θi > 0 and cos θo > 0):
//!
//! | parameter              | type     | default                                   |
//! |------------------------|----------|-------------------------------------------|
//! | `material`             | string   | `none` (η = 0, k = 1: F ≡ 1)              |
//! | `eta`, `k`             | spectrum | 0, 1 (from `material`)                    |
//! | `specular_reflectance` | spectrum | 1                                         |
//! | `distribution`         | string   | `beckmann` (or `ggx`)                     |
//! | `alpha` / `alpha_u`, `alpha_v` | float or texture | 0.1                      |
//! | `sample_visible`       | boolean  | true                                      |
//!
//! Additions over Mitsuba: as for `conductor`, `ext_ior`, the index of a dielectric exterior;
//! `multiple_scattering` (boolean, default false: Mitsuba's single-scattering model).

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::fresnel::fresnel_conductor_exterior;
use crate::fresnel_polarized::{conductor_reflection, facet_mueller};
use crate::ior::{Ior, IorValue, SampledIor};
use crate::lanes::fresnel::fresnel_conductor;
use crate::lanes::{BsdfSamples, F32s, Isa, Mask, MicrofacetLanes, Portable, SampledSpectra, Vec3s};
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
use crate::microsurface::{Microsurface, eval_rng, sample_rng};
use crate::mueller::Mueller;
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// A rough conductor: the microfacet BRDF over mirror facets of complex index η + ik.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughConductor<S = Spectrum, I = Ior> {
    /// Real part n of the complex index of refraction.
    pub eta: S,
    /// Imaginary part k (extinction coefficient).
    pub k: S,
    /// Index of the dielectric the metal is immersed in (1 = vacuum; not in Mitsuba).
    pub ext_ior: I,
    /// Tint multiplying the Fresnel term (not physically based; default 1).
    pub specular_reflectance: S,
    /// Normal distribution and roughness (α_u along the shading frame's x, the surface tangent).
    pub distribution: MicrofacetDistribution,
    /// Follow the inter-reflections between facets (Heitz et al. 2016); false: single scattering.
    pub multiple_scattering: bool,
}

impl Default for RoughConductor {
    /// Mitsuba's defaults: `material="none"`, Beckmann, α = 0.1, visible normals.
    fn default() -> Self {
        Self::mirror(MicrofacetDistribution::isotropic(MicrofacetKind::Beckmann, 0.1))
    }
}

impl RoughConductor {
    /// A rough conductor of complex index `eta` + i`k` in vacuum, untinted.
    pub fn new(eta: Spectrum, k: Spectrum, distribution: MicrofacetDistribution) -> Self {
        Self {
            eta,
            k,
            ext_ior: Ior::Constant(1.0),
            specular_reflectance: Spectrum::Constant(1.0),
            distribution,
            multiple_scattering: false,
        }
    }

    /// The rough ideal mirror, η = 0, k = 1 (F ≡ 1, Mitsuba `material="none"`).
    pub fn mirror(distribution: MicrofacetDistribution) -> Self {
        Self::new(Spectrum::Constant(0.0), Spectrum::Constant(1.0), distribution)
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> RoughConductor<SampledSpectrum, SampledIor> {
        RoughConductor {
            eta: self.eta.sample(wl),
            k: self.k.sample(wl),
            ext_ior: self.ext_ior.at(wl),
            specular_reflectance: self.specular_reflectance.sample(wl),
            distribution: self.distribution,
            multiple_scattering: self.multiple_scattering,
        }
    }
}

/// [`RoughConductor`] (single scattering) for `N` lanes: the kernel of a renderer that shades
/// `N` hits at once, each lane with its own wavelengths and roughness. Lane `k` agrees with the
/// scalar model at lane `k`'s parameters to rounding (`tests/lanes/`).
#[derive(Clone, Copy, Debug)]
pub struct RoughConductorLanes<const N: usize, X: Isa = Portable> {
    /// η/η_ext per lane and wavelength.
    pub eta: SampledSpectra<N, X>,
    /// k/η_ext per lane and wavelength.
    pub k: SampledSpectra<N, X>,
    /// The tint.
    pub specular_reflectance: SampledSpectra<N, X>,
    /// Distribution and per-lane roughness.
    pub distribution: MicrofacetLanes<N, X>,
}

impl RoughConductor {
    /// This model at each lane's wavelengths; `None` with `multiple_scattering`, whose random
    /// walk has no lane kernel.
    #[inline(always)]
    pub fn lanes<const N: usize, X: Isa>(
        &self,
        wl: &[SampledWavelengths; N],
    ) -> Option<RoughConductorLanes<N, X>> {
        if self.multiple_scattering {
            return None;
        }
        let (mut eta, mut k) = (self.eta.sample_lanes(wl), self.k.sample_lanes(wl));
        if self.ext_ior != Ior::Constant(1.0) {
            let ext = SampledSpectra::from_fn(|j| self.ext_ior.sample(&wl[j]));
            (eta, k) = (eta.safe_div(ext), k.safe_div(ext));
        }
        Some(RoughConductorLanes {
            eta,
            k,
            specular_reflectance: self.specular_reflectance.sample_lanes(wl),
            distribution: self.distribution.lanes(),
        })
    }
}

impl<const N: usize, X: Isa> RoughConductorLanes<N, X> {
    /// (f, pdf) per lane from the half vector of (wi, wo), as the scalar `eval_pdf_lobe`.
    #[inline(always)]
    fn eval_pdf_lobe(&self, wi: Vec3s<N, X>, wo: Vec3s<N, X>) -> (SampledSpectra<N, X>, F32s<N, X>) {
        let h = (wi + wo).normalize_or(Vec3::ZERO);
        let valid = wi.z.gt(0.0) & wo.z.gt(0.0) & h.z.gt(0.0) & wi.dot(h).gt(0.0) & wo.dot(h).gt(0.0);
        let distr = &self.distribution;
        let d = distr.d(h);
        let valid = valid & d.ne(0.0);
        let g1_wi = distr.g1(wi, h);
        let value = d * (g1_wi * distr.g1(wo, h)) / (4.0 * wi.z * wo.z);
        let pdf = distr.pdf_from(wi, h, d, g1_wi) / (4.0 * wo.dot(h));
        let pdf = (valid & pdf.is_finite()).and_then(pdf);
        let ok = valid & value.is_finite() & value.ne(0.0);
        let cos = wi.dot(h);
        let mut f = SampledSpectra::ZERO;
        for i in 0..N_SPECTRUM_SAMPLES {
            let fr = fresnel_conductor(cos, self.eta.0[i], self.k.0[i]);
            f.0[i] = ok.and_then(fr * self.specular_reflectance.0[i] * value);
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
        if !ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) {
            return (SampledSpectra::ZERO, F32s::ZERO);
        }
        self.eval_pdf_lobe(wi, wo)
    }

    /// A direction per lane ([`Bsdf::sample`]; `u1` is not used, as in the scalar model).
    #[inline(always)]
    pub fn sample(&self, ctx: &BsdfContext, wi: Vec3s<N, X>, u2: [F32s<N, X>; 2]) -> BsdfSamples<N, X> {
        let enabled = Mask::splat(ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION));
        let (m, pdf_m) = self.distribution.sample(wi, u2);
        let cos_im = wi.dot(m);
        let wo = wi.reflect_about(m).normalize();
        let (f, pdf) = self.eval_pdf_lobe(wi, wo);
        let valid = enabled & wi.z.gt(0.0) & pdf_m.gt(0.0) & cos_im.gt(0.0) & pdf.gt(0.0);
        BsdfSamples {
            valid,
            wo,
            weight: (f * (wo.z / pdf)).masked(valid),
            pdf,
            eta: F32s::ONE,
            flags: [BsdfFlags::GLOSSY_REFLECTION; N],
        }
    }
}

impl<S: SpectralValue, I: IorValue> RoughConductor<S, I> {
    /// Fresnel reflectance times the tint for a microfacet seen at cosine `cos_theta` (> 0).
    #[inline]
    fn fresnel(&self, cos_theta: f32, wl: &SampledWavelengths) -> SampledSpectrum {
        fresnel_conductor_exterior(
            cos_theta,
            self.eta.sample(wl),
            self.k.sample(wl),
            self.ext_ior.sample(wl),
        ) * self.specular_reflectance.sample(wl)
    }

    /// The half vector of a valid configuration (both directions above, facing h), else `None`.
    #[inline]
    fn half_vector(wi: Vec3, wo: Vec3) -> Option<Vec3> {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return None;
        }
        let h = (wi + wo).normalize_or_zero();
        (h.z > 0.0 && wi.dot(h) > 0.0 && wo.dot(h) > 0.0).then_some(h)
    }
}

impl<S: SpectralValue, I: IorValue> RoughConductor<S, I> {
    /// (f, pdf) at (wi, wo), both from the half vector of the two directions; zero outside the
    /// lobe. `sample` uses it too, so its weight and pdf are exactly eval's and pdf's: at grazing
    /// angles the half vector recomputed from the rounded ωo differs from the sampled m by a
    /// rounding error that a sharp D would otherwise amplify to percents.
    #[inline]
    fn eval_pdf_lobe(&self, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> (SampledSpectrum, f32) {
        let Some(h) = Self::half_vector(wi, wo) else {
            return (SampledSpectrum::ZERO, 0.0);
        };
        let distr = &self.distribution;
        let d = distr.d(h);
        if d == 0.0 {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let value = d * distr.g(wi, wo, h) / (4.0 * wi.z * wo.z);
        let pdf = distr.pdf(wi, h) / (4.0 * wo.dot(h));
        let pdf = if pdf.is_finite() { pdf } else { 0.0 };
        if !value.is_finite() || value == 0.0 {
            return (SampledSpectrum::ZERO, pdf);
        }
        (self.fresnel(wi.dot(h), wl) * value, pdf)
    }

    /// (f, MIS-only pdf) of the multiple-scattering model: the walk's stochastic estimate.
    fn eval_pdf_ms(&self, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> (SampledSpectrum, f32) {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let ms = Microsurface::new(self.distribution);
        let mut rng = eval_rng(wi, wo, wl);
        let f_cos = ms.eval_conductor(wi, wo, |c| self.fresnel(c, wl), &mut rng);
        (f_cos / wo.z, ms.pdf_conductor(wi, wo))
    }
}

impl<S: SpectralValue, I: IorValue> Bsdf for RoughConductor<S, I> {
    fn flags(&self) -> BsdfFlags {
        let d = &self.distribution;
        if d.alpha_u != d.alpha_v {
            BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::ANISOTROPIC
        } else {
            BsdfFlags::GLOSSY_REFLECTION
        }
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.eval_pdf(ctx, wi, wo, wl).0
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        if self.multiple_scattering {
            if !ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) {
                return 0.0;
            }
            return Microsurface::new(self.distribution).pdf_conductor(wi, wo);
        }
        self.eval_pdf(ctx, wi, wo, wl).1
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
        if !ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) {
            return (SampledSpectrum::ZERO, 0.0);
        }
        if self.multiple_scattering {
            return self.eval_pdf_ms(wi, wo, wl);
        }
        self.eval_pdf_lobe(wi, wo, wl)
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) || wi.z <= 0.0 {
            return None;
        }
        if self.multiple_scattering {
            let ms = Microsurface::new(self.distribution);
            let wl = &*wl;
            let walk = ms.sample_conductor(wi, |c| self.fresnel(c, wl), &mut sample_rng(wi, u1, u2))?;
            let pdf = ms.pdf_conductor(wi, walk.wo);
            return (pdf > 0.0).then_some(BsdfSample {
                wo: walk.wo,
                weight: walk.weight,
                pdf,
                flags: BsdfFlags::GLOSSY_REFLECTION,
                eta: 1.0,
            });
        }
        let (m, pdf_m) = self.distribution.sample(wi, u2);
        let cos_im = wi.dot(m);
        if pdf_m <= 0.0 || cos_im <= 0.0 {
            return None;
        }
        let wo = (2.0 * cos_im * m - wi).normalize();
        // Mitsuba's weight is F G1(ωo, m) (visible normals) or F G (ωi·m)/(cos θi cos θm): the
        // same as f cos θo / pdf below, evaluated at the half vector of (ωi, ωo).
        let (f, pdf) = self.eval_pdf_lobe(wi, wo, wl);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: f * (wo.z / pdf),
            pdf,
            flags: BsdfFlags::GLOSSY_REFLECTION,
            eta: 1.0,
        })
    }

    /// `eval` with the conductor's Fresnel Mueller matrix at the half vector (polarizing).
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        self.polarize(self.eval(ctx, wi, wo, wl), ctx, wi, wo, wl)
    }

    /// `sample` with the conductor's Fresnel Mueller matrix at the half vector.
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

impl<S: SpectralValue, I: IorValue> RoughConductor<S, I> {
    /// The unpolarized value `f` at (wi, wo) as a Mueller matrix: the Fresnel reflection at the
    /// half vector in its s/p frames (Mitsuba's polarized `roughconductor`).
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
        let h = (wi + wo).normalize_or_zero();
        let fresnel = conductor_reflection(
            wi.dot(h),
            self.eta.sample(wl),
            self.k.sample(wl),
            self.ext_ior.sample(wl),
        );
        facet_mueller(f, &fresnel, h, ctx, wi, wo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::albedo::directional_albedo;
    use crate::bsdf::TransportMode;
    use crate::microfacet::MicrofacetKind::{Beckmann, Ggx};

    fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
        let (st, ct) = theta_deg.to_radians().sin_cos();
        let (sp, cp) = phi_deg.to_radians().sin_cos();
        Vec3::new(st * cp, st * sp, ct)
    }

    #[test]
    fn multiple_scattering_lobes_depolarize_and_keep_the_unpolarized_value() {
        let mut c = RoughConductor::new(
            Spectrum::Constant(0.2),
            Spectrum::Constant(3.9),
            MicrofacetDistribution::isotropic(Ggx, 0.5),
        );
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(550.0);
        let (wi, wo) = (dir(60.0, 0.0), dir(50.0, 170.0));
        let polarized = c.eval_mueller(&ctx, wi, wo, &wl);
        assert!(polarized.get(1, 0)[0].abs() > 1e-3, "single scattering polarizes");
        c.multiple_scattering = true;
        let m = c.eval_mueller(&ctx, wi, wo, &wl);
        assert_eq!(m.get(0, 0), c.eval(&ctx, wi, wo, &wl));
        for (r, k) in (0..4).flat_map(|r| (0..4).map(move |k| (r, k))).skip(1) {
            assert_eq!(m.get(r, k), SampledSpectrum::ZERO, "M{r}{k}");
        }
    }

    #[test]
    fn white_albedo_is_the_vndf_masking_average_and_shows_the_energy_loss() {
        // With F ≡ 1 the directional albedo (quadrature of eval over directions) equals
        // E_{m∼D_wi}[G1(ωo, m)] (quadrature over the visible-normal sampler): two independent
        // integrations of the same physics. Single scattering loses energy as α grows.
        let wl = SampledWavelengths::fixed(550.0);
        for kind in [Beckmann, Ggx] {
            let mut previous = 1.0f32;
            for alpha in [0.1f32, 0.3, 0.6, 1.0] {
                let distr = MicrofacetDistribution::isotropic(kind, alpha);
                let m = RoughConductor::mirror(distr);
                let wi = dir(45.0, 0.0);
                let quad = directional_albedo(&m, TransportMode::Radiance, wi, &wl, 4_000_000).r[0];
                let vndf = distr.vndf_expectation(wi, 256, |h| {
                    let wo = 2.0 * wi.dot(h) * h - wi;
                    distr.g1(wo, h) as f64
                }) as f32;
                assert!((quad - vndf).abs() < 2e-3, "{kind:?} α={alpha}: {quad} vs {vndf}");
                assert!(
                    vndf <= previous + 1e-4 && vndf <= 1.0 + 1e-4,
                    "{kind:?} α={alpha}: {vndf}"
                );
                previous = vndf;
            }
            assert!(previous < 0.9, "{kind:?}: α = 1 loses energy ({previous})");
        }
    }

    #[test]
    fn sampling_weight_is_eval_over_pdf_for_both_samplers() {
        let ctx = BsdfContext::radiance();
        let mut wl = SampledWavelengths::fixed(600.0);
        for kind in [Beckmann, Ggx] {
            for visible in [true, false] {
                let distr = MicrofacetDistribution::new(kind, 0.2, 0.5, visible);
                let m = RoughConductor::new(Spectrum::Constant(0.2), Spectrum::Constant(3.9), distr);
                for (i, wi) in [dir(0.0, 0.0), dir(50.0, 20.0), dir(85.0, 200.0)]
                    .into_iter()
                    .enumerate()
                {
                    for j in 0..16 {
                        let u = Vec2::new((j as f32 + 0.3) / 16.0, ((j * 7 + i) % 16) as f32 / 16.0 + 0.02);
                        let Some(s) = m.sample(&ctx, wi, 0.5, u, &mut wl) else {
                            continue;
                        };
                        let f = m.eval(&ctx, wi, s.wo, &wl)[0];
                        let pdf = m.pdf(&ctx, wi, s.wo, &wl);
                        assert!(
                            (pdf / s.pdf - 1.0).abs() < 1e-3,
                            "{distr:?}: pdf {pdf} vs {}",
                            s.pdf
                        );
                        let w = f * s.wo.z / pdf;
                        assert!(
                            (w - s.weight[0]).abs() < 1e-3 * w.max(1e-3),
                            "{distr:?}: {w} vs {}",
                            s.weight[0]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn one_sided_and_reciprocal() {
        let m = RoughConductor::default();
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(500.0);
        let (a, b) = (dir(30.0, 10.0), dir(40.0, 170.0));
        assert_eq!(m.eval(&ctx, -a, b, &wl), SampledSpectrum::ZERO);
        assert_eq!(m.eval(&ctx, a, -b, &wl), SampledSpectrum::ZERO);
        assert_eq!(m.pdf(&ctx, -a, b, &wl), 0.0);
        let (fab, fba) = (m.eval(&ctx, a, b, &wl)[0], m.eval(&ctx, b, a, &wl)[0]);
        assert!(fab > 0.0 && (fab - fba).abs() < 1e-5 * fab);
        let delta_only = ctx.with_lobes(BsdfFlags::DELTA_REFLECTION);
        assert_eq!(m.eval(&delta_only, a, b, &wl), SampledSpectrum::ZERO);
        let mut wl = wl;
        assert!(m.sample(&delta_only, a, 0.5, Vec2::splat(0.5), &mut wl).is_none());
    }

    #[test]
    fn specular_peak_value() {
        // At normal incidence and exitance, h = z: f = F(1) D(z) / 4 (G = 1), D(z) = 1/(π α²).
        let (n, k) = (0.2f32, 3.9f32);
        let distr = MicrofacetDistribution::isotropic(Ggx, 0.3);
        let m = RoughConductor::new(Spectrum::Constant(n), Spectrum::Constant(k), distr);
        let wl = SampledWavelengths::fixed(550.0);
        let f0 = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        let expect = f0 / (4.0 * std::f32::consts::PI * 0.09);
        let f = m.eval(&BsdfContext::radiance(), Vec3::Z, Vec3::Z, &wl)[0];
        assert!((f / expect - 1.0).abs() < 1e-5, "{f} vs {expect}");
    }

    #[test]
    fn zero_roughness_behaves_like_the_smooth_conductor() {
        // α = 0 is clamped to 1e-4: every sample leaves in the mirror direction (to 1e-3 rad)
        // with the smooth conductor's weight F(cos θi), never NaN, never black.
        use crate::bsdfs::Conductor;
        let (eta, k) = (Spectrum::Constant(0.2), Spectrum::Constant(3.9));
        let smooth = Conductor::new(eta.clone(), k.clone());
        let ctx = BsdfContext::radiance();
        for kind in [Beckmann, Ggx] {
            for visible in [true, false] {
                let rough = RoughConductor::new(
                    eta.clone(),
                    k.clone(),
                    MicrofacetDistribution::new(kind, 0.0, 0.0, visible),
                );
                for theta in [0.0f32, 30.0, 75.0, 89.0] {
                    let wi = dir(theta, 40.0);
                    let mut wl = SampledWavelengths::fixed(550.0);
                    let s0 = smooth.sample(&ctx, wi, 0.5, Vec2::ZERO, &mut wl).unwrap();
                    for u in [Vec2::new(0.1, 0.2), Vec2::new(0.5, 0.5), Vec2::new(0.93, 0.71)] {
                        let s = rough.sample(&ctx, wi, 0.5, u, &mut wl).unwrap();
                        assert!(
                            s.wo.distance(s0.wo) < 1e-3,
                            "{kind:?} θ={theta}: {} vs {}",
                            s.wo,
                            s0.wo
                        );
                        assert!(s.weight.is_finite() && s.pdf.is_finite());
                        // Sampling all normals, the weight carries (wi·m)/cos θi: a normal tilted
                        // by δ (the lobe's width, α = 1e-4, further in GGX's tail) moves it by up
                        // to tan δ · tan θi (0.02 at 89°).
                        let m = (wi + s.wo).normalize();
                        let tan_delta = m.truncate().length() / m.z;
                        let tol = 1e-3 + 1.1 * tan_delta * theta.to_radians().tan();
                        assert!(
                            (s.weight[0] - s0.weight[0]).abs() < tol,
                            "{kind:?} θ={theta} visible={visible}: {} vs {}",
                            s.weight[0],
                            s0.weight[0]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn anisotropy_follows_the_tangent() {
        // α_u (along x) small, α_v (along y) large: moving ωo away from the mirror direction
        // along y costs less than along x.
        let d = MicrofacetDistribution::new(Ggx, 0.05, 0.3, true);
        let m = RoughConductor::mirror(d);
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(550.0);
        let wi = Vec3::Z;
        let along_x = m.eval(&ctx, wi, dir(10.0, 0.0), &wl)[0];
        let along_y = m.eval(&ctx, wi, dir(10.0, 90.0), &wl)[0];
        assert!(along_y > 10.0 * along_x, "{along_y} vs {along_x}");
    }
}
