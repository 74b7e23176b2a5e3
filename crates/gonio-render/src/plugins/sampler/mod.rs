//! `<sampler>` plugins (nested in a sensor; Mitsuba 3 `src/samplers/`). The runtime samplers are
//! in [`crate::sampler`]. Every sampler takes [`SAMPLE_COUNT`] and [`SEED`]; the stratified ones
//! also [`JITTER`].

pub mod independent;
pub mod ldsampler;
pub mod multijitter;
pub mod orthogonal;
pub mod stratified;

use crate::plugins::{DefaultValue, ParamSpec, ParamType};
use crate::scene::{SamplerDesc, SamplerKind};
use crate::xml::{Params, SceneError};

/// `sample_count`, shared by every sampler.
pub const SAMPLE_COUNT: ParamSpec = ParamSpec::new(
    "sample_count",
    ParamType::Integer,
    DefaultValue::Int(4),
    "samples per pixel (≥ 1)",
);
/// `seed`, shared by every sampler.
pub const SEED: ParamSpec = ParamSpec::new(
    "seed",
    ParamType::Integer,
    DefaultValue::Int(0),
    "seed of the sample sequences (≥ 0)",
);
/// `jitter`, shared by the stratified samplers.
pub const JITTER: ParamSpec = ParamSpec::new(
    "jitter",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "jitter the samples inside their strata",
);

/// The `jitter` parameter of a stratified sampler.
fn jitter(p: &mut Params<'_>) -> Result<bool, SceneError> {
    p.bool(JITTER.name, JITTER.default.bool())
}

/// A sampler of `kind` with the shared parameters read from `p`.
fn with_common(p: &mut Params<'_>, kind: SamplerKind) -> Result<SamplerDesc, SceneError> {
    let sample_count = p.int_in(SAMPLE_COUNT.name, SAMPLE_COUNT.default.int(), 1, u32::MAX as i64)? as u32;
    let seed = p.int_in(SEED.name, SEED.default.int(), 0, i64::MAX)? as u64;
    Ok(SamplerDesc {
        kind,
        sample_count,
        seed,
    })
}
