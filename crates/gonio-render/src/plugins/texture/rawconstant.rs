//! `rawconstant`: one value everywhere, taken as it is written (Mitsuba 3
//! `src/textures/rawconstant.cpp`): a number is the same at every wavelength (never × D65, even
//! on an emitter); three numbers are a colour read raw where a plugin reads colours (a normal
//! map's constant), uplifted as an unbounded colour where a spectrum is needed (Mitsuba's
//! spectral variants refuse that).
//!
//! | parameter | type | default |
//! |---|---|---|
//! | `value` | float or rgb | required |

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Value, err};

const VALUE: ParamSpec = ParamSpec::new(
    "value",
    ParamType::Rgb,
    DefaultValue::None,
    "the value: one number, or three (a raw colour); finite",
);

/// The `rawconstant` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "rawconstant",
    summary: "One value everywhere, as written: a number (not × D65 on emitters) or a raw colour.",
    params: &[VALUE],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let Some(prop) = p.get(VALUE.name) else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "<texture type=\"rawconstant\"> needs a value",
        ));
    };
    let values: Vec<f64> = match prop.value {
        Value::Float(v) => vec![v],
        Value::Int(v) => vec![v as f64],
        Value::Rgb(c) => c.to_vec(),
        _ => return Err(p.wrong_type(prop, "float or rgb")),
    };
    if !values.iter().all(|v| (*v as f32).is_finite() && *v >= 0.0) {
        return Err(err(
            &prop.value_loc,
            ErrorKind::BadValue,
            format!("invalid value {values:?} (finite and non-negative)"),
        ));
    }
    Ok(match values[..] {
        [r, g, b] => Texture::raw_rgb([r, g, b]),
        _ => Texture::constant(values[0] as f32),
    })
}
