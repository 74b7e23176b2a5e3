//! [`Principled`] on `N` lanes: every float parameter per lane (as a texture drives it), the
//! base colour at each lane's wavelengths. Formula for formula the scalar `eval_pdf_cos` and
//! `sample` of [`super`], each `if` of the scalar model a per-lane mask; lanes agree with the
//! scalar model at their own parameters to rounding (`tests/lanes/principled.rs`).
//!
//! The scalar model has no feature the lanes cannot express (η is a real number, not a
//! spectrum: nothing terminates secondary wavelengths), so [`Principled::lanes`] always
//! succeeds.

use super::super::principled_common_lanes::{
    Gtr1Lanes, choose_lobe, cie_y_lanes, diffuse_shape, facet_compatible, ggx_alphas, refract_through,
    schlick_fresnel, schlick_fresnel_spectrum, schlick_r0, sheen_shape, smith_ggx1, tint_color,
    tint_luminance,
};
use super::{Principled, PrincipledRates};
use crate::bsdf::{BsdfContext, BsdfFlags, TransportMode};
use crate::lanes::fresnel::fresnel_dielectric;
use crate::lanes::warp::square_to_cosine_hemisphere;
use crate::lanes::{BsdfSamples, F32s, Isa, Mask, MicrofacetLanes, Portable, SampledSpectra, Vec3s};
use crate::microfacet::MicrofacetKind;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use std::f32::consts::FRAC_1_PI;

/// [`Principled`] for `N` lanes, each with its own wavelengths and parameters.
#[derive(Clone, Copy, Debug)]
pub struct PrincipledLanes<'a, const N: usize, X: Isa = Portable> {
    /// c per lane and wavelength.
    pub base_color: SampledSpectra<N, X>,
    /// r per lane.
    pub roughness: F32s<N, X>,
    /// Anisotropy per lane.
    pub anisotropic: F32s<N, X>,
    /// Metallic blend per lane.
    pub metallic: F32s<N, X>,
    /// Transmission blend per lane.
    pub spec_trans: F32s<N, X>,
    /// η = n_int/n_ext per lane.
    pub eta: F32s<N, X>,
    /// Specular tint per lane.
    pub spec_tint: F32s<N, X>,
    /// Sheen weight per lane.
    pub sheen: F32s<N, X>,
    /// Sheen tint per lane.
    pub sheen_tint: F32s<N, X>,
    /// Fake-subsurface blend per lane.
    pub flatness: F32s<N, X>,
    /// Clearcoat weight per lane.
    pub clearcoat: F32s<N, X>,
    /// Clearcoat gloss per lane.
    pub clearcoat_gloss: F32s<N, X>,
    /// Lobe-selection rates (floats in Mitsuba, shared by the lanes).
    pub rates: PrincipledRates,
    /// Each lane's wavelengths (ȳ is looked up at them only where some lane tints; a texture
    /// may replace `base_color` without touching them), borrowed: a copy of 16 lanes' sets is
    /// 512 bytes per call.
    wavelengths: &'a [SampledWavelengths; N],
}

impl Principled {
    /// This model at each lane's wavelengths, its parameters in every lane.
    #[inline(always)]
    pub fn lanes<'a, const N: usize, X: Isa>(
        &self,
        wl: &'a [SampledWavelengths; N],
    ) -> PrincipledLanes<'a, N, X> {
        PrincipledLanes {
            base_color: self.base_color.sample_lanes(wl),
            roughness: F32s::splat(self.roughness),
            anisotropic: F32s::splat(self.anisotropic),
            metallic: F32s::splat(self.metallic),
            spec_trans: F32s::splat(self.spec_trans),
            eta: F32s::splat(self.eta),
            spec_tint: F32s::splat(self.spec_tint),
            sheen: F32s::splat(self.sheen),
            sheen_tint: F32s::splat(self.sheen_tint),
            flatness: F32s::splat(self.flatness),
            clearcoat: F32s::splat(self.clearcoat),
            clearcoat_gloss: F32s::splat(self.clearcoat_gloss),
            rates: self.rates,
            wavelengths: wl,
        }
    }
}

/// The per-lane quantities of one (wi, wo) that eval and the pdf share.
struct Geometry<const N: usize, X: Isa> {
    active: Mask<N, X>,
    front: Mask<N, X>,
    reflect: Mask<N, X>,
    eta_path: F32s<N, X>,
    h: Vec3s<N, X>,
    denom2: F32s<N, X>,
    cos_ih: F32s<N, X>,
    cos_oh: F32s<N, X>,
}

impl<const N: usize, X: Isa> PrincipledLanes<'_, N, X> {
    /// Lane `k` as the scalar model (at lane `k`'s wavelengths).
    pub fn lane(&self, k: usize) -> Principled<SampledSpectrum> {
        Principled {
            base_color: self.base_color.lane(k),
            roughness: self.roughness.lane(k),
            anisotropic: self.anisotropic.lane(k),
            metallic: self.metallic.lane(k),
            spec_trans: self.spec_trans.lane(k),
            eta: self.eta.lane(k),
            spec_tint: self.spec_tint.lane(k),
            sheen: self.sheen.lane(k),
            sheen_tint: self.sheen_tint.lane(k),
            flatness: self.flatness.lane(k),
            clearcoat: self.clearcoat.lane(k),
            clearcoat_gloss: self.clearcoat_gloss.lane(k),
            rates: self.rates,
        }
    }

    /// The main lobes' GGX per lane (visible normals).
    #[inline(always)]
    fn spec_distribution(&self) -> MicrofacetLanes<N, X> {
        let (ax, ay) = ggx_alphas(self.roughness, self.anisotropic);
        MicrofacetLanes::new(MicrofacetKind::Ggx, ax, ay, true)
    }

    /// (w_brdf, w_bsdf) per lane.
    #[inline(always)]
    fn weights(&self) -> (F32s<N, X>, F32s<N, X>) {
        let dm = F32s::ONE - self.metallic;
        (dm * (F32s::ONE - self.spec_trans), dm * self.spec_trans)
    }

    /// The scalar `lobe_probs` per lane: (diffuse, clearcoat, transmission, reflection).
    #[inline(always)]
    fn lobe_probs(
        &self,
        ctx: &BsdfContext,
        front: Mask<N, X>,
        f: F32s<N, X>,
        w_brdf: F32s<N, X>,
        w_bsdf: F32s<N, X>,
    ) -> [F32s<N, X>; 4] {
        let en = |l: BsdfFlags| if ctx.is_enabled(l) { 1.0f32 } else { 0.0 };
        let (g_r, g_t, d_r) = (
            en(BsdfFlags::GLOSSY_REFLECTION),
            en(BsdfFlags::GLOSSY_TRANSMISSION),
            en(BsdfFlags::DIFFUSE_REFLECTION),
        );
        let r = &self.rates;
        let one_minus_f = F32s::ONE - f;
        let back = !front & w_bsdf.gt(0.0);
        [
            front.and_then(d_r * w_brdf * r.diffuse),
            front.and_then(g_r * 0.25 * self.clearcoat * r.clearcoat),
            front.select(
                g_t * r.main_specular * w_bsdf * one_minus_f,
                back.and_then(g_t * one_minus_f),
            ),
            front.select(
                g_r * r.main_specular * (F32s::ONE - w_bsdf * one_minus_f),
                back.and_then(g_r * f),
            ),
        ]
    }

    /// The scalar `half_vector` and the masks of a (wi, wo) pair.
    #[inline(always)]
    fn geometry(&self, wi: Vec3s<N, X>, wo: Vec3s<N, X>) -> Geometry<N, X> {
        let (ci, co) = (wi.z, wo.z);
        let cc = ci * co;
        let (reflect, refract) = (cc.gt(0.0), cc.lt(0.0));
        let front = ci.gt(0.0);
        let eta_path = front.select(self.eta, self.eta.recip());
        // Reflection: ωi + ωo; refraction: ω_ext + η ω_int (only where some lane refracts).
        let mut h = (wi + wo).normalize();
        let mut denom2 = F32s::ZERO;
        if (!reflect).any() {
            let ext = front.select3(wi, wo);
            let int = front.select3(wo, wi);
            let sum = ext + int * self.eta;
            let len2 = sum.length_squared();
            let len = len2.sqrt();
            let h_t = Vec3s::new(sum.x / len, sum.y / len, sum.z / len);
            let denom2_t = front.select(len2, len2 / (self.eta * self.eta));
            h = reflect.select3(h, h_t);
            denom2 = (!reflect).and_then(denom2_t);
        }
        let h = h.z.lt(0.0).select3(-h, h);
        let active = ci.ne(0.0) & (reflect | refract) & h.is_finite();
        Geometry {
            active,
            front,
            reflect,
            eta_path,
            h,
            denom2,
            cos_ih: wi.dot(h),
            cos_oh: wo.dot(h),
        }
    }

    /// f·|cos θo| and the pdf per lane, the lobes of `ctx` (the scalar `eval_pdf_cos`).
    #[inline(always)]
    fn eval_pdf_cos(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        wo: Vec3s<N, X>,
    ) -> (SampledSpectra<N, X>, F32s<N, X>) {
        let Geometry {
            active,
            front,
            reflect,
            eta_path,
            h,
            denom2,
            cos_ih,
            cos_oh,
        } = self.geometry(wi, wo);
        let (ci, co) = (wi.z, wo.z);
        let (w_brdf, w_bsdf) = self.weights();
        // F at ωi·h, symmetric in (ωi, ωo) as the scalar model's.
        let cos_f = reflect.select(0.5 * (cos_ih + cos_oh), front.select(cos_ih, cos_oh));
        let f_val = fresnel_dielectric(cos_f, self.eta).reflectance;
        let refl_ok = active & reflect & facet_compatible(h, wi, wo, ci, true);
        let refr_ok = active & !reflect & facet_compatible(h, wi, wo, ci, false);
        let distr = self.spec_distribution();
        let d = distr.d(h);
        let g1_wi = distr.g1(wi, h);
        let g = g1_wi * distr.g1(wo, h);
        let c = self.base_color;
        let (en_gr, en_gt, en_dr) = (
            ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION),
            ctx.is_enabled(BsdfFlags::GLOSSY_TRANSMISSION),
            ctx.is_enabled(BsdfFlags::DIFFUSE_REFLECTION),
        );
        let spec_tinted = self.spec_tint.ne(0.0);
        let sheen_tinted = self.sheen_tint.ne(0.0);
        let tinted = spec_tinted | sheen_tinted;
        let lum = if tinted.any() {
            tinted.select(tint_luminance(c, cie_y_lanes(self.wavelengths)), F32s::ONE)
        } else {
            F32s::ONE
        };
        let dm = F32s::ONE - self.metallic;
        let mut value = SampledSpectra::ZERO;

        // Main specular reflection.
        let spec_r = refl_ok & f_val.gt(0.0);
        if en_gr && spec_r.any() {
            let outside = cos_f.ge(0.0);
            let eta_it = outside.select(self.eta, self.eta.recip());
            let mut f_s = SampledSpectra::ZERO;
            let metal = self.metallic.ne(0.0);
            if metal.any() {
                let t = schlick_fresnel_spectrum(c, cos_f, self.eta) * self.metallic;
                f_s = f_s + t.masked(metal);
            }
            if spec_tinted.any() {
                let r0 = tint_color(c, lum) * schlick_r0(eta_it);
                let t = schlick_fresnel_spectrum(r0, cos_f, self.eta) * (dm * self.spec_tint);
                f_s = f_s + t.masked(spec_tinted);
            }
            let dielectric = dm * (F32s::ONE - self.spec_tint) * f_val;
            let fp_back = w_bsdf * f_val;
            let mut fp = f_s;
            for v in fp.0.iter_mut() {
                *v = front.select(*v + dielectric, fp_back);
            }
            value = value + (fp * (d * g / (4.0 * ci.abs()))).masked(spec_r);
        }
        // Main specular transmission.
        let spec_t = refr_ok & w_bsdf.gt(0.0) & f_val.lt(1.0);
        if en_gt && spec_t.any() {
            let scale = match ctx.mode {
                TransportMode::Radiance => (eta_path * eta_path).recip(),
                TransportMode::Importance => F32s::ONE,
            };
            let t = (scale * (F32s::ONE - f_val) * d * g * eta_path * eta_path * cos_ih * cos_oh
                / (ci * denom2))
                .abs();
            let k = w_bsdf * t;
            value = value + c.map(|v| spec_t.and_then(v.safe_sqrt() * k));
        }
        let front_reflect = active & front & reflect;
        // Clearcoat.
        let coat = front_reflect & refl_ok & self.clearcoat.gt(0.0);
        if en_gr && coat.any() {
            let fcc = schlick_fresnel(F32s::splat(0.04), cos_f, self.eta);
            let dcc = Gtr1Lanes::from_gloss(self.clearcoat_gloss).d(h);
            let gcc = smith_ggx1(wi, h, 0.25) * smith_ggx1(wo, h, 0.25);
            let v = coat.and_then(self.clearcoat * 0.25 * fcc * dcc * gcc * co.abs());
            value = value.map(|x| x + v);
        }
        // Diffuse, retro-reflection, fake subsurface, sheen.
        let diffuse = front_reflect & w_brdf.gt(0.0);
        if en_dr && diffuse.any() {
            let shape = diffuse_shape(ci, co, cos_oh, self.roughness, self.flatness);
            let k = w_brdf * co.abs() * FRAC_1_PI * shape;
            value = value + (c * k).masked(diffuse);
            let sheen = diffuse & self.sheen.gt(0.0) & dm.gt(0.0);
            if sheen.any() {
                let tint =
                    SampledSpectra::select(sheen_tinted, tint_color(c, lum), SampledSpectra::splat(1.0));
                let s = sheen_shape(cos_oh, self.sheen_tint, tint) * (self.sheen * dm * co.abs());
                value = value + s.masked(sheen);
            }
        }

        // The pdf of `sample`.
        let probs = self.lobe_probs(ctx, front, f_val, w_brdf, w_bsdf);
        let total = probs[0] + probs[1] + probs[2] + probs[3];
        let has_total = !total.is_nan() & total.gt(0.0);
        let [p_d, p_cc, p_t, p_r] = [
            probs[0] / total,
            probs[1] / total,
            probs[2] / total,
            probs[3] / total,
        ];
        let dwh_dwo = reflect.select(
            (4.0 * cos_oh).recip().abs(),
            (eta_path * eta_path * cos_oh / denom2).abs(),
        );
        let wi_up = front.select3(wi, -wi);
        // G1 is even in its direction: G1(wi_up, h) = G1(wi, h).
        let pdf_m = distr.pdf_from(wi_up, h, d, g1_wi);
        let mut pdf = refl_ok.and_then(p_r * pdf_m * dwh_dwo);
        let coat_pdf = refl_ok & p_cc.gt(0.0);
        if coat_pdf.any() {
            let p = p_cc * Gtr1Lanes::from_gloss(self.clearcoat_gloss).pdf(h) * dwh_dwo;
            pdf += coat_pdf.and_then(p);
        }
        pdf += (active & reflect).and_then(p_d * wo.z.gt(0.0).and_then(wo.z * FRAC_1_PI));
        pdf += refr_ok.and_then(p_t * pdf_m * dwh_dwo);
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
    /// `u1`; each lobe's direction is computed only if some lane picked it.
    #[inline(always)]
    pub fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3s<N, X>,
        u1: F32s<N, X>,
        u2: [F32s<N, X>; 2],
    ) -> BsdfSamples<N, X> {
        let ci = wi.z;
        let front = ci.gt(0.0);
        let (w_brdf, w_bsdf) = self.weights();
        let distr = self.spec_distribution();
        let wi_up = front.select3(wi, -wi);
        let (m, _) = distr.sample(wi_up, u2);
        let fres = fresnel_dielectric(wi.dot(m), self.eta);
        let probs = self.lobe_probs(ctx, front, fres.reflectance, w_brdf, w_bsdf);
        let choice = choose_lobe(probs, u1);
        let [diffuse, coat, trans, refl] = choice.chosen;
        let mut ok = choice.valid & ci.ne(0.0);
        let mut wo = Vec3s::default();
        if diffuse.any() {
            wo = diffuse.select3(square_to_cosine_hemisphere(u2), wo);
        }
        if coat.any() {
            let m_cc = Gtr1Lanes::from_gloss(self.clearcoat_gloss).sample(u2);
            let wo_cc = wi.reflect_about(m_cc).normalize();
            ok = ok & (!coat | facet_compatible(m_cc, wi, wo_cc, ci, true));
            wo = coat.select3(wo_cc, wo);
        }
        if trans.any() {
            let wo_t = refract_through(wi, m, fres.cos_theta_t, fres.eta_ti).normalize();
            let crosses = facet_compatible(m, wi, wo_t, ci, false) & (ci * wo_t.z).lt(0.0);
            ok = ok & (!trans | crosses);
            wo = trans.select3(wo_t, wo);
        }
        if refl.any() {
            let wo_r = wi.reflect_about(m).normalize();
            ok = ok & (!refl | facet_compatible(m, wi, wo_r, ci, true));
            wo = refl.select3(wo_r, wo);
        }
        let side = ci * wo.z;
        ok = ok & side.ne(0.0) & (trans | !side.lt(0.0));
        let (v, pdf) = self.eval_pdf_cos(ctx, wi, wo);
        let valid = ok & pdf.gt(0.0);
        BsdfSamples {
            valid,
            wo,
            weight: v.map(|x| valid.and_then(x / pdf)),
            pdf,
            eta: trans.select(fres.eta_it, F32s::ONE),
            flags: std::array::from_fn(|k| {
                if diffuse.test(k) {
                    BsdfFlags::DIFFUSE_REFLECTION
                } else if trans.test(k) {
                    BsdfFlags::GLOSSY_TRANSMISSION
                } else {
                    BsdfFlags::GLOSSY_REFLECTION
                }
            }),
        }
    }
}
