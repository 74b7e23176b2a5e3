//! `uniform`: the same value at every wavelength (Mitsuba 3 `src/spectra/uniform.cpp`).

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};
use gonio_core::spectra::Spectrum;

const VALUE: ParamSpec = ParamSpec::new(
    "value",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "the value (not × D65, even on emitters)",
);

/// The `uniform` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "uniform",
    summary: "Uniform spectrum: one value at every wavelength.",
    params: &[VALUE],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let v = p.float(VALUE.name, VALUE.default.float())?;
    Ok(Texture::Spectrum(Spectrum::Constant(v as f32)))
}
