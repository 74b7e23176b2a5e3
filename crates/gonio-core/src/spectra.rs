//! Spectrum kinds: wavelength-dependent quantities as functions of λ (nm), independent of any
//! particular path. A [`Spectrum`] is evaluated at the four wavelengths of a path with
//! [`Spectrum::sample`].
//!
//! Kinds: constant, piecewise linear (Mitsuba's `<spectrum value="400:0.1, 500:0.3"/>` and
//! `.spd` files, pbrt's named tables), RGB-uplifted (Jakob & Hanika 2019), blackbody, and the
//! dispersion formulas of Sellmeier and Cauchy.

use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use std::sync::Arc;

/// What a piecewise-linear table returns outside its wavelength range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extrapolation {
    /// 0 outside the table (Mitsuba `irregular`, pbrt `PiecewiseLinear`).
    Zero,
    /// The end values continue (measured η/k data: zero η and k would give NaN Fresnel).
    Clamp,
}

/// A spectrum given as (λ, value) samples with linear interpolation.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseLinear {
    lambda: Vec<f32>,
    value: Vec<f32>,
    extrapolation: Extrapolation,
}

impl PiecewiseLinear {
    /// From samples; `lambda` must be strictly increasing, both the same length ≥ 1.
    /// Returns `None` otherwise (the scene reader turns that into an error naming the value).
    pub fn new(lambda: Vec<f32>, value: Vec<f32>, extrapolation: Extrapolation) -> Option<Self> {
        let ok = !lambda.is_empty()
            && lambda.len() == value.len()
            && lambda.windows(2).all(|w| w[0] < w[1])
            && lambda.iter().chain(&value).all(|x| x.is_finite());
        ok.then_some(Self { lambda, value, extrapolation })
    }

    /// From interleaved `[λ₀, v₀, λ₁, v₁, ...]` static data.
    pub fn from_interleaved(data: &[f32], extrapolation: Extrapolation) -> Option<Self> {
        if data.len() % 2 != 0 {
            return None;
        }
        let lambda = data.iter().step_by(2).copied().collect();
        let value = data.iter().skip(1).step_by(2).copied().collect();
        Self::new(lambda, value, extrapolation)
    }

    /// Value at `lambda` (nm).
    pub fn eval(&self, lambda: f32) -> f32 {
        let (l, v) = (&self.lambda, &self.value);
        let n = l.len();
        if lambda < l[0] || lambda > l[n - 1] {
            return match self.extrapolation {
                Extrapolation::Zero => 0.0,
                Extrapolation::Clamp => {
                    if lambda < l[0] {
                        v[0]
                    } else {
                        v[n - 1]
                    }
                }
            };
        }
        if n == 1 {
            return v[0];
        }
        // Index of the last sample ≤ lambda, kept inside [0, n − 2].
        let i = l.partition_point(|&x| x <= lambda).clamp(1, n - 1) - 1;
        let t = (lambda - l[i]) / (l[i + 1] - l[i]);
        v[i] + t * (v[i + 1] - v[i])
    }

    /// Largest sample value.
    pub fn max_value(&self) -> f32 {
        self.value.iter().copied().fold(f32::MIN, f32::max)
    }

    /// The sample wavelengths, nm.
    pub fn lambdas(&self) -> &[f32] {
        &self.lambda
    }
    /// The sample values.
    pub fn values(&self) -> &[f32] {
        &self.value
    }
}

/// A wavelength-dependent quantity. Cheap to clone (tables are shared).
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f32),
    /// Linear interpolation between samples.
    PiecewiseLinear(Arc<PiecewiseLinear>),
}

impl Spectrum {
    /// A constant spectrum.
    pub const fn constant(v: f32) -> Self {
        Spectrum::Constant(v)
    }

    /// Value at one wavelength (nm).
    pub fn eval(&self, lambda: f32) -> f32 {
        match self {
            Spectrum::Constant(v) => *v,
            Spectrum::PiecewiseLinear(p) => p.eval(lambda),
        }
    }

    /// Values at the four wavelengths of a path.
    #[inline]
    pub fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Spectrum::Constant(v) => SampledSpectrum::splat(*v),
            _ => SampledSpectrum::from_fn(|i| self.eval(wl.lambda(i))),
        }
    }

    /// True when the value does not depend on λ.
    pub fn is_constant(&self) -> bool {
        matches!(self, Spectrum::Constant(_))
    }

    /// The constant value, if the spectrum is constant.
    pub fn as_constant(&self) -> Option<f32> {
        match self {
            Spectrum::Constant(v) => Some(*v),
            _ => None,
        }
    }

    /// An upper bound of the value over 360–830 nm.
    pub fn max_value(&self) -> f32 {
        match self {
            Spectrum::Constant(v) => *v,
            Spectrum::PiecewiseLinear(p) => p.max_value(),
        }
    }

    /// Mean over 360–830 nm (1 nm steps): Mitsuba's `mean()` of a texture, used by `plastic`
    /// to weigh its sampling between lobes.
    pub fn mean(&self) -> f32 {
        match self {
            Spectrum::Constant(v) => *v,
            _ => {
                let n = 471;
                (0..n).map(|i| self.eval(360.0 + i as f32)).sum::<f32>() / n as f32
            }
        }
    }
}

impl From<f32> for Spectrum {
    fn from(v: f32) -> Self {
        Spectrum::Constant(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piecewise_linear_interpolates_and_extrapolates() {
        let p = PiecewiseLinear::new(vec![400.0, 500.0, 600.0], vec![0.1, 0.3, 0.2], Extrapolation::Zero)
            .unwrap();
        assert_eq!(p.eval(400.0), 0.1);
        assert!((p.eval(450.0) - 0.2).abs() < 1e-6);
        assert!((p.eval(550.0) - 0.25).abs() < 1e-6);
        assert_eq!(p.eval(600.0), 0.2);
        assert_eq!(p.eval(399.0), 0.0);
        assert_eq!(p.eval(601.0), 0.0);
        let c = PiecewiseLinear { extrapolation: Extrapolation::Clamp, ..p };
        assert_eq!(c.eval(300.0), 0.1);
        assert_eq!(c.eval(700.0), 0.2);
    }

    #[test]
    fn piecewise_linear_rejects_bad_tables() {
        assert!(PiecewiseLinear::new(vec![500.0, 400.0], vec![1.0, 2.0], Extrapolation::Zero).is_none());
        assert!(PiecewiseLinear::new(vec![], vec![], Extrapolation::Zero).is_none());
        assert!(PiecewiseLinear::new(vec![400.0], vec![f32::NAN], Extrapolation::Zero).is_none());
        assert!(PiecewiseLinear::from_interleaved(&[400.0, 1.0, 500.0], Extrapolation::Zero).is_none());
    }
}
