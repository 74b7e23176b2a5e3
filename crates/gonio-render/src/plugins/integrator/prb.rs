//! Mitsuba 3's differentiable integrators, rendered for their primal image only:
//! `prb`, `prb_basic` (path replay backpropagation, Vicini et al. 2021), `prb_projective`
//! (Zhang et al. 2023) and `direct_projective` (`python/ad/integrators/*.py`).
//!
//! Their primal image is the path tracer's (`prb*`, `prb_projective`: emission and next-event
//! estimation by MIS, BSDF sampling, Russian roulette from `rr_depth`) or direct illumination
//! (`direct_projective` fixes `max_depth` to 2: one emitter and one BSDF sample by MIS, which is
//! Mitsuba's `direct` with its defaults), so gonio renders them with its `path` and `direct`
//! integrators. Their parameters are accepted with Mitsuba's names, defaults and checks; those
//! that only steer derivatives (`sppc`, `sppp`, `sppi`, `guiding*`, `project_seed`) are read
//! and ignored. The path tracer's estimator rows of ours (`thin_shadows` … `split_lights`) take
//! `path`'s defaults: ours, or Mitsuba's under `--mitsuba-estimators`.
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `max_depth` | 6 (as Mitsuba's differentiable integrators) | −1 unbounded; ignored (2) by `direct_projective` |
//! | `rr_depth` | 5 | Russian roulette from this depth (≥ 1) |
//! | `hide_emitters` | false | hide directly visible emitters |
//! | `samples_per_pass`, `timeout` | −1 | accepted, ignored |
//! | `sppc`, `sppp`, `sppi` | the render's spp | projective only; derivative sample counts |
//! | `guiding`, `guiding_proj`, `guiding_rounds` | `octree`, true, 1 | projective only |
//! | `project_seed` | `both` | projective only: `both`, `bsdf` or `emitter` |

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{IntegratorDesc, IntegratorKind};
use crate::xml::{Builder, Params, SceneError};

pub(super) const MAX_DEPTH: ParamSpec = ParamSpec::new(
    "max_depth",
    ParamType::Integer,
    DefaultValue::Int(6),
    "longest path, in segments; −1 is unbounded (Mitsuba's differentiable integrators default to 6)",
);
const SPPC: ParamSpec = ParamSpec::new(
    "sppc",
    ParamType::Integer,
    DefaultValue::Derived("the render's spp"),
    "samples for the continuous derivative (ignored: primal image only)",
);
const SPPP: ParamSpec = ParamSpec::new(
    "sppp",
    ParamType::Integer,
    DefaultValue::Derived("the render's spp"),
    "samples for the primarily visible discontinuities (ignored)",
);
const SPPI: ParamSpec = ParamSpec::new(
    "sppi",
    ParamType::Integer,
    DefaultValue::Derived("the render's spp"),
    "samples for the indirect discontinuities (ignored)",
);
const GUIDING: ParamSpec = ParamSpec::new(
    "guiding",
    ParamType::String,
    DefaultValue::Str("octree"),
    "`none`, `grid` or `octree` (ignored)",
);
const GUIDING_PROJ: ParamSpec = ParamSpec::new(
    "guiding_proj",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ignored)",
);
const GUIDING_ROUNDS: ParamSpec = ParamSpec::new(
    "guiding_rounds",
    ParamType::Integer,
    DefaultValue::Int(1),
    "(ignored)",
);
const PROJECT_SEED: ParamSpec = ParamSpec::new(
    "project_seed",
    ParamType::String,
    DefaultValue::Str("both"),
    "`both`, `bsdf` or `emitter` (ignored)",
);

// `rr_depth`, `hide_emitters`, `samples_per_pass`, `timeout`: the rows of `path`.
use super::path::{HIDE_EMITTERS, RR_DEPTH, SAMPLES_PER_PASS, TIMEOUT};

const COMMON: [ParamSpec; 5] = [MAX_DEPTH, RR_DEPTH, HIDE_EMITTERS, SAMPLES_PER_PASS, TIMEOUT];
const PROJECTIVE: [ParamSpec; 12] = [
    MAX_DEPTH,
    RR_DEPTH,
    HIDE_EMITTERS,
    SAMPLES_PER_PASS,
    TIMEOUT,
    SPPC,
    SPPP,
    SPPI,
    GUIDING,
    GUIDING_PROJ,
    GUIDING_ROUNDS,
    PROJECT_SEED,
];

/// The `prb` plugin.
pub static PRB: Plugin<IntegratorDesc> = Plugin {
    name: "prb",
    summary: "Mitsuba's path replay backpropagation: its primal image, rendered by the path tracer.",
    params: &COMMON,
    build: build_path,
};

/// The `prb_basic` plugin.
pub static PRB_BASIC: Plugin<IntegratorDesc> = Plugin {
    name: "prb_basic",
    summary: "Mitsuba's basic path replay backpropagation: its primal image, rendered by the path tracer.",
    params: &COMMON,
    build: build_path,
};

/// The `prb_projective` plugin.
pub static PRB_PROJECTIVE: Plugin<IntegratorDesc> = Plugin {
    name: "prb_projective",
    summary: "Mitsuba's projective-sampling path integrator: its primal image, rendered by the path tracer.",
    params: &PROJECTIVE,
    build: build_path,
};

/// The `direct_projective` plugin.
pub static DIRECT_PROJECTIVE: Plugin<IntegratorDesc> = Plugin {
    name: "direct_projective",
    summary: "Mitsuba's projective-sampling direct integrator: its primal image, rendered by `direct` (one emitter and one BSDF sample).",
    params: &PROJECTIVE,
    build: build_direct,
};

/// Reads every row of the plugin's table: `(max_depth, rr_depth, hide_emitters)`.
fn read(p: &mut Params<'_>) -> Result<(i32, u32, bool), SceneError> {
    let (max_depth, rr_depth, hide_emitters) = super::path::read_path_rows(p, &MAX_DEPTH)?;
    p.float(TIMEOUT.name, TIMEOUT.default.float())?;
    if p.obj.ty.ends_with("_projective") {
        for spp in [SPPC, SPPP, SPPI] {
            p.int_opt(spp.name)?;
        }
        p.choice(GUIDING.name, GUIDING.default.str(), &["none", "grid", "octree"])?;
        p.bool(GUIDING_PROJ.name, GUIDING_PROJ.default.bool())?;
        p.int_in(GUIDING_ROUNDS.name, GUIDING_ROUNDS.default.int(), 0, i64::MAX)?;
        p.choice(
            PROJECT_SEED.name,
            PROJECT_SEED.default.str(),
            &["both", "bsdf", "emitter"],
        )?;
    }
    Ok((max_depth, rr_depth, hide_emitters))
}

fn build_path<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    let (max_depth, rr_depth, hide_emitters) = read(p)?;
    // The path tracer's estimators: ours, or Mitsuba's under `--mitsuba-estimators`.
    Ok(super::path::with_estimator_defaults(
        p,
        IntegratorDesc {
            max_depth,
            rr_depth,
            hide_emitters,
            kind: IntegratorKind::Path,
            ..IntegratorDesc::default()
        },
    ))
}

fn build_direct<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    let (_, _, hide_emitters) = read(p)?;
    Ok(IntegratorDesc {
        max_depth: 2,
        hide_emitters,
        kind: IntegratorKind::Direct {
            emitter_samples: 1,
            bsdf_samples: 1,
        },
        ..IntegratorDesc::mitsuba_estimators()
    })
}
