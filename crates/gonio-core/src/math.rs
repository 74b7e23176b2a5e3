//! Small numeric helpers shared by the tables and the samplers.

/// The interval of a sorted array that contains `x`: the largest `i` with `a[i] <= x`, clamped to
/// `[0, a.len() − 2]` so that `a[i + 1]` exists (0 when `a` has fewer than two entries). Values
/// below `a[0]` give 0 and values at or above the last entry give `a.len() − 2`, so callers
/// extrapolate from the first or last interval or clamp their weight.
///
/// pbrt-v4's `FindInterval` (Pharr, Jakob and Humphreys, *Physically Based Rendering*, 4th ed.,
/// `util/math.h`), by binary search. Used for the sorted axes of spectra, the RGB-to-spectrum
/// table and tabulated BRDFs, and for the CDFs of [`crate::sampling::Distribution1D`].
#[inline]
pub fn find_interval(a: &[f32], x: f32) -> usize {
    // partition_point is the first index with a[i] > x (the array is sorted).
    a.partition_point(|&v| v <= x)
        .saturating_sub(1)
        .min(a.len().saturating_sub(2))
}

/// ⌊x⌋, bit for bit `f32::floor` (−0.0 and the infinities included; NaN stays NaN), without a
/// call.
///
/// The portable x86-64 target has no rounding instruction (`roundss` is SSE4.1), so
/// `f32::floor` there is a call into compiler-builtins' software floor, about 24 instructions
/// (1.7 % of the copper preview's, from the lookups of environment maps, bitmaps, spectra and
/// the film). Values of magnitude 2²³ and above, and NaN, are their own floor; below, the
/// truncation toward zero, one less where it rounded up.
#[inline(always)]
pub fn floor(x: f32) -> f32 {
    if !(x.abs() < 8_388_608.0) {
        return x;
    }
    let t = x as i32 as f32;
    if t > x { t - 1.0 } else { t.copysign(x) }
}

/// ⌈x⌉ as −⌊−x⌋ ([`floor`]), bit for bit `f32::ceil`, without a call.
#[inline]
pub fn ceil(x: f32) -> f32 {
    -floor(-x)
}

/// `i` wrapped into `[0, n)` (`n > 0`), as `i.rem_euclid(n)`, without the division where `i` is at
/// most one period outside: the texel indices of a lookup at coordinates in [0, 1], the
/// common case of repeating textures and environment maps (a 64-bit division is tens of cycles,
/// four to eight of them per bilinear lookup).
#[inline]
pub fn wrap_repeat(i: i64, n: i64) -> i64 {
    debug_assert!(n > 0, "wrap_repeat needs a positive period, not {n}");
    if i >= 0 {
        if i < n {
            i
        } else if i - n < n {
            i - n
        } else {
            i.rem_euclid(n)
        }
    } else if i >= -n {
        i + n
    } else {
        i.rem_euclid(n)
    }
}

/// Below this `x`, `eˣ` rounds to 0 in `f32` (it is below 2⁻¹⁵⁰, the half of the smallest
/// subnormal): −0x1.9fe368p6 ≈ −103.972 076, the first `f32` above ln 2⁻¹⁵⁰ and glibc's `expf`
/// underflow bound.
const EXP_ZERO_BELOW: f32 = f32::from_bits(0xC2CF_F1B4);

/// `eˣ`, bit for bit `f32::exp`, that returns 0 for exponents below ln 2⁻¹⁵⁰ without calling the
/// platform's `expf`, whose underflow path (glibc's `__math_uflowf`, which sets `errno`) costs
/// several times a normal call. For densities such as Beckmann's D, whose exponent −tan²θ/α² is
/// below −104 for most directions when α is small (5 % of a near-specular battery's time went
/// there).
#[inline]
pub fn exp_or_zero(x: f32) -> f32 {
    if x < EXP_ZERO_BELOW { 0.0 } else { x.exp() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_and_ceil_are_f32s_bit_for_bit() {
        let special = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -1.5,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            1e-45,
            -1e-45,
            8_388_607.5,
            -8_388_607.5,
            8_388_608.0,
            -8_388_609.0,
            2_147_483_648.0,
            -2_147_483_904.0,
            1e30,
            -1e30,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ];
        // Every 97th bit pattern besides: all exponents and signs, many mantissas.
        let patterns = (0..=u32::MAX / 97).map(|k| f32::from_bits(k * 97));
        for x in special.into_iter().chain(patterns) {
            if x.is_nan() {
                // A NaN's payload is not the point (libm may quiet a signalling one).
                assert!(floor(x).is_nan() && ceil(x).is_nan());
                continue;
            }
            assert_eq!(
                floor(x).to_bits(),
                x.floor().to_bits(),
                "floor({x:e}) bits {:#x}",
                x.to_bits()
            );
            assert_eq!(
                ceil(x).to_bits(),
                x.ceil().to_bits(),
                "ceil({x:e}) bits {:#x}",
                x.to_bits()
            );
        }
    }

    #[test]
    fn finds_the_largest_lower_node_and_clamps() {
        let a = [0.0, 1.0, 2.0, 4.0];
        assert_eq!(find_interval(&a, -1.0), 0);
        assert_eq!(find_interval(&a, 0.0), 0);
        assert_eq!(find_interval(&a, 0.5), 0);
        assert_eq!(find_interval(&a, 1.0), 1);
        assert_eq!(find_interval(&a, 3.9), 2);
        assert_eq!(find_interval(&a, 4.0), 2);
        assert_eq!(find_interval(&a, 9.0), 2);
        // Repeated entries (empty CDF cells): the last of the equal nodes.
        let cdf = [0.0, 0.25, 0.25, 1.0];
        assert_eq!(find_interval(&cdf, 0.25), 2);
        assert_eq!(find_interval(&cdf, 0.2), 0);
        assert_eq!(find_interval(&[3.0], 5.0), 0);
        assert_eq!(find_interval(&[], 5.0), 0);
    }

    #[test]
    fn exp_or_zero_is_exp_bit_for_bit() {
        let mut x = -120.0f32;
        while x < 90.0 {
            assert_eq!(exp_or_zero(x).to_bits(), x.exp().to_bits(), "{x}");
            x += 0.003_7;
        }
        // Either side of the bound: the largest f32 whose exponential is 0, and the bound.
        let below = f32::from_bits(EXP_ZERO_BELOW.to_bits() + 1);
        assert_eq!(exp_or_zero(below), 0.0);
        for x in [
            below,
            EXP_ZERO_BELOW,
            f32::NEG_INFINITY,
            -0.0,
            0.0,
            f32::MIN,
            -1e30,
        ] {
            assert_eq!(exp_or_zero(x).to_bits(), x.exp().to_bits(), "{x}");
        }
        assert!(exp_or_zero(f32::NAN).is_nan());
    }

    #[test]
    fn wrap_repeat_is_rem_euclid() {
        for n in [1i64, 2, 3, 7, 64, 1000] {
            for i in -5 * n - 3..5 * n + 3 {
                assert_eq!(wrap_repeat(i, n), i.rem_euclid(n), "{i} mod {n}");
            }
        }
        for i in [i64::MIN, i64::MAX, i64::MIN + 1, -1, 0] {
            assert_eq!(wrap_repeat(i, 37), i.rem_euclid(37), "{i}");
        }
    }
}
