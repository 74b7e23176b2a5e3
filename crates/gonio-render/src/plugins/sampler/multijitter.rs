//! `multijitter`: correlated multi-jittered samples (Kensler 2013, "Correlated Multi-Jittered
//! Sampling"; Mitsuba 3 `src/samplers/multijitter.cpp`).

use super::{JITTER, SAMPLE_COUNT, SEED, jitter, with_common};
use crate::plugins::Plugin;
use crate::scene::{SamplerDesc, SamplerKind};
use crate::xml::{Builder, Params, SceneError};

/// The `multijitter` plugin.
pub static PLUGIN: Plugin<SamplerDesc> = Plugin {
    name: "multijitter",
    summary: "Multi-jittered samples: stratified in 2D and in each 1D projection.",
    params: &[SAMPLE_COUNT, SEED, JITTER],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SamplerDesc, SceneError> {
    let kind = SamplerKind::MultiJitter { jitter: jitter(p)? };
    with_common(p, kind)
}
