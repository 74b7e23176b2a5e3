//! `blackbody`: Planck's law at a temperature, as a radiance (Mitsuba 3
//! `src/spectra/blackbody.cpp`; the spectrum itself is
//! [`gonio_core::Spectrum::blackbody_radiance`]).
//!
//! B(λ, T) = 2hc² / (λ⁵ (e^{hc/(λ k_B T)} − 1)) in W·m⁻²·sr⁻¹·nm⁻¹ between `wavelength_min` and
//! `wavelength_max` (ends included) and 0 outside, as Mitsuba evaluates it: physical units, so a
//! 5000 K emitter has a radiance near 11 000 at 456 nm (a scene modelled in metres gives
//! watts). `scale` is ours (Mitsuba's plugin has none).
//!
//! | parameter | type | default |
//! |---|---|---|
//! | `temperature` | float | required (K, positive) |
//! | `wavelength_min`, `wavelength_max` | float | 360, 830 (nm) |
//! | `scale` | float | 1 (ours) |

use super::{SCALE, scale, wavelength_range};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use gonio_core::spectra::Spectrum;

const TEMPERATURE: ParamSpec = ParamSpec::new(
    "temperature",
    ParamType::Float,
    DefaultValue::None,
    "temperature in kelvin (required, positive)",
);

const WAVELENGTH_MIN: ParamSpec = ParamSpec::new(
    "wavelength_min",
    ParamType::Float,
    DefaultValue::Float(360.0),
    "shortest wavelength emitted (nm; 0 below)",
);

const WAVELENGTH_MAX: ParamSpec = ParamSpec::new(
    "wavelength_max",
    ParamType::Float,
    DefaultValue::Float(830.0),
    "longest wavelength emitted (nm; 0 above)",
);

/// The `blackbody` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "blackbody",
    summary: "Black-body radiance (Planck's law) at `temperature` in W·m⁻²·sr⁻¹·nm⁻¹ (physical units, as Mitsuba's), 0 outside `wavelength_min`–`wavelength_max`; times `scale` (ours).",
    params: &[TEMPERATURE, WAVELENGTH_MIN, WAVELENGTH_MAX, SCALE],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let Some((t, tloc)) = p.float_opt(TEMPERATURE.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "<spectrum type=\"blackbody\"> needs a temperature",
        ));
    };
    if !(t > 0.0 && t.is_finite()) {
        return Err(err(
            tloc,
            ErrorKind::BadValue,
            format!("invalid temperature {t} K (must be positive)"),
        ));
    }
    let range = wavelength_range(p, &WAVELENGTH_MIN, &WAVELENGTH_MAX)?;
    let scale = scale(p)? as f32;
    let b = Spectrum::blackbody_radiance(t as f32, range);
    let s = b.scaled(scale).ok_or_else(|| {
        err(
            &p.obj.loc,
            ErrorKind::BadValue,
            format!("blackbody of {t} K times scale {scale} is not finite"),
        )
    })?;
    Ok(Texture::Spectrum(s))
}
