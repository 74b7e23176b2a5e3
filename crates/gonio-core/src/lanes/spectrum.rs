//! The spectral values of `N` paths at their four wavelengths each, and a BSDF sample of `N`
//! lanes.

use super::{F32s, Isa, Mask, Portable, Vec3s};
use crate::bsdf::BsdfFlags;
use crate::spectra::Spectrum;
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use std::ops::{Add, Mul};

/// A [`SampledSpectrum`] per lane, stored by wavelength: `self.0[i]` holds wavelength slot `i`
/// of every lane, so that a spectral operation is [`N_SPECTRUM_SAMPLES`] vector operations.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SampledSpectra<const N: usize, X: Isa = Portable>(pub [F32s<N, X>; N_SPECTRUM_SAMPLES]);

impl<const N: usize, X: Isa> SampledSpectra<N, X> {
    /// Zero everywhere.
    pub const ZERO: Self = Self([F32s::ZERO; N_SPECTRUM_SAMPLES]);

    /// The same value at every wavelength of every lane.
    #[inline(always)]
    pub fn splat(v: f32) -> Self {
        Self([F32s::splat(v); N_SPECTRUM_SAMPLES])
    }
    /// Lane `k` is `f(k)`.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> SampledSpectrum) -> Self {
        let mut r = Self::ZERO;
        for k in 0..N {
            let a = f(k).to_array();
            for (i, v) in a.into_iter().enumerate() {
                r.0[i].0[k] = v;
            }
        }
        r
    }
    /// Lane `k`.
    #[inline(always)]
    pub fn lane(&self, k: usize) -> SampledSpectrum {
        SampledSpectrum::from_fn(|i| self.0[i].0[k])
    }
    /// Applies `f` to each wavelength slot. (Kernels use the operators and methods below,
    /// which are plain loops: a closure that LLVM declines to inline, as it does inside
    /// `std::array::from_fn`, is compiled for the baseline instruction set, outside the
    /// kernel's vector context.)
    #[inline(always)]
    pub fn map(self, mut f: impl FnMut(F32s<N, X>) -> F32s<N, X>) -> Self {
        let mut r = self;
        for v in r.0.iter_mut() {
            *v = f(*v);
        }
        r
    }
    /// Per lane: `self` where `m` is set, 0 elsewhere.
    #[inline(always)]
    pub fn masked(self, m: Mask<N, X>) -> Self {
        let mut r = self;
        for v in r.0.iter_mut() {
            *v = m.and_then(*v);
        }
        r
    }
    /// Per lane: `a` where `m` is set, `b` elsewhere.
    #[inline(always)]
    pub fn select(m: Mask<N, X>, a: Self, b: Self) -> Self {
        let mut r = b;
        for i in 0..N_SPECTRUM_SAMPLES {
            r.0[i] = m.select(a.0[i], b.0[i]);
        }
        r
    }
    /// Division where the divisor is not 0, else 0 (as [`SampledSpectrum::safe_div`]).
    #[inline(always)]
    pub fn safe_div(self, d: Self) -> Self {
        let mut r = self;
        for i in 0..N_SPECTRUM_SAMPLES {
            r.0[i] = d.0[i].ne(0.0).and_then(self.0[i] / d.0[i]);
        }
        r
    }
    /// `1 − a·self` per wavelength (the denominator of a coated model's series).
    #[inline(always)]
    pub fn one_minus_scaled(self, a: f32) -> Self {
        let mut r = self;
        for v in r.0.iter_mut() {
            *v = 1.0 - *v * a;
        }
        r
    }
}

impl<const N: usize, X: Isa> Mul for SampledSpectra<N, X> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let mut r = self;
        for i in 0..N_SPECTRUM_SAMPLES {
            r.0[i] = self.0[i] * o.0[i];
        }
        r
    }
}

impl<const N: usize, X: Isa> Mul<F32s<N, X>> for SampledSpectra<N, X> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: F32s<N, X>) -> Self {
        let mut r = self;
        for v in r.0.iter_mut() {
            *v *= s;
        }
        r
    }
}

impl<const N: usize, X: Isa> Add for SampledSpectra<N, X> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        let mut r = self;
        for i in 0..N_SPECTRUM_SAMPLES {
            r.0[i] = self.0[i] + o.0[i];
        }
        r
    }
}

impl Spectrum {
    /// This spectrum at each lane's wavelengths (a broadcast for a constant).
    #[inline(always)]
    pub fn sample_lanes<const N: usize, X: Isa>(&self, wl: &[SampledWavelengths; N]) -> SampledSpectra<N, X> {
        match self {
            Spectrum::Constant(v) => SampledSpectra::splat(*v),
            _ => SampledSpectra::from_fn(|k| self.sample(&wl[k])),
        }
    }
}

/// [`crate::BsdfSample`] for `N` lanes: the lanes where `valid` is clear drew nothing (the
/// scalar `sample` returned `None`), and their other fields are unspecified.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSamples<const N: usize, X: Isa = Portable> {
    /// Lanes holding a sample.
    pub valid: Mask<N, X>,
    /// Sampled direction, local frame.
    pub wo: Vec3s<N, X>,
    /// f·|cos θo|/pdf (smooth lobes) or the lobe's throughput over its probability (delta).
    pub weight: SampledSpectra<N, X>,
    /// Solid-angle density, or the discrete probability of a delta lobe.
    pub pdf: F32s<N, X>,
    /// Relative index crossed, n(wo side)/n(wi side); 1 for reflections.
    pub eta: F32s<N, X>,
    /// The lobe sampled, per lane.
    pub flags: [BsdfFlags; N],
}
