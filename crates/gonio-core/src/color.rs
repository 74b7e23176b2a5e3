//! Colour: CIE 1931 colour matching, the D65 illuminant, XYZ ↔ linear sRGB, and the spectral
//! estimator that turns a path's four wavelengths into colour.
//!
//! * CIE 1931 2° observer x̄, ȳ, z̄ tabulated at 1 nm on [360, 830] (`data/cie1931.rs`), evaluated
//!   by linear interpolation ([`cie_xyz`]); 0 outside the table.
//! * `CIE_Y_INTEGRAL` = ∫ȳ dλ = 106.856895 nm (pbrt-v4 `CIE_Y_integral`; the 1 nm table sums to
//!   106.85692).
//! * Spectral estimator (pbrt-v4 `SampledSpectrum::ToXYZ`): for radiance L at wavelengths λᵢ with
//!   densities pᵢ,
//!
//!   ```text
//!   XYZ = (1/CIE_Y_INTEGRAL) · (1/N) Σᵢ x̄ȳz̄(λᵢ) Lᵢ / pᵢ      (safe division: pᵢ = 0 adds 0)
//!   ```
//!
//!   so terminated secondary wavelengths (dispersion) contribute nothing ([`xyz_from_sampled`]).
//! * Deterministic integrals at 1 nm steps: a reflectance ρ under D65,
//!   `XYZ = Σ x̄ȳz̄ D65 ρ / Σ ȳ D65` (a constant 1 gives the D65 white, Y = 1), and an emission S,
//!   `XYZ = Σ x̄ȳz̄ S / CIE_Y_INTEGRAL`.
//! * XYZ → linear sRGB (Rec. 709 primaries, D65 white; IEC 61966-2-1 matrices as used by pbrt-v3 and
//!   Mitsuba): rows (3.240479, −1.537150, −0.498535), (−0.969256, 1.875991, 0.041556),
//!   (0.055648, −0.204043, 1.057311); the inverse rows (0.412453, 0.357580, 0.180423),
//!   (0.212671, 0.715160, 0.072169), (0.019334, 0.119193, 0.950227).
//! * sRGB transfer curve (IEC 61966-2-1): encode x ≤ 0.0031308 → 12.92 x, else
//!   1.055 x^(1/2.4) − 0.055; decode the inverse with threshold 0.04045.
//!
//! The D65 table (`data/d65.rs`, 5 nm, 300–830 nm) is interpolated linearly; [`d65_normalized`]
//! scales it so that ∫ȳ·D65 dλ = `CIE_Y_INTEGRAL`, i.e. luminance Y = 1 through the estimator
//! (pbrt-v4's normalization of named illuminants).

use crate::data::cie1931::{CIE_LAMBDA_START, CIE_SAMPLES, CIE_X, CIE_Y, CIE_Z};
use crate::data::d65::{D65, D65_LAMBDA_START, D65_LAMBDA_STEP, D65_SAMPLES};
use crate::spectra::Spectrum;
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use glam::{Mat3, Vec3, Vec4};
use std::sync::LazyLock;

/// ∫ȳ(λ) dλ over the CIE 1931 table, nm (pbrt-v4 `CIE_Y_integral`).
pub const CIE_Y_INTEGRAL: f32 = 106.856895;

/// XYZ → linear sRGB (Rec. 709 primaries, D65 white). Column-major storage of the rows
/// (3.240479, −1.537150, −0.498535), (−0.969256, 1.875991, 0.041556), (0.055648, −0.204043, 1.057311).
#[allow(clippy::excessive_precision)]
pub const LINEAR_SRGB_FROM_XYZ: Mat3 = Mat3::from_cols_array(&[
    3.240479, -0.969256, 0.055648, //
    -1.537150, 1.875991, -0.204043, //
    -0.498535, 0.041556, 1.057311,
]);

/// Linear sRGB → XYZ, the inverse of [`LINEAR_SRGB_FROM_XYZ`]. Rows (0.412453, 0.357580, 0.180423),
/// (0.212671, 0.715160, 0.072169), (0.019334, 0.119193, 0.950227).
#[allow(clippy::excessive_precision)]
pub const XYZ_FROM_LINEAR_SRGB: Mat3 = Mat3::from_cols_array(&[
    0.412453, 0.212671, 0.019334, //
    0.357580, 0.715160, 0.119193, //
    0.180423, 0.072169, 0.950227,
]);

/// Linear sRGB of a CIE XYZ colour.
#[inline]
pub fn linear_srgb_from_xyz(xyz: Vec3) -> Vec3 {
    LINEAR_SRGB_FROM_XYZ * xyz
}

/// CIE XYZ of a linear sRGB colour.
#[inline]
pub fn xyz_from_linear_srgb(rgb: Vec3) -> Vec3 {
    XYZ_FROM_LINEAR_SRGB * rgb
}

/// Luminance Y of a linear sRGB colour: the Y row of [`XYZ_FROM_LINEAR_SRGB`],
/// Y = 0.212671 R + 0.715160 G + 0.072169 B (Rec. 709 primaries, D65 white; IEC 61966-2-1).
/// The one luminance of gonio (env-map sampling, blend weights from bitmaps), consistent with the
/// colour conversions here, so an RGB colour and its XYZ agree on Y.
#[inline]
#[allow(clippy::excessive_precision)]
pub fn luminance(rgb: [f32; 3]) -> f32 {
    0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2]
}

/// Linear interpolation in a table sampled every `step` nm from `start`; 0 outside.
#[inline]
fn lerp_table(table: &[f32], start: f32, step: f32, lambda: f32) -> f32 {
    let x = (lambda - start) / step;
    let last = (table.len() - 1) as f32;
    if !(0.0..=last).contains(&x) {
        return 0.0;
    }
    let i = (x as usize).min(table.len() - 2);
    let t = x - i as f32;
    table[i] + t * (table[i + 1] - table[i])
}

/// The CIE 1931 colour matching functions (x̄, ȳ, z̄) at `lambda` nm (linear interpolation of the
/// 1 nm table; 0 outside [360, 830]).
#[inline]
pub fn cie_xyz(lambda: f32) -> Vec3 {
    let x = (lambda - CIE_LAMBDA_START).max(-1.0);
    if !(0.0..=(CIE_SAMPLES - 1) as f32).contains(&x) {
        return Vec3::ZERO;
    }
    let i = (x as usize).min(CIE_SAMPLES - 2);
    let t = x - i as f32;
    let a = Vec3::new(CIE_X[i], CIE_Y[i], CIE_Z[i]);
    let b = Vec3::new(CIE_X[i + 1], CIE_Y[i + 1], CIE_Z[i + 1]);
    a + t * (b - a)
}

/// ȳ(λ) alone (luminous efficiency), linear interpolation; 0 outside [360, 830].
#[inline]
pub fn cie_y(lambda: f32) -> f32 {
    lerp_table(&CIE_Y, CIE_LAMBDA_START, 1.0, lambda)
}

/// The CIE D65 relative spectral power (100 at 560 nm), linear interpolation of the 5 nm table;
/// 0 outside [300, 830].
#[inline]
pub fn d65(lambda: f32) -> f32 {
    debug_assert_eq!(D65.len(), D65_SAMPLES);
    lerp_table(&D65, D65_LAMBDA_START, D65_LAMBDA_STEP, lambda)
}

/// 1 / Σ_{λ=360..830} ȳ(λ) D65(λ) × CIE_Y_INTEGRAL: the factor that gives D65 unit luminance.
static D65_SCALE: LazyLock<f32> = LazyLock::new(|| {
    let s: f64 = (0..CIE_SAMPLES)
        .map(|i| CIE_Y[i] as f64 * d65(CIE_LAMBDA_START + i as f32) as f64)
        .sum();
    (CIE_Y_INTEGRAL as f64 / s) as f32
});

/// D65 scaled so that ∫ȳ·D65 dλ = `CIE_Y_INTEGRAL` (luminance 1 through the estimator): the
/// illuminant of an RGB emitter (`Spectrum::rgb_illuminant`).
#[inline]
pub fn d65_normalized(lambda: f32) -> f32 {
    d65(lambda) * *D65_SCALE
}

/// [`d65_normalized`] at four wavelengths, each value equal bit for bit to its (one check of the
/// scale and the four interpolations side by side: an RGB emitter's spectrum at a path's
/// wavelengths, `RgbSpectrum::sample`).
#[inline]
pub fn d65_normalized4(lambda: [f32; 4]) -> [f32; 4] {
    let scale = *D65_SCALE;
    let last = (D65_SAMPLES - 1) as f32;
    let x = (Vec4::from_array(lambda) - Vec4::splat(D65_LAMBDA_START)) / Vec4::splat(D65_LAMBDA_STEP);
    let inside = x.cmpge(Vec4::ZERO) & x.cmple(Vec4::splat(last));
    // Outside the table (or NaN) lane k reads interval 0 and is zeroed below, as `lerp_table`
    // gives 0 there.
    let x = Vec4::select(inside, x, Vec4::ZERO);
    let i = x.to_array().map(|x| (x as usize).min(D65_SAMPLES - 2));
    let a = Vec4::from_array(i.map(|i| D65[i]));
    let b = Vec4::from_array(i.map(|i| D65[i + 1]));
    let t = x - Vec4::from_array(i.map(|i| i as f32));
    let v = (a + t * (b - a)) * scale;
    Vec4::select(inside, v, Vec4::ZERO).to_array()
}

/// The Monte Carlo estimate of CIE XYZ from radiance `l` carried at the wavelengths `wl`:
/// mean_i[x̄ȳz̄(λᵢ) Lᵢ / pᵢ] / CIE_Y_INTEGRAL, where a zero pdf (terminated wavelength)
/// contributes 0.
pub fn xyz_from_sampled(l: SampledSpectrum, wl: &SampledWavelengths) -> Vec3 {
    let pdf = wl.pdf();
    let mut acc = Vec3::ZERO;
    for i in 0..N_SPECTRUM_SAMPLES {
        if pdf[i] != 0.0 {
            acc += cie_xyz(wl.lambda(i)) * (l[i] / pdf[i]);
        }
    }
    acc / (N_SPECTRUM_SAMPLES as f32 * CIE_Y_INTEGRAL)
}

/// The Monte Carlo estimate of luminance Y alone (the ȳ row of [`xyz_from_sampled`]).
pub fn y_from_sampled(l: SampledSpectrum, wl: &SampledWavelengths) -> f32 {
    let pdf = wl.pdf();
    let mut acc = 0.0;
    for i in 0..N_SPECTRUM_SAMPLES {
        if pdf[i] != 0.0 {
            acc += cie_y(wl.lambda(i)) * (l[i] / pdf[i]);
        }
    }
    acc / (N_SPECTRUM_SAMPLES as f32 * CIE_Y_INTEGRAL)
}

/// The Monte Carlo estimate of linear sRGB from radiance `l` at the wavelengths `wl`
/// ([`xyz_from_sampled`] followed by [`linear_srgb_from_xyz`]).
pub fn linear_srgb_from_sampled(l: SampledSpectrum, wl: &SampledWavelengths) -> Vec3 {
    linear_srgb_from_xyz(xyz_from_sampled(l, wl))
}

/// Σ over λ = 360, 361, …, 830 nm of x̄ȳz̄(λ) w(λ) s(λ), in f64.
fn sum_cmf_weighted(w: impl Fn(f32) -> f64, s: &Spectrum) -> [f64; 3] {
    let mut acc = [0.0f64; 3];
    for i in 0..CIE_SAMPLES {
        let lambda = CIE_LAMBDA_START + i as f32;
        let v = w(lambda) * s.eval(lambda) as f64;
        acc[0] += CIE_X[i] as f64 * v;
        acc[1] += CIE_Y[i] as f64 * v;
        acc[2] += CIE_Z[i] as f64 * v;
    }
    acc
}

/// XYZ of a reflectance spectrum under D65, normalized so that a constant 1 has Y = 1
/// (deterministic 1 nm sum).
pub fn reflectance_to_xyz(s: &Spectrum) -> Vec3 {
    let acc = sum_cmf_weighted(|l| d65(l) as f64, s);
    let norm: f64 = (0..CIE_SAMPLES)
        .map(|i| CIE_Y[i] as f64 * d65(CIE_LAMBDA_START + i as f32) as f64)
        .sum();
    Vec3::new(
        (acc[0] / norm) as f32,
        (acc[1] / norm) as f32,
        (acc[2] / norm) as f32,
    )
}

/// Linear sRGB of a reflectance spectrum seen under D65 (1 nm integration; a constant 1 gives
/// (1, 1, 1) up to the 1e-4 rounding of the standard matrices).
pub fn spectrum_to_linear_srgb(s: &Spectrum) -> Vec3 {
    linear_srgb_from_xyz(reflectance_to_xyz(s))
}

/// XYZ of an emission spectrum: Σ x̄ȳz̄ S / CIE_Y_INTEGRAL at 1 nm steps (no illuminant).
pub fn emission_to_xyz(s: &Spectrum) -> Vec3 {
    let acc = sum_cmf_weighted(|_| 1.0, s);
    let n = CIE_Y_INTEGRAL as f64;
    Vec3::new((acc[0] / n) as f32, (acc[1] / n) as f32, (acc[2] / n) as f32)
}

/// Linear sRGB of an emission spectrum (no illuminant): what a camera with the CIE observer sees
/// looking straight at an emitter of radiance `s`.
pub fn emission_to_linear_srgb(s: &Spectrum) -> Vec3 {
    linear_srgb_from_xyz(emission_to_xyz(s))
}

/// The sRGB transfer curve (linear → encoded), for 8-bit output. Negative input gives 0.
#[inline]
pub fn srgb_encode(x: f32) -> f32 {
    if x <= 0.0031308 {
        12.92 * x.max(0.0)
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse sRGB transfer curve (encoded → linear), for 8-bit input textures.
#[inline]
pub fn srgb_decode(x: f32) -> f32 {
    if x <= 0.04045 {
        x.max(0.0) / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN};

    #[test]
    fn d65_four_at_a_time_is_d65_normalized_bit_for_bit() {
        // Every 1/8 nm over the table and beyond it on both sides, and values that are not
        // wavelengths at all.
        let mut lambdas: Vec<f32> = (0..8 * 700).map(|k| 250.0 + k as f32 / 8.0).collect();
        lambdas.extend([f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0, 830.0, 300.0]);
        for c in lambdas.chunks(4) {
            let mut l = [555.0f32; 4];
            l[..c.len()].copy_from_slice(c);
            let four = d65_normalized4(l);
            for k in 0..4 {
                assert_eq!(four[k].to_bits(), d65_normalized(l[k]).to_bits(), "λ = {}", l[k]);
            }
        }
        let wl = crate::spectrum::SampledWavelengths::from_parts([400.0, 512.3, 640.7, 829.9], [1.0; 4]);
        assert_eq!(wl.d65(), d65_normalized4(wl.lambdas()));
    }

    #[test]
    fn luminance_is_the_y_of_the_xyz_conversion() {
        for rgb in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.3, 0.5, 0.9]] {
            let y = xyz_from_linear_srgb(Vec3::from(rgb)).y;
            assert!(
                (luminance(rgb) - y).abs() < 1e-7,
                "{rgb:?}: {} vs {y}",
                luminance(rgb)
            );
        }
        // D65 white has unit luminance.
        assert!((luminance([1.0; 3]) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn cie_table_sums_match_the_y_integral() {
        // pbrt-v4 util/spectrum_test.cpp (XYZ): Σx̄, Σȳ, Σz̄ over the 1 nm table / CIE_Y_integral
        // within 0.5 % of 1.
        let sx: f64 = CIE_X.iter().map(|&v| v as f64).sum();
        let sy: f64 = CIE_Y.iter().map(|&v| v as f64).sum();
        let sz: f64 = CIE_Z.iter().map(|&v| v as f64).sum();
        for s in [sx, sy, sz] {
            assert!((s / CIE_Y_INTEGRAL as f64 - 1.0).abs() < 5e-3, "sum {s}");
        }
        // The re-sum of ȳ is 106.85692 (pbrt-v4's CIE_Y_integral in util/spectrum.h is 106.856895).
        assert!((sy - 106.85692).abs() < 1e-4, "Σȳ = {sy}");
        assert_eq!(CIE_X.len(), 471);
    }

    #[test]
    fn cie_interpolation_hits_the_table_and_vanishes_outside() {
        assert_eq!(cie_xyz(360.0), Vec3::new(CIE_X[0], CIE_Y[0], CIE_Z[0]));
        assert_eq!(cie_xyz(555.0).y, CIE_Y[195]);
        assert_eq!(cie_xyz(830.0).x, CIE_X[470]);
        let mid = cie_xyz(555.5);
        assert!((mid.y - 0.5 * (CIE_Y[195] + CIE_Y[196])).abs() < 1e-7);
        assert_eq!(cie_xyz(359.9), Vec3::ZERO);
        assert_eq!(cie_xyz(830.1), Vec3::ZERO);
        assert_eq!(cie_xyz(f32::NAN), Vec3::ZERO);
    }

    #[test]
    fn matrices_are_inverse() {
        let p = LINEAR_SRGB_FROM_XYZ * XYZ_FROM_LINEAR_SRGB;
        assert!(p.abs_diff_eq(Mat3::IDENTITY, 2e-6), "{p:?}");
    }

    #[test]
    fn d65_white_point_and_unit_spectrum() {
        let w = reflectance_to_xyz(&Spectrum::constant(1.0));
        let (x, y) = (w.x / (w.x + w.y + w.z), w.y / (w.x + w.y + w.z));
        // CIE D65 chromaticity (0.31272, 0.32903) for the 2° observer.
        assert!(
            (x - 0.31272).abs() < 5e-5 && (y - 0.32903).abs() < 5e-5,
            "xy = ({x}, {y})"
        );
        assert!((w.y - 1.0).abs() < 1e-6);
        let rgb = spectrum_to_linear_srgb(&Spectrum::constant(1.0));
        assert!((rgb - Vec3::ONE).abs().max_element() < 2e-4, "{rgb}");
        // The normalized D65 emits unit luminance.
        let lum: f64 = (0..471)
            .map(|i| (cie_y(360.0 + i as f32) * d65_normalized(360.0 + i as f32)) as f64)
            .sum();
        assert!((lum / CIE_Y_INTEGRAL as f64 - 1.0).abs() < 1e-5, "{lum}");
        assert!((d65(560.0) - 100.0).abs() < 1e-4);
        assert!((d65(562.5) - 0.5 * (100.0 + 98.1671)).abs() < 1e-3);
    }

    #[test]
    fn visible_importance_sampling_estimates_the_y_integral() {
        // pbrt-v4 util/spectrum_test.cpp (SamplingPdfY): 1000 stratified u, importance-sampled ∫ȳ
        // within 0.1 %.
        let n = 1000;
        let mut y = 0.0f64;
        for k in 0..n {
            let wl = SampledWavelengths::sample_visible((k as f32 + 0.5) / n as f32);
            y += wl.estimate(SampledSpectrum::from_fn(|i| cie_y(wl.lambda(i)))) as f64;
        }
        let est = y / n as f64;
        assert!((est / CIE_Y_INTEGRAL as f64 - 1.0).abs() < 1e-3, "{est}");
    }

    #[test]
    fn visible_and_uniform_sampling_agree_on_the_cmf_sum() {
        // pbrt-v4 util/spectrum_test.cpp (SamplingPdfXYZ): 10000 stratified u, ∫(x̄ + ȳ + z̄) with the
        // visible pdf within 0.1 % of the uniform estimate.
        let n = 10_000;
        let g = |wl: &SampledWavelengths| SampledSpectrum::from_fn(|i| cie_xyz(wl.lambda(i)).element_sum());
        let (mut vis, mut uni) = (0.0f64, 0.0f64);
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            let wv = SampledWavelengths::sample_visible(u);
            let wu = SampledWavelengths::sample_uniform(u, LAMBDA_MIN, LAMBDA_MAX);
            vis += wv.estimate(g(&wv)) as f64;
            uni += wu.estimate(g(&wu)) as f64;
        }
        assert!((vis / uni - 1.0).abs() < 1e-3, "{vis} vs {uni}");
        // And the Y estimator alone agrees with the XYZ one.
        let wl = SampledWavelengths::sample_visible(0.3);
        let l = SampledSpectrum::new([0.2, 0.4, 0.6, 0.8]);
        assert!((y_from_sampled(l, &wl) - xyz_from_sampled(l, &wl).y).abs() < 1e-6);
    }

    #[test]
    fn constant_one_estimates_xyz_near_one() {
        // pbrt-v4 util/spectrum_test.cpp (XYZ): a constant 1 over 100 stratified uniform wavelength
        // sets → XYZ within 3.5 % of (1, 1, 1).
        let n = 100;
        let mut acc = Vec3::ZERO;
        for k in 0..n {
            let wl = SampledWavelengths::sample_uniform((k as f32 + 0.5) / n as f32, LAMBDA_MIN, LAMBDA_MAX);
            acc += xyz_from_sampled(SampledSpectrum::ONE, &wl);
        }
        acc /= n as f32;
        assert!((acc - Vec3::ONE).abs().max_element() < 0.035, "{acc}");
    }

    #[test]
    fn terminated_wavelengths_contribute_nothing() {
        let mut wl = SampledWavelengths::sample_visible(0.37);
        let l = SampledSpectrum::new([1.0, 5.0, 7.0, 11.0]);
        let full = xyz_from_sampled(l, &wl);
        wl.terminate_secondary();
        let hero = xyz_from_sampled(l, &wl);
        // Only the hero survives, with weight N/(N p₀) = 1/p₀.
        let expect = cie_xyz(wl.hero()) * (1.0 / wl.pdf()[0]) / (4.0 * CIE_Y_INTEGRAL);
        assert!((hero - expect).abs().max_element() < 1e-6 * expect.max_element().max(1.0));
        assert!(hero != full);
        // Garbage in terminated slots (NaN) must not leak into the colour.
        let nan = SampledSpectrum::new([1.0, f32::NAN, f32::INFINITY, f32::NAN]);
        assert!(xyz_from_sampled(nan, &wl).is_finite());
    }

    #[test]
    fn srgb_transfer_round_trips() {
        for i in 0..=1000 {
            let x = i as f32 / 1000.0;
            assert!((srgb_decode(srgb_encode(x)) - x).abs() < 1e-5);
        }
        assert!((srgb_encode(0.5) - 0.735357).abs() < 1e-5);
        assert!((srgb_encode(0.002) - 0.02584).abs() < 1e-6);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert_eq!(srgb_encode(-1.0), 0.0);
    }
}
