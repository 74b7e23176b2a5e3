//! Piecewise-constant distributions for importance sampling: a 1D discrete/continuous
//! distribution (light selection, triangles of a mesh by area, rows of an environment map) and a
//! 2D one built from a marginal over rows and conditionals per row (environment maps, the
//! sampling tables of `tabulated`).
//!
//! These are pbrt-v4's `PiecewiseConstant1D` and `PiecewiseConstant2D` (Pharr, Jakob and
//! Humphreys, *Physically Based Rendering*, 4th ed., §A.1 and §A.5, `util/sampling.h`) under the
//! names this crate has always used: the CDF is searched with [`find_interval`], the cell's
//! probability is the difference of its two CDF entries (so [`Distribution1D::pmf`] is exactly
//! the probability with which sampling returns the cell), and zero-valued cells are never drawn.
//!
//! The search starts from a guide table (Chen and Asau 1974, "On generating random variates from
//! an empirical distribution"): entry k is the cell of u = k/n, so the cell of any u lies between
//! two consecutive entries, usually the same cell or the next. The answer is the binary search's
//! bit for bit (a bucket spanning many cells falls back to it); it saves the dependent loads
//! and mispredicted branches of about log₂ n halvings per draw, which an environment map's rows
//! and columns made 8 % of a material preview's render time.

use crate::math::find_interval;
use glam::Vec2;

/// The longest linear scan between two guide entries before the binary search takes over.
const GUIDE_SCAN: usize = 8;

/// A piecewise-constant density on [0, 1) with `n` equal cells, from non-negative cell values.
/// Also a discrete distribution over the cells (probability ∝ value).
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1D {
    func: Vec<f32>,
    /// cdf[i] = P(cell < i); cdf[n] = 1.
    cdf: Vec<f32>,
    /// guide[k] = the cell of u = k/n, k = 0..=n (module docs).
    guide: Vec<u32>,
    /// Σ func / n (the integral of the piecewise-constant function over [0, 1)).
    integral: f32,
}

impl Distribution1D {
    /// From cell values (negative or non-finite values count as 0). When every value is 0 the
    /// distribution is uniform, so sampling never fails; [`Self::integral`] is then 0.
    pub fn new(values: &[f32]) -> Self {
        let n = values.len().max(1);
        let func: Vec<f32> = (0..n)
            .map(|i| {
                values
                    .get(i)
                    .copied()
                    .filter(|v| v.is_finite() && *v > 0.0)
                    .unwrap_or(0.0)
            })
            .collect();
        let (mut cdf, mut guide) = (Vec::with_capacity(n + 1), Vec::with_capacity(n + 1));
        let integral = push_cdf(&func, &mut cdf, &mut guide);
        Self {
            func,
            cdf,
            guide,
            integral,
        }
    }

    fn view(&self) -> CdfView<'_> {
        CdfView {
            cdf: &self.cdf,
            guide: &self.guide,
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.func.len()
    }

    /// True when there are no cells (never: at least one cell is always kept).
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// ∫₀¹ of the piecewise-constant function (Σ values / n).
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Discrete probability of cell `i`.
    pub fn pmf(&self, i: usize) -> f32 {
        self.view().pmf(i)
    }

    /// Draws a cell with probability ∝ its value: (index, probability, `u` rescaled to [0, 1)
    /// inside the cell for reuse).
    pub fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        self.view().sample_discrete(u)
    }

    /// Draws x ∈ [0, 1) with the piecewise-constant density: (x, density at x, cell).
    pub fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        self.view().sample_continuous(u)
    }

    /// Density of [`Self::sample_continuous`] at x ∈ [0, 1).
    pub fn pdf_continuous(&self, x: f32) -> f32 {
        self.view().pdf_continuous(x)
    }
}

/// Appends the normalized CDF (n + 1 entries) and guide table (n + 1 entries) of the non-negative
/// cell values `func` (n ≥ 1) to `cdf` and `guide`; returns Σ func / n. All-zero values give
/// the uniform CDF.
fn push_cdf(func: &[f32], cdf: &mut Vec<f32>, guide: &mut Vec<u32>) -> f32 {
    let n = func.len();
    let base = cdf.len();
    cdf.push(0.0);
    let mut acc = 0.0f64;
    for &f in func {
        acc += f as f64 / n as f64;
        cdf.push(acc as f32);
    }
    let row = &mut cdf[base..];
    if acc > 0.0 {
        for c in row.iter_mut() {
            *c = (*c as f64 / acc) as f32;
        }
    } else {
        for (i, c) in row.iter_mut().enumerate() {
            *c = i as f32 / n as f32;
        }
    }
    row[n] = 1.0;
    let row = &cdf[base..];
    guide.extend((0..=n).map(|k| find_interval(row, k as f32 / n as f32) as u32));
    acc as f32
}

/// One distribution's CDF and guide table (module docs), borrowed: a [`Distribution1D`]'s, or a
/// row of a [`Distribution2D`], whose rows share two flat arrays.
#[derive(Clone, Copy)]
struct CdfView<'a> {
    /// cdf[i] = P(cell < i); cdf[n] = 1.
    cdf: &'a [f32],
    /// guide[k] = the cell of u = k/n, k = 0..=n.
    guide: &'a [u32],
}

impl CdfView<'_> {
    /// Number of cells.
    #[inline]
    fn n(&self) -> usize {
        self.cdf.len() - 1
    }

    /// The cell containing `u`: largest i with cdf[i] ≤ u, skipping empty cells.
    #[inline]
    fn find(&self, u: f32) -> usize {
        // Cells of zero probability have cdf[i] == cdf[i+1] and are never returned: the largest
        // i with cdf[i] ≤ u is past them.
        let n = self.n();
        let k = ((u * n as f32) as usize).min(n - 1);
        let (lo, hi) = (self.guide[k] as usize, self.guide[k + 1] as usize);
        // The answer lies in [lo, hi] when cdf[lo] ≤ u < cdf[hi + 1] (rounding of k/n aside,
        // which the test catches, as it catches NaN).
        if self.cdf[lo] <= u && (hi + 1 >= n || u < self.cdf[hi + 1]) && hi - lo <= GUIDE_SCAN {
            let mut i = lo;
            while i < hi && self.cdf[i + 1] <= u {
                i += 1;
            }
            return i;
        }
        find_interval(self.cdf, u)
    }

    #[inline]
    fn pmf(&self, i: usize) -> f32 {
        match (self.cdf.get(i), self.cdf.get(i + 1)) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    #[inline]
    fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let i = self.find(u);
        let (a, b) = (self.cdf[i], self.cdf[i + 1]);
        let p = b - a;
        let ur = if p > 0.0 {
            ((u - a) / p).clamp(0.0, 1.0 - f32::EPSILON)
        } else {
            0.0
        };
        (i, p, ur)
    }

    #[inline]
    fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let n = self.n();
        let (i, p, ur) = self.sample_discrete(u);
        let x = ((i as f32 + ur) / n as f32).min(1.0 - f32::EPSILON);
        (x, p * n as f32, i)
    }

    #[inline]
    fn pdf_continuous(&self, x: f32) -> f32 {
        let n = self.n();
        let i = ((x * n as f32) as usize).min(n - 1);
        self.pmf(i) * n as f32
    }
}

/// A piecewise-constant density on [0, 1)² over a `width` × `height` grid (row-major values,
/// row = v, column = u): a marginal over rows and one conditional per row. The rows' CDFs and
/// guide tables lie in two flat arrays (row r at r·(width + 1)), so a draw reads no per-row
/// header: an environment map's rows are drawn at random, and each indirection was a cache miss.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution2D {
    width: usize,
    height: usize,
    row_cdf: Vec<f32>,
    row_guide: Vec<u32>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// From `width * height` row-major cell values.
    pub fn new(values: &[f32], width: usize, height: usize) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        let mut row_cdf = Vec::with_capacity((width + 1) * height);
        let mut row_guide = Vec::with_capacity((width + 1) * height);
        let mut row = vec![0.0f32; width];
        let integrals: Vec<f32> = (0..height)
            .map(|r| {
                for (i, x) in row.iter_mut().enumerate() {
                    *x = values
                        .get(r * width + i)
                        .copied()
                        .filter(|v| v.is_finite() && *v > 0.0)
                        .unwrap_or(0.0);
                }
                push_cdf(&row, &mut row_cdf, &mut row_guide)
            })
            .collect();
        Self {
            width,
            height,
            row_cdf,
            row_guide,
            marginal: Distribution1D::new(&integrals),
        }
    }

    #[inline]
    fn row(&self, r: usize) -> CdfView<'_> {
        let span = r * (self.width + 1)..(r + 1) * (self.width + 1);
        CdfView {
            cdf: &self.row_cdf[span.clone()],
            guide: &self.row_guide[span],
        }
    }

    /// Draws (u, v) ∈ [0, 1)² and its density.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (v, pdf_v, row) = self.marginal.sample_continuous(u.y);
        let (x, pdf_u, _) = self.row(row).sample_continuous(u.x);
        (Vec2::new(x, v), pdf_v * pdf_u)
    }

    /// Draws a cell with probability ∝ its value: ((column, row), probability, `u` rescaled to
    /// [0, 1)² inside the cell). `u.y` chooses the row and `u.x` the column, as in
    /// [`Self::sample`].
    pub fn sample_discrete(&self, u: Vec2) -> ((usize, usize), f32, Vec2) {
        let (row, p_row, v) = self.marginal.sample_discrete(u.y);
        let (col, p_col, x) = self.row(row).sample_discrete(u.x);
        ((col, row), p_row * p_col, Vec2::new(x, v))
    }

    /// Discrete probability of cell (`col`, `row`) under [`Self::sample_discrete`].
    pub fn pmf(&self, col: usize, row: usize) -> f32 {
        if row < self.height {
            self.marginal.pmf(row) * self.row(row).pmf(col)
        } else {
            0.0
        }
    }

    /// Density of [`Self::sample`] at `uv`.
    pub fn pdf(&self, uv: Vec2) -> f32 {
        let h = self.height;
        let row = ((uv.y.clamp(0.0, 1.0) * h as f32) as usize).min(h - 1);
        self.marginal.pdf_continuous(uv.y.clamp(0.0, 1.0))
            * self.row(row).pdf_continuous(uv.x.clamp(0.0, 1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The guide table must not change a single draw: every cell the binary search over the CDF
    /// finds, for peaked, sparse, uniform and one-cell distributions, at CDF nodes (where ties
    /// decide), just beside them, at the ends, outside [0, 1) and at NaN.
    #[test]
    fn guided_search_is_the_binary_search_bit_for_bit() {
        let mut rng = crate::rng::Pcg32::new(7, 11);
        let mut cases: Vec<Vec<f32>> = vec![
            vec![1.0],
            vec![0.0; 5],
            vec![1.0; 1000],
            vec![0.0, 0.0, 5.0, 0.0, 0.0, 0.0, 1e-9, 0.0],
        ];
        // A bright sun in a dim sky: one cell holding nearly all, thousands of nearly empty.
        let mut sun = vec![1e-6f32; 4096];
        sun[3000] = 1e6;
        cases.push(sun);
        cases.push(
            (0..777)
                .map(|_| {
                    let x = rng.next_f32();
                    if x < 0.5 { 0.0 } else { x.powi(8) * 1e3 }
                })
                .collect(),
        );
        for values in &cases {
            let d = Distribution1D::new(values);
            let mut us: Vec<f32> = vec![
                -1.0,
                -0.0,
                0.0,
                1.0,
                2.0,
                f32::NAN,
                f32::INFINITY,
                1.0 - f32::EPSILON / 2.0,
            ];
            for &c in &d.cdf {
                us.extend([c, c.next_down(), c.next_up()]);
            }
            us.extend((0..2000).map(|_| rng.next_f32()));
            for u in us {
                assert_eq!(
                    d.view().find(u),
                    find_interval(&d.cdf, u),
                    "u = {u} over {} cells",
                    values.len()
                );
            }
        }
    }

    /// The flat row layout of `Distribution2D` draws what a marginal over one `Distribution1D`
    /// per row draws, bit for bit (rows with zeros, an all-zero row, NaN and negative values).
    #[test]
    fn two_d_rows_draw_as_separate_one_d_distributions() {
        let (w, h) = (37, 11);
        let mut rng = crate::rng::Pcg32::new(3, 5);
        let mut values: Vec<f32> = (0..w * h)
            .map(|_| {
                let x = rng.next_f32();
                if x < 0.3 { 0.0 } else { x * x * 10.0 }
            })
            .collect();
        values[5] = f32::NAN;
        values[6] = -2.0;
        for v in &mut values[4 * w..5 * w] {
            *v = 0.0;
        }
        let d = Distribution2D::new(&values, w, h);
        let rows: Vec<Distribution1D> = values.chunks(w).map(Distribution1D::new).collect();
        let marginal = Distribution1D::new(&rows.iter().map(|r| r.integral()).collect::<Vec<_>>());
        for _ in 0..5000 {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let (v, pdf_v, row) = marginal.sample_continuous(u.y);
            let (x, pdf_u, _) = rows[row].sample_continuous(u.x);
            assert_eq!(d.sample(u), (Vec2::new(x, v), pdf_v * pdf_u));
            let ((c, r), p, _) = d.sample_discrete(u);
            assert_eq!(p, marginal.pmf(r) * rows[r].pmf(c));
            assert_eq!(
                d.pdf(u),
                marginal.pdf_continuous(u.y)
                    * rows[((u.y * h as f32) as usize).min(h - 1)].pdf_continuous(u.x)
            );
        }
    }

    #[test]
    fn discrete_probabilities_follow_values() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]);
        assert!((d.pmf(0) - 0.25).abs() < 1e-6);
        assert_eq!(d.pmf(1), 0.0);
        assert!((d.pmf(2) - 0.75).abs() < 1e-6);
        let mut counts = [0usize; 3];
        let n = 10_000;
        for k in 0..n {
            let (i, p, ur) = d.sample_discrete((k as f32 + 0.5) / n as f32);
            assert!((0.0..1.0).contains(&ur));
            assert_eq!(p, d.pmf(i));
            counts[i] += 1;
        }
        assert_eq!(counts, [2500, 0, 7500]);
    }

    #[test]
    fn all_zero_is_uniform() {
        let d = Distribution1D::new(&[0.0, 0.0]);
        assert_eq!(d.integral(), 0.0);
        assert!((d.pmf(0) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn continuous_pdf_matches_sampling() {
        let d = Distribution1D::new(&[0.5, 2.0, 1.5, 0.0]);
        for k in 0..100 {
            let (x, pdf, _) = d.sample_continuous((k as f32 + 0.5) / 100.0);
            assert!((pdf - d.pdf_continuous(x)).abs() < 1e-4, "{x} {pdf}");
        }
        // x = 0.3 lies in cell 1 (value 2 of total 4): pmf 0.5, density 0.5·4 = 2.
        assert!((d.pdf_continuous(0.3) - 2.0).abs() < 1e-5);
    }

    #[test]
    fn two_d_pdf_integrates_to_one_and_matches_samples() {
        let (w, h) = (7, 5);
        let vals: Vec<f32> = (0..w * h).map(|i| ((i * 37) % 11) as f32).collect();
        let d = Distribution2D::new(&vals, w, h);
        let mut integral = 0.0;
        for j in 0..h {
            for i in 0..w {
                integral += d.pdf(Vec2::new(
                    (i as f32 + 0.5) / w as f32,
                    (j as f32 + 0.5) / h as f32,
                ));
            }
        }
        integral /= (w * h) as f32;
        assert!((integral - 1.0).abs() < 1e-4, "{integral}");
        for k in 0..200 {
            let u = Vec2::new(((k * 7919) % 200) as f32 / 200.0, (k as f32 + 0.5) / 200.0);
            let (uv, pdf) = d.sample(u);
            assert!(pdf > 0.0);
            assert!((pdf - d.pdf(uv)).abs() / pdf < 1e-3);
        }
    }

    #[test]
    fn two_d_discrete_cells_follow_values() {
        // 2 × 2 grid, row-major: row 0 = (1, 0), row 1 = (1, 2).
        let d = Distribution2D::new(&[1.0, 0.0, 1.0, 2.0], 2, 2);
        assert!((d.pmf(0, 0) - 0.25).abs() < 1e-6);
        assert_eq!(d.pmf(1, 0), 0.0);
        assert!((d.pmf(0, 1) - 0.25).abs() < 1e-6);
        assert!((d.pmf(1, 1) - 0.5).abs() < 1e-6);
        assert_eq!(d.pmf(0, 2), 0.0);
        let mut counts = [0usize; 4];
        let n = 12;
        for j in 0..n {
            for i in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let ((c, r), p, ur) = d.sample_discrete(u);
                assert_eq!(p, d.pmf(c, r));
                assert!((0.0..1.0).contains(&ur.x) && (0.0..1.0).contains(&ur.y));
                counts[r * 2 + c] += 1;
            }
        }
        assert_eq!(counts, [36, 0, 36, 72]);
    }
}
