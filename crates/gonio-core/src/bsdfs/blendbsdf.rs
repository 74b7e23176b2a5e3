//! `blendbsdf`: the linear mix of two BSDFs.
//!
//! Lecture, slide "Linearity": BSDFs add, so a material that is partly one thing and partly
//! another is the weighted sum
//!
//! ```text
//!     f = (1 − w) f₀ + w f₁,      w ∈ [0, 1]
//! ```
//!
//! `eval` and `pdf` are the same linear blends (the pdf of "choose child 1 with probability w,
//! then sample it" is (1 − w)p₀ + w p₁). `sample` picks child 1 with probability w (u1 is
//! rescaled and reused), samples it, and then:
//!
//! * a **smooth** outcome gets Mitsuba's one-sample mixture weight
//!   [(1 − w)f₀ + w f₁]|cos θo| / [(1 − w)p₀ + w p₁], both children evaluated at ωo (so
//!   weight = eval·|cos|/pdf holds for the blend);
//! * a **delta** outcome gets weight = f_δ/P(select) = (w·T₁)/(w·P₁) = the child's own weight, and
//!   pdf w·P₁ (a discrete probability). The other child's solid-angle density is *not* added.
//!
//! **Deliberate deviation from Mitsuba 3.9.1**, which adds the delta child's discrete probability
//! to the other child's density and so is biased for delta + smooth mixes: for a 50/50 blend of
//! a perfect mirror and a black diffuse it returns albedo 0.379 = 0.5/(1 + 1/π) at normal
//! incidence (0.408 at 45°, 0.474 at 80°) instead of 0.5. [`BlendBsdf::mitsuba_delta_pdf`]
//! restores Mitsuba's estimator for comparisons with its renders: a delta outcome of the chosen
//! child c (blend factor w_c, the other child o evaluated at ωo) gets
//!
//! ```text
//!     pdf = w_c P_c + (1 − w_c) p_o(ωo),   weight = [w_c f̂_c + (1 − w_c) f_o |cos θo|] / pdf
//! ```
//!
//! with f̂_c = weight_c · P_c the child's delta value (Mitsuba's `blendbsdf::sample` after its
//! PR #1681); smooth outcomes are the same in both.
//!
//! The mixture weight is unbiased because every child's `sample` returns a direction wherever its
//! `pdf` says it does, zero weight included (the `Bsdf::sample` contract): a black diffuse child
//! still proposes directions at which the other child is evaluated
//! (`blend_of_black_and_white_diffuse_is_half`).
//!
//! Mitsuba 3 plugin `blendbsdf` (`src/bsdfs/blendbsdf.cpp`):
//!
//! | parameter      | type           | default                                          |
//! |----------------|----------------|--------------------------------------------------|
//! | `weight`       | float, texture | required in 3.9.1 (docs: 0.5); clipped to [0, 1] |
//! | (nested BSDFs) | 2 × `bsdf`     | required; w = 0 gives the first, w = 1 the second |

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::mueller::Mueller;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::weight::Weight;
use glam::{Vec2, Vec3};

/// (1 − w)·`bsdf0` + w·`bsdf1`.
#[derive(Clone, Copy)]
pub struct BlendBsdf<'a> {
    /// w, the share of `bsdf1`; clipped to [0, 1] when used.
    pub weight: f32,
    /// The BSDF at w = 0.
    pub bsdf0: &'a dyn Bsdf,
    /// The BSDF at w = 1.
    pub bsdf1: &'a dyn Bsdf,
    /// Mitsuba 3.9.1's estimator for delta outcomes (module documentation): biased for delta +
    /// smooth mixes, for comparisons only. `false` (the default) is the exact one.
    pub mitsuba_delta_pdf: bool,
}

impl std::fmt::Debug for BlendBsdf<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BlendBsdf")
            .field("weight", &self.weight)
            .field("mitsuba_delta_pdf", &self.mitsuba_delta_pdf)
            .field("bsdf0_flags", &self.bsdf0.flags())
            .field("bsdf1_flags", &self.bsdf1.flags())
            .finish()
    }
}

impl<'a> BlendBsdf<'a> {
    /// The blend (1 − weight)·bsdf0 + weight·bsdf1.
    pub fn new(weight: f32, bsdf0: &'a dyn Bsdf, bsdf1: &'a dyn Bsdf) -> Self {
        Self {
            weight,
            bsdf0,
            bsdf1,
            mitsuba_delta_pdf: false,
        }
    }

    /// The same blend with Mitsuba 3.9.1's estimator for delta outcomes when `on`.
    pub fn with_mitsuba_delta_pdf(self, on: bool) -> Self {
        Self {
            mitsuba_delta_pdf: on,
            ..self
        }
    }

    /// The child not chosen when `chosen_is_1` says which was.
    #[inline]
    fn other(&self, chosen_is_1: bool) -> &'a dyn Bsdf {
        if chosen_is_1 { self.bsdf0 } else { self.bsdf1 }
    }

    /// w clipped to [0, 1] (NaN counts as 0).
    #[inline]
    fn w(&self) -> f32 {
        if self.weight >= 1.0 {
            1.0
        } else if self.weight > 0.0 {
            self.weight
        } else {
            0.0
        }
    }
}

impl Bsdf for BlendBsdf<'_> {
    fn flags(&self) -> BsdfFlags {
        self.bsdf0.flags() | self.bsdf1.flags()
    }

    fn pdf_is_exact(&self) -> bool {
        self.bsdf0.pdf_is_exact() && self.bsdf1.pdf_is_exact()
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let w = self.w();
        let mut f = SampledSpectrum::ZERO;
        if w < 1.0 {
            f += self.bsdf0.eval(ctx, wi, wo, wl) * (1.0 - w);
        }
        if w > 0.0 {
            f += self.bsdf1.eval(ctx, wi, wo, wl) * w;
        }
        f
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        let w = self.w();
        let mut p = 0.0;
        if w < 1.0 {
            p += (1.0 - w) * self.bsdf0.pdf(ctx, wi, wo, wl);
        }
        if w > 0.0 {
            p += w * self.bsdf1.pdf(ctx, wi, wo, wl);
        }
        p
    }

    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        let w = self.w();
        let (mut f, mut p) = (SampledSpectrum::ZERO, 0.0);
        if w < 1.0 {
            let (f0, p0) = self.bsdf0.eval_pdf(ctx, wi, wo, wl);
            f += f0 * (1.0 - w);
            p += (1.0 - w) * p0;
        }
        if w > 0.0 {
            let (f1, p1) = self.bsdf1.eval_pdf(ctx, wi, wo, wl);
            f += f1 * w;
            p += w * p1;
        }
        (f, p)
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let w = self.w();
        let chosen_is_1 = u1 < w;
        let (chosen, p_select, u1) = if chosen_is_1 {
            (self.bsdf1, w, u1 / w)
        } else {
            (self.bsdf0, 1.0 - w, (u1 - w) / (1.0 - w))
        };
        let u1 = u1.clamp(0.0, 1.0 - f32::EPSILON / 2.0);
        let mut s = chosen.sample(ctx, wi, u1, u2, wl)?;
        if s.flags.is_delta() && self.mitsuba_delta_pdf && p_select < 1.0 {
            // Mitsuba's: the discrete probability added to the other child's density.
            let (f_o, p_o) = self.other(chosen_is_1).eval_pdf(ctx, wi, s.wo, wl);
            let pdf = p_select * s.pdf + (1.0 - p_select) * p_o;
            if !(pdf > 0.0) {
                return None;
            }
            s.weight =
                (s.weight * (p_select * s.pdf) + f_o * ((1.0 - p_select) * s.wo.z.abs())) * (1.0 / pdf);
            s.pdf = pdf;
            return Some(s);
        }
        if s.flags.is_delta() {
            // f_δ/P(select): the blend factor and the selection probability cancel.
            s.pdf *= p_select;
            return Some(s);
        }
        if !self.pdf_is_exact() {
            // A child's pdf is for MIS only: no f/pdf may be formed. The chosen child's exact
            // weight is the mixture's (blend factor over selection probability = 1); the
            // reported pdf is the mixture's, as `pdf` returns it, for the MIS weights.
            s.pdf = self.pdf(ctx, wi, s.wo, wl);
            return (s.pdf > 0.0).then_some(s);
        }
        // Smooth: one-sample mixture over both children at the sampled direction.
        let (f, pdf) = self.eval_pdf(ctx, wi, s.wo, wl);
        if pdf <= 0.0 {
            return None;
        }
        // A black result is still returned (this blend may itself be a mixture's child).
        s.weight = f * (s.wo.z.abs() / pdf);
        s.pdf = pdf;
        Some(s)
    }

    fn null_transmission(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        let w = self.w();
        let t0 = self.bsdf0.null_transmission(wi, wl);
        let t1 = self.bsdf1.null_transmission(wi, wl);
        if t0.is_none() && t1.is_none() {
            return None;
        }
        Some(t0.unwrap_or(SampledSpectrum::ZERO) * (1.0 - w) + t1.unwrap_or(SampledSpectrum::ZERO) * w)
    }

    /// (1 − w)·M0 + w·M1 (both children answer in the same implicit bases).
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        let w = self.w();
        let mut f = Mueller::ZERO;
        if w < 1.0 {
            f += self.bsdf0.eval_mueller(ctx, wi, wo, wl) * (1.0 - w);
        }
        if w > 0.0 {
            f += self.bsdf1.eval_mueller(ctx, wi, wo, wl) * w;
        }
        f
    }

    /// [`Bsdf::sample`]'s lobe choice and mixture weight with Mueller matrices.
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        let w = self.w();
        let chosen_is_1 = u1 < w;
        let (chosen, p_select, u1) = if chosen_is_1 {
            (self.bsdf1, w, u1 / w)
        } else {
            (self.bsdf0, 1.0 - w, (u1 - w) / (1.0 - w))
        };
        let u1 = u1.clamp(0.0, 1.0 - f32::EPSILON / 2.0);
        let mut s = chosen.sample_mueller(ctx, wi, u1, u2, wl)?;
        if s.flags.is_delta() && self.mitsuba_delta_pdf && p_select < 1.0 {
            // As in `sample`; both children answer in the same implicit bases.
            let other = self.other(chosen_is_1);
            let p_o = other.pdf(ctx, wi, s.wo, wl);
            let pdf = p_select * s.pdf + (1.0 - p_select) * p_o;
            if !(pdf > 0.0) {
                return None;
            }
            let f_o = other.eval_mueller(ctx, wi, s.wo, wl);
            s.weight = s.weight * (p_select * s.pdf / pdf) + f_o * ((1.0 - p_select) * s.wo.z.abs() / pdf);
            s.pdf = pdf;
            return Some(s);
        }
        if s.flags.is_delta() {
            s.pdf *= p_select;
            return Some(s);
        }
        let pdf = self.pdf(ctx, wi, s.wo, wl);
        if pdf <= 0.0 {
            return None;
        }
        // With a stochastic child the chosen child's exact throughput stays, as in `sample`.
        if self.pdf_is_exact() {
            s.weight = self.eval_mueller(ctx, wi, s.wo, wl) * (s.wo.z.abs() / pdf);
        }
        s.pdf = pdf;
        Some(s)
    }

    fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        let w = self.w();
        let t0 = self.bsdf0.null_transmission_mueller(wi, wl);
        let t1 = self.bsdf1.null_transmission_mueller(wi, wl);
        if t0.is_none() && t1.is_none() {
            return None;
        }
        Some(t0.unwrap_or(Mueller::ZERO) * (1.0 - w) + t1.unwrap_or(Mueller::ZERO) * w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::{Conductor, Dielectric, Diffuse, Plastic, ThinDielectric, TwoSided};
    use crate::spectra::Spectrum;
    use std::f32::consts::FRAC_1_PI;

    fn dir(theta_deg: f32) -> Vec3 {
        let t = theta_deg.to_radians();
        Vec3::new(t.sin(), 0.0, t.cos())
    }

    /// Fixed-seed uniforms in [0, 1) (the core's Weyl sequence hashed by `mix64`).
    fn uniforms(seed: u64) -> impl FnMut() -> f32 {
        let mut r = crate::hash::WeylHash(seed);
        move || r.next_f32()
    }

    /// Mean and standard error of the sample weight at 550 nm.
    fn albedo(b: &dyn Bsdf, ctx: &BsdfContext, wi: Vec3, n: usize, seed: u64) -> (f64, f64) {
        let mut u = uniforms(seed);
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let mut wl = SampledWavelengths::fixed(550.0);
            let (u1, u2) = (u(), Vec2::new(u(), u()));
            let w = b
                .sample(ctx, wi, u1, u2, &mut wl)
                .map_or(0.0, |s| s.weight[0] as f64);
            sum += w;
            sum2 += w * w;
        }
        let mean = sum / n as f64;
        (mean, ((sum2 / n as f64 - mean * mean) / n as f64).sqrt())
    }

    /// A stand-in for a stochastic model: a Lambertian whose `pdf` is only an approximation
    /// (twice the true density, as an MIS-only pdf may be), with exact sample weights.
    struct ApproximatePdf(Diffuse);

    impl Bsdf for ApproximatePdf {
        fn flags(&self) -> BsdfFlags {
            self.0.flags()
        }
        fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
            self.0.eval(ctx, wi, wo, wl)
        }
        fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
            2.0 * self.0.pdf(ctx, wi, wo, wl)
        }
        fn sample(
            &self,
            ctx: &BsdfContext,
            wi: Vec3,
            u1: f32,
            u2: Vec2,
            wl: &mut SampledWavelengths,
        ) -> Option<BsdfSample> {
            self.0.sample(ctx, wi, u1, u2, wl)
        }
        fn pdf_is_exact(&self) -> bool {
            false
        }
    }

    #[test]
    fn a_blend_with_a_stochastic_child_keeps_the_exact_sample_weights() {
        // Forming f·cos/pdf with an MIS-only pdf would halve this child's contribution; the
        // blend must keep the chosen child's exact throughput instead.
        let walk = ApproximatePdf(Diffuse::new(Spectrum::Constant(0.8)));
        let grey = Diffuse::new(Spectrum::Constant(0.2));
        let blend = BlendBsdf::new(0.3, &grey, &walk);
        assert!(!blend.pdf_is_exact() && !TwoSided::new(&blend).pdf_is_exact());
        let expect = 0.7 * 0.2 + 0.3 * 0.8;
        for deg in [0.0f32, 60.0] {
            let (mean, se) = albedo(&blend, &BsdfContext::radiance(), dir(deg), 100_000, 9);
            assert!(
                (mean - expect).abs() < 4.0 * se,
                "{deg}°: {mean} ± {se} vs {expect}"
            );
        }
    }

    /// `mitsuba_delta_pdf` reproduces Mitsuba 3.9.1's measured albedos of the same blend and the
    /// closed form of its estimator: the mirror outcome (probability ½) weighs
    /// ½ / (½ + ½ cos θ/π), so the albedo is ½ / (1 + cos θ/π).
    #[test]
    fn mitsuba_delta_pdf_reproduces_mitsubas_biased_albedo() {
        let mirror = Conductor::mirror();
        let black = Diffuse::new(Spectrum::Constant(0.0));
        let blend = BlendBsdf::new(0.5, &mirror, &black).with_mitsuba_delta_pdf(true);
        let ctx = BsdfContext::radiance();
        for (deg, mitsuba) in [(0.0f32, 0.379), (45.0, 0.408), (80.0, 0.474)] {
            let closed_form = 0.5 / (1.0 + deg.to_radians().cos() as f64 * FRAC_1_PI as f64);
            let (mean, se) = albedo(&blend, &ctx, dir(deg), 100_000, 3);
            assert!(
                (mean - closed_form).abs() < 4.0 * se,
                "θ {deg}: {mean} ± {se} vs {closed_form}"
            );
            // Mitsuba's figures are given to three decimals.
            assert!(
                (mean - mitsuba).abs() < 4.0 * se + 5e-4,
                "θ {deg}: {mean} vs Mitsuba {mitsuba}"
            );
        }
        // Smooth outcomes are the exact blend's: the same sample as without the switch.
        let mut wl = SampledWavelengths::fixed(550.0);
        let grey = Diffuse::new(Spectrum::Constant(0.5));
        let exact = BlendBsdf::new(0.5, &mirror, &grey);
        let s0 = exact
            .sample(&ctx, dir(30.0), 0.25, Vec2::new(0.3, 0.7), &mut wl)
            .unwrap();
        let s1 = exact
            .with_mitsuba_delta_pdf(true)
            .sample(&ctx, dir(30.0), 0.25, Vec2::new(0.3, 0.7), &mut wl)
            .unwrap();
        assert!(!s0.flags.is_delta());
        assert_eq!((s0.wo, s0.weight[0], s0.pdf), (s1.wo, s1.weight[0], s1.pdf));
    }

    #[test]
    fn mirror_black_diffuse_half_blend_has_albedo_half_unlike_mitsuba_0_379() {
        // Mitsuba 3.9.1 (measured) gives 0.379 / 0.408 / 0.474 at 0° / 45° / 80°.
        let mirror = Conductor::mirror();
        let black = Diffuse::new(Spectrum::Constant(0.0));
        let blend = BlendBsdf::new(0.5, &mirror, &black);
        let ctx = BsdfContext::radiance();
        for (deg, mitsuba) in [(0.0f32, 0.379), (45.0, 0.408), (80.0, 0.474)] {
            let (mean, se) = albedo(&blend, &ctx, dir(deg), 100_000, 3);
            assert!((mean - 0.5).abs() < 4.0 * se, "θ {deg}: {mean} ± {se}");
            assert!(
                (mean - mitsuba).abs() > 8.0 * se,
                "differs from Mitsuba's biased value"
            );
        }
        // The delta outcome: weight = the mirror's own (1), pdf = P(select) = 0.5.
        let mut wl = SampledWavelengths::fixed(550.0);
        let s = blend
            .sample(&ctx, dir(30.0), 0.75, Vec2::new(0.3, 0.7), &mut wl)
            .unwrap();
        assert_eq!(
            (s.flags, s.weight[0], s.pdf),
            (BsdfFlags::DELTA_REFLECTION, 1.0, 0.5)
        );
        // The black diffuse child still proposes its direction, with zero weight (the
        // `Bsdf::sample` contract that keeps mixtures unbiased).
        let black_sample = blend
            .sample(&ctx, dir(30.0), 0.25, Vec2::new(0.3, 0.7), &mut wl)
            .expect("a smooth sample is returned even when black");
        assert_eq!(black_sample.flags, BsdfFlags::DIFFUSE_REFLECTION);
        assert!(black_sample.weight.is_black() && black_sample.pdf > 0.0);
    }

    #[test]
    fn eval_and_pdf_are_linear_blends() {
        let d0 = Diffuse::new(Spectrum::Constant(0.2));
        let p1 = Plastic::new(Spectrum::Constant(0.8), 1.5, 1.0, true, Spectrum::Constant(1.0));
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(550.0);
        let (wi, wo) = (dir(30.0), Vec3::new(-0.3, 0.5, 0.81).normalize());
        for w in [0.0f32, 0.2, 0.5, 1.0, 1.7, -0.3] {
            let b = BlendBsdf::new(w, &d0, &p1);
            let wc = w.clamp(0.0, 1.0);
            let f = b.eval(&ctx, wi, wo, &wl)[0];
            let expect = (1.0 - wc) * d0.eval(&ctx, wi, wo, &wl)[0] + wc * p1.eval(&ctx, wi, wo, &wl)[0];
            assert!((f - expect).abs() < 1e-7, "w {w}");
            let p = b.pdf(&ctx, wi, wo, &wl);
            let expect = (1.0 - wc) * d0.pdf(&ctx, wi, wo, &wl) + wc * p1.pdf(&ctx, wi, wo, &wl);
            assert!((p - expect).abs() < 1e-7);
            let (fe, pe) = b.eval_pdf(&ctx, wi, wo, &wl);
            assert!((fe[0] - f).abs() < 1e-7 && (pe - p).abs() < 1e-7);
        }
    }

    #[test]
    fn smooth_weight_is_blend_eval_over_blend_pdf_and_albedo_is_linear() {
        // Mitsuba blendbsdf test04 pattern, and the albedo of diffuse + plastic at w = 0.2 is
        // 0.8·0.3 + 0.2·a_plastic.
        let d0 = Diffuse::new(Spectrum::Constant(0.3));
        let p1 = Plastic::new(Spectrum::Constant(0.8), 1.5, 1.0, true, Spectrum::Constant(1.0));
        let b = BlendBsdf::new(0.2, &d0, &p1);
        let ctx = BsdfContext::radiance();
        let mut u = uniforms(5);
        for _ in 0..2000 {
            let wi = dir(60.0 * u());
            let mut wl = SampledWavelengths::fixed(550.0);
            let Some(s) = b.sample(&ctx, wi, u(), Vec2::new(u(), u()), &mut wl) else {
                continue;
            };
            if s.flags.is_delta() {
                assert_eq!(s.flags, BsdfFlags::DELTA_REFLECTION);
                continue;
            }
            let (f, pdf) = b.eval_pdf(&ctx, wi, s.wo, &wl);
            assert!((s.pdf - pdf).abs() <= 1e-6 * pdf);
            assert!((s.weight[0] - f[0] * s.wo.z / pdf).abs() <= 1e-5 * s.weight[0]);
        }
        let wi = dir(45.0);
        let (a_p, se_p) = albedo(&p1, &ctx, wi, 100_000, 8);
        let (a_b, se_b) = albedo(&b, &ctx, wi, 100_000, 9);
        let expect = 0.8 * 0.3 + 0.2 * a_p;
        let se = (se_b * se_b + (0.2 * se_p).powi(2)).sqrt();
        assert!((a_b - expect).abs() < 4.0 * se, "{a_b} vs {expect} ± {se}");
    }

    #[test]
    fn delta_plus_delta_and_glass_blends_conserve_energy() {
        // Same-measure mixes: mirror + thin glass; lossless in importance mode ⇒ albedo 1 with
        // per-sample weights exactly 1.
        let mirror = Conductor::mirror();
        let sheet = ThinDielectric::default();
        let glass = Dielectric::default();
        let ctx = BsdfContext::importance();
        for (b0, b1) in [(&mirror as &dyn Bsdf, &sheet as &dyn Bsdf), (&glass, &sheet)] {
            let b = BlendBsdf::new(0.3, b0, b1);
            let mut u = uniforms(1);
            for deg in [0.0f32, 50.0, 85.0] {
                for _ in 0..200 {
                    let mut wl = SampledWavelengths::fixed(550.0);
                    let s = b
                        .sample(&ctx, dir(deg), u(), Vec2::new(u(), u()), &mut wl)
                        .unwrap();
                    assert!((s.weight[0] - 1.0).abs() < 1e-6 && s.flags.is_delta());
                }
            }
        }
        // Null transmission blends linearly, an opaque child contributing 0.
        let d = Diffuse::default();
        let wl = SampledWavelengths::fixed(550.0);
        let t = BlendBsdf::new(0.25, &d, &sheet)
            .null_transmission(Vec3::Z, &wl)
            .unwrap()[0];
        assert!((t - 0.25 * 0.922086).abs() < 1e-6);
        assert!(
            BlendBsdf::new(0.25, &d, &mirror)
                .null_transmission(Vec3::Z, &wl)
                .is_none()
        );
    }

    #[test]
    fn diffuse_plus_diffuse_is_exact() {
        // Same-measure smooth mixes are unbiased (Mitsuba 3.9.1 too); every weight is the blended ρ.
        let a = Diffuse::new(Spectrum::Constant(0.2));
        let c = Diffuse::new(Spectrum::Constant(0.9));
        let b = BlendBsdf::new(0.5, &a, &c);
        let ctx = BsdfContext::radiance();
        let mut u = uniforms(2);
        for _ in 0..500 {
            let mut wl = SampledWavelengths::fixed(550.0);
            let s = b
                .sample(&ctx, dir(20.0), u(), Vec2::new(u(), u()), &mut wl)
                .unwrap();
            assert!((s.weight[0] - 0.55).abs() < 1e-6);
            assert!((s.pdf - s.wo.z * FRAC_1_PI).abs() < 1e-6);
        }
    }

    #[test]
    fn blend_of_black_and_white_diffuse_is_half() {
        // Regression: a black diffuse child that dropped its (zero-weight) samples made this
        // blend 0.25 instead of 0.5: the white child's light at the black child's directions
        // was lost.
        let black = Diffuse::new(Spectrum::Constant(0.0));
        let white = Diffuse::new(Spectrum::Constant(1.0));
        let blend = BlendBsdf::new(0.5, &black, &white);
        let ctx = BsdfContext::radiance();
        let wi = dir(30.0);
        let (n, mut sum) = (64, 0.0f64);
        for i in 0..n {
            for j in 0..n {
                for k in 0..2 {
                    let u2 = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let mut wl = SampledWavelengths::fixed(550.0);
                    if let Some(s) = blend.sample(&ctx, wi, 0.25 + 0.5 * k as f32, u2, &mut wl) {
                        sum += s.weight[0] as f64;
                    }
                }
            }
        }
        // Every weight is exactly 0.5 (f·cos/pdf with both pdfs cos θ/π), so the mean is exact.
        let albedo = sum / (2 * n * n) as f64;
        assert!((albedo - 0.5).abs() < 1e-6, "albedo {albedo}");
    }
}
