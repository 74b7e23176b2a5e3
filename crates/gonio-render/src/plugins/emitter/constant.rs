//! `constant`: light of the same radiance from every direction (Mitsuba 3
//! `src/emitters/constant.cpp`).

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::EmitterDesc;
use crate::xml::{Builder, Params, SceneError};
use gonio_core::spectra::RgbKind;

const RADIANCE: ParamSpec = ParamSpec::new(
    "radiance",
    ParamType::Spectrum,
    DefaultValue::Float(1.0),
    "radiance arriving from every direction (numbers and colours × D65)",
);

/// The `constant` plugin.
pub static PLUGIN: Plugin<EmitterDesc> = Plugin {
    name: "constant",
    summary: "Constant environment: uniform radiance from the sphere of directions.",
    params: &[RADIANCE, super::MEDIUM],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<EmitterDesc, SceneError> {
    let radiance = b.spectrum(p, &RADIANCE, RgbKind::Illuminant)?;
    Ok(EmitterDesc::Constant { radiance })
}
