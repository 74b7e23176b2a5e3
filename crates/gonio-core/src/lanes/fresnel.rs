//! Fresnel reflectances on lanes: the formulas of [`crate::fresnel`], operation for operation.

use super::{F32s, Isa, Portable};

/// Unpolarized reflectance ½(r_s + r_p) of a conductor of complex index η + ik per lane
/// ([`crate::fresnel::fresnel_conductor_sp`], NaN-free for η = k = 0).
#[inline(always)]
pub fn fresnel_conductor<const N: usize, X: Isa>(
    cos_theta_i: F32s<N, X>,
    eta: F32s<N, X>,
    k: F32s<N, X>,
) -> F32s<N, X> {
    let c = cos_theta_i.clamp(0.0, 1.0);
    let c2 = c * c;
    let s2 = F32s::ONE - c2;
    let (eta2, k2) = (eta * eta, k * k);
    let t1 = eta2 - k2 - s2;
    let a2b2 = (t1 * t1 + 4.0 * eta2 * k2).safe_sqrt();
    let a = (0.5 * (a2b2 + t1)).safe_sqrt();
    let term1 = a2b2 + c2;
    let term2 = 2.0 * a * c;
    let den_s = term1 + term2;
    let r_s = den_s.gt(0.0).select((term1 - term2) / den_s, F32s::ONE);
    let term3 = a2b2 * c2 + s2 * s2;
    let term4 = term2 * s2;
    let den_p = term3 + term4;
    let r_p = den_p.gt(0.0).select(r_s * (term3 - term4) / den_p, r_s);
    0.5 * (r_s + r_p)
}

/// [`crate::fresnel::FresnelDielectric`] per lane.
#[derive(Clone, Copy, Debug)]
pub struct FresnelDielectrics<const N: usize, X: Isa = Portable> {
    /// F, the reflectance.
    pub reflectance: F32s<N, X>,
    /// cos θt, signed as the far side.
    pub cos_theta_t: F32s<N, X>,
    /// η_it = n_t/n_i.
    pub eta_it: F32s<N, X>,
    /// η_ti = n_i/n_t.
    pub eta_ti: F32s<N, X>,
}

/// Reflectance of a dielectric interface of relative index `eta` (interior over exterior) per
/// lane, from either side ([`crate::fresnel::fresnel_dielectric`]).
#[inline(always)]
pub fn fresnel_dielectric<const N: usize, X: Isa>(
    cos_theta_i: F32s<N, X>,
    eta: F32s<N, X>,
) -> FresnelDielectrics<N, X> {
    let outside = cos_theta_i.ge(0.0);
    let rcp_eta = eta.recip();
    let eta_it = outside.select(eta, rcp_eta);
    let eta_ti = outside.select(rcp_eta, eta);
    let cos_theta_t_sqr = F32s::ONE - eta_ti * eta_ti * (F32s::ONE - cos_theta_i * cos_theta_i);
    let ci = cos_theta_i.abs();
    let ct = cos_theta_t_sqr.safe_sqrt();
    let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
    let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
    let r = 0.5 * (a_s * a_s + a_p * a_p);
    let r = ci.eq(0.0).select(F32s::ONE, r);
    let r = eta.eq(1.0).select(F32s::ZERO, r);
    FresnelDielectrics {
        reflectance: r,
        cos_theta_t: outside.select(-ct, ct),
        eta_it,
        eta_ti,
    }
}
