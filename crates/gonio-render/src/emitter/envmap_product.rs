//! Next-event sampling of an environment map times the clamped cosine at the shading point
//! (beyond Mitsuba; the `envmap` parameter `product_sampling`).
//!
//! An environment map sampled ∝ its radiance ignores the cos θ of the reflection equation: a
//! floor under a sky spends samples on bright directions near its horizon, and on directions
//! below it where the map is bright there too, which contribute nothing; the cosine's
//! variation over the bright parts is noise. Drawing directions ∝ L(ω)·max(0, n·ω) for the
//! shading normal n removes most of it. On Mitsuba's material preview (`museum.exr` over a
//! diffuse floor), for an unoccluded floor point, one light sample and one cosine-weighted BSDF
//! sample combined by the power heuristic have a relative variance of 0.29 with the compensated
//! density of MIS compensation alone and 0.05 with the tables below (quadrature over the map's
//! texels; `bench/RESULTS.md`).
//!
//! # The tables
//!
//! The sphere of shading normals is cut into the [`CELLS`] × [`CELLS`] cells of the octahedral
//! map (Meyer et al. 2010; centres n_k), the image into tiles of `tile_w × tile_h` texels (at
//! most 64 × 32 tiles). For a normal in cell k a tile T is drawn with probability
//!
//! `P_k(T) ∝ max(0, W(T) − c_k·S(T)) · max(0, n_k·d_T)`,
//!
//! with w(t) = L(t)·sin θ the light's own weight of texel t (its luminance, × sin θ for the
//! texel's solid angle), W(T) = Σ w(t) and S(T) = Σ sin θ over the tile's texels, d_T the
//! direction of the tile's centre and c_k the compensation: half the cosine-weighted mean
//! luminance of the cell's hemisphere, c_k = ½ Σ W(T)·cos_T / Σ S(T)·cos_T (0 without MIS
//! compensation). It is MIS compensation (Karlík et al. 2019) made local: tiles dimmer than
//! c_k are left to BSDF sampling. The map's *global* mean, which `mis_compensation` subtracts
//! without the cosine, is a reference that suits some normals and fails others: under
//! `museum.exr`, a surface facing the map's dim half gets two thirds of its light from texels
//! below the global mean, and the relative variance of one light and one BSDF sample at an
//! unoccluded point is 0.25 with the global mean, 0.12 with none and 0.05 with c_k; facing the
//! bright half (the preview's floor) 0.02, 0.15 and 0.05; c_k keeps it at 0.05–0.07 over five
//! normals (quadrature over the map's texels, `bench/RESULTS.md`). A texel t of T is then
//! drawn with probability w(t)/W(T), and a point of the texel uniformly. The density at image
//! coordinates (u, v) in texel t of tile T is
//!
//! `p(u, v) = P_k(T) · w(t)/W(T) · W·H`
//!
//! (W × H texels), per solid angle p(u, v)/(2π² sin θ) as for the map's own density. A cell's
//! table is built the first time a normal in it asks (most scenes see few normals); it is a
//! pure function of the cell, so images do not depend on which thread built it.
//!
//! # Where it may be used
//!
//! Only where the BSDF is sampled too and weighed against the light by MIS
//! ([`super::LightRef::mis`]), and only reflects ([`super::LightRef::hemisphere`]). The density
//! is zero for tiles below the horizon of the cell's centre, which a normal elsewhere in the
//! cell may still see a little of; BSDF sampling covers those directions, and the MIS weight
//! gives it their whole contribution, so the estimate stays unbiased. Maps smaller than 32 × 16
//! texels have no tables (a tile would be too wide for the cosine at its centre).
//!
//! # Memory
//!
//! Four bytes per texel (the texels' CDFs within their tiles) and at most 1024 × (2049 + 33) × 4
//! bytes (8.5 MB) for the cells' tables (each CDF and its every 64th entry, the coarse level of
//! its search), whatever the map's size.

use glam::{Vec2, Vec3};
use gonio_core::rng::ONE_MINUS_EPSILON;
use std::sync::OnceLock;

/// Normal cells per side of the octahedral map (32 × 32 = 1024 cells of ≈ 0.012 sr).
pub const CELLS: usize = 32;
const MAX_TILES_X: usize = 64;
/// The smallest map with product tables (texels of at most 11.25° × 11.25°).
pub const MIN_WIDTH: usize = 32;
/// See [`MIN_WIDTH`].
pub const MIN_HEIGHT: usize = 16;
const MAX_TILES_Y: usize = 32;

/// The product tables of one environment map (module docs).
#[derive(Clone, Debug)]
pub struct CosineProduct {
    width: usize,
    height: usize,
    tile_w: usize,
    tile_h: usize,
    tiles_x: usize,
    /// W(T) per tile, row-major over tiles.
    tile_mass: Vec<f32>,
    /// S(T) per tile (Σ sin θ over its texels).
    tile_solid: Vec<f32>,
    /// The compensation's fraction of the hemisphere's mean (½, or 0 without compensation).
    compensation: f32,
    /// World direction of each tile's centre.
    tile_dir: Vec<Vec3>,
    /// Per tile, the CDF of its texels (row-major inside the tile; `tile_w·tile_h + 1` entries
    /// from 0 to 1).
    texel_cdf: Vec<f32>,
    /// Per normal cell, the CDF over tiles (`tiles + 1` entries), empty when no tile is lit
    /// above the cell centre's horizon.
    cells: Vec<OnceLock<Box<[f32]>>>,
}

impl CosineProduct {
    /// The tables for a `width × height` map whose texel weights (luminance × sin θ, row-major)
    /// are `weights`, compensated by `compensation` × each cell's mean (module docs: ½ with MIS
    /// compensation, 0 without); `uv_to_dir` maps image coordinates to world directions. `None`
    /// when no weight is positive, or when the map is smaller than [`MIN_WIDTH`] ×
    /// [`MIN_HEIGHT`] texels: a texel, and so a tile, would span more than 11.25°, too much for
    /// the cosine at its centre to stand for it (a 1 × 1 map is a constant environment whose one
    /// tile would face one way); the light's own density serves there.
    pub fn new(
        weights: &[f32],
        width: usize,
        height: usize,
        compensation: f32,
        uv_to_dir: impl Fn(Vec2) -> Vec3,
    ) -> Option<Self> {
        if width < MIN_WIDTH
            || height < MIN_HEIGHT
            || weights.len() != width * height
            || !weights.iter().any(|&w| w > 0.0)
        {
            return None;
        }
        let tile_w = width.div_ceil(MAX_TILES_X);
        let tile_h = height.div_ceil(MAX_TILES_Y);
        let (tiles_x, tiles_y) = (width.div_ceil(tile_w), height.div_ceil(tile_h));
        let per_tile = tile_w * tile_h;
        let tiles = tiles_x * tiles_y;
        let mut tile_mass = Vec::with_capacity(tiles);
        let mut tile_solid = Vec::with_capacity(tiles);
        let mut tile_dir = Vec::with_capacity(tiles);
        let mut texel_cdf = Vec::with_capacity(tiles * (per_tile + 1));
        let mut cum = Vec::with_capacity(per_tile + 1);
        for ty in 0..tiles_y {
            for tx in 0..tiles_x {
                let (x0, y0) = (tx * tile_w, ty * tile_h);
                let (x1, y1) = ((x0 + tile_w).min(width), (y0 + tile_h).min(height));
                cum.clear();
                cum.push(0.0f64);
                let mut sum = 0.0f64;
                let mut solid = 0.0f64;
                for j in 0..tile_h {
                    if y0 + j < height {
                        let theta = std::f64::consts::PI * ((y0 + j) as f64 + 0.5) / height as f64;
                        solid += theta.sin() * (x1 - x0) as f64;
                    }
                    for i in 0..tile_w {
                        let (x, y) = (x0 + i, y0 + j);
                        let w = if x < width && y < height {
                            weights[y * width + x]
                        } else {
                            0.0
                        };
                        if w.is_finite() && w > 0.0 {
                            sum += w as f64;
                        }
                        cum.push(sum);
                    }
                }
                tile_mass.push(sum as f32);
                tile_solid.push(solid as f32);
                if sum > 0.0 {
                    texel_cdf.extend(cum[..per_tile].iter().map(|&c| (c / sum) as f32));
                    texel_cdf.push(1.0);
                } else {
                    // Never drawn (its mass is zero); a valid CDF all the same.
                    texel_cdf.extend((0..=per_tile).map(|k| k as f32 / per_tile as f32));
                }
                let centre = Vec2::new(
                    0.5 * (x0 + x1) as f32 / width as f32,
                    0.5 * (y0 + y1) as f32 / height as f32,
                );
                tile_dir.push(uv_to_dir(centre));
            }
        }
        Some(Self {
            width,
            height,
            tile_w,
            tile_h,
            tiles_x,
            tile_mass,
            tile_solid,
            compensation,
            tile_dir,
            texel_cdf,
            cells: (0..CELLS * CELLS).map(|_| OnceLock::new()).collect(),
        })
    }

    /// The tile CDF of the cell of normal `n` (built on first use) and its every
    /// [`BLOCK`]-th entry (see [`Self::build_cell`]); `None` when that cell sees no light.
    #[inline]
    fn cell_cdf(&self, n: Vec3) -> Option<(&[f32], &[f32])> {
        let k = octahedral_cell(n);
        let table = self.cells[k].get_or_init(|| self.build_cell(k));
        (!table.is_empty()).then(|| table.split_at(self.tile_mass.len() + 1))
    }

    fn build_cell(&self, k: usize) -> Box<[f32]> {
        let n = octahedral_centre(k);
        let cosines = self.tile_dir.iter().map(|d| n.dot(*d).max(0.0) as f64);
        // c_k: the compensation × the cosine-weighted mean of the cell's hemisphere.
        let (mut lit, mut solid) = (0.0f64, 0.0f64);
        for ((&m, &s), cos) in self.tile_mass.iter().zip(&self.tile_solid).zip(cosines.clone()) {
            lit += m as f64 * cos;
            solid += s as f64 * cos;
        }
        let c = if solid > 0.0 {
            self.compensation as f64 * lit / solid
        } else {
            0.0
        };
        let mut cdf = Vec::with_capacity(self.tile_mass.len() + 1);
        let mut sum = 0.0f64;
        cdf.push(0.0f64);
        for ((&m, &s), cos) in self.tile_mass.iter().zip(&self.tile_solid).zip(cosines) {
            sum += (m as f64 - c * s as f64).max(0.0) * cos;
            cdf.push(sum);
        }
        if !(sum > 0.0) {
            return Box::new([]);
        }
        let last = cdf.len() - 1;
        let cdf: Vec<f32> = cdf
            .iter()
            .enumerate()
            .map(|(i, &c)| if i == last { 1.0 } else { (c / sum) as f32 })
            .collect();
        // The CDF, then its coarse level.
        let coarse = coarse_level(&cdf);
        [cdf, coarse].concat().into_boxed_slice()
    }

    /// Image coordinates ∝ the light's weights × max(0, n_k·d) for the cell of the shading
    /// normal `n`, and their density p(u, v) (module docs); `None` when the cell sees no light.
    pub fn sample(&self, n: Vec3, u: Vec2) -> Option<(Vec2, f32)> {
        let (cdf, coarse) = self.cell_cdf(n)?;
        let (tile, p_tile, ux) = pick(cdf, two_level_count(cdf, coarse, u.x), u.x)?;
        let per_tile = self.tile_w * self.tile_h;
        let texels = &self.texel_cdf[tile * (per_tile + 1)..(tile + 1) * (per_tile + 1)];
        let (t, p_texel, uy) = pick(texels, partition_count(texels, u.y), u.y)?;
        let x = (tile % self.tiles_x) * self.tile_w + t % self.tile_w;
        let y = (tile / self.tiles_x) * self.tile_h + t / self.tile_w;
        let uv = Vec2::new(
            ((x as f32 + ux) / self.width as f32).min(ONE_MINUS_EPSILON),
            ((y as f32 + uy) / self.height as f32).min(ONE_MINUS_EPSILON),
        );
        let pdf = p_tile * p_texel * (self.width * self.height) as f32;
        (pdf > 0.0).then_some((uv, pdf))
    }

    /// Density p(u, v) of [`Self::sample`] with the same normal at image coordinates `uv`.
    pub fn pdf(&self, n: Vec3, uv: Vec2) -> f32 {
        let Some((cdf, _)) = self.cell_cdf(n) else {
            return 0.0;
        };
        let x = ((uv.x * self.width as f32) as usize).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as usize).min(self.height - 1);
        let tile = (y / self.tile_h) * self.tiles_x + x / self.tile_w;
        let t = (y % self.tile_h) * self.tile_w + x % self.tile_w;
        let per_tile = self.tile_w * self.tile_h;
        let texels = &self.texel_cdf[tile * (per_tile + 1)..];
        (cdf[tile + 1] - cdf[tile]) * (texels[t + 1] - texels[t]) * (self.width * self.height) as f32
    }
}

/// Entries of the cell CDFs per block of their two-level search.
const BLOCK: usize = 64;

/// How many entries of the non-decreasing `values` are at most `u`: the partition point a binary
/// search finds, counted instead. The comparisons do not wait on each other, and a block of 64
/// is four to eight cache lines loaded at once; a binary search over a cell's 2049 entries waits
/// on eleven dependent loads, most of them misses (12 % of the copper preview's render time).
#[inline]
fn count_le(values: &[f32], u: f32) -> usize {
    values.iter().map(|&c| (c <= u) as u32).sum::<u32>() as usize
}

/// The coarse level of a CDF's search: its entries 0, [`BLOCK`], 2·[`BLOCK`], ….
fn coarse_level(cdf: &[f32]) -> Vec<f32> {
    cdf.iter().step_by(BLOCK).copied().collect()
}

/// [`count_le`] over `cdf` in two levels: a whole block for each entry of `coarse`
/// ([`coarse_level`]) at most `u` but the last, then a count inside the block that holds the
/// CDF's crossing.
#[inline]
fn two_level_count(cdf: &[f32], coarse: &[f32], u: f32) -> usize {
    let block = count_le(coarse, u).saturating_sub(1) * BLOCK;
    block + count_le(&cdf[block..(block + BLOCK).min(cdf.len())], u)
}

/// [`count_le`] for a CDF of at most `2 · BLOCK` entries (a tile of at most 127 texels: the
/// 512 × 256 preview map's tiles are 8 × 8), a binary search above (a tile of a 1024 × 512 map
/// has 16 × 16 texels, of a 4096 × 2048 one 4096: a count would compare them all).
#[inline]
fn partition_count(values: &[f32], u: f32) -> usize {
    if values.len() <= 2 * BLOCK {
        count_le(values, u)
    } else {
        values.partition_point(|&c| c <= u)
    }
}

/// The cell of a CDF `cdf` (`n + 1` entries from 0 to 1) that `u` falls in, given the number
/// `below` of its entries at most `u` ([`count_le`]), its probability and `u` rescaled to
/// [0, 1) within it. Empty cells are never returned.
#[inline]
fn pick(cdf: &[f32], below: usize, u: f32) -> Option<(usize, f32, f32)> {
    let cells = cdf.len().checked_sub(1)?;
    let i = below.saturating_sub(1).min(cells.checked_sub(1)?);
    let p = cdf[i + 1] - cdf[i];
    (p > 0.0).then(|| (i, p, ((u - cdf[i]) / p).clamp(0.0, ONE_MINUS_EPSILON)))
}

/// The octahedral-map cell of a unit direction among [`CELLS`] × [`CELLS`]
/// ([`octahedral_cell_of`]).
#[inline]
fn octahedral_cell(n: Vec3) -> usize {
    octahedral_cell_of(n, CELLS)
}

/// The octahedral-map cell of a unit direction: the octahedron |x| + |y| + |z| = 1 unfolded
/// onto [−1, 1]², its lower half folded over the corners, cut into `cells × cells` (row-major).
#[inline(always)]
pub(super) fn octahedral_cell_of(n: Vec3, cells: usize) -> usize {
    let p = octahedral_encode(n);
    let cell = |c: f32| (((c + 1.0) * 0.5 * cells as f32) as usize).min(cells - 1);
    cell(p.y) * cells + cell(p.x)
}

#[inline(always)]
fn octahedral_encode(n: Vec3) -> Vec2 {
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    if !(l1 > 0.0) {
        return Vec2::ZERO;
    }
    let p = Vec2::new(n.x, n.y) / l1;
    if n.z >= 0.0 {
        p
    } else {
        Vec2::new((1.0 - p.y.abs()) * sign(p.x), (1.0 - p.x.abs()) * sign(p.y))
    }
}

#[inline(always)]
fn sign(x: f32) -> f32 {
    if x >= 0.0 { 1.0 } else { -1.0 }
}

/// The unit direction at the centre of octahedral cell `k` among [`CELLS`] × [`CELLS`].
fn octahedral_centre(k: usize) -> Vec3 {
    octahedral_centre_of(k, CELLS)
}

/// The unit direction at the centre of octahedral cell `k` among `cells × cells` (the inverse
/// map of [`octahedral_cell_of`]'s encoding).
pub(super) fn octahedral_centre_of(k: usize, cells: usize) -> Vec3 {
    let c = |i: usize| (i as f32 + 0.5) / cells as f32 * 2.0 - 1.0;
    octahedral_decode(Vec2::new(c(k % cells), c(k / cells)))
}

/// The unit direction at point `p` ∈ [−1, 1]² of the octahedral map (the inverse of
/// [`octahedral_encode`]).
fn octahedral_decode(p: Vec2) -> Vec3 {
    let z = 1.0 - p.x.abs() - p.y.abs();
    let (x, y) = if z >= 0.0 {
        (p.x, p.y)
    } else {
        ((1.0 - p.y.abs()) * sign(p.x), (1.0 - p.x.abs()) * sign(p.y))
    };
    Vec3::new(x, y, z).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octahedral_cells_contain_their_centres() {
        for k in 0..CELLS * CELLS {
            assert_eq!(octahedral_cell(octahedral_centre(k)), k, "cell {k}");
        }
    }

    #[test]
    fn maps_too_coarse_for_the_cosine_have_no_product_tables() {
        let dir = |uv: Vec2| {
            let (st, ct) = (std::f32::consts::PI * uv.y).sin_cos();
            let (sp, cp) = (std::f32::consts::TAU * uv.x).sin_cos();
            Vec3::new(st * sp, ct, -st * cp)
        };
        for (w, h) in [(1, 1), (31, 16), (32, 15)] {
            assert!(
                CosineProduct::new(&vec![1.0; w * h], w, h, 0.5, dir).is_none(),
                "{w} × {h}"
            );
        }
        assert!(CosineProduct::new(&vec![1.0; 32 * 16], 32, 16, 0.5, dir).is_some());
        assert!(CosineProduct::new(&vec![0.0; 32 * 16], 32, 16, 0.5, dir).is_none());
    }

    #[test]
    fn the_two_level_count_finds_the_binary_search_partition_point() {
        // CDFs with empty cells (repeated entries), of lengths around the block size, and u on
        // and between their entries: the count over the coarse level and one block is the
        // partition point of `c <= u` over the whole CDF.
        let mut rng = gonio_core::rng::Pcg32::new(7, 11);
        for len in [2usize, 3, 64, 65, 66, 129, 200, 2049] {
            for _ in 0..20 {
                let mut cdf = vec![0.0f32];
                for _ in 1..len - 1 {
                    let step = if rng.next_f32() < 0.3 { 0.0 } else { rng.next_f32() };
                    cdf.push(cdf.last().unwrap() + step);
                }
                let sum = *cdf.last().unwrap();
                let mut cdf: Vec<f32> = cdf
                    .iter()
                    .map(|&c| if sum > 0.0 { c / sum } else { 0.0 })
                    .collect();
                cdf.push(1.0);
                let coarse = coarse_level(&cdf);
                let probes = (0..50)
                    .map(|_| rng.next_f32())
                    .chain(cdf[..len - 1].iter().copied());
                for u in probes {
                    let expected = cdf.partition_point(|&c| c <= u);
                    assert_eq!(two_level_count(&cdf, &coarse, u), expected, "len {len}, u {u}");
                    assert_eq!(partition_count(&cdf, u), expected, "len {len}, u {u}");
                }
            }
        }
    }

    #[test]
    fn octahedral_cells_are_small() {
        // Every direction lies within 7.6° of its cell's centre (7.56° the largest of 4·10⁶
        // random directions; the cells along the octahedron's edges are the longest).
        let mut worst = 0.0f32;
        for i in 0..200 {
            for j in 0..100 {
                let (phi, ct) = (
                    i as f32 / 200.0 * std::f32::consts::TAU,
                    j as f32 / 99.0 * 2.0 - 1.0,
                );
                let st = (1.0 - ct * ct).max(0.0).sqrt();
                let d = Vec3::new(st * phi.cos(), st * phi.sin(), ct);
                worst = worst.max(
                    d.dot(octahedral_centre(octahedral_cell(d)))
                        .clamp(-1.0, 1.0)
                        .acos(),
                );
            }
        }
        assert!(worst < 7.6f32.to_radians(), "{}°", worst.to_degrees());
    }
}
