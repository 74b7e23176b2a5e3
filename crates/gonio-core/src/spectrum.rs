//! Spectral samples carried along a path: [`SampledSpectrum`] and [`SampledWavelengths`].
//!
//! A path carries radiance at [`N_SPECTRUM_SAMPLES`] = 4 wavelengths at once (hero wavelength
//! sampling, Wilkie et al. 2014): the hero λ₀ is drawn from a pdf over the visible range
//! [`LAMBDA_MIN`, `LAMBDA_MAX`] = [360, 830] nm and the other three are the hero rotated by
//! ¼, ½ and ¾ in the sampling domain. Every spectral estimate is
//!
//! ```text
//!     (1/N) Σᵢ g(λᵢ) / p(λᵢ)        (safe division: a zero pdf contributes nothing)
//! ```
//!
//! **Dispersion.** After a wavelength-dependent refraction only the hero survives
//! ([`SampledWavelengths::terminate_secondary`]: p₁ = p₂ = p₃ = 0, p₀ /= N), and the estimator
//! above stays unbiased. Two rules make this impossible to forget:
//! 1. the pdfs are private; the only way to turn a spectral value into colour is through the
//!    estimator (`crate::color`), which divides by the pdfs and so drops terminated wavelengths;
//! 2. a refraction needs one scalar η, and the only way to get a scalar η out of a dispersive
//!    [`crate::ior::Ior`] is [`crate::ior::Ior::hero_eta`], which takes `&mut SampledWavelengths`
//!    and terminates the secondaries itself.
//!
//! pbrt-v4's SpectralFilm forgot rule 1 (PR #550); here no accumulator sees a wavelength
//! without its pdf.

use glam::Vec4;
use std::ops::{Add, AddAssign, Div, DivAssign, Index, IndexMut, Mul, MulAssign, Neg, Sub, SubAssign};

/// Wavelengths per path.
pub const N_SPECTRUM_SAMPLES: usize = 4;
/// Lower end of the visible range, nm.
pub const LAMBDA_MIN: f32 = 360.0;
/// Upper end of the visible range, nm.
pub const LAMBDA_MAX: f32 = 830.0;

/// A spectral quantity at the [`N_SPECTRUM_SAMPLES`] wavelengths of a path (radiance, throughput,
/// reflectance...). Element-wise arithmetic on an SSE `Vec4`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SampledSpectrum(pub Vec4);

impl SampledSpectrum {
    /// All zero.
    pub const ZERO: Self = Self(Vec4::ZERO);
    /// All one.
    pub const ONE: Self = Self(Vec4::ONE);

    /// The same value at every wavelength.
    #[inline]
    pub fn splat(v: f32) -> Self {
        Self(Vec4::splat(v))
    }
    /// From four values, one per wavelength.
    #[inline]
    pub fn new(v: [f32; N_SPECTRUM_SAMPLES]) -> Self {
        Self(Vec4::from_array(v))
    }
    /// Evaluates `f` at each index 0..4.
    #[inline]
    pub fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        Self::new([f(0), f(1), f(2), f(3)])
    }
    /// The four values.
    #[inline]
    pub fn to_array(self) -> [f32; N_SPECTRUM_SAMPLES] {
        self.0.to_array()
    }
    /// Applies `f` to each value.
    #[inline]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self(Vec4::new(f(self.0.x), f(self.0.y), f(self.0.z), f(self.0.w)))
    }
    /// Largest value.
    #[inline]
    pub fn max_component(self) -> f32 {
        self.0.max_element()
    }
    /// Smallest value.
    #[inline]
    pub fn min_component(self) -> f32 {
        self.0.min_element()
    }
    /// Mean of the four values.
    #[inline]
    pub fn average(self) -> f32 {
        self.0.element_sum() / N_SPECTRUM_SAMPLES as f32
    }
    /// True when every value is zero.
    #[inline]
    pub fn is_black(self) -> bool {
        self.0 == Vec4::ZERO
    }
    /// True when every value is finite (no NaN, no infinity).
    #[inline]
    pub fn is_finite(self) -> bool {
        self.0.is_finite()
    }
    /// Element-wise `self / d`, with 0 where `d` is 0.
    #[inline]
    pub fn safe_div(self, d: Self) -> Self {
        Self::from_fn(|i| if d[i] != 0.0 { self[i] / d[i] } else { 0.0 })
    }
    /// Element-wise square root (of max(0, x)).
    #[inline]
    pub fn sqrt(self) -> Self {
        Self(self.0.max(Vec4::ZERO).sqrt())
    }
    /// Element-wise exponential.
    #[inline]
    pub fn exp(self) -> Self {
        self.map(f32::exp)
    }
    /// Element-wise clamp to [lo, hi].
    #[inline]
    pub fn clamp(self, lo: f32, hi: f32) -> Self {
        Self(self.0.clamp(Vec4::splat(lo), Vec4::splat(hi)))
    }
    /// Element-wise max(x, 0).
    #[inline]
    pub fn clamp_zero(self) -> Self {
        Self(self.0.max(Vec4::ZERO))
    }
}

impl std::fmt::Display for SampledSpectrum {
    /// `[a, b, c, d]`, each with the formatter's precision (default 6 significant digits).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = f.precision().unwrap_or(6);
        let [a, b, c, d] = self.to_array();
        write!(f, "[{a:.p$}, {b:.p$}, {c:.p$}, {d:.p$}]")
    }
}

impl Index<usize> for SampledSpectrum {
    type Output = f32;
    #[inline]
    fn index(&self, i: usize) -> &f32 {
        &self.0.as_ref()[i]
    }
}
impl IndexMut<usize> for SampledSpectrum {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut f32 {
        &mut self.0.as_mut()[i]
    }
}

macro_rules! spectrum_binop {
    ($tr:ident, $f:ident, $tra:ident, $fa:ident, $op:tt) => {
        impl $tr for SampledSpectrum {
            type Output = Self;
            #[inline]
            fn $f(self, o: Self) -> Self { Self(self.0 $op o.0) }
        }
        impl $tr<f32> for SampledSpectrum {
            type Output = Self;
            #[inline]
            fn $f(self, o: f32) -> Self { Self(self.0 $op Vec4::splat(o)) }
        }
        impl $tra for SampledSpectrum {
            #[inline]
            fn $fa(&mut self, o: Self) { self.0 = self.0 $op o.0; }
        }
        impl $tra<f32> for SampledSpectrum {
            #[inline]
            fn $fa(&mut self, o: f32) { self.0 = self.0 $op Vec4::splat(o); }
        }
    };
}
spectrum_binop!(Add, add, AddAssign, add_assign, +);
spectrum_binop!(Sub, sub, SubAssign, sub_assign, -);
spectrum_binop!(Mul, mul, MulAssign, mul_assign, *);
spectrum_binop!(Div, div, DivAssign, div_assign, /);

impl Mul<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    #[inline]
    fn mul(self, s: SampledSpectrum) -> SampledSpectrum {
        s * self
    }
}
impl Sub<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    #[inline]
    fn sub(self, s: SampledSpectrum) -> SampledSpectrum {
        SampledSpectrum(Vec4::splat(self) - s.0)
    }
}
impl Neg for SampledSpectrum {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self(-self.0)
    }
}

/// Parameters of the visible-wavelength pdf p(λ) = A / cosh²(B (λ − 538 nm)) on [360, 830] nm
/// (Radziszewski et al., as in pbrt-v4 `SampleVisibleWavelengths`), fitted to x̄ + ȳ + z̄.
const VISIBLE_B: f64 = 0.0072;
const VISIBLE_CENTER: f64 = 538.0;

fn visible_tanh_range() -> (f64, f64) {
    let lo = (VISIBLE_B * (LAMBDA_MIN as f64 - VISIBLE_CENTER)).tanh();
    let hi = (VISIBLE_B * (LAMBDA_MAX as f64 - VISIBLE_CENTER)).tanh();
    (lo, hi)
}

/// Density of [`sample_visible_wavelength`], in 1/nm; 0 outside [360, 830].
pub fn visible_wavelength_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let (lo, hi) = visible_tanh_range();
    let a = VISIBLE_B / (hi - lo);
    let c = (VISIBLE_B * (lambda as f64 - VISIBLE_CENTER)).cosh();
    (a / (c * c)) as f32
}

/// Inverse-CDF sample of the visible pdf: λ(u) = 538 − atanh(tanh(B(360−538)) ·(1−u) … )/B.
pub fn sample_visible_wavelength(u: f32) -> f32 {
    let (lo, hi) = visible_tanh_range();
    let t = lo + (hi - lo) * u as f64;
    let l = VISIBLE_CENTER + t.atanh() / VISIBLE_B;
    (l as f32).clamp(LAMBDA_MIN, LAMBDA_MAX)
}

/// The wavelengths a path carries and the density each was drawn with.
///
/// Fields are private so that no code can use a wavelength without its pdf (see the module
/// docs on dispersion).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    lambda: [f32; N_SPECTRUM_SAMPLES],
    pdf: [f32; N_SPECTRUM_SAMPLES],
    /// The normalized D65 illuminant at `lambda`, made once with the wavelengths: every RGB
    /// emitter's spectrum multiplies by it at each lookup.
    d65: [f32; N_SPECTRUM_SAMPLES],
}

impl SampledWavelengths {
    /// The wavelengths `lambda` with densities `pdf` (the one place that builds the struct).
    #[inline]
    fn make(lambda: [f32; N_SPECTRUM_SAMPLES], pdf: [f32; N_SPECTRUM_SAMPLES]) -> Self {
        Self {
            lambda,
            pdf,
            d65: crate::color::d65_normalized4(lambda),
        }
    }

    /// Hero wavelength from the visible pdf, the others rotated by i/4 in sample space
    /// (Mitsuba's `sample_shifted`, pbrt's `SampleVisible`).
    pub fn sample_visible(u: f32) -> Self {
        Self::sample_shifted(u, |up| {
            let lambda = sample_visible_wavelength(up);
            (lambda, visible_wavelength_pdf(lambda))
        })
    }

    /// The hero wavelength `one(u)` and the others `one(u + i/4)` (wrapped into [0, 1)), each
    /// `one` returning a wavelength and its density (Mitsuba's `sample_shifted`).
    #[inline]
    pub fn sample_shifted(u: f32, one: impl Fn(f32) -> (f32, f32)) -> Self {
        let mut lambda = [0.0; N_SPECTRUM_SAMPLES];
        let mut pdf = [0.0; N_SPECTRUM_SAMPLES];
        for i in 0..N_SPECTRUM_SAMPLES {
            let mut up = u + i as f32 / N_SPECTRUM_SAMPLES as f32;
            if up >= 1.0 {
                up -= 1.0;
            }
            (lambda[i], pdf[i]) = one(up);
        }
        Self::make(lambda, pdf)
    }

    /// Hero wavelength uniform in [lo, hi], the others spaced (hi − lo)/4 apart, wrapped.
    pub fn sample_uniform(u: f32, lo: f32, hi: f32) -> Self {
        let mut lambda = [0.0; N_SPECTRUM_SAMPLES];
        lambda[0] = lo + (hi - lo) * u;
        let delta = (hi - lo) / N_SPECTRUM_SAMPLES as f32;
        for i in 1..N_SPECTRUM_SAMPLES {
            let mut l = lambda[i - 1] + delta;
            if l > hi {
                l = lo + (l - hi);
            }
            lambda[i] = l;
        }
        Self::make(lambda, [1.0 / (hi - lo); N_SPECTRUM_SAMPLES])
    }

    /// One fixed wavelength, for point queries (`gonio bsdf eval ... lambda_nm`): all four
    /// entries are `lambda` with pdf 1, so each slot of a result holds the value at `lambda`.
    pub fn fixed(lambda: f32) -> Self {
        Self::make([lambda; N_SPECTRUM_SAMPLES], [1.0; N_SPECTRUM_SAMPLES])
    }

    /// Four given wavelengths with given pdfs (tests, instruments).
    pub fn from_parts(lambda: [f32; N_SPECTRUM_SAMPLES], pdf: [f32; N_SPECTRUM_SAMPLES]) -> Self {
        Self::make(lambda, pdf)
    }

    /// Wavelength `i`, nm.
    #[inline]
    pub fn lambda(&self, i: usize) -> f32 {
        self.lambda[i]
    }
    /// All four wavelengths, nm.
    #[inline]
    pub fn lambdas(&self) -> [f32; N_SPECTRUM_SAMPLES] {
        self.lambda
    }
    /// The normalized D65 illuminant at the four wavelengths ([`crate::color::d65_normalized`],
    /// bit for bit), computed once when the wavelengths were drawn.
    #[inline]
    pub fn d65(&self) -> [f32; N_SPECTRUM_SAMPLES] {
        self.d65
    }
    /// The hero wavelength λ₀, nm.
    #[inline]
    pub fn hero(&self) -> f32 {
        self.lambda[0]
    }
    /// The pdfs, 1/nm (zero for terminated secondaries).
    #[inline]
    pub fn pdf(&self) -> SampledSpectrum {
        SampledSpectrum::new(self.pdf)
    }

    /// Keeps only the hero wavelength: p₁..p₃ = 0 and p₀ /= N (idempotent). Called by every
    /// wavelength-dependent change of direction (dispersion).
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        for p in &mut self.pdf[1..] {
            *p = 0.0;
        }
        self.pdf[0] /= N_SPECTRUM_SAMPLES as f32;
    }

    /// True once [`Self::terminate_secondary`] has been called.
    #[inline]
    pub fn secondary_terminated(&self) -> bool {
        self.pdf[1..].iter().all(|&p| p == 0.0)
    }

    /// The Monte Carlo estimate (1/N) Σ g(λᵢ)/p(λᵢ) of ∫ g(λ) dλ from one spectral sample
    /// (safe division: terminated wavelengths contribute nothing).
    pub fn estimate(&self, g: SampledSpectrum) -> f32 {
        g.safe_div(self.pdf()).average()
    }
}

/// Weight of the visible sech² pdf in [`render_wavelength_pdf`]; the rest goes to the mean of
/// the normalized colour matching functions.
pub const RENDER_VISIBLE_WEIGHT: f64 = 0.65;

/// The CIE 1931 matching functions' mean, each normalized to unit integral, at the 1 nm knots:
/// (x̄/∫x̄ + ȳ/∫ȳ + z̄/∫z̄)/3. The integrals are the trapezoid sums, exact for the linear
/// interpolation between knots that [`crate::color::cie_xyz`] does, so the mean integrates to 1
/// under the same rule.
fn cmf_mean_knots() -> Vec<f64> {
    use crate::data::cie1931::{CIE_SAMPLES, CIE_X, CIE_Y, CIE_Z};
    let trapezoid = |t: &[f32]| -> f64 {
        (0..CIE_SAMPLES - 1)
            .map(|i| 0.5 * (t[i] as f64 + t[i + 1] as f64))
            .sum()
    };
    let (ix, iy, iz) = (trapezoid(&CIE_X), trapezoid(&CIE_Y), trapezoid(&CIE_Z));
    (0..CIE_SAMPLES)
        .map(|i| (CIE_X[i] as f64 / ix + CIE_Y[i] as f64 / iy + CIE_Z[i] as f64 / iz) / 3.0)
        .collect()
}

/// Density of the hero wavelengths the renderer draws, in 1/nm on [360, 830]:
///
/// ```text
///     p(λ) = 0.65 · p_sech²(λ) + 0.35 · (x̄/∫x̄ + ȳ/∫ȳ + z̄/∫z̄)(λ) / 3
/// ```
///
/// The visible pdf alone ([`visible_wavelength_pdf`], fitted to x̄ + ȳ + z̄) puts few samples
/// below 450 nm, where z̄ (blue) has most of its weight and ȳ little, so the blue channel is the
/// noisiest under warm light; the matching functions' mean, each normalized, gives the three
/// channels equal shares. Measured on the bench scenes: 0.74–1.00× the relMSE of the sech² pdf
/// (`bench/RESULTS.md`), and under a 2700 K blackbody the worst channel's variance falls by
/// more than a quarter (test `render_wavelengths_balance_the_channels_under_warm_light`).
/// The sech² part keeps the density well away from zero at the ends of the range.
pub fn render_wavelength_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    static CMF: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    let g = CMF.get_or_init(cmf_mean_knots);
    let x = (lambda - LAMBDA_MIN) as f64;
    let i = (x as usize).min(g.len() - 2);
    let t = x - i as f64;
    let cmf = g[i] + t * (g[i + 1] - g[i]);
    (RENDER_VISIBLE_WEIGHT * visible_wavelength_pdf(lambda) as f64 + (1.0 - RENDER_VISIBLE_WEIGHT) * cmf)
        as f32
}

/// Hero-wavelength sampling for rendering through a table: the inverse CDF of
/// [`render_wavelength_pdf`] (the visible sech² pdf of Radziszewski et al., as in pbrt and
/// Mitsuba, blended with the colour matching functions' mean), tabulated at 4096 points and
/// interpolated linearly. The table's points are the CDF inverted exactly (bisection in `f64` of
/// the closed-form sech² CDF plus the piecewise-quadratic integral of the linearly interpolated
/// matching functions). Linear interpolation of the inverse CDF samples the piecewise-constant
/// density p = (1/N)/(λᵢ₊₁ − λᵢ) on each interval, which is returned with each wavelength, so the
/// estimator stays exactly unbiased; that density is within 1.5 % of [`render_wavelength_pdf`]
/// everywhere. Lookups replace four `f64` atanh and cosh per camera sample (a fifth of a render's
/// time, with the analytic sech² sampler). The four wavelengths are the hero and its rotations
/// by ¼, ½ and ¾ in sample space, as in [`SampledWavelengths::sample_visible`]. The table is
/// computed once per process ([`VisibleWavelengthTable::get`]).
#[derive(Clone, Debug)]
pub struct VisibleWavelengthTable {
    /// Interval `i` as `[λᵢ, λᵢ₊₁ − λᵢ, pᵢ, 0]`, where pᵢ = 1/(N (λᵢ₊₁ − λᵢ)) is the density on
    /// it (the division done once, here): one 16-byte load per lookup.
    intervals: Vec<[f32; 4]>,
}

impl VisibleWavelengthTable {
    const N: usize = 4096;

    fn new() -> Self {
        let g = cmf_mean_knots();
        // Cumulative integral of the matching functions' mean at each knot.
        let mut prefix = vec![0.0f64; g.len()];
        for i in 1..g.len() {
            prefix[i] = prefix[i - 1] + 0.5 * (g[i - 1] + g[i]);
        }
        let (lo, hi) = visible_tanh_range();
        let cdf = |l: f64| -> f64 {
            let sech = ((VISIBLE_B * (l - VISIBLE_CENTER)).tanh() - lo) / (hi - lo);
            let x = (l - LAMBDA_MIN as f64).clamp(0.0, (g.len() - 1) as f64);
            let i = (x as usize).min(g.len() - 2);
            let t = x - i as f64;
            let cmf = prefix[i] + g[i] * t + 0.5 * (g[i + 1] - g[i]) * t * t;
            RENDER_VISIBLE_WEIGHT * sech + (1.0 - RENDER_VISIBLE_WEIGHT) * cmf
        };
        let lambda: Vec<f32> = (0..=Self::N)
            .map(|k| {
                let u = k as f64 / Self::N as f64;
                let (mut a, mut b) = (LAMBDA_MIN as f64, LAMBDA_MAX as f64);
                for _ in 0..60 {
                    let m = 0.5 * (a + b);
                    if cdf(m) < u {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                match k {
                    0 => LAMBDA_MIN,
                    _ if k == Self::N => LAMBDA_MAX,
                    _ => (0.5 * (a + b)) as f32,
                }
            })
            .collect();
        let intervals = lambda
            .windows(2)
            .map(|w: &[f32]| {
                let width = w[1] - w[0];
                [w[0], width, 1.0 / (Self::N as f32 * width), 0.0]
            })
            .collect();
        Self { intervals }
    }

    /// The table (built on first use).
    pub fn get() -> &'static Self {
        static TABLE: std::sync::OnceLock<VisibleWavelengthTable> = std::sync::OnceLock::new();
        TABLE.get_or_init(Self::new)
    }

    /// One wavelength for `u` ∈ [0, 1) and the table's density there: (λ, p(λ)).
    #[inline]
    pub fn one(&self, u: f32) -> (f32, f32) {
        let x = (u * Self::N as f32).clamp(0.0, Self::N as f32 - 1e-3);
        let i = (x as usize).min(Self::N - 1);
        let [a, width, pdf, _] = self.intervals[i];
        let t = x - i as f32;
        (a + t * width, pdf)
    }

    /// The hero wavelength for `u` and its three rotations, with their densities: [`Self::one`]
    /// at u + k/4 (wrapped), the four lanes at once (the same arithmetic, bit for bit).
    #[inline]
    pub fn sample(&self, u: f32) -> SampledWavelengths {
        let uk = Vec4::splat(u) + Vec4::new(0.0, 0.25, 0.5, 0.75);
        let uk = Vec4::select(uk.cmpge(Vec4::ONE), uk - Vec4::ONE, uk);
        let n = Self::N as f32;
        let x = (uk * n).clamp(Vec4::ZERO, Vec4::splat(n - 1e-3));
        // x ∈ [0, N − 10⁻³]: its truncation is a valid interval index.
        let i = x.to_array().map(|x| (x as usize).min(Self::N - 1));
        let t = x - Vec4::from_array(i.map(|i| i as f32));
        let [e0, e1, e2, e3] = i.map(|i| Vec4::from_array(self.intervals[i]));
        // Transpose: the rows are λᵢ, widths and densities over the four lanes.
        let (a, width, pdf) = (
            Vec4::new(e0.x, e1.x, e2.x, e3.x),
            Vec4::new(e0.y, e1.y, e2.y, e3.y),
            Vec4::new(e0.z, e1.z, e2.z, e3.z),
        );
        SampledWavelengths::from_parts((a + t * width).to_array(), pdf.to_array())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wavelength_table_density_is_exact_and_close_to_the_render_pdf() {
        let t = VisibleWavelengthTable::get();
        let n = 100_000;
        // The returned density integrates to one over [360, 830] (Σ p·Δλ per interval = 1/N).
        let mut worst = 0.0f32;
        let mut y_est = 0.0f64;
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            let (l, p) = t.one(u);
            assert!((360.0..=830.0).contains(&l));
            worst = worst.max((p / render_wavelength_pdf(l) - 1.0).abs());
            y_est += (crate::color::cie_y(l) / p) as f64;
        }
        assert!(
            worst < 1.5e-2,
            "table density departs from the render pdf by {worst}"
        );
        // Unbiased: the estimate of ∫ȳ dλ with the table's density matches CIE_Y_INTEGRAL.
        let y = y_est / n as f64;
        assert!(
            (y / crate::color::CIE_Y_INTEGRAL as f64 - 1.0).abs() < 2e-4,
            "∫ȳ = {y}"
        );
        // The four wavelengths are the hero and its rotations by ¼ in sample space, wrapped,
        // with their densities: `one`'s, bit for bit.
        for u in [0.0, 0.1, 0.3, 0.5, 0.74, 0.99, 1.0 - f32::EPSILON] {
            let wl = t.sample(u);
            for k in 0..4 {
                let mut uk = u + 0.25 * k as f32;
                if uk >= 1.0 {
                    uk -= 1.0;
                }
                assert_eq!((wl.lambda(k), wl.pdf()[k]), t.one(uk), "u = {u}, k = {k}");
            }
        }
    }

    /// Relative variance of the one-wavelength estimate ∫ c̄·S dλ ≈ c̄(λ)S(λ)/p(λ) of each linear
    /// sRGB channel c̄ (rows of XYZ → sRGB applied to x̄, ȳ, z̄): ∫ (c̄S)²/p dλ / (∫ c̄S dλ)² − 1,
    /// by 0.01 nm midpoint quadrature; the worst of the three.
    fn worst_channel_relative_variance(s: impl Fn(f32) -> f64, pdf: impl Fn(f32) -> f32) -> f64 {
        let m = crate::color::LINEAR_SRGB_FROM_XYZ;
        let (mut first, mut second) = ([0.0f64; 3], [0.0f64; 3]);
        let h = 0.01f64;
        let n = ((LAMBDA_MAX - LAMBDA_MIN) as f64 / h) as usize;
        for i in 0..n {
            let l = LAMBDA_MIN + ((i as f64 + 0.5) * h) as f32;
            let c = m * crate::color::cie_xyz(l);
            let (sv, p) = (s(l), pdf(l) as f64);
            for (k, ck) in c.to_array().into_iter().enumerate() {
                let g = ck as f64 * sv;
                first[k] += g * h;
                second[k] += g * g / p * h;
            }
        }
        (0..3)
            .map(|k| second[k] / (first[k] * first[k]) - 1.0)
            .fold(0.0, f64::max)
    }

    #[test]
    fn render_wavelengths_balance_the_channels_under_warm_light() {
        // Under a 2700 K blackbody (an incandescent bulb), the sech² pdf leaves the blue channel
        // with few samples; the blend lowers the worst channel's variance by more than a quarter.
        let warm = |l: f32| crate::spectra::planck(l as f64, 2700.0);
        let sech = worst_channel_relative_variance(warm, visible_wavelength_pdf);
        let blend = worst_channel_relative_variance(warm, render_wavelength_pdf);
        assert!(
            blend < 0.75 * sech,
            "2700 K: worst channel relvar {blend} vs sech² {sech}"
        );
        // Under D65 (the white of sRGB, what an RGB scene's lights are) it costs at most 10 %.
        let d65 = |l: f32| crate::color::d65(l) as f64;
        let sech = worst_channel_relative_variance(d65, visible_wavelength_pdf);
        let blend = worst_channel_relative_variance(d65, render_wavelength_pdf);
        assert!(
            blend < 1.1 * sech,
            "D65: worst channel relvar {blend} vs sech² {sech}"
        );
    }

    #[test]
    fn visible_and_render_pdfs_integrate_to_one() {
        let n = 47_000;
        let h = (LAMBDA_MAX - LAMBDA_MIN) as f64 / n as f64;
        let integral = |pdf: fn(f32) -> f32| -> f64 {
            (0..n)
                .map(|i| pdf(LAMBDA_MIN + ((i as f64 + 0.5) * h) as f32) as f64 * h)
                .sum()
        };
        for (name, pdf) in [
            ("visible", visible_wavelength_pdf as fn(f32) -> f32),
            ("render", render_wavelength_pdf),
        ] {
            let s = integral(pdf);
            assert!((s - 1.0).abs() < 1e-5, "{name} pdf: integral {s}");
        }
    }

    #[test]
    fn visible_sampling_matches_reference_values() {
        // Inverse CDF of pbrt-v4's SampleVisibleWavelengths (util/sampling.h), computed: λ(0) = 360,
        // λ(0.5) = 545.90, λ(1) = 830.
        assert!((sample_visible_wavelength(0.0) - 360.0).abs() < 1e-3);
        assert!((sample_visible_wavelength(0.5) - 545.90).abs() < 0.01);
        assert!((sample_visible_wavelength(1.0) - 830.0).abs() < 1e-3);
        assert!((visible_wavelength_pdf(538.0) - 0.0039398042).abs() < 1e-8);
    }

    #[test]
    fn hero_rotation_is_stratified_in_sample_space() {
        let wl = SampledWavelengths::sample_visible(0.1);
        for i in 0..4 {
            let expect = sample_visible_wavelength(0.1 + 0.25 * i as f32);
            assert!((wl.lambda(i) - expect).abs() < 1e-3);
        }
    }

    #[test]
    fn terminate_secondary_keeps_estimator_unbiased() {
        // ∫ g over [360, 830] for g(λ) = λ/100 with uniform wavelengths, estimated with and
        // without termination: both must converge to the same value.
        let g = |wl: &SampledWavelengths| SampledSpectrum::from_fn(|i| wl.lambda(i) / 100.0);
        let exact = (830.0f64.powi(2) - 360.0f64.powi(2)) / 200.0;
        let n = 20_000;
        let (mut full, mut term) = (0.0f64, 0.0f64);
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            let wl = SampledWavelengths::sample_uniform(u, LAMBDA_MIN, LAMBDA_MAX);
            full += wl.estimate(g(&wl)) as f64;
            let mut wt = wl;
            wt.terminate_secondary();
            wt.terminate_secondary(); // idempotent
            assert!(wt.secondary_terminated());
            term += wt.estimate(g(&wt)) as f64;
        }
        assert!((full / n as f64 - exact).abs() / exact < 1e-4);
        assert!((term / n as f64 - exact).abs() / exact < 1e-4);
    }
}
