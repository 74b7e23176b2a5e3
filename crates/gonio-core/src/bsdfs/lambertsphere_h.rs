//! The exact multiple-scattering machinery of `lambertsphere`: Chandrasekhar's H-functions of the
//! truncated (l ≤ 2) Lambert-sphere phase function and the exact constants of its Fourier modes
//! m = 0 and m = 1, computed numerically in double precision and tabulated once on a (μ, c) grid.
//!
//! The truncated phase function P̃(u) = 1 − (4/3)P₁(u) + (5/16)P₂(u) (d'Eon 2021, "An Analytic
//! BRDF for Materials with Spherical Lambertian Scatterers", CGF 40(4)) has the
//! characteristic functions (Chandrasekhar 1960, *Radiative Transfer*)
//!
//! ```text
//!     Ψ⁽⁰⁾(μ) = c/384·(−15(c − 1)(4c + 9)μ⁴ + (c(20c + 281) − 346)μ² + 207)
//!     Ψ⁽¹⁾(μ) = −c/192·(μ² − 1)(5(4c + 9)μ² − 64)
//!     Ψ⁽²⁾(μ) = 15c/256·(μ² − 1)²
//! ```
//!
//! and each H⁽ᵐ⁾ solves H(μ) = 1 + μH(μ)∫₀¹ Ψ(μ′)H(μ′)/(μ + μ′) dμ′ (Chandrasekhar). The paper
//! evaluates it through K⁽ᵐ⁾ (Eqs. 24–26) and a Fock-type integral; we iterate the equation's
//! equivalent form (with Chandrasekhar's identity ∫ΨH = 1 − √(1 − 2∫Ψ))
//!
//! ```text
//!     1/H(μ) = √(1 − 2∫₀¹Ψ) + ∫₀¹ μ′Ψ(μ′)H(μ′)/(μ + μ′) dμ′
//! ```
//!
//! which converges also in the conservative case (c = 1, m = 0), on a composite Gauss–Legendre
//! rule graded towards μ = 0; the same formula gives H off the nodes.
//!
//! **Mode 1** (paper Eq. 27): f⁽¹⁾ = cH⁽¹⁾(μi)H⁽¹⁾(μo)S/(6π(μi + μo))·((1 + lμi)(1 + lμo) +
//! (45/64)m μiμo) with, from the moments aₙ = ∫₀¹H⁽¹⁾μⁿ dμ,
//! l = −5c(4c + 9)(a₁ − a₃)/(64(3 + c(a₀ − a₂))) and m = 1 + 4c/9 − 64l²/45.
//!
//! **Mode 0**: f⁽⁰⁾ = H⁽⁰⁾(μi)H⁽⁰⁾(μo)Q(μi, μo)/(2π(μi + μo)) with
//! Q = (c/2)Σₗ wₗ pₗ(μi)pₗ(μo), w = (1, 4/3, 5/16), where ψₗ = H⁽⁰⁾pₗ are Chandrasekhar's
//! ψ-functions of the three Legendre terms and pₗ are quadratics with pₗ(0) = Pₗ(0). The six
//! unknown coefficients solve the ψ-equations
//!
//! ```text
//!     ψₗ(μ) = Pₗ(μ) + (−1)ˡ (c/2) μ Σₖ wₖ ψₖ(μ) ∫₀¹ ψₖ(μ′)Pₗ(μ′)/(μ + μ′) dμ′
//! ```
//!
//! (the invariant-imbedding form of the reflection function), which we satisfy in the least
//! squares sense at 20 values of μ by Gauss–Newton, continued from c = 0 (where pₗ = Pₗ) up to
//! c = 1. Then Q = A + B(μi + μo) + Cμiμo + Dμiμo(μi + μo) + Eμi²μo² + F(μi² + μo²).

use std::sync::OnceLock;

/// Legendre weights of the truncated phase function in the m = 0 reflection function:
/// (−1)ˡ xₗ for x = (1, −4/3, 5/16).
const W0: [f64; 3] = [1.0, 4.0 / 3.0, 5.0 / 16.0];

/// A quadrature rule on [0, 1].
#[derive(Clone, Debug)]
pub struct Rule {
    /// Nodes, increasing.
    pub nodes: Vec<f64>,
    /// Weights (sum 1).
    pub weights: Vec<f64>,
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on Pₙ, Golub–Welsch-free).
fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (z * p1 - p0) / (z * z - 1.0);
            let dz = p1 / dp;
            z -= dz;
            if dz.abs() < 1e-15 {
                break;
            }
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
    (x, w)
}

impl Rule {
    /// Composite Gauss–Legendre, 16 nodes on each of the panels [0, 10⁻³], [10⁻³, 10⁻²],
    /// [10⁻², 0.05], [0.05, 0.2], [0.2, 0.5], [0.5, 1]: H has a μ ln μ term at 0.
    pub fn graded() -> Self {
        let edges = [0.0, 1e-3, 1e-2, 0.05, 0.2, 0.5, 1.0];
        let (x, w) = gauss_legendre(16);
        let mut nodes = Vec::new();
        let mut weights = Vec::new();
        for p in edges.windows(2) {
            let (a, b) = (p[0], p[1]);
            for (xi, wi) in x.iter().zip(&w) {
                nodes.push(a + (b - a) * (xi + 1.0) / 2.0);
                weights.push((b - a) / 2.0 * wi);
            }
        }
        let mut idx: Vec<usize> = (0..nodes.len()).collect();
        idx.sort_by(|&a, &b| nodes[a].total_cmp(&nodes[b]));
        Rule {
            nodes: idx.iter().map(|&i| nodes[i]).collect(),
            weights: idx.iter().map(|&i| weights[i]).collect(),
        }
    }
}

/// Chandrasekhar's characteristic function Ψ⁽ᵐ⁾(μ) of the truncated phase function (m ≤ 2).
pub fn psi(m: usize, c: f64, mu: f64) -> f64 {
    let m2 = mu * mu;
    match m {
        0 => {
            c / 384.0
                * (-15.0 * (c - 1.0) * (4.0 * c + 9.0) * m2 * m2
                    + (c * (20.0 * c + 281.0) - 346.0) * m2
                    + 207.0)
        }
        1 => -c / 192.0 * (m2 - 1.0) * (5.0 * (4.0 * c + 9.0) * m2 - 64.0),
        _ => 15.0 * c / 256.0 * (m2 - 1.0) * (m2 - 1.0),
    }
}

/// ∫₀¹ Ψ⁽ᵐ⁾(μ) dμ in closed form: c(89 + 59c − 4c²)/288, c(4c − 55)/288, c/32.
pub fn psi_integral(m: usize, c: f64) -> f64 {
    match m {
        0 => c * (89.0 + 59.0 * c - 4.0 * c * c) / 288.0,
        1 => c * (4.0 * c - 55.0) / 288.0,
        _ => c / 32.0,
    }
}

/// An H-function H⁽ᵐ⁾ for one c, known at the nodes of a rule and by its integral form anywhere.
#[derive(Clone, Debug)]
pub struct HFunction {
    /// √(1 − 2∫Ψ) (= 1/H(∞)).
    root: f64,
    /// Nodes of the rule.
    nodes: Vec<f64>,
    /// Weight × μ′Ψ(μ′) × H(μ′) at each node: what the integral form sums.
    kernel: Vec<f64>,
    /// H at the nodes.
    values: Vec<f64>,
    weights: Vec<f64>,
}

impl HFunction {
    /// Solves for H⁽ᵐ⁾ at albedo `c` ∈ [0, 1] on `rule` (to 1e-14 in the iterates).
    pub fn solve(m: usize, c: f64, rule: &Rule) -> Self {
        Self::solve_from(m, c, rule, None)
    }

    /// [`HFunction::solve`] starting from `start` (H at the nodes for a nearby c), if given.
    pub fn solve_from(m: usize, c: f64, rule: &Rule, start: Option<&HFunction>) -> Self {
        let n = rule.nodes.len();
        // The discrete ∫Ψ equals the closed form (Ψ is a quartic, integrated exactly).
        let root = (1.0 - 2.0 * psi_integral(m, c)).max(0.0).sqrt();
        let wpsi: Vec<f64> = (0..n)
            .map(|k| rule.weights[k] * rule.nodes[k] * psi(m, c, rule.nodes[k]))
            .collect();
        let mut h = start.map_or_else(|| vec![1.0; n], |s| s.values.clone());
        let mut next = vec![0.0; n];
        // In the conservative case the plain iteration alternates between two states (the map
        // is H → 1/(kH)); averaging successive iterates keeps the fixed point and converges.
        for _ in 0..20_000 {
            let mut change = 0.0f64;
            for (nj, mu) in next.iter_mut().zip(&rule.nodes) {
                let s: f64 = (0..n).map(|k| wpsi[k] * h[k] / (mu + rule.nodes[k])).sum();
                *nj = 1.0 / (root + s);
            }
            for (hj, nj) in h.iter_mut().zip(&next) {
                let v = 0.5 * (*hj + nj);
                change = change.max((v - *hj).abs());
                *hj = v;
            }
            if change < 1e-14 {
                break;
            }
        }
        Self {
            root,
            nodes: rule.nodes.clone(),
            kernel: (0..n).map(|k| wpsi[k] * h[k]).collect(),
            values: h,
            weights: rule.weights.clone(),
        }
    }

    /// H(μ) for μ ≥ 0.
    pub fn eval(&self, mu: f64) -> f64 {
        let s: f64 = self
            .nodes
            .iter()
            .zip(&self.kernel)
            .map(|(x, k)| k / (mu + x))
            .sum();
        1.0 / (self.root + s)
    }

    /// The moment ∫₀¹ H(μ)μⁿ dμ.
    pub fn moment(&self, n: i32) -> f64 {
        self.nodes
            .iter()
            .zip(&self.values)
            .zip(&self.weights)
            .map(|((x, h), w)| w * h * x.powi(n))
            .sum()
    }

    /// H at the rule's nodes.
    pub fn values(&self) -> &[f64] {
        &self.values
    }
}

/// The exact m = 1 constants (l, m) of Eq. 27 from the moments of H⁽¹⁾.
pub fn mode1_constants(c: f64, h1: &HFunction) -> (f64, f64) {
    let a: Vec<f64> = (0..4).map(|n| h1.moment(n)).collect();
    let l = -5.0 * c * (4.0 * c + 9.0) * (a[1] - a[3]) / (64.0 * (3.0 + c * (a[0] - a[2])));
    (l, 1.0 + 4.0 * c / 9.0 - 64.0 * l * l / 45.0)
}

/// Legendre polynomial Pₗ(μ), l ≤ 2.
fn legendre(l: usize, mu: f64) -> f64 {
    match l {
        0 => 1.0,
        1 => mu,
        _ => 0.5 * (3.0 * mu * mu - 1.0),
    }
}

/// The quadratics pₗ(μ) = Pₗ(0) + bₗμ + dₗμ² of the m = 0 ψ-functions, as
/// `[b₀, d₀, b₁, d₁, b₂, d₂]`.
pub type Mode0Coefficients = [f64; 6];

fn p_of(x: &Mode0Coefficients, l: usize, mu: f64) -> f64 {
    let a = [1.0, 0.0, -0.5][l];
    a + x[2 * l] * mu + x[2 * l + 1] * mu * mu
}

/// Residuals of the ψ-equations at 20 values of μ for the coefficients `x`.
#[allow(clippy::needless_range_loop)] // l and k index several arrays at once
fn mode0_residuals(c: f64, h0: &HFunction, rule: &Rule, x: &Mode0Coefficients, out: &mut Vec<f64>) {
    out.clear();
    let hn = h0.values();
    for e in 1..=20 {
        let mu = e as f64 / 20.0;
        let h = h0.eval(mu);
        // I[k][l] = ∫ H p_k P_l/(μ + μ′).
        let mut integral = [[0.0f64; 3]; 3];
        for (j, (&x1, &w)) in rule.nodes.iter().zip(&rule.weights).enumerate() {
            let base = w * hn[j] / (mu + x1);
            for (k, row) in integral.iter_mut().enumerate() {
                let pk = p_of(x, k, x1);
                for (l, v) in row.iter_mut().enumerate() {
                    *v += base * pk * legendre(l, x1);
                }
            }
        }
        for l in 0..3 {
            let sign = if l == 1 { -1.0 } else { 1.0 };
            let sum: f64 = (0..3).map(|k| W0[k] * p_of(x, k, mu) * integral[k][l]).sum();
            out.push(h * p_of(x, l, mu) - legendre(l, mu) - sign * 0.5 * c * mu * h * sum);
        }
    }
}

/// Solves the m = 0 ψ-equations for the quadratics' coefficients at albedo `c`, starting from
/// `guess` (the solution at a nearby c; at c = 0 it is Pₗ itself: (0, 0, 1, 0, 0, 3/2)).
/// Gauss–Newton with a finite-difference Jacobian and step halving.
pub fn mode0_coefficients(
    c: f64,
    h0: &HFunction,
    rule: &Rule,
    guess: Mode0Coefficients,
) -> Mode0Coefficients {
    let mut x = guess;
    let (mut r, mut rt) = (Vec::new(), Vec::new());
    let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>();
    for _ in 0..50 {
        mode0_residuals(c, h0, rule, &x, &mut r);
        let f0 = norm(&r);
        if f0 < 1e-26 {
            break;
        }
        // Jacobian columns.
        let mut jac = vec![vec![0.0; r.len()]; 6];
        for (i, col) in jac.iter_mut().enumerate() {
            let mut xp = x;
            let h = 1e-7 * (1.0 + x[i].abs());
            xp[i] += h;
            mode0_residuals(c, h0, rule, &xp, &mut rt);
            for (k, v) in col.iter_mut().enumerate() {
                *v = (rt[k] - r[k]) / h;
            }
        }
        // Normal equations JᵀJ δ = −Jᵀr.
        let mut a = [[0.0f64; 7]; 6];
        for i in 0..6 {
            for j in 0..6 {
                a[i][j] = jac[i].iter().zip(&jac[j]).map(|(p, q)| p * q).sum();
            }
            a[i][6] = -jac[i].iter().zip(&r).map(|(p, q)| p * q).sum::<f64>();
        }
        let Some(delta) = solve6(a) else { break };
        let mut step = 1.0;
        let mut improved = false;
        for _ in 0..30 {
            let mut xn = x;
            for i in 0..6 {
                xn[i] += step * delta[i];
            }
            mode0_residuals(c, h0, rule, &xn, &mut rt);
            if norm(&rt) < f0 {
                x = xn;
                improved = true;
                break;
            }
            step *= 0.5;
        }
        if !improved {
            break;
        }
    }
    x
}

/// Gaussian elimination with partial pivoting on an augmented 6 × 7 system.
#[allow(clippy::needless_range_loop)] // row operations read as in the textbook
fn solve6(mut a: [[f64; 7]; 6]) -> Option<[f64; 6]> {
    for col in 0..6 {
        let piv = (col..6).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, piv);
        for row in col + 1..6 {
            let f = a[row][col] / a[col][col];
            for k in col..7 {
                a[row][k] -= f * a[col][k];
            }
        }
    }
    let mut x = [0.0; 6];
    for row in (0..6).rev() {
        let s: f64 = (row + 1..6).map(|k| a[row][k] * x[k]).sum();
        x[row] = (a[row][6] - s) / a[row][row];
    }
    Some(x)
}

/// Q's coefficients (A, B, C, D, E, F) from the quadratics: Q = (c/2)Σ wₗ pₗ(μi)pₗ(μo).
pub fn q_coefficients(c: f64, x: &Mode0Coefficients) -> [f64; 6] {
    let a = [1.0, 0.0, -0.5];
    let mut q = [0.0; 6];
    for l in 0..3 {
        let (al, bl, dl) = (a[l], x[2 * l], x[2 * l + 1]);
        let w = 0.5 * c * W0[l];
        q[0] += w * al * al;
        q[1] += w * al * bl;
        q[2] += w * bl * bl;
        q[3] += w * bl * dl;
        q[4] += w * dl * dl;
        q[5] += w * al * dl;
    }
    q
}

/// Grid sizes of the tables: μ = u², u uniform on [0, 1]; c = 1 − s², s uniform on [0, 1].
pub const N_U: usize = 48;
/// See [`N_U`].
pub const N_S: usize = 48;
/// Padded sizes: one ghost node beyond each end, so that every cubic has its four taps.
const PU: usize = N_U + 2;
const PS: usize = N_S + 2;

/// The tables the exact model interpolates (f32, bicubic Catmull–Rom in (u, s)).
///
/// Ghost nodes: u < 0 is μ = u² again (H(u²) is even in u); u > 1 and s > 1 (c < 0) are H's
/// own values there (the integral form holds for any μ ≥ 0 and c ≤ 1); s < 0 would be c > 1, so
/// that ghost is the quadratic extrapolation 3T₀ − 3T₁ + T₂.
#[derive(Debug)]
pub struct Tables {
    /// H⁽ᵐ⁾ at padded (u, s), `[m][s * PU + u]`.
    h: [Vec<f32>; 3],
    /// Per padded s: B, C, D, F (of Q) and l, m (of mode 1).
    constants: Vec<[f32; 6]>,
}

/// Catmull–Rom weights and first padded index for coordinate `t` ∈ [0, 1] on a grid of `n`
/// points with one ghost node at each end.
#[inline]
pub fn catmull_rom(t: f32, n: usize) -> (usize, [f32; 4]) {
    let x = t.clamp(0.0, 1.0) * (n - 1) as f32;
    let i = (x as usize).min(n - 2);
    let f = x - i as f32;
    let (f2, f3) = (f * f, f * f * f);
    let w = [
        -0.5 * f3 + f2 - 0.5 * f,
        1.5 * f3 - 2.5 * f2 + 1.0,
        -1.5 * f3 + 2.0 * f2 + 0.5 * f,
        0.5 * f3 - 0.5 * f2,
    ];
    // Grid node i − 1 is padded index i.
    (i, w)
}

/// The interpolation position in c of a table lookup (shared by every lookup at that c).
#[derive(Clone, Copy, Debug)]
pub struct CPosition {
    i: usize,
    w: [f32; 4],
}

/// The interpolation position in μ of a table lookup.
#[derive(Clone, Copy, Debug)]
pub struct MuPosition {
    i: usize,
    w: [f32; 4],
}

impl CPosition {
    /// For an albedo c ∈ [0, 1].
    #[inline]
    pub fn new(c: f32) -> Self {
        let (i, w) = catmull_rom((1.0 - c).max(0.0).sqrt(), N_S);
        Self { i, w }
    }
}

impl MuPosition {
    /// For μ ∈ [0, 1].
    #[inline]
    pub fn new(mu: f32) -> Self {
        let (i, w) = catmull_rom(mu.max(0.0).sqrt(), N_U);
        Self { i, w }
    }
}

impl Tables {
    /// Builds every table (a fraction of a second; see [`tables`]).
    #[allow(clippy::needless_range_loop)] // ghost rows are written from the rows after them
    pub fn build() -> Self {
        let rule = Rule::graded();
        let mut h = [
            vec![0.0f32; PU * PS],
            vec![0.0f32; PU * PS],
            vec![0.0f32; PU * PS],
        ];
        let mut constants = vec![[0.0f32; 6]; PS];
        // From c slightly below 0 (the ghost s > 1) towards c = 1 (s = 0), each solve starting
        // from the previous one (continuation of the m = 0 solve from its c = 0 solution).
        let mut guess: Mode0Coefficients = [0.0, 0.0, 1.0, 0.0, 0.0, 1.5];
        let mut previous: Option<Vec<HFunction>> = None;
        for si in (1..PS).rev() {
            let s = (si as f64 - 1.0) / (N_S - 1) as f64;
            let c = 1.0 - s * s;
            let hs: Vec<HFunction> = (0..3)
                .map(|m| {
                    HFunction::solve_from(m, c, &rule, previous.as_ref().map(|p: &Vec<HFunction>| &p[m]))
                })
                .collect();
            for (m, hm) in hs.iter().enumerate() {
                for ui in 0..PU {
                    let u = (ui as f64 - 1.0) / (N_U - 1) as f64;
                    h[m][si * PU + ui] = hm.eval(u * u) as f32;
                }
            }
            guess = mode0_coefficients(c, &hs[0], &rule, guess);
            let q = q_coefficients(c, &guess);
            let (l, mm) = mode1_constants(c, &hs[1]);
            constants[si] = [
                q[1] as f32,
                q[2] as f32,
                q[3] as f32,
                q[5] as f32,
                l as f32,
                mm as f32,
            ];
            previous = Some(hs);
        }
        let extrapolate = |a: f32, b: f32, c: f32| 3.0 * a - 3.0 * b + c;
        for table in h.iter_mut() {
            for ui in 0..PU {
                table[ui] = extrapolate(table[PU + ui], table[2 * PU + ui], table[3 * PU + ui]);
            }
        }
        for k in 0..6 {
            constants[0][k] = extrapolate(constants[1][k], constants[2][k], constants[3][k]);
        }
        Self { h, constants }
    }

    /// H⁽ᵐ⁾(μ) at albedo c (positions from [`MuPosition::new`], [`CPosition::new`]).
    #[inline]
    pub fn h(&self, m: usize, mu: &MuPosition, c: &CPosition) -> f32 {
        let t = &self.h[m];
        let mut sum = 0.0;
        for (a, wa) in c.w.iter().enumerate() {
            let row = &t[(c.i + a) * PU + mu.i..][..4];
            let r = mu.w[0] * row[0] + mu.w[1] * row[1] + mu.w[2] * row[2] + mu.w[3] * row[3];
            sum += wa * r;
        }
        sum
    }

    /// (B, C, D, F, l, m) at albedo c.
    #[inline]
    pub fn constants(&self, c: &CPosition) -> [f32; 6] {
        let mut out = [0.0f32; 6];
        for (a, wa) in c.w.iter().enumerate() {
            let k = &self.constants[c.i + a];
            for (o, v) in out.iter_mut().zip(k) {
                *o += wa * v;
            }
        }
        out
    }
}

/// The tables, built on first use and shared by every exact `lambertsphere` afterwards.
pub fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(Tables::build)
}
