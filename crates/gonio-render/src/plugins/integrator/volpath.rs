//! Mitsuba 3's volumetric path tracers: `volpath`, `volpathmis` (`src/integrators/volpath.cpp`,
//! `volpathmis.cpp`) and the differentiable `prbvolpath` (`python/ad/integrators/prbvolpath.py`),
//! for their image.
//!
//! In a scene with participating media (a shape's `interior`/`exterior`, a sensor's medium)
//! they render with gonio's volumetric path tracer (`crate::integrator::volpath`: free-flight
//! sampling, phase-function and light sampling in media, Mitsuba's estimator and depth
//! counting; spectral MIS over the sample's wavelengths where `volpathmis` offers it, in all
//! three). Without a medium their estimator is the path tracer's (emission and next-event
//! estimation by MIS, BSDF sampling, Russian roulette from `rr_depth`), so gonio renders them
//! with its `path` integrator and the path tracer's estimator rows (ours, or Mitsuba's under
//! `--mitsuba-estimators`). One difference under `--mitsuba-estimators`: Mitsuba's volumetric
//! tracers let shadow rays through `null` surfaces (medium boundaries), its `path` does not, and
//! gonio's `path` then does not either (its own default, `thin_shadows`, lets them through as
//! the volumetric tracers do).
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `max_depth` | −1 (`prbvolpath`: 6, as Mitsuba's differentiable integrators) | longest path, in segments; −1 unbounded |
//! | `rr_depth` | 5 | Russian roulette from this depth (≥ 1) |
//! | `hide_emitters` | false | hide directly visible emitters |
//! | `samples_per_pass`, `timeout` | −1 | accepted, ignored |

use super::path::{HIDE_EMITTERS, MAX_DEPTH, RR_DEPTH, SAMPLES_PER_PASS, TIMEOUT};
use crate::plugins::Plugin;
use crate::scene::{IntegratorDesc, IntegratorKind};
use crate::xml::{Builder, Params, SceneError};

const ROWS: [crate::plugins::ParamSpec; 5] = [MAX_DEPTH, RR_DEPTH, HIDE_EMITTERS, SAMPLES_PER_PASS, TIMEOUT];
const PRB_ROWS: [crate::plugins::ParamSpec; 5] = [
    super::prb::MAX_DEPTH,
    RR_DEPTH,
    HIDE_EMITTERS,
    SAMPLES_PER_PASS,
    TIMEOUT,
];

/// The `volpath` plugin.
pub static VOLPATH: Plugin<IntegratorDesc> = Plugin {
    name: "volpath",
    summary: "Mitsuba's volumetric path tracer: participating media; without them, the path tracer (its estimator there).",
    params: &ROWS,
    build,
};

/// The `volpathmis` plugin.
pub static VOLPATHMIS: Plugin<IntegratorDesc> = Plugin {
    name: "volpathmis",
    summary: "Mitsuba's volumetric path tracer with spectral MIS: participating media; without them, the path tracer.",
    params: &ROWS,
    build,
};

/// The `prbvolpath` plugin.
pub static PRBVOLPATH: Plugin<IntegratorDesc> = Plugin {
    name: "prbvolpath",
    summary: "Mitsuba's differentiable volumetric path tracer: its primal image (participating media; without them, the path tracer).",
    params: &PRB_ROWS,
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    let max_depth = if p.obj.ty == "prbvolpath" {
        &super::prb::MAX_DEPTH
    } else {
        &MAX_DEPTH
    };
    let (max_depth, rr_depth, hide_emitters) = super::path::read_path_rows(p, max_depth)?;
    p.float(TIMEOUT.name, TIMEOUT.default.float())?;
    Ok(super::path::with_estimator_defaults(
        p,
        IntegratorDesc {
            max_depth,
            rr_depth,
            hide_emitters,
            volumetric: true,
            kind: IntegratorKind::Path,
            ..IntegratorDesc::default()
        },
    ))
}
