//! `ldsampler`: Mitsuba 3's low-discrepancy sampler (`src/samplers/ldsampler.cpp`: randomly
//! scrambled (0, 2)-sequences per pair of dimensions, Kollig and Keller 2002, "Efficient
//! multidimensional sampling").
//!
//! Ours is an alias of our Owen-scrambled Sobol pattern ([`crate::sampler::Pattern::Sobol`],
//! Burley 2020, "Practical hash-based Owen scrambling"): its first two dimensions are the same
//! (0, 2)-sequence (Sobol's first two components), randomized by a nested uniform (Owen)
//! scrambling instead of Kollig–Keller's random digit scrambling, and the higher dimensions are
//! further Sobol components rather than independently shuffled pairs. Both give the same expected
//! image; the noise differs in its details, not its order. As in Mitsuba, `sample_count` is rounded
//! up to a power of four (1 → 4, 10 → 16, 17 → 64) with a warning.
//!
//! | parameter | default |
//! |---|---|
//! | `sample_count` | 4 (rounded up to a power of four) |
//! | `seed` | 0 |

use super::{SAMPLE_COUNT, SEED, with_common};
use crate::plugins::Plugin;
use crate::scene::{SamplerDesc, SamplerKind};
use crate::xml::{Builder, Params, SceneError};

/// The `ldsampler` plugin.
pub static PLUGIN: Plugin<SamplerDesc> = Plugin {
    name: "ldsampler",
    summary: "Low-discrepancy samples (ours: Owen-scrambled Sobol points, the same (0, 2)-sequence in the first two dimensions); `sample_count` rounded up to a power of four. Under a reconstruction filter that reaches neighbouring pixels (the default `gaussian`) the pixels take blocks of one sequence in Z order (as pbrt-v4's `zsobol`): the samples of every aligned 2ᵏ × 2ᵏ square of pixels are one net, not only each pixel's. The same pattern replaces `independent` unless `--sampler independent` is given.",
    params: &[SAMPLE_COUNT, SEED],
    build,
};

/// Mitsuba's count: the smallest power of four ≥ n (at least 4).
pub fn rounded_count(n: u32) -> u32 {
    let mut c = 4u64;
    while c < n as u64 {
        c *= 4;
    }
    c.min(1 << 30) as u32
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SamplerDesc, SceneError> {
    let mut s = with_common(p, SamplerKind::LowDiscrepancy)?;
    let n = rounded_count(s.sample_count);
    if n != s.sample_count {
        b.warnings.push(format!(
            "{}: ldsampler: sample_count {} should be a power of four; rounding to {n}, as Mitsuba does",
            p.obj.loc, s.sample_count
        ));
        s.sample_count = n;
    }
    Ok(s)
}
