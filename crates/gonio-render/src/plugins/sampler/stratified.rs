//! `stratified`: one sample per stratum of a grid (Mitsuba 3 `src/samplers/stratified.cpp`).

use super::{JITTER, SAMPLE_COUNT, SEED, jitter, with_common};
use crate::plugins::Plugin;
use crate::scene::{SamplerDesc, SamplerKind};
use crate::xml::{Builder, Params, SceneError};

/// The `stratified` plugin.
pub static PLUGIN: Plugin<SamplerDesc> = Plugin {
    name: "stratified",
    summary: "Stratified samples: one per cell of a regular grid, optionally jittered.",
    params: &[SAMPLE_COUNT, SEED, JITTER],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SamplerDesc, SceneError> {
    let kind = SamplerKind::Stratified { jitter: jitter(p)? };
    with_common(p, kind)
}
