//! `disk`: the unit disk in the plane z = 0, normal +z (Mitsuba 3 `src/shapes/disk.cpp`);
//! `to_world` may only rotate, scale uniformly and translate it.

use super::{BSDF, EMITTER, FLIP_NORMALS, TO_WORLD, assemble, check_similarity, common};
use crate::plugins::Plugin;
use crate::scene::{Geometry, ShapeDesc};
use crate::xml::{Builder, Params, SceneError};

/// The `disk` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "disk",
    summary: "Unit disk in z = 0 with normal +z, placed by `to_world` (a similarity).",
    params: &[TO_WORLD, FLIP_NORMALS, BSDF, EMITTER],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let c = common(p)?;
    check_similarity(p, c.to_world())?;
    assemble(b, p, c, Geometry::Disk, false)
}
