//! `ptracer`: light (particle) tracing (Mitsuba 3 `src/integrators/ptracer.cpp`): paths start at
//! the emitters and every vertex is joined to the camera (`crate::integrator`'s `ptracer`
//! module). `spp` counts light paths per pixel, as in Mitsuba.
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `max_depth` | −1 | longest path in segments, camera segment included; −1 unbounded |
//! | `rr_depth` | 5 | depth at which Russian roulette starts |
//! | `hide_emitters` | false | no emitters seen directly |
//! | `samples_per_pass` | −1 | accepted and ignored (gonio renders in passes of its own) |
//! | `thin_shadows` | true (Mitsuba: false) | (ours) connections to the camera cross null surfaces and `thindielectric` sheets, attenuated by their transmittance |

use super::path::{HIDE_EMITTERS, RR_DEPTH, SAMPLES_PER_PASS};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{IntegratorDesc, IntegratorKind};
use crate::xml::{Builder, Params, SceneError};

const THIN_SHADOWS: ParamSpec = ParamSpec::new(
    "thin_shadows",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) joins to the camera cross null surfaces and `thindielectric` sheets, attenuated by their transmittance, and a light path's straight pass through one counts no segment (Mitsuba's joins stop at them)",
)
.mitsuba(DefaultValue::Bool(false));
const MAX_DEPTH: ParamSpec = ParamSpec::new(
    "max_depth",
    ParamType::Integer,
    DefaultValue::Int(-1),
    "longest path, in segments (1: emitters seen directly, 2: direct lighting); −1 is unbounded",
);

/// The `ptracer` plugin.
pub static PLUGIN: Plugin<IntegratorDesc> = Plugin {
    name: "ptracer",
    summary: "Light tracing: paths from the emitters, each vertex joined to the camera and splatted; spp counts light paths per pixel.",
    params: &[MAX_DEPTH, RR_DEPTH, HIDE_EMITTERS, SAMPLES_PER_PASS, THIN_SHADOWS],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    let (max_depth, rr_depth, hide_emitters) = super::path::read_path_rows(p, &MAX_DEPTH)?;
    let thin_shadows = p.bool(THIN_SHADOWS.name, p.default_of(&THIN_SHADOWS).bool())?;
    Ok(IntegratorDesc {
        max_depth,
        rr_depth,
        thin_shadows,
        // Mitsuba's roulette cap (the light tracer has no trapped-light fireflies to fix).
        rr_survival: 0.95,
        hide_emitters,
        kind: IntegratorKind::PTracer,
        ..IntegratorDesc::mitsuba_estimators()
    })
}
