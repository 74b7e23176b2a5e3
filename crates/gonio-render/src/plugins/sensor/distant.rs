//! `distant`: Mitsuba 3's distant radiancemeter (`src/sensors/distant.cpp`), the radiance
//! leaving the scene towards one direction, averaged over a target: parallel rays along
//! `to_world`'s +z (or along `direction`) start outside the scene (two bounding-sphere radii
//! before their target) and pass through the `target` point, through points drawn uniformly over
//! the area of a nested `target` shape (which only guides the rays: it is not part of the
//! scene), or, without a target, through points uniform over the cross-section of the scene's
//! bounding sphere. A film of 1 × 1 pixels, as Mitsuba requires. The runtime camera is
//! [`crate::camera::DistantSensor`]; light tracing does not connect to it.
//!
//! | parameter | default |
//! |---|---|
//! | `to_world` | identity (not with `direction`) |
//! | `direction` | (0, 0, 1): where the rays go |
//! | `target` | none: a point, or a nested shape |
//! | nested `film`, `sampler` | hdrfilm (1 × 1 pixels required), independent |

use super::perspective::{FILM, MEDIUM, SAMPLER, SRF, film_and_sampler};
use super::radiancemeter::{check_forward, frame_along};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin, SHAPE_PLUGINS};
use crate::scene::{Geometry, Projection, SensorDesc, TargetShape};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};

const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "the rays run along this frame's +z (not with `direction`)",
);
const DIRECTION: ParamSpec = ParamSpec::new(
    "direction",
    ParamType::Point,
    DefaultValue::None,
    "where the rays go (a vector, normalized; default (0, 0, 1))",
);
const TARGET: ParamSpec = ParamSpec::new(
    "target",
    ParamType::Point,
    DefaultValue::None,
    "the point every ray passes through, or a nested shape (`<shape name=\"target\" ...>`) over whose area the rays are spread; default the scene's bounding sphere",
);

/// The `distant` plugin.
pub static PLUGIN: Plugin<SensorDesc> = Plugin {
    name: "distant",
    summary: "Distant radiancemeter: the radiance leaving the scene against `direction`, averaged over a target point, shape or the scene's cross-section; film of 1 × 1 pixels.",
    params: &[TO_WORLD, DIRECTION, TARGET, FILM, SAMPLER, MEDIUM, SRF],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SensorDesc, SceneError> {
    let (film, sampler) = film_and_sampler(b, p)?;
    super::one_pixel(&film, p, "a distant sensor records one value")?;
    let has_to_world = p.has(TO_WORLD.name);
    let to_world = p.affine(TO_WORLD.name)?;
    let to_world = match p.point_opt(DIRECTION.name)? {
        Some(_) if has_to_world => {
            return Err(err(
                &p.obj.loc,
                ErrorKind::Grammar,
                "give the distant sensor's direction either by to_world or by direction, not both (as Mitsuba requires)",
            ));
        }
        Some(direction) => frame_along(Some(direction), glam::Vec3::ZERO)?,
        None => to_world,
    };
    check_forward(&to_world, p, "distant sensor")?;
    // A nested shape (Mitsuba's `<shape name="target" ...>`), or else a point.
    let shapes = p.objects(Tag::Shape)?;
    let target_point = if shapes.is_empty() {
        p.point_opt(TARGET.name)?.map(|(v, _)| v.as_vec3())
    } else {
        None
    };
    let target_shape = match shapes.as_slice() {
        [] => None,
        [(i, prop)] => {
            let shape = b.build_plugin(SHAPE_PLUGINS, *i)?;
            if let Some((_, loc)) = b.shape_sensor.take() {
                return Err(err(
                    &loc,
                    ErrorKind::Grammar,
                    "a distant sensor's target shape cannot hold a sensor of its own",
                ));
            }
            if !matches!(
                shape.geometry,
                Geometry::Sphere { .. } | Geometry::Rectangle | Geometry::Disk | Geometry::Mesh(_)
            ) {
                return Err(err(
                    &prop.loc,
                    ErrorKind::Grammar,
                    "a distant sensor's target shape must have an area to sample (sphere, rectangle, disk or mesh)",
                ));
            }
            Some(TargetShape(std::sync::Arc::new(shape)))
        }
        [_, (_, extra), ..] => {
            return Err(err(
                &extra.loc,
                ErrorKind::Grammar,
                "a distant sensor takes one target shape",
            ));
        }
    };
    if target_point.is_some_and(|t| !t.is_finite()) {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            "the distant sensor's target is not finite",
        ));
    }
    Ok(SensorDesc {
        to_world,
        fov_x_deg: 0.0,
        projection: Projection::Distant { target_point },
        near_clip: 0.0,
        far_clip: f32::INFINITY,
        film,
        sampler,
        children: Vec::new(),
        target_shape,
    })
}
