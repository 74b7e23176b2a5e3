//! The pieces of [`super::principled_common`] on `N` lanes, formula for formula (the same
//! operations in the same order, so that lane `k` agrees with the scalar helper at lane `k`'s
//! arguments to rounding; the transcendental functions are [`crate::lanes::math`]'s).
//!
//! Every function is `#[inline(always)]`: a lane kernel compiled for a vector extension must
//! inline all it calls.

use super::principled_common::cie_y_5nm;
use crate::lanes::math::{ln, powf, sin_cos};
use crate::lanes::{F32s, Isa, Mask, Portable, SampledSpectra, Vec3s};
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledWavelengths};
use std::f32::consts::PI;

/// Schlick's weight (1 − c)⁵ with c clamped to [0, 1], per lane.
#[inline(always)]
pub fn schlick_weight<const N: usize, X: Isa>(cos: F32s<N, X>) -> F32s<N, X> {
    let m = (F32s::ONE - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// [`super::principled_common::schlick_fresnel_weight`] per lane: S(|cos θi|) entering the
/// denser side, S(cos θt) otherwise.
#[inline(always)]
pub fn schlick_fresnel_weight<const N: usize, X: Isa>(
    cos_theta_i: F32s<N, X>,
    eta: F32s<N, X>,
) -> F32s<N, X> {
    let outside = cos_theta_i.ge(0.0);
    let rcp_eta = eta.recip();
    let eta_it = outside.select(eta, rcp_eta);
    let eta_ti = outside.select(rcp_eta, eta);
    let denser = eta_it.gt(1.0);
    let cos_t2 = F32s::ONE - (F32s::ONE - cos_theta_i * cos_theta_i) * eta_ti * eta_ti;
    denser.select(
        schlick_weight(cos_theta_i.abs()),
        schlick_weight(cos_t2.max(0.0).sqrt()),
    )
}

/// Schlick's approximation R0 + (1 − R0) S for an R0 per lane.
#[inline(always)]
pub fn schlick_fresnel<const N: usize, X: Isa>(
    r0: F32s<N, X>,
    cos_theta_i: F32s<N, X>,
    eta: F32s<N, X>,
) -> F32s<N, X> {
    let s = schlick_fresnel_weight(cos_theta_i, eta);
    r0 + (F32s::ONE - r0) * s
}

/// Schlick's approximation per lane and wavelength.
#[inline(always)]
pub fn schlick_fresnel_spectrum<const N: usize, X: Isa>(
    r0: SampledSpectra<N, X>,
    cos_theta_i: F32s<N, X>,
    eta: F32s<N, X>,
) -> SampledSpectra<N, X> {
    let s = schlick_fresnel_weight(cos_theta_i, eta);
    r0.map(|r| r + (F32s::ONE - r) * s)
}

/// R0 = ((η − 1)/(η + 1))² per lane.
#[inline(always)]
pub fn schlick_r0<const N: usize, X: Isa>(eta: F32s<N, X>) -> F32s<N, X> {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// Mitsuba's 5 nm ȳ ([`cie_y_5nm`]) at each lane's wavelengths: what [`tint_luminance`] weighs
/// the base colour with.
#[inline(always)]
pub fn cie_y_lanes<const N: usize, X: Isa>(wl: &[SampledWavelengths; N]) -> SampledSpectra<N, X> {
    let mut r = SampledSpectra::ZERO;
    for (k, wl) in wl.iter().enumerate() {
        for i in 0..N_SPECTRUM_SAMPLES {
            r.0[i].0[k] = cie_y_5nm(wl.lambda(i));
        }
    }
    r
}

/// [`super::principled_common::tint_luminance`] per lane, with ȳ from [`cie_y_lanes`].
#[inline(always)]
pub fn tint_luminance<const N: usize, X: Isa>(
    c: SampledSpectra<N, X>,
    cie_y: SampledSpectra<N, X>,
) -> F32s<N, X> {
    let mut sum = F32s::ZERO;
    for i in 0..N_SPECTRUM_SAMPLES {
        sum += cie_y.0[i] * c.0[i];
    }
    sum / N_SPECTRUM_SAMPLES as f32
}

/// The colour of a tint per lane: c / lum, 1 where lum ≤ 0.
#[inline(always)]
pub fn tint_color<const N: usize, X: Isa>(c: SampledSpectra<N, X>, lum: F32s<N, X>) -> SampledSpectra<N, X> {
    let pos = lum.gt(0.0);
    c.map(|v| pos.select(v / lum, F32s::ONE))
}

/// [`super::principled_common::ggx_alphas`] per lane.
#[inline(always)]
pub fn ggx_alphas<const N: usize, X: Isa>(
    roughness: F32s<N, X>,
    anisotropic: F32s<N, X>,
) -> (F32s<N, X>, F32s<N, X>) {
    let r2 = roughness * roughness;
    let iso = anisotropic.eq(0.0);
    let aspect = (F32s::ONE - 0.9 * anisotropic).sqrt();
    let a = r2.max(1e-3);
    (
        iso.select(a, (r2 / aspect).max(1e-3)),
        iso.select(a, (r2 * aspect).max(1e-3)),
    )
}

/// [`super::principled_common::facet_compatible`] per lane.
#[inline(always)]
pub fn facet_compatible<const N: usize, X: Isa>(
    m: Vec3s<N, X>,
    wi: Vec3s<N, X>,
    wo: Vec3s<N, X>,
    cos_theta_i: F32s<N, X>,
    reflection: bool,
) -> Mask<N, X> {
    let m = cos_theta_i.lt(0.0).select3(-m, m);
    let o = wo.dot(m);
    wi.dot(m).gt(0.0) & if reflection { o.gt(0.0) } else { o.lt(0.0) }
}

/// [`super::principled_common::refract_through`] per lane.
#[inline(always)]
pub fn refract_through<const N: usize, X: Isa>(
    wi: Vec3s<N, X>,
    m: Vec3s<N, X>,
    cos_theta_t: F32s<N, X>,
    eta_ti: F32s<N, X>,
) -> Vec3s<N, X> {
    m * (wi.dot(m) * eta_ti + cos_theta_t) - wi * eta_ti
}

/// [`super::principled_common::Gtr1`] with an α per lane.
#[derive(Clone, Copy, Debug)]
pub struct Gtr1Lanes<const N: usize, X: Isa = Portable> {
    /// α per lane.
    pub alpha: F32s<N, X>,
}

impl<const N: usize, X: Isa> Gtr1Lanes<N, X> {
    /// α = 0.1 (1 − g) + 0.001 g per lane.
    #[inline(always)]
    pub fn from_gloss(gloss: F32s<N, X>) -> Self {
        Self {
            alpha: 0.1 - 0.1 * gloss + 0.001 * gloss,
        }
    }

    /// D(m) per lane (0 where D cos θm ≤ 10⁻²⁰).
    #[inline(always)]
    pub fn d(&self, m: Vec3s<N, X>) -> F32s<N, X> {
        let a2 = self.alpha * self.alpha;
        let c2 = m.z * m.z;
        let r = (a2 - 1.0) / (PI * ln(a2) * (1.0 + (a2 - 1.0) * c2));
        (r * m.z).gt(1e-20).and_then(r)
    }

    /// D(m) cos θm per lane.
    #[inline(always)]
    pub fn pdf(&self, m: Vec3s<N, X>) -> F32s<N, X> {
        m.z.ge(0.0).and_then(m.z * self.d(m))
    }

    /// A normal per lane with density D(m) cos θm.
    #[inline(always)]
    pub fn sample(&self, u: [F32s<N, X>; 2]) -> Vec3s<N, X> {
        let (sin_phi, cos_phi) = sin_cos(2.0 * PI * u[0]);
        let a2 = self.alpha * self.alpha;
        let cos2 = (F32s::ONE - powf(a2, F32s::ONE - u[1])) / (F32s::ONE - a2);
        let sin_t = (F32s::ONE - cos2).max(0.0).sqrt();
        let cos_t = cos2.max(0.0).sqrt();
        Vec3s::new(cos_phi * sin_t, sin_phi * sin_t, cos_t)
    }
}

/// [`super::principled_common::smith_ggx1`] per lane.
#[inline(always)]
pub fn smith_ggx1<const N: usize, X: Isa>(v: Vec3s<N, X>, m: Vec3s<N, X>, alpha: f32) -> F32s<N, X> {
    let facing = (v.dot(m) * v.z).gt(0.0);
    let c2 = v.z * v.z;
    let tan2 = (F32s::ONE - c2) / c2;
    let g = 2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt());
    facing.and_then(v.z.eq(1.0).select(F32s::ONE, g))
}

/// [`super::principled_common::diffuse_shape`] per lane (the fake subsurface blended in only
/// where some lane has flatness ≠ 0).
#[inline(always)]
pub fn diffuse_shape<const N: usize, X: Isa>(
    cos_i: F32s<N, X>,
    cos_o: F32s<N, X>,
    cos_d: F32s<N, X>,
    roughness: F32s<N, X>,
    flatness: F32s<N, X>,
) -> F32s<N, X> {
    let (fo, fi) = (schlick_weight(cos_o.abs()), schlick_weight(cos_i.abs()));
    let f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
    let rr = 2.0 * roughness * cos_d * cos_d;
    let f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
    let base = f_diff + f_retro;
    let flat = flatness.ne(0.0);
    if !flat.any() {
        return base;
    }
    let fss90 = 0.5 * rr;
    let fss = (1.0 + (fss90 - 1.0) * fo) * (1.0 + (fss90 - 1.0) * fi);
    let f_ss = 1.25 * (fss * ((cos_o.abs() + cos_i.abs()).recip() - 0.5) + 0.5);
    flat.select(base + (f_ss - base) * flatness, base)
}

/// [`super::principled_common::sheen_shape`] per lane.
#[inline(always)]
pub fn sheen_shape<const N: usize, X: Isa>(
    cos_d: F32s<N, X>,
    sheen_tint: F32s<N, X>,
    tint: SampledSpectra<N, X>,
) -> SampledSpectra<N, X> {
    let fd = schlick_weight(cos_d.abs());
    tint.map(|t| (1.0 + (t - 1.0) * sheen_tint) * fd)
}

/// The lobe [`choose_lobe`] picked per lane, as one mask per lobe (at most one set per lane).
#[derive(Clone, Copy, Debug)]
pub struct LobeChoice<const N: usize, X: Isa, const K: usize> {
    /// Lanes where a lobe was picked (the scalar returned `Some`).
    pub valid: Mask<N, X>,
    /// `chosen[i]`: the lanes that picked lobe `i`.
    pub chosen: [Mask<N, X>; K],
}

/// [`super::principled_common::choose_lobe`] per lane: lobe `i` where
/// acc_i ≤ u1 < acc_i + p_i/total, the last lobe for the remainder where its probability is > 0.
#[inline(always)]
pub fn choose_lobe<const N: usize, X: Isa, const K: usize>(
    probs: [F32s<N, X>; K],
    u1: F32s<N, X>,
) -> LobeChoice<N, X, K> {
    let mut total = F32s::ZERO;
    for p in probs {
        total += p;
    }
    let ok = !total.is_nan() & total.gt(0.0) & total.is_finite();
    let mut chosen = [Mask::NONE; K];
    let mut taken = Mask::NONE;
    let mut acc = F32s::ZERO;
    for i in 0..K - 1 {
        let p = probs[i] / total;
        chosen[i] = ok & !taken & u1.ge(acc) & u1.lt(acc + p);
        taken = taken | chosen[i];
        acc += p;
    }
    chosen[K - 1] = ok & !taken & probs[K - 1].gt(0.0);
    LobeChoice {
        valid: taken | chosen[K - 1],
        chosen,
    }
}
