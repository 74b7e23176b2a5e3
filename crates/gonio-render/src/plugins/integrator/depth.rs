//! `depth`: the distance to the first surface along each camera ray (Mitsuba 3
//! `src/integrators/depth.cpp`): the value t of the hit o + t·d (d of unit length) in every
//! colour channel, 0 where the ray leaves the scene. It has no parameters.

use crate::plugins::Plugin;
use crate::scene::{IntegratorDesc, IntegratorKind};
use crate::xml::{Builder, Params, SceneError};

/// The `depth` plugin.
pub static PLUGIN: Plugin<IntegratorDesc> = Plugin {
    name: "depth",
    summary: "Distance from the camera to the first hit along each ray (0 where the ray escapes), in R, G and B.",
    params: &[],
    build,
};

fn build<'d>(_: &mut Builder<'d>, _: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    Ok(IntegratorDesc {
        kind: IntegratorKind::Depth,
        ..IntegratorDesc::mitsuba_estimators()
    })
}
