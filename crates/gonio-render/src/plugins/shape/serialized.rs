//! `serialized`: one mesh of a Mitsuba serialized file (Mitsuba 3 `src/shapes/serialized.cpp`;
//! loader [`crate::mesh::serialized::load_serialized`]).

use super::{BSDF, EMITTER, FACE_NORMALS, FLIP_NORMALS, MEDIA, MeshFormat, TO_WORLD, assemble, common, mesh};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{Geometry, ShapeDesc};
use crate::xml::{Builder, Params, SceneError};

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the `.serialized` file, found as Mitsuba's file resolver finds it (required)",
);
const SHAPE_INDEX: ParamSpec = ParamSpec::new(
    "shape_index",
    ParamType::Integer,
    DefaultValue::Int(0),
    "which mesh of the file (0: the first)",
);

/// The `serialized` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "serialized",
    summary: "One mesh of a Mitsuba `.serialized` file (zlib-compressed, format versions 3 and 4); vertex normals are computed when the mesh has none (unless `face_normals`).",
    params: &[
        TO_WORLD,
        FLIP_NORMALS,
        FILENAME,
        SHAPE_INDEX,
        FACE_NORMALS,
        BSDF,
        EMITTER,
        MEDIA,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let c = common(p)?;
    let face_normals = p.bool(FACE_NORMALS.name, FACE_NORMALS.default.bool())?;
    let shape_index = p.int_in(
        SHAPE_INDEX.name,
        SHAPE_INDEX.default.int(),
        0,
        i64::from(u32::MAX),
    )? as u32;
    let m = mesh(
        b,
        p,
        &FILENAME,
        MeshFormat::Serialized { shape_index },
        false,
        face_normals,
    )?;
    assemble(b, p, c, Geometry::Mesh(m), face_normals)
}
