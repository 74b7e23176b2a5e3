//! **Test support**: deliberately broken BSDFs, one defect each, kept to prove that every check
//! of the battery can fail (issue 4: `gonio check` must fail on a broken BSDF kept in the
//! tests). Never use them for rendering.
//!
//! | model | defect | rows that must fail |
//! |---|---|---|
//! | [`PdfOffByFactor`] | `pdf` = factor × the true density | `chi2`, `sample_pdf_vs_pdf`, `pdf_normalization` |
//! | [`WrongSampler`] | draws uniform-hemisphere directions but reports the cosine pdf | `chi2` |
//! | [`WrongWeight`] | sample weight ρ·2cos θo instead of ρ | `weight_vs_eval`, `albedo_estimators` |
//! | [`EnergyGain`] | a Lambertian with ρ = 1.2 (consistent otherwise) | `energy` |
//! | [`NonReciprocal`] | f = ρ/π·(½ + ½cos²θi), ignores the transport mode | `reciprocity`, `adjoint` |
//! | [`Anisotropic`] | f = ρ/π·(1 + ½cos 2φi cos 2φo) (reciprocal, energy-conserving) | `isotropy` |
//! | [`NanAtGrazing`] | f = ρ/π·(cos θo/cos θo): NaN at exactly grazing wo | `health` |
//! | [`MinimalGlass`] with `scale_radiance = false` | smooth dielectric without the radiance-mode 1/η² | `delta_reciprocity` |
//! | [`MislabelledLobe`] | reflected samples flagged as diffuse *transmission* | `lobe_flags` |
//! | [`FalselyAnisotropic`] | a Lambertian whose flags claim anisotropy | `isotropy` |
//! | [`EvalPdfMismatch`] | a fused `eval_pdf` that returns half the pdf | `eval_pdf` |
//! | [`DiffuseTransmitter`] with `claimed_eta ≠ 1` | symmetric f across an interface it says changes the index | `eta2_law` |
//!
//! [`MinimalGlass`] with `scale_radiance = true` is a correct smooth dielectric and
//! [`DiffuseTransmitter`] with `claimed_eta = 1` a correct Lambertian transmitter: the positive
//! controls that show the delta-lobe and transmission checks pass on right models.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, TransportMode};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, TAU};

/// One-sided Lambertian sampling shared by the broken models: cosine-hemisphere `wo` and its pdf.
fn cosine_sample(ctx: &BsdfContext, wi: Vec3, u2: Vec2) -> Option<(Vec3, f32)> {
    if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 {
        return None;
    }
    let wo = square_to_cosine_hemisphere(u2);
    let pdf = square_to_cosine_hemisphere_pdf(wo);
    (pdf > 0.0).then_some((wo, pdf))
}

fn diffuse_sample(wo: Vec3, weight: f32, pdf: f32) -> Option<BsdfSample> {
    (weight > 0.0).then_some(BsdfSample {
        wo,
        weight: SampledSpectrum::splat(weight),
        pdf,
        flags: BsdfFlags::DIFFUSE_REFLECTION,
        eta: 1.0,
    })
}

fn upper(ctx: &BsdfContext, wi: Vec3, wo: Vec3) -> bool {
    ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) && wi.z > 0.0 && wo.z > 0.0
}

macro_rules! lambert_pdf {
    () => {
        fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> f32 {
            if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 {
                return 0.0;
            }
            square_to_cosine_hemisphere_pdf(wo)
        }
    };
}

/// A Lambertian (ρ = 0.5) whose `pdf` is `factor` times the density `sample` really uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PdfOffByFactor {
    /// The error factor (1 would be correct).
    pub factor: f32,
}

impl Bsdf for PdfOffByFactor {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if upper(ctx, wi, wo) {
            SampledSpectrum::splat(0.5 * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> f32 {
        if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 {
            return 0.0;
        }
        self.factor * square_to_cosine_hemisphere_pdf(wo)
    }
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = cosine_sample(ctx, wi, u2)?;
        diffuse_sample(wo, 0.5, pdf)
    }
}

/// A Lambertian (ρ = 0.5) that draws directions uniformly over the hemisphere while reporting
/// (and weighting by) the cosine-weighted pdf: `eval`, `pdf` and the weights agree with each
/// other, only the distribution of `wo` is wrong.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct WrongSampler;

impl Bsdf for WrongSampler {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if upper(ctx, wi, wo) {
            SampledSpectrum::splat(0.5 * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    lambert_pdf!();
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) || wi.z <= 0.0 {
            return None;
        }
        let z = u2.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let (s, c) = (TAU * u2.y).sin_cos();
        let wo = Vec3::new(r * c, r * s, z);
        let pdf = square_to_cosine_hemisphere_pdf(wo);
        if pdf <= 0.0 {
            return None;
        }
        diffuse_sample(wo, 0.5, pdf)
    }
}

/// A Lambertian (ρ = 0.5) whose sample weight is ρ·2cos θo instead of ρ = f·cos θo/pdf.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct WrongWeight;

impl Bsdf for WrongWeight {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if upper(ctx, wi, wo) {
            SampledSpectrum::splat(0.5 * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    lambert_pdf!();
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = cosine_sample(ctx, wi, u2)?;
        diffuse_sample(wo, 0.5 * 2.0 * wo.z, pdf)
    }
}

/// A consistent Lambertian with the unphysical reflectance ρ = 1.2: reflects more than it
/// receives.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct EnergyGain;

impl Bsdf for EnergyGain {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if upper(ctx, wi, wo) {
            SampledSpectrum::splat(1.2 * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    lambert_pdf!();
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = cosine_sample(ctx, wi, u2)?;
        diffuse_sample(wo, 1.2, pdf)
    }
}

/// f = ρ/π·(½ + ½cos²θi), ρ = 0.8: consistent sampling, albedo ≤ 1, but f(a,b) ≠ f(b,a); it
/// also ignores the transport mode, so importance mode is not the transpose.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct NonReciprocal;

impl NonReciprocal {
    fn value(wi: Vec3) -> f32 {
        0.8 * (0.5 + 0.5 * wi.z * wi.z)
    }
}

impl Bsdf for NonReciprocal {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if upper(ctx, wi, wo) {
            SampledSpectrum::splat(Self::value(wi) * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    lambert_pdf!();
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = cosine_sample(ctx, wi, u2)?;
        diffuse_sample(wo, Self::value(wi), pdf)
    }
}

/// f = ρ/π·(1 + ½cos 2φi cos 2φo), ρ = 0.5: reciprocal, consistent, albedo ρ, but not
/// invariant under a rotation about the normal.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Anisotropic;

impl Anisotropic {
    fn cos2phi(w: Vec3) -> f32 {
        let r2 = w.x * w.x + w.y * w.y;
        if r2 > 0.0 {
            (w.x * w.x - w.y * w.y) / r2
        } else {
            1.0
        }
    }
    fn value(wi: Vec3, wo: Vec3) -> f32 {
        0.5 * (1.0 + 0.5 * Self::cos2phi(wi) * Self::cos2phi(wo))
    }
}

impl Bsdf for Anisotropic {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if upper(ctx, wi, wo) {
            SampledSpectrum::splat(Self::value(wi, wo) * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    lambert_pdf!();
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = cosine_sample(ctx, wi, u2)?;
        diffuse_sample(wo, Self::value(wi, wo), pdf)
    }
}

/// A Lambertian (ρ = 0.5) written as ρ/π·(cos θo/cos θo): 0/0 = NaN at an exactly grazing `wo`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct NanAtGrazing;

impl Bsdf for NanAtGrazing {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    // The defect is the point: cos θo/cos θo is 0/0 at grazing.
    #[allow(clippy::eq_op)]
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) && wi.z > 0.0 && wo.z >= 0.0 {
            SampledSpectrum::splat(0.5 * FRAC_1_PI * (wo.z / wo.z))
        } else {
            SampledSpectrum::ZERO
        }
    }
    lambert_pdf!();
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = cosine_sample(ctx, wi, u2)?;
        diffuse_sample(wo, 0.5, pdf)
    }
}

/// Unpolarized Fresnel reflectance of a dielectric interface for cos θi ≥ 0 and relative index
/// η = n_t/n_i; returns (F, cos θt), F = 1 under total internal reflection.
fn fresnel(cos_i: f32, eta: f32) -> (f32, f32) {
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return (1.0, 0.0);
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    (0.5 * (rs * rs + rp * rp), cos_t)
}

/// A minimal smooth dielectric of index `eta` inside, 1 outside, sampled with probability F for
/// reflection. With `scale_radiance = true` it is correct (radiance-mode refraction weight
/// (η_i/η_t)²): the positive control. With `false` it forgets that factor, which breaks the
/// generalized reciprocity (η² law) and the adjoint relation of its delta transmission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MinimalGlass {
    /// Interior index of refraction (exterior 1).
    pub eta: f32,
    /// Apply the radiance-mode (η_i/η_t)² factor.
    pub scale_radiance: bool,
}

impl Bsdf for MinimalGlass {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DELTA_REFLECTION | BsdfFlags::DELTA_TRANSMISSION | BsdfFlags::NON_SYMMETRIC
    }
    fn eval(&self, _: &BsdfContext, _: Vec3, _: Vec3, _: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::ZERO
    }
    fn pdf(&self, _: &BsdfContext, _: Vec3, _: Vec3, _: &SampledWavelengths) -> f32 {
        0.0
    }
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        _u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let eta = if wi.z > 0.0 { self.eta } else { 1.0 / self.eta };
        let (f, cos_t) = fresnel(wi.z.abs(), eta);
        let refl_on = ctx.is_enabled(BsdfFlags::DELTA_REFLECTION);
        let tran_on = ctx.is_enabled(BsdfFlags::DELTA_TRANSMISSION);
        let p_r = match (refl_on, tran_on) {
            (true, true) => f,
            (true, false) => 1.0,
            (false, true) => 0.0,
            (false, false) => return None,
        };
        if u1 < p_r {
            let w = if tran_on { 1.0 } else { f };
            return (f > 0.0).then_some(BsdfSample {
                wo: Vec3::new(-wi.x, -wi.y, wi.z),
                weight: SampledSpectrum::splat(w),
                pdf: p_r,
                flags: BsdfFlags::DELTA_REFLECTION,
                eta: 1.0,
            });
        }
        if f >= 1.0 {
            return None;
        }
        let wo = Vec3::new(-wi.x / eta, -wi.y / eta, -wi.z.signum() * cos_t).normalize();
        let mut w = if refl_on { 1.0 } else { 1.0 - f };
        if self.scale_radiance && ctx.mode == TransportMode::Radiance {
            w /= eta * eta;
        }
        Some(BsdfSample {
            wo,
            weight: SampledSpectrum::splat(w),
            pdf: 1.0 - p_r,
            flags: BsdfFlags::DELTA_TRANSMISSION | BsdfFlags::NON_SYMMETRIC,
            eta,
        })
    }
}

/// A Lambertian (ρ = 0.5) whose samples claim to be diffuse transmission although they leave on
/// wi's side (and its flags say reflection only).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct MislabelledLobe;

impl Bsdf for MislabelledLobe {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if upper(ctx, wi, wo) {
            SampledSpectrum::splat(0.5 * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    lambert_pdf!();
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = cosine_sample(ctx, wi, u2)?;
        let mut s = diffuse_sample(wo, 0.5, pdf)?;
        s.flags = BsdfFlags::DIFFUSE_TRANSMISSION;
        Some(s)
    }
}

/// A correct Lambertian (ρ = 0.5) whose flags say [`BsdfFlags::ANISOTROPIC`]: the isotropy row
/// must see that the announced variation is not there.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FalselyAnisotropic;

impl Bsdf for FalselyAnisotropic {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION | BsdfFlags::ANISOTROPIC
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if upper(ctx, wi, wo) {
            SampledSpectrum::splat(0.5 * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    lambert_pdf!();
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = cosine_sample(ctx, wi, u2)?;
        diffuse_sample(wo, 0.5, pdf)
    }
}

/// A correct Lambertian (ρ = 0.5) except for its fused `eval_pdf`, which returns half the pdf
/// (the kind of slip a hand-optimized fused path makes).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct EvalPdfMismatch;

impl Bsdf for EvalPdfMismatch {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_REFLECTION
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if upper(ctx, wi, wo) {
            SampledSpectrum::splat(0.5 * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    lambert_pdf!();
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = cosine_sample(ctx, wi, u2)?;
        diffuse_sample(wo, 0.5, pdf)
    }
    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        (self.eval(ctx, wi, wo, wl), 0.5 * self.pdf(ctx, wi, wo, wl))
    }
}

/// Lambertian transmission f = ρ_t/π between opposite sides (two-sided, no reflection),
/// cosine-sampled on the other side. `sample` reports `eta` = `claimed_eta` when entering from
/// above (1/`claimed_eta` from below). With `claimed_eta = 1` it is correct; otherwise its
/// symmetric f contradicts the generalized reciprocity f(a,b)/η_a² = f(b,a)/η_b² of an interface
/// that changes the index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmitter {
    /// ρ_t, the diffuse transmittance.
    pub rho_t: f32,
    /// The relative index `sample` reports (1 = no interface).
    pub claimed_eta: f32,
}

impl Bsdf for DiffuseTransmitter {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE_TRANSMISSION
    }
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        if ctx.is_enabled(BsdfFlags::DIFFUSE_TRANSMISSION) && wi.z * wo.z < 0.0 {
            SampledSpectrum::splat(self.rho_t * FRAC_1_PI)
        } else {
            SampledSpectrum::ZERO
        }
    }
    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> f32 {
        if ctx.is_enabled(BsdfFlags::DIFFUSE_TRANSMISSION) && wi.z * wo.z < 0.0 {
            wo.z.abs() * FRAC_1_PI
        } else {
            0.0
        }
    }
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        _wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !ctx.is_enabled(BsdfFlags::DIFFUSE_TRANSMISSION) || wi.z == 0.0 {
            return None;
        }
        let mut wo = square_to_cosine_hemisphere(u2);
        if wi.z > 0.0 {
            wo.z = -wo.z;
        }
        let pdf = wo.z.abs() * FRAC_1_PI;
        (pdf > 0.0).then_some(BsdfSample {
            wo,
            weight: SampledSpectrum::splat(self.rho_t),
            pdf,
            flags: BsdfFlags::DIFFUSE_TRANSMISSION,
            eta: if wi.z > 0.0 {
                self.claimed_eta
            } else {
                1.0 / self.claimed_eta
            },
        })
    }
}
