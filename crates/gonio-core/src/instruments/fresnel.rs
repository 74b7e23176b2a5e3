//! Fresnel curves (lecture slides "Fresnel Reflectance", "Fresnel Reflection and Transmission",
//! "Thin vs Thick Glass", "Fresnel Conductor: Gold"): reflectance against angle for s- and
//! p-polarized and unpolarized light, on both sides of a dielectric and for conductors;
//! reflectance against wavelength; a single interface against the Stokes thin slab.
//!
//! Every number comes from [`crate::fresnel`]: this module only sweeps its arguments.

use crate::fresnel::{
    fresnel_conductor_sp, fresnel_dielectric, fresnel_dielectric_amplitudes, thin_slab_reflectance,
    thin_slab_transmittance,
};
use crate::spectra::Spectrum;

/// Reflectances against the angle of incidence.
#[derive(Clone, Debug, PartialEq)]
pub struct AngleCurves {
    /// Angles of incidence, degrees, 0 to 90.
    pub angles_deg: Vec<f32>,
    /// s-polarized (perpendicular) reflectance R_s.
    pub rs: Vec<f32>,
    /// p-polarized (parallel) reflectance R_p.
    pub rp: Vec<f32>,
    /// Unpolarized reflectance R = (R_s + R_p)/2.
    pub r: Vec<f32>,
}

fn angles(samples: usize) -> Vec<f32> {
    let n = samples.max(2);
    (0..n).map(|k| 90.0 * k as f32 / (n - 1) as f32).collect()
}

/// A dielectric interface seen from the side of relative index `eta` = n_other/n_this
/// (η = 1.5: from air onto glass; η = 1/1.5: from inside the glass).
pub fn dielectric_vs_angle(eta: f32, samples: usize) -> AngleCurves {
    let angles_deg = angles(samples);
    let (mut rs, mut rp, mut r) = (vec![], vec![], vec![]);
    for &a in &angles_deg {
        let c = a.to_radians().cos().max(0.0);
        let (a_s, a_p) = fresnel_dielectric_amplitudes(c, eta);
        rs.push(a_s * a_s);
        rp.push(a_p * a_p);
        r.push(fresnel_dielectric(c, eta).reflectance);
    }
    AngleCurves {
        angles_deg,
        rs,
        rp,
        r,
    }
}

/// A conductor of complex index n + ik (exterior index 1).
pub fn conductor_vs_angle(n: f32, k: f32, samples: usize) -> AngleCurves {
    let angles_deg = angles(samples);
    let (mut rs, mut rp, mut r) = (vec![], vec![], vec![]);
    for &a in &angles_deg {
        let (s, p) = fresnel_conductor_sp(a.to_radians().cos().max(0.0), n, k);
        rs.push(s);
        rp.push(p);
        r.push(0.5 * (s + p));
    }
    AngleCurves {
        angles_deg,
        rs,
        rp,
        r,
    }
}

/// Brewster's angle, degrees: tan θ_B = η (r_p = 0 there).
pub fn brewster_angle_deg(eta: f32) -> f32 {
    eta.atan().to_degrees()
}

/// The critical angle, degrees, sin θ_c = η, for η < 1 (total internal reflection past it);
/// `None` for η ≥ 1.
pub fn critical_angle_deg(eta: f32) -> Option<f32> {
    (eta < 1.0).then(|| eta.asin().to_degrees())
}

/// Normal-incidence reflectance of a conductor against wavelength: `(λ, R(λ))` at `samples`
/// wavelengths over [`lo`, `hi`] nm, at incidence angle `angle_deg`.
pub fn conductor_vs_wavelength(
    eta: &Spectrum,
    k: &Spectrum,
    lo: f32,
    hi: f32,
    samples: usize,
    angle_deg: f32,
) -> Vec<(f32, f32)> {
    let c = angle_deg.to_radians().cos();
    wavelengths(lo, hi, samples)
        .map(|l| {
            let (s, p) = fresnel_conductor_sp(c, eta.eval(l), k.eval(l));
            (l, 0.5 * (s + p))
        })
        .collect()
}

/// A glass's dispersion: `(λ, n(λ), R(λ))`, the index and the reflectance at `angle_deg` from
/// an exterior of index `ext`.
pub fn dielectric_vs_wavelength(
    ior: &Spectrum,
    ext: f32,
    lo: f32,
    hi: f32,
    samples: usize,
    angle_deg: f32,
) -> Vec<(f32, f32, f32)> {
    let c = angle_deg.to_radians().cos();
    wavelengths(lo, hi, samples)
        .map(|l| {
            let n = ior.eval(l);
            (l, n, fresnel_dielectric(c, n / ext).reflectance)
        })
        .collect()
}

fn wavelengths(lo: f32, hi: f32, samples: usize) -> impl Iterator<Item = f32> {
    let n = samples.max(2);
    (0..n).map(move |k| lo + (hi - lo) * k as f32 / (n - 1) as f32)
}

/// A single interface against the Stokes thin slab (two parallel interfaces, all inter-
/// reflections summed, no absorption): per angle, (R, R' = R + T²R/(1 − R²), T' = 1 − R').
#[derive(Clone, Debug, PartialEq)]
pub struct ThinSlabCurves {
    /// Angles of incidence, degrees.
    pub angles_deg: Vec<f32>,
    /// Single-interface reflectance R.
    pub single: Vec<f32>,
    /// Slab reflectance R'.
    pub slab_r: Vec<f32>,
    /// Slab transmittance T'.
    pub slab_t: Vec<f32>,
}

/// [`ThinSlabCurves`] for a slab of relative index `eta`.
pub fn thin_slab_vs_angle(eta: f32, samples: usize) -> ThinSlabCurves {
    let angles_deg = angles(samples);
    let single: Vec<f32> = angles_deg
        .iter()
        .map(|a| fresnel_dielectric(a.to_radians().cos().max(0.0), eta).reflectance)
        .collect();
    let slab_r = single.iter().map(|&r| thin_slab_reflectance(r)).collect();
    let slab_t = single.iter().map(|&r| thin_slab_transmittance(r)).collect();
    ThinSlabCurves {
        angles_deg,
        single,
        slab_r,
        slab_t,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brewster_and_critical_angles_of_glass() {
        assert!((brewster_angle_deg(1.5) - 56.3099).abs() < 1e-3);
        assert!((critical_angle_deg(1.0 / 1.5).unwrap() - 41.8103).abs() < 1e-3);
        assert_eq!(critical_angle_deg(1.5), None);
        // R_p vanishes at Brewster's angle, from outside and from inside.
        for eta in [1.5f32, 1.0 / 1.5] {
            let c = brewster_angle_deg(eta).to_radians().cos();
            let (_, a_p) = fresnel_dielectric_amplitudes(c, eta);
            assert!(a_p.abs() < 1e-6, "η = {eta}: r_p = {a_p}");
        }
    }

    #[test]
    fn dielectric_curves_have_known_values() {
        let c = dielectric_vs_angle(1.5, 91);
        assert!(
            (c.r[0] - 0.04).abs() < 1e-6 && (c.rs[0] - 0.04).abs() < 1e-6 && (c.rp[0] - 0.04).abs() < 1e-6
        );
        assert!((c.r[45] - 0.0502399).abs() < 1e-5);
        assert!((c.r[90] - 1.0).abs() < 1e-6);
        for k in 0..91 {
            assert!((c.r[k] - 0.5 * (c.rs[k] + c.rp[k])).abs() < 1e-6);
            assert!(c.rp[k] <= c.rs[k] + 1e-7, "R_p ≤ R_s for a dielectric");
        }
        let inside = dielectric_vs_angle(1.0 / 1.5, 91);
        assert!(
            inside.r[42..].iter().all(|&r| (r - 1.0).abs() < 1e-6),
            "TIR past 41.8°"
        );
        assert!(inside.r[41] < 1.0);
    }

    #[test]
    fn conductor_and_slab_curves_have_known_values() {
        let c = conductor_vs_angle(0.2, 3.0, 10);
        let f0 = ((0.2f32 - 1.0).powi(2) + 9.0) / ((1.2f32).powi(2) + 9.0);
        assert!((c.r[0] - f0).abs() < 1e-5);
        let s = thin_slab_vs_angle(1.5, 10);
        assert!((s.slab_r[0] - 2.0 * 0.04 / 1.04).abs() < 1e-6, "R' = 2R/(1+R)");
        assert!((s.slab_r[3] + s.slab_t[3] - 1.0).abs() < 1e-6);
        let d = dielectric_vs_wavelength(&Spectrum::Constant(1.5), 1.0, 400.0, 700.0, 4, 0.0);
        assert!((d[2].2 - 0.04).abs() < 1e-6 && d[3].0 == 700.0);
    }
}
