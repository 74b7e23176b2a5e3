//! Phase functions: the angular distribution of light scattered in a participating medium, the
//! medium's counterpart of the BSDF (Mitsuba 3 `src/phase/`, pbrt-v4 §11.3).
//!
//! A phase function p(ωi, ωo) is a density over the sphere of outgoing directions
//! (∫ p dωo = 1), reciprocal, and here a function of cos θ = ωi · ωo alone. Directions follow the
//! BSDF convention of Mitsuba and pbrt: both point away from the scattering point, ωi back
//! towards where the light goes (−d for a ray of direction d), so forward scattering is
//! ωo = −ωi, cos θ = −1.
//!
//! | plugin | p(cos θ) | parameter (default) |
//! |---|---|---|
//! | `isotropic` | 1/(4π) | — |
//! | `hg` (Henyey and Greenstein 1941) | (1 − g²) / (4π (1 + g² + 2g cos θ)^{3/2}) | `g` ∈ (−1, 1) (0.8) |
//!
//! g is the mean cosine of the deflection (−ωi · ωo); g > 0 scatters forwards.
//! | `rayleigh` | 3 (1 + cos² θ) / (16π) | — |
//!
//! Every model is sampled exactly (the sample's weight p/pdf is 1): Henyey–Greenstein by the
//! inverse of its cumulative distribution in cos θ (pbrt-v4's `SampleHenyeyGreenstein`),
//! Rayleigh by Cardano's root of the cubic its distribution is.

use crate::frame::Frame;
use crate::warp::square_to_uniform_sphere;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// 1/(4π).
const INV_FOUR_PI: f32 = 0.25 / PI;

/// A phase function (`Copy`, allocation free).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhaseFunction {
    /// The same density in every direction, 1/(4π).
    Isotropic,
    /// Henyey–Greenstein with mean cosine `g` of the deflection (|g| < 1).
    HenyeyGreenstein {
        /// Asymmetry: the mean of cos(deflection); > 0 scatters forwards.
        g: f32,
    },
    /// Rayleigh scattering by particles much smaller than the wavelength (unpolarized).
    Rayleigh,
}

/// A direction drawn from a phase function, with its density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseSample {
    /// The outgoing direction (unit).
    pub wo: Vec3,
    /// Its density (equal to the phase function's value: the weight is 1).
    pub pdf: f32,
}

/// Henyey–Greenstein's density for the cosine `cos_theta` = ωi · ωo (see the module table).
#[inline]
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let denom = 1.0 + g * g + 2.0 * g * cos_theta;
    INV_FOUR_PI * (1.0 - g * g) / (denom * denom.max(0.0).sqrt())
}

/// Rayleigh's density for the cosine `cos_theta` between the two directions.
#[inline]
pub fn rayleigh(cos_theta: f32) -> f32 {
    3.0 / (16.0 * PI) * (1.0 + cos_theta * cos_theta)
}

impl PhaseFunction {
    /// p(ωi, ωo).
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> f32 {
        let c = wi.dot(wo).clamp(-1.0, 1.0);
        match *self {
            PhaseFunction::Isotropic => INV_FOUR_PI,
            PhaseFunction::HenyeyGreenstein { g } => henyey_greenstein(c, g),
            PhaseFunction::Rayleigh => rayleigh(c),
        }
    }

    /// Draws ωo for `wi` from two uniform numbers; its density is [`PhaseFunction::eval`].
    #[inline]
    pub fn sample(&self, wi: Vec3, u: Vec2) -> PhaseSample {
        let wo = match *self {
            PhaseFunction::Isotropic => square_to_uniform_sphere(u),
            PhaseFunction::HenyeyGreenstein { g } => {
                // cos θ = ωi · ωo by the inverse cumulative distribution (pbrt-v4,
                // `SampleHenyeyGreenstein`): negative mostly for g > 0.
                let cos_theta = if g.abs() < 1e-3 {
                    1.0 - 2.0 * u.x
                } else {
                    let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
                    -(1.0 + g * g - s * s) / (2.0 * g)
                };
                around(wi, cos_theta.clamp(-1.0, 1.0), u.y)
            }
            PhaseFunction::Rayleigh => {
                // The cumulative distribution of μ = cos θ is (μ³ + 3μ + 4)/8: solve
                // μ³ + 3μ − (8u − 4) = 0 by Cardano (one real root).
                let q = 4.0 * u.x - 2.0;
                let r = (q * q + 1.0).sqrt();
                let mu = (q + r).cbrt() + (q - r).cbrt();
                around(wi, mu.clamp(-1.0, 1.0), u.y)
            }
        };
        PhaseSample {
            wo,
            pdf: self.eval(wi, wo),
        }
    }

    /// The mean cosine of the deflection (g; 0 for the symmetric models).
    pub fn mean_cosine(&self) -> f32 {
        match *self {
            PhaseFunction::HenyeyGreenstein { g } => g,
            _ => 0.0,
        }
    }
}

/// The unit direction at cosine `cos_theta` from the unit `axis`, at azimuth 2π·`u`.
#[inline]
fn around(axis: Vec3, cos_theta: f32, u: f32) -> Vec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let (s, c) = (2.0 * PI * u).sin_cos();
    Frame::from_normal(axis).to_world(Vec3::new(sin_theta * c, sin_theta * s, cos_theta))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ p dω by the midpoint rule in cos θ (the models depend on it alone).
    fn integral(p: PhaseFunction) -> f64 {
        let n = 200_000;
        let wi = Vec3::Z;
        (0..n)
            .map(|i| {
                let c = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                let s = (1.0 - c * c).sqrt();
                p.eval(wi, Vec3::new(s as f32, 0.0, c as f32)) as f64
            })
            .sum::<f64>()
            * 2.0
            / n as f64
            * 2.0
            * std::f64::consts::PI
    }

    #[test]
    fn every_phase_function_integrates_to_one() {
        for p in [
            PhaseFunction::Isotropic,
            PhaseFunction::Rayleigh,
            PhaseFunction::HenyeyGreenstein { g: 0.0 },
            PhaseFunction::HenyeyGreenstein { g: 0.7 },
            PhaseFunction::HenyeyGreenstein { g: -0.5 },
        ] {
            let i = integral(p);
            assert!((i - 1.0).abs() < 1e-4, "{p:?}: ∫p = {i}");
        }
    }

    #[test]
    fn positive_g_scatters_forwards_and_g_is_the_mean_deflection_cosine() {
        let p = PhaseFunction::HenyeyGreenstein { g: 0.7 };
        let wi = Vec3::Z;
        // Forward is −ωi.
        assert!(p.eval(wi, -Vec3::Z) > 10.0 * p.eval(wi, Vec3::Z));
        // E[−ωi · ωo] = g over the sampled directions.
        let n = 200_000;
        let mut rng = crate::rng::Pcg32::new(7, 1);
        let mean: f64 = (0..n)
            .map(|_| {
                let s = p.sample(wi, Vec2::new(rng.next_f32(), rng.next_f32()));
                -(s.wo.dot(wi)) as f64
            })
            .sum::<f64>()
            / n as f64;
        // The deflection cosine's standard deviation is below 1: 5σ is under 0.012.
        assert!((mean - 0.7).abs() < 0.012, "mean cosine {mean}");
    }

    #[test]
    fn samples_are_unit_and_carry_the_density_of_eval() {
        let mut rng = crate::rng::Pcg32::new(3, 5);
        for p in [
            PhaseFunction::Isotropic,
            PhaseFunction::Rayleigh,
            PhaseFunction::HenyeyGreenstein { g: 0.9 },
            PhaseFunction::HenyeyGreenstein { g: -0.3 },
        ] {
            let wi = Vec3::new(0.3, -0.5, 0.8).normalize();
            for _ in 0..1000 {
                let s = p.sample(wi, Vec2::new(rng.next_f32(), rng.next_f32()));
                assert!((s.wo.length() - 1.0).abs() < 1e-4);
                assert!((s.pdf - p.eval(wi, s.wo)).abs() <= 1e-5 * s.pdf.max(1.0));
                assert!(s.pdf > 0.0);
            }
        }
    }

    /// The sampled cosines ωi · ωo follow the distribution 2π·p integrates to (Kolmogorov–Smirnov:
    /// D below 1.63/√N, the 1 % level), and the azimuth about ωi is uniform.
    #[test]
    fn sampled_cosines_follow_the_density() {
        let n = 100_000;
        let wi = Vec3::new(-0.2, 0.6, 0.7).normalize();
        for p in [
            PhaseFunction::Isotropic,
            PhaseFunction::Rayleigh,
            PhaseFunction::HenyeyGreenstein { g: 0.8 },
            PhaseFunction::HenyeyGreenstein { g: -0.4 },
        ] {
            let mut rng = crate::rng::Pcg32::new(11, 3);
            let mut mu: Vec<f64> = Vec::with_capacity(n);
            let frame = Frame::from_normal(wi);
            let mut quadrants = [0usize; 4];
            for _ in 0..n {
                let s = p.sample(wi, Vec2::new(rng.next_f32(), rng.next_f32()));
                mu.push(wi.dot(s.wo).clamp(-1.0, 1.0) as f64);
                let l = frame.to_local(s.wo);
                quadrants[(l.x >= 0.0) as usize * 2 + (l.y >= 0.0) as usize] += 1;
            }
            mu.sort_by(f64::total_cmp);
            // The cumulative distribution of μ by the midpoint rule on a fine grid.
            let m = 20_000;
            let mut cdf = vec![0.0f64; m + 1];
            for k in 0..m {
                let c = -1.0 + 2.0 * (k as f64 + 0.5) / m as f64;
                let s = (1.0 - c * c).sqrt();
                let wo = frame.to_world(Vec3::new(s as f32, 0.0, c as f32));
                cdf[k + 1] = cdf[k] + 2.0 * std::f64::consts::PI * p.eval(wi, wo) as f64 * 2.0 / m as f64;
            }
            let at = |x: f64| {
                let t = ((x + 1.0) / 2.0 * m as f64).clamp(0.0, m as f64);
                let k = (t as usize).min(m - 1);
                cdf[k] + (cdf[k + 1] - cdf[k]) * (t - k as f64)
            };
            let d = mu
                .iter()
                .enumerate()
                .map(|(i, &x)| {
                    let f = at(x);
                    (f - i as f64 / n as f64)
                        .abs()
                        .max((f - (i + 1) as f64 / n as f64).abs())
                })
                .fold(0.0, f64::max);
            assert!(d < 1.63 / (n as f64).sqrt(), "{p:?}: KS D = {d}");
            for q in quadrants {
                // Each quadrant of azimuth holds a quarter: 5σ of a binomial is 0.007.
                assert!((q as f64 / n as f64 - 0.25).abs() < 0.007, "{p:?}: {quadrants:?}");
            }
        }
    }

    #[test]
    fn rayleigh_sampling_inverts_its_cumulative_distribution() {
        let p = PhaseFunction::Rayleigh;
        for u in [0.0f32, 0.1, 0.37, 0.5, 0.81, 0.999] {
            let s = p.sample(Vec3::Z, Vec2::new(u, 0.2));
            let mu = s.wo.z as f64;
            let cdf = (mu * mu * mu + 3.0 * mu + 4.0) / 8.0;
            assert!((cdf - u as f64).abs() < 1e-5, "u {u}: cdf {cdf}");
        }
    }
}
