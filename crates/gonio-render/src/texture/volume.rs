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
//! gives a constant spectrum; three channels are linear RGB uplifted as an unbounded colour
//! (Mitsuba: per-voxel coefficients of rgb/(2·max) times 2·max; gonio interpolates the RGB and
//! uplifts the result, as for bilinear bitmaps). `raw` three-channel grids are not spectra
//! (Mitsuba refuses to evaluate them as such; the reader refuses them).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `filename` | string | (required) | the `.vol` grid (1 or 3 channels) |
//! | `filter_type` | string | `trilinear` | `trilinear` or `nearest` |
//! | `wrap_mode` | string | `clamp` | `clamp`, `repeat` or `mirror` outside [0, 1]³ |
//! | `raw` | boolean | false | no colour conversion of 3-channel data |
//! | `to_world` | transform | identity | places the unit cube of the grid |
//! | `accel` | boolean | true | accepted (GPU texture units in Mitsuba) |

use super::WrapMode;
use glam::{Affine3A, Vec3};
use gonio_core::Spectrum;
use std::sync::Arc;

/// A `<volume>` as built: a grid, or one value everywhere (`constvolume`, which its users turn
/// into their constant form: a medium's spectrum, a blend's number, a constant texture).
#[derive(Clone, Debug, PartialEq)]
pub enum Volume {
    /// `gridvolume`.
    Grid(Arc<GridVolume>),
    /// `constvolume`.
    Constant(Spectrum),
}

/// A grid of samples over the unit cube of its local space.
#[derive(Clone, Debug, PartialEq)]
pub struct GridVolume {
    /// Samples along x, y, z.
    pub res: [usize; 3],
    /// Channels per sample (1 or 3).
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
        let x = x.to_array();
        if !x.iter().all(|v| v.is_finite()) {
            return [0.0; 3];
        }
        let n = self.res.map(|r| r as i64);
        if !self.trilinear {
            let i: [usize; 3] = std::array::from_fn(|a| {
                let t = (x[a] * n[a] as f32).floor() as i64;
                self.wrap.wrap(t, n[a])
            });
            return self.at(i);
        }
        let mut lo = [0usize; 3];
        let mut hi = [0usize; 3];
        let mut f = [0f32; 3];
        for a in 0..3 {
            let t = x[a] * n[a] as f32 - 0.5;
            let i = t.floor();
            f[a] = t - i;
            lo[a] = self.wrap.wrap(i as i64, n[a]);
            hi[a] = self.wrap.wrap(i as i64 + 1, n[a]);
        }
        let mut v = [0f32; 3];
        for corner in 0..8 {
            let pick = |a: usize| corner >> a & 1 == 1;
            let idx = std::array::from_fn(|a| if pick(a) { hi[a] } else { lo[a] });
            let w: f32 = (0..3).map(|a| if pick(a) { f[a] } else { 1.0 - f[a] }).product();
            let s = self.at(idx);
            for c in 0..3 {
                v[c] += w * s[c];
            }
        }
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
