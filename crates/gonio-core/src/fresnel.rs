//! Fresnel equations: dielectric and conductor reflectance, refraction directions, the
//! hemispherical averages r̃ (Fdr) and the thin-slab Stokes sums.
//!
//! Lecture, slides "Fresnel Equations" and "Coated Diffuse BRDF"; Mitsuba 3
//! `include/mitsuba/render/fresnel.h`; pbrt-v4 `util/scattering.h`.
//!
//! # Dielectric
//!
//! With the relative index η = n_int/n_ext, ci = |cos θi|, Snell's law
//! cos²θt = 1 − η_ti²(1 − cos²θi) and η_it = η (from outside) or 1/η (from inside):
//!
//! ```text
//!     r_s = (ci − η_it ct)/(ci + η_it ct)      r_p = (ct − η_it ci)/(ct + η_it ci)
//!     F   = ½ (r_s² + r_p²)
//! ```
//!
//! Total internal reflection (cos²θt < 0) gives ct = 0 and F = 1 without a special case.
//!
//! # Conductor
//!
//! Complex index η̃ = n + ik, relative to the exterior medium (Moeller's real-arithmetic form, as
//! Mitsuba; c = cos θi, s² = 1 − c²):
//!
//! ```text
//!     t1 = n² − k² − s²,   A = sqrt(t1² + 4n²k²),   a = sqrt((A + t1)/2)
//!     R_s = (A + c² − 2ac)/(A + c² + 2ac)
//!     R_p = R_s (A c² + s⁴ − 2ac s²)/(A c² + s⁴ + 2ac s²)
//!     F   = ½ (R_s + R_p)
//! ```
//!
//! # Hemispherical averages
//!
//! r̃ = Fdr(η) = 2∫₀¹ F(μ, η) μ dμ, by Gauss–Legendre quadrature in f64 (not a polynomial fit).
//! η > 1 is the external average, η < 1 the internal one (with TIR). The two are tied by
//! 1 − Fdr(1/η) = (1 − Fdr(η))/η².

use crate::quadrature::gauss_legendre;
use crate::spectrum::SampledSpectrum;
use glam::Vec3;

/// What [`fresnel_dielectric`] finds at a smooth dielectric interface (the four values of
/// Mitsuba's `fresnel(cos_theta_i, eta)`, named).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FresnelDielectric {
    /// Unpolarized reflectance F ∈ [0, 1]; the transmittance is 1 − F.
    pub reflectance: f32,
    /// Cosine of the refracted direction, signed and **opposite** to `cos_theta_i` (the refracted
    /// ray leaves on the other side); 0 under total internal reflection.
    pub cos_theta_t: f32,
    /// Relative index η_it = n_t/n_i seen from the incident side.
    pub eta_it: f32,
    /// Its reciprocal η_ti = n_i/n_t (scales the tangential part of the refracted direction).
    pub eta_ti: f32,
}

/// Unpolarized Fresnel reflectance of a smooth dielectric interface, exactly as Mitsuba's
/// `fresnel(cos_theta_i, eta)`.
///
/// `cos_theta_i` is signed: positive when the incident direction lies on the exterior side (the
/// side the normal points to). `eta` = n_int/n_ext. Returns the reflectance, the cosine of the
/// refracted direction and the relative indices seen from the incident side
/// ([`FresnelDielectric`]). η = 1 gives F = 0; grazing incidence gives F = 1.
#[inline]
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> FresnelDielectric {
    let outside = cos_theta_i >= 0.0;
    let rcp_eta = 1.0 / eta;
    let (eta_it, eta_ti) = if outside { (eta, rcp_eta) } else { (rcp_eta, eta) };
    let cos_theta_t_sqr = 1.0 - eta_ti * eta_ti * (1.0 - cos_theta_i * cos_theta_i);
    let ci = cos_theta_i.abs();
    let ct = cos_theta_t_sqr.max(0.0).sqrt();
    let index_matched = eta == 1.0;
    let r = if index_matched {
        0.0
    } else if ci == 0.0 {
        1.0
    } else {
        let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
        let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
        0.5 * (a_s * a_s + a_p * a_p)
    };
    let cos_theta_t = if cos_theta_i >= 0.0 { -ct } else { ct };
    FresnelDielectric {
        reflectance: r,
        cos_theta_t,
        eta_it,
        eta_ti,
    }
}

/// The s (perpendicular) and p (parallel) amplitude reflection coefficients of a dielectric
/// interface, `(r_s, r_p)`, with the same arguments as [`fresnel_dielectric`]:
/// r_s = (ci − η_it ct)/(ci + η_it ct), r_p = (ct − η_it ci)/(ct + η_it ci) (Mitsuba's sign
/// convention for r_p; only the squares matter for unpolarized light). F = ½(r_s² + r_p²).
///
/// r_p vanishes at Brewster's angle, tan θ_B = η_it. Under total internal reflection the physical
/// amplitudes are complex of unit modulus (a phase shift); this real form then returns (1, −1),
/// which has the right moduli.
#[inline]
pub fn fresnel_dielectric_amplitudes(cos_theta_i: f32, eta: f32) -> (f32, f32) {
    let outside = cos_theta_i >= 0.0;
    let (eta_it, eta_ti) = if outside {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let ci = cos_theta_i.abs();
    let ct = (1.0 - eta_ti * eta_ti * (1.0 - ci * ci)).max(0.0).sqrt();
    if ci == 0.0 && ct == 0.0 {
        // Grazing and TIR at once: the limit of the TIR branch.
        return (1.0, -1.0);
    }
    let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
    let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
    (a_s, a_p)
}

/// [`fresnel_dielectric`]'s reflectance per wavelength for a per-wavelength relative index (for
/// amplitudes of a dispersive interface; never use it to pick a refraction direction).
#[inline]
pub fn fresnel_dielectric_spectrum(cos_theta_i: f32, eta: SampledSpectrum) -> SampledSpectrum {
    SampledSpectrum::from_fn(|i| fresnel_dielectric(cos_theta_i, eta[i]).reflectance)
}

/// s- and p-polarized reflectances `(R_s, R_p)` of a conductor with complex relative index
/// n + ik at one wavelength (Moeller's form, as Mitsuba's `fresnel_conductor`). `cos_theta_i` is
/// clamped to [0, 1] (callers pass |cos θi|).
///
/// n = k = 0 (a table evaluated outside its range) makes Mitsuba's formula 0/0 at normal
/// incidence; here every 0/0 is replaced by its limit, which for n, k → 0 is total reflection
/// (F0 = ((n−1)² + k²)/((n+1)² + k²) → 1).
#[inline]
pub fn fresnel_conductor_sp(cos_theta_i: f32, eta: f32, k: f32) -> (f32, f32) {
    let c = cos_theta_i.clamp(0.0, 1.0);
    let c2 = c * c;
    let s2 = 1.0 - c2;
    let (eta2, k2) = (eta * eta, k * k);
    let t1 = eta2 - k2 - s2;
    let a2b2 = (t1 * t1 + 4.0 * eta2 * k2).max(0.0).sqrt();
    let a = (0.5 * (a2b2 + t1)).max(0.0).sqrt();
    let term1 = a2b2 + c2;
    let term2 = 2.0 * a * c;
    let den_s = term1 + term2;
    let r_s = if den_s > 0.0 { (term1 - term2) / den_s } else { 1.0 };
    let term3 = a2b2 * c2 + s2 * s2;
    let term4 = term2 * s2;
    let den_p = term3 + term4;
    let r_p = if den_p > 0.0 {
        r_s * (term3 - term4) / den_p
    } else {
        r_s
    };
    (r_s, r_p)
}

/// Unpolarized reflectance of a conductor with complex index η + ik per wavelength, exterior
/// index 1 (Mitsuba's `fresnel_conductor`). NaN-free for η = k = 0 (see [`fresnel_conductor_sp`]).
#[inline]
pub fn fresnel_conductor(cos_theta_i: f32, eta: SampledSpectrum, k: SampledSpectrum) -> SampledSpectrum {
    SampledSpectrum::from_fn(|i| {
        let (r_s, r_p) = fresnel_conductor_sp(cos_theta_i, eta[i], k[i]);
        0.5 * (r_s + r_p)
    })
}

/// Unpolarized conductor reflectance under a dielectric of real index `ext_ior` (a metal under
/// water), which Mitsuba lacks: the Fresnel amplitudes depend only on the relative complex index
/// (n + ik)/n_ext, with θi measured in the exterior medium.
#[inline]
pub fn fresnel_conductor_exterior(
    cos_theta_i: f32,
    eta: SampledSpectrum,
    k: SampledSpectrum,
    ext_ior: SampledSpectrum,
) -> SampledSpectrum {
    fresnel_conductor(cos_theta_i, eta.safe_div(ext_ior), k.safe_div(ext_ior))
}

/// Refraction in the local frame (normal +z), Mitsuba's `refract(wi, cos_theta_t, eta_ti)`:
/// ωt = (−η_ti ωi.x, −η_ti ωi.y, cos θt), with `cos_theta_t` and `eta_ti` as returned by
/// [`fresnel_dielectric`] (cos θt already carries the sign of the far side).
#[inline]
pub fn refract(wi: Vec3, cos_theta_t: f32, eta_ti: f32) -> Vec3 {
    Vec3::new(-eta_ti * wi.x, -eta_ti * wi.y, cos_theta_t)
}

/// Refraction of `wi` (pointing away from the surface) about an arbitrary unit normal `n`, pbrt's
/// `Refract(wi, n, eta)`: η is the index of the medium on the −n side relative to the one on the
/// +n side. Works from either side: if wi·n < 0 the normal is flipped and η inverted.
///
/// Returns `(wt, etap)`, etap = the relative index actually crossed (n_t/n_i), or `None` under
/// total internal reflection. wt = −wi/etap + (cos θi/etap − cos θt) n.
#[inline]
pub fn refract_about(wi: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(wi);
    let (mut n, mut eta) = (n, eta);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    Some((-wi / eta + (cos_i / eta - cos_t) * n, eta))
}

/// Stokes sum for a parallel slab with single-interface reflectance `r` and no absorption:
/// R' = r + (1 − r)² r (1 + r² + r⁴ + …) = r + (1 − r)² r/(1 − r²) = 2r/(1 + r).
#[inline]
pub fn thin_slab_reflectance(r: f32) -> f32 {
    if r >= 1.0 {
        return 1.0;
    }
    r + (1.0 - r) * (1.0 - r) * r / (1.0 - r * r)
}

/// Transmittance of the same slab: T' = (1 − r)²/(1 − r²) = (1 − r)/(1 + r) = 1 − R'.
#[inline]
pub fn thin_slab_transmittance(r: f32) -> f32 {
    if r >= 1.0 {
        return 0.0;
    }
    (1.0 - r) / (1.0 + r)
}

/// [`fresnel_dielectric`]'s reflectance in f64 (for the quadratures below).
fn fresnel_dielectric_f64(cos_theta_i: f64, eta: f64) -> f64 {
    let (eta_it, eta_ti) = if cos_theta_i >= 0.0 {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let ci = cos_theta_i.abs();
    let ct = (1.0 - eta_ti * eta_ti * (1.0 - ci * ci)).max(0.0).sqrt();
    if eta == 1.0 {
        return 0.0;
    }
    if ci == 0.0 {
        return 1.0;
    }
    let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
    let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
    0.5 * (a_s * a_s + a_p * a_p)
}

/// Gauss–Legendre order of each quadrature panel.
const N_GL: usize = 24;

/// ∫₀¹ f, composite Gauss–Legendre on panels graded geometrically towards 0 from `scale` (the
/// distance of the integrand's nearest singularity from 0), so that a near-singular integrand
/// still converges to machine precision.
fn integrate_graded(f: impl Fn(f64) -> f64, scale: f64) -> f64 {
    let rule = gauss_legendre(N_GL, -1.0, 1.0);
    let mut sum = 0.0;
    let mut panel = |a: f64, b: f64| {
        let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
        for &(x, w) in &rule {
            sum += w * h * f(m + h * x);
        }
    };
    let mut b = scale.clamp(1e-12, 1.0);
    panel(0.0, b);
    while b < 1.0 {
        let a = b;
        b = (2.0 * b).min(1.0);
        panel(a, b);
    }
    sum
}

/// The hemispherical (cosine-weighted) average of the dielectric Fresnel reflectance, the
/// lecture's r̃: Fdr(η) = 2∫₀¹ F(μ, η) μ dμ, by Gauss–Legendre quadrature in f64.
///
/// * η > 1: external average (light from the exterior onto a denser interior).
/// * η < 1: internal average; F = 1 below μc = sqrt(1 − η²) (TIR) contributes μc² exactly, and the
///   rest is integrated with μ = μc + (1 − μc)s², which removes the square-root kink at μc.
///
/// Accurate to ~1e-15 for η in [1.0001, 10]; Fdr(1) = 0.
pub fn fresnel_diffuse_reflectance(eta: f64) -> f64 {
    if eta == 1.0 {
        return 0.0;
    }
    if eta > 1.0 {
        // cos θt = sqrt(μ² + η² − 1)/η has branch points at μ = ±i sqrt(η² − 1).
        let scale = (eta * eta - 1.0).sqrt();
        integrate_graded(|mu| 2.0 * mu * fresnel_dielectric_f64(mu, eta), scale)
    } else {
        let mu_c = (1.0 - eta * eta).sqrt();
        let span = 1.0 - mu_c;
        // In s, cos θt ∝ s sqrt(μ + μc): branch points at s = ±i sqrt(2μc/(1 − μc)).
        let scale = (2.0 * mu_c / span).sqrt();
        let rest = integrate_graded(
            |s| {
                let mu = mu_c + span * s * s;
                2.0 * mu * fresnel_dielectric_f64(mu, eta) * 2.0 * span * s
            },
            scale,
        );
        mu_c * mu_c + rest
    }
}

/// Mitsuba's polynomial fits of Fdr (`fresnel_diffuse_reflectance` in `fresnel.h`): Egan &
/// Hilgeman 1973 for η < 1, d'Eon & Irving 2011 for η ≥ 1. Kept **only for comparison** with
/// Mitsuba's numbers; gonio uses the quadrature [`fresnel_diffuse_reflectance`]. The fits miss
/// the identity 1 − Fdr(1/η) = (1 − Fdr(η))/η² by ~1e-3, which makes Mitsuba's `plastic` gain
/// energy at ρ = 1.
pub fn fresnel_diffuse_reflectance_fit(eta: f32) -> f32 {
    if eta < 1.0 {
        -1.4399 * eta * eta + 0.7099 * eta + 0.6681 + 0.0636 / eta
    } else {
        let x = 1.0 / eta;
        0.919317 - 3.4793 * x + 6.75335 * x * x - 7.80989 * x * x * x + 4.98554 * x * x * x * x
            - 1.36881 * x * x * x * x * x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f32, b: f32, tol: f32) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn dielectric_matches_reference_table() {
        // Values computed in f64 from the Fresnel equations (Born & Wolf, Principles of Optics,
        // §1.5.2), as (F, cos θt, η_it, η_ti) like Mitsuba 3's fresnel() in render/fresnel.h.
        let FresnelDielectric {
            reflectance: f,
            cos_theta_t: ct,
            eta_it: eit,
            eta_ti: eti,
        } = fresnel_dielectric(1.0, 1.5);
        assert!(close(f, 0.04, 1e-7) && ct == -1.0 && eit == 1.5 && close(eti, 1.0 / 1.5, 1e-7));
        let FresnelDielectric {
            reflectance: f,
            cos_theta_t: ct,
            eta_it: eit,
            eta_ti: eti,
        } = fresnel_dielectric(-1.0, 1.5);
        assert!(close(f, 0.04, 1e-7) && ct == 1.0 && close(eit, 1.0 / 1.5, 1e-7) && eti == 1.5);
        let FresnelDielectric {
            reflectance: f,
            cos_theta_t: ct,
            ..
        } = fresnel_dielectric(0.0, 1.5);
        assert!(f == 1.0 && close(ct, -(1.0f32 - 1.0 / 2.25).sqrt(), 1e-7));
        let FresnelDielectric {
            reflectance: f,
            cos_theta_t: ct,
            ..
        } = fresnel_dielectric(0.0, 1.0 / 1.5);
        assert!(f == 1.0 && ct == 0.0);

        let c45 = 45f32.to_radians().cos();
        let FresnelDielectric {
            reflectance: f,
            cos_theta_t: ct,
            ..
        } = fresnel_dielectric(c45, 1.5);
        let expect = 0.5 * (0.09201336304552442f64.powi(2) + 0.3033370452904235f64.powi(2));
        assert!(close(f, expect as f32, 1e-7), "{f}");
        assert!(close(ct, -28.1255057f32.to_radians().cos(), 1e-6) && close(ct, -0.881917, 1e-6));
        let (a_s, a_p) = fresnel_dielectric_amplitudes(c45, 1.5);
        // s is the larger amplitude: |r_s| = 0.3033370, |r_p| = 0.0920134.
        assert!(close(a_s.abs(), 0.30333705, 1e-7) && close(a_p.abs(), 0.09201336, 1e-7));

        let c10 = 10f32.to_radians().cos();
        let FresnelDielectric {
            reflectance: f,
            cos_theta_t: ct,
            ..
        } = fresnel_dielectric(c10, 1.0 / 1.5);
        let expect = 0.5 * (0.19046797197779405f64.powi(2) + 0.20949431963852014f64.powi(2));
        assert!(close(f, expect as f32, 1e-6) && close(f, 0.0400830, 1e-6), "{f}");
        assert!(close(ct, -15.098086605f32.to_radians().cos(), 1e-6));

        let FresnelDielectric {
            reflectance: f,
            cos_theta_t: ct,
            ..
        } = fresnel_dielectric(c45, 1.0 / 1.5);
        assert!(f == 1.0 && ct == 0.0, "TIR");

        let FresnelDielectric {
            reflectance: f,
            cos_theta_t: ct,
            ..
        } = fresnel_dielectric(80f32.to_radians().cos(), 1.5);
        assert!(close(f, 0.387704354691473, 1e-6), "{f}");
        assert!(close(ct.abs().acos().to_degrees(), 41.03641052520335, 1e-4));

        for c in [1.0, 0.7, 0.1, -0.5] {
            assert_eq!(fresnel_dielectric(c, 1.0).reflectance, 0.0, "index matched");
        }
    }

    #[test]
    fn bk7_and_polypropylene_values() {
        // η = 1.504183 and 1.489587 (Mitsuba's bk7/air and polypropylene/air, render/ior.h); F
        // computed from the Fresnel equations.
        let eta = 1.5046f32 / 1.000277;
        for (deg, f) in [
            (0.0f32, 0.040536),
            (45.0, 0.050825),
            (60.0, 0.089880),
            (80.0, 0.388403),
        ] {
            let got = fresnel_dielectric(deg.to_radians().cos(), eta).reflectance;
            assert!(close(got, f, 2e-6), "{deg}: {got}");
        }
        let eta = 1.49f32 / 1.000277;
        assert!(close(fresnel_dielectric(1.0, eta).reflectance, 0.038673, 2e-6));
        assert!(close(fresnel_dielectric(0.5, eta).reflectance, 0.087453, 2e-6));
    }

    #[test]
    fn normal_incidence_is_f0_and_symmetric_from_both_sides() {
        for eta in [1.1f32, 1.33, 1.5, 2.0, 2.419] {
            let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
            assert!(close(fresnel_dielectric(1.0, eta).reflectance, f0, 1e-7));
            assert!(close(fresnel_dielectric(-1.0, eta).reflectance, f0, 1e-7));
            assert!(close(fresnel_dielectric(1.0, 1.0 / eta).reflectance, f0, 1e-7));
        }
    }

    #[test]
    fn p_amplitude_vanishes_at_brewster_angle() {
        for eta in [1.33f32, 1.5, 2.4] {
            let theta_b = eta.atan();
            let (a_s, a_p) = fresnel_dielectric_amplitudes(theta_b.cos(), eta);
            assert!(a_p.abs() < 1e-6, "η {eta}: r_p {a_p}");
            assert!(a_s.abs() > 0.1);
            // From the dense side, tan θ_B = 1/η.
            let theta_b_in = (1.0 / eta).atan();
            let (_, a_p) = fresnel_dielectric_amplitudes(-theta_b_in.cos(), eta);
            assert!(a_p.abs() < 1e-6);
            // F is the mean of the squared amplitudes.
            let c = 0.37;
            let (a_s, a_p) = fresnel_dielectric_amplitudes(c, eta);
            assert!(close(
                fresnel_dielectric(c, eta).reflectance,
                0.5 * (a_s * a_s + a_p * a_p),
                1e-7
            ));
        }
    }

    #[test]
    fn total_internal_reflection_starts_at_critical_angle() {
        let eta = 1.5f32;
        let theta_c = (1.0 / eta).asin();
        assert!(close(theta_c.to_degrees(), 41.81031, 1e-4));
        let eps = 1e-3;
        let FresnelDielectric {
            reflectance: f_below,
            cos_theta_t: ct_below,
            ..
        } = fresnel_dielectric(-(theta_c - eps).cos(), eta);
        assert!(f_below < 1.0 && ct_below > 0.0);
        let FresnelDielectric {
            reflectance: f_above,
            cos_theta_t: ct_above,
            ..
        } = fresnel_dielectric(-(theta_c + eps).cos(), eta);
        assert!(f_above == 1.0 && ct_above == 0.0);
        // bk7/air: 41.67°.
        let theta_c = (1.000277f32 / 1.5046).asin().to_degrees();
        assert!(close(theta_c, 41.67, 0.01));
    }

    #[test]
    fn refraction_obeys_snell_and_is_invertible() {
        for (deg, eta) in [(30.0f32, 1.5f32), (60.0, 1.5), (20.0, 1.0 / 1.5), (75.0, 2.4)] {
            let t = deg.to_radians();
            let wi = Vec3::new(t.sin() * 0.6, t.sin() * 0.8, t.cos());
            let FresnelDielectric {
                reflectance: f,
                cos_theta_t: ct,
                eta_ti,
                ..
            } = fresnel_dielectric(wi.z, eta);
            if f == 1.0 {
                continue;
            }
            let wt = refract(wi, ct, eta_ti);
            assert!(close(wt.length(), 1.0, 1e-6));
            let sin_i = (1.0 - wi.z * wi.z).sqrt();
            let sin_t = (1.0 - wt.z * wt.z).sqrt();
            assert!(close(sin_i, eta * sin_t, 1e-6), "Snell");
            // General form agrees.
            let (wt2, etap) = refract_about(wi, Vec3::Z, eta).unwrap();
            assert!((wt - wt2).length() < 1e-6 && close(etap, eta, 1e-7));
            // And back: the reversed path arrives from wt and leaves towards wi.
            let FresnelDielectric {
                cos_theta_t: ct2,
                eta_ti: eta_ti2,
                ..
            } = fresnel_dielectric(wt.z, eta);
            let back = refract(wt, ct2, eta_ti2);
            assert!((back - wi).length() < 1e-6);
        }
        // refract_about with a tilted normal is Snell about that normal; TIR gives None.
        let n = Vec3::new(0.3, -0.2, 0.9).normalize();
        let wi = Vec3::new(-0.4, 0.5, 0.7).normalize();
        let (wt, _) = refract_about(wi, n, 1.33).unwrap();
        let sin_i = wi.cross(n).length();
        let sin_t = wt.cross(n).length();
        assert!(close(sin_i, 1.33 * sin_t, 1e-6) && wt.dot(n) < 0.0);
        // Coplanar, with the tangential part reversed (wt continues through the surface).
        assert!(
            wi.cross(n).normalize().dot(wt.cross(n).normalize()) < -0.9999,
            "coplanar"
        );
        let grazing_inside = Vec3::new(0.9, 0.0, -(1.0f32 - 0.81).sqrt());
        assert!(refract_about(grazing_inside, Vec3::Z, 1.5).is_none());
    }

    /// pbrt-v4's `FrComplex`: the dielectric formulas in complex arithmetic, an independent
    /// check of Moeller's real form.
    fn fr_complex(cos_i: f64, n: f64, k: f64) -> (f64, f64) {
        #[derive(Clone, Copy)]
        struct C(f64, f64);
        let add = |a: C, b: C| C(a.0 + b.0, a.1 + b.1);
        let sub = |a: C, b: C| C(a.0 - b.0, a.1 - b.1);
        let mul = |a: C, b: C| C(a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let div = |a: C, b: C| {
            let d = b.0 * b.0 + b.1 * b.1;
            C((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        };
        let sqrt = |a: C| {
            let r = (a.0 * a.0 + a.1 * a.1).sqrt();
            let re = ((r + a.0) / 2.0).sqrt();
            let im = ((r - a.0) / 2.0).sqrt().copysign(a.1);
            C(re, im)
        };
        let norm = |a: C| a.0 * a.0 + a.1 * a.1;
        let eta = C(n, k);
        let ci = C(cos_i, 0.0);
        let sin2_i = C(1.0 - cos_i * cos_i, 0.0);
        let sin2_t = div(sin2_i, mul(eta, eta));
        let ct = sqrt(sub(C(1.0, 0.0), sin2_t));
        let r_parl = div(sub(mul(eta, ci), ct), add(mul(eta, ci), ct));
        let r_perp = div(sub(ci, mul(eta, ct)), add(ci, mul(eta, ct)));
        (norm(r_perp), norm(r_parl))
    }

    #[test]
    fn conductor_matches_complex_arithmetic_and_f0() {
        for (n, k) in [
            (0.3504f32, 2.7141f32),
            (1.6579, 1.9560),
            (0.959, 6.687),
            (2.0, 4.0),
            (0.2, 0.01),
        ] {
            let f0 = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
            let (rs, rp) = fresnel_conductor_sp(1.0, n, k);
            assert!(close(rs, f0, 1e-6) && close(rp, f0, 1e-6), "F0 {n} {k}");
            for c in [0.95f32, 0.7, 0.5, 0.2, 0.03] {
                let (rs, rp) = fresnel_conductor_sp(c, n, k);
                let (es, ep) = fr_complex(c as f64, n as f64, k as f64);
                assert!(
                    close(rs, es as f32, 2e-5) && close(rp, ep as f32, 2e-5),
                    "{n} {k} {c}: {rs} {es}, {rp} {ep}"
                );
            }
        }
        // Gold at 550 nm / 400 nm (n, k of pbrt-v4's metal-Au tables, util/spectrum.cpp; R computed
        // from the complex Fresnel equations): R(0°) 0.848 / 0.391, R(60°) 0.843 / 0.416.
        let f = |c, n, k| fresnel_conductor(c, SampledSpectrum::splat(n), SampledSpectrum::splat(k))[0];
        assert!(close(f(1.0, 0.3504, 2.7141), 0.848, 1e-3));
        assert!(close(f(0.5, 0.3504, 2.7141), 0.843, 1e-3));
        assert!(close(f(1.0, 1.6579, 1.9560), 0.391, 1e-3));
        assert!(close(f(0.5, 1.6579, 1.9560), 0.416, 1e-3));
    }

    #[test]
    fn conductor_with_zero_k_is_the_dielectric() {
        for eta in [1.5f32, 1.0 / 1.5] {
            for deg in [0.0f32, 10.0, 30.0, 45.0, 60.0, 80.0, 89.0] {
                let c = deg.to_radians().cos();
                let fc = fresnel_conductor(c, SampledSpectrum::splat(eta), SampledSpectrum::ZERO)[0];
                let fd = fresnel_dielectric(c, eta).reflectance;
                assert!(close(fc, fd, 2e-6), "η {eta} θ {deg}: {fc} vs {fd}");
            }
        }
    }

    #[test]
    fn conductor_n0_k1_is_a_perfect_mirror_and_zero_index_is_not_nan() {
        for c in [1.0f32, 0.8, 0.5, 0.1, 0.0] {
            let f = fresnel_conductor(c, SampledSpectrum::ZERO, SampledSpectrum::ONE);
            assert!(
                (f - SampledSpectrum::ONE).0.abs().max_element() < 1e-6,
                "{c}: {f:?}"
            );
            // n = k = 0 (table out of range): Mitsuba's formula gives 0/0 at normal incidence.
            let f = fresnel_conductor(c, SampledSpectrum::ZERO, SampledSpectrum::ZERO);
            assert!(
                f.is_finite() && (f - SampledSpectrum::ONE).0.abs().max_element() < 1e-6,
                "{c}: {f:?}"
            );
        }
    }

    #[test]
    fn conductor_under_water_uses_relative_index() {
        let (n, k, w) = (0.3504f32, 2.7141f32, 1.333f32);
        let f = fresnel_conductor_exterior(
            1.0,
            SampledSpectrum::splat(n),
            SampledSpectrum::splat(k),
            SampledSpectrum::splat(w),
        )[0];
        // F0 with the complex index relative to water: |(ñ − n_w)/(ñ + n_w)|².
        let f0 = ((n - w).powi(2) + k * k) / ((n + w).powi(2) + k * k);
        assert!(close(f, f0, 1e-6));
        assert!(
            f < fresnel_conductor(1.0, SampledSpectrum::splat(n), SampledSpectrum::splat(k))[0],
            "gold is darker under water"
        );
        // And at an angle against complex arithmetic with the relative index.
        let c = 0.4f32;
        let got = fresnel_conductor_exterior(
            c,
            SampledSpectrum::splat(n),
            SampledSpectrum::splat(k),
            SampledSpectrum::splat(w),
        )[0];
        let (es, ep) = fr_complex(c as f64, (n / w) as f64, (k / w) as f64);
        assert!(close(got, (0.5 * (es + ep)) as f32, 2e-5));
    }

    /// Closed form of the external average, η > 1: Walsh's analytic integral, as given by Prahl
    /// 1988, Light Transport in Tissue (PhD thesis, U. Texas), Appendix B, Eq. B.41.
    fn fdr_closed_form(n: f64) -> f64 {
        let n2 = n * n;
        let n4 = n2 * n2;
        0.5 + (n - 1.0) * (3.0 * n + 1.0) / (6.0 * (n + 1.0).powi(2))
            + n2 * (n2 - 1.0).powi(2) / (n2 + 1.0).powi(3) * ((n - 1.0) / (n + 1.0)).ln()
            - 2.0 * n * n2 * (n2 + 2.0 * n - 1.0) / ((n2 + 1.0) * (n4 - 1.0))
            + 8.0 * n4 * (n4 + 1.0) / ((n2 + 1.0) * (n4 - 1.0).powi(2)) * n.ln()
    }

    #[test]
    fn hemispherical_fresnel_by_quadrature_matches_closed_form_and_table() {
        // Exact values (closed form below; the internal ones by the identity of the next test),
        // 16 digits at η = 1.5.
        assert!((fresnel_diffuse_reflectance(1.5) - 0.0917779593423509).abs() < 1e-12);
        assert!((fresnel_diffuse_reflectance(1.0 / 1.5) - 0.5963457597077115).abs() < 1e-12);
        let table = [
            (1.1, 0.025157, 0.194345),
            (1.33, 0.065931, 0.471949),
            (1.489587, 0.090245, 0.589992),
            (1.9, 0.147476, 0.763844),
            (2.0, 0.160597, 0.790149),
            (2.5, 0.221867, 0.875499),
        ];
        for (eta, ext, int) in table {
            let e = fresnel_diffuse_reflectance(eta);
            let i = fresnel_diffuse_reflectance(1.0 / eta);
            assert!(
                (e - ext).abs() < 6e-7 && (i - int).abs() < 6e-7,
                "η {eta}: {e} {i}"
            );
        }
        for eta in [1.001, 1.01, 1.1, 1.33, 1.5, 2.0, 2.419, 4.0, 10.0] {
            let q = fresnel_diffuse_reflectance(eta);
            assert!(
                (q - fdr_closed_form(eta)).abs() < 1e-11,
                "η {eta}: {q} vs {}",
                fdr_closed_form(eta)
            );
        }
        assert_eq!(fresnel_diffuse_reflectance(1.0), 0.0);
    }

    #[test]
    fn hemispherical_fresnel_reciprocity_identity() {
        // 1 − Fdr(1/η) = (1 − Fdr(η))/η²: the internal average is computed independently (TIR
        // part exact, the rest in the substituted variable), so this is a real check.
        for eta in [1.0005f64, 1.01, 1.1, 1.33, 1.489587, 1.5, 1.9, 2.0, 2.5, 3.5, 6.0] {
            let lhs = 1.0 - fresnel_diffuse_reflectance(1.0 / eta);
            let rhs = (1.0 - fresnel_diffuse_reflectance(eta)) / (eta * eta);
            assert!((lhs - rhs).abs() < 1e-9, "η {eta}: {lhs} vs {rhs}");
        }
    }

    #[test]
    fn hemispherical_fresnel_fits_are_mitsubas() {
        // Mitsuba's fits (fresnel_diffuse_reflectance in render/fresnel.h) evaluated at these η:
        // they miss the exact values by up to ~5e-4.
        for (eta, fit, fit_inv) in [
            (1.33f32, 0.065908, 0.472439),
            (1.489587, 0.090239, 0.590479),
            (1.5, 0.091774, 0.596811),
            (1.9, 0.147484, 0.763707),
            (2.0, 0.160589, 0.790275),
        ] {
            assert!(close(fresnel_diffuse_reflectance_fit(eta), fit, 2e-6));
            assert!(close(fresnel_diffuse_reflectance_fit(1.0 / eta), fit_inv, 2e-6));
        }
    }

    #[test]
    fn thin_slab_stokes_sums() {
        // Stokes' sums R′ = 2R/(1 + R), T′ = (1 − R)/(1 + R) at η = 1.504183 (R: Fresnel equations).
        for (r, rp, tp) in [
            (0.040536f32, 0.077914f32, 0.922086f32),
            (0.050825, 0.096734, 0.903266),
            (0.089880, 0.164935, 0.835065),
            (0.388403, 0.559496, 0.440504),
        ] {
            assert!(close(thin_slab_reflectance(r), rp, 1.5e-6), "{r}");
            assert!(close(thin_slab_transmittance(r), tp, 1.5e-6));
            assert!(
                close(thin_slab_reflectance(r), 2.0 * r / (1.0 + r), 1e-6),
                "closed form"
            );
            assert!(close(
                thin_slab_reflectance(r) + thin_slab_transmittance(r),
                1.0,
                1e-6
            ));
            // The explicit series R + T²R Σ R^{2j}.
            let t = 1.0 - r;
            let series: f32 = r + (0..40).map(|j| t * t * r * r.powi(2 * j)).sum::<f32>();
            assert!(close(series, thin_slab_reflectance(r), 1e-6));
        }
        assert_eq!(thin_slab_reflectance(1.0), 1.0);
        assert_eq!(thin_slab_transmittance(1.0), 0.0);
        assert_eq!(thin_slab_reflectance(0.0), 0.0);
    }

    #[test]
    fn spectrum_version_is_per_wavelength() {
        let eta = SampledSpectrum::new([1.53, 1.52, 1.51, 1.0]);
        let f = fresnel_dielectric_spectrum(0.6, eta);
        for i in 0..4 {
            assert_eq!(f[i], fresnel_dielectric(0.6, eta[i]).reflectance);
        }
        assert_eq!(f[3], 0.0);
    }
}
