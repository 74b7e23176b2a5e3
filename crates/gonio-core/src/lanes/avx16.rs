//! The element-wise operations of 16 lanes as whole-register AVX-512 instructions.
//!
//! The 512-bit counterparts of [`super::avx8`], under the same names, so that `wide8!` runs one
//! expression with either module: used by 16-lane values whose instruction set
//! ([`super::Isa::AVX512`]) has AVX-512F, i.e. those [`super::dispatch`] makes after detecting
//! AVX-512 and every lane of a program compiled for it. Masks keep the lane types' layout (each
//! lane 0 or −1 in a vector register), not AVX-512's mask registers: a comparison's mask
//! register is expanded into a vector, and a selection reads its mask back from one, a few
//! single-cycle instructions that leave every kernel's code unchanged.
//!
//! Each function gives the bits of the loop it replaces (IEEE operations, no fused
//! multiply-add; `min`/`max` as `x < o ? x : o`, like `vminps`). Only AVX-512F is needed.

#![allow(clippy::missing_safety_doc)]

use std::arch::x86_64::*;

macro_rules! binary {
    ($($name:ident = $intr:ident, $doc:literal;)*) => {$(
        #[doc = $doc]
        #[inline]
        #[target_feature(enable = "avx512f")]
        pub unsafe fn $name(a: __m512, b: __m512) -> __m512 {
            $intr(a, b)
        }
    )*};
}

binary! {
    add = _mm512_add_ps, "a + b";
    sub = _mm512_sub_ps, "a − b";
    mul = _mm512_mul_ps, "a · b";
    div = _mm512_div_ps, "a / b";
    min = _mm512_min_ps, "a < b ? a : b";
    max = _mm512_max_ps, "a > b ? a : b";
}

/// `v` in every lane (named as the 256-bit intrinsic it stands for in `wide8!`'s expressions).
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn _mm256_set1_ps(v: f32) -> __m512 {
    _mm512_set1_ps(v)
}

/// The bits of `a` as 16 integer lanes.
#[inline]
#[target_feature(enable = "avx512f")]
fn int(a: __m512) -> __m512i {
    _mm512_castps_si512(a)
}

/// The integer lanes `a` as 16 float lanes, bit for bit.
#[inline]
#[target_feature(enable = "avx512f")]
fn float(a: __m512i) -> __m512 {
    _mm512_castsi512_ps(a)
}

/// √a.
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn sqrt(a: __m512) -> __m512 {
    _mm512_sqrt_ps(a)
}

/// |a| (the sign bit cleared).
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn abs(a: __m512) -> __m512 {
    float(_mm512_and_epi32(int(a), _mm512_set1_epi32(i32::MAX)))
}

/// −a (the sign bit flipped).
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn neg(a: __m512) -> __m512 {
    float(_mm512_xor_epi32(int(a), _mm512_set1_epi32(i32::MIN)))
}

/// The lanes where `a P b` for the comparison predicate `P` (`_CMP_LT_OQ`, …): all bits set
/// or clear (a `Mask`'s −1 or 0).
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn cmp<const P: i32>(a: __m512, b: __m512) -> __m512 {
    float(_mm512_maskz_mov_epi32(
        _mm512_cmp_ps_mask::<P>(a, b),
        _mm512_set1_epi32(-1),
    ))
}

/// The mask register of a vector mask (lanes 0 or −1).
#[inline]
#[target_feature(enable = "avx512f")]
fn bits(m: __m512) -> __mmask16 {
    _mm512_test_epi32_mask(int(m), int(m))
}

/// `a` where `m` is set (−1), `b` where it is clear (0).
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn select(m: __m512, a: __m512, b: __m512) -> __m512 {
    _mm512_mask_blend_ps(bits(m), b, a)
}

/// m & n.
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn and(m: __m512, n: __m512) -> __m512 {
    float(_mm512_and_epi32(int(m), int(n)))
}

/// m | n.
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn or(m: __m512, n: __m512) -> __m512 {
    float(_mm512_or_epi32(int(m), int(n)))
}

/// !m.
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn not(m: __m512) -> __m512 {
    float(_mm512_xor_epi32(int(m), _mm512_set1_epi32(-1)))
}

/// Whether some lane of `m` is set.
#[inline]
#[target_feature(enable = "avx512f")]
pub unsafe fn any(m: __m512) -> bool {
    bits(m) != 0
}
