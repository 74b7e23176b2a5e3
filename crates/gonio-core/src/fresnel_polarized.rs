//! Polarized Fresnel equations: the complex amplitudes a_s, a_p of a plane interface and the
//! Mueller matrices of specular reflection and transmission built from them.
//!
//! Sources: Mitsuba 3 `include/mitsuba/render/fresnel.h` (`fresnel_polarized`) and
//! `include/mitsuba/render/mueller.h` (`specular_reflection`, `specular_transmission`); Born &
//! Wolf, *Principles of Optics*, §1.5; Clarke, *Stellar Polarimetry*, appendix A.2 (the root
//! of cos θt under total internal reflection).
//!
//! # Amplitudes (Verdet sign convention, as Mitsuba)
//!
//! With ci = |cos θi|, η_it the relative index seen from the incident side (complex n − ik for a
//! conductor: the absorbing index has a negative imaginary part here) and
//! cos θt = √(1 − (1 − ci²)/η_it²) (imaginary part ≤ 0; under total internal reflection it is
//! purely imaginary, −i√(sin²θi/η_it² − 1)):
//!
//! ```text
//!     a_s = (ci − η_it cos θt)/(ci + η_it cos θt)      a_p = (η_it ci − cos θt)/(η_it ci + cos θt)
//! ```
//!
//! R_s = |a_s|², R_p = |a_p|², F = (R_s + R_p)/2; δ = arg a_p − arg a_s is the retardance.
//!
//! # Mueller matrices, in the s/p frames
//!
//! Both matrices act between bases whose x-axis is the s direction, x = normalize(n × ω) for the
//! beam direction ω (incident: −ω_light_in; outgoing: ω_light_out), and whose y-axis is
//! ω × x (in the plane of incidence):
//!
//! ```text
//!     reflection   = [a b 0 0; b a 0 0; 0 0 c cosδ  −c sinδ; 0 0 c sinδ  c cosδ],
//!                    a = (R_s + R_p)/2, b = (R_s − R_p)/2, c = √(R_s R_p)
//!     transmission = [a b 0 0; b a 0 0; 0 0 c 0; 0 0 0 c],
//!                    a = (T_s + T_p)/2, b = (T_s − T_p)/2, c = √(T_s T_p), T = 1 − R (dielectrics)
//! ```
//!
//! The unpolarized element a is taken from [`crate::fresnel`]'s real-arithmetic functions, bit for
//! bit, so an unpolarized observer of these matrices sees exactly gonio's unpolarized values; the
//! complex amplitudes contribute only the phase δ (for a dielectric outside total internal
//! reflection δ is 0 or π).

use crate::bsdf::{BsdfContext, light_directions};
use crate::fresnel::{fresnel_conductor_sp, fresnel_dielectric, fresnel_dielectric_amplitudes};
use crate::mueller::{Mueller, MuellerMatrix, StokesBasis};
use crate::spectrum::SampledSpectrum;
use glam::Vec3;
use num_complex::Complex32;

/// Mitsuba's `fresnel_polarized` for a complex relative index η = n + ik (either sign of k; a
/// real η is a dielectric): `(a_s, a_p)` for the signed `cos_theta_i` (negative: incidence from
/// the interior, η_it = 1/η). Index-matched (η = 1) and invalid (η = 0) interfaces give 0.
pub fn fresnel_amplitudes(cos_theta_i: f32, eta: Complex32) -> (Complex32, Complex32) {
    // The absorbing index with a negative imaginary part (the physics convention these
    // amplitudes are written in).
    let eta = if eta.im > 0.0 { eta.conj() } else { eta };
    if eta.norm_sqr() == 0.0 || (eta.im == 0.0 && eta.re == 1.0) {
        return (Complex32::new(0.0, 0.0), Complex32::new(0.0, 0.0));
    }
    let eta_it = if cos_theta_i >= 0.0 { eta } else { eta.inv() };
    let eta_ti = eta_it.inv();
    let ci = cos_theta_i.abs();
    let cos_t_sqr = Complex32::new(1.0, 0.0) - eta_ti * eta_ti * (1.0 - ci * ci);
    let mut cos_t = if eta.im == 0.0 {
        // Real index (Mitsuba's real overload): √|x| made imaginary with the sign of x, so a
        // negative cos²θt gives cos θt = −i√(−cos²θt).
        let r = cos_t_sqr.re.abs().sqrt();
        if cos_t_sqr.re >= 0.0 {
            Complex32::new(r, 0.0)
        } else {
            Complex32::new(0.0, -r)
        }
    } else {
        cos_t_sqr.sqrt()
    };
    if cos_t.im > 0.0 {
        cos_t = cos_t.conj();
    }
    let a_s = (ci - eta_it * cos_t) / (ci + eta_it * cos_t);
    let a_p = (eta_it * ci - cos_t) / (eta_it * ci + cos_t);
    (a_s, a_p)
}

/// (cos δ, sin δ) of the retardance δ = arg a_p − arg a_s; (1, 0) when either amplitude is 0.
#[inline]
fn retardance_cs(a_s: Complex32, a_p: Complex32) -> (f32, f32) {
    let z = a_p * a_s.conj();
    let n = z.norm();
    if n > 0.0 && n.is_finite() {
        (z.re / n, z.im / n)
    } else {
        (1.0, 0.0)
    }
}

/// The retardance δ = arg a_p − arg a_s of a reflection, radians in (−π, π].
pub fn reflection_retardance(cos_theta_i: f32, eta: Complex32) -> f32 {
    let (a_s, a_p) = fresnel_amplitudes(cos_theta_i, eta);
    let (c, s) = retardance_cs(a_s, a_p);
    s.atan2(c)
}

/// The reflection Mueller matrix of a dielectric interface (relative index η = n_int/n_ext per
/// wavelength) in the s/p frames (module docs), for the signed `cos_theta_i` of the incident
/// light. M00 is exactly `fresnel_dielectric(cos_theta_i, η).reflectance`.
pub fn dielectric_reflection(cos_theta_i: f32, eta: SampledSpectrum) -> MuellerMatrix {
    let mut el = [[0.0f32; 4]; 4];
    for (i, e) in el.iter_mut().enumerate() {
        let f = fresnel_dielectric(cos_theta_i, eta[i]).reflectance;
        let (r_s, r_p) = fresnel_dielectric_amplitudes(cos_theta_i, eta[i]);
        let (rs, rp) = if f >= 1.0 {
            (1.0, 1.0)
        } else {
            (r_s * r_s, r_p * r_p)
        };
        let (a_s, a_p) = fresnel_amplitudes(cos_theta_i, Complex32::new(eta[i], 0.0));
        let (cd, sd) = retardance_cs(a_s, a_p);
        let c = (rs * rp).sqrt();
        *e = [f, 0.5 * (rs - rp), c * cd, c * sd];
    }
    interface_matrix(el)
}

/// The transmission Mueller matrix of a dielectric interface in the s/p frames, without the
/// radiance factor η_ti² (applied by the caller, as for the unpolarized weight). M00 is exactly
/// 1 − `fresnel_dielectric(cos_theta_i, η).reflectance`; 0 under total internal reflection.
pub fn dielectric_transmission(cos_theta_i: f32, eta: SampledSpectrum) -> MuellerMatrix {
    let mut el = [[0.0f32; 4]; 4];
    for (i, e) in el.iter_mut().enumerate() {
        let f = fresnel_dielectric(cos_theta_i, eta[i]).reflectance;
        if f >= 1.0 {
            continue;
        }
        let (r_s, r_p) = fresnel_dielectric_amplitudes(cos_theta_i, eta[i]);
        let (ts, tp) = ((1.0 - r_s * r_s).max(0.0), (1.0 - r_p * r_p).max(0.0));
        *e = [1.0 - f, 0.5 * (ts - tp), (ts * tp).sqrt(), 0.0];
    }
    interface_matrix(el)
}

/// The reflection Mueller matrix of a conductor of complex index (n + ik)/n_ext per wavelength,
/// in the s/p frames, for the incidence cosine `cos_theta_i` (clamped to [0, 1]). M00 is exactly
/// [`crate::fresnel::fresnel_conductor_exterior`].
pub fn conductor_reflection(
    cos_theta_i: f32,
    eta: SampledSpectrum,
    k: SampledSpectrum,
    ext_ior: SampledSpectrum,
) -> MuellerMatrix {
    let (eta, k) = (eta.safe_div(ext_ior), k.safe_div(ext_ior));
    let mut el = [[0.0f32; 4]; 4];
    for (i, e) in el.iter_mut().enumerate() {
        let (rs, rp) = fresnel_conductor_sp(cos_theta_i, eta[i], k[i]);
        let (a_s, a_p) = fresnel_amplitudes(cos_theta_i.clamp(0.0, 1.0), Complex32::new(eta[i], k[i]));
        let (cd, sd) = retardance_cs(a_s, a_p);
        let c = (rs * rp).max(0.0).sqrt();
        *e = [0.5 * (rs + rp), 0.5 * (rs - rp), c * cd, c * sd];
    }
    interface_matrix(el)
}

/// [a b 0 0; b a 0 0; 0 0 c −d; 0 0 d c] from per-wavelength [a, b, c, d].
fn interface_matrix(el: [[f32; 4]; 4]) -> MuellerMatrix {
    let col = |j: usize| SampledSpectrum::from_fn(|i| el[i][j]);
    MuellerMatrix::interface(col(0), col(1), col(2), col(3))
}

/// Divides every element by M00, per wavelength (a pure polarization "shape" with M00 = 1; a
/// wavelength with M00 = 0 becomes the depolarizer diag(1, 0, 0, 0)). Multiplying the shape by an
/// unpolarized weight w gives a matrix whose M00 is w exactly. Non-finite elements (0/0 limits of
/// the callers' formulas) become 0.
pub fn normalized(m: &MuellerMatrix) -> MuellerMatrix {
    let a = m.0[0][0];
    let inv = SampledSpectrum::from_fn(|i| {
        if a[i] != 0.0 && a[i].is_finite() {
            1.0 / a[i]
        } else {
            0.0
        }
    });
    let mut r = m.scaled(inv);
    for row in r.0.iter_mut() {
        for v in row.iter_mut() {
            *v = v.map(|x| if x.is_finite() { x } else { 0.0 });
        }
    }
    r.0[0][0] = SampledSpectrum::ONE;
    r
}

/// An interface matrix given in the s/p frames of a plane of incidence with normal `n` (the
/// macro-normal +z, or a microfacet normal), placed between Mitsuba's implicit bases:
/// light arrives travelling along `light_in` and leaves along `light_out` (module docs of
/// [`crate::mueller`]). When a direction is parallel to `n` the s-axis is +x (Mitsuba's choice).
pub fn interface_mueller(m: MuellerMatrix, n: Vec3, light_in: Vec3, light_out: Vec3) -> Mueller {
    let s_in = StokesBasis::perpendicular_to_plane(light_in, n, Vec3::X);
    let s_out = StokesBasis::perpendicular_to_plane(light_out, n, Vec3::X);
    Mueller::new(m, s_in, s_out).in_bases(StokesBasis::implicit(light_in), StokesBasis::implicit(light_out))
}

/// A BSDF value `f` (per wavelength, unpolarized) whose only polarizing factor is a Fresnel
/// interface at the (micro)facet normal `m`, as a Mueller matrix between the implicit bases of the
/// query (wi, wo): f × `fresnel`/M00(`fresnel`), placed in the s/p frames of the plane through `m`
/// (Mitsuba's rough conductor and dielectric). M00 is `f` exactly.
pub fn facet_mueller(
    f: SampledSpectrum,
    fresnel: &MuellerMatrix,
    m: Vec3,
    ctx: &BsdfContext,
    wi: Vec3,
    wo: Vec3,
) -> Mueller {
    let (light_in, light_out) = light_directions(ctx, wi, wo);
    interface_mueller(normalized(fresnel).scaled(f), m, light_in, light_out)
}
