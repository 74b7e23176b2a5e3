//! The coarse luminance table of an `envmap` that resampled next-event estimation weighs its
//! candidates by (`integrator/resampled.rs`): 128 × 128 octahedral cells over world directions,
//! each the mean luminance of the texels whose centres it holds plus a tenth of the largest the
//! lookup weighs anywhere in it, so that no direction's light is more than ten times what the
//! table says (the mean alone leaves the bilinear fringe of a lone bright texel, a sun, in cells
//! that hold none of its weight; the bound alone is as wide as a glossy lobe). 64 KB, built
//! before rendering where it may serve (otherwise on first use): 45–53 ms for a 512 × 256 map,
//! 0.5–0.7 s for 4096 × 2048 (a release build, one thread).

use super::EnvMapLight;
use crate::emitter::envmap_product::{octahedral_cell_of, octahedral_centre_of};
use glam::{Vec2, Vec3};
use gonio_core::color::luminance;
use std::f32::consts::{PI, TAU};

/// Octahedral cells per side of [`EnvMapLight::resampling_luminance`]'s table (128 × 128 cells,
/// 1.6° wide on average, 0.9° at the narrowest).
const RESAMPLING_CELLS: usize = 128;

/// The largest angle (radians) between the points at which
/// [`EnvMapLight::resampling_luminance`]'s table is filled from one patch of the map (under half
/// the narrowest cell's side, 0.0156).
const RESAMPLING_PROBE_SPACING: f32 = 0.007;

/// The share of a cell's bound in [`EnvMapLight::resampling_luminance`]'s table: the light in
/// any direction is at most 1/share times the table (10).
const RESAMPLING_BOUND_SHARE: f32 = 0.1;

/// [`EnvMapLight::resampling_luminance`] with its table at hand
/// ([`EnvMapLight::resampling_lookup`]): what a lane kernel calls lane by lane.
#[derive(Clone, Copy, Debug)]
pub struct ResamplingLookup<'a> {
    table: &'a [f32],
    floor: f32,
}

impl ResamplingLookup<'_> {
    /// [`EnvMapLight::resampling_luminance`] of world direction `dir`.
    #[inline(always)]
    pub fn luminance(&self, dir: Vec3) -> f32 {
        self.table[octahedral_cell_of(dir, RESAMPLING_CELLS)] + self.floor
    }
}

impl EnvMapLight {
    /// A coarse stand-in for the luminance arriving from world direction `dir` (× the scale;
    /// module docs): the table's cell, at least a tenth of the luminance the lookup gives
    /// anywhere in it, plus 10⁻³ of the map's mean, so that no direction of a map that is not
    /// black has none. Resampled next-event estimation weighs its candidates by it (any function
    /// positive where the light is keeps that estimator unbiased; the closer to L, the less
    /// noise).
    #[inline]
    pub fn resampling_luminance(&self, dir: Vec3) -> f32 {
        self.resampling_lookup().luminance(dir)
    }

    /// [`Self::resampling_luminance`] for many lookups: the table (built on first use) and the
    /// floor every entry adds.
    #[inline]
    pub fn resampling_lookup(&self) -> ResamplingLookup<'_> {
        ResamplingLookup {
            table: self
                .resampling_table
                .get_or_init(|| self.build_resampling_table()),
            floor: 1e-3 * self.mean_luminance,
        }
    }

    /// Builds [`Self::resampling_luminance`]'s table now, if not yet built (it is otherwise built
    /// by its first use, while the render's other threads wait for it).
    pub fn prepare_resampling(&self) {
        self.resampling_lookup();
    }

    /// [`Self::resampling_luminance`]'s table (module docs): per octahedral cell, the mean
    /// luminance of the texels whose centres fall in it (in a cell that holds none, the lookup
    /// at its centre; sharp, but a lone bright texel's bilinear fringe reaches cells that hold
    /// none of it) plus [`RESAMPLING_BOUND_SHARE`] of a bound of the luminance the lookup gives
    /// anywhere in the cell, so that the table is never below a tenth of the light it stands
    /// for.
    ///
    /// The lookup between four neighbouring texel centres (a patch; beyond the first and last
    /// rows' centres, the row alone) weighs those four: its luminance is at most the largest of
    /// theirs (a weighted mean), or with Mitsuba's lookup, which multiplies the interpolated
    /// shapes by the interpolated scales, the largest shape's luminance times the largest
    /// scale. Each patch's bound is raised into every cell a grid of points over the patch falls
    /// in, spaced at most [`RESAMPLING_PROBE_SPACING`] apart (a fine map's patch is one point
    /// per corner; near the poles a coarse map's spans many cells), and the bounds are then
    /// dilated by one cell on the grid, for the slivers between points. One thread builds it,
    /// two rows of texel cells at a time.
    fn build_resampling_table(&self) -> Box<[f32]> {
        let (w, h, n) = (self.width, self.height, RESAMPLING_CELLS);
        // Row j's v (its centre).
        let row_v = |j: usize| {
            if self.mitsuba_lookup {
                j as f32 / (h - 1).max(1) as f32
            } else {
                (j as f32 + 0.5) / h as f32
            }
        };
        // A texel's luminance, split into the factors a patch's bound takes the largest of:
        // (luminance, 1), or with Mitsuba's lookup (shape's luminance, scale 2·max(rgb)).
        let parts = |i: usize, j: usize| {
            let rgb = self.rgb[j * w + i];
            let l = luminance(rgb);
            let f = 2.0 * rgb[0].max(rgb[1]).max(rgb[2]);
            if !self.mitsuba_lookup {
                (l, 1.0)
            } else if f > 0.0 {
                (l / f, f)
            } else {
                (0.0, 0.0)
            }
        };
        // The cells of row j's texel centres, accumulating the cells' means.
        let (mut lit, mut solid) = (vec![0.0f64; n * n], vec![0.0f64; n * n]);
        let mut row_cells = |j: usize, cells: &mut Vec<u32>| {
            cells.clear();
            let sin_theta = (PI * row_v(j)).sin().max(0.0) as f64;
            for i in 0..w {
                let dir = self.uv_to_dir(Vec2::new((i as f32 + 0.5) / w as f32, row_v(j)));
                let k = octahedral_cell_of(dir, n);
                cells.push(k as u32);
                lit[k] += luminance(self.rgb[j * w + i]) as f64 * sin_theta;
                solid[k] += sin_theta;
            }
        };
        let (mut upper, mut lower) = (Vec::with_capacity(w), Vec::with_capacity(w));
        row_cells(0, &mut lower);
        // The bounds, patch row by patch row: −1 (above the first centre, the first row alone)
        // to h − 1 (below the last).
        let mut bound = vec![0.0f32; n * n];
        for j in -1..h as isize {
            let (j0, j1) = (
                (j.max(0) as usize).min(h - 1),
                ((j + 1).max(0) as usize).min(h - 1),
            );
            if j >= 0 && j1 > j0 {
                std::mem::swap(&mut upper, &mut lower);
                row_cells(j1, &mut lower);
            }
            let v0 = if j < 0 { 0.0 } else { row_v(j0) };
            let v1 = if j + 1 >= h as isize { 1.0 } else { row_v(j1) };
            if !(v1 > v0) {
                continue;
            }
            let sin_max = if v0 <= 0.5 && v1 >= 0.5 {
                1.0
            } else {
                (PI * v0).sin().max((PI * v1).sin())
            };
            let steps_v = ((PI * (v1 - v0) / RESAMPLING_PROBE_SPACING).ceil() as usize).max(1);
            let steps_u = ((TAU / w as f32 * sin_max / RESAMPLING_PROBE_SPACING).ceil() as usize).max(1);
            // A patch between four centres and finer than the spacing: its corners' cells.
            let corners_only = steps_u == 1 && steps_v == 1 && j >= 0 && j1 > j0;
            for i in 0..w {
                let i1 = (i + 1) % w;
                let corners = [parts(i, j0), parts(i1, j0), parts(i, j1), parts(i1, j1)];
                let l = corners.iter().map(|c| c.0).fold(0.0, f32::max)
                    * corners.iter().map(|c| c.1).fold(0.0, f32::max);
                if !(l > 0.0) {
                    continue;
                }
                if corners_only {
                    for k in [upper[i], upper[i1], lower[i], lower[i1]] {
                        bound[k as usize] = bound[k as usize].max(l);
                    }
                    continue;
                }
                for b in 0..=steps_v {
                    let v = v0 + (v1 - v0) * b as f32 / steps_v as f32;
                    for a in 0..=steps_u {
                        let u = (i as f32 + 0.5 + a as f32 / steps_u as f32) / w as f32;
                        let k = octahedral_cell_of(self.uv_to_dir(Vec2::new(u.fract(), v)), n);
                        bound[k] = bound[k].max(l);
                    }
                }
            }
        }
        (0..n * n)
            .map(|k| {
                // The bound dilated by one cell, for the slivers between points.
                let (x, y) = (k % n, k / n);
                let mut dilated = 0.0f32;
                for yy in y.saturating_sub(1)..=(y + 1).min(n - 1) {
                    for xx in x.saturating_sub(1)..=(x + 1).min(n - 1) {
                        dilated = dilated.max(bound[yy * n + xx]);
                    }
                }
                // A cell finer than the texels may hold no centre: the lookup at its own.
                let mean = if solid[k] > 0.0 {
                    (lit[k] / solid[k]) as f32
                } else {
                    luminance(self.lookup_rgb(self.dir_to_uv(octahedral_centre_of(k, n))))
                };
                (mean + RESAMPLING_BOUND_SHARE * dilated) * self.scale
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::uplift_emission_texel;
    use glam::Affine3A;
    use gonio_core::warp;

    /// The resampling table is at least a tenth of the light in every direction (within
    /// rounding): resampled next-event estimation divides by it, and a table far below the
    /// light, as a cell's mean alone is in the bilinear fringe of a lone bright texel, makes
    /// fireflies. Checked for a sun-like texel (blue, 10⁴, beside a white one of 10³, on a sky
    /// of 10⁻²) in a map finer than the table's cells (1024 × 512) and one coarser (16 × 8), in
    /// the middle, at the seam and at a pole, over directions everywhere and densely around the
    /// texel, with both lookups (Mitsuba's, shapes times scales, exceeds its texels' largest
    /// luminance between the blue and the white); and a constant map's table is its luminance,
    /// plus the bound's tenth, plus the floor's 10⁻³.
    #[test]
    fn the_resampling_table_bounds_the_light() {
        let uplift = uplift_emission_texel;
        let spread = |k: usize| Vec2::new((k as f32 * 0.754_877_7).fract(), (k as f32 * 0.569_840_3).fract());
        let constant = EnvMapLight::new(16, 8, vec![[0.5; 3]; 128], 2.0, Affine3A::IDENTITY, uplift).unwrap();
        let l = luminance([0.5; 3]) * 2.0;
        for k in 0..2000 {
            let got = constant.resampling_luminance(warp::square_to_uniform_sphere(spread(k)));
            assert!((got - l * 1.101).abs() <= 1e-5 * l, "{got} against {l}");
        }
        for (w, h) in [(1024, 512), (16, 8)] {
            for (bi, bj) in [(w / 5, h / 3), (w - 1, h / 2), (w / 3, 0)] {
                let mut rgb = vec![[0.01f32; 3]; w * h];
                rgb[bj * w + bi] = [0.0, 0.0, 1e4];
                rgb[bj * w + (bi + 1) % w] = [1e3; 3];
                let bilinear = EnvMapLight::new(w, h, rgb.clone(), 1.5, Affine3A::IDENTITY, uplift).unwrap();
                let mitsuba = bilinear.clone().with_mitsuba_lookup();
                for map in [&bilinear, &mitsuba] {
                    let around = (0..4000).map(|k| {
                        // Within two texels of the bright one.
                        let o = (spread(k) - Vec2::splat(0.5)) * 4.0;
                        Vec2::new(
                            (bi as f32 + 0.5 + o.x) / w as f32,
                            (bj as f32 + 0.5 + o.y) / h as f32,
                        )
                        .rem_euclid(Vec2::ONE)
                    });
                    let everywhere =
                        (0..4000).map(|k| map.dir_to_uv(warp::square_to_uniform_sphere(spread(k))));
                    for uv in around.chain(everywhere) {
                        // The lookup's luminance: Σ wᵢ Lᵢ, or Mitsuba's (Σ wᵢ Lᵢ/fᵢ)(Σ wᵢ fᵢ).
                        let (mut shape, mut scale, mut plain) = (0.0f32, 0.0f32, 0.0f32);
                        for (t, wt) in map.bilinear(uv) {
                            let (lt, ft) = (luminance(rgb[t]), 2.0 * rgb[t].into_iter().fold(0.0, f32::max));
                            plain += wt * lt;
                            shape += wt * lt / ft;
                            scale += wt * ft;
                        }
                        let light = if map.mitsuba_lookup { shape * scale } else { plain } * 1.5;
                        let table = map.resampling_luminance(map.uv_to_dir(uv));
                        assert!(
                            table >= 0.1 * light * (1.0 - 1e-4),
                            "{w} × {h}, bright texel ({bi}, {bj}), Mitsuba's lookup {}: {table} below a \
                             tenth of the light {light} at {uv}",
                            map.mitsuba_lookup
                        );
                    }
                }
            }
        }
    }
}
