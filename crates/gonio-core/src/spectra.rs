//! Spectrum kinds: wavelength-dependent quantities as functions of λ (nm), independent of any
//! particular path. A [`Spectrum`] is evaluated at the four wavelengths of a path with
//! [`Spectrum::sample`].
//!
//! Kinds and their formulas:
//! * constant;
//! * piecewise linear (Mitsuba's `<spectrum value="400:0.1, 500:0.3"/>` and `.spd` files, pbrt's
//!   named tables; [`PiecewiseLinear`]): the interval's lerp; outside the table 0 (Mitsuba
//!   `irregular`) or the end values (measured η/k);
//! * RGB-uplifted (Jakob & Hanika 2019, [`crate::rgb2spec`]): s(λ) = S(c₀λ² + c₁λ + c₂) with
//!   S(x) = ½ + x/(2√(1 + x²)). *Albedo*: rgb clamped to [0, 1], value s(λ). *Unbounded* (pbrt
//!   `RGBUnboundedSpectrum`): m = max(r, g, b), scale = 2m, coefficients of rgb/scale, value
//!   scale·s(λ). *Illuminant* (pbrt `RGBIlluminantSpectrum`, Mitsuba's `d65` emitter texture):
//!   unbounded × D65 normalized to unit luminance, so `rgb_illuminant([1, 1, 1])` is the sRGB white
//!   and renders as linear sRGB (1, 1, 1);
//! * blackbody: Planck's law B(λ, T) = 2hc² / (λ⁵ (e^{hc/(λ k_B T)} − 1)) (c = 299792458 m/s,
//!   h = 6.62606957e-34 J s, k_B = 1.3806488e-23 J/K, as pbrt-v4), either divided by its value
//!   at Wien's peak λ_max = 2.8977721e-3 m·K / T, so the peak is 1 (pbrt `BlackbodySpectrum`,
//!   [`Spectrum::blackbody`]), or as a radiance in W·m⁻²·sr⁻¹·nm⁻¹ (B·10⁻⁹), 0 outside a
//!   wavelength range (Mitsuba's `blackbody`: 360–830 nm by default,
//!   [`Spectrum::blackbody_radiance`]);
//! * Sellmeier: n²(λ) = 1 + Σⱼ Bⱼ λ²/(λ² − Cⱼ), λ in µm, Cⱼ in µm² (Schott catalogue form);
//! * Cauchy: n(λ) = A + B/λ², λ in µm, B in µm².

use crate::color::d65_normalized;
use crate::rgb2spec::{RgbSigmoid, srgb_to_sigmoid_refined};
use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN, SampledSpectrum, SampledWavelengths};
use std::sync::Arc;

mod piecewise_linear;

pub use piecewise_linear::{Extrapolation, PiecewiseLinear};

/// Which role an RGB-uplifted spectrum plays (how the colour was turned into a spectrum).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RgbKind {
    /// A reflectance in [0, 1] (pbrt `RGBAlbedoSpectrum`).
    Albedo,
    /// Any non-negative quantity (η, k, σ): scale·s(λ) (pbrt `RGBUnboundedSpectrum`).
    Unbounded,
    /// Emission: scale·s(λ)·D65(λ) with unit-luminance D65 (pbrt `RGBIlluminantSpectrum`).
    Illuminant,
}

/// An RGB colour uplifted to a spectrum: 3 sigmoid coefficients, a scale and the role (`Copy`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbSpectrum {
    /// The sigmoid polynomial (values in [0, 1]).
    pub sigmoid: RgbSigmoid,
    /// Multiplier of the sigmoid (1 for albedos, 2·max(rgb) otherwise).
    pub scale: f32,
    /// Role of the spectrum.
    pub kind: RgbKind,
}

impl RgbSpectrum {
    /// Value at `lambda` nm.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        let v = self.scale * self.sigmoid.eval(lambda);
        match self.kind {
            RgbKind::Illuminant => v * d65_normalized(lambda),
            _ => v,
        }
    }

    /// Mitsuba's `mean()` of an RGB spectrum (`srgb_model_mean`): the average of [`Self::eval`]
    /// at 16 wavelengths evenly spaced over 360–830 nm, four at a time (a bitmap takes it per
    /// texel).
    pub fn mean(&self) -> f32 {
        const STEP: f32 = (830.0 - 360.0) / 15.0;
        let mut acc = glam::Vec4::ZERO;
        for k in 0..4 {
            let lambda = glam::Vec4::from_array([0, 1, 2, 3].map(|i| 360.0 + STEP * (4 * k + i) as f32));
            let v = self.sigmoid.eval4(lambda);
            acc += match self.kind {
                RgbKind::Illuminant => v * glam::Vec4::from_array(lambda.to_array().map(d65_normalized)),
                _ => v,
            };
        }
        self.scale * acc.element_sum() / 16.0
    }

    /// Values at the four wavelengths of a path, each equal bit for bit to [`Self::eval`]'s (the
    /// sigmoid polynomial evaluated four lanes at once).
    #[inline]
    pub fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        let lambda = glam::Vec4::from_array(wl.lambdas());
        let v = glam::Vec4::splat(self.scale) * self.sigmoid.eval4(lambda);
        match self.kind {
            RgbKind::Illuminant => SampledSpectrum(v * glam::Vec4::from_array(wl.d65())),
            _ => SampledSpectrum(v),
        }
    }
}

/// Planck's law: spectral radiance of a blackbody at `lambda_nm` and `temperature_k`, in
/// W·m⁻²·sr⁻¹·m⁻¹ (pbrt-v4 `Blackbody`). 0 for a non-positive temperature.
pub fn planck(lambda_nm: f64, temperature_k: f64) -> f64 {
    if temperature_k.is_nan() || temperature_k <= 0.0 || lambda_nm.is_nan() || lambda_nm <= 0.0 {
        return 0.0;
    }
    const C: f64 = 299792458.0;
    const H: f64 = 6.62606957e-34;
    const KB: f64 = 1.3806488e-23;
    let l = lambda_nm * 1e-9;
    (2.0 * H * C * C) / (l.powi(5) * ((H * C / (l * KB * temperature_k)).exp_m1()))
}

/// Wien's displacement constant b, m·K: λ_max = b/T.
pub const WIEN_B: f64 = 2.8977721e-3;

/// A blackbody emitter: Planck's law times a factor, 0 outside a wavelength range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blackbody {
    temperature: f32,
    norm: f32,
    /// The wavelengths (nm, both ends included) outside which the spectrum is 0.
    range: [f32; 2],
}

impl Blackbody {
    /// Blackbody of `temperature_k` kelvin normalized to a peak of 1 at every wavelength (pbrt's);
    /// `None` unless the temperature is positive and finite.
    pub fn new(temperature_k: f32) -> Option<Self> {
        if !(temperature_k > 0.0 && temperature_k.is_finite()) {
            return None;
        }
        let t = temperature_k as f64;
        let peak = planck(WIEN_B / t * 1e9, t);
        Some(Self {
            temperature: temperature_k,
            norm: (1.0 / peak) as f32,
            range: [0.0, f32::INFINITY],
        })
    }

    /// Blackbody radiance of `temperature_k` kelvin in W·m⁻²·sr⁻¹·nm⁻¹ (B(λ, T)·10⁻⁹) within
    /// `range` (nm, ends included) and 0 outside (Mitsuba 3's `blackbody`); `None` unless the
    /// temperature is positive and finite and the range finite, non-negative and in order.
    pub fn radiance(temperature_k: f32, range: [f32; 2]) -> Option<Self> {
        let ok = range.iter().all(|l| l.is_finite() && *l >= 0.0) && range[0] <= range[1];
        Some(Self {
            norm: 1e-9,
            range,
            ..Self::new(temperature_k).filter(|_| ok)?
        })
    }

    /// The same spectrum times `k` (non-negative and finite).
    pub fn scaled(self, k: f32) -> Self {
        Self {
            norm: self.norm * k,
            ..self
        }
    }

    /// The temperature, K.
    pub fn temperature(&self) -> f32 {
        self.temperature
    }

    /// The wavelengths (nm, ends included) outside which the spectrum is 0 (`[0, ∞]` for
    /// pbrt's normalized form).
    pub fn range(&self) -> [f32; 2] {
        self.range
    }

    /// The factor times B(λ, T) inside the range, 0 outside.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        if lambda < self.range[0] || lambda > self.range[1] {
            return 0.0;
        }
        (planck(lambda as f64, self.temperature as f64) * self.norm as f64) as f32
    }

    /// The largest value over 360–830 nm: B is unimodal in λ, so its value at Wien's peak
    /// clamped to the part of the visible range the spectrum covers.
    fn max_value(&self) -> f32 {
        let (lo, hi) = (self.range[0].max(LAMBDA_MIN), self.range[1].min(LAMBDA_MAX));
        if lo > hi {
            return 0.0;
        }
        let peak_nm = (WIEN_B / self.temperature as f64 * 1e9) as f32;
        self.eval(peak_nm.clamp(lo, hi))
    }
}

/// The Sellmeier dispersion formula n²(λ) = 1 + Σⱼ Bⱼ λ²/(λ² − Cⱼ) (λ in µm, Cⱼ in µm²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sellmeier {
    /// B₁, B₂, B₃ (dimensionless).
    pub b: [f32; 3],
    /// C₁, C₂, C₃ in µm².
    pub c_um2: [f32; 3],
}

impl Sellmeier {
    /// n(λ) at `lambda` nm (computed in f64); 0 where the formula has no real positive value
    /// (near a pole), which [`crate::ior::Ior`] turns into 1.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        let l2 = (lambda as f64 * 1e-3).powi(2);
        let mut n2 = 1.0f64;
        for j in 0..3 {
            n2 += self.b[j] as f64 * l2 / (l2 - self.c_um2[j] as f64);
        }
        if n2 > 0.0 && n2.is_finite() {
            n2.sqrt() as f32
        } else {
            0.0
        }
    }
}

/// The two-term Cauchy formula n(λ) = A + B/λ² (λ in µm, B in µm²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cauchy {
    /// A (dimensionless).
    pub a: f32,
    /// B in µm².
    pub b_um2: f32,
}

impl Cauchy {
    /// n(λ) at `lambda` nm.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        let l_um = lambda * 1e-3;
        self.a + self.b_um2 / (l_um * l_um)
    }
}

/// A wavelength-dependent quantity. Cheap to clone (tables are shared).
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f32),
    /// Linear interpolation between samples.
    PiecewiseLinear(Arc<PiecewiseLinear>),
    /// An RGB colour uplifted with Jakob & Hanika's sigmoid polynomials.
    Rgb(RgbSpectrum),
    /// Planck's law, normalized to peak 1 (pbrt's) or as a radiance (Mitsuba's).
    Blackbody(Blackbody),
    /// Sellmeier dispersion formula (an index of refraction).
    Sellmeier(Sellmeier),
    /// Cauchy dispersion formula (an index of refraction).
    Cauchy(Cauchy),
}

/// 1 nm scan of `f` over the visible range (both ends included).
fn scan_visible(f: impl Fn(f32) -> f32) -> impl Iterator<Item = f32> {
    let n = (LAMBDA_MAX - LAMBDA_MIN) as usize;
    (0..=n).map(move |i| f(LAMBDA_MIN + i as f32))
}

impl Spectrum {
    /// A constant spectrum.
    pub const fn constant(v: f32) -> Self {
        Spectrum::Constant(v)
    }

    /// A piecewise-linear spectrum.
    pub fn piecewise(p: PiecewiseLinear) -> Self {
        Spectrum::PiecewiseLinear(Arc::new(p))
    }

    /// A reflectance from linear sRGB; components are clamped to [0, 1] (NaN → 0).
    pub fn rgb_albedo(rgb: [f32; 3]) -> Self {
        Spectrum::Rgb(RgbSpectrum {
            sigmoid: srgb_to_sigmoid_refined(rgb),
            scale: 1.0,
            kind: RgbKind::Albedo,
        })
    }

    fn rgb_scaled(rgb: [f32; 3], kind: RgbKind) -> Self {
        let rgb = rgb.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
        let m = rgb[0].max(rgb[1]).max(rgb[2]);
        if m <= 0.0 {
            let sigmoid = RgbSigmoid::constant(0.0);
            return Spectrum::Rgb(RgbSpectrum {
                sigmoid,
                scale: 0.0,
                kind,
            });
        }
        let scale = 2.0 * m;
        let sigmoid = srgb_to_sigmoid_refined(rgb.map(|v| v / scale));
        Spectrum::Rgb(RgbSpectrum { sigmoid, scale, kind })
    }

    /// Any non-negative quantity from linear sRGB (η, k, σ given as colours): scale = 2·max,
    /// coefficients of rgb/scale (pbrt `RGBUnboundedSpectrum`). Negative or non-finite components
    /// count as 0 (the scene reader rejects them first).
    pub fn rgb_unbounded(rgb: [f32; 3]) -> Self {
        Self::rgb_scaled(rgb, RgbKind::Unbounded)
    }

    /// Emission from linear sRGB: the unbounded uplift × D65 of unit luminance, so that
    /// `rgb_illuminant([1, 1, 1])` is exactly D65 and renders as linear sRGB (1, 1, 1) (Mitsuba's
    /// spectral variants, pbrt `RGBIlluminantSpectrum`).
    pub fn rgb_illuminant(rgb: [f32; 3]) -> Self {
        Self::rgb_scaled(rgb, RgbKind::Illuminant)
    }

    /// CIE D65 of unit luminance (Mitsuba `<spectrum type="d65"/>`), = `rgb_illuminant([1, 1, 1])`.
    pub fn d65() -> Self {
        Self::rgb_illuminant([1.0; 3])
    }

    /// A blackbody of `temperature_k` kelvin normalized to peak 1 (pbrt's `blackbody`). A
    /// non-positive or non-finite temperature gives the zero spectrum (the scene reader rejects
    /// it first).
    pub fn blackbody(temperature_k: f32) -> Self {
        match Blackbody::new(temperature_k) {
            Some(b) => Spectrum::Blackbody(b),
            None => Spectrum::Constant(0.0),
        }
    }

    /// Blackbody radiance in W·m⁻²·sr⁻¹·nm⁻¹ within `range` nm and 0 outside (Mitsuba 3's
    /// `blackbody`, whose range is 360–830 nm by default; [`Blackbody::radiance`]). Invalid
    /// arguments give the zero spectrum (the scene reader rejects them first).
    pub fn blackbody_radiance(temperature_k: f32, range: [f32; 2]) -> Self {
        match Blackbody::radiance(temperature_k, range) {
            Some(b) => Spectrum::Blackbody(b),
            None => Spectrum::Constant(0.0),
        }
    }

    /// The spectrum times `k`, exactly, for every kind but the dispersion formulas (`None`:
    /// they are indices of refraction, not amounts); `None` too where a product is not finite.
    pub fn scaled(&self, k: f32) -> Option<Self> {
        if !k.is_finite() {
            return None;
        }
        let s = match self {
            Spectrum::Constant(v) => Spectrum::Constant(v * k),
            Spectrum::PiecewiseLinear(p) => Spectrum::piecewise(p.scaled(k)?),
            Spectrum::Rgb(r) => Spectrum::Rgb(RgbSpectrum {
                scale: r.scale * k,
                ..*r
            }),
            Spectrum::Blackbody(b) => Spectrum::Blackbody(b.scaled(k)),
            Spectrum::Sellmeier(_) | Spectrum::Cauchy(_) => return None,
        };
        s.max_value().is_finite().then_some(s)
    }

    /// A Sellmeier index of refraction (B dimensionless, C in µm²).
    pub fn sellmeier(b: [f32; 3], c_um2: [f32; 3]) -> Self {
        Spectrum::Sellmeier(Sellmeier { b, c_um2 })
    }

    /// A Cauchy index of refraction n = a + b/λ² (λ in µm, b in µm²).
    pub fn cauchy(a: f32, b_um2: f32) -> Self {
        Spectrum::Cauchy(Cauchy { a, b_um2 })
    }

    /// Value at one wavelength (nm).
    pub fn eval(&self, lambda: f32) -> f32 {
        match self {
            Spectrum::Constant(v) => *v,
            Spectrum::PiecewiseLinear(p) => p.eval(lambda),
            Spectrum::Rgb(r) => r.eval(lambda),
            Spectrum::Blackbody(b) => b.eval(lambda),
            Spectrum::Sellmeier(s) => s.eval(lambda),
            Spectrum::Cauchy(c) => c.eval(lambda),
        }
    }

    /// Values at the four wavelengths of a path.
    #[inline]
    pub fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Spectrum::Constant(v) => SampledSpectrum::splat(*v),
            Spectrum::Rgb(r) => r.sample(wl),
            _ => SampledSpectrum::from_fn(|i| self.eval(wl.lambda(i))),
        }
    }

    /// True when the value does not depend on λ over the visible range.
    pub fn is_constant(&self) -> bool {
        self.as_constant().is_some()
    }

    /// The constant value, if the spectrum does not depend on λ over the visible range (a constant,
    /// a flat table, a grey RGB reflectance, Cauchy with B = 0, Sellmeier with all Bⱼ = 0).
    pub fn as_constant(&self) -> Option<f32> {
        match self {
            Spectrum::Constant(v) => Some(*v),
            Spectrum::PiecewiseLinear(p) => p.constant_value(),
            Spectrum::Rgb(r) => (r.kind != RgbKind::Illuminant && r.sigmoid.is_flat())
                .then(|| r.scale * r.sigmoid.eval(550.0)),
            Spectrum::Blackbody(_) => None,
            Spectrum::Sellmeier(s) => (s.b == [0.0; 3]).then_some(1.0),
            Spectrum::Cauchy(c) => (c.b_um2 == 0.0).then_some(c.a),
        }
    }

    /// An upper bound of the value over 360–830 nm (exact for every kind except the RGB
    /// illuminant, where it is scale · max s · max D65).
    pub fn max_value(&self) -> f32 {
        match self {
            Spectrum::Constant(v) => *v,
            Spectrum::PiecewiseLinear(p) => p.max_value(),
            Spectrum::Rgb(r) => {
                let m = r.scale * r.sigmoid.max_value();
                match r.kind {
                    RgbKind::Illuminant => m * scan_visible(d65_normalized).fold(0.0, f32::max),
                    _ => m,
                }
            }
            Spectrum::Blackbody(b) => b.max_value(),
            // Normal dispersion decreases with λ; the scan also covers anomalous tables.
            Spectrum::Sellmeier(_) | Spectrum::Cauchy(_) => {
                scan_visible(|l| self.eval(l)).fold(f32::MIN, f32::max)
            }
        }
    }

    /// Mitsuba 3's `mean()` of a texture, which `plastic`, `roughplastic` and `pplastic` use to
    /// weigh their sampling between lobes (and light selection to estimate power): a sampled
    /// spectrum's integral over its own range divided by that range ([`PiecewiseLinear::mean`]),
    /// an RGB spectrum's average at 16 wavelengths evenly spaced over 360–830 nm
    /// (`srgb_model_mean`), a constant's value; other kinds average 360–830 nm in 1 nm steps.
    pub fn mean(&self) -> f32 {
        if let Some(v) = self.as_constant() {
            return v;
        }
        match self {
            Spectrum::PiecewiseLinear(p) => p.mean(),
            Spectrum::Rgb(r) => r.mean(),
            _ => {
                let n = 471;
                (0..n).map(|i| self.eval(360.0 + i as f32)).sum::<f32>() / n as f32
            }
        }
    }
}

/// A spectral parameter as a BSDF model holds it: a [`Spectrum`] (any wavelengths; what the
/// battery and the instruments use) or a [`SampledSpectrum`] already evaluated at one path's
/// wavelengths (the `Copy` BSDF value a material becomes at a hit, see
/// [`crate::bsdfs::SurfaceBsdf`]). Models are generic over it, so their formulas are written once.
pub trait SpectralValue: Clone + std::fmt::Debug + Send + Sync {
    /// Values at the four wavelengths of a path.
    fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum;
}

impl SpectralValue for Spectrum {
    #[inline]
    fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        Spectrum::sample(self, wl)
    }
}

/// Already evaluated: the wavelengths must be the ones it was evaluated at.
impl SpectralValue for SampledSpectrum {
    #[inline]
    fn sample(&self, _wl: &SampledWavelengths) -> SampledSpectrum {
        *self
    }
}

impl From<f32> for Spectrum {
    fn from(v: f32) -> Self {
        Spectrum::Constant(v)
    }
}

impl From<PiecewiseLinear> for Spectrum {
    fn from(p: PiecewiseLinear) -> Self {
        Spectrum::piecewise(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_detection_per_kind() {
        assert_eq!(Spectrum::cauchy(1.5, 0.0).as_constant(), Some(1.5));
        assert_eq!(Spectrum::cauchy(1.5, 0.004).as_constant(), None);
        assert_eq!(
            Spectrum::sellmeier([0.0; 3], [0.01, 0.02, 100.0]).as_constant(),
            Some(1.0)
        );
        assert!(!Spectrum::blackbody(5000.0).is_constant());
        let flat = PiecewiseLinear::new(vec![300.0, 900.0], vec![2.0, 2.0], Extrapolation::Zero).unwrap();
        assert_eq!(Spectrum::piecewise(flat).as_constant(), Some(2.0));
        let short = PiecewiseLinear::new(vec![400.0, 700.0], vec![2.0, 2.0], Extrapolation::Zero).unwrap();
        assert_eq!(Spectrum::piecewise(short.clone()).as_constant(), None);
        let clamped = short.with_extrapolation(Extrapolation::Clamp);
        assert_eq!(Spectrum::piecewise(clamped).as_constant(), Some(2.0));
        let grey = Spectrum::rgb_albedo([0.25, 0.25, 0.25]);
        assert!((grey.as_constant().unwrap() - 0.25).abs() < 1e-6);
        assert!((Spectrum::rgb_unbounded([3.0, 3.0, 3.0]).as_constant().unwrap() - 3.0).abs() < 1e-5);
        assert_eq!(Spectrum::rgb_illuminant([1.0, 1.0, 1.0]).as_constant(), None);
        assert_eq!(Spectrum::rgb_albedo([0.9, 0.1, 0.1]).as_constant(), None);
    }

    #[test]
    fn blackbody_matches_planck_reference_values() {
        // pbrt-v4 util/spectrum_test.cpp (Blackbody; values from spectralcalc.com), within 0.1 %.
        for (l, t, b) in [
            (483.0, 6000.0, 3.1849e13),
            (600.0, 6000.0, 2.86772e13),
            (500.0, 3700.0, 1.59845e12),
            (600.0, 4500.0, 7.46497e12),
        ] {
            let v = planck(l, t);
            assert!((v / b - 1.0).abs() < 1e-3, "B({l}, {t}) = {v:e}, expected {b:e}");
        }
        // Normalized: the Wien peak is 1, everything else is below.
        let s = Spectrum::blackbody(6000.0);
        let peak = (WIEN_B / 6000.0 * 1e9) as f32;
        assert!((s.eval(peak) - 1.0).abs() < 1e-6);
        assert!(s.eval(400.0) < 1.0 && s.eval(700.0) < 1.0);
        assert_eq!(s.max_value(), s.eval(peak));
        // Peak outside the visible range (2000 K → 1449 nm): max at 830 nm.
        let cold = Spectrum::blackbody(2000.0);
        let brute = scan_visible(|l| cold.eval(l)).fold(0.0f32, f32::max);
        assert!((cold.max_value() - brute).abs() < 1e-6 * brute.max(1.0));
        assert!(cold.max_value() < 1.0);
        assert_eq!(Spectrum::blackbody(-5.0), Spectrum::Constant(0.0));
        assert_eq!(Spectrum::blackbody(f32::NAN), Spectrum::Constant(0.0));
    }

    #[test]
    fn blackbody_radiance_matches_mitsuba() {
        // W·m⁻²·sr⁻¹·nm⁻¹, 0 outside 360–830 nm: Mitsuba 3's src/render/tests/test_spectra.py
        // (`test03_blackbody`, 5000 K) and Mitsuba 3.9.1 `scalar_spectral` at 3000 K.
        let hot = Spectrum::blackbody_radiance(5000.0, [360.0, 830.0]);
        let cold = Spectrum::blackbody_radiance(3000.0, [360.0, 830.0]);
        for (s, l, expected) in [
            (&hot, 350.0, 0.0),
            (&hot, 456.0, 10997.9),
            (&hot, 700.0, 11812.0),
            (&hot, 840.0, 0.0),
            (&cold, 359.9, 0.0),
            (&cold, 360.0, 32.265572),
            (&cold, 456.0, 163.484253),
            (&cold, 550.0, 386.542328),
            (&cold, 700.0, 750.596375),
            (&cold, 830.0, 938.49707),
            (&cold, 830.1, 0.0),
        ] {
            let v = s.eval(l);
            assert!(
                (v - expected).abs() <= 1e-4 * expected,
                "B({l} nm) = {v}, Mitsuba {expected}"
            );
        }
        // The peaks: 5000 K at 580 nm, inside; 3000 K at 966 nm, so the range's end.
        let peak = (WIEN_B / 5000.0 * 1e9) as f32;
        assert_eq!(hot.max_value(), hot.eval(peak));
        assert_eq!(cold.max_value(), cold.eval(830.0));
        // Mitsuba's `wavelength_min` and `wavelength_max` (ends included).
        let band = Spectrum::blackbody_radiance(5000.0, [400.0, 700.0]);
        assert_eq!(band.eval(399.9), 0.0);
        assert!((band.eval(400.0) - 8743.565).abs() < 1.0);
        assert_eq!(band.max_value(), band.eval(peak));
        assert_eq!(
            Spectrum::blackbody_radiance(5000.0, [900.0, 1000.0]).max_value(),
            0.0
        );
        for range in [
            [700.0, 400.0],
            [f32::NAN, 830.0],
            [-1.0, 830.0],
            [360.0, f32::INFINITY],
        ] {
            assert_eq!(
                Spectrum::blackbody_radiance(5000.0, range),
                Spectrum::Constant(0.0)
            );
        }
        assert_eq!(
            Spectrum::blackbody_radiance(0.0, [360.0, 830.0]),
            Spectrum::Constant(0.0)
        );
    }

    #[test]
    fn scaled_multiplies_every_amount_and_refuses_indices() {
        let table = PiecewiseLinear::new(vec![400.0, 700.0], vec![1.0, 3.0], Extrapolation::Zero).unwrap();
        for s in [
            Spectrum::Constant(0.5),
            Spectrum::piecewise(table),
            Spectrum::rgb_albedo([0.2, 0.5, 0.8]),
            Spectrum::rgb_illuminant([2.0, 1.0, 0.5]),
            Spectrum::blackbody(4000.0),
            Spectrum::blackbody_radiance(4000.0, [360.0, 830.0]),
        ] {
            let twice = s.scaled(2.0).unwrap();
            for l in [380.0, 450.0, 555.5, 650.0, 800.0] {
                assert!(
                    (twice.eval(l) - 2.0 * s.eval(l)).abs() <= 1e-6 * s.eval(l),
                    "{s:?} at {l}"
                );
            }
            assert_eq!(s.scaled(f32::NAN), None);
        }
        assert_eq!(Spectrum::cauchy(1.5, 0.004).scaled(2.0), None);
        assert_eq!(Spectrum::Constant(1e38).scaled(1e10), None);
    }

    #[test]
    fn cauchy_and_sellmeier_formulas() {
        // Two-term Cauchy BK7 (textbook table, e.g. Wikipedia "Cauchy's equation"): A = 1.5046,
        // B = 0.00420 µm² → n(500 nm) = 1.5046 + 0.0168.
        let c = Spectrum::cauchy(1.5046, 0.00420);
        assert!((c.eval(500.0) - 1.5214).abs() < 1e-6);
        assert!((c.max_value() - c.eval(360.0)).abs() < 1e-6);
        // Sellmeier with one term B = 1, C = 0: n² = 2 at every λ.
        let s = Spectrum::sellmeier([1.0, 0.0, 0.0], [0.0, 0.0, 0.0]);
        assert!((s.eval(432.1) - 2f32.sqrt()).abs() < 1e-6);
        // At a pole the value is 0 (an Ior turns it into 1), never NaN.
        let pole = Spectrum::sellmeier([1.0, 0.0, 0.0], [0.25, 0.0, 0.0]);
        assert_eq!(pole.eval(500.0), 0.0);
    }

    #[test]
    fn rgb_kinds_are_cheap_and_scaled() {
        let a = Spectrum::rgb_albedo([2.0, -1.0, 0.5]);
        let Spectrum::Rgb(r) = a else {
            panic!("not an RGB spectrum")
        };
        assert_eq!(r.kind, RgbKind::Albedo);
        assert_eq!(r.scale, 1.0);
        assert!(std::mem::size_of::<RgbSpectrum>() <= 20);
        let u = Spectrum::rgb_unbounded([0.0, 0.0, 0.0]);
        assert_eq!(u.eval(500.0), 0.0);
        assert_eq!(u.max_value(), 0.0);
        let Spectrum::Rgb(r) = Spectrum::rgb_unbounded([4.0, 1.0, 2.0]) else {
            panic!()
        };
        assert_eq!(r.scale, 8.0);
        assert!(
            Spectrum::rgb_illuminant([f32::NAN, 1.0, 1.0])
                .eval(500.0)
                .is_finite()
        );
    }

    #[test]
    fn mean_is_the_visible_average() {
        let p = PiecewiseLinear::new(vec![360.0, 830.0], vec![0.0, 1.0], Extrapolation::Zero).unwrap();
        assert!((Spectrum::piecewise(p).mean() - 0.5).abs() < 1e-5);
        assert_eq!(Spectrum::constant(0.3).mean(), 0.3);
    }

    /// Mitsuba 3.9.1's `mean()` of the same spectra (`means` in
    /// `testdata/mitsuba/reference/mitsuba-spot-values.json`, made by
    /// `crates/gonio-core/benches/mitsuba_spot_values.py`): an `irregular` spectrum averages over
    /// its own range, not over the visible one (the sampling weight of `plastic` depends on it),
    /// and an RGB spectrum over 16 wavelengths. RGB values differ by our own uplifting table (up
    /// to 2 % per wavelength).
    #[test]
    fn mean_matches_mitsubas_for_sampled_and_rgb_spectra() {
        let p = PiecewiseLinear::new(
            vec![400.0, 500.0, 600.0, 700.0],
            vec![0.393418, 0.27199, 0.83903, 0.507508],
            Extrapolation::Zero,
        )
        .unwrap();
        let m = Spectrum::piecewise(p).mean();
        assert!((m - 0.520_494_3).abs() < 1e-6, "irregular mean {m}");
        for (rgb, mitsuba) in [([0.2, 0.5, 0.8], 0.418_522), ([0.9, 0.1, 0.05], 0.583_103)] {
            let m = Spectrum::rgb_albedo(rgb).mean();
            assert!((m / mitsuba - 1.0).abs() < 5e-3, "srgb {rgb:?}: {m} vs {mitsuba}");
        }
    }
}
