//! RGB → spectrum: the sigmoid-polynomial uplifting of Jakob & Hanika 2019 ("A Low-Dimensional
//! Function Space for Efficient Spectral Upsampling", Computer Graphics Forum 38(2)), with our own
//! coefficient-table optimizer.
//!
//! **Function space.** A reflectance is s(λ) = S(c₀λ² + c₁λ + c₂) with the sigmoid
//! S(x) = ½ + x / (2√(1 + x²)) ∈ (0, 1) (S(±∞) = 1, 0). λ is in nm in the stored coefficients.
//!
//! **Lookup** (res = [`TABLE_RES`]): grey colours r = g = b use the closed form c₀ = c₁ = 0,
//! c₂ = (r − ½)/√(r(1 − r)). Otherwise let c be the index of the largest component, z = rgb\[c\],
//! x = rgb[c+1]·(res−1)/z, y = rgb[c+2]·(res−1)/z (indices mod 3); the coefficients are the
//! trilinear interpolation of the table over (x, y) on a uniform grid and z on the grid
//! zₖ = smoothstep(smoothstep(k/(res−1))), smoothstep(t) = t²(3 − 2t), dense near 0 and 1.
//!
//! **Optimizer** ([`optimize_table`]), after the description in the paper and pbrt-v4's
//! `rgb2spec_opt`, but with the 1 nm CIE 1931 tables and D65 of [`crate::color`] as quadrature so
//! that [`crate::color::spectrum_to_linear_srgb`] reproduces the target tightly:
//! * in normalized wavelength t = (λ − 360)/470, coefficients (A, B, C), ρᵢ = S(A tᵢ² + B tᵢ + C) at
//!   λᵢ = 360, 361, …, 830 nm;
//! * rgb(ρ) = M_XYZ→sRGB · Σᵢ x̄ȳz̄(λᵢ) D65(λᵢ) ρᵢ / Σᵢ ȳ(λᵢ) D65(λᵢ);
//! * residual r = Lab(target) − Lab(rgb(ρ)) in CIELAB relative to the D65 white (CIE76 ΔE);
//! * Gauss–Newton: 3×3 Jacobian by central differences (step 1e-4), solve J·δ = r with partial
//!   pivoting, coefficients −= δ; if max |coefficient| > 200 all three are scaled back to 200
//!   (no step functions); stop when |r|² < 1e-6 or after 15 steps;
//! * continuation: for each largest component l, each grid (x, y), start from the flat spectrum
//!   (0, 0, 0) at z-index res/5 and walk up to res − 1, each solve warm-started from the previous
//!   one, then walk down from res/5 − 1 to 0 starting from the res/5 solution;
//! * storage in nm: with c₀ = 360, c₁ = 1/470, A′ = A c₁², B′ = B c₁ − 2A c₀ c₁²,
//!   C′ = C − B c₀ c₁ + A (c₀ c₁)².
//!
//! **Polish** ([`srgb_to_sigmoid_refined`], used by `Spectrum::rgb_*`): the trilinear
//! interpolation of the res-64 table is off by up to 1.8e-3 in linear sRGB (median 2e-4, measured
//! on 2000 random colours in [0.02, 0.98]³, worst near saturated near-whites where the coefficients
//! diverge); up to six Newton steps on the linear sRGB residual with the analytic Jacobian
//! Σᵢ tbl\[k\]\[i\] S′(xᵢ) (tᵢ², tᵢ, 1), S′(x) = ½(1 + x²)^(−3/2), bring the round trip to ≈ 5e-6.
//!
//! **Table file** (`data/rgb2spec_srgb.bin`, little endian, written by
//! `cargo run -p gonio-core --release --example rgb2spec_opt`): the 8 bytes `GRGB2SP1`, `u32` res,
//! res `f32` z nodes, then 3·res³·3 `f32` coefficients at index ((l·res + k)·res + j)·res + i
//! (l = largest component, k = z, j = y, i = x), three per entry. The library embeds it with
//! `include_bytes!`; no file is read at run time.

use crate::color::{LINEAR_SRGB_FROM_XYZ, XYZ_FROM_LINEAR_SRGB, cie_xyz, d65};
use crate::math::find_interval;
use std::sync::LazyLock;

/// Resolution of the shipped sRGB table along each axis.
pub const TABLE_RES: usize = 64;

const MAGIC: &[u8; 8] = b"GRGB2SP1";
const LAMBDA_START: f64 = 360.0;
const LAMBDA_RANGE: f64 = 470.0;
const N_QUAD: usize = 471;

/// The sigmoid S(x) = ½ + x / (2√(1 + x²)), with S(−∞) = 0 and S(+∞) = 1.
#[inline]
pub fn sigmoid(x: f32) -> f32 {
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

#[inline]
fn sigmoid64(x: f64) -> f64 {
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

/// smoothstep(t) = t²(3 − 2t).
#[inline]
fn smoothstep(t: f64) -> f64 {
    t * t * (3.0 - 2.0 * t)
}

/// The z grid of a table of resolution `res`: zₖ = smoothstep(smoothstep(k/(res − 1))).
pub fn z_nodes(res: usize) -> Vec<f32> {
    (0..res)
        .map(|k| smoothstep(smoothstep(k as f64 / (res - 1) as f64)) as f32)
        .collect()
}

/// A sigmoid-polynomial spectrum s(λ) = S(c₀λ² + c₁λ + c₂), λ in nm: a reflectance in (0, 1).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct RgbSigmoid {
    /// Coefficient of λ².
    pub c0: f32,
    /// Coefficient of λ.
    pub c1: f32,
    /// Constant term.
    pub c2: f32,
}

impl RgbSigmoid {
    /// The flat spectrum of value `v` ∈ [0, 1]: c₂ = (v − ½)/√(v(1 − v)) (±∞ at 0 and 1).
    pub fn constant(v: f32) -> Self {
        let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
        let c2 = if v <= 0.0 {
            f32::NEG_INFINITY
        } else if v >= 1.0 {
            f32::INFINITY
        } else {
            ((v as f64 - 0.5) / (v as f64 * (1.0 - v as f64)).sqrt()) as f32
        };
        Self { c0: 0.0, c1: 0.0, c2 }
    }

    /// Value at `lambda` nm.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        if self.c0 == 0.0 && self.c1 == 0.0 {
            return sigmoid(self.c2);
        }
        // Horner form, as in pbrt.
        sigmoid((self.c0 * lambda + self.c1) * lambda + self.c2)
    }

    /// Values at four wavelengths at once (nm), each equal bit for bit to [`Self::eval`]'s: the
    /// same operations in the same order, lane by lane (a path's spectra are evaluated four
    /// wavelengths at a time, so this is the form the renderer's hot paths call).
    #[inline]
    pub fn eval4(&self, lambda: glam::Vec4) -> glam::Vec4 {
        use glam::Vec4;
        // With c₀ = c₁ = 0 the polynomial is exactly c₂ (0·λ + 0 = 0 for finite λ), as in `eval`.
        let x = (Vec4::splat(self.c0) * lambda + Vec4::splat(self.c1)) * lambda + Vec4::splat(self.c2);
        let s = Vec4::splat(0.5) + x / (Vec4::splat(2.0) * (Vec4::ONE + x * x).sqrt());
        if x.is_finite() {
            return s;
        }
        // ±∞ (a flat 0 or 1, or an overflowing polynomial): the limits, as `sigmoid` gives them.
        Vec4::from_array(x.to_array().map(sigmoid))
    }

    /// True when the spectrum does not depend on λ.
    pub fn is_flat(&self) -> bool {
        self.c0 == 0.0 && self.c1 == 0.0
    }

    /// Maximum over [360, 830] nm: S is monotonic, so the largest of the values at both ends and
    /// at the vertex −c₁/(2c₀) of the polynomial if it lies inside.
    pub fn max_value(&self) -> f32 {
        let mut m = self.eval(360.0).max(self.eval(830.0));
        if self.c0 != 0.0 {
            let vertex = -self.c1 / (2.0 * self.c0);
            if (360.0..=830.0).contains(&vertex) {
                m = m.max(self.eval(vertex));
            }
        }
        m
    }
}

/// A coefficient table for one RGB gamut (here sRGB / D65).
#[derive(Clone, Debug, PartialEq)]
pub struct RgbToSpectrumTable {
    res: usize,
    z_nodes: Vec<f32>,
    coeffs: Vec<f32>,
}

impl RgbToSpectrumTable {
    /// From the table file format (module docs). Errors name what is wrong.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, String> {
        if bytes.len() < 12 || &bytes[..8] != MAGIC {
            return Err("rgb2spec table: missing GRGB2SP1 header".into());
        }
        let res = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize;
        if !(2..=256).contains(&res) {
            return Err(format!("rgb2spec table: resolution {res} out of range 2..=256"));
        }
        let n_coeffs = 3 * res * res * res * 3;
        let expect = 12 + 4 * (res + n_coeffs);
        if bytes.len() != expect {
            return Err(format!(
                "rgb2spec table: {} bytes, expected {expect} for res {res}",
                bytes.len()
            ));
        }
        let floats: Vec<f32> = bytes[12..]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let (z, c) = floats.split_at(res);
        if !z.windows(2).all(|w| w[0] < w[1]) || c.iter().any(|v| !v.is_finite()) {
            return Err("rgb2spec table: z nodes not increasing or non-finite coefficients".into());
        }
        Ok(Self {
            res,
            z_nodes: z.to_vec(),
            coeffs: c.to_vec(),
        })
    }

    /// Builds a table from its parts (`coeffs` as returned by [`optimize_table`]).
    pub fn from_parts(res: usize, coeffs: Vec<f32>) -> Result<Self, String> {
        if res < 2 || coeffs.len() != 3 * res * res * res * 3 {
            return Err(format!(
                "rgb2spec table: {} coefficients do not fit res {res}",
                coeffs.len()
            ));
        }
        Ok(Self {
            res,
            z_nodes: z_nodes(res),
            coeffs,
        })
    }

    /// The table file bytes (module docs).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(12 + 4 * (self.z_nodes.len() + self.coeffs.len()));
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&(self.res as u32).to_le_bytes());
        for v in self.z_nodes.iter().chain(&self.coeffs) {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out
    }

    /// Resolution along each axis.
    pub fn res(&self) -> usize {
        self.res
    }

    /// The stored coefficients of grid entry (l, k, j, i) (largest component, z, y, x).
    pub fn entry(&self, l: usize, k: usize, j: usize, i: usize) -> [f32; 3] {
        let idx = 3 * (((l * self.res + k) * self.res + j) * self.res + i);
        [self.coeffs[idx], self.coeffs[idx + 1], self.coeffs[idx + 2]]
    }

    /// Sigmoid coefficients of a reflectance `rgb` ∈ [0, 1]³ (components are clamped to [0, 1];
    /// NaN counts as 0).
    pub fn lookup(&self, rgb: [f32; 3]) -> RgbSigmoid {
        let rgb = rgb.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) });
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            return RgbSigmoid::constant(rgb[0]);
        }
        let c = if rgb[0] > rgb[1] {
            if rgb[0] > rgb[2] { 0 } else { 2 }
        } else if rgb[1] > rgb[2] {
            1
        } else {
            2
        };
        let res = self.res;
        let z = rgb[c];
        let scale = (res - 1) as f32 / z;
        let x = rgb[(c + 1) % 3] * scale;
        let y = rgb[(c + 2) % 3] * scale;
        let xi = (x as usize).min(res - 2);
        let yi = (y as usize).min(res - 2);
        // Largest k with z_nodes[k] <= z, kept inside [0, res − 2].
        let zi = find_interval(&self.z_nodes, z);
        let dx = x - xi as f32;
        let dy = y - yi as f32;
        let dz = (z - self.z_nodes[zi]) / (self.z_nodes[zi + 1] - self.z_nodes[zi]);
        let mut out = [0.0f32; 3];
        for (o, out_c) in out.iter_mut().enumerate() {
            let co = |dk: usize, dj: usize, di: usize| {
                self.coeffs[3 * (((c * res + zi + dk) * res + yi + dj) * res + xi + di) + o]
            };
            let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
            *out_c = lerp(
                dz,
                lerp(
                    dy,
                    lerp(dx, co(0, 0, 0), co(0, 0, 1)),
                    lerp(dx, co(0, 1, 0), co(0, 1, 1)),
                ),
                lerp(
                    dy,
                    lerp(dx, co(1, 0, 0), co(1, 0, 1)),
                    lerp(dx, co(1, 1, 0), co(1, 1, 1)),
                ),
            );
        }
        RgbSigmoid {
            c0: out[0],
            c1: out[1],
            c2: out[2],
        }
    }
}

static SRGB_TABLE_BYTES: &[u8] = include_bytes!("../data/rgb2spec_srgb.bin");

static SRGB_TABLE: LazyLock<RgbToSpectrumTable> = LazyLock::new(|| {
    // The embedded table is validated by the tests of this module; a broken file is a build defect.
    RgbToSpectrumTable::from_bytes(SRGB_TABLE_BYTES).expect("embedded rgb2spec_srgb.bin is valid")
});

/// The shipped sRGB (D65) table, decoded on first use.
pub fn srgb_table() -> &'static RgbToSpectrumTable {
    &SRGB_TABLE
}

/// Sigmoid coefficients of an sRGB reflectance (components clamped to [0, 1]).
pub fn srgb_to_sigmoid(rgb: [f32; 3]) -> RgbSigmoid {
    srgb_table().lookup(rgb)
}

/// Sigmoid coefficients of an sRGB reflectance: the table lookup polished by Newton's method on
/// the linear sRGB residual (module docs: the same 1 nm D65 quadrature), so that
/// [`crate::color::spectrum_to_linear_srgb`] returns `rgb` to ~1e-5. The polish costs a few µs;
/// use [`srgb_to_sigmoid`] for bulk data such as bitmap texels (table error ≲ 2e-3).
pub fn srgb_to_sigmoid_refined(rgb: [f32; 3]) -> RgbSigmoid {
    let rgb = rgb.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) });
    refine(srgb_to_sigmoid(rgb), rgb)
}

/// nm coefficients → normalized-λ coefficients (t = (λ − 360)/470).
fn from_nm(s: RgbSigmoid) -> [f64; 3] {
    let (a, b, c) = (s.c0 as f64, s.c1 as f64, s.c2 as f64);
    [
        a * LAMBDA_RANGE * LAMBDA_RANGE,
        LAMBDA_RANGE * (2.0 * LAMBDA_START * a + b),
        (a * LAMBDA_START + b) * LAMBDA_START + c,
    ]
}

/// Newton polish of `s` towards the linear sRGB `target` (reflectance, each component in [0, 1]).
fn refine(s: RgbSigmoid, target: [f32; 3]) -> RgbSigmoid {
    if s.is_flat() || !(s.c0.is_finite() && s.c1.is_finite() && s.c2.is_finite()) {
        return s;
    }
    let q = &*QUADRATURE;
    let target = target.map(|v| v as f64);
    let err = |c: [f64; 3]| {
        let rgb = coeffs_to_rgb(q, c);
        [rgb[0] - target[0], rgb[1] - target[1], rgb[2] - target[2]]
    };
    let norm = |e: [f64; 3]| e.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut c = from_nm(s);
    let mut e = err(c);
    for _ in 0..6 {
        if norm(e) < 1e-7 {
            break;
        }
        // J[k][m] = Σᵢ tbl[k][i] S′(xᵢ) φₘ(tᵢ), φ = (t², t, 1), S′(x) = ½ (1 + x²)^(−3/2).
        let mut jac = [[0.0f64; 3]; 3];
        for i in 0..N_QUAD {
            let t = q.t[i];
            let x = (c[0] * t + c[1]) * t + c[2];
            let ds = 0.5 / (1.0 + x * x).powf(1.5);
            let phi = [t * t, t, 1.0];
            for (row, tbl) in jac.iter_mut().zip(&q.rgb_tbl) {
                let w = tbl[i] * ds;
                for (j, p) in row.iter_mut().zip(phi) {
                    *j += w * p;
                }
            }
        }
        let Some(step) = solve3(jac, e) else { break };
        // Backtracking: accept the largest of 1, ½, ¼, ⅛ of the step that lowers the error.
        let mut improved = false;
        let mut f = 1.0;
        for _ in 0..4 {
            let trial = [c[0] - f * step[0], c[1] - f * step[1], c[2] - f * step[2]];
            let et = err(trial);
            if trial.iter().all(|v| v.is_finite() && v.abs() < 1e4) && norm(et) < norm(e) {
                c = trial;
                e = et;
                improved = true;
                break;
            }
            f *= 0.5;
        }
        if !improved {
            break;
        }
    }
    let [c0, c1, c2] = to_nm(c);
    let refined = RgbSigmoid { c0, c1, c2 };
    // Keep the table's answer unless the polish (after rounding to f32) is better.
    let check = |s: RgbSigmoid| norm(err(from_nm(s)));
    if check(refined) <= check(s) { refined } else { s }
}

// ------------------------------------------------------------------------------------------------
// Optimizer
// ------------------------------------------------------------------------------------------------

/// Quadrature data shared by every solve: rgb_tbl[k][i] maps ρ(λᵢ) to linear sRGB channel k.
struct Quadrature {
    t: [f64; N_QUAD],
    rgb_tbl: [[f64; N_QUAD]; 3],
    white_xyz: [f64; 3],
}

static QUADRATURE: LazyLock<Quadrature> = LazyLock::new(|| {
    let mut t = [0.0; N_QUAD];
    let mut xyz_w = [[0.0f64; N_QUAD]; 3];
    let mut norm = 0.0f64;
    for i in 0..N_QUAD {
        let lambda = LAMBDA_START as f32 + i as f32;
        t[i] = i as f64 / LAMBDA_RANGE;
        let cmf = cie_xyz(lambda);
        let ill = d65(lambda) as f64;
        xyz_w[0][i] = cmf.x as f64 * ill;
        xyz_w[1][i] = cmf.y as f64 * ill;
        xyz_w[2][i] = cmf.z as f64 * ill;
        norm += cmf.y as f64 * ill;
    }
    let m = LINEAR_SRGB_FROM_XYZ.to_cols_array_2d();
    let mut rgb_tbl = [[0.0f64; N_QUAD]; 3];
    let mut white_xyz = [0.0f64; 3];
    for i in 0..N_QUAD {
        for k in 0..3 {
            // m[col][row]
            rgb_tbl[k][i] = (0..3).map(|j| m[j][k] as f64 * xyz_w[j][i]).sum::<f64>() / norm;
        }
        for j in 0..3 {
            white_xyz[j] += xyz_w[j][i] / norm;
        }
    }
    Quadrature {
        t,
        rgb_tbl,
        white_xyz,
    }
});

fn lab_f(t: f64) -> f64 {
    const DELTA: f64 = 6.0 / 29.0;
    if t > DELTA * DELTA * DELTA {
        t.cbrt()
    } else {
        t / (3.0 * DELTA * DELTA) + 4.0 / 29.0
    }
}

/// CIELAB of a linear sRGB colour relative to the quadrature's D65 white.
fn rgb_to_lab(q: &Quadrature, rgb: [f64; 3]) -> [f64; 3] {
    let m = XYZ_FROM_LINEAR_SRGB.to_cols_array_2d();
    let xyz: [f64; 3] = std::array::from_fn(|r| (0..3).map(|c| m[c][r] as f64 * rgb[c]).sum());
    let fx = lab_f(xyz[0] / q.white_xyz[0]);
    let fy = lab_f(xyz[1] / q.white_xyz[1]);
    let fz = lab_f(xyz[2] / q.white_xyz[2]);
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// Linear sRGB under D65 of the sigmoid spectrum with normalized coefficients `c`.
fn coeffs_to_rgb(q: &Quadrature, c: [f64; 3]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for i in 0..N_QUAD {
        let t = q.t[i];
        let s = sigmoid64((c[0] * t + c[1]) * t + c[2]);
        for (k, o) in out.iter_mut().enumerate() {
            *o += q.rgb_tbl[k][i] * s;
        }
    }
    out
}

fn residual(q: &Quadrature, c: [f64; 3], target_lab: [f64; 3]) -> [f64; 3] {
    let lab = rgb_to_lab(q, coeffs_to_rgb(q, c));
    [
        target_lab[0] - lab[0],
        target_lab[1] - lab[1],
        target_lab[2] - lab[2],
    ]
}

/// Solves the 3×3 system a·x = b by Gaussian elimination with partial pivoting; `None` if singular.
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for col in 0..3 {
        let piv = (col..3).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() < 1e-15 {
            return None;
        }
        a.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..3 {
            let f = a[row][col] / a[col][col];
            let pivot_row = a[col];
            for (v, p) in a[row].iter_mut().zip(pivot_row).skip(col) {
                *v -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; 3];
    for row in (0..3).rev() {
        let s: f64 = (row + 1..3).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / a[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Gauss–Newton fit of normalized coefficients to a linear sRGB target, warm-started from `c`.
/// Returns the coefficients and the final squared CIELAB residual.
fn gauss_newton(q: &Quadrature, target_rgb: [f64; 3], mut c: [f64; 3]) -> ([f64; 3], f64) {
    const MAX_ITER: usize = 15;
    const STEP: f64 = 1e-4;
    let target_lab = rgb_to_lab(q, target_rgb);
    let mut r2 = f64::INFINITY;
    for _ in 0..MAX_ITER {
        let r = residual(q, c, target_lab);
        r2 = r.iter().map(|v| v * v).sum();
        if r2 < 1e-6 {
            break;
        }
        // J[i][j] = ∂r_i/∂c_j by central differences.
        let mut jac = [[0.0f64; 3]; 3];
        for j in 0..3 {
            let (mut cp, mut cm) = (c, c);
            cp[j] += STEP;
            cm[j] -= STEP;
            let rp = residual(q, cp, target_lab);
            let rm = residual(q, cm, target_lab);
            for i in 0..3 {
                jac[i][j] = (rp[i] - rm[i]) / (2.0 * STEP);
            }
        }
        let Some(dx) = solve3(jac, r) else { break };
        for j in 0..3 {
            c[j] -= dx[j];
        }
        let max = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if max > 200.0 {
            for v in &mut c {
                *v *= 200.0 / max;
            }
        }
    }
    (c, r2)
}

/// Normalized-λ coefficients (t = (λ − 360)/470) → nm coefficients.
fn to_nm(c: [f64; 3]) -> [f32; 3] {
    let (c0, c1) = (LAMBDA_START, 1.0 / LAMBDA_RANGE);
    let (a, b, cc) = (c[0], c[1], c[2]);
    [
        (a * c1 * c1) as f32,
        (b * c1 - 2.0 * a * c0 * c1 * c1) as f32,
        (cc - b * c0 * c1 + a * (c0 * c1).powi(2)) as f32,
    ]
}

/// Fits one table row: largest component `l`, y index `j`, x index `i`, all z indices. Returns
/// `res` coefficient triples in nm units (index = z index), by the continuation of the module docs.
pub fn optimize_row(res: usize, l: usize, j: usize, i: usize) -> Vec<[f32; 3]> {
    let q = &*QUADRATURE;
    let z = z_nodes(res);
    let x = i as f64 / (res - 1) as f64;
    let y = j as f64 / (res - 1) as f64;
    let target = |k: usize| {
        let b = z[k] as f64;
        let mut rgb = [0.0; 3];
        rgb[l] = b;
        rgb[(l + 1) % 3] = x * b;
        rgb[(l + 2) % 3] = y * b;
        rgb
    };
    let start = res / 5;
    let mut out = vec![[0.0f32; 3]; res];
    let mut c = [0.0f64; 3];
    let mut c_start = c;
    for (k, o) in out.iter_mut().enumerate().skip(start) {
        c = gauss_newton(q, target(k), c).0;
        if k == start {
            c_start = c;
        }
        *o = to_nm(c);
    }
    c = c_start;
    for k in (0..start).rev() {
        c = gauss_newton(q, target(k), c).0;
        out[k] = to_nm(c);
    }
    out
}

/// Fits the whole sRGB table at resolution `res` (single-threaded; about a minute at res 64 in
/// release builds). Layout as in the module docs; pass the result to
/// [`RgbToSpectrumTable::from_parts`].
pub fn optimize_table(res: usize) -> Vec<f32> {
    let mut coeffs = vec![0.0f32; 3 * res * res * res * 3];
    for l in 0..3 {
        for j in 0..res {
            for i in 0..res {
                store_row(&mut coeffs, res, l, j, i, &optimize_row(res, l, j, i));
            }
        }
    }
    coeffs
}

/// Writes a row computed by [`optimize_row`] into a coefficient array of the table layout.
pub fn store_row(coeffs: &mut [f32], res: usize, l: usize, j: usize, i: usize, row: &[[f32; 3]]) {
    for (k, c) in row.iter().enumerate() {
        let idx = 3 * (((l * res + k) * res + j) * res + i);
        coeffs[idx..idx + 3].copy_from_slice(c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigmoid_limits_and_inverse() {
        assert_eq!(sigmoid(f32::INFINITY), 1.0);
        assert_eq!(sigmoid(f32::NEG_INFINITY), 0.0);
        assert_eq!(sigmoid(0.0), 0.5);
        for v in [0.01f32, 0.2, 0.5, 0.77, 0.999] {
            let s = RgbSigmoid::constant(v);
            assert!((s.eval(500.0) - v).abs() < 1e-6, "{v}");
        }
        assert_eq!(RgbSigmoid::constant(0.0).eval(600.0), 0.0);
        assert_eq!(RgbSigmoid::constant(1.0).eval(600.0), 1.0);
    }

    #[test]
    fn z_nodes_are_smoothstep_squared() {
        let z = z_nodes(64);
        assert_eq!(z[0], 0.0);
        assert_eq!(z[63], 1.0);
        let t = 20.0f64 / 63.0;
        assert!((z[20] as f64 - smoothstep(smoothstep(t))).abs() < 1e-7);
        assert!(z.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn solve3_solves_and_rejects_singular() {
        let a = [[2.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 4.0]];
        let x = solve3(a, [3.0, 5.0, 5.0]).unwrap();
        for (v, e) in x.iter().zip([1.0, 1.0, 1.0]) {
            assert!((v - e).abs() < 1e-12);
        }
        assert!(
            solve3(
                [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]],
                [1.0, 2.0, 3.0]
            )
            .is_none()
        );
    }

    #[test]
    fn normalized_to_nm_conversion_preserves_the_polynomial() {
        let c = [3.0, -7.0, 1.5];
        let nm = to_nm(c);
        for lambda in [360.0f64, 512.0, 830.0] {
            let t = (lambda - 360.0) / 470.0;
            let p = (c[0] * t + c[1]) * t + c[2];
            let q = (nm[0] as f64 * lambda + nm[1] as f64) * lambda + nm[2] as f64;
            assert!((p - q).abs() < 1e-4, "{p} vs {q}");
        }
    }

    #[test]
    fn embedded_table_is_valid_and_round_trips_through_bytes() {
        let t = RgbToSpectrumTable::from_bytes(SRGB_TABLE_BYTES).unwrap();
        assert_eq!(t.res(), TABLE_RES);
        assert_eq!(RgbToSpectrumTable::from_bytes(&t.to_bytes()).unwrap(), t);
        assert!(RgbToSpectrumTable::from_bytes(b"nonsense").is_err());
        assert!(RgbToSpectrumTable::from_bytes(&SRGB_TABLE_BYTES[..SRGB_TABLE_BYTES.len() - 4]).is_err());
    }

    #[test]
    fn optimizer_reproduces_stored_table_entries() {
        // Keeps generator and table in sync: re-fit a few rows and compare with the shipped table.
        // On the machine that generated the table the coefficients agree bit for bit; a different
        // libm may move a converged fit inside its tolerance, so an entry also passes when its
        // spectrum agrees within 2e-4 everywhere (a changed quadrature, illuminant or matrix moves
        // colours by 1e-3 and more).
        let table = srgb_table();
        for (l, j, i) in [(0, 0, 0), (1, 17, 40), (2, 63, 5), (0, 31, 63)] {
            let row = optimize_row(TABLE_RES, l, j, i);
            for (k, c) in row.iter().enumerate() {
                let s = table.entry(l, k, j, i);
                let same_coeffs = (0..3).all(|o| (c[o] - s[o]).abs() <= 1e-5 * s[o].abs().max(1.0));
                let (a, b) = (
                    RgbSigmoid {
                        c0: c[0],
                        c1: c[1],
                        c2: c[2],
                    },
                    RgbSigmoid {
                        c0: s[0],
                        c1: s[1],
                        c2: s[2],
                    },
                );
                let diff = (360..=830)
                    .map(|lambda| (a.eval(lambda as f32) - b.eval(lambda as f32)).abs())
                    .fold(0.0, f32::max);
                assert!(
                    same_coeffs || diff < 2e-4,
                    "entry ({l},{k},{j},{i}): refit {c:?} vs stored {s:?} (Δs {diff})"
                );
            }
        }
    }

    #[test]
    fn max_value_matches_a_brute_force_scan() {
        let table = srgb_table();
        let mut state = 0x2545F4914F6CDD1Du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        for _ in 0..200 {
            let s = table.lookup([next(), next(), next()]);
            let brute = (0..=470 * 16)
                .map(|k| s.eval(360.0 + k as f32 / 16.0))
                .fold(0.0f32, f32::max);
            assert!(
                (s.max_value() - brute).abs() < 1e-4,
                "{s:?}: {} vs {brute}",
                s.max_value()
            );
            // An upper bound up to the f32 rounding of the polynomial near its vertex.
            assert!(s.max_value() >= brute - 1e-4);
        }
        // A polynomial with its vertex inside the range: a bump at 550 nm.
        let bump = RgbSigmoid {
            c0: -1e-3,
            c1: 1.1,
            c2: -300.0,
        };
        let brute = (0..=470 * 16)
            .map(|k| bump.eval(360.0 + k as f32 / 16.0))
            .fold(0.0f32, f32::max);
        assert!((bump.max_value() - brute).abs() < 1e-4);
    }

    #[test]
    fn eval4_is_eval_bit_for_bit() {
        // Fitted coefficients of real colours, flat ones with their infinite limits, and
        // polynomials large enough that x² overflows.
        let mut sets: Vec<RgbSigmoid> = [0.0f32, 0.03, 0.5, 0.97, 1.0]
            .into_iter()
            .map(RgbSigmoid::constant)
            .collect();
        for rgb in [
            [0.8f32, 0.1, 0.1],
            [0.1, 0.7, 0.2],
            [0.2, 0.3, 0.9],
            [0.95, 0.9, 0.1],
        ] {
            sets.push(srgb_to_sigmoid_refined(rgb));
        }
        sets.push(RgbSigmoid {
            c0: 1e30,
            c1: -1e30,
            c2: 3.0,
        });
        sets.push(RgbSigmoid {
            c0: -0.0,
            c1: 0.0,
            c2: -0.0,
        });
        for s in sets {
            for k in 0..64 {
                let l = glam::Vec4::new(360.0, 441.3, 555.5, 830.0) + k as f32 * 1.37;
                let v = s.eval4(l).to_array();
                for i in 0..4 {
                    assert_eq!(v[i].to_bits(), s.eval(l[i]).to_bits(), "{s:?} at {}", l[i]);
                }
            }
        }
    }
}
