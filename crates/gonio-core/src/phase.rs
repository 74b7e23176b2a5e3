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
//! | `rayleigh` | 3 (1 + cos² θ) / (16π) | — |
//! | `tabphase` | p(μ)/(2π), p piecewise linear in μ = −cos θ on n nodes spread evenly over [−1, 1], normalized | `values` (the nodes) |
//!
//! g is the mean cosine of the deflection (−ωi · ωo); g > 0 scatters forwards. `tabphase`'s table
//! is laid out in the physics convention, μ = 1 forwards (Mitsuba 3 `src/phase/tabphase.cpp`).
//!
//! Every model is sampled exactly (the sample's weight p/pdf is 1): Henyey–Greenstein by the
//! inverse of its cumulative distribution in cos θ (pbrt-v4's `SampleHenyeyGreenstein`),
//! Rayleigh by Cardano's root of the cubic its distribution is, a table by choosing a cell by
//! its trapezoid's mass and inverting the linear density inside it.

use crate::frame::Frame;
use crate::sampling::Distribution1D;
use crate::warp::square_to_uniform_sphere;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::Arc;

/// 1/(4π).
const INV_FOUR_PI: f32 = 0.25 / PI;

/// A phase function (allocation free to evaluate and sample; a table is shared, not copied).
#[derive(Clone, Debug, PartialEq)]
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
    /// A table over the cosine of the deflection (Mitsuba's `tabphase`).
    Tabulated(Arc<TabulatedPhase>),
}

/// A phase function tabulated over μ = −ωi · ωo (the cosine of the deflection; 1 forwards) on
/// n ≥ 2 nodes spread evenly over [−1, 1], linear between them and normalized to ∫ p dω = 1:
/// p(ωi, ωo) = p̂(μ)/(2π) with ∫₋₁¹ p̂ dμ = 1 (Mitsuba's `tabphase`, its
/// `ContinuousDistribution`).
#[derive(Clone, Debug, PartialEq)]
pub struct TabulatedPhase {
    /// p̂ at the nodes, normalized.
    nodes: Box<[f32]>,
    /// The cells by the mass of their trapezoids.
    cells: Distribution1D,
}

impl TabulatedPhase {
    /// The table of these node values (not normalized). `None` unless there are at least two,
    /// all finite and non-negative, and some positive.
    pub fn new(values: &[f32]) -> Option<Self> {
        if values.len() < 2 || values.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return None;
        }
        let h = 2.0 / (values.len() - 1) as f64;
        let masses: Vec<f32> = values
            .windows(2)
            .map(|w| (0.5 * (w[0] as f64 + w[1] as f64) * h) as f32)
            .collect();
        let integral: f64 = masses.iter().map(|&m| m as f64).sum();
        if !(integral > 0.0 && integral.is_finite()) {
            return None;
        }
        Some(Self {
            nodes: values.iter().map(|&v| (v as f64 / integral) as f32).collect(),
            cells: Distribution1D::new(&masses),
        })
    }

    /// Width of a cell in μ.
    #[inline]
    fn cell_width(&self) -> f32 {
        2.0 / (self.nodes.len() - 1) as f32
    }

    /// p̂(μ): the normalized density over μ ∈ [−1, 1] (linear between the nodes).
    #[inline]
    pub fn density(&self, mu: f32) -> f32 {
        let n = self.nodes.len();
        let t = ((mu + 1.0) / self.cell_width()).clamp(0.0, (n - 1) as f32);
        let i = (t as usize).min(n - 2);
        let f = t - i as f32;
        self.nodes[i] * (1.0 - f) + self.nodes[i + 1] * f
    }

    /// Draws μ with density p̂ from a uniform number.
    #[inline]
    pub fn sample_mu(&self, u: f32) -> f32 {
        let (i, _, v) = self.cells.sample_discrete(u);
        let (y0, y1) = (self.nodes[i], self.nodes[i + 1]);
        // Inside the cell, the density ∝ y0 + (y1 − y0)·t; its cumulative mass
        // y0·t + (y1 − y0)·t²/2 equals v·(y0 + y1)/2 at t: the root in [0, 1], written without
        // the cancellation of (−y0 + √…)/(y1 − y0) (a cell drawn has y0 + y1 > 0).
        let target = v * (y0 + y1);
        let t = (target / (y0 + (y0 * y0 + (y1 - y0) * target).max(0.0).sqrt())).clamp(0.0, 1.0);
        (-1.0 + (i as f32 + t) * self.cell_width()).clamp(-1.0, 1.0)
    }
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
        match self {
            PhaseFunction::Isotropic => INV_FOUR_PI,
            PhaseFunction::HenyeyGreenstein { g } => henyey_greenstein(c, *g),
            PhaseFunction::Rayleigh => rayleigh(c),
            PhaseFunction::Tabulated(t) => t.density(-c) * (0.5 / PI),
        }
    }

    /// Draws ωo for `wi` from two uniform numbers; its density is [`PhaseFunction::eval`].
    #[inline]
    pub fn sample(&self, wi: Vec3, u: Vec2) -> PhaseSample {
        let wo = match self {
            PhaseFunction::Isotropic => square_to_uniform_sphere(u),
            &PhaseFunction::HenyeyGreenstein { g } => {
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
            PhaseFunction::Tabulated(t) => around(wi, -t.sample_mu(u.x), u.y),
        };
        PhaseSample {
            wo,
            pdf: self.eval(wi, wo),
        }
    }

    /// The mean cosine of the deflection (g; 0 for the symmetric models).
    pub fn mean_cosine(&self) -> f32 {
        match self {
            PhaseFunction::HenyeyGreenstein { g } => *g,
            PhaseFunction::Tabulated(t) => {
                // ∫ μ p̂(μ) dμ, exact for the linear pieces (Simpson's rule on each cell).
                let h = t.cell_width();
                (0..t.nodes.len() - 1)
                    .map(|i| {
                        let (a, b) = (-1.0 + i as f32 * h, -1.0 + (i + 1) as f32 * h);
                        let (ya, yb) = (t.nodes[i], t.nodes[i + 1]);
                        let m = 0.5 * (a + b);
                        h / 6.0 * (a * ya + 4.0 * m * 0.5 * (ya + yb) + b * yb)
                    })
                    .sum()
            }
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

    /// A table with slopes of both signs, a flat cell and a zero node.
    fn tables() -> [PhaseFunction; 2] {
        [
            PhaseFunction::Tabulated(Arc::new(
                TabulatedPhase::new(&[0.2, 0.5, 0.5, 0.1, 1.0, 4.0]).unwrap(),
            )),
            PhaseFunction::Tabulated(Arc::new(TabulatedPhase::new(&[0.0, 3.0, 0.0, 0.0, 2.0]).unwrap())),
        ]
    }

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
        ]
        .into_iter()
        .chain(tables())
        {
            let i = integral(p.clone());
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
        ]
        .into_iter()
        .chain(tables())
        {
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
        ]
        .into_iter()
        .chain(tables())
        {
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

    /// The table is read in the physics convention (μ = 1 forwards, ωo = −ωi), linear between
    /// its nodes, normalized, and its mean cosine is ∫ μ p̂ dμ.
    #[test]
    fn a_table_is_read_forwards_linear_and_normalized() {
        let t = TabulatedPhase::new(&[1.0, 3.0]).unwrap();
        // p̂(μ) = (2 + μ)/4 on [−1, 1]: ∫ = 1.
        for mu in [-1.0f32, -0.3, 0.0, 0.6, 1.0] {
            assert!((t.density(mu) - (2.0 + mu) / 4.0).abs() < 1e-6, "μ {mu}");
        }
        let p = PhaseFunction::Tabulated(Arc::new(t));
        let wi = Vec3::Z;
        assert!((p.eval(wi, -Vec3::Z) - 0.75 / (2.0 * PI)).abs() < 1e-6);
        assert!((p.eval(wi, Vec3::Z) - 0.25 / (2.0 * PI)).abs() < 1e-6);
        // ∫ μ (2 + μ)/4 dμ = 1/6.
        assert!((p.mean_cosine() - 1.0 / 6.0).abs() < 1e-6);
        for bad in [
            &[1.0f32][..],
            &[0.0, 0.0],
            &[1.0, -0.1],
            &[1.0, f32::NAN],
            &[f32::INFINITY, 1.0],
        ] {
            assert!(TabulatedPhase::new(bad).is_none(), "{bad:?}");
        }
    }
}
