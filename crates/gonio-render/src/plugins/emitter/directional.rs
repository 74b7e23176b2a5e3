//! `directional`: light from one direction, as from an infinitely distant source (Mitsuba 3
//! `src/emitters/directional.cpp`).

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::EmitterDesc;
use crate::xml::{Builder, ErrorKind, Params, SceneError, err, to_affine};
use glam::Vec3;
use gonio_core::spectra::RgbKind;

const IRRADIANCE: ParamSpec = ParamSpec::new(
    "irradiance",
    ParamType::Spectrum,
    DefaultValue::Float(1.0),
    "irradiance on a surface facing the light, W/m² (numbers and colours × D65)",
);
const DIRECTION: ParamSpec = ParamSpec::new(
    "direction",
    ParamType::Point,
    DefaultValue::Derived("(0, 0, 1)"),
    "direction the light travels in (instead of `to_world`); non-zero",
);
const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "the light travels along the image of +z (instead of `direction`)",
);

/// The `directional` plugin.
pub static PLUGIN: Plugin<EmitterDesc> = Plugin {
    name: "directional",
    summary: "Directional light: parallel rays along `direction`.",
    params: &[IRRADIANCE, DIRECTION, TO_WORLD, super::MEDIUM],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<EmitterDesc, SceneError> {
    let irradiance = b.spectrum(p, &IRRADIANCE, RgbKind::Illuminant)?;
    let dir = p.point_opt(DIRECTION.name)?;
    let tw = p.transform_opt(TO_WORLD.name)?;
    let (d, loc) = match (dir, tw) {
        (Some(_), Some((_, loc))) => {
            return Err(err(
                loc,
                ErrorKind::Grammar,
                "give either direction or to_world, not both",
            ));
        }
        (Some((v, loc)), None) => (v.as_vec3(), loc),
        (None, Some((m, loc))) => (to_affine(m, loc, TO_WORLD.name)?.transform_vector3(Vec3::Z), loc),
        (None, None) => (Vec3::Z, &p.obj.loc),
    };
    if !(d.length_squared() > 0.0) || !d.is_finite() {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!("invalid direction {d} (must be non-zero)"),
        ));
    }
    Ok(EmitterDesc::Directional {
        direction: d.normalize(),
        irradiance,
    })
}
