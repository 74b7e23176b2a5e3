//! `point`: an isotropic point light (Mitsuba 3 `src/emitters/point.cpp`).

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::EmitterDesc;
use crate::xml::{Builder, ErrorKind, Params, SceneError, err, to_affine};
use glam::Vec3;
use gonio_core::spectra::RgbKind;

const INTENSITY: ParamSpec = ParamSpec::new(
    "intensity",
    ParamType::Spectrum,
    DefaultValue::Float(1.0),
    "radiant intensity, W/sr (numbers and colours × D65)",
);
const POSITION: ParamSpec = ParamSpec::new(
    "position",
    ParamType::Point,
    DefaultValue::Derived("(0, 0, 0)"),
    "world position (instead of `to_world`)",
);
const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "places the light at the image of the origin (instead of `position`)",
);

/// The `point` plugin.
pub static PLUGIN: Plugin<EmitterDesc> = Plugin {
    name: "point",
    summary: "Point light radiating the same intensity in every direction.",
    params: &[INTENSITY, POSITION, TO_WORLD, super::MEDIUM],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<EmitterDesc, SceneError> {
    let intensity = b.spectrum(p, &INTENSITY, RgbKind::Illuminant)?;
    let pos = p.point_opt(POSITION.name)?;
    let tw = p.transform_opt(TO_WORLD.name)?;
    let position = match (pos, tw) {
        (Some(_), Some((_, loc))) => {
            return Err(err(
                loc,
                ErrorKind::Grammar,
                "give either position or to_world, not both",
            ));
        }
        (Some((v, _)), None) => v.as_vec3(),
        (None, Some((m, loc))) => to_affine(m, loc, TO_WORLD.name)?.transform_point3(Vec3::ZERO),
        (None, None) => Vec3::ZERO,
    };
    Ok(EmitterDesc::Point { position, intensity })
}
