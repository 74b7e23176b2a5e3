//! `obj`: a Wavefront OBJ triangle mesh (Mitsuba 3 `src/shapes/obj.cpp`; loader [`crate::mesh::load_obj`]).

use super::{BSDF, EMITTER, FACE_NORMALS, FLIP_NORMALS, MEDIA, MeshFormat, TO_WORLD, mesh_file};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::ShapeDesc;
use crate::xml::{Builder, Params, SceneError};

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the Wavefront OBJ file, relative to the scene file (required)",
);
const FLIP_TEX_COORDS: ParamSpec = ParamSpec::new(
    "flip_tex_coords",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "use 1 − v as the v texture coordinate",
);

/// The `obj` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "obj",
    summary: "Wavefront OBJ triangle mesh; vertex normals are computed when the file has none (unless `face_normals`).",
    params: &[
        TO_WORLD,
        FLIP_NORMALS,
        FILENAME,
        FACE_NORMALS,
        FLIP_TEX_COORDS,
        BSDF,
        EMITTER,
        MEDIA,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    mesh_file(b, p, &FILENAME, &FLIP_TEX_COORDS, MeshFormat::Obj)
}
