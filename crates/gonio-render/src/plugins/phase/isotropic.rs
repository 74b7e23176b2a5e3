//! `isotropic`: scattering into every direction alike, p = 1/(4π) (Mitsuba 3
//! `src/phase/isotropic.cpp`). No parameters.

use crate::medium::Phase;
use crate::plugins::Plugin;
use crate::xml::{Builder, Params, SceneError};
use gonio_core::phase::PhaseFunction;

/// The `isotropic` plugin.
pub static PLUGIN: Plugin<Phase> = Plugin {
    name: "isotropic",
    summary: "Isotropic phase function, 1/(4π).",
    params: &[],
    build,
};

fn build<'d>(_: &mut Builder<'d>, _: &mut Params<'d>) -> Result<Phase, SceneError> {
    Ok(Phase::Model(PhaseFunction::Isotropic))
}
