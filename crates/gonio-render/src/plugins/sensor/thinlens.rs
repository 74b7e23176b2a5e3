//! `thinlens`: Mitsuba 3's thin-lens camera (`src/sensors/thinlens.cpp`; Kolb, Mitchell and
//! Hanrahan 1995, "A realistic camera model for computer graphics").
//!
//! The pinhole ray of film position (s, t) (as `perspective`) meets the plane z = f
//! (`focus_distance`) at the point F = p_near · f / p_near.z. A lens point
//! A = r·concentric(u) (the Shirley–Chiu map of the 2D sample u onto the unit disk, r =
//! `aperture_radius`, in the z = 0 plane) gives the ray from A towards F; it starts on the near
//! plane and ends on the far plane. Points at distance f are in focus; r = 0 is the pinhole.
//! The runtime camera is [`crate::camera::ThinLensCamera`].
//!
//! | parameter | default |
//! |---|---|
//! | `aperture_radius` | required (≥ 0) |
//! | `focus_distance` | `far_clip` |
//! | `fov` / `focal_length`, `fov_axis`, `near_clip`, `far_clip`, `to_world` | as `perspective` |
//! | nested `film`, `sampler` | hdrfilm, independent |

use super::perspective::{
    FAR_CLIP, FILM, FOCAL_LENGTH, FOV, FOV_AXIS, MEDIUM, NEAR_CLIP, PRINCIPAL_POINT_OFFSET_X,
    PRINCIPAL_POINT_OFFSET_Y, SAMPLER, SHUTTER_CLOSE, SHUTTER_OPEN, SRF, TO_WORLD, build_projective,
};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{Projection, SensorDesc};
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};

const APERTURE_RADIUS: ParamSpec = ParamSpec::new(
    "aperture_radius",
    ParamType::Float,
    DefaultValue::None,
    "radius of the lens (required; 0 is a pinhole)",
);
const FOCUS_DISTANCE: ParamSpec = ParamSpec::new(
    "focus_distance",
    ParamType::Float,
    DefaultValue::Derived("far_clip"),
    "distance of the plane in focus (positive)",
);

/// The `thinlens` plugin.
pub static PLUGIN: Plugin<SensorDesc> = Plugin {
    name: "thinlens",
    summary: "Thin-lens camera: depth of field from a lens of radius `aperture_radius` focused at `focus_distance`.",
    params: &[
        APERTURE_RADIUS,
        FOCUS_DISTANCE,
        TO_WORLD,
        FOV,
        FOCAL_LENGTH,
        FOV_AXIS,
        NEAR_CLIP,
        FAR_CLIP,
        PRINCIPAL_POINT_OFFSET_X,
        PRINCIPAL_POINT_OFFSET_Y,
        SHUTTER_OPEN,
        SHUTTER_CLOSE,
        FILM,
        SAMPLER,
        MEDIUM,
        SRF,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SensorDesc, SceneError> {
    let Some((r, r_loc)) = p.float_opt(APERTURE_RADIUS.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "<sensor type=\"thinlens\"> needs an aperture_radius",
        ));
    };
    if !(r >= 0.0 && r.is_finite()) {
        return Err(err(
            r_loc,
            ErrorKind::BadValue,
            format!("invalid aperture_radius {r} (must be finite and ≥ 0)"),
        ));
    }
    let focus = p.float_opt(FOCUS_DISTANCE.name)?;
    let mut s = build_projective(b, p, true)?;
    let focus_distance = match focus {
        None => s.far_clip as f64,
        Some((f, loc)) => {
            if !(f > 0.0 && f.is_finite()) {
                return Err(err(
                    loc,
                    ErrorKind::BadValue,
                    format!("invalid focus_distance {f} (must be positive and finite)"),
                ));
            }
            f
        }
    };
    s.projection = Projection::ThinLens {
        aperture_radius: r as f32,
        focus_distance: focus_distance as f32,
    };
    Ok(s)
}
