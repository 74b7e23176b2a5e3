//! `constvolume`: one value throughout space (Mitsuba 3 `src/volumes/const.cpp`), the long form
//! of a number or colour given directly as a medium's `albedo` or `sigma_t`.
//!
//! Its users take the constant form of their parameter: a medium's albedo or extinction is the
//! spectrum, a `blendphase` weight its mean over the wavelengths (Mitsuba's `eval_1`), a `volume`
//! texture the constant texture. An `<rgb>` value with components up to 1 is uplifted as a
//! reflectance (as Mitsuba's `srgb` texture), a larger one as an unbounded colour (a medium's
//! extinction; an albedo above 1 is refused where it is used).
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `value` | 1 | the value: a number, `<rgb>` or `<spectrum>` |
//! | `to_world` | identity | places its box, the world-axis-aligned bounds of the transformed unit cube: a `heterogeneous` medium's extinction is 0 outside it (Mitsuba's); other users ignore it |

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::volume::Volume;
use crate::xml::{Builder, Params, SceneError, Value};
use gonio_core::spectra::RgbKind;

const VALUE: ParamSpec = ParamSpec::new(
    "value",
    ParamType::Spectrum,
    DefaultValue::Float(1.0),
    "the value everywhere: a number, `<rgb>` or `<spectrum>`",
);
const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "places its box (the axis-aligned bounds of the transformed unit cube) outside which a heterogeneous medium given this extinction is empty (Mitsuba's); other users ignore it",
);

/// The `constvolume` plugin.
pub static PLUGIN: Plugin<Volume> = Plugin {
    name: "constvolume",
    summary: "One value (number, colour or spectrum) throughout space.",
    params: &[VALUE, TO_WORLD],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Volume, SceneError> {
    let kind = match p
        .obj
        .props
        .iter()
        .find(|x| x.name == VALUE.name)
        .map(|x| &x.value)
    {
        Some(Value::Rgb(c)) if c.iter().any(|&v| v > 1.0) => RgbKind::Unbounded,
        _ => RgbKind::Albedo,
    };
    let value = b.spectrum_param(p, VALUE.name, kind, VALUE.default.float() as f32)?;
    let to_world = p.affine(TO_WORLD.name)?;
    Ok(Volume::Constant(value, to_world))
}
