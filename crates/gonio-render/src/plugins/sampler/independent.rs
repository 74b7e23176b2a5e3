//! `independent`: independent uniform samples (Mitsuba 3 `src/samplers/independent.cpp`).

use super::{SAMPLE_COUNT, SEED, with_common};
use crate::plugins::Plugin;
use crate::scene::{SamplerDesc, SamplerKind};
use crate::xml::{Builder, Params, SceneError};

/// The `independent` plugin.
pub static PLUGIN: Plugin<SamplerDesc> = Plugin {
    name: "independent",
    summary: "Independent uniform random samples.",
    params: &[SAMPLE_COUNT, SEED],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SamplerDesc, SceneError> {
    with_common(p, SamplerKind::Independent)
}
