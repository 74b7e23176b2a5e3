//! `regular`: values at evenly spaced wavelengths, linearly interpolated, 0 outside (Mitsuba 3
//! `src/spectra/regular.cpp`): n values at λᵢ = λ_min + i·(λ_max − λ_min)/(n − 1).
//!
//! | parameter | type | default |
//! |---|---|---|
//! | `wavelength_min`, `wavelength_max` | float | required (nm) |
//! | `values` | string | required: at least two numbers, non-negative |

use super::{number_list, sampled, wavelength_range};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};

const WAVELENGTH_MIN: ParamSpec = ParamSpec::new(
    "wavelength_min",
    ParamType::Float,
    DefaultValue::None,
    "wavelength of the first value (nm, required)",
);

const WAVELENGTH_MAX: ParamSpec = ParamSpec::new(
    "wavelength_max",
    ParamType::Float,
    DefaultValue::None,
    "wavelength of the last value (nm, required)",
);

const VALUES: ParamSpec = ParamSpec::new(
    "values",
    ParamType::String,
    DefaultValue::None,
    "the values, separated by commas or spaces (at least two)",
);

/// The `regular` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "regular",
    summary: "Values at evenly spaced wavelengths from `wavelength_min` to `wavelength_max`, linearly interpolated, 0 outside.",
    params: &[WAVELENGTH_MIN, WAVELENGTH_MAX, VALUES],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let [lo, hi] = wavelength_range(p, &WAVELENGTH_MIN, &WAVELENGTH_MAX)?;
    let (values, loc) = number_list(p, &VALUES, 2)?;
    let step = (hi as f64 - lo as f64) / (values.len() - 1) as f64;
    let lambda = (0..values.len())
        .map(|i| (lo as f64 + i as f64 * step) as f32)
        .collect();
    let values = values.iter().map(|&v| v as f32).collect();
    Ok(Texture::Spectrum(sampled(lambda, values, &loc)?))
}
