//! `shapegroup`: shapes made available for instancing (Mitsuba 3 `src/shapes/shapegroup.cpp`).
//!
//! A group is not rendered by itself; each `instance` that refers to it places its shapes with
//! its own `to_world`, sharing one copy of their geometry and acceleration structure
//! ([`crate::geometry::instance`]). As in Mitsuba, a group may not hold an emitter or another
//! `shapegroup`/`instance`; an empty group is allowed.
//!
//! | parameter | default |
//! |---|---|
//! | nested `shape`s | none |

use crate::geometry::instance::ShapeGroup;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{Geometry, ShapeDesc};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};
use glam::Affine3A;
use std::sync::Arc;

const SHAPES: ParamSpec = ParamSpec::new(
    "(nested shape)",
    ParamType::Shape,
    DefaultValue::None,
    "the group's shapes (no emitters, no nested shapegroup or instance)",
);

/// The `shapegroup` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "shapegroup",
    summary: "Shapes for instancing: not rendered by themselves, placed by `instance` shapes that refer to the group (one copy in memory).",
    params: &[SHAPES],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let mut shapes = Vec::new();
    // A nested `merge` stands for its shapes.
    let mut members = Vec::new();
    for (i, prop) in p.objects(Tag::Shape)? {
        let mut kids = Vec::new();
        super::merge::flatten(b, i, &mut kids)?;
        members.extend(kids.into_iter().map(|k| (k, prop)));
    }
    for (i, prop) in members {
        let ty = b.doc.objs[i].ty.as_str();
        if ty == "shapegroup" || ty == "instance" {
            return Err(err(
                &prop.loc,
                ErrorKind::BadValue,
                format!(
                    "<shape type=\"shapegroup\">: nested instancing is not permitted (found a nested \"{ty}\")"
                ),
            ));
        }
        let shape = b.build_plugin(super::super::SHAPE_PLUGINS, i)?;
        if let Some((_, loc)) = b.shape_sensor.take() {
            return Err(err(
                &loc,
                ErrorKind::Grammar,
                "an irradiancemeter cannot measure over a shape of a shapegroup (place the shape itself)",
            ));
        }
        if shape.emitter.is_some() {
            return Err(err(
                &prop.loc,
                ErrorKind::BadValue,
                "<shape type=\"shapegroup\">: instancing of emitters is not supported",
            ));
        }
        shapes.push(shape);
    }
    p.finish()?;
    let id = p.obj.id.clone().unwrap_or_else(|| "shapegroup".to_owned());
    Ok(ShapeDesc {
        geometry: Geometry::Group(Arc::new(ShapeGroup::new(id, shapes))),
        to_world: Affine3A::IDENTITY,
        flip_normals: false,
        face_normals: false,
        outside_only: false,
        media: Default::default(),
        material: b.shape_material(None, false)?,
        emitter: None,
        id: p.obj.id.clone(),
    })
}

/// The group built from object `idx`, once however many instances place it.
pub(crate) fn group(b: &mut Builder<'_>, idx: usize) -> Result<Arc<ShapeGroup>, SceneError> {
    if let Some(g) = b.groups.get(&idx) {
        return Ok(g.clone());
    }
    b.enter(idx, &b.doc.objs[idx].loc.clone())?;
    let desc = b.run_plugin(&PLUGIN, idx);
    b.leave();
    let Geometry::Group(g) = desc?.geometry else {
        unreachable!("the shapegroup plugin builds a group")
    };
    b.groups.insert(idx, g.clone());
    Ok(g)
}
