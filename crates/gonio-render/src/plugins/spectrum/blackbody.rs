//! `blackbody`: Planck's law at a temperature (Mitsuba 3 `src/spectra/blackbody.cpp`; the
//! spectrum itself is [`gonio_core::Spectrum::blackbody`]).

use super::{SCALE, scale};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use gonio_core::spectra::{Extrapolation, PiecewiseLinear, Spectrum};

const TEMPERATURE: ParamSpec = ParamSpec::new(
    "temperature",
    ParamType::Float,
    DefaultValue::None,
    "temperature in kelvin (required, positive)",
);

/// The `blackbody` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "blackbody",
    summary: "Black-body emission spectrum (Planck's law) at `temperature`, times `scale`.",
    params: &[TEMPERATURE, SCALE],
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
    let scale = scale(p)? as f32;
    let b = Spectrum::blackbody(t as f32);
    Ok(Texture::Spectrum(if scale == 1.0 { b } else { scaled(b, scale) }))
}

/// A spectrum times a factor (as a 1 nm table over the visible range).
fn scaled(s: Spectrum, k: f32) -> Spectrum {
    let lambda: Vec<f32> = (360..=830).map(|l| l as f32).collect();
    let value = lambda.iter().map(|&l| k * s.eval(l)).collect();
    match PiecewiseLinear::new(lambda, value, Extrapolation::Zero) {
        Some(p) => Spectrum::piecewise(p),
        None => Spectrum::Constant(0.0),
    }
}
