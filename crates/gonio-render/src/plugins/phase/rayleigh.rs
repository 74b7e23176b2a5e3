//! `rayleigh`: scattering by particles much smaller than the wavelength, p = 3(1 + cos²θ)/(16π)
//! (Mitsuba 3 `src/phase/rayleigh.cpp`, unpolarized). No parameters.

use crate::medium::Phase;
use crate::plugins::Plugin;
use crate::xml::{Builder, Params, SceneError};
use gonio_core::phase::PhaseFunction;

/// The `rayleigh` plugin.
pub static PLUGIN: Plugin<Phase> = Plugin {
    name: "rayleigh",
    summary: "Rayleigh phase function, 3(1 + cos²θ)/(16π) (unpolarized).",
    params: &[],
    build,
};

fn build<'d>(_: &mut Builder<'d>, _: &mut Params<'d>) -> Result<Phase, SceneError> {
    Ok(Phase::Model(PhaseFunction::Rayleigh))
}
