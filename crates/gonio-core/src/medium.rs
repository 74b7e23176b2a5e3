//! Free-flight sampling in a homogeneous participating medium at several wavelengths at once
//! (the distance part of a volumetric path tracer; Mitsuba 3 `src/media/homogeneous.cpp` and
//! `volpath.cpp`, pbrt-v4 §14.1).
//!
//! Along a ray in a medium of extinction σt(λ) the transmittance is T(λ, t) = exp(−σt(λ) t). A
//! path tracer draws the distance to the next collision from σt·T, at one wavelength: with a
//! chromatic σt the other wavelengths of the sample would then carry ratios of exponentials
//! that blow up. Here the wavelength whose σt drives the draw is itself chosen at random among
//! the sample's live wavelengths, so the density of the distance is the mixture (one-sample MIS
//! with the balance heuristic over wavelengths, "spectral MIS"):
//!
//! * a collision at t < t_max has density p(t) = (1/n) Σⱼ σt(λⱼ) T(λⱼ, t), and the path's
//!   throughput is multiplied by T(λ, t)/p(t) (the caller multiplies by σs(λ) = α(λ)·σt(λ) at
//!   a scattering event);
//! * no collision before the surface at t_max has probability P = (1/n) Σⱼ T(λⱼ, t_max), and
//!   the factor is T(λ, t_max)/P.
//!
//! With a grey σt both factors reduce to the analogue ones: α at a collision, 1 at the surface.
//! Mitsuba draws at one wavelength chosen at random and divides by that wavelength's density
//! alone (unbiased, noisier where σt varies); the expectation is the same.

use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};

/// A distance drawn by [`sample_free_flight`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeFlight {
    /// Distance along the ray: the collision's, or `t_max` when none occurred.
    pub t: f32,
    /// True when the medium scatters or absorbs at `t` (< `t_max`).
    pub collided: bool,
    /// The factor of the throughput: T/p at a collision (σs not included), T/P without one.
    pub weight: SampledSpectrum,
}

/// The number of the sample's wavelengths still carried (1 after a dispersive refraction).
#[inline]
fn live(wl: &SampledWavelengths) -> usize {
    if wl.secondary_terminated() {
        1
    } else {
        N_SPECTRUM_SAMPLES
    }
}

/// Draws the distance to the next collision along a ray in a medium of extinction `sigma_t`
/// (per wavelength, ≥ 0) before the surface at `t_max` (may be infinite) from one uniform number
/// `u` (see the module documentation). A ray that escapes to infinity through a medium with
/// σt > 0 at every live wavelength always collides. [`sample_distance`] and
/// [`flight_weight`] in one.
pub fn sample_free_flight(
    sigma_t: SampledSpectrum,
    t_max: f32,
    u: f32,
    wl: &SampledWavelengths,
) -> FreeFlight {
    let t = sample_distance(sigma_t, u, wl);
    let collided = t < t_max;
    let t = if collided { t } else { t_max };
    FreeFlight {
        t,
        collided,
        weight: flight_weight(sigma_t, t, collided, wl),
    }
}

/// The distance to the next collision in an unbounded medium of extinction `sigma_t`, drawn from
/// `u` at a wavelength chosen by `u` among the live ones (infinite where that σt is 0). A
/// renderer can draw it before it knows where the next surface is, and look for that surface
/// only up to it (Mitsuba's order): the flight collided if no surface is nearer.
#[inline]
pub fn sample_distance(sigma_t: SampledSpectrum, u: f32, wl: &SampledWavelengths) -> f32 {
    let s = sigma_t.to_array();
    let (c, u) = if s.iter().all(|&x| x == s[0]) {
        (0, u)
    } else {
        // The wavelength that drives the draw, and u reused for the distance.
        let n = live(wl);
        let scaled = u * n as f32;
        let c = (scaled as usize).min(n - 1);
        (c, scaled - c as f32)
    };
    let u = u.clamp(0.0, 1.0 - f32::EPSILON / 2.0);
    if s[c] > 0.0 {
        -(1.0 - u).ln() / s[c]
    } else {
        f32::INFINITY
    }
}

/// The throughput's factor for a flight drawn by [`sample_distance`] that `collided` at `t`
/// (T/p, σs not included) or reached a surface at `t` (T/P; `t` infinite: escaped).
#[inline]
pub fn flight_weight(
    sigma_t: SampledSpectrum,
    t: f32,
    collided: bool,
    wl: &SampledWavelengths,
) -> SampledSpectrum {
    let n = live(wl);
    let s = sigma_t.to_array();
    if s.iter().all(|&x| x == s[0]) {
        // Grey: the analogue flight (1/σt at a collision, 1 past it), no exponentials.
        return mask(SampledSpectrum::splat(if collided { 1.0 / s[0] } else { 1.0 }), n);
    }
    if collided {
        let tr = (sigma_t * -t).exp();
        let pdf = (sigma_t * tr).to_array()[..n].iter().sum::<f32>() / n as f32;
        mask(tr * (1.0 / pdf), n)
    } else {
        let tr = transmittance(sigma_t, t);
        let p = tr.to_array()[..n].iter().sum::<f32>() / n as f32;
        if p > 0.0 {
            mask(tr * (1.0 / p), n)
        } else {
            SampledSpectrum::splat(0.0)
        }
    }
}

/// What a tentative collision of delta tracking is ([`null_collision_event`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tracking {
    /// A real collision: the throughput's factor 1/p̄ before σs (the caller multiplies by
    /// σs = α·σt at a scattering event).
    Real(SampledSpectrum),
    /// A null collision: the throughput's factor σn/(σ̄·(1 − p̄)), σn = σ̄ − σt; the flight goes
    /// on.
    Null(SampledSpectrum),
}

/// Delta tracking in a heterogeneous medium under a grey majorant `sigma_bar` ≥ σt(λ) (pbrt-v4
/// §14.2, Woodcock tracking): tentative collisions come at rate σ̄; at one, where the
/// extinction is `sigma_t`, the event is real with probability p̄ = mean σt(λ)/σ̄ over the live
/// wavelengths, null otherwise, and weighted so that each wavelength's estimate is unbiased:
/// real σt(λ)/(σ̄·p̄) (returned without σt, see [`Tracking::Real`]), null σn(λ)/(σ̄·(1 − p̄)).
/// With a grey σt this is analogue delta tracking (weights α and 1). `u` is uniform.
pub fn null_collision_event(
    sigma_t: SampledSpectrum,
    sigma_bar: f32,
    u: f32,
    wl: &SampledWavelengths,
) -> Tracking {
    let n = live(wl);
    let mean = sigma_t.to_array()[..n].iter().sum::<f32>() / n as f32;
    let p_real = (mean / sigma_bar).clamp(0.0, 1.0);
    if u < p_real {
        Tracking::Real(mask(SampledSpectrum::splat(1.0 / (sigma_bar * p_real)), n))
    } else {
        let sigma_n = (sigma_bar - sigma_t).clamp_zero();
        Tracking::Null(mask(sigma_n * (1.0 / (sigma_bar * (1.0 - p_real))), n))
    }
}

/// The transmittance exp(−σt·d) over a distance `d` (0 where d is infinite and σt > 0).
#[inline]
pub fn transmittance(sigma_t: SampledSpectrum, d: f32) -> SampledSpectrum {
    if d.is_finite() {
        (sigma_t * -d).exp()
    } else {
        SampledSpectrum::from_fn(|j| if sigma_t.to_array()[j] > 0.0 { 0.0 } else { 1.0 })
    }
}

/// `w` with the wavelengths past the first `n` set to 0.
#[inline]
fn mask(w: SampledSpectrum, n: usize) -> SampledSpectrum {
    if n == N_SPECTRUM_SAMPLES {
        w
    } else {
        SampledSpectrum::from_fn(|j| if j < n { w.to_array()[j] } else { 0.0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;

    fn wl() -> SampledWavelengths {
        SampledWavelengths::sample_visible(0.3)
    }

    #[test]
    fn a_grey_medium_weighs_collisions_by_one_and_passes_by_one() {
        let s = SampledSpectrum::splat(2.0);
        let mut rng = Pcg32::new(1, 2);
        for _ in 0..1000 {
            let f = sample_free_flight(s, 0.7, rng.next_f32(), &wl());
            for w in f.weight.to_array() {
                let expected = if f.collided { 0.5 } else { 1.0 };
                assert!((w - expected).abs() < 1e-4, "{f:?}");
            }
        }
    }

    /// The estimator's mean equals the transmittance to the surface (collisions end the walk with
    /// weight 0 when the medium only absorbs: E = T(t_max)), and the collision density integrates
    /// the absorbed part: E[weight·σt at collisions] = 1 − T(t_max), per wavelength.
    #[test]
    fn chromatic_free_flights_are_unbiased_at_every_wavelength() {
        let sigma = SampledSpectrum::new([0.5, 1.5, 3.0, 6.0]);
        let t_max = 0.8;
        let n = 400_000;
        let mut rng = Pcg32::new(9, 4);
        let mut pass = [0f64; 4];
        let mut absorbed = [0f64; 4];
        for _ in 0..n {
            let f = sample_free_flight(sigma, t_max, rng.next_f32(), &wl());
            for j in 0..4 {
                if f.collided {
                    absorbed[j] += (f.weight.to_array()[j] * sigma.to_array()[j]) as f64;
                } else {
                    pass[j] += f.weight.to_array()[j] as f64;
                }
            }
        }
        for j in 0..4 {
            let tr = (-(sigma.to_array()[j] as f64) * t_max as f64).exp();
            let (p, a) = (pass[j] / n as f64, absorbed[j] / n as f64);
            // The weights are bounded by a few units: 5σ/√n is below 0.02.
            assert!((p - tr).abs() < 0.02, "λ{j}: pass {p} against T {tr}");
            assert!(
                (a - (1.0 - tr)).abs() < 0.02,
                "λ{j}: absorbed {a} against {}",
                1.0 - tr
            );
        }
    }

    #[test]
    fn an_infinite_flight_through_a_medium_always_collides() {
        let s = SampledSpectrum::new([0.5, 1.0, 2.0, 4.0]);
        for u in [0.0f32, 0.3, 0.999_999] {
            let f = sample_free_flight(s, f32::INFINITY, u, &wl());
            assert!(f.collided && f.t.is_finite() && f.weight.is_finite(), "{f:?}");
        }
        assert_eq!(transmittance(s, f32::INFINITY), SampledSpectrum::splat(0.0));
    }

    /// Through a slab whose σt(λ) varies along it, under a majorant, the product of the null
    /// weights of the flights that pass is the transmittance exp(−∫σt), per wavelength.
    #[test]
    fn delta_tracking_is_unbiased_at_every_wavelength() {
        let sigma = |x: f32| SampledSpectrum::new([0.5, 1.0, 2.0, 3.0]) * (0.5 + x);
        let (d, bar) = (1.0f32, 4.5f32);
        let n = 200_000;
        let mut rng = Pcg32::new(5, 6);
        let mut pass = [0f64; 4];
        for _ in 0..n {
            let mut t = 0.0;
            let mut w = SampledSpectrum::splat(1.0);
            loop {
                t += -(1.0 - rng.next_f32()).ln() / bar;
                if t >= d {
                    for j in 0..4 {
                        pass[j] += w.to_array()[j] as f64;
                    }
                    break;
                }
                match null_collision_event(sigma(t), bar, rng.next_f32(), &wl()) {
                    Tracking::Real(_) => break,
                    Tracking::Null(f) => w *= f,
                }
            }
        }
        for j in 0..4 {
            // ∫₀¹ σ(0.5 + x) dx = σ.
            let tr = (-(SampledSpectrum::new([0.5, 1.0, 2.0, 3.0]).to_array()[j] as f64)).exp();
            let p = pass[j] / n as f64;
            assert!((p - tr).abs() < 0.01, "λ{j}: {p} against {tr}");
        }
    }

    #[test]
    fn after_dispersion_only_the_hero_wavelength_is_carried() {
        let mut w = wl();
        w.terminate_secondary();
        let f = sample_free_flight(SampledSpectrum::new([1.0, 2.0, 3.0, 4.0]), 0.5, 0.9, &w);
        let a = f.weight.to_array();
        assert!(a[0] > 0.0 && a[1..].iter().all(|&x| x == 0.0), "{f:?}");
    }
}
