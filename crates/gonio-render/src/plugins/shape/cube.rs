//! `cube`: the cube [−1, 1]³ as a triangle mesh (Mitsuba 3 `src/shapes/cube.cpp`;
//! [`crate::mesh::cube`]).

use super::{BSDF, EMITTER, FACE_NORMALS, FLIP_NORMALS, MEDIA, TO_WORLD, assemble, common};
use crate::plugins::Plugin;
use crate::scene::{Geometry, ShapeDesc};
use crate::xml::{Builder, Params, SceneError};
use std::sync::Arc;

/// The `cube` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "cube",
    summary: "Cube [−1, 1]³ (12 triangles), placed by `to_world`.",
    params: &[TO_WORLD, FLIP_NORMALS, FACE_NORMALS, BSDF, EMITTER, MEDIA],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let c = common(p)?;
    let face_normals = p.bool(FACE_NORMALS.name, FACE_NORMALS.default.bool())?;
    let geometry = Geometry::Mesh(Arc::new(crate::mesh::cube()));
    assemble(b, p, c, geometry, face_normals)
}
