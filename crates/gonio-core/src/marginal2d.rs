//! A bilinear density on the unit square, sampled by its marginal and conditional CDFs, with
//! optional dependence on up to three parameters: Mitsuba 3's `Marginal2D<Float, D, true>` (the
//! *continuous* variant, `include/mitsuba/core/distr_2d.h`), the warp behind its RGL `measured`
//! BSDF (Dupuy and Jakob 2018).
//!
//! The data are `w × h` values on the corners of (w − 1) × (h − 1) patches of [0, 1]² (x the
//! fastest index), one such slice per node of the parameter grid (parameters slowest first).
//! Between nodes, and within a patch, everything is linear: the density is the bilinear
//! interpolant, and CDFs and densities are interpolated multilinearly in the parameters.
//!
//! * `eval(p)`: the interpolated value at p (normalized to integrate to 1 per slice, or as
//!   given).
//! * `sample(u)`: the row from the marginal CDF of the rows' integrals, continuous within the
//!   row's interval (the integral along x varies linearly in y there, so the inversion solves a
//!   quadratic); then the column the same way along x at that y. The map is continuous, and
//!   bijective where the density is positive; it returns the point and its density.
//! * `invert(p)`: the inverse map, and the density at p. Where the density vanishes on a whole
//!   row (or slice) the inverse is not defined and Mitsuba divides by 0 (NaN); gonio returns 0
//!   for that coordinate.
//!
//! Parameter lookups follow Mitsuba's `interpolate_weights`: the interval whose lower node is
//! the last one strictly below the value, the weight clamped to [0, 1] (constant beyond the
//! ends). Written here (not a crate) because the point is to reproduce Mitsuba's map exactly: an
//! RGL table is indexed by the sample-space point this warp gives.

use glam::Vec2;

/// The most parameters a table may depend on.
pub const MAX_PARAMS: usize = 3;

/// Why a table was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum Marginal2DError {
    /// A side of the grid has fewer than two values.
    TooSmall(usize, usize),
    /// More parameters than [`MAX_PARAMS`].
    TooManyParams(usize),
    /// A parameter axis is empty, not finite or not increasing.
    BadParam {
        /// Which parameter.
        axis: usize,
        /// Index of the offending value.
        index: usize,
        /// The value.
        value: f32,
    },
    /// A parameter axis has no value.
    EmptyParam(usize),
    /// The data's length is not the grid times the parameter nodes.
    Size {
        /// Values expected.
        expected: usize,
        /// Values given.
        got: usize,
    },
    /// A value is negative, NaN or infinite.
    BadValue {
        /// Index into the data.
        index: usize,
        /// The value.
        value: f32,
    },
    /// A slice to be normalized integrates to 0 (or so little that 1/integral overflows).
    ZeroSlice(usize),
}

impl std::fmt::Display for Marginal2DError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::TooSmall(w, h) => write!(f, "the grid is {w} × {h}; each side needs at least 2 values"),
            Self::TooManyParams(n) => write!(f, "{n} parameters; at most {MAX_PARAMS}"),
            Self::BadParam { axis, index, value } => write!(
                f,
                "parameter {axis}: value {value} at index {index} is not finite or not larger than the one before"
            ),
            Self::EmptyParam(axis) => write!(f, "parameter {axis} has no value"),
            Self::Size { expected, got } => {
                write!(f, "{got} values; the grid and parameters call for {expected}")
            }
            Self::BadValue { index, value } => {
                write!(f, "value {value} at index {index} is not a finite number ≥ 0")
            }
            Self::ZeroSlice(slice) => {
                write!(
                    f,
                    "slice {slice} integrates to 0 (or below 1/f32::MAX) and cannot be normalized"
                )
            }
        }
    }
}

impl std::error::Error for Marginal2DError {}

/// Mitsuba's continuous `Marginal2D` (see the module docs).
#[derive(Clone, PartialEq)]
pub struct Marginal2D {
    /// (w, h).
    size: [usize; 2],
    params: Vec<Vec<f32>>,
    /// Stride of each parameter in slices (0 for a one-node axis).
    strides: Vec<usize>,
    data: Vec<f32>,
    marg_cdf: Vec<f32>,
    cond_cdf: Vec<f32>,
    normalized: bool,
    patch_size: Vec2,
    inv_patch_size: Vec2,
}

impl std::fmt::Debug for Marginal2D {
    /// The shape, not the values (a measured table holds hundreds of thousands).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Marginal2D")
            .field("size", &self.size)
            .field(
                "param_nodes",
                &self.params.iter().map(Vec::len).collect::<Vec<_>>(),
            )
            .field("normalized", &self.normalized)
            .field("sampling", &!self.marg_cdf.is_empty())
            .finish_non_exhaustive()
    }
}

/// Where the parameters fall: the slice offset and each axis's (lower, upper) weights.
#[derive(Clone, Copy, Debug)]
struct ParamWeights {
    slice: usize,
    w: [(f32, f32); MAX_PARAMS],
}

impl Marginal2D {
    /// A table of `size` = (w, h) corners per slice, `params` the parameter axes (slowest
    /// first), `data` the values (slices in parameter order, each row-major with y slowest).
    /// `normalize`: scale each slice to integrate to 1 over [0, 1]². `sampling`: build the CDFs
    /// for [`Self::sample`] and [`Self::invert`] (without them those answer `None`).
    pub fn new(
        size: [usize; 2],
        params: Vec<Vec<f32>>,
        data: &[f32],
        normalize: bool,
        sampling: bool,
    ) -> Result<Self, Marginal2DError> {
        let [w, h] = size;
        if w < 2 || h < 2 {
            return Err(Marginal2DError::TooSmall(w, h));
        }
        if params.len() > MAX_PARAMS {
            return Err(Marginal2DError::TooManyParams(params.len()));
        }
        let mut strides = vec![0; params.len()];
        let mut slices = 1usize;
        for (i, axis) in params.iter().enumerate().rev() {
            if axis.is_empty() {
                return Err(Marginal2DError::EmptyParam(i));
            }
            for (index, &value) in axis.iter().enumerate() {
                if !value.is_finite() || (index > 0 && value <= axis[index - 1]) {
                    return Err(Marginal2DError::BadParam {
                        axis: i,
                        index,
                        value,
                    });
                }
            }
            strides[i] = if axis.len() > 1 { slices } else { 0 };
            slices = slices.saturating_mul(axis.len());
        }
        let n_data = w.saturating_mul(h);
        let expected = slices.saturating_mul(n_data);
        if data.len() != expected {
            return Err(Marginal2DError::Size {
                expected,
                got: data.len(),
            });
        }
        if let Some(index) = data.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(Marginal2DError::BadValue {
                index,
                value: data[index],
            });
        }
        let (n_marg, n_cond) = (h - 1, (w - 1) * h);
        let (scale_x, scale_y) = (0.5 / (w - 1) as f64, 0.5 / (h - 1) as f64);
        let mut out = Vec::with_capacity(expected);
        let (mut marg_cdf, mut cond_cdf) = (Vec::new(), Vec::new());
        let mut row_sums = vec![0.0f64; h];
        for (slice, d) in data.chunks_exact(n_data).enumerate() {
            let mut norm = 1.0f32;
            if sampling {
                let cond_start = cond_cdf.len();
                for (y, row) in d.chunks_exact(w).enumerate() {
                    let mut acc = 0.0f64;
                    for pair in row.windows(2) {
                        acc += scale_x * (pair[0] as f64 + pair[1] as f64);
                        cond_cdf.push(acc as f32);
                    }
                    row_sums[y] = acc;
                }
                let marg_start = marg_cdf.len();
                let mut acc = 0.0f64;
                for y in 0..h - 1 {
                    acc += scale_y * (row_sums[y] + row_sums[y + 1]);
                    marg_cdf.push(acc as f32);
                }
                if normalize {
                    norm = (1.0 / acc) as f32;
                    if !(acc > 0.0 && norm.is_finite()) {
                        return Err(Marginal2DError::ZeroSlice(slice));
                    }
                }
                cond_cdf[cond_start..].iter_mut().for_each(|v| *v *= norm);
                marg_cdf[marg_start..].iter_mut().for_each(|v| *v *= norm);
                debug_assert_eq!(cond_cdf.len() - cond_start, n_cond);
                debug_assert_eq!(marg_cdf.len() - marg_start, n_marg);
            } else if normalize {
                let mut sum = 0.0f64;
                for y in 0..h - 1 {
                    for x in 0..w - 1 {
                        let i = y * w + x;
                        sum += d[i] as f64 + d[i + 1] as f64 + d[i + w] as f64 + d[i + w + 1] as f64;
                    }
                }
                norm = (1.0 / (scale_x * scale_y * sum)) as f32;
                if !(sum > 0.0 && norm.is_finite()) {
                    return Err(Marginal2DError::ZeroSlice(slice));
                }
            }
            out.extend(d.iter().map(|v| v * norm));
        }
        let n_patches = Vec2::new((w - 1) as f32, (h - 1) as f32);
        Ok(Self {
            size,
            params,
            strides,
            data: out,
            marg_cdf,
            cond_cdf,
            normalized: normalize,
            patch_size: 1.0 / n_patches,
            inv_patch_size: n_patches,
        })
    }

    /// The parameters' slice offset and weights; `param` holds one value per parameter.
    #[inline]
    fn weights(&self, param: &[f32]) -> ParamWeights {
        assert!(
            param.len() >= self.params.len(),
            "Marginal2D: {} parameters given, {} needed",
            param.len(),
            self.params.len()
        );
        let mut pw = ParamWeights {
            slice: 0,
            w: [(1.0, 0.0); MAX_PARAMS],
        };
        for (dim, axis) in self.params.iter().enumerate() {
            if axis.len() == 1 {
                continue;
            }
            let (index, w1) = param_interval(axis, param[dim]);
            pw.w[dim] = (1.0 - w1, w1);
            pw.slice += self.strides[dim] * index;
        }
        pw
    }

    /// `table[i0 + offset]` interpolated over the parameters (`size`: the table's length per
    /// slice), as Mitsuba's `lookup`, the last parameter outermost.
    #[inline]
    fn lookup(
        &self,
        table: &[f32],
        offset: usize,
        i0: usize,
        size: usize,
        pw: &ParamWeights,
        dim: usize,
    ) -> f32 {
        if dim == 0 {
            return table[i0 + offset];
        }
        let d = dim - 1;
        let i1 = i0 + self.strides[d] * size;
        let v0 = self.lookup(table, offset, i0, size, pw, d);
        let v1 = self.lookup(table, offset, i1, size, pw, d);
        v0 * pw.w[d].0 + v1 * pw.w[d].1
    }

    #[inline]
    fn at(&self, table: &[f32], offset: usize, i0: usize, size: usize, pw: &ParamWeights) -> f32 {
        self.lookup(table, offset, i0, size, pw, self.params.len())
    }

    /// The four corners (v00, v10, v01, v11) of the patch at data index `index` (slice
    /// included).
    #[inline]
    fn corners(&self, index: usize, pw: &ParamWeights) -> [f32; 4] {
        let (w, n) = (self.size[0], self.size[0] * self.size[1]);
        [0, 1, w, w + 1].map(|o| self.at(&self.data, o, index, n, pw))
    }

    /// The patch of `p` ∈ [0, 1]² (clamped) and the position within it.
    #[inline]
    fn patch(&self, p: Vec2) -> ([usize; 2], Vec2) {
        let p = p.clamp(Vec2::ZERO, Vec2::ONE) * self.inv_patch_size;
        let offset = [
            (p.x as usize).min(self.size[0] - 2),
            (p.y as usize).min(self.size[1] - 2),
        ];
        (offset, p - Vec2::new(offset[0] as f32, offset[1] as f32))
    }

    /// The density (or the interpolated value, unnormalized) at `p` for parameters `param`.
    pub fn eval(&self, p: Vec2, param: &[f32]) -> f32 {
        let pw = self.weights(param);
        let ([x, y], t) = self.patch(p);
        let index = x + y * self.size[0] + pw.slice * self.size[0] * self.size[1];
        let [v00, v10, v01, v11] = self.corners(index, &pw);
        (1.0 - t.x) * ((1.0 - t.y) * v00 + t.y * v01) + t.x * ((1.0 - t.y) * v10 + t.y * v11)
    }

    /// Warps `u` ∈ [0, 1]² to a point distributed as the density; `(point, density)`, or `None`
    /// without the CDFs.
    pub fn sample(&self, u: Vec2, param: &[f32]) -> Option<(Vec2, f32)> {
        if self.marg_cdf.is_empty() {
            return None;
        }
        let [w, h] = self.size;
        let (n_cond, n_marg, n_data) = ((w - 1) * h, h - 1, w * h);
        let pw = self.weights(param);
        let mut s = u.clamp(Vec2::splat(EPSILON), Vec2::splat(ONE_MINUS_EPSILON));
        let offset_marg = pw.slice * n_marg;
        let marg = |i: usize| self.at(&self.marg_cdf, 0, offset_marg + i, n_marg, &pw);
        if !self.normalized {
            s.y *= marg(n_marg - 1);
        }
        let row = first_not(0, n_marg - 1, |i| marg(i) < s.y);
        if row > 0 {
            s.y -= marg(row - 1);
        }
        let offset_cond = pw.slice * n_cond + row * (w - 1);
        let cond = |o: usize, i: usize| self.at(&self.cond_cdf, o, offset_cond + i, n_cond, &pw);
        let (r0, r1) = (cond(w - 2, 0), cond(2 * (w - 1) - 1, 0));
        s.y = sample_segment(s.y, self.inv_patch_size.y, r0, r1);
        s.x *= lerp(r0, r1, s.y);
        let fetch = |i: usize| lerp(cond(0, i), cond(w - 1, i), s.y);
        let col = first_not(0, w - 1, |i| fetch(i) < s.x);
        if col > 0 {
            s.x -= fetch(col - 1);
        }
        let [v00, v10, v01, v11] = self.corners(pw.slice * n_data + row * w + col, &pw);
        let (c0, c1) = (lerp(v00, v01, s.y), lerp(v10, v11, s.y));
        s.x = sample_segment(s.x, self.inv_patch_size.x, c0, c1);
        let p = (Vec2::new(col as f32, row as f32) + s) * self.patch_size;
        Some((p, lerp(c0, c1, s.x)))
    }

    /// The inverse of [`Self::sample`]: the `u` that warps to `p`, and the density at `p`;
    /// `None` without the CDFs.
    pub fn invert(&self, p: Vec2, param: &[f32]) -> Option<(Vec2, f32)> {
        if self.marg_cdf.is_empty() {
            return None;
        }
        let [w, h] = self.size;
        let (n_cond, n_marg, n_data) = ((w - 1) * h, h - 1, w * h);
        let pw = self.weights(param);
        let ([x, y], mut s) = self.patch(p);
        let [v00, v10, v01, v11] = self.corners(pw.slice * n_data + y * w + x, &pw);
        let (c0, c1) = (lerp(v00, v01, s.y), lerp(v10, v11, s.y));
        let pdf = lerp(c0, c1, s.x);
        s.x = invert_segment(s.x, self.patch_size.x, c0, c1);
        let offset_cond = pw.slice * n_cond + y * (w - 1);
        let cond = |o: usize, i: usize| self.at(&self.cond_cdf, o, offset_cond + i, n_cond, &pw);
        if x > 0 {
            s.x += lerp(cond(0, x - 1), cond(w - 1, x - 1), s.y);
        }
        let (r0, r1) = (cond(w - 2, 0), cond(2 * (w - 1) - 1, 0));
        // A row of zero density: Mitsuba divides by 0 (NaN); its CDF is flat, so 0.
        let row_mass = lerp(r0, r1, s.y);
        s.x = if row_mass != 0.0 { s.x / row_mass } else { 0.0 };
        s.y = invert_segment(s.y, self.patch_size.y, r0, r1);
        let offset_marg = pw.slice * n_marg;
        let marg = |i: usize| self.at(&self.marg_cdf, 0, offset_marg + i, n_marg, &pw);
        if y > 0 {
            s.y += marg(y - 1);
        }
        if !self.normalized {
            let total = marg(n_marg - 1);
            s.y = if total != 0.0 { s.y / total } else { 0.0 };
        }
        Some((s, pdf))
    }
}

/// Mitsuba's parameter lookup (`Distribution2D::interpolate_weights`) on an increasing `axis` of
/// at least two nodes: the interval [i, i + 1] whose lower node is the last one strictly below
/// `x` (so on a node, the interval that ends there), clamped to [0, n − 2], and the upper node's
/// weight clamped to [0, 1] (constant beyond the ends; 0 for a NaN `x`).
#[inline]
pub fn param_interval(axis: &[f32], x: f32) -> (usize, f32) {
    let index = axis
        .partition_point(|&v| v < x)
        .saturating_sub(1)
        .min(axis.len() - 2);
    let (p0, p1) = (axis[index], axis[index + 1]);
    let w1 = ((x - p0) / (p1 - p0)).clamp(0.0, 1.0);
    (index, if w1.is_nan() { 0.0 } else { w1 })
}

/// Mitsuba's `dr::Epsilon<float>` (2⁻²⁴) and `OneMinusEpsilon` (the largest float below 1).
const EPSILON: f32 = 5.960_464_5e-8;
const ONE_MINUS_EPSILON: f32 = 0.999_999_94;

/// a + (b − a)t, as Dr.Jit's `lerp`.
#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a - a * t + b * t
}

/// The first index in `[start, end]` where `pred` fails (`end` if it never does), `pred`
/// monotone: Dr.Jit's `binary_search`.
#[inline]
fn first_not(start: usize, end: usize, pred: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (start, end);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if pred(mid) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Inverts the CDF of a density linear from v0 to v1 over an interval of width 1/inv_width:
/// the position in [0, 1] whose integral is `sample` (a quadratic; linear when v0 ≈ v1).
#[inline]
fn sample_segment(sample: f32, inv_width: f32, v0: f32, v1: f32) -> f32 {
    let non_const = (v0 - v1).abs() > 1e-4 * (v0 + v1);
    let divisor = if non_const { v0 - v1 } else { v0 + v1 };
    let mut s = sample * 2.0 * inv_width;
    if non_const {
        s = v0 - (v0 * v0 + s * (v1 - v0)).max(0.0).sqrt();
    }
    if divisor != 0.0 { s / divisor } else { s }
}

/// The integral of that density from 0 to `sample` (of the interval's width `width`).
#[inline]
fn invert_segment(sample: f32, width: f32, v0: f32, v1: f32) -> f32 {
    sample * lerp(v0, v1, 0.5 * sample) * width
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> Marginal2D {
        // 4 × 3 corners, two slices over one parameter.
        let data: Vec<f32> = (0..24).map(|i| 0.5 + ((i * 7) % 5) as f32).collect();
        Marginal2D::new([4, 3], vec![vec![0.0, 2.0]], &data, true, true).unwrap()
    }

    #[test]
    fn sample_and_invert_are_inverses_and_agree_with_eval() {
        let t = table();
        for (i, param) in [0.0f32, 0.7, 2.0, 5.0].into_iter().enumerate() {
            for k in 0..50 {
                let u = Vec2::new(((k * 37 + i) % 50) as f32 / 50.0 + 0.01, (k as f32 + 0.5) / 50.0);
                let (p, pdf) = t.sample(u, &[param]).unwrap();
                let (back, pdf2) = t.invert(p, &[param]).unwrap();
                assert!((back - u).abs().max_element() < 2e-5, "{u} → {p} → {back}");
                let e = t.eval(p, &[param]);
                assert!(
                    (pdf - e).abs() < 1e-4 * e && (pdf2 - e).abs() < 1e-4 * e,
                    "{pdf} {pdf2} {e}"
                );
            }
        }
    }

    #[test]
    fn a_normalized_slice_integrates_to_one() {
        let t = table();
        let n = 200;
        for param in [0.0, 1.3] {
            let mut sum = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let p = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    sum += t.eval(p, &[param]) as f64;
                }
            }
            assert!(
                (sum / (n * n) as f64 - 1.0).abs() < 1e-4,
                "{}",
                sum / (n * n) as f64
            );
        }
    }

    #[test]
    fn bad_tables_are_refused() {
        assert_eq!(
            Marginal2D::new([1, 3], vec![], &[1.0; 3], true, true),
            Err(Marginal2DError::TooSmall(1, 3))
        );
        assert!(matches!(
            Marginal2D::new([2, 2], vec![], &[1.0, -1.0, 1.0, 1.0], true, true),
            Err(Marginal2DError::BadValue { index: 1, .. })
        ));
        assert_eq!(
            Marginal2D::new([2, 2], vec![], &[0.0; 4], true, true),
            Err(Marginal2DError::ZeroSlice(0))
        );
        assert!(matches!(
            Marginal2D::new([2, 2], vec![vec![1.0, 1.0]], &[1.0; 8], true, true),
            Err(Marginal2DError::BadParam {
                axis: 0,
                index: 1,
                ..
            })
        ));
        assert_eq!(
            Marginal2D::new([2, 2], vec![vec![1.0, 2.0]], &[1.0; 4], true, true),
            Err(Marginal2DError::Size { expected: 8, got: 4 })
        );
        assert_eq!(
            Marginal2D::new([2, 2], vec![vec![]], &[], true, true),
            Err(Marginal2DError::EmptyParam(0))
        );
        assert_eq!(
            Marginal2D::new([2, 2], vec![vec![0.0]; 4], &[1.0; 4], true, true),
            Err(Marginal2DError::TooManyParams(4))
        );
        // Positive but so small that 1/integral overflows f32.
        assert_eq!(
            Marginal2D::new([3, 3], vec![], &[1e-40; 9], true, true),
            Err(Marginal2DError::ZeroSlice(0))
        );
        assert_eq!(
            Marginal2D::new([3, 3], vec![], &[1e-40; 9], true, false),
            Err(Marginal2DError::ZeroSlice(0))
        );
        // Hostile sizes: an error, not an overflow.
        assert!(matches!(
            Marginal2D::new([1 << 40, 1 << 40], vec![], &[], true, true),
            Err(Marginal2DError::Size { .. })
        ));
    }

    #[test]
    fn inverting_where_a_row_has_no_density_gives_no_nan() {
        let t = Marginal2D::new([2, 3], vec![], &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0], true, true).unwrap();
        let (u, pdf) = t.invert(Vec2::new(0.5, 0.25), &[]).unwrap();
        assert!(u.is_finite() && pdf == 0.0, "{u} {pdf}");
        let t = Marginal2D::new([2, 2], vec![], &[0.0; 4], false, true).unwrap();
        let (u, _) = t.invert(Vec2::new(0.3, 0.6), &[]).unwrap();
        assert!(u.is_finite(), "{u}");
    }
}
