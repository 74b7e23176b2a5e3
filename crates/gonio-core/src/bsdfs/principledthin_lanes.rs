//! [`PrincipledThin`] on `N` lanes: every float parameter per lane (as a texture drives it),
//! the base colour at each lane's wavelengths. Formula for formula the scalar `eval_pdf_cos`
//! and `sample` of [`super`], each `if` of the scalar model a per-lane mask; lanes agree with
//! the scalar model at their own parameters to rounding (`tests/lanes/principled.rs`).
//!
//! Nothing of the scalar model is out of the lanes' reach (η is a real number; nothing
//! terminates secondary wavelengths), so [`PrincipledThin::lanes`] always succeeds.

use super::super::principled_common_lanes::{
    choose_lobe, cie_y_lanes, diffuse_shape, facet_compatible, ggx_alphas, schlick_fresnel_spectrum,
    schlick_r0, sheen_shape, tint_color, tint_luminance,
};
use super::{PrincipledThin, PrincipledThinRates};
use crate::bsdf::{BsdfContext, BsdfFlags};
use crate::lanes::fresnel::fresnel_dielectric;
use crate::lanes::warp::square_to_cosine_hemisphere;
use crate::lanes::{BsdfSamples, F32s, Isa, Mask, MicrofacetLanes, Portable, SampledSpectra, Vec3s};
use crate::microfacet::MicrofacetKind;
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use std::f32::consts::FRAC_1_PI;

/// [`PrincipledThin`] for `N` lanes, each with its own wavelengths and parameters.
#[derive(Clone, Copy, Debug)]
pub struct PrincipledThinLanes<'a, const N: usize, X: Isa = Portable> {
    /// c per lane and wavelength.
    pub base_color: SampledSpectra<N, X>,
    /// r per lane.
    pub roughness: F32s<N, X>,
    /// Anisotropy per lane.
    pub anisotropic: F32s<N, X>,
    /// s per lane.
    pub spec_trans: F32s<N, X>,
    /// η of the sheet per lane.
    pub eta: F32s<N, X>,
    /// Specular tint per lane.
    pub spec_tint: F32s<N, X>,
    /// Sheen weight per lane.
    pub sheen: F32s<N, X>,
    /// Sheen tint per lane.
    pub sheen_tint: F32s<N, X>,
    /// Fake-subsurface blend per lane.
    pub flatness: F32s<N, X>,
    /// Mitsuba's `diff_trans` per lane.
    pub diff_trans: F32s<N, X>,
    /// Lobe-selection rates (floats in Mitsuba, shared by the lanes).
    pub rates: PrincipledThinRates,
    /// Each lane's wavelengths (ȳ is looked up at them only where some lane tints; a texture
    /// may replace `base_color` without touching them), borrowed: a copy of 16 lanes' sets is
    /// 512 bytes per call (at 8 lanes the copy was 24 % of this kernel's instructions at its
    /// defaults, callgrind).
    wavelengths: &'a [SampledWavelengths; N],
}

impl PrincipledThin {
    /// This model at each lane's wavelengths, its parameters in every lane.
    #[inline(always)]
    pub fn lanes<'a, const N: usize, X: Isa>(
        &self,
        wl: &'a [SampledWavelengths; N],
    ) -> PrincipledThinLanes<'a, N, X> {
        PrincipledThinLanes {
            base_color: self.base_color.sample_lanes(wl),
            roughness: F32s::splat(self.roughness),
            anisotropic: F32s::splat(self.anisotropic),
            spec_trans: F32s::splat(self.spec_trans),
            eta: F32s::splat(self.eta),
            spec_tint: F32s::splat(self.spec_tint),
            sheen: F32s::splat(self.sheen),
            sheen_tint: F32s::splat(self.sheen_tint),
            flatness: F32s::splat(self.flatness),
            diff_trans: F32s::splat(self.diff_trans),
            rates: self.rates,
            wavelengths: wl,
        }
    }
}

impl<const N: usize, X: Isa> PrincipledThinLanes<'_, N, X> {
    /// Lane `k` as the scalar model (at lane `k`'s wavelengths).
    pub fn lane(&self, k: usize) -> PrincipledThin<SampledSpectrum> {
        PrincipledThin {
            base_color: self.base_color.lane(k),
            roughness: self.roughness.lane(k),
            anisotropic: self.anisotropic.lane(k),
            spec_trans: self.spec_trans.lane(k),
            eta: self.eta.lane(k),
            spec_tint: self.spec_tint.lane(k),
            sheen: self.sheen.lane(k),
            sheen_tint: self.sheen_tint.lane(k),
            flatness: self.flatness.lane(k),
            diff_trans: self.diff_trans.lane(k),
            rates: self.rates,
        }
    }

    /// The reflection's GGX and the transmission's, of roughness (0.65 η − 0.35) r, per lane.
    #[inline(always)]
    fn distributions(&self) -> (MicrofacetLanes<N, X>, MicrofacetLanes<N, X>) {
        let (ax, ay) = ggx_alphas(self.roughness, self.anisotropic);
        let r_t = (0.65 * self.eta - 0.35) * self.roughness;
        let (tx, ty) = ggx_alphas(r_t, self.anisotropic);
        (
            MicrofacetLanes::new(MicrofacetKind::Ggx, ax, ay, true),
            MicrofacetLanes::new(MicrofacetKind::Ggx, tx, ty, true),
        )
    }

    /// The scalar `probs` per lane: (specular reflection, specular transmission, diffuse
    /// reflection, diffuse transmission).
    #[inline(always)]
    fn probs(&self, ctx: &BsdfContext) -> [F32s<N, X>; 4] {
        let en = |l: BsdfFlags| if ctx.is_enabled(l) { 1.0f32 } else { 0.0 };
        let (s, t, r) = (self.spec_trans, 0.5 * self.diff_trans, &self.rates);
        [
            en(BsdfFlags::GLOSSY_REFLECTION) * s * r.specular_reflectance * 0.5,
            en(BsdfFlags::GLOSSY_TRANSMISSION) * s * r.specular_transmittance * 0.5,
            en(BsdfFlags::DIFFUSE_REFLECTION) * r.diffuse_reflectance * (F32s::ONE - s) * (F32s::ONE - t),
            en(BsdfFlags::DIFFUSE_TRANSMISSION) * r.diffuse_transmittance * (F32s::ONE - s) * t,
        ]
    }

    /// f·|cos θo| and the pdf per lane, the lobes of `ctx` (the scalar `eval_pdf_cos`).
    #[inline(always)]
    fn eval_pdf_cos(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        wo: Vec3s<N, X>,
    ) -> (SampledSpectra<N, X>, F32s<N, X>) {
        let nonzero = wi.z.ne(0.0) & wo.z.ne(0.0);
        // The sheet is the same from both sides: turn ωi to +z and ωo with it.
        let flip = wi.z.lt(0.0).select(F32s::splat(-1.0), F32s::ONE);
        let (wi, wo) = (wi * flip, wo * flip);
        let (ci, co) = (wi.z, wo.z);
        let reflect = co.gt(0.0);
        let wo_r = Vec3s::new(wo.x, wo.y, co.abs());
        let h = (wi + wo_r).normalize();
        let active = nonzero & h.is_finite();
        let (s, t) = (self.spec_trans, 0.5 * self.diff_trans);
        let c = self.base_color;
        let spec_tinted = self.spec_tint.ne(0.0);
        let sheen_tinted = self.sheen_tint.ne(0.0);
        let tinted = spec_tinted | sheen_tinted;
        let lum = if tinted.any() {
            tinted.select(tint_luminance(c, cie_y_lanes(self.wavelengths)), F32s::ONE)
        } else {
            F32s::ONE
        };
        let mut value = SampledSpectra::ZERO;
        let probs = self.probs(ctx);
        let total = probs[0] + probs[1] + probs[2] + probs[3];
        let has_total = !total.is_nan() & total.gt(0.0);
        let (p_dr, p_dt) = (probs[2] / total, probs[3] / total);
        let mut pdf = F32s::ZERO;
        // The glossy lobes (the dielectric sheet), only where some lane has them: their masks,
        // D, G1(wi) (eval or pdf) and F.
        let specular = s.gt(0.0);
        if specular.any() {
            let refl_ok = active & reflect & facet_compatible(h, wi, wo, ci, true);
            let refr_ok = active & !reflect & facet_compatible(h, wi, wo, ci, false);
            let (p_sr, p_st) = (probs[0] / total, probs[1] / total);
            let (m_r, m_t) = (refl_ok & p_sr.gt(0.0), refr_ok & p_st.gt(0.0));
            let (spec_r, spec_t) = (refl_ok & specular, refr_ok & specular);
            let (distr_r, distr_t) = self.distributions();
            let cos_ih = wi.dot(h);
            let fr = fresnel_dielectric(cos_ih, self.eta).reflectance;
            let dwh_dwo = (4.0 * wo_r.dot(h)).recip().abs();
            if (spec_r | m_r).any() {
                let (d_r, g1i_r) = (distr_r.d(h), distr_r.g1(wi, h));
                if ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) && spec_r.any() {
                    let mut f_t = SampledSpectra([fr; N_SPECTRUM_SAMPLES]);
                    if spec_tinted.any() {
                        let r0 = tint_color(c, lum) * schlick_r0(self.eta);
                        let f_s = schlick_fresnel_spectrum(r0, cos_ih, self.eta);
                        for i in 0..N_SPECTRUM_SAMPLES {
                            f_t.0[i] = spec_tinted.select(fr + (f_s.0[i] - fr) * self.spec_tint, fr);
                        }
                    }
                    let dg = d_r * (g1i_r * distr_r.g1(wo, h));
                    value = value + (f_t * (s * dg / (4.0 * ci))).masked(spec_r);
                }
                if m_r.any() {
                    pdf += m_r.and_then(p_sr * distr_r.pdf_from(wi, h, d_r, g1i_r) * dwh_dwo);
                }
            }
            if (spec_t | m_t).any() {
                let (d_t, g1i_t) = (distr_t.d(h), distr_t.g1(wi, h));
                if ctx.is_enabled(BsdfFlags::GLOSSY_TRANSMISSION) && spec_t.any() {
                    let dg = d_t * (g1i_t * distr_t.g1(wo, h));
                    value = value + (c * (s * (F32s::ONE - fr) * dg / (4.0 * ci))).masked(spec_t);
                }
                if m_t.any() {
                    pdf += m_t.and_then(p_st * distr_t.pdf_from(wi, h, d_t, g1i_t) * dwh_dwo);
                }
            }
        }
        let cos_d = h.dot(wo);
        let diffuse = active & reflect & s.lt(1.0) & t.lt(1.0);
        if ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION) && diffuse.any() {
            let shape = diffuse_shape(ci, co, cos_d, self.roughness, self.flatness);
            let k = (F32s::ONE - s) * co * FRAC_1_PI * (F32s::ONE - t) * shape;
            value = value + (c * k).masked(diffuse);
            let sheen = diffuse & self.sheen.gt(0.0);
            if sheen.any() {
                let tint =
                    SampledSpectra::select(sheen_tinted, tint_color(c, lum), SampledSpectra::splat(1.0));
                let k = self.sheen * (F32s::ONE - s) * (F32s::ONE - t) * co;
                value = value + (sheen_shape(cos_d, self.sheen_tint, tint) * k).masked(sheen);
            }
        }
        let diff_t = active & !reflect & s.lt(1.0) & t.gt(0.0);
        if ctx.is_enabled(BsdfFlags::DIFFUSE_TRANSMISSION) && diff_t.any() {
            let k = (F32s::ONE - s) * t * FRAC_1_PI * co.abs();
            value = value + (c * k).masked(diff_t);
        }

        // The rest of the pdf of `sample`: the cosine densities of ±ωo (p_dr above, p_dt below).
        let cos_pdf = wo.z.abs() * FRAC_1_PI;
        pdf += reflect.select(p_dr * cos_pdf, wo.z.lt(0.0).and_then(p_dt * cos_pdf));
        let pdf = (active & has_total & pdf.is_finite()).and_then(pdf);
        (value.masked(active), pdf)
    }

    /// f(wi, wo) per lane (the scalar [`crate::Bsdf::eval`]): [`Self::eval_pdf`]'s value; the pdf's
    /// arithmetic, unused, is dropped by the compiler once this is inlined.
    #[inline(always)]
    pub fn eval(&self, ctx: &BsdfContext, wi: Vec3s<N, X>, wo: Vec3s<N, X>) -> SampledSpectra<N, X> {
        self.eval_pdf(ctx, wi, wo).0
    }

    /// f(wi, wo) and the pdf of `sample` per lane (the scalar [`crate::Bsdf::eval_pdf`]).
    #[inline(always)]
    pub fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        wo: Vec3s<N, X>,
    ) -> (SampledSpectra<N, X>, F32s<N, X>) {
        let (v, pdf) = self.eval_pdf_cos(ctx, wi, wo);
        let mut black = Mask::ALL;
        for i in 0..v.0.len() {
            black = black & v.0[i].eq(0.0);
        }
        let cos = wo.z.abs();
        (v.map(|x| (!black).and_then(x / cos)), pdf)
    }

    /// A direction per lane (the scalar [`crate::Bsdf::sample`]): each lane picks its lobe with
    /// `u1`; the two glossy lobes share one visible-normal sampling (each lane with its lobe's
    /// roughness), the diffuse ones one cosine sampling, each only if some lane needs it.
    #[inline(always)]
    pub fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        u1: F32s<N, X>,
        u2: [F32s<N, X>; 2],
    ) -> BsdfSamples<N, X> {
        let flip = wi.z.lt(0.0).select(F32s::splat(-1.0), F32s::ONE);
        let wi_f = wi * flip;
        let choice = choose_lobe(self.probs(ctx), u1);
        let [spec_r, spec_t, diff_r, diff_t] = choice.chosen;
        let mut ok = choice.valid & wi.z.ne(0.0);
        let mut wo_f = Vec3s::default();
        let glossy = spec_r | spec_t;
        if glossy.any() {
            let (distr_r, distr_t) = self.distributions();
            let distr = MicrofacetLanes {
                alpha_u: spec_t.select(distr_t.alpha_u, distr_r.alpha_u),
                alpha_v: spec_t.select(distr_t.alpha_v, distr_r.alpha_v),
                ..distr_r
            };
            let (m, _) = distr.sample(wi_f, u2);
            let wo = wi_f.reflect_about(m).normalize();
            let wo = Vec3s::new(wo.x, wo.y, spec_t.select(-wo.z, wo.z));
            let fc_r = facet_compatible(m, wi_f, wo, wi_f.z, true);
            let fc_t = facet_compatible(m, wi_f, wo, wi_f.z, false);
            let up = wo.z.gt(0.0);
            let fine = (spec_r & fc_r & up) | (spec_t & fc_t & !up);
            ok = ok & (!glossy | fine);
            wo_f = glossy.select3(wo, wo_f);
        }
        let diffuse = diff_r | diff_t;
        if diffuse.any() {
            let w = square_to_cosine_hemisphere(u2);
            wo_f = diff_r.select3(w, diff_t.select3(-w, wo_f));
        }
        let wo = wo_f * flip;
        let (v, pdf) = self.eval_pdf_cos(ctx, wi, wo);
        let valid = ok & pdf.gt(0.0);
        BsdfSamples {
            valid,
            wo,
            weight: v.map(|x| valid.and_then(x / pdf)),
            pdf,
            eta: F32s::ONE,
            flags: std::array::from_fn(|k| {
                if spec_t.test(k) {
                    BsdfFlags::GLOSSY_TRANSMISSION
                } else if diff_r.test(k) {
                    BsdfFlags::DIFFUSE_REFLECTION
                } else if diff_t.test(k) {
                    BsdfFlags::DIFFUSE_TRANSMISSION
                } else {
                    BsdfFlags::GLOSSY_REFLECTION
                }
            }),
        }
    }
}
