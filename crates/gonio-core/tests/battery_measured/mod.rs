//! Battery runs of the models played back from measured tables: `tabulated` (gonio's own
//! format) and `measured_polarized` (Mitsuba's pBRDF tables). Part of the `battery` test binary
//! (its Šidák family, `RUNS`).

use super::*;
use gonio_core::bsdfs::MeasuredPolarized;
use gonio_core::bsdfs::measured_polarized::PbrdfTable;
use gonio_core::fresnel_polarized::dielectric_reflection;
use gonio_core::spectrum::SampledSpectrum;

// ---- tabulated (issue 4's measured-table plugin) ----------------------------------------------

/// A table on a regular (θi, θo, φd) grid at 450 and 650 nm, values from `f(θi, θo, φd, λ)`.
fn table(n_theta: usize, n_phi: usize, f: impl Fn(f32, f32, f32, f32) -> f32) -> Tabulated {
    let th: Vec<f32> = (0..n_theta)
        .map(|i| 90.0 * i as f32 / (n_theta - 1) as f32)
        .collect();
    let ph: Vec<f32> = (0..n_phi)
        .map(|i| 180.0 * i as f32 / (n_phi - 1) as f32)
        .collect();
    let wl = vec![450.0, 650.0];
    let mut values = Vec::new();
    for &ti in &th {
        for &to in &th {
            for &pd in &ph {
                for &l in &wl {
                    values.push(f(ti, to, pd, l));
                }
            }
        }
    }
    Tabulated::new(TabulatedData::new(th.clone(), th, ph, wl, values, None, "battery".into()).unwrap())
}

#[test]
fn tabulated_lambertian() {
    let t = table(
        10,
        7,
        |_, _, _, l| if l < 500.0 { 0.5 } else { 0.8 } / std::f32::consts::PI,
    );
    assert_passes("tabulated Lambertian ρ=0.5/0.8", &t);
}

#[test]
fn tabulated_phong_lobe() {
    // 0.3/π + 0.5·(n+2)/(2π)·cos^n α, α the angle to the mirror direction: albedo ≤ 0.8.
    let n = 10.0f32;
    let t = table(19, 19, |ti, to, pd, _| {
        let (ti, to, pd) = (ti.to_radians(), to.to_radians(), pd.to_radians());
        // wi = (sin ti, 0, cos ti) mirrored = (−sin ti, 0, cos ti); wo at azimuth pd.
        let cos_a = (-ti.sin() * to.sin() * pd.cos() + ti.cos() * to.cos()).max(0.0);
        let pi = std::f32::consts::PI;
        0.3 / pi + 0.5 * (n + 2.0) / (2.0 * pi) * cos_a.powf(n)
    });
    assert_passes("tabulated Phong n=10", &t);
}

#[test]
fn tabulated_noisy_measurement() {
    // Random entries in [0, 0.3] (a noisy, non-reciprocal raw table: the plugin symmetrizes).
    let rng = std::cell::RefCell::new(Pcg32::new(11, 0));
    let t = table(7, 5, |_, _, _, _| 0.3 * rng.borrow_mut().next_f32());
    assert_passes("tabulated noisy 7×7×5", &t);
}

// ---- measured_polarized (Mitsuba's pBRDF tables, Baek et al. 2020) ---------------------------

/// A pBRDF table on (φd, θd, θh) nodes at 450, 550 and 650 nm: a depolarizing diffuse term
/// ρ/π plus a glossy term k·F(θd)·D(θh)/(4 cos θd) with F the Fresnel reflection Mueller matrix
/// of glass (η = 1.5, in the s/p frames the table's frames are) and D Beckmann (α = 0.3). Both
/// terms are physical Mueller matrices, so every interpolation of them is; both depend on θd
/// and θh only, so the table is reciprocal (exchanging ωi and ωo turns φd by π); its albedo is
/// at most ρ + k·∫D dωh ≈ ρ + 1.05 k.
fn pbrdf(rho: [f32; 3], k: f32, nan_corner: bool) -> PbrdfTable {
    use std::f32::consts::{FRAC_PI_2, PI};
    let phi_d: Vec<f32> = (0..9).map(|i| -PI + i as f32 * PI / 4.0).collect();
    let theta_d: Vec<f32> = (0..12).map(|i| FRAC_PI_2 * i as f32 / 11.0).collect();
    // Denser near the normal, where the lobe is.
    let theta_h: Vec<f32> = (0..16).map(|i| FRAC_PI_2 * (i as f32 / 15.0).powi(2)).collect();
    let wl = [450.0, 550.0, 650.0];
    let alpha = 0.3f32;
    let beckmann = |th: f32| {
        let c = th.cos();
        if c <= 1e-4 {
            return 0.0;
        }
        let t2 = (1.0 - c * c) / (c * c);
        (-t2 / (alpha * alpha)).exp() / (PI * alpha * alpha * c.powi(4))
    };
    let mut m = Vec::new();
    for _ in &phi_d {
        for (d, &td) in theta_d.iter().enumerate() {
            for (h, &th) in theta_h.iter().enumerate() {
                let fresnel = dielectric_reflection(td.cos(), SampledSpectrum::splat(1.5));
                let g = k * beckmann(th) / (4.0 * td.cos().max(1e-3));
                for r in rho {
                    for row in 0..4 {
                        for col in 0..4 {
                            let mut v = g * fresnel.0[row][col][0];
                            if row + col == 0 {
                                v += r / PI;
                            }
                            // An unmeasurable corner, as the dataset marks them.
                            if nan_corner && d == theta_d.len() - 1 && h == theta_h.len() - 1 {
                                v = f32::NAN;
                            }
                            m.push(v);
                        }
                    }
                }
            }
        }
    }
    PbrdfTable::new(phi_d, theta_d, theta_h, wl.to_vec(), m).unwrap()
}

#[test]
fn measured_polarized_glossy_glass_over_diffuse() {
    let b = MeasuredPolarized::new(pbrdf([0.5, 0.3, 0.7], 0.3, false), 0.3, None);
    assert_passes("measured_polarized diffuse + glass lobe, alpha_sample 0.3", &b);
}

#[test]
fn measured_polarized_sharp_sampling_lobe_and_a_nan_corner() {
    // The sampling lobe narrower than the table's (only the noise changes) and a NaN node at
    // grazing θd and θh (its neighbourhood evaluates to 0).
    let b = MeasuredPolarized::new(pbrdf([0.2, 0.2, 0.2], 0.6, true), 0.05, None);
    assert_passes("measured_polarized alpha_sample 0.05, NaN corner", &b);
}

#[test]
fn measured_polarized_one_wavelength() {
    let b = MeasuredPolarized::new(pbrdf([0.1, 0.6, 0.9], 0.3, false), 0.1, Some(600.0));
    assert_passes("measured_polarized at 600 nm only", &b);
}
