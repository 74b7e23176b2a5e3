//! `instance`: a `shapegroup` placed in the scene (Mitsuba 3 `src/shapes/instance.cpp`).
//!
//! The group's shapes keep their materials and `flip_normals`; the instance adds `to_world`.
//! The reader turns one instance into one scene shape per member of the group
//! ([`Geometry::Instance`] with `member: Some(i)`), so that each carries its own material while
//! the geometry and its BVH stay shared ([`crate::geometry::instance`]).
//!
//! | parameter | default |
//! |---|---|
//! | `to_world` | identity |
//! | one nested or referenced `shapegroup` | required |

use super::TO_WORLD;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{Geometry, ShapeDesc};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};

const GROUP: ParamSpec = ParamSpec::new(
    "(nested shapegroup)",
    ParamType::Shape,
    DefaultValue::None,
    "the `shapegroup` to place, nested or referenced (required, exactly one)",
);

/// The `instance` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "instance",
    summary: "A `shapegroup` placed by `to_world` (a two-level BVH: the group's geometry and BVH are shared by all its instances).",
    params: &[TO_WORLD, GROUP],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let to_world = p.affine(TO_WORLD.name)?;
    let shapes = p.objects(Tag::Shape)?;
    let idx = match shapes.as_slice() {
        [] => {
            return Err(err(
                &p.obj.loc,
                ErrorKind::Grammar,
                "<shape type=\"instance\">: a reference to a shapegroup must be specified",
            ));
        }
        [(i, prop)] => {
            if b.doc.objs[*i].ty != "shapegroup" {
                return Err(err(
                    &prop.loc,
                    ErrorKind::BadValue,
                    format!(
                        "<shape type=\"instance\">: only a shapegroup can be placed by an instance (found a \"{}\")",
                        b.doc.objs[*i].ty
                    ),
                ));
            }
            *i
        }
        [_, (_, extra), ..] => {
            return Err(err(
                &extra.loc,
                ErrorKind::Grammar,
                "<shape type=\"instance\">: only a single shapegroup can be specified per instance",
            ));
        }
    };
    p.finish()?;
    let group = super::shapegroup::group(b, idx)?;
    let desc = ShapeDesc {
        geometry: Geometry::Instance { group, member: None },
        to_world,
        flip_normals: false,
        face_normals: false,
        outside_only: false,
        media: Default::default(),
        material: b.shape_material(None, false)?,
        emitter: None,
        id: p.obj.id.clone(),
    };
    crate::geometry::WorldShape::check_placement(&desc, "<shape type=\"instance\">")
        .map_err(|e| err(&p.obj.loc, ErrorKind::BadValue, e.to_string()))?;
    Ok(desc)
}

/// Adds the top-level `<shape>` object `idx` to the scene's `shapes`: a `shapegroup` adds
/// nothing (it is built and checked, and placed by its instances), an `instance` adds one shape
/// per member of its group, a `merge` its nested shapes, any other shape itself.
pub(crate) fn place(b: &mut Builder<'_>, idx: usize, shapes: &mut Vec<ShapeDesc>) -> Result<(), SceneError> {
    match b.doc.objs[idx].ty.as_str() {
        "shapegroup" => {
            super::shapegroup::group(b, idx)?;
            return Ok(());
        }
        "merge" => {
            let mut kids = Vec::new();
            super::merge::flatten(b, idx, &mut kids)?;
            for kid in kids {
                place(b, kid, shapes)?;
            }
            return Ok(());
        }
        _ => {}
    }
    let desc = b.build_plugin(super::super::SHAPE_PLUGINS, idx)?;
    expand(desc, shapes);
    if let Some((mut sensor, loc)) = b.shape_sensor.take() {
        sensor.projection = crate::scene::Projection::IrradianceMeter {
            shape: shapes.len() - 1,
        };
        b.shape_sensors.push((sensor, loc));
    }
    Ok(())
}

/// Pushes `desc`, or for an unexpanded instance one shape per member of its group.
pub fn expand(desc: ShapeDesc, shapes: &mut Vec<ShapeDesc>) {
    match &desc.geometry {
        Geometry::Instance { group, member: None } => {
            for (i, m) in group.shapes.iter().enumerate() {
                shapes.push(ShapeDesc {
                    geometry: Geometry::Instance {
                        group: group.clone(),
                        member: Some(i),
                    },
                    material: m.material,
                    outside_only: m.outside_only,
                    media: m.media,
                    ..desc.clone()
                });
            }
        }
        Geometry::Group(_) => {}
        _ => shapes.push(desc),
    }
}
