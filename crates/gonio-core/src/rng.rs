//! Random numbers for the renderer and the checks: a PCG32 generator and stratified /
//! low-discrepancy point sets.
//!
//! # Why our own generator
//!
//! Monte Carlo results must be reproducible bit for bit: a pixel's samples, a χ² histogram, a
//! failing test. That needs a generator that is (1) deterministic across platforms and crate
//! versions (the `rand` family does not promise stable streams across major versions), (2)
//! seedable per pixel *and* per sample index without shared state (PCG32's `stream` selects one
//! of 2⁶³ independent sequences, so the renderer seeds `(pixel, pass)` and the checks seed
//! `(seed, configuration)`), (3) cheap to copy into every thread (16 bytes) and (4) about fifteen
//! lines long. [`Pcg32`] is O'Neill's PCG-XSH-RR 64/32 (`pcg32_srandom_r` / `pcg32_random_r` of
//! the reference C implementation, the generator Mitsuba 3's `chi2.py` and pbrt-v4 use), so our
//! streams are identical to theirs for the same `(seed, stream)`.
//!
//! # Stratified and low-discrepancy samples
//!
//! Independent uniforms are not the only input a BSDF's `sample` sees: a renderer feeds it
//! stratified or quasi-Monte Carlo points, whose dimensions are correlated in a structured way,
//! and a `sample` can behave on those differently from independent uniforms (Mitsuba 3 issue
//! #1288). So the χ² check also runs with [`Stratified2D`] (jittered grid) and [`Kronecker`]
//! (Roberts' R_d sequence with a Cranley–Patterson random shift); see `check::chi2` for what
//! those configurations can and cannot detect.

use glam::Vec2;

/// The largest `f32` below 1: every `[0, 1)` sample is clamped to it.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

const PCG32_MULT: u64 = 0x5851_f42d_4c95_7f2d;

/// PCG-XSH-RR 64/32 (O'Neill 2014): 64-bit state, 32-bit output, selectable stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// The generator for `seed` on stream `stream` (`pcg32_srandom_r(seed, stream)`).
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut r = Self {
            state: 0,
            inc: (stream << 1) | 1,
        };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }

    /// The next 32 uniformly distributed bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(PCG32_MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// A uniform `f32` in [0, 1): the top 24 bits scaled by 2⁻²⁴ (every value exact).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    /// A uniform `f64` in [0, 1) from 53 random bits (two draws).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        let hi = (self.next_u32() as u64) << 21;
        let lo = (self.next_u32() >> 11) as u64;
        (hi | lo) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A point uniform in [0, 1)².
    #[inline]
    pub fn next_vec2(&mut self) -> Vec2 {
        let x = self.next_f32();
        Vec2::new(x, self.next_f32())
    }

    /// A uniform integer in `0..n` (Lemire's multiply-shift with rejection, unbiased); `n > 0`.
    #[inline]
    pub fn next_below(&mut self, n: u32) -> u32 {
        assert!(n > 0, "next_below(0)");
        let threshold = n.wrapping_neg() % n;
        loop {
            let m = self.next_u32() as u64 * n as u64;
            if (m as u32) >= threshold {
                return (m >> 32) as u32;
            }
        }
    }
}

/// A jittered `nx × ny` grid over [0, 1)²: one uniform point in each cell, cells in row order.
/// `nx · ny` points in all; the iterator then ends.
#[derive(Clone, Debug)]
pub struct Stratified2D {
    nx: u32,
    ny: u32,
    index: u32,
    rng: Pcg32,
}

impl Stratified2D {
    /// An `nx × ny` jittered grid, jitter drawn from `rng`.
    pub fn new(nx: u32, ny: u32, rng: Pcg32) -> Self {
        assert!(nx > 0 && ny > 0, "empty stratified grid");
        Self {
            nx,
            ny,
            index: 0,
            rng,
        }
    }

    /// Number of points (`nx · ny`).
    pub fn len(&self) -> usize {
        self.nx as usize * self.ny as usize
    }

    /// Always false: a grid has at least one cell.
    pub fn is_empty(&self) -> bool {
        false
    }
}

impl Iterator for Stratified2D {
    type Item = Vec2;
    fn next(&mut self) -> Option<Vec2> {
        if self.index >= self.nx * self.ny {
            return None;
        }
        let (i, j) = (self.index % self.nx, self.index / self.nx);
        self.index += 1;
        let j2 = self.rng.next_vec2();
        Some(Vec2::new(
            ((i as f32 + j2.x) / self.nx as f32).min(ONE_MINUS_EPSILON),
            ((j as f32 + j2.y) / self.ny as f32).min(ONE_MINUS_EPSILON),
        ))
    }
}

/// The Kronecker (rank-1 lattice) sequence R_d of Roberts (2018): x_i = frac(s + i·α) with
/// αⱼ = φ_d^−(j+1), φ_d the unique positive root of x^(d+1) = x + 1 (φ₁ = golden ratio). Its
/// discrepancy is O(log N / N) like Halton's; a random shift `s` (Cranley–Patterson rotation)
/// keeps every point uniformly distributed, so Monte Carlo estimates stay unbiased.
#[derive(Clone, Debug)]
pub struct Kronecker<const D: usize> {
    alpha: [f64; D],
    shift: [f64; D],
    index: u64,
}

impl<const D: usize> Kronecker<D> {
    /// R_D with a random shift drawn from `rng`.
    pub fn new(rng: &mut Pcg32) -> Self {
        // φ_d by Newton's method on x^(d+1) − x − 1 from x = 2 (monotone convergence).
        let mut phi = 2.0f64;
        for _ in 0..64 {
            let f = phi.powi(D as i32 + 1) - phi - 1.0;
            let df = (D as f64 + 1.0) * phi.powi(D as i32) - 1.0;
            phi -= f / df;
        }
        let alpha = std::array::from_fn(|j| phi.powi(-(j as i32 + 1)).fract());
        let shift = std::array::from_fn(|_| rng.next_f64());
        Self {
            alpha,
            shift,
            index: 0,
        }
    }

    /// The `i`-th point.
    pub fn point(&self, i: u64) -> [f32; D] {
        std::array::from_fn(|j| {
            let x = (self.shift[j] + i as f64 * self.alpha[j]).fract() as f32;
            x.min(ONE_MINUS_EPSILON)
        })
    }
}

impl<const D: usize> Iterator for Kronecker<D> {
    type Item = [f32; D];
    fn next(&mut self) -> Option<[f32; D]> {
        let p = self.point(self.index);
        self.index += 1;
        Some(p)
    }
}

/// A random permutation of `0..n` (Fisher–Yates), for decorrelating stratified dimensions
/// (Latin-hypercube padding). Allocates: for checks and set-up, not for inner loops.
pub fn permutation(n: u32, rng: &mut Pcg32) -> Vec<u32> {
    let mut p: Vec<u32> = (0..n).collect();
    for i in (1..n).rev() {
        let j = rng.next_below(i + 1);
        p.swap(i as usize, j as usize);
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pcg32_matches_reference_stream() {
        // O'Neill's pcg-c-basic `pcg32-demo` (deterministic mode, seed 42, stream 54): the
        // first six outputs of pcg32_srandom_r(&rng, 42u, 54u).
        let mut r = Pcg32::new(42, 54);
        let expect = [
            0xa15c02b7u32,
            0x7b47f409,
            0xba1d3330,
            0x83d2f293,
            0xbfa4784b,
            0xcbed606e,
        ];
        for e in expect {
            assert_eq!(r.next_u32(), e);
        }
    }

    #[test]
    fn floats_are_in_unit_interval_with_correct_mean() {
        let mut r = Pcg32::new(7, 3);
        let n = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let x = r.next_f32();
            assert!((0.0..1.0).contains(&x));
            sum += x as f64;
        }
        // Mean of U(0,1) has standard error sqrt(1/12/n) = 6.5e-4; 5σ.
        assert!((sum / n as f64 - 0.5).abs() < 5.0 * (1.0 / 12.0 / n as f64).sqrt());
    }

    #[test]
    fn next_below_is_unbiased() {
        let mut r = Pcg32::new(1, 1);
        let mut counts = [0u32; 3];
        let n = 300_000;
        for _ in 0..n {
            counts[r.next_below(3) as usize] += 1;
        }
        // Binomial σ = sqrt(n p (1−p)) ≈ 258; 5σ.
        for c in counts {
            assert!(
                (c as f64 - n as f64 / 3.0).abs() < 5.0 * (n as f64 * 2.0 / 9.0).sqrt(),
                "{counts:?}"
            );
        }
    }

    #[test]
    fn stratified_grid_puts_one_point_per_cell() {
        let g = Stratified2D::new(7, 5, Pcg32::new(3, 0));
        assert_eq!(g.len(), 35);
        let mut seen = [false; 35];
        for p in g {
            let (i, j) = ((p.x * 7.0) as usize, (p.y * 5.0) as usize);
            assert!(!seen[j * 7 + i]);
            seen[j * 7 + i] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn kronecker_r2_has_low_discrepancy() {
        // Every one of the 16×16 cells of [0,1)² receives 4096/256 = 16 ± a few points (an iid
        // sequence would scatter by ±4σ = ±16); R₂ is known to keep cell counts within ±3.
        let mut rng = Pcg32::new(9, 9);
        let seq = Kronecker::<2>::new(&mut rng);
        let mut cells = [0i32; 256];
        for p in seq.take(4096) {
            cells[(p[1] * 16.0) as usize * 16 + (p[0] * 16.0) as usize] += 1;
        }
        let worst = cells.iter().map(|c| (c - 16).abs()).max().unwrap();
        assert!(worst <= 3, "worst deviation {worst}");
        // φ₂ = 1.32471795724 (the plastic number).
        let mut rng = Pcg32::new(0, 0);
        let k = Kronecker::<2>::new(&mut rng);
        assert!((k.alpha[0] - 1.0 / 1.324_717_957_244_746).abs() < 1e-12);
    }

    #[test]
    fn permutation_is_a_permutation() {
        let mut rng = Pcg32::new(5, 5);
        let mut p = permutation(1000, &mut rng);
        assert_ne!(p[..10], (0..10).collect::<Vec<_>>()[..]);
        p.sort_unstable();
        assert_eq!(p, (0..1000).collect::<Vec<_>>());
    }
}
