//! `ply`: a Stanford PLY triangle mesh, ASCII or binary (Mitsuba 3 `src/shapes/ply.cpp`; loader [`crate::mesh::load_ply`]).

use super::{BSDF, EMITTER, FACE_NORMALS, FLIP_NORMALS, MEDIA, MeshFormat, TO_WORLD, mesh_file};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::ShapeDesc;
use crate::xml::{Builder, Params, SceneError};

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the Stanford PLY file, relative to the scene file (required)",
);
const FLIP_TEX_COORDS: ParamSpec = ParamSpec::new(
    "flip_tex_coords",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "use 1 − v as the v texture coordinate",
);

/// The `ply` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "ply",
    summary: "Stanford PLY triangle mesh; vertex normals are computed when the file has none (unless `face_normals`).",
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
    mesh_file(b, p, &FILENAME, &FLIP_TEX_COORDS, MeshFormat::Ply)
}
