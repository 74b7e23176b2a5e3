//! `orthographic`: Mitsuba 3's orthographic camera (`src/sensors/orthographic.cpp`).
//!
//! Rays run parallel to the camera's +z axis. Film position (s, t) ∈ [0, 1]² (s to the right,
//! t downwards) starts its ray at the camera-space point (1 − 2s, (1 − 2t)/aspect, near_clip),
//! aspect = width/height, mapped by `to_world` (whose scale sets the size of the view: without
//! one the film covers [−1, 1] horizontally); the ray goes `far_clip − near_clip` along
//! normalize(to_world · +z). The runtime camera is [`crate::camera::OrthographicCamera`].
//!
//! | parameter | default |
//! |---|---|
//! | `to_world` | identity (scale allowed) |
//! | `near_clip`, `far_clip` | 0.01, 10000 |
//! | `focus_distance`, `shutter_open`, `shutter_close` | accepted and ignored |
//! | nested `film`, `sampler` | hdrfilm, independent |

use super::perspective::{
    FAR_CLIP, FILM, FOCUS_DISTANCE, MEDIUM, NEAR_CLIP, SAMPLER, SHUTTER_CLOSE, SHUTTER_OPEN, SRF,
    build_projective,
};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{Projection, SensorDesc};
use crate::xml::{Builder, Params, SceneError};

const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "camera to world (+z forward, +y up); its scale sets the extent of the view ([−1, 1] across the width without one)",
);

/// The `orthographic` plugin.
pub static PLUGIN: Plugin<SensorDesc> = Plugin {
    name: "orthographic",
    summary: "Orthographic camera: parallel rays along +z of `to_world` from [−1, 1] × [−1/aspect, 1/aspect] on the near plane.",
    params: &[
        TO_WORLD,
        NEAR_CLIP,
        FAR_CLIP,
        FOCUS_DISTANCE,
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
    let mut s = build_projective(b, p, false)?;
    s.projection = Projection::Orthographic;
    Ok(s)
}
