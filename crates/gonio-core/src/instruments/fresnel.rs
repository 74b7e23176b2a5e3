//! Fresnel curves (lecture slides "Fresnel Reflectance", "Fresnel Reflection and Transmission",
//! "Thin vs Thick Glass", "Fresnel Conductor: Gold"): reflectance against angle for s- and
//! p-polarized and unpolarized light, on both sides of a dielectric and for conductors;
//! reflectance against wavelength; a single interface against the Stokes thin slab; the
//! polarization of reflected and transmitted light (degree of polarization for unpolarized
//! incident light, and the retardance δ = arg r_p − arg r_s of a reflection: total internal
//! reflection, metals).
//!
//! Every number comes from [`crate::fresnel`] and [`crate::fresnel_polarized`]: this module only
//! sweeps their arguments.

use crate::fresnel::{
    fresnel_conductor_sp, fresnel_dielectric, fresnel_dielectric_amplitudes, thin_slab_reflectance,
    thin_slab_transmittance,
};
use crate::fresnel_polarized::reflection_retardance;
use crate::spectra::Spectrum;
use num_complex::Complex32;

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

/// The polarization a plane interface gives unpolarized light, against the angle of incidence.
///
/// With R_s, R_p the intensity reflectances and T = 1 − R the transmittances, unpolarized
/// incident light leaves with the Stokes vector (R_s + R_p, R_s − R_p, 0, 0)/2 in the s/p frame
/// of the reflection (and the same with T for the transmission), so its degree of polarization
/// is |R_s − R_p|/(R_s + R_p) (|T_s − T_p|/(T_s + T_p)). The retardance is the phase δ of
/// r_p/r_s (Verdet's convention, as Mitsuba: δ = π at normal incidence on a dielectric); under
/// total internal reflection tan(δ/2) = cos θ √(sin²θ − η²)/sin²θ (Born & Wolf §1.5.4).
#[derive(Clone, Debug, PartialEq)]
pub struct PolarizationCurves {
    /// Angles of incidence, degrees, 0 to 90.
    pub angles_deg: Vec<f32>,
    /// Degree of polarization of the reflected light.
    pub dop_reflected: Vec<f32>,
    /// Degree of polarization of the transmitted light; NaN where nothing is transmitted (total
    /// internal reflection, conductors).
    pub dop_transmitted: Vec<f32>,
    /// Retardance of the reflection, δ = arg r_p − arg r_s, degrees in (−180, 180].
    pub retardance_deg: Vec<f32>,
}

fn dop(a: f32, b: f32) -> f32 {
    if a + b > 0.0 {
        (a - b).abs() / (a + b)
    } else {
        f32::NAN
    }
}

/// [`PolarizationCurves`] of a dielectric interface seen from the side of relative index `eta`
/// (η < 1: from the denser side, with total internal reflection past the critical angle).
pub fn dielectric_polarization_vs_angle(eta: f32, samples: usize) -> PolarizationCurves {
    let angles_deg = angles(samples);
    let (mut dr, mut dt, mut ret) = (vec![], vec![], vec![]);
    for &a in &angles_deg {
        let c = a.to_radians().cos().max(0.0);
        let tir = fresnel_dielectric(c, eta).reflectance >= 1.0;
        let (a_s, a_p) = fresnel_dielectric_amplitudes(c, eta);
        let (rs, rp) = if tir { (1.0, 1.0) } else { (a_s * a_s, a_p * a_p) };
        dr.push(dop(rs, rp));
        dt.push(if tir { f32::NAN } else { dop(1.0 - rs, 1.0 - rp) });
        ret.push(reflection_retardance(c, Complex32::new(eta, 0.0)).to_degrees());
    }
    PolarizationCurves {
        angles_deg,
        dop_reflected: dr,
        dop_transmitted: dt,
        retardance_deg: ret,
    }
}

/// [`PolarizationCurves`] of a conductor of complex index n + ik (exterior index 1); nothing is
/// transmitted (`dop_transmitted` is NaN).
pub fn conductor_polarization_vs_angle(n: f32, k: f32, samples: usize) -> PolarizationCurves {
    let angles_deg = angles(samples);
    let (mut dr, mut ret) = (vec![], vec![]);
    for &a in &angles_deg {
        let c = a.to_radians().cos().max(0.0);
        let (s, p) = fresnel_conductor_sp(c, n, k);
        dr.push(dop(s, p));
        ret.push(reflection_retardance(c, Complex32::new(n, k)).to_degrees());
    }
    let dt = vec![f32::NAN; angles_deg.len()];
    PolarizationCurves {
        angles_deg,
        dop_reflected: dr,
        dop_transmitted: dt,
        retardance_deg: ret,
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

    /// Brewster: the reflected light is fully (s-)polarized, from either side; at normal
    /// incidence nothing is polarized and δ = 180°; the transmitted light is never fully
    /// polarized and has the closed-form degree (T_p − T_s)/(T_p + T_s).
    #[test]
    fn dielectric_polarization_closed_forms() {
        for eta in [1.5f32, 1.0 / 1.5, 2.4] {
            let b = brewster_angle_deg(eta);
            let c = dielectric_polarization_vs_angle(eta, 2);
            assert!(c.dop_reflected[0] < 1e-6 && (c.retardance_deg[0].abs() - 180.0).abs() < 1e-3);
            let at = |deg: f32| {
                let curves = dielectric_polarization_vs_angle(eta, 9001);
                let i = (deg * 100.0).round() as usize;
                (
                    curves.dop_reflected[i],
                    curves.dop_transmitted[i],
                    curves.retardance_deg[i],
                )
            };
            // The grid has 0.01° steps: Brewster's angle lies within 0.005° of a node.
            let (r, t, _) = at(b);
            assert!(r > 0.9995, "η = {eta}: DoP at Brewster {r}");
            let (ci, si) = (b.to_radians().cos() as f64, b.to_radians().sin() as f64);
            let e = eta as f64;
            let ct = (1.0 - si * si / (e * e)).sqrt();
            let rs = ((ci - e * ct) / (ci + e * ct)).powi(2);
            let want = rs / (2.0 - rs); // T_p = 1 at Brewster
            assert!((t as f64 - want).abs() < 1e-3, "η = {eta}: DoP_t {t} vs {want}");
        }
    }

    /// Total internal reflection: |r_s| = |r_p| = 1, DoP 0, nothing transmitted, and the
    /// textbook retardance tan(δ/2) = cos θ √(sin²θ − η²)/sin²θ.
    #[test]
    fn tir_retardance_is_the_textbook_formula() {
        let eta = 1.0f32 / 1.5;
        let c = dielectric_polarization_vs_angle(eta, 91);
        let crit = critical_angle_deg(eta).unwrap();
        let mut checked = 0;
        for (i, &a) in c.angles_deg.iter().enumerate() {
            if a <= crit + 0.01 || a >= 90.0 {
                continue;
            }
            let (ct, st) = (a.to_radians().cos() as f64, a.to_radians().sin() as f64);
            let e = eta as f64;
            let want = 2.0 * (ct * (st * st - e * e).sqrt() / (st * st)).atan();
            assert!(
                (c.retardance_deg[i] as f64 - want.to_degrees()).abs() < 2e-3,
                "θ = {a}: δ {} vs {}",
                c.retardance_deg[i],
                want.to_degrees()
            );
            assert!(c.dop_reflected[i] < 1e-6 && c.dop_transmitted[i].is_nan());
            checked += 1;
        }
        assert!(checked >= 45);
        // The maximum retardance of TIR: 2 atan((1 − η²)/(2η)) at sin²θ = 2η²/(1 + η²).
        let fine = dielectric_polarization_vs_angle(eta, 901);
        let max = fine
            .angles_deg
            .iter()
            .zip(&fine.retardance_deg)
            .filter(|(a, _)| **a > crit)
            .map(|(_, d)| *d)
            .fold(f32::MIN, f32::max) as f64;
        let e = eta as f64;
        let want = (2.0 * ((1.0 - e * e) / (2.0 * e)).atan()).to_degrees();
        assert!((max - want).abs() < 0.05, "{max} vs {want}");
    }

    /// Metals: δ is the phase of r_p/r_s from the complex Fresnel equations (computed here in
    /// f64, independently), and the degree of polarization (R_s − R_p)/(R_s + R_p).
    #[test]
    fn conductor_retardance_is_the_phase_of_rp_over_rs() {
        use num_complex::Complex64;
        let (n, k) = (0.2f64, 3.9f64); // Ag-like at 600 nm
        let c = conductor_polarization_vs_angle(n as f32, k as f32, 91);
        for deg in [0usize, 30, 60, 75, 85] {
            let (ci, si) = ((deg as f64).to_radians().cos(), (deg as f64).to_radians().sin());
            let nn = Complex64::new(n, -k);
            let ct = (Complex64::new(1.0, 0.0) - si * si / (nn * nn)).sqrt();
            let rs = (ci - nn * ct) / (ci + nn * ct);
            let rp = (nn * ci - ct) / (nn * ci + ct);
            let want = (rp / rs).arg().to_degrees();
            let mut d = c.retardance_deg[deg] as f64 - want;
            d -= 360.0 * (d / 360.0).round();
            assert!(d.abs() < 0.02, "θ = {deg}: δ {} vs {want}", c.retardance_deg[deg]);
            let (a, b) = (rs.norm_sqr(), rp.norm_sqr());
            assert!((c.dop_reflected[deg] as f64 - (a - b) / (a + b)).abs() < 1e-4);
        }
        assert!(c.dop_transmitted.iter().all(|x| x.is_nan()));
    }
}
