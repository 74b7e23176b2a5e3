//! The element-wise operations of 8 lanes as whole-register AVX instructions.
//!
//! LLVM turns the lane loops of [`super::F32s`] into vector code by itself, but inside a long
//! kernel it rebuilds many of them 4 wide or lane by lane (`bench/RESULTS.md`); written as one
//! intrinsic per operation the 8-lane kernels ran 1.1–1.7× faster on AVX2. These forms are used
//! by lanes whose instruction set ([`super::Isa`]) has AVX: those [`super::dispatch`] makes after
//! detecting it, and every lane where the whole program is compiled for AVX
//! (`RUSTFLAGS="-C target-cpu=native"` or `x86-64-v3`). Inlined into a kernel running under
//! `#[target_feature(enable = "avx2,fma")]`, each is one instruction.
//!
//! Each function gives the bits of the loop it replaces (IEEE operations, no fused
//! multiply-add; `min`/`max` as `x < o ? x : o`, like `minps`), so the lane kernels agree with
//! their scalar twins in both builds.

#![allow(clippy::missing_safety_doc)]

use std::arch::x86_64::*;

macro_rules! binary {
    ($($name:ident = $intr:ident, $doc:literal;)*) => {$(
        #[doc = $doc]
        #[inline]
        #[target_feature(enable = "avx")]
        pub unsafe fn $name(a: __m256, b: __m256) -> __m256 {
            $intr(a, b)
        }
    )*};
}

binary! {
    add = _mm256_add_ps, "a + b";
    sub = _mm256_sub_ps, "a − b";
    mul = _mm256_mul_ps, "a · b";
    div = _mm256_div_ps, "a / b";
    min = _mm256_min_ps, "a < b ? a : b";
    max = _mm256_max_ps, "a > b ? a : b";
}

/// √a.
#[inline]
#[target_feature(enable = "avx")]
pub unsafe fn sqrt(a: __m256) -> __m256 {
    _mm256_sqrt_ps(a)
}

/// |a| (the sign bit cleared).
#[inline]
#[target_feature(enable = "avx")]
pub unsafe fn abs(a: __m256) -> __m256 {
    _mm256_andnot_ps(_mm256_set1_ps(-0.0), a)
}

/// −a (the sign bit flipped).
#[inline]
#[target_feature(enable = "avx")]
pub unsafe fn neg(a: __m256) -> __m256 {
    _mm256_xor_ps(_mm256_set1_ps(-0.0), a)
}

/// The lanes where `a P b` for the comparison predicate `P` (`_CMP_LT_OQ`, …): all bits set
/// or clear (a `Mask`'s −1 or 0).
#[inline]
#[target_feature(enable = "avx")]
pub unsafe fn cmp<const P: i32>(a: __m256, b: __m256) -> __m256 {
    _mm256_cmp_ps::<P>(a, b)
}

/// `a` where `m` is set (−1), `b` where it is clear (0).
#[inline]
#[target_feature(enable = "avx")]
pub unsafe fn select(m: __m256, a: __m256, b: __m256) -> __m256 {
    _mm256_blendv_ps(b, a, m)
}

/// m & n.
#[inline]
#[target_feature(enable = "avx")]
pub unsafe fn and(m: __m256, n: __m256) -> __m256 {
    _mm256_and_ps(m, n)
}

/// m | n.
#[inline]
#[target_feature(enable = "avx")]
pub unsafe fn or(m: __m256, n: __m256) -> __m256 {
    _mm256_or_ps(m, n)
}

/// !m.
#[inline]
#[target_feature(enable = "avx")]
pub unsafe fn not(m: __m256) -> __m256 {
    _mm256_xor_ps(m, _mm256_castsi256_ps(_mm256_set1_epi32(-1)))
}

/// Whether some lane of `m` is set (its sign bit: the masks are 0 or −1).
#[inline]
#[target_feature(enable = "avx")]
pub unsafe fn any(m: __m256) -> bool {
    _mm256_movemask_ps(m) != 0
}

#[cfg(test)]
mod tests {
    //! Each form against the scalar expression its loop evaluates, bit for bit, over ordinary
    //! values, signed zeros, infinities, NaN and subnormals (when the CPU has AVX: the kernels
    //! `dispatch` runs on AVX2 call these forms in every build).
    use super::_CMP_EQ_OQ;
    use super::{_CMP_GE_OQ, _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ, _CMP_NEQ_UQ};

    /// The forms on arrays (the lane types' layout).
    mod arr {
        use super::super as f;
        use std::arch::x86_64::__m256;
        use std::mem::transmute;
        type A = [f32; 8];
        type M = [i32; 8];
        fn v(a: A) -> __m256 {
            // SAFETY: the same 32 bytes of plain data.
            unsafe { transmute(a) }
        }
        fn vm(m: M) -> __m256 {
            // SAFETY: as above.
            unsafe { transmute(m) }
        }
        macro_rules! wrap {
            ($($n:ident($($a:ident: $t:ident),*) -> $r:ty;)*) => {$(
                #[allow(clippy::useless_transmute)] // identity for the `bool` results
                pub unsafe fn $n($($a: $t),*) -> $r {
                    // SAFETY: the caller's (the CPU has AVX); results are 32 bytes or a bool.
                    unsafe { transmute(f::$n($(wrap!(@in $t, $a)),*)) }
                }
            )*};
            (@in A, $a:ident) => { v($a) };
            (@in M, $a:ident) => { vm($a) };
        }
        wrap! {
            add(a: A, b: A) -> A;
            sub(a: A, b: A) -> A;
            mul(a: A, b: A) -> A;
            div(a: A, b: A) -> A;
            min(a: A, b: A) -> A;
            max(a: A, b: A) -> A;
            sqrt(a: A) -> A;
            abs(a: A) -> A;
            neg(a: A) -> A;
            select(m: M, a: A, b: A) -> A;
            and(m: M, n: M) -> M;
            or(m: M, n: M) -> M;
            not(m: M) -> M;
            any(m: M) -> bool;
        }
        pub unsafe fn cmp<const P: i32>(a: A, b: A) -> M {
            // SAFETY: as above.
            unsafe { transmute(f::cmp::<P>(v(a), v(b))) }
        }
    }
    use arr::*;

    fn inputs() -> Vec<[f32; 8]> {
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.5,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            1e-40,
        ];
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            f32::from_bits((state >> 32) as u32 & 0xbfff_ffff) // finite or NaN, both signs
        };
        let mut v = vec![special, special.map(|x| -x)];
        for _ in 0..200 {
            v.push(std::array::from_fn(
                |k| if k % 3 == 0 { special[k] } else { next() },
            ));
        }
        v
    }

    fn same(a: [f32; 8], b: [f32; 8]) -> bool {
        a.iter()
            .zip(&b)
            .all(|(x, y)| x.to_bits() == y.to_bits() || x.is_nan() && y.is_nan())
    }

    #[test]
    fn avx8_forms_give_the_loops_bits() {
        if !is_x86_feature_detected!("avx") {
            return;
        }
        let v = inputs();
        let m = |c: [bool; 8]| c.map(|b| -(b as i32));
        for (i, &a) in v.iter().enumerate() {
            let b = v[(i * 7 + 3) % v.len()];
            // SAFETY: the CPU has AVX (checked above).
            unsafe {
                assert!(same(add(a, b), std::array::from_fn(|k| a[k] + b[k])));
                assert!(same(sub(a, b), std::array::from_fn(|k| a[k] - b[k])));
                assert!(same(mul(a, b), std::array::from_fn(|k| a[k] * b[k])));
                assert!(same(div(a, b), std::array::from_fn(|k| a[k] / b[k])));
                let lt: [f32; 8] = std::array::from_fn(|k| if a[k] < b[k] { a[k] } else { b[k] });
                let gt: [f32; 8] = std::array::from_fn(|k| if a[k] > b[k] { a[k] } else { b[k] });
                assert!(same(min(a, b), lt) && same(max(a, b), gt));
                assert!(same(sqrt(a), a.map(f32::sqrt)));
                assert!(same(abs(a), a.map(f32::abs)));
                assert!(same(neg(a), a.map(|x| -x)));
                assert_eq!(cmp::<_CMP_LT_OQ>(a, b), m(std::array::from_fn(|k| a[k] < b[k])));
                assert_eq!(cmp::<_CMP_LE_OQ>(a, b), m(std::array::from_fn(|k| a[k] <= b[k])));
                assert_eq!(cmp::<_CMP_GT_OQ>(a, b), m(std::array::from_fn(|k| a[k] > b[k])));
                assert_eq!(cmp::<_CMP_GE_OQ>(a, b), m(std::array::from_fn(|k| a[k] >= b[k])));
                assert_eq!(cmp::<_CMP_EQ_OQ>(a, b), m(std::array::from_fn(|k| a[k] == b[k])));
                assert_eq!(cmp::<_CMP_NEQ_UQ>(a, b), m(std::array::from_fn(|k| a[k] != b[k])));
                let c = cmp::<_CMP_LT_OQ>(a, b);
                let d = cmp::<_CMP_NEQ_UQ>(a, a);
                assert!(same(
                    select(c, a, b),
                    std::array::from_fn(|k| if c[k] != 0 { a[k] } else { b[k] })
                ));
                assert_eq!(and(c, d), std::array::from_fn(|k| c[k] & d[k]));
                assert_eq!(or(c, d), std::array::from_fn(|k| c[k] | d[k]));
                assert_eq!(not(c), c.map(|x| !x));
                assert_eq!(any(c), c.iter().any(|&x| x != 0));
                assert_eq!(any(d), a.iter().any(|x| x.is_nan()));
            }
        }
    }
}
