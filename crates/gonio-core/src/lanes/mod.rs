//! Many samples per call: `N` single-precision lanes, for kernels that evaluate a BSDF for `N`
//! paths at once (8 lanes on AVX2, 16 on AVX-512, chosen at run time).
//!
//! [`F32s`] is `[f32; N]` with element-wise arithmetic written as plain loops; once inlined into
//! a function compiled for a vector extension ([`dispatch`]), LLVM turns every loop into one
//! vector instruction per register. Control flow becomes data: a comparison gives a [`Mask`]
//! (all bits set or clear per lane, as the hardware's), and `mask.select(a, b)` replaces an
//! `if`. [`math`] has the transcendental functions as branch-free polynomials (Cephes), since
//! `f32::sin` and friends are library calls that would leave the vector registers lane by lane.
//!
//! Where the CPU is known to have AVX, the 8-lane operations are explicit AVX intrinsics instead
//! (`lanes/avx8.rs`; 16 lanes: the AVX-512 forms of `lanes/avx16.rs` where the CPU has it, else
//! the 8-lane forms on each half): LLVM leaves much of the loops' code 4 wide or scalar inside
//! long kernels, and the explicit forms made the kernels 1.1–1.7× faster. What
//! proves the CPU's extensions is the lanes' second type parameter, their instruction set
//! ([`Isa`]): [`dispatch`] runs a kernel with lanes of an instruction set only it can name, after
//! detecting it, so a portable binary uses the intrinsics wherever it runs on AVX2; lanes any code
//! makes ([`Portable`], the default: `F32s<8>`) use them only in a program compiled for AVX as a
//! whole (`RUSTFLAGS="-C target-cpu=native"`).
//!
//! Why our own type and not a crate: `std::simd` is not on stable Rust, and the stable crates
//! (`wide`) pick their instruction set when the crate is compiled, not when the program runs, so
//! a binary built for any x86-64 would never use AVX2 or AVX-512. Plain arrays under
//! `#[target_feature]` give run-time dispatch with no `unsafe` in the kernels themselves (the
//! `unsafe` is in the operations, behind the instruction-set type).
//!
//! Every kernel built on these types has a scalar twin that is the reference: the tests compare
//! them lane by lane (`tests/lanes/`).

// Indexed loops over lanes are the form LLVM vectorizes; Cephes' constants are kept as published.
#![allow(clippy::needless_range_loop, clippy::excessive_precision)]

#[cfg(target_arch = "x86_64")]
mod avx16;
#[cfg(target_arch = "x86_64")]
mod avx8;
#[cfg(all(test, target_arch = "x86_64"))]
mod forms_tests;
pub mod fresnel;
pub mod math;
pub mod microfacet;
pub mod spectrum;
mod vec3;
pub mod warp;

pub use microfacet::MicrofacetLanes;
pub use spectrum::{BsdfSamples, SampledSpectra};
pub use vec3::Vec3s;

use std::marker::PhantomData;
use std::ops::{Add, AddAssign, BitAnd, BitOr, Div, DivAssign, Mul, MulAssign, Neg, Not, Sub, SubAssign};

/// `N` f32 lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(transparent)]
pub struct F32s<const N: usize, X: Isa = Portable>(pub [f32; N], PhantomData<X>);

/// A per-lane condition: 0 (false) or −1 (all bits set, true) in each lane, the layout of the
/// vector comparison instructions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(transparent)]
pub struct Mask<const N: usize, X: Isa = Portable>(pub [i32; N], PhantomData<X>);

/// The instruction set lanes may use, a type parameter of every lane type: the proof, carried
/// in the type, that an explicit vector form is safe to run.
///
/// [`Portable`] is what any code may name: its lanes use explicit AVX forms only where the whole
/// program is compiled for AVX (`-C target-cpu=native`, `x86-64-v3`), and are loops otherwise.
/// The other instruction sets are types only [`dispatch`] names, after detecting the CPU's
/// extensions, when it runs a [`LaneKernel`]: code generic over `X` can hold their lanes, code
/// outside cannot make them (the trait is sealed, the types unnameable). Inside the kernel's
/// `#[target_feature]` function the explicit forms inline as single instructions (LLVM leaves
/// many of the equivalent loops 4 wide or scalar inside long kernels).
pub trait Isa:
    sealed::Sealed + Copy + Clone + std::fmt::Debug + Default + PartialEq + Eq + Send + Sync + 'static
{
    /// Whether the CPU running code that holds these lanes has AVX.
    const AVX: bool;
    /// Whether it has AVX2 (the integer and gather forms).
    const AVX2: bool;
    /// Whether it has AVX-512F (16 lanes are then one register).
    const AVX512: bool;
}

mod sealed {
    pub trait Sealed {}
}

/// Lanes any code may make: explicit AVX forms where the program is compiled for AVX, loops
/// otherwise. The default instruction set of the lane types.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Portable;
impl sealed::Sealed for Portable {}
impl Isa for Portable {
    const AVX: bool = cfg!(all(target_arch = "x86_64", target_feature = "avx"));
    const AVX2: bool = cfg!(all(target_arch = "x86_64", target_feature = "avx2"));
    const AVX512: bool = cfg!(all(target_arch = "x86_64", target_feature = "avx512f"));
}

/// The instruction sets [`dispatch`] detects (not re-exported: no code outside can name them).
mod detected {
    /// AVX2 + FMA, detected at run time.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    pub struct Avx2;
    impl super::sealed::Sealed for Avx2 {}
    impl super::Isa for Avx2 {
        const AVX: bool = true;
        const AVX2: bool = true;
        const AVX512: bool = false;
    }
    /// AVX-512 (F, VL, BW, DQ) with AVX2 + FMA, detected at run time.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    pub struct Avx512;
    impl super::sealed::Sealed for Avx512 {}
    impl super::Isa for Avx512 {
        const AVX: bool = true;
        const AVX2: bool = true;
        const AVX512: bool = true;
    }
}

impl<const N: usize, X: Isa> Default for F32s<N, X> {
    #[inline(always)]
    fn default() -> Self {
        Self([0.0; N], PhantomData)
    }
}

macro_rules! lanewise {
    ($($i:ident = $src:expr),* => $e:expr) => {{
        let mut r = [0.0f32; N];
        for k in 0..N {
            $(let $i = $src.0[k];)*
            r[k] = $e;
        }
        F32s(r, PhantomData)
    }};
}

/// The 8-lane case of an operation as its [`avx8`] form, returned from the enclosing function,
/// when `N = 8` and the lanes' instruction set `X` may use AVX ([`Isa::AVX`]); the 16-lane case
/// as the [`avx16`] form of the same name (one 512-bit register) where `X` may use AVX-512
/// ([`Isa::AVX512`]), else as the `avx8` form on each half (two 256-bit registers); otherwise
/// nothing, and the loop after it runs. In the 512-bit case the expression's `avx8` and
/// `_mm256_set1_ps` name `avx16`'s forms (block-scoped imports shadow the module's).
/// `wide8!(a = self, b = o => avx8::add(a, b))` loads the named lanes (`F32s<8, X>` or `Mask<8, X>`) into registers; the form's register is stored as
/// the result (`wide8!(.. => bool: expr)` for a `bool`). Both conditions are constants, so each
/// instance of an operation compiles to the form alone or to the loop alone.
macro_rules! wide8 {
    ($($v:ident = $src:expr),* => bool: $e:expr) => {
        #[cfg(target_arch = "x86_64")]
        if N == 16 && X::AVX512 {
            // SAFETY: `X::AVX512` holds only where the CPU has AVX-512F (see below for AVX);
            // N = 16 makes the lane arrays 16 lanes (64 bytes).
            #[allow(unused_imports)]
            return unsafe {
                use crate::lanes::avx16 as avx8;
                $(let $v = std::arch::x86_64::_mm512_loadu_ps($src.0.as_ptr() as *const f32);)*
                $e
            };
        }
        #[cfg(target_arch = "x86_64")]
        if N == 8 && X::AVX {
            // SAFETY: as below.
            return unsafe {
                $(let $v = std::arch::x86_64::_mm256_loadu_ps($src.0.as_ptr() as *const f32);)*
                $e
            };
        }
        #[cfg(target_arch = "x86_64")]
        if N == 16 && X::AVX {
            // SAFETY: as below.
            return unsafe {
                let lo = {
                    $(let $v = std::arch::x86_64::_mm256_loadu_ps($src.0.as_ptr() as *const f32);)*
                    $e
                };
                let hi = {
                    $(let $v = std::arch::x86_64::_mm256_loadu_ps(
                        ($src.0.as_ptr() as *const f32).add(8),
                    );)*
                    $e
                };
                lo || hi
            };
        }
    };
    ($($v:ident = $src:expr),* => $e:expr) => {
        #[cfg(target_arch = "x86_64")]
        if N == 16 && X::AVX512 {
            // SAFETY: `X::AVX512` holds only where the CPU has AVX-512F (as `X::AVX` below);
            // N = 16 makes the lane arrays 16 lanes (64 bytes), one 512-bit register.
            #[allow(unused_unsafe, unused_imports)]
            return unsafe {
                use std::arch::x86_64::*;
                use crate::lanes::avx16 as avx8;
                use crate::lanes::avx16::_mm256_set1_ps;
                $(let $v = _mm512_loadu_ps($src.0.as_ptr() as *const f32);)*
                store16x($e)
            };
        }
        #[cfg(target_arch = "x86_64")]
        if N == 8 && X::AVX {
            // SAFETY: `X::AVX` holds only where the CPU has AVX (`Isa`: the whole program is
            // compiled for it, or `dispatch` detected it before naming `X`), and N = 8 makes
            // the lane arrays the 8 lanes (32 bytes) the forms take and give.
            #[allow(unused_unsafe, unused_imports)]
            return unsafe {
                use std::arch::x86_64::*;
                $(let $v = _mm256_loadu_ps($src.0.as_ptr() as *const f32);)*
                store8($e)
            };
        }
        #[cfg(target_arch = "x86_64")]
        if N == 16 && X::AVX {
            // SAFETY: as above; N = 16 makes the lane arrays two halves of 8 lanes (64 bytes).
            #[allow(unused_unsafe, unused_imports)]
            return unsafe {
                use std::arch::x86_64::*;
                let lo = {
                    $(let $v = _mm256_loadu_ps($src.0.as_ptr() as *const f32);)*
                    $e
                };
                let hi = {
                    $(let $v = _mm256_loadu_ps(($src.0.as_ptr() as *const f32).add(8));)*
                    $e
                };
                store16(lo, hi)
            };
        }
    };
}

/// The 8 lanes of `v` as `T` (`F32s<8, X>` or `Mask<8, X>`, 32 bytes).
///
/// # Safety
/// `T` must be 32 bytes of lanes; the CPU has AVX.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn store8<T: Copy>(v: std::arch::x86_64::__m256) -> T {
    debug_assert_eq!(std::mem::size_of::<T>(), 32);
    let mut r = std::mem::MaybeUninit::<T>::uninit();
    // SAFETY: the caller's: `r` holds 32 bytes, AVX is available.
    unsafe {
        std::arch::x86_64::_mm256_storeu_ps(r.as_mut_ptr() as *mut f32, v);
        r.assume_init()
    }
}

/// The 16 lanes of `v` as `T` (`F32s<16, X>` or `Mask<16, X>`, 64 bytes).
///
/// # Safety
/// `T` must be 64 bytes of lanes; the CPU has AVX-512F.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn store16x<T: Copy>(v: std::arch::x86_64::__m512) -> T {
    debug_assert_eq!(std::mem::size_of::<T>(), 64);
    let mut r = std::mem::MaybeUninit::<T>::uninit();
    // SAFETY: the caller's: `r` holds 64 bytes, AVX-512F is available.
    unsafe {
        std::arch::x86_64::_mm512_storeu_ps(r.as_mut_ptr() as *mut f32, v);
        r.assume_init()
    }
}

/// The 16 lanes `lo`, `hi` as `T` (`F32s<16, X>` or `Mask<16, X>`, 64 bytes).
///
/// # Safety
/// `T` must be 64 bytes of lanes; the CPU has AVX.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn store16<T: Copy>(lo: std::arch::x86_64::__m256, hi: std::arch::x86_64::__m256) -> T {
    debug_assert_eq!(std::mem::size_of::<T>(), 64);
    let mut r = std::mem::MaybeUninit::<T>::uninit();
    // SAFETY: the caller's: `r` holds 64 bytes, AVX is available.
    unsafe {
        let p = r.as_mut_ptr() as *mut f32;
        std::arch::x86_64::_mm256_storeu_ps(p, lo);
        std::arch::x86_64::_mm256_storeu_ps(p.add(8), hi);
        r.assume_init()
    }
}

macro_rules! compare {
    ($name:ident, $op:tt, $pred:ident, $doc:literal) => {
        #[doc = $doc]
        #[inline(always)]
        pub fn $name(self, o: impl Into<Self>) -> Mask<N, X> {
            let o = o.into();
            wide8!(a = self, b = o => avx8::cmp::<$pred>(a, b));
            let mut r = [0i32; N];
            for k in 0..N {
                r[k] = -((self.0[k] $op o.0[k]) as i32);
            }
            Mask(r, PhantomData)
        }
    };
}

impl<const N: usize, X: Isa> F32s<N, X> {
    /// All lanes zero.
    pub const ZERO: Self = Self([0.0; N], PhantomData);
    /// All lanes one.
    pub const ONE: Self = Self([1.0; N], PhantomData);

    /// The lanes `v`.
    #[inline(always)]
    pub const fn from_array(v: [f32; N]) -> Self {
        Self(v, PhantomData)
    }
    /// The same value in every lane.
    #[inline(always)]
    pub fn splat(v: f32) -> Self {
        Self([v; N], PhantomData)
    }
    /// Lane `k` is `f(k)`.
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
        Self(std::array::from_fn(f), PhantomData)
    }
    /// The lanes.
    #[inline(always)]
    pub fn to_array(self) -> [f32; N] {
        self.0
    }
    /// Lane `k`.
    #[inline(always)]
    pub fn lane(self, k: usize) -> f32 {
        self.0[k]
    }
    /// √x (NaN below 0).
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        wide8!(a = self => avx8::sqrt(a));
        lanewise!(x = self => x.sqrt())
    }
    /// √max(x, 0): the square root of a quantity that rounding may push below 0.
    #[inline(always)]
    pub fn safe_sqrt(self) -> Self {
        lanewise!(x = self => (if x > 0.0 { x } else { 0.0 }).sqrt())
    }
    /// |x|.
    #[inline(always)]
    pub fn abs(self) -> Self {
        wide8!(a = self => avx8::abs(a));
        lanewise!(x = self => x.abs())
    }
    /// Lane-wise minimum: `self < o ? self : o`, one `minps` (so `o` where `self` is NaN, as
    /// `f32::min`; but NaN where `o` is, which `f32::min` would drop: keep constants in `o`).
    #[inline(always)]
    pub fn min(self, o: impl Into<Self>) -> Self {
        let o = o.into();
        wide8!(a = self, b = o => avx8::min(a, b));
        lanewise!(x = self, o = o => if x < o { x } else { o })
    }
    /// Lane-wise maximum: `self > o ? self : o`, one `maxps` (see [`Self::min`] for NaN).
    #[inline(always)]
    pub fn max(self, o: impl Into<Self>) -> Self {
        let o = o.into();
        wide8!(a = self, b = o => avx8::max(a, b));
        lanewise!(x = self, o = o => if x > o { x } else { o })
    }
    /// Clamped to [lo, hi].
    #[inline(always)]
    pub fn clamp(self, lo: f32, hi: f32) -> Self {
        self.max(lo).min(hi)
    }
    /// Linear interpolation in `table` at positions `self` ∈ [0, len − 1] per lane:
    /// (1 − w)·`table[i]` + w·`table[i + 1]` with i = ⌊x⌋ clamped to len − 2 and w = x − i (a
    /// position past the end extrapolates from the last interval). NaN or a negative position
    /// reads interval 0. Panics if `table` has fewer than 2 entries. With AVX-512F at 16 lanes or
    /// AVX2 at 8 the two reads are gathers (`interval_ends`).
    #[inline(always)]
    pub fn lerp_table(self, table: &[f32]) -> Self {
        assert!(table.len() >= 2, "lerp_table needs two entries");
        // Clamped as floats (`max` gives 0 for NaN), so that truncation gives the interval.
        let x = self.max(0.0).min((table.len() - 2) as f32);
        // SAFETY: every lane of `x` lies in [0, len − 2], and len ≥ 2.
        let (i, t0, t1) = unsafe { x.interval_ends(table) };
        let w = self - i;
        (1.0 - w) * t0 + w * t1
    }
    /// ⌊x⌋ as a float, table[⌊x⌋] and table[⌊x⌋ + 1], per lane; two gathers where the
    /// instruction set has them.
    ///
    /// # Safety
    /// `table` has at least 2 entries and every lane lies in [0, len − 2].
    #[inline(always)]
    unsafe fn interval_ends(self, table: &[f32]) -> (Self, Self, Self) {
        #[cfg(target_arch = "x86_64")]
        if N == 16 && X::AVX512 {
            // SAFETY: `X::AVX512` holds only where the CPU has AVX-512F (`Isa`), and N = 16
            // makes the lanes 64 bytes; 0 ≤ ⌊x⌋ ≤ len − 2 (the caller's), so both gathers read
            // inside `table`.
            return unsafe {
                use std::arch::x86_64::*;
                let i = _mm512_cvttps_epi32(_mm512_loadu_ps(self.0.as_ptr()));
                (
                    store16x(_mm512_cvtepi32_ps(i)),
                    store16x(_mm512_i32gather_ps::<4>(i, table.as_ptr())),
                    store16x(_mm512_i32gather_ps::<4>(i, table.as_ptr().add(1))),
                )
            };
        }
        #[cfg(target_arch = "x86_64")]
        if N == 8 && X::AVX2 {
            // SAFETY: `X::AVX2` holds only where the CPU has AVX2 (`Isa`), N = 8 makes the lanes
            // 32 bytes; indices as above.
            return unsafe {
                use std::arch::x86_64::*;
                let i = _mm256_cvttps_epi32(_mm256_loadu_ps(self.0.as_ptr()));
                (
                    store8(_mm256_cvtepi32_ps(i)),
                    store8(_mm256_i32gather_ps::<4>(table.as_ptr(), i)),
                    store8(_mm256_i32gather_ps::<4>(table.as_ptr().add(1), i)),
                )
            };
        }
        let i: [usize; N] = std::array::from_fn(|k| {
            let x = self.0[k];
            debug_assert!((0.0..=(table.len() - 2) as f32).contains(&x));
            // SAFETY: 0 ≤ x ≤ len − 2 (the caller's), within i32. (`as usize` would saturate,
            // which LLVM may spell out lane by lane.)
            unsafe { x.to_int_unchecked::<i32>() as usize }
        });
        (
            Self::from_fn(|k| i[k] as f32),
            Self::from_fn(|k| table[i[k]]),
            Self::from_fn(|k| table[i[k] + 1]),
        )
    }
    /// The magnitude of `self` with the sign of `s`.
    #[inline(always)]
    pub fn copysign(self, s: Self) -> Self {
        lanewise!(x = self, s = s => x.copysign(s))
    }
    /// 1/x.
    #[inline(always)]
    pub fn recip(self) -> Self {
        wide8!(a = self => avx8::div(_mm256_set1_ps(1.0), a));
        lanewise!(x = self => 1.0 / x)
    }
    /// Lanes that are neither infinite nor NaN.
    #[inline(always)]
    pub fn is_finite(self) -> Mask<N, X> {
        // |x| < ∞ is false for NaN and ±∞: one comparison instead of a classification.
        self.abs().lt(f32::INFINITY)
    }
    /// Lanes that are NaN.
    #[inline(always)]
    pub fn is_nan(self) -> Mask<N, X> {
        self.ne(self)
    }
    /// Sum of the lanes.
    #[inline(always)]
    pub fn sum(self) -> f32 {
        self.0.iter().sum()
    }
    /// The bits of each lane.
    #[inline(always)]
    pub fn to_bits(self) -> [u32; N] {
        self.0.map(f32::to_bits)
    }
    /// Lanes from bits.
    #[inline(always)]
    pub fn from_bits(b: [u32; N]) -> Self {
        Self(b.map(f32::from_bits), PhantomData)
    }

    compare!(lt, <, _CMP_LT_OQ, "Lanes where `self < o`.");
    compare!(le, <=, _CMP_LE_OQ, "Lanes where `self ≤ o`.");
    compare!(gt, >, _CMP_GT_OQ, "Lanes where `self > o`.");
    compare!(ge, >=, _CMP_GE_OQ, "Lanes where `self ≥ o`.");
    compare!(eq, ==, _CMP_EQ_OQ, "Lanes where `self == o`.");
    compare!(ne, !=, _CMP_NEQ_UQ, "Lanes where `self != o` (NaN lanes included).");
}

impl<const N: usize, X: Isa> From<f32> for F32s<N, X> {
    #[inline(always)]
    fn from(v: f32) -> Self {
        Self::splat(v)
    }
}

macro_rules! binary_op {
    ($tr:ident, $f:ident, $op:tt, $tra:ident, $fa:ident) => {
        impl<const N: usize, X: Isa> $tr for F32s<N, X> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                wide8!(a = self, b = o => avx8::$f(a, b));
                lanewise!(x = self, o = o => x $op o)
            }
        }
        impl<const N: usize, X: Isa> $tr<f32> for F32s<N, X> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: f32) -> Self {
                wide8!(a = self => avx8::$f(a, _mm256_set1_ps(o)));
                lanewise!(x = self => x $op o)
            }
        }
        impl<const N: usize, X: Isa> $tr<F32s<N, X>> for f32 {
            type Output = F32s<N, X>;
            #[inline(always)]
            fn $f(self, o: F32s<N, X>) -> F32s<N, X> {
                let s = self;
                wide8!(b = o => avx8::$f(_mm256_set1_ps(s), b));
                lanewise!(o = o => s $op o)
            }
        }
        impl<const N: usize, X: Isa> $tra for F32s<N, X> {
            #[inline(always)]
            fn $fa(&mut self, o: Self) {
                *self = *self $op o;
            }
        }
    };
}

binary_op!(Add, add, +, AddAssign, add_assign);
binary_op!(Sub, sub, -, SubAssign, sub_assign);
binary_op!(Mul, mul, *, MulAssign, mul_assign);
binary_op!(Div, div, /, DivAssign, div_assign);

impl<const N: usize, X: Isa> Neg for F32s<N, X> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        wide8!(a = self => avx8::neg(a));
        lanewise!(x = self => -x)
    }
}

impl<const N: usize, X: Isa> Mask<N, X> {
    /// No lane set.
    pub const NONE: Self = Self([0; N], PhantomData);
    /// Every lane set.
    pub const ALL: Self = Self([-1; N], PhantomData);

    /// The conditions `m` (each lane 0 or −1).
    #[inline(always)]
    pub const fn from_array(m: [i32; N]) -> Self {
        Self(m, PhantomData)
    }
    /// The same condition in every lane.
    #[inline(always)]
    pub fn splat(b: bool) -> Self {
        Self([-(b as i32); N], PhantomData)
    }
    /// Lane `k` is `f(k)`.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> bool) -> Self {
        Self(std::array::from_fn(|k| -(f(k) as i32)), PhantomData)
    }
    /// Whether lane `k` is set.
    #[inline(always)]
    pub fn test(self, k: usize) -> bool {
        self.0[k] != 0
    }
    /// True if some lane is set.
    #[inline(always)]
    pub fn any(self) -> bool {
        wide8!(a = self => bool: avx8::any(a));
        self.0.iter().fold(0, |a, &m| a | m) != 0
    }
    /// True if every lane is set.
    #[inline(always)]
    pub fn all(self) -> bool {
        self.0.iter().fold(-1, |a, &m| a & m) != 0
    }
    /// Per lane: `a` where set, `b` where clear.
    #[inline(always)]
    pub fn select(self, a: F32s<N, X>, b: F32s<N, X>) -> F32s<N, X> {
        wide8!(m = self, x = a, y = b => avx8::select(m, x, y));
        let mut r = [0.0f32; N];
        for k in 0..N {
            r[k] = if self.0[k] != 0 { a.0[k] } else { b.0[k] };
        }
        F32s(r, PhantomData)
    }
    /// `select(a, b)` on three coordinates.
    #[inline(always)]
    pub fn select3(self, a: Vec3s<N, X>, b: Vec3s<N, X>) -> Vec3s<N, X> {
        Vec3s::new(
            self.select(a.x, b.x),
            self.select(a.y, b.y),
            self.select(a.z, b.z),
        )
    }
    /// `a` where set, 0 where clear.
    #[inline(always)]
    pub fn and_then(self, a: F32s<N, X>) -> F32s<N, X> {
        self.select(a, F32s::ZERO)
    }
}

impl<const N: usize, X: Isa> BitAnd for Mask<N, X> {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        wide8!(a = self, b = o => avx8::and(a, b));
        let mut r = [0i32; N];
        for k in 0..N {
            r[k] = self.0[k] & o.0[k];
        }
        Mask(r, PhantomData)
    }
}

impl<const N: usize, X: Isa> BitOr for Mask<N, X> {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        wide8!(a = self, b = o => avx8::or(a, b));
        let mut r = [0i32; N];
        for k in 0..N {
            r[k] = self.0[k] | o.0[k];
        }
        Mask(r, PhantomData)
    }
}

impl<const N: usize, X: Isa> Not for Mask<N, X> {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        wide8!(a = self => avx8::not(a));
        Mask(self.0.map(|m| !m), PhantomData)
    }
}

/// A computation over lanes of any width, run by [`dispatch`] at the widest width the CPU has.
///
/// Everything `run` calls must be `#[inline(always)]` (as every function of this module and of
/// the lane kernels is): code that is not inlined is compiled for the baseline instruction set.
pub trait LaneKernel {
    /// What the computation returns (independent of the width).
    type Output;
    /// The computation with `N` lanes of instruction set `X` (build every lane value of the
    /// computation as `F32s<N, X>`, `Vec3s<N, X>`, …, so that it uses `X`'s forms).
    fn run<const N: usize, X: Isa>(self) -> Self::Output;
}

/// The lane width [`dispatch`] picks on this CPU: 16 with AVX-512 (F, VL, BW, DQ), 8 with
/// AVX2 + FMA, else 4 (SSE2, the x86-64 baseline, and every other architecture).
pub fn lane_width() -> usize {
    match level() {
        Level::Avx512 => 16,
        Level::Avx2 => 8,
        Level::Baseline => 4,
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Level {
    Avx512,
    Avx2,
    Baseline,
}

/// The extension level, detected once (with the `GONIO_LANES` cap) and cached.
#[cfg(target_arch = "x86_64")]
fn level() -> Level {
    use std::sync::OnceLock;
    static LEVEL: OnceLock<Level> = OnceLock::new();
    *LEVEL.get_or_init(|| {
        let cap = std::env::var("GONIO_LANES").ok();
        let avx512 = is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512vl")
            && is_x86_feature_detected!("avx512bw")
            && is_x86_feature_detected!("avx512dq");
        let avx2 = is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma");
        match cap.as_deref() {
            Some("4") => Level::Baseline,
            _ if avx512 && cap.as_deref() != Some("8") => Level::Avx512,
            _ if avx2 => Level::Avx2,
            _ => Level::Baseline,
        }
    })
}

#[cfg(not(target_arch = "x86_64"))]
fn level() -> Level {
    Level::Baseline
}

/// Runs `k` with the widest lanes the CPU supports (see [`lane_width`]; the environment variable
/// `GONIO_LANES=8` or `=4` caps the width, for comparisons).
pub fn dispatch<K: LaneKernel>(k: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    {
        match level() {
            // SAFETY: `level` checked that the CPU has these extensions.
            Level::Avx512 => unsafe { run_avx512(k) },
            // SAFETY: as above.
            Level::Avx2 => unsafe { run_avx2(k) },
            Level::Baseline => k.run::<4, Portable>(),
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        k.run::<4, Portable>()
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma")]
fn run_avx512<K: LaneKernel>(k: K) -> K::Output {
    // A 64-byte-aligned local makes LLVM realign this frame, and with it the kernel's 512-bit
    // spill slots; without it they sit wherever the caller's 16-byte-aligned stack put them,
    // and three placements in four split every spill across two cache lines (principledthin:
    // 30 µs instead of 21 per 4096 lanes, depending on the process's stack address).
    let anchor = StackAlign64([]);
    std::hint::black_box(&anchor);
    k.run::<16, detected::Avx512>()
}

/// A zero-sized value that forces its frame to 64-byte alignment ([`run_avx512`], [`run_avx2`]).
#[cfg(target_arch = "x86_64")]
#[repr(C, align(64))]
struct StackAlign64([u8; 0]);

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn run_avx2<K: LaneKernel>(k: K) -> K::Output {
    // As in `run_avx512`: 256-bit spill slots on a 16-byte-aligned stack split one in four.
    let anchor = StackAlign64([]);
    std::hint::black_box(&anchor);
    k.run::<8, detected::Avx2>()
}
