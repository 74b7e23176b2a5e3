//! `sphere`: an analytic sphere (Mitsuba 3 `src/shapes/sphere.cpp`); `to_world` may only rotate,
//! scale uniformly and translate it.

use super::{BSDF, EMITTER, FLIP_NORMALS, MEDIA, TO_WORLD, assemble, check_similarity, common};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{Geometry, ShapeDesc};
use crate::xml::{Builder, Params, SceneError};
use glam::DVec3;

const CENTER: ParamSpec = ParamSpec::new(
    "center",
    ParamType::Point,
    DefaultValue::Derived("(0, 0, 0)"),
    "centre, in object space",
);
const RADIUS: ParamSpec = ParamSpec::new(
    "radius",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "radius, in object space (positive)",
);

/// The `sphere` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "sphere",
    summary: "Sphere of the given centre and radius.",
    params: &[TO_WORLD, FLIP_NORMALS, CENTER, RADIUS, BSDF, EMITTER, MEDIA],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let c = common(p)?;
    let center = p.point_opt(CENTER.name)?.map_or(DVec3::ZERO, |(c, _)| c);
    let radius = p.float_checked(
        RADIUS.name,
        RADIUS.default.float(),
        |r| r > 0.0,
        "must be positive",
    )?;
    check_similarity(p, c.to_world())?;
    let geometry = Geometry::Sphere {
        center: center.as_vec3(),
        radius: radius as f32,
    };
    assemble(b, p, c, geometry, false)
}
