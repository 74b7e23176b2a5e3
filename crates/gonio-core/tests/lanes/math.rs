//! `lanes::math` against the standard library (and libm for erf) over each function's range.

use gonio_core::lanes::F32s;
use gonio_core::lanes::math::{acos, erf, erf_inv, exp, ln, sin_cos, sin_cos_quarter};

/// How a deviation is measured.
#[derive(Clone, Copy)]
enum Deviation {
    Absolute,
    Relative,
    /// Relative to max(1, |want|): relative for large values, absolute near 0.
    RelativeAboveOne,
}
use Deviation::*;

/// The largest deviation of `f` from `g` over `xs`.
fn max_err(
    xs: impl Iterator<Item = f32>,
    f: impl Fn(F32s<8>) -> F32s<8>,
    g: impl Fn(f32) -> f32,
    how: Deviation,
) -> f32 {
    let xs: Vec<f32> = xs.collect();
    let mut worst = 0.0f32;
    for chunk in xs.chunks(8) {
        let x = F32s::<8>::from_fn(|k| chunk[k % chunk.len()]);
        let y = f(x);
        for (k, &x) in chunk.iter().enumerate() {
            let (got, want) = (y.lane(k) as f64, g(x) as f64);
            let e = match how {
                Absolute => (got - want).abs(),
                Relative => ((got - want) / want).abs(),
                RelativeAboveOne => ((got - want) / want.abs().max(1.0)).abs(),
            };
            worst = worst.max(e as f32);
        }
    }
    worst
}

fn grid(lo: f32, hi: f32, n: usize) -> impl Iterator<Item = f32> {
    (0..=n).map(move |i| lo + (hi - lo) * i as f32 / n as f32)
}

#[test]
fn sin_cos_within_2e7_of_std() {
    let s = max_err(
        grid(-100.0, 100.0, 200_000),
        |x| sin_cos(x).0,
        |x| (x as f64).sin() as f32,
        Absolute,
    );
    let c = max_err(
        grid(-100.0, 100.0, 200_000),
        |x| sin_cos(x).1,
        |x| (x as f64).cos() as f32,
        Absolute,
    );
    assert!(s < 2e-7 && c < 2e-7, "sin {s:e}, cos {c:e}");
}

#[test]
fn sin_cos_quarter_within_2e7_of_std_on_its_range() {
    let q = std::f32::consts::FRAC_PI_4;
    let s = max_err(
        grid(-q, q, 200_000),
        |x| sin_cos_quarter(x).0,
        |x| (x as f64).sin() as f32,
        Absolute,
    );
    let c = max_err(
        grid(-q, q, 200_000),
        |x| sin_cos_quarter(x).1,
        |x| (x as f64).cos() as f32,
        Absolute,
    );
    assert!(s < 2e-7 && c < 2e-7, "sin {s:e}, cos {c:e}");
}

#[test]
fn exp_within_3_ulp_of_std() {
    // Down to where e^x is still a normal number.
    let e = max_err(
        grid(-87.0, 88.0, 200_000),
        exp,
        |x| (x as f64).exp() as f32,
        Relative,
    );
    assert!(e < 3.6e-7, "exp {e:e}");
    let edge = exp(F32s::<4>::from_array([f32::NEG_INFINITY, -1000.0, 1000.0, 0.0]));
    assert_eq!(edge.0, [0.0, 0.0, f32::INFINITY, 1.0]);
}

#[test]
fn ln_within_3_ulp_of_std() {
    // 10⁻³⁰ .. 10³⁸ geometrically, through 1.
    let e = max_err(
        (0..400_000).map(|i| 1e-30f32 * 1.0004f32.powi(i)),
        ln,
        |x| (x as f64).ln() as f32,
        RelativeAboveOne,
    );
    assert!(e < 3.6e-7, "ln {e:e}");
    let edge = ln(F32s::<4>::from_array([0.0, -1.0, f32::INFINITY, 1.0]));
    assert_eq!(edge.0[0], f32::NEG_INFINITY);
    assert!(edge.0[1].is_nan());
    assert_eq!((edge.0[2], edge.0[3]), (f32::INFINITY, 0.0));
}

#[test]
fn erf_within_6e7_of_libm() {
    // A&S 7.1.26's 1.5·10⁻⁷ plus the rounding of its single-precision evaluation (measured
    // 4.8·10⁻⁷, 8 ulp of 1).
    let e = max_err(grid(-6.0, 6.0, 200_000), erf, libm::erff, Absolute);
    assert!(e < 6e-7, "erf {e:e}");
    assert_eq!(
        erf(F32s::<2>::from_array([f32::INFINITY, f32::NEG_INFINITY])).0,
        [1.0, -1.0]
    );
}

#[test]
fn erf_inv_inverts_erf() {
    // erf(erf⁻¹(y)) = y, measured with libm's erf in double precision, relative to the
    // smaller of |y| and the tail mass 1 − |y|.
    let mut worst = 0.0f64;
    for y in grid(-0.999_99, 0.999_99, 100_000) {
        let x = erf_inv(F32s::<1>::from_array([y])).lane(0) as f64;
        worst = worst
            .max((libm::erf(x) - y as f64).abs() / (1.0 - (y as f64).abs()).min(y.abs() as f64).max(1e-30));
    }
    assert!(
        worst < 2e-5,
        "erf(erf⁻¹(y)) relative to the nearer tail {worst:e}"
    );
}

#[test]
fn acos_within_3e7_of_std() {
    let e = max_err(
        grid(-1.0, 1.0, 200_000),
        acos,
        |x| (x as f64).acos() as f32,
        Absolute,
    );
    assert!(e < 3e-7, "acos {e:e}");
}
