//! `orthogonal`: Mitsuba 3's orthogonal-array sampler (`src/samplers/orthogonal.cpp`; Jarosz,
//! Enayet, Kensler, Kilpatrick and Christensen 2019, "Orthogonal array sampling for Monte Carlo
//! rendering"): for p² samples (p prime), Bush's construction of an orthogonal array of strength
//! `strength`, jittered, so that every projection onto `strength` dimensions is stratified on
//! the p × p grid (p^strength cells for strength > 2).
//!
//! Ours is an alias of our correlated multi-jittered pattern ([`crate::sampler::Pattern::MultiJitter`],
//! Kensler 2013): for each pair of dimensions a jittered p × p grid whose 1D projections are also
//! stratified into p² intervals, which is what a strength-2 orthogonal array with jitter
//! guarantees (and a little more, in 1D). Higher strengths are accepted but only the 2D
//! stratification is kept. Both give the same expected image. As in Mitsuba, `sample_count` is
//! rounded up to the square of a prime (1 → 4, 10 → 25, 26 → 49) with a warning.
//!
//! | parameter | default |
//! |---|---|
//! | `sample_count` | 4 (rounded up to a prime squared) |
//! | `seed` | 0 |
//! | `jitter` | true |
//! | `strength` | 2 |

use super::{JITTER, SAMPLE_COUNT, SEED, jitter, with_common};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{SamplerDesc, SamplerKind};
use crate::xml::{Builder, Params, SceneError};

const STRENGTH: ParamSpec = ParamSpec::new(
    "strength",
    ParamType::Integer,
    DefaultValue::Int(2),
    "strength of the orthogonal array (≥ 2); ours stratifies every pair of dimensions, as strength 2",
);

/// The `orthogonal` plugin.
pub static PLUGIN: Plugin<SamplerDesc> = Plugin {
    name: "orthogonal",
    summary: "Orthogonal-array samples (ours: correlated multi-jittered, the stratification of a strength-2 array); `sample_count` rounded up to a prime squared.",
    params: &[SAMPLE_COUNT, SEED, JITTER, STRENGTH],
    build,
};

/// Mitsuba's count: p² for the smallest prime p ≥ max(⌈√n⌉, 2).
pub fn rounded_count(n: u32) -> u32 {
    let is_prime = |p: u64| p >= 2 && (2..).take_while(|d| d * d <= p).all(|d| !p.is_multiple_of(d));
    let mut p = (n as f64).sqrt().ceil().max(2.0) as u64;
    while !is_prime(p) {
        p += 1;
    }
    (p * p).min(1 << 31) as u32
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SamplerDesc, SceneError> {
    let jitter = jitter(p)?;
    p.int_in(STRENGTH.name, STRENGTH.default.int(), 2, 64)?;
    let mut s = with_common(p, SamplerKind::Orthogonal { jitter })?;
    let n = rounded_count(s.sample_count);
    if n != s.sample_count {
        b.warnings.push(format!(
            "{}: orthogonal: sample_count {} should be the square of a prime; rounding to {n}, as Mitsuba does",
            p.obj.loc, s.sample_count
        ));
        s.sample_count = n;
    }
    Ok(s)
}
