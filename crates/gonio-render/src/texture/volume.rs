//! `gridvolume` (Mitsuba 3 `src/volumes/grid.cpp`) and the `volume` texture that evaluates it at
//! a surface point (`src/textures/volume.cpp`).
//!
//! The grid (a `.vol` file, read by [`crate::geometry::sdfgrid::read_vol`]) spans the unit cube
//! of its local space; `to_world` places it (the bounding box the file states is ignored, as in
//! Mitsuba unless `use_grid_bbox`). At a world point p, x = to_world⁻¹(p) ∈ [0, 1]³ and with
//! n samples along an axis:
//!
//! * `trilinear`: sample centres at (i + ½)/n; t = x·n − ½, i = ⌊t⌋, f = t − i, and the value
//!   is Σ over the 8 corners of Π (f or 1 − f) · v[i or i + 1] (per axis);
//! * `nearest`: v[⌊x·n⌋];
//!
//! indices outside [0, n) are mapped by `wrap_mode` (`clamp`, `repeat`, `mirror`). One channel
//! gives a constant spectrum. Three channels are linear RGB turned into spectra as Mitsuba
//! 3.9.1's spectral variants do it ([`GridVolume::spectrum_local`]): each sample is stored as
//! its scale s = 2·max(rgb) and the sigmoid spectrum S of rgb/s; `nearest` gives s·S(λ),
//! `trilinear` the interpolated spectra times the interpolated scales,
//! (Σ wᵢ Sᵢ(λ))·(Σ wᵢ sᵢ), not the spectrum of the interpolated colour (the form checked
//! against Mitsuba's `gridvolume.eval` between two voxels of different colours).
//! Media read it so (extinction, and albedo clamped to [0, 1] per wavelength where Mitsuba's
//! saturated colours exceed 1); the `volume` texture of a surface, whose value is one spectrum,
//! uplifts the interpolated colour instead (equal at sample centres and with `nearest`). `raw`
//! three-channel grids are not spectra (Mitsuba refuses to evaluate them as such; the reader
//! refuses them).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `filename` | string | (required) | the `.vol` grid (1 or 3 channels; 6 for an `sggx` phase function's matrix) |
//! | `filter_type` | string | `trilinear` | `trilinear` or `nearest` |
//! | `wrap_mode` | string | `clamp` | `clamp`, `repeat` or `mirror` outside [0, 1]³ |
//! | `raw` | boolean | false | no colour conversion of 3-channel data |
//! | `to_world` | transform | identity | places the unit cube of the grid |
//! | `accel` | boolean | true | accepted (GPU texture units in Mitsuba) |

use super::WrapMode;
use glam::{Affine3A, Vec3, Vec4};
use gonio_core::rgb2spec::{RgbSigmoid, srgb_to_sigmoid};
use gonio_core::{SampledSpectrum, SampledWavelengths, Spectrum};
use std::sync::Arc;

/// A `<volume>` as built: a grid, or one value everywhere (`constvolume`, which its users turn
/// into their constant form: a medium's spectrum, a blend's number, a constant texture).
#[derive(Clone, Debug, PartialEq)]
pub enum Volume {
    /// `gridvolume`.
    Grid(Arc<GridVolume>),
    /// `constvolume`: the value, and its `to_world` (whose unit cube's axis-aligned bounds are
    /// where a heterogeneous medium given it exists, as in Mitsuba).
    Constant(Spectrum, Affine3A),
}

/// A grid of samples over the unit cube of its local space.
#[derive(Clone, Debug, PartialEq)]
pub struct GridVolume {
    /// Samples along x, y, z.
    pub res: [usize; 3],
    /// Channels per sample (1 or 3; 6 for an `sggx` phase function's matrix).
    pub channels: usize,
    /// Samples, x fastest, channels interleaved.
    pub data: Vec<f32>,
    /// Trilinear (true) or nearest lookups.
    pub trilinear: bool,
    /// Indices outside the grid.
    pub wrap: WrapMode,
    /// Three channels read without colour conversion.
    pub raw: bool,
    /// World to the grid's local space.
    pub to_local: Affine3A,
    /// Three-channel colour grids: each sample's sigmoid spectrum of rgb/s and its scale
    /// s = 2·max(rgb) ([`spectral_samples`]), in `data`'s order; empty otherwise.
    pub spectra: Vec<(RgbSigmoid, f32)>,
}

/// Mitsuba's stored form of colour samples (`channels` = 3, not raw): for each, the sigmoid of
/// rgb/s with s = 2·max(rgb) (negative and non-finite components read as 0), and s. Empty for
/// other grids.
pub fn spectral_samples(data: &[f32], channels: usize, raw: bool) -> Vec<(RgbSigmoid, f32)> {
    if channels != 3 || raw {
        return Vec::new();
    }
    data.chunks_exact(3)
        .map(|c| {
            let rgb = [c[0], c[1], c[2]].map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
            let s = 2.0 * rgb[0].max(rgb[1]).max(rgb[2]);
            if s > 0.0 {
                (srgb_to_sigmoid(rgb.map(|v| v / s)), s)
            } else {
                (RgbSigmoid::constant(0.0), 0.0)
            }
        })
        .collect()
}

impl GridVolume {
    /// The sample (i, j, k), channel by channel (up to 3).
    fn at(&self, i: [usize; 3]) -> [f32; 3] {
        let idx = ((i[2] * self.res[1] + i[1]) * self.res[0] + i[0]) * self.channels;
        let s = &self.data[idx..idx + self.channels];
        if self.channels == 1 {
            [s[0]; 3]
        } else {
            [s[0], s[1], s[2]]
        }
    }

    /// The channels at the world point `p` (one channel repeated three times).
    pub fn eval(&self, p: Vec3) -> [f32; 3] {
        self.eval_local(self.to_local.transform_point3(p))
    }

    /// [`GridVolume::eval`] at a point `x` already in the grid's space ([0, 1]³ inside).
    pub fn eval_local(&self, x: Vec3) -> [f32; 3] {
        let mut v = [0f32; 3];
        self.for_each_weight(x, |i, w| {
            let s = self.at(i);
            for c in 0..3 {
                v[c] += w * s[c];
            }
        });
        v
    }

    /// The spectrum at a point `x` in the grid's space: one channel as a constant, three as
    /// Mitsuba's spectral variants read them (the module's documentation).
    pub fn spectrum_local(&self, x: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if self.spectra.is_empty() {
            return SampledSpectrum::splat(self.eval_local(x)[0]);
        }
        let lambda = Vec4::from_array(wl.lambdas());
        let (mut spectrum, mut scale) = (Vec4::ZERO, 0.0);
        self.for_each_weight(x, |i, w| {
            let idx = (i[2] * self.res[1] + i[1]) * self.res[0] + i[0];
            let (sigmoid, s) = self.spectra[idx];
            spectrum += w * sigmoid.eval4(lambda);
            scale += w * s;
        });
        SampledSpectrum(spectrum * scale)
    }

    /// Calls `f(sample, weight)` for the samples a lookup at `x` (grid space) combines: one of
    /// weight 1 (`nearest`) or the eight trilinear corners; none for a non-finite `x`.
    fn for_each_weight(&self, x: Vec3, mut f: impl FnMut([usize; 3], f32)) {
        let x = x.to_array();
        if !x.iter().all(|v| v.is_finite()) {
            return;
        }
        let n = self.res.map(|r| r as i64);
        if !self.trilinear {
            let i = std::array::from_fn(|a| self.wrap.wrap((x[a] * n[a] as f32).floor() as i64, n[a]));
            return f(i, 1.0);
        }
        let mut lo = [0usize; 3];
        let mut hi = [0usize; 3];
        let mut t = [0f32; 3];
        for a in 0..3 {
            let u = x[a] * n[a] as f32 - 0.5;
            let i = u.floor();
            t[a] = u - i;
            lo[a] = self.wrap.wrap(i as i64, n[a]);
            hi[a] = self.wrap.wrap(i as i64 + 1, n[a]);
        }
        for corner in 0..8 {
            let pick = |a: usize| corner >> a & 1 == 1;
            let idx = std::array::from_fn(|a| if pick(a) { hi[a] } else { lo[a] });
            let w: f32 = (0..3).map(|a| if pick(a) { t[a] } else { 1.0 - t[a] }).product();
            f(idx, w);
        }
    }

    /// The six channels at a point `x` in the grid's space (a six-channel grid: an `sggx`
    /// phase function's matrix, interpolated entry by entry as Mitsuba's `eval_6` does).
    pub fn eval6_local(&self, x: Vec3) -> [f32; 6] {
        debug_assert_eq!(self.channels, 6);
        let mut v = [0f32; 6];
        self.for_each_weight(x, |i, w| {
            let idx = ((i[2] * self.res[1] + i[1]) * self.res[0] + i[0]) * 6;
            for (c, s) in v.iter_mut().zip(&self.data[idx..idx + 6]) {
                *c += w * s;
            }
        });
        v
    }

    /// The largest value (for bounds).
    pub fn max(&self) -> f32 {
        self.data.iter().copied().fold(0.0, f32::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gonio_core::spectra::RgbKind;

    /// Two colour samples along x (0.8, 0.1, 0) and (0, 0.3, 0.6), read at four wavelengths by
    /// Mitsuba 3.9.1 `scalar_spectral` (`gridvolume.eval`, x = 0.25, 0.5, 0.6, 0.75; the first
    /// and last are the two sample centres): the interpolated spectra times the interpolated
    /// scales, not the spectrum of the interpolated colour (Mitsuba's uplift of (0.24, 0.24,
    /// 0.42) at x = 0.6: 0.4065, 0.2658, 0.2337, 0.3141, which the test also tells apart).
    #[test]
    fn colour_grids_read_as_mitsuba_reads_them() {
        let data = vec![0.8, 0.1, 0.0, 0.0, 0.3, 0.6];
        let grid = |trilinear| GridVolume {
            res: [2, 1, 1],
            channels: 3,
            spectra: spectral_samples(&data, 3, false),
            data: data.clone(),
            trilinear,
            wrap: WrapMode::Clamp,
            raw: false,
            to_local: Affine3A::IDENTITY,
        };
        let wl = SampledWavelengths::from_parts([450.0, 520.0, 600.0, 680.0], [1.0; 4]);
        let mitsuba_trilinear = [
            (0.25, [0.021224072, 0.067321204, 0.45384845, 1.3132418]),
            (0.5, [0.34624627, 0.25438297, 0.2666507, 0.5930005]),
            (0.6, [0.45004115, 0.31356955, 0.20220892, 0.3493908]),
            (0.75, [0.57764697, 0.38559416, 0.11672914, 0.031640887]),
        ];
        let mitsuba_nearest = [(0.25, mitsuba_trilinear[0].1), (0.6, mitsuba_trilinear[3].1)];
        // The reading this replaced, the interpolated colour uplifted, is 10 % lower at 680 nm.
        let g = grid(true);
        let old =
            crate::texture::uplift(g.eval_local(Vec3::new(0.6, 0.5, 0.5)), RgbKind::Unbounded).sample(&wl)[3];
        let new = g.spectrum_local(Vec3::new(0.6, 0.5, 0.5), &wl)[3];
        assert!(
            (old - 0.3141).abs() < 2e-3 && (new - old).abs() > 0.03,
            "{old} vs {new}"
        );
        for (trilinear, cases) in [(true, &mitsuba_trilinear[..]), (false, &mitsuba_nearest[..])] {
            let g = grid(trilinear);
            for &(x, want) in cases {
                let got = g.spectrum_local(Vec3::new(x, 0.5, 0.5), &wl);
                for k in 0..4 {
                    // The sigmoid table's interpolation: a few 1e-4 from Mitsuba's.
                    assert!(
                        (got[k] - want[k]).abs() <= 2e-3 * want[k].max(0.05),
                        "trilinear {trilinear} x {x} λ {}: {} vs Mitsuba {}",
                        wl.lambda(k),
                        got[k],
                        want[k]
                    );
                }
            }
        }
    }

    /// A 2 × 2 × 2 grid with v = x-index + 2·y-index + 4·z-index.
    fn cube(trilinear: bool, wrap: WrapMode) -> GridVolume {
        GridVolume {
            res: [2, 2, 2],
            channels: 1,
            data: (0..8).map(|i| i as f32).collect(),
            trilinear,
            wrap,
            raw: false,
            to_local: Affine3A::IDENTITY,
            spectra: Vec::new(),
        }
    }

    #[test]
    fn trilinear_lookups_hit_the_samples_and_interpolate_between_them() {
        let g = cube(true, WrapMode::Clamp);
        // Sample centres at ¼ and ¾.
        assert_eq!(g.eval(Vec3::new(0.25, 0.25, 0.25))[0], 0.0);
        assert_eq!(g.eval(Vec3::new(0.75, 0.75, 0.75))[0], 7.0);
        assert_eq!(g.eval(Vec3::new(0.75, 0.25, 0.75))[0], 5.0);
        // The value is linear in each axis between the centres: 1·fx + 2·fy + 4·fz.
        let p = Vec3::new(0.25 + 0.5 * 0.3, 0.25 + 0.5 * 0.6, 0.25 + 0.5 * 0.9);
        assert!((g.eval(p)[0] - (0.3 + 2.0 * 0.6 + 4.0 * 0.9)).abs() < 1e-5);
        // Clamped beyond the centres and outside the cube.
        assert_eq!(g.eval(Vec3::new(0.0, 0.0, 0.0))[0], 0.0);
        assert_eq!(g.eval(Vec3::new(5.0, -3.0, 0.75))[0], 5.0);
    }

    #[test]
    fn wrap_modes_nearest_lookups_and_to_world() {
        // Repeat: half-way between the last centre (¾) and the next tile's first (1¼) along x.
        let g = cube(true, WrapMode::Repeat);
        assert!((g.eval(Vec3::new(1.0, 0.25, 0.25))[0] - 0.5).abs() < 1e-6);
        // Mirror: the sample beyond the edge is the edge sample itself.
        let g = cube(true, WrapMode::Mirror);
        assert_eq!(g.eval(Vec3::new(1.0, 0.25, 0.25))[0], 1.0);
        // Nearest: the cell containing the point.
        let g = cube(false, WrapMode::Clamp);
        assert_eq!(g.eval(Vec3::new(0.6, 0.4, 0.9))[0], 5.0);
        // to_world = scale 2, translate (1, 0, 0): world (2.5, 1.5, 0.5) is local (0.75, 0.75, 0.25).
        let mut g = cube(true, WrapMode::Clamp);
        let to_world =
            Affine3A::from_scale_rotation_translation(Vec3::splat(2.0), glam::Quat::IDENTITY, Vec3::X);
        g.to_local = to_world.inverse();
        assert!((g.eval(Vec3::new(2.5, 1.5, 0.5))[0] - 3.0).abs() < 1e-5);
    }
}
