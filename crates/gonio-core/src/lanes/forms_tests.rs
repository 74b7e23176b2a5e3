//! Every lane operation with an explicit form against its loop, bit for bit, through the lane
//! types themselves (so the loads, stores and halves of `wide8!` are tested along with the
//! forms): lanes of the instruction set `dispatch` names on AVX2, at 8 lanes (one register) and
//! 16 (two halves), and of the one it names on AVX-512 at 16 lanes (one 512-bit register),
//! against `Portable` lanes, whose operations are the loops in a portable build. Each runs where
//! the CPU has what its instruction set names, as the dispatch does.

use super::detected::{Avx2, Avx512};
use super::{F32s, Isa, Mask, Portable};
use crate::rng::Pcg32;

/// Ordinary values of both signs and magnitudes, signed zeros, infinities, NaN, subnormals.
fn values<const N: usize>(rng: &mut Pcg32) -> [f32; N] {
    const SPECIAL: [f32; 8] = [
        0.0,
        -0.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        1e-40,
        -3e-39,
        1.0,
    ];
    std::array::from_fn(|_| {
        let u = rng.next_f32();
        if u < 0.3 {
            SPECIAL[rng.next_below(8) as usize]
        } else {
            let mag = (rng.next_f32() * 20.0 - 10.0).exp2();
            if rng.next_f32() < 0.5 { -mag } else { mag }
        }
    })
}

fn bits<const N: usize, X: Isa>(x: F32s<N, X>) -> [u32; N] {
    x.to_bits()
}

/// The results of every operation on `a`, `b` (and `c` for masks), as bits.
fn run<const N: usize, X: Isa>(a: [f32; N], b: [f32; N], s: f32) -> Vec<Vec<u32>> {
    let (x, y) = (F32s::<N, X>::from_array(a), F32s::<N, X>::from_array(b));
    let m = x.lt(y);
    let n = x.ge(s);
    let mask = |m: Mask<N, X>| m.0.iter().map(|&v| v as u32).collect::<Vec<_>>();
    let f = |v: F32s<N, X>| bits(v).to_vec();
    vec![
        f(x + y),
        f(x - y),
        f(x * y),
        f(x / y),
        f(x + s),
        f(x - s),
        f(x * s),
        f(x / s),
        f(s + y),
        f(s - y),
        f(s * y),
        f(s / y),
        f(-x),
        f(x.sqrt()),
        f(x.abs()),
        f(x.min(y)),
        f(x.max(y)),
        f(x.recip()),
        mask(x.lt(y)),
        mask(x.le(y)),
        mask(x.gt(y)),
        mask(x.ge(y)),
        mask(x.eq(y)),
        mask(x.ne(y)),
        mask(x.is_finite()),
        mask(m & n),
        mask(m | n),
        mask(!m),
        vec![
            m.any() as u32,
            (m & n).any() as u32,
            Mask::<N, X>::NONE.any() as u32,
        ],
        f(m.select(x, y)),
        f(n.and_then(y)),
        // Positions inside, at and past both ends of a 5-entry table, and the specials.
        f((x * 0.01 + 2.0).lerp_table(&TABLE)),
        f(x.lerp_table(&TABLE)),
    ]
}

/// A table for `lerp_table` (a zero among its entries, as a coat table's end may be).
const TABLE: [f32; 5] = [0.9, 0.75, 0.5, 0.125, 0.0];

fn agree<const N: usize, X: Isa>(seed: u64) {
    let mut rng = Pcg32::new(seed, 1);
    for round in 0..2000 {
        let (a, b) = (values::<N>(&mut rng), values::<N>(&mut rng));
        // Lanes equal in some rounds, so that comparisons and masks see ties.
        let b = if round % 5 == 0 { a } else { b };
        let s = values::<1>(&mut rng)[0];
        let forms = run::<N, X>(a, b, s);
        let loops = run::<N, Portable>(a, b, s);
        for (i, (f, l)) in forms.iter().zip(&loops).enumerate() {
            assert_eq!(f, l, "operation {i}, {N} lanes, a = {a:?}, b = {b:?}, s = {s}");
        }
    }
}

#[test]
fn the_dispatched_lanes_give_the_loops_bits_at_8_and_16_lanes() {
    if !(is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")) {
        eprintln!("skipped: this CPU has no AVX2 + FMA, so dispatch never names these lanes");
        return;
    }
    agree::<8, Avx2>(1);
    agree::<16, Avx2>(2);
}

#[test]
fn the_avx512_lanes_give_the_loops_bits_at_16_lanes() {
    if !is_x86_feature_detected!("avx512f") {
        eprintln!("skipped: this CPU has no AVX-512F, so dispatch never names these lanes");
        return;
    }
    agree::<16, Avx512>(3);
    // Where AVX-512 lanes are 8 wide (a kernel run at 8 lanes on such a CPU), the AVX forms.
    agree::<8, Avx512>(4);
}
