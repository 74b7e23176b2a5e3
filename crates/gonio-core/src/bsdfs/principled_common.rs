//! Pieces shared by `principled` and `principledthin` (Burley 2012, "Physically Based Shading at
//! Disney"; Burley 2015, "Extending the Disney BRDF to a BSDF with Integrated Subsurface
//! Scattering"), in the form Mitsuba 3 gives them (`src/bsdfs/principledhelpers.h`):
//!
//! ```text
//!   Schlick weight       S(c)   = (1 − c)⁵, c clamped to [0, 1]
//!   Schlick Fresnel      F(R0)  = R0 + (1 − R0) S(c),  c = |cos θi| when η_it > 1, else cos θt
//!                                 (the transmitted cosine; 0 under total internal reflection)
//!   R0 of an index       R0(η)  = ((η − 1)/(η + 1))²
//!   tint                 C_tint = base_color / lum(base_color)   (1 where lum = 0)
//!   GTR1 (clearcoat)     D(m)   = (α² − 1) / (π ln α² (1 + (α² − 1) cos²θm)),
//!                        sampled by cos²θm = (1 − α^{2(1−ξ₂)})/(1 − α²), φ = 2π ξ₁
//!   GGX G1 (clearcoat)   G1(v)  = 2 / (1 + sqrt(1 + α² tan²θv)),   α = 0.25
//!   main roughness       α_x = max(10⁻³, r²/a), α_y = max(10⁻³, r² a), a = sqrt(1 − 0.9 anisotropic)
//! ```
//!
//! and the diffuse family (Burley 2012 §5.3; 2015 §3): with F_L = S(|cos θo|), F_V = S(|cos θi|),
//! cos θd = h·ωo and R_R = 2 r cos²θd,
//!
//! ```text
//!   f_diffuse = (1 − F_L/2)(1 − F_V/2)
//!   f_retro   = R_R (F_L + F_V + F_L F_V (R_R − 1))
//!   f_ss      = 1.25 (F_ss (1/(|cos θo| + |cos θi|) − 0.5) + 0.5),
//!               F_ss = (1 + (F_ss90 − 1) F_L)(1 + (F_ss90 − 1) F_V), F_ss90 = R_R/2
//!   f_sheen   = sheen S(|cos θd|) lerp(1, C_tint, sheen_tint)
//! ```
//!
//! The luminance that normalizes the tint is Mitsuba's spectral one, the mean of ȳ(λ) times the
//! base colour over the path's wavelengths (not the Monte Carlo estimator of
//! [`crate::color::y_from_sampled`]: the tint is a shading choice, not a measurement).

use crate::data::cie1931::CIE_Y;
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Schlick's weight (1 − c)⁵ with c clamped to [0, 1].
#[inline]
pub fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// The weight S of Schlick's approximation F = R0 + (1 − R0) S at a facet with signed cosine
/// `cos_theta_i` (positive outside) of an interface of relative index `eta` = n_int/n_ext:
/// S(|cos θi|) when entering the denser side, S(cos θt) otherwise (1 under total internal
/// reflection).
#[inline]
pub fn schlick_fresnel_weight(cos_theta_i: f32, eta: f32) -> f32 {
    let outside = cos_theta_i >= 0.0;
    let rcp_eta = 1.0 / eta;
    let (eta_it, eta_ti) = if outside { (eta, rcp_eta) } else { (rcp_eta, eta) };
    if eta_it > 1.0 {
        schlick_weight(cos_theta_i.abs())
    } else {
        let cos_t2 = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * eta_ti * eta_ti;
        schlick_weight(cos_t2.max(0.0).sqrt())
    }
}

/// Schlick's approximation R0 + (1 − R0) S for a scalar R0 (see [`schlick_fresnel_weight`]).
#[inline]
pub fn schlick_fresnel(r0: f32, cos_theta_i: f32, eta: f32) -> f32 {
    let s = schlick_fresnel_weight(cos_theta_i, eta);
    r0 + (1.0 - r0) * s
}

/// Schlick's approximation per wavelength.
#[inline]
pub fn schlick_fresnel_spectrum(r0: SampledSpectrum, cos_theta_i: f32, eta: f32) -> SampledSpectrum {
    let s = schlick_fresnel_weight(cos_theta_i, eta);
    r0 + (SampledSpectrum::ONE - r0) * s
}

/// R0 = ((η − 1)/(η + 1))², the normal-incidence reflectance of an index η.
#[inline]
pub fn schlick_r0(eta: f32) -> f32 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// ȳ(λ) as Mitsuba 3 tabulates it (`cie1931_y`): the CIE 1931 values every 5 nm from 360 to
/// 830 nm (the 1 nm table's values there), linearly interpolated; 0 outside.
#[inline]
pub fn cie_y_5nm(lambda: f32) -> f32 {
    const MIN: f32 = 360.0;
    const MAX: f32 = 830.0;
    const SAMPLES: usize = 95;
    if !(MIN..=MAX).contains(&lambda) {
        return 0.0;
    }
    let x = (lambda - MIN) / (MAX - MIN) * (SAMPLES - 1) as f32;
    let i0 = (x as usize).min(SAMPLES - 2);
    let w1 = x - i0 as f32;
    // The 5 nm nodes are the 1 nm table's entries 5i (no interpolation needed to read them).
    (1.0 - w1) * CIE_Y[5 * i0] + w1 * CIE_Y[5 * i0 + 5]
}

/// The luminance that normalizes a tint: the mean of ȳ(λₖ) cₖ over the path's wavelengths, with
/// Mitsuba's 5 nm ȳ ([`cie_y_5nm`]; Mitsuba 3's `luminance(value, wavelengths)` in its spectral
/// variants).
#[inline]
pub fn tint_luminance(c: SampledSpectrum, wl: &SampledWavelengths) -> f32 {
    tint_luminances([c], wl)[0]
}

/// [`tint_luminance`] of several values at the same wavelengths, reading ȳ once per wavelength
/// (the same sums, bit for bit).
#[inline]
pub fn tint_luminances<const M: usize>(cs: [SampledSpectrum; M], wl: &SampledWavelengths) -> [f32; M] {
    let y: [f32; N_SPECTRUM_SAMPLES] = std::array::from_fn(|k| cie_y_5nm(wl.lambda(k)));
    cs.map(|c| {
        let mut sum = 0.0;
        for k in 0..N_SPECTRUM_SAMPLES {
            sum += y[k] * c[k];
        }
        sum / N_SPECTRUM_SAMPLES as f32
    })
}

/// The colour of a tint: c / lum (hue and saturation without brightness), 1 where lum ≤ 0.
#[inline]
pub fn tint_color(c: SampledSpectrum, lum: f32) -> SampledSpectrum {
    if lum > 0.0 { c / lum } else { SampledSpectrum::ONE }
}

/// The GGX roughness (α_x, α_y) of the main specular lobes from `roughness` r and
/// `anisotropic` (Burley 2012, addendum B): α = r², stretched by a = sqrt(1 − 0.9 anisotropic),
/// each at least 10⁻³ (so r = 0 stays finite).
#[inline]
pub fn ggx_alphas(roughness: f32, anisotropic: f32) -> (f32, f32) {
    let r2 = roughness * roughness;
    if anisotropic == 0.0 {
        let a = r2.max(1e-3);
        return (a, a);
    }
    let aspect = (1.0 - 0.9 * anisotropic).sqrt();
    ((r2 / aspect).max(1e-3), (r2 * aspect).max(1e-3))
}

/// True when `m` (flipped to the side of `wi`) is a facet both directions can see: for a
/// reflection both lie on its front; for a refraction `wo` lies behind it.
#[inline]
pub fn facet_compatible(m: Vec3, wi: Vec3, wo: Vec3, cos_theta_i: f32, reflection: bool) -> bool {
    let m = if cos_theta_i < 0.0 { -m } else { m };
    wi.dot(m) > 0.0
        && if reflection {
            wo.dot(m) > 0.0
        } else {
            wo.dot(m) < 0.0
        }
}

/// Mirror reflection of `wi` about the facet normal `m`.
#[inline]
pub fn reflect_about(wi: Vec3, m: Vec3) -> Vec3 {
    2.0 * wi.dot(m) * m - wi
}

/// Refraction of `wi` through the facet `m` with the cosine and η_ti of
/// [`crate::fresnel::fresnel_dielectric`] evaluated at wi·m (Mitsuba's `refract(wi, m, cos θt,
/// η_ti)`).
#[inline]
pub fn refract_through(wi: Vec3, m: Vec3, cos_theta_t: f32, eta_ti: f32) -> Vec3 {
    m * (wi.dot(m) * eta_ti + cos_theta_t) - wi * eta_ti
}

/// Burley's GTR1 ("generalized Trowbridge–Reitz", γ = 1) normal distribution of the clearcoat,
/// sampled by its normals (D cos θm), as Mitsuba 3's `GTR1Isotropic`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gtr1 {
    /// Roughness α (the clearcoat maps gloss 0..1 to α = 0.1..0.001).
    pub alpha: f32,
}

impl Gtr1 {
    /// The clearcoat's distribution for `clearcoat_gloss` g: α = 0.1 (1 − g) + 0.001 g.
    #[inline]
    pub fn from_gloss(gloss: f32) -> Self {
        Self {
            alpha: 0.1 - 0.1 * gloss + 0.001 * gloss,
        }
    }

    /// D(m) (0 where D cos θm ≤ 10⁻²⁰).
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        let a2 = self.alpha * self.alpha;
        let c2 = m.z * m.z;
        let r = (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * c2));
        if r * m.z > 1e-20 { r } else { 0.0 }
    }

    /// The density of [`Self::sample`] per solid angle of m: D(m) cos θm.
    #[inline]
    pub fn pdf(&self, m: Vec3) -> f32 {
        if m.z < 0.0 { 0.0 } else { m.z * self.d(m) }
    }

    /// A normal with density D(m) cos θm.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let (sin_phi, cos_phi) = (2.0 * PI * u.x).sin_cos();
        let a2 = self.alpha * self.alpha;
        let cos2 = (1.0 - a2.powf(1.0 - u.y)) / (1.0 - a2);
        let sin_t = (1.0 - cos2).max(0.0).sqrt();
        let cos_t = cos2.max(0.0).sqrt();
        Vec3::new(cos_phi * sin_t, sin_phi * sin_t, cos_t)
    }
}

/// Separable Smith masking of an isotropic GGX of roughness `alpha` for direction `v` and facet
/// `m` (used by the clearcoat with α = 0.25): 0 when v sees the back of m, 1 at normal
/// incidence.
#[inline]
pub fn smith_ggx1(v: Vec3, m: Vec3, alpha: f32) -> f32 {
    if v.dot(m) * v.z <= 0.0 {
        return 0.0;
    }
    if v.z == 1.0 {
        return 1.0;
    }
    let c2 = v.z * v.z;
    let tan2 = (1.0 - c2) / c2;
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// The diffuse family of the reflection side (see the module docs): returns
/// lerp(f_diffuse + f_retro, f_ss, flatness), without base colour, weight or 1/π.
#[inline]
pub fn diffuse_shape(cos_i: f32, cos_o: f32, cos_d: f32, roughness: f32, flatness: f32) -> f32 {
    let (fo, fi) = (schlick_weight(cos_o.abs()), schlick_weight(cos_i.abs()));
    let f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
    let rr = 2.0 * roughness * cos_d * cos_d;
    let f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
    if flatness == 0.0 {
        return f_diff + f_retro;
    }
    let fss90 = 0.5 * rr;
    let fss = (1.0 + (fss90 - 1.0) * fo) * (1.0 + (fss90 - 1.0) * fi);
    let f_ss = 1.25 * (fss * (1.0 / (cos_o.abs() + cos_i.abs()) - 0.5) + 0.5);
    let base = f_diff + f_retro;
    base + (f_ss - base) * flatness
}

/// The sheen's colour lerp(1, C_tint, sheen_tint) times S(|cos θd|), without its weight.
#[inline]
pub fn sheen_shape(cos_d: f32, sheen_tint: f32, tint: SampledSpectrum) -> SampledSpectrum {
    let fd = schlick_weight(cos_d.abs());
    (SampledSpectrum::ONE + (tint - SampledSpectrum::ONE) * sheen_tint) * fd
}

/// Picks one of `probs.len()` lobes with `u1` ∈ [0, 1) in proportion to `probs` (unnormalized,
/// ≥ 0); the last lobe takes the remainder (Mitsuba's order of tests). `None` when all are 0.
#[inline]
pub fn choose_lobe<const N: usize>(probs: [f32; N], u1: f32) -> Option<usize> {
    let total: f32 = probs.iter().sum();
    if total.is_nan() || total <= 0.0 || !total.is_finite() {
        return None;
    }
    let mut acc = 0.0;
    for (i, p) in probs.iter().enumerate().take(N - 1) {
        let p = p / total;
        if u1 >= acc && u1 < acc + p {
            return Some(i);
        }
        acc += p;
    }
    (probs[N - 1] > 0.0).then_some(N - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gtr1_is_normalized_and_its_sampler_matches() {
        // ∫ D(m) cos θm dm = 1 (midpoint rule in cos θ, D is isotropic), and the
        // sampler maps the ends of ξ₂ to the pole and the horizon (α = 10⁻³, the glossiest
        // clearcoat, is too sharp for this rule: its peak is 10⁻⁶ wide in cos θ).
        for alpha in [0.02f32, 0.1, 0.5] {
            let g = Gtr1 { alpha };
            let n = 200_000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let c = (i as f64 + 0.5) / n as f64;
                let m = Vec3::new((1.0 - c * c).sqrt() as f32, 0.0, c as f32);
                sum += g.d(m) as f64 * c * 2.0 * std::f64::consts::PI / n as f64;
            }
            assert!((sum - 1.0).abs() < 2e-3, "α={alpha}: {sum}");
            let m = g.sample(Vec2::new(0.3, 0.0));
            assert!((m.z - 1.0).abs() < 1e-6, "ξ₂ = 0 is the pole");
            let m = g.sample(Vec2::new(0.3, 1.0));
            assert!(m.z.abs() < 1e-3, "ξ₂ = 1 is the horizon");
        }
    }

    #[test]
    fn mitsubas_five_nanometre_y() {
        // Values of Mitsuba 3.9.1's `cie1931_y` (between and on its 5 nm nodes, and outside).
        for (l, y) in [
            (380.5f32, 4.149_999_6e-5f32),
            (432.7, 0.014_429_615),
            (555.3, 0.999_7),
            (829.0, 4.897_534e-7),
            (359.0, 0.0),
        ] {
            assert!(
                (cie_y_5nm(l) - y).abs() <= 1e-6 * y.max(1e-3),
                "{l}: {} vs {y}",
                cie_y_5nm(l)
            );
        }
    }

    #[test]
    fn schlick_limits() {
        assert_eq!(schlick_weight(1.0), 0.0);
        assert_eq!(schlick_weight(0.0), 1.0);
        assert!((schlick_fresnel(0.04, 1.0, 1.5) - 0.04).abs() < 1e-7);
        // Inside a denser medium beyond the critical angle: total reflection.
        assert_eq!(schlick_fresnel(0.04, -0.2, 1.5), 1.0);
        assert!((schlick_r0(1.5) - 0.04).abs() < 1e-7);
        assert_eq!(ggx_alphas(0.0, 0.0), (1e-3, 1e-3));
        let (ax, ay) = ggx_alphas(0.5, 0.8);
        assert!(ax > ay && ((ax * ay).sqrt() - 0.25).abs() < 1e-6);
    }

    #[test]
    fn lobe_choice_follows_the_probabilities() {
        assert_eq!(choose_lobe([1.0, 0.0, 1.0], 0.2), Some(0));
        assert_eq!(choose_lobe([1.0, 0.0, 1.0], 0.7), Some(2));
        assert_eq!(choose_lobe([0.0, 0.0, 0.0], 0.7), None);
        assert_eq!(choose_lobe([0.0, 2.0, 0.0], 0.99), Some(1));
    }
}
