//! Directional albedo: the fraction of light arriving from θ that leaves on the same side,
//! R(θ), and on the other side, T(θ), estimated by Monte Carlo through [`Bsdf::sample`] (delta
//! lobes included), with the standard error of each estimate.
//!
//! With Mitsuba naming, R(θ) = ∫ f(wi, wo) |cos θo| dωo over wo on wi's side, T over the other
//! side; E\[weight\] estimates it whatever the sampling strategy. In importance mode this is the
//! fraction of incident *power* a photon from θ carries away (energy conservation: R + T ≤ 1);
//! in radiance mode a refraction carries the η² factor of radiance.

use crate::bsdf::{Bsdf, BsdfContext, TransportMode};
use crate::check::energy::albedo_sampled_by;
use crate::rng::Pcg32;
use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES, SampledWavelengths};
use glam::Vec3;

/// Which wavelengths the albedo is averaged over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Wavelengths {
    /// One wavelength, nm.
    Fixed(f32),
    /// The mean over [360, 830] nm (uniform), four hero-rotated wavelengths per sample.
    Visible,
}

/// R and T at one incident angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlbedoPoint {
    /// Incident polar angle, degrees (measured on wi's side of the surface).
    pub theta_deg: f32,
    /// Reflected fraction R.
    pub r: f64,
    /// Standard error of R.
    pub r_stderr: f64,
    /// Transmitted fraction T.
    pub t: f64,
    /// Standard error of T.
    pub t_stderr: f64,
}

/// R(θ), T(θ) at each angle in `thetas_deg`, `samples` samples each, from a wi in the x–z plane
/// on the front side (+z) or, with `back_side`, on the back side (−z). The estimator is the
/// battery's ([`crate::check::energy::albedo_sampled_by`]): one implementation.
pub fn directional_albedo<B: Bsdf + ?Sized>(
    bsdf: &B,
    thetas_deg: &[f32],
    samples: usize,
    mode: TransportMode,
    wavelengths: Wavelengths,
    back_side: bool,
    seed: u64,
) -> Vec<AlbedoPoint> {
    let ctx = BsdfContext {
        mode,
        ..BsdfContext::radiance()
    };
    let samples = samples.max(2);
    thetas_deg
        .iter()
        .enumerate()
        .map(|(k, &theta_deg)| {
            let t = theta_deg.to_radians();
            let mut wi = Vec3::new(t.sin(), 0.0, t.cos());
            if back_side {
                wi.z = -wi.z;
            }
            let mut rng = Pcg32::new(seed, k as u64);
            let a = match wavelengths {
                Wavelengths::Fixed(l) => albedo_sampled_by(
                    bsdf,
                    &ctx,
                    wi,
                    samples,
                    &mut rng,
                    |_| SampledWavelengths::fixed(l),
                    |_, w| [w[0] as f64; N_SPECTRUM_SAMPLES],
                ),
                // The visible-range mean (1/Δλ)∫ a(λ) dλ, by the spectral estimator.
                Wavelengths::Visible => albedo_sampled_by(
                    bsdf,
                    &ctx,
                    wi,
                    samples,
                    &mut rng,
                    |rng| SampledWavelengths::sample_uniform(rng.next_f32(), LAMBDA_MIN, LAMBDA_MAX),
                    |wl, w| [(wl.estimate(w) / (LAMBDA_MAX - LAMBDA_MIN)) as f64; N_SPECTRUM_SAMPLES],
                ),
            };
            AlbedoPoint {
                theta_deg,
                r: a.r[0],
                r_stderr: a.r_se[0],
                t: a.t[0],
                t_stderr: a.t_se[0],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::Diffuse;
    use crate::spectra::Spectrum;

    #[test]
    fn lambertian_albedo_is_rho_at_every_angle_and_nothing_is_transmitted() {
        let d = Diffuse::new(Spectrum::Constant(0.7));
        let pts = directional_albedo(
            &d,
            &[0.0, 45.0, 85.0],
            1000,
            TransportMode::Radiance,
            Wavelengths::Fixed(550.0),
            false,
            1,
        );
        for p in pts {
            assert!((p.r - 0.7).abs() < 1e-6, "{p:?}");
            assert!(p.r_stderr < 1e-6);
            assert_eq!(p.t, 0.0);
        }
        let back = directional_albedo(
            &d,
            &[30.0],
            100,
            TransportMode::Radiance,
            Wavelengths::Visible,
            true,
            1,
        );
        assert_eq!(back[0].r, 0.0, "one-sided: nothing from below");
    }
}
