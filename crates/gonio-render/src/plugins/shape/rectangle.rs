//! `rectangle`: the square [−1, 1]² in the plane z = 0, normal +z (Mitsuba 3
//! `src/shapes/rectangle.cpp`).

use super::{BSDF, EMITTER, FLIP_NORMALS, MEDIA, TO_WORLD, assemble, common};
use crate::plugins::Plugin;
use crate::scene::{Geometry, ShapeDesc};
use crate::xml::{Builder, Params, SceneError};

/// The `rectangle` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "rectangle",
    summary: "Rectangle [−1, 1]² in z = 0 with normal +z, placed by `to_world`.",
    params: &[TO_WORLD, FLIP_NORMALS, BSDF, EMITTER, MEDIA],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let c = common(p)?;
    assemble(b, p, c, Geometry::Rectangle, false)
}
