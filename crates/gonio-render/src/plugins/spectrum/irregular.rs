//! `irregular`: values at given wavelengths, linearly interpolated, 0 outside (Mitsuba 3
//! `src/spectra/irregular.cpp`; the inline `<spectrum value="400:0.1, 500:0.3"/>` is the same
//! spectrum).
//!
//! | parameter | type | default |
//! |---|---|---|
//! | `wavelengths` | string | required: increasing, nm |
//! | `values` | string | required: one per wavelength, non-negative |

use super::{number_list, sampled};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};

const WAVELENGTHS: ParamSpec = ParamSpec::new(
    "wavelengths",
    ParamType::String,
    DefaultValue::None,
    "the wavelengths (nm, strictly increasing, at least two)",
);

const VALUES: ParamSpec = ParamSpec::new(
    "values",
    ParamType::String,
    DefaultValue::None,
    "the value at each wavelength",
);

/// The `irregular` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "irregular",
    summary: "Values at the given `wavelengths`, linearly interpolated, 0 outside.",
    params: &[WAVELENGTHS, VALUES],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let (lambda, _) = number_list(p, &WAVELENGTHS, 2)?;
    let (values, loc) = number_list(p, &VALUES, 2)?;
    let lambda = lambda.iter().map(|&v| v as f32).collect();
    let values = values.iter().map(|&v| v as f32).collect();
    Ok(Texture::Spectrum(sampled(lambda, values, &loc)?))
}
