//! What a sensor records of the radiance it receives: linear sRGB through the CIE 1931 observer,
//! or the responses to spectral bands (Mitsuba 3's `specfilm`, `src/films/specfilm.cpp`).
//!
//! A band j is a sensor response function (SRF) Sⱼ(λ), not necessarily normalized nor limited to
//! the visible range; its channel records
//!
//! ```text
//! cⱼ = ∫ Sⱼ(λ) L(λ) dλ,
//! ```
//!
//! estimated from the four wavelengths of a camera sample as cⱼ ≈ (1/4) Σᵢ Sⱼ(λᵢ) L(λᵢ)/p(λᵢ).
//! The wavelengths are drawn, as Mitsuba draws them, from one density for all bands,
//! p(λ) ∝ g(λ) with g the sum of the SRFs (so a single band's channel has no spectral noise
//! under a flat spectrum), the hero at u and the others rotated by i/4 in sample space
//! (`sample_shifted`). g is piecewise linear between the union of the bands' knots: exactly the
//! sum where every band is a table (`<spectrum value="λ:v, ...">`, an `.spd` file), which are 0
//! outside their knots as Mitsuba's `irregular` spectra are; a band that is no table contributes
//! its values at every nanometre of its range: a blackbody's own (Mitsuba's `wavelength_min`,
//! `wavelength_max`), else 360–830 nm (a number, an RGB colour), the range Mitsuba gives such
//! spectra. Wherever g > 0 the estimator is unbiased; where a band is
//! non-zero and g is 0 (between two knots of value 0) its radiance is missed, as in Mitsuba.
//!
//! | `SensorResponse` | channels | wavelengths |
//! |---|---|---|
//! | `Srgb` | `R`, `G`, `B` (linear sRGB, [`crate::color::linear_srgb_from_sampled`]) | the renderer's visible density |
//! | `Bands` | one per band, in the given order | [`SpectralBands::sample`] |
//! | `Filtered` (a sensor's `srf`) | `R`, `G`, `B` of S(λ)·L(λ) | [`SpectralBands::sample`] of S alone |

use crate::sampling::Distribution1D;
use crate::spectra::{Extrapolation, Spectrum};
use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use std::sync::Arc;

/// The most bands one film records (the splat path keeps a band's values on the stack).
pub const MAX_BANDS: usize = 64;

/// What the film's channels are.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum SensorResponse {
    /// Linear sRGB (`R`, `G`, `B`).
    #[default]
    Srgb,
    /// One channel per spectral band (`specfilm`).
    Bands(Arc<SpectralBands>),
    /// Linear sRGB of the radiance filtered by one response function S (a sensor's `srf`):
    /// the colour of S(λ)·L(λ), the wavelengths drawn ∝ S, as Mitsuba's sensors do.
    Filtered(Arc<SpectralBands>),
}

impl SensorResponse {
    /// Number of channels a sample's value has: 3, or the number of bands.
    pub fn len(&self) -> usize {
        match self {
            SensorResponse::Srgb | SensorResponse::Filtered(_) => 3,
            SensorResponse::Bands(b) => b.len(),
        }
    }

    /// The bands the wavelengths are drawn from, if not the renderer's visible density.
    pub fn wavelength_bands(&self) -> Option<&SpectralBands> {
        match self {
            SensorResponse::Srgb => None,
            SensorResponse::Bands(b) | SensorResponse::Filtered(b) => Some(b),
        }
    }

    /// Always false: a response has at least one channel.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Writes the estimate of each channel from radiance `l` at the wavelengths `wl` into
    /// `out[..self.len()]`.
    #[inline]
    pub fn record(&self, l: SampledSpectrum, wl: &SampledWavelengths, out: &mut [f32]) {
        match self {
            SensorResponse::Srgb => {
                out[..3].copy_from_slice(&crate::color::linear_srgb_from_sampled(l, wl).to_array())
            }
            SensorResponse::Bands(b) => b.record(l, wl, out),
            SensorResponse::Filtered(b) => {
                let filtered = l * b.srfs()[0].sample(wl);
                out[..3].copy_from_slice(&crate::color::linear_srgb_from_sampled(filtered, wl).to_array())
            }
        }
    }
}

/// Spectral bands and the wavelength density made for them.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralBands {
    /// The channels' names.
    names: Vec<String>,
    /// The sensor response functions, one per channel.
    srfs: Vec<Spectrum>,
    /// Knots λₖ of the sampling density (increasing).
    knots: Vec<f32>,
    /// g(λₖ), the sum of the SRFs at the knots.
    g: Vec<f32>,
    /// Interval k's area ∫ g over [λₖ, λₖ₊₁] (trapezoid), for choosing an interval.
    intervals: Distribution1D,
    /// ∫ g dλ over all knots.
    integral: f32,
}

/// Why bands cannot be recorded.
#[derive(Clone, Debug, PartialEq)]
pub enum BandsError {
    /// No band at all.
    NoBands,
    /// More than [`MAX_BANDS`].
    TooMany(usize),
    /// The SRFs' integral is zero or not finite (zero everywhere, negative, or too large).
    Empty,
    /// A band's table reaches a wavelength that is not positive (nm).
    Wavelength(f32),
}

impl std::fmt::Display for BandsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BandsError::NoBands => write!(f, "at least one spectral band (a nested <spectrum>) is needed"),
            BandsError::TooMany(n) => write!(f, "{n} spectral bands; at most {MAX_BANDS} are supported"),
            BandsError::Empty => write!(
                f,
                "the spectral bands' integral is zero or not finite (the bands zero everywhere, negative, or too large): no wavelength to sample"
            ),
            BandsError::Wavelength(l) => write!(
                f,
                "a band reaches the wavelength {l} nm; wavelengths must be positive"
            ),
        }
    }
}

impl std::error::Error for BandsError {}

/// The most knots a band that is no table contributes.
const MAX_SPAN_KNOTS: usize = 100_000;

/// The knots a band contributes to the sampling density: a table's own, 0 outside them; a
/// blackbody with a finite range (Mitsuba's) is tabulated every nanometre over that range (at
/// most [`MAX_SPAN_KNOTS`] knots, from 1 nm); any other spectrum every nanometre over the visible
/// range.
fn band_knots(s: &Spectrum) -> Vec<f32> {
    let span = |lo: f32, hi: f32| -> Vec<f32> {
        let n = ((hi - lo).ceil() as usize).clamp(1, MAX_SPAN_KNOTS);
        (0..=n).map(|i| lo + (hi - lo) * i as f32 / n as f32).collect()
    };
    match s {
        Spectrum::PiecewiseLinear(p) if p.extrapolation() == Extrapolation::Zero => p.lambdas().to_vec(),
        Spectrum::Blackbody(b) if b.range()[1].is_finite() => {
            span(b.range()[0].max(1.0), b.range()[1].max(1.0))
        }
        _ => span(LAMBDA_MIN, LAMBDA_MAX),
    }
}

impl SpectralBands {
    /// Bands with these names and SRFs (values outside a table's knots are 0, as for Mitsuba's
    /// tables).
    pub fn new(bands: Vec<(String, Spectrum)>) -> Result<Self, BandsError> {
        let (names, srfs): (Vec<String>, Vec<Spectrum>) = bands.into_iter().unzip();
        if srfs.is_empty() {
            return Err(BandsError::NoBands);
        }
        if srfs.len() > MAX_BANDS {
            return Err(BandsError::TooMany(srfs.len()));
        }
        let mut knots: Vec<f32> = srfs
            .iter()
            .flat_map(band_knots)
            .filter(|l| l.is_finite())
            .collect();
        if let Some(&l) = knots.iter().find(|&&l| l <= 0.0) {
            return Err(BandsError::Wavelength(l));
        }
        knots.sort_by(f32::total_cmp);
        knots.dedup();
        // A table's value at its own end knots may differ from its 0 just outside them; the
        // density's interpolant between two knots is the exact sum wherever every table is
        // linear there, which holds between consecutive knots of the union.
        let g: Vec<f32> = knots
            .iter()
            .map(|&l| srfs.iter().map(|s| s.eval(l)).sum::<f32>())
            .collect();
        if knots.len() < 2 || g.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err(BandsError::Empty);
        }
        let areas: Vec<f32> = (0..knots.len() - 1)
            .map(|k| 0.5 * (g[k] + g[k + 1]) * (knots[k + 1] - knots[k]))
            .collect();
        let integral: f32 = areas.iter().map(|&a| a as f64).sum::<f64>() as f32;
        if !(integral > 0.0 && integral.is_finite()) {
            return Err(BandsError::Empty);
        }
        Ok(Self {
            names,
            srfs,
            intervals: Distribution1D::new(&areas),
            knots,
            g,
            integral,
        })
    }

    /// Number of bands.
    pub fn len(&self) -> usize {
        self.srfs.len()
    }

    /// Always false ([`SpectralBands::new`] refuses no bands).
    pub fn is_empty(&self) -> bool {
        self.srfs.is_empty()
    }

    /// The channels' names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The SRFs, in channel order.
    pub fn srfs(&self) -> &[Spectrum] {
        &self.srfs
    }

    /// The wavelength range the density covers, nm.
    pub fn range(&self) -> (f32, f32) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }

    /// ∫ g dλ, the integral of the sum of the SRFs (as the density interpolates it).
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// The density p(λ) = g(λ)/∫g the wavelengths are drawn from (0 outside the knots).
    pub fn pdf(&self, lambda: f32) -> f32 {
        let (lo, hi) = self.range();
        if !(lambda >= lo && lambda <= hi) {
            return 0.0;
        }
        let k = self
            .knots
            .partition_point(|&l| l <= lambda)
            .clamp(1, self.knots.len() - 1)
            - 1;
        let width = self.knots[k + 1] - self.knots[k];
        let t = if width > 0.0 {
            (lambda - self.knots[k]) / width
        } else {
            0.0
        };
        (self.g[k] + t * (self.g[k + 1] - self.g[k])) / self.integral
    }

    /// One wavelength for `u` ∈ [0, 1) and its density: the interval by its area, then the
    /// linear density on it inverted exactly.
    pub fn sample_one(&self, u: f32) -> (f32, f32) {
        let (k, _, u) = self.intervals.sample_discrete(u);
        let (a, b) = (self.g[k], self.g[k + 1]);
        let width = self.knots[k + 1] - self.knots[k];
        // CDF on the interval ∝ a t + (b − a) t²/2 over t ∈ [0, 1].
        let u = u.clamp(0.0, 1.0);
        let t = if (a - b).abs() <= 1e-6 * (a + b) {
            u
        } else {
            (a - ((1.0 - u) * a * a + u * b * b).max(0.0).sqrt()) / (a - b)
        };
        let t = t.clamp(0.0, 1.0);
        let lambda = self.knots[k] + t * width;
        let density = (a + t * (b - a)) / self.integral;
        (lambda, density)
    }

    /// The hero wavelength for `u` and its three rotations by ¼ in sample space, with their
    /// densities.
    pub fn sample(&self, u: f32) -> SampledWavelengths {
        SampledWavelengths::sample_shifted(u, |ui| self.sample_one(ui))
    }

    /// cⱼ ≈ (1/4) Σᵢ Sⱼ(λᵢ) L(λᵢ)/p(λᵢ) for each band, into `out[..self.len()]` (a wavelength of
    /// zero density, terminated or outside the bands, contributes 0).
    pub fn record(&self, l: SampledSpectrum, wl: &SampledWavelengths, out: &mut [f32]) {
        let pdf = wl.pdf();
        let mut weighted = [0.0f32; N_SPECTRUM_SAMPLES];
        for i in 0..N_SPECTRUM_SAMPLES {
            if pdf[i] > 0.0 {
                weighted[i] = l[i] / (pdf[i] * N_SPECTRUM_SAMPLES as f32);
            }
        }
        for (o, s) in out.iter_mut().zip(&self.srfs) {
            let w = s.sample(wl);
            *o = (0..N_SPECTRUM_SAMPLES).map(|i| w[i] * weighted[i]).sum();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectra::PiecewiseLinear;

    fn named(srfs: Vec<Spectrum>) -> Vec<(String, Spectrum)> {
        srfs.into_iter()
            .enumerate()
            .map(|(i, s)| (format!("band{i}"), s))
            .collect()
    }

    fn table(pairs: &[(f32, f32)]) -> Spectrum {
        Spectrum::piecewise(
            PiecewiseLinear::new(
                pairs.iter().map(|p| p.0).collect(),
                pairs.iter().map(|p| p.1).collect(),
                Extrapolation::Zero,
            )
            .unwrap(),
        )
    }

    /// ∫ S(λ) L(λ) dλ by a fine midpoint sum over [lo, hi].
    fn integral(f: impl Fn(f32) -> f32, lo: f32, hi: f32) -> f64 {
        let n = 200_000;
        let h = (hi - lo) as f64 / n as f64;
        (0..n)
            .map(|i| f(lo + ((i as f64 + 0.5) * h) as f32) as f64 * h)
            .sum()
    }

    #[test]
    fn the_density_integrates_to_one_and_sampling_follows_it() {
        let bands = SpectralBands::new(named(vec![
            table(&[(400.0, 0.0), (450.0, 2.0), (500.0, 0.0)]),
            table(&[(480.0, 1.0), (700.0, 1.0)]),
            // Outside the visible range: Mitsuba's bands need not stay in it.
            table(&[(900.0, 0.5), (950.0, 3.0)]),
        ]))
        .unwrap();
        let (lo, hi) = bands.range();
        assert_eq!((lo, hi), (400.0, 950.0));
        let total = integral(|l| bands.pdf(l), lo, hi);
        assert!((total - 1.0).abs() < 1e-4, "{total}");
        // Histogram of stratified samples in 55 bins of 10 nm against the density's integral.
        let n = 1 << 20;
        let mut hist = [0u32; 55];
        for k in 0..n {
            let (l, p) = bands.sample_one((k as f32 + 0.5) / n as f32);
            assert!(
                (p - bands.pdf(l)).abs() <= 1e-5 * (1.0 + bands.pdf(l)),
                "{l}: {p} vs {}",
                bands.pdf(l)
            );
            hist[(((l - lo) / 10.0) as usize).min(54)] += 1;
        }
        for (b, &count) in hist.iter().enumerate() {
            let a = lo + 10.0 * b as f32;
            let expected = integral(|l| bands.pdf(l), a, a + 10.0);
            let got = count as f64 / n as f64;
            assert!(
                (got - expected).abs() < 1e-4 + 1e-3 * expected,
                "bin {b}: {got} vs {expected}"
            );
        }
    }

    #[test]
    fn each_channel_estimates_the_integral_of_its_band_times_the_radiance() {
        let bands = SpectralBands::new(named(vec![
            table(&[(400.0, 0.0), (450.0, 2.0), (500.0, 0.0)]),
            table(&[(480.0, 1.0), (700.0, 1.0)]),
            Spectrum::Constant(0.25),
        ]))
        .unwrap();
        let radiance = |l: f32| 1.0 + (l - 360.0) / 470.0;
        let n = 1 << 16;
        let mut sum = [0.0f64; 3];
        let mut out = [0.0f32; 3];
        for k in 0..n {
            let wl = bands.sample((k as f32 + 0.5) / n as f32);
            let l = SampledSpectrum::new(wl.lambdas().map(radiance));
            bands.record(l, &wl, &mut out);
            for j in 0..3 {
                sum[j] += out[j] as f64 / n as f64;
            }
        }
        for (j, s) in bands.srfs().iter().enumerate() {
            let exact = integral(|l| s.eval(l) * radiance(l), 360.0, 830.0);
            assert!(
                (sum[j] - exact).abs() < 1e-3 * exact,
                "band {j}: {} vs {exact}",
                sum[j]
            );
        }
    }

    /// A blackbody band over 300–1000 nm (Mitsuba's `blackbody` with its range): its wavelengths
    /// reach the whole range, and its channel estimates ∫ B(λ) dλ there.
    #[test]
    fn a_blackbody_band_is_sampled_over_its_own_range() {
        let b = crate::spectra::Blackbody::radiance(3000.0, [300.0, 1000.0]).unwrap();
        let s = Spectrum::Blackbody(b);
        let bands = SpectralBands::new(named(vec![s.clone()])).unwrap();
        assert_eq!(bands.range(), (300.0, 1000.0));
        let n = 1 << 14;
        let mut sum = 0.0f64;
        let mut out = [0.0f32];
        for k in 0..n {
            let wl = bands.sample((k as f32 + 0.5) / n as f32);
            bands.record(SampledSpectrum::splat(1.0), &wl, &mut out);
            sum += out[0] as f64 / n as f64;
        }
        let exact = integral(|l| s.eval(l), 300.0, 1000.0);
        assert!((sum - exact).abs() < 1e-3 * exact, "{sum} vs {exact}");
    }

    /// One band under a flat spectrum: every sample gives the band's integral (no spectral noise).
    #[test]
    fn a_single_band_under_a_flat_spectrum_is_exact_per_sample() {
        let bands =
            SpectralBands::new(named(vec![table(&[(500.0, 1.0), (550.0, 3.0), (600.0, 1.0)])])).unwrap();
        let mut out = [0.0f32];
        for k in 0..100 {
            let wl = bands.sample(k as f32 / 100.0);
            bands.record(SampledSpectrum::splat(2.0), &wl, &mut out);
            assert!((out[0] - 2.0 * 200.0).abs() < 1e-3 * 400.0, "{}", out[0]);
        }
    }

    #[test]
    fn bands_that_cannot_be_sampled_are_refused() {
        assert_eq!(
            SpectralBands::new(named(vec![])).unwrap_err(),
            BandsError::NoBands
        );
        assert_eq!(
            SpectralBands::new(named(vec![table(&[(400.0, 0.0), (500.0, 0.0)])])).unwrap_err(),
            BandsError::Empty
        );
        assert_eq!(
            SpectralBands::new(named(vec![Spectrum::Constant(f32::NAN)])).unwrap_err(),
            BandsError::Empty
        );
        assert_eq!(
            SpectralBands::new(named(vec![table(&[(-100.0, 1.0), (500.0, 1.0)])])).unwrap_err(),
            BandsError::Wavelength(-100.0)
        );
        // An integral beyond f32's range.
        assert_eq!(
            SpectralBands::new(named(vec![table(&[(400.0, 2.0), (3e38, 2.0)])])).unwrap_err(),
            BandsError::Empty
        );
        assert_eq!(
            SpectralBands::new(named(vec![Spectrum::Constant(1.0); MAX_BANDS + 1])).unwrap_err(),
            BandsError::TooMany(MAX_BANDS + 1)
        );
    }
}
