//! `radiancemeter`: the radiance arriving at one point from one direction (Mitsuba 3
//! `src/sensors/radiancemeter.cpp`): every camera sample is the ray from `origin` along
//! `direction` (or from `to_world`'s origin along its +z), recorded in a film of one pixel. The
//! runtime camera is [`crate::camera::RadianceMeter`]; light tracing cannot reach it (a delta in
//! position and direction), so `ptracer` sees nothing, as in Mitsuba.
//!
//! | parameter | default |
//! |---|---|
//! | `to_world` | identity (not with `origin`/`direction`) |
//! | `origin`, `direction` | (0, 0, 0), (0, 0, 1) |
//! | nested `film`, `sampler` | hdrfilm (1 × 1 pixels required), independent |

use super::perspective::{FILM, MEDIUM, SAMPLER, SRF, film_and_sampler};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{Projection, SensorDesc};
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use glam::{Affine3A, Mat3, Vec3};

const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "the ray: from this frame's origin along its +z (not with `origin` or `direction`)",
);
const ORIGIN: ParamSpec = ParamSpec::new(
    "origin",
    ParamType::Point,
    DefaultValue::None,
    "where the ray starts (default (0, 0, 0))",
);
const DIRECTION: ParamSpec = ParamSpec::new(
    "direction",
    ParamType::Point,
    DefaultValue::None,
    "where the ray goes (a vector, normalized; default (0, 0, 1))",
);

/// The `radiancemeter` plugin.
pub static PLUGIN: Plugin<SensorDesc> = Plugin {
    name: "radiancemeter",
    summary: "Radiance meter: the radiance along one ray (from `origin` along `direction`) into a film of 1 × 1 pixels.",
    params: &[TO_WORLD, ORIGIN, DIRECTION, FILM, SAMPLER, MEDIUM, SRF],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SensorDesc, SceneError> {
    let (film, sampler) = film_and_sampler(b, p)?;
    super::one_pixel(&film, p, "a radiancemeter records one ray")?;
    let has_to_world = p.has(TO_WORLD.name);
    let to_world = p.affine(TO_WORLD.name)?;
    let origin = p.point_opt(ORIGIN.name)?;
    let direction = p.point_opt(DIRECTION.name)?;
    if has_to_world && (origin.is_some() || direction.is_some()) {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "give the radiancemeter's ray either by to_world or by origin and direction, not both",
        ));
    }
    let to_world = if has_to_world {
        to_world
    } else {
        let o = origin.map_or(Vec3::ZERO, |(v, _)| v.as_vec3());
        if !o.is_finite() {
            return Err(err(
                &p.obj.loc,
                ErrorKind::BadValue,
                format!("invalid origin {o}"),
            ));
        }
        frame_along(direction, o)?
    };
    check_forward(&to_world, p, "radiancemeter")?;
    Ok(SensorDesc {
        to_world,
        fov_x_deg: 0.0,
        projection: Projection::RadianceMeter,
        near_clip: 0.0,
        far_clip: f32::INFINITY,
        film,
        sampler,
        children: Vec::new(),
        target_shape: None,
    })
}

/// The frame at `origin` whose +z is `direction` (a vector, normalized; +z when absent), as the
/// `direction` parameter of `radiancemeter` and `distant` gives it: refused when not finite or
/// zero.
pub(super) fn frame_along(
    direction: Option<(glam::DVec3, &crate::xml::Location)>,
    origin: Vec3,
) -> Result<Affine3A, SceneError> {
    let d = match direction {
        None => Vec3::Z,
        Some((v, loc)) => {
            let d = v.as_vec3();
            if !(d.is_finite() && d.length() > 0.0) {
                return Err(err(
                    loc,
                    ErrorKind::BadValue,
                    format!(
                        "invalid direction ({}, {}, {}) (must be finite and non-zero)",
                        v.x, v.y, v.z
                    ),
                ));
            }
            d.normalize()
        }
    };
    let (x, y) = d.any_orthonormal_pair();
    Ok(Affine3A::from_mat3_translation(Mat3::from_cols(x, y, d), origin))
}

/// Refuses a sensor frame without a +z direction (the rays' direction of `radiancemeter` and
/// `distant`).
pub(super) fn check_forward(to_world: &Affine3A, p: &Params<'_>, sensor: &str) -> Result<(), SceneError> {
    if to_world.is_finite() && to_world.matrix3.z_axis.length() > 0.0 {
        Ok(())
    } else {
        Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            format!("the {sensor}'s to_world has no +z direction"),
        ))
    }
}
