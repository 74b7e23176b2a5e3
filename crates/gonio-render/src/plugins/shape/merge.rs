//! `merge`: shapes written together (Mitsuba 3 `src/shapes/merge.cpp`, which merges the meshes
//! that share a BSDF into one to speed up its ray tracing). The image is that of the nested
//! shapes placed one by one, and so gonio places them: each keeps its own BSDF, emitter and
//! `to_world`, and the acceleration structure spans them all anyway.
//!
//! | parameter | default |
//! |---|---|
//! | nested `shape`s | none |

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::ShapeDesc;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};

const SHAPES: ParamSpec = ParamSpec::new(
    "(nested shape)",
    ParamType::Shape,
    DefaultValue::None,
    "the shapes, placed as if written one by one (at the top level of the scene or in a `shapegroup`)",
);

/// The `merge` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "merge",
    summary: "Nested shapes placed as if written one by one (Mitsuba merges their meshes for speed; the image is the same).",
    params: &[SHAPES],
    build,
};

/// A `merge` is expanded where it is placed ([`children`]); anywhere else (an `instance`'s
/// group reference) it is not a shape.
fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    Err(err(
        &p.obj.loc,
        ErrorKind::BadValue,
        "<shape type=\"merge\"> may stand at the top level of the scene or in a shapegroup only",
    ))
}

/// The nested `<shape>` objects of the `merge` object `idx`, its parameters checked.
pub(crate) fn children(b: &Builder<'_>, idx: usize) -> Result<Vec<usize>, SceneError> {
    let mut p = Params::with_specs(b.doc, idx, PLUGIN.params);
    let kids = p.objects(Tag::Shape)?.into_iter().map(|(i, _)| i).collect();
    p.finish()?;
    Ok(kids)
}

/// The shapes `idx` stands for: itself, or for a `merge` its nested shapes, merges within it
/// expanded in turn (appended to `out`).
pub(crate) fn flatten(b: &mut Builder<'_>, idx: usize, out: &mut Vec<usize>) -> Result<(), SceneError> {
    if b.doc.objs[idx].ty != "merge" {
        out.push(idx);
        return Ok(());
    }
    let loc = b.doc.objs[idx].loc.clone();
    b.enter(idx, &loc)?;
    for kid in children(b, idx)? {
        flatten(b, kid, out)?;
    }
    b.leave();
    Ok(())
}
