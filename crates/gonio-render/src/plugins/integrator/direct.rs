//! `direct`: direct illumination with multiple importance sampling (Mitsuba 3
//! `src/integrators/direct.cpp`; Veach & Guibas 1995, "Optimally combining sampling techniques
//! for Monte Carlo rendering").
//!
//! At the first hit x seen along a camera ray, with n_L = `emitter_samples` light samples and
//! n_B = `bsdf_samples` BSDF samples:
//!
//! L = L_e(x) + (1/n_L) Σ_i f·L_i·|cos|·w_L/p_L + (1/n_B) Σ_j f·L_e·|cos|·w_B/p_B,
//!
//! w_L = (n_L p_L)² / ((n_L p_L)² + (n_B p_B)²) and w_B likewise (the power heuristic with the
//! sample counts, Veach's eq. 9.13); a delta light or a delta BSDF lobe has w = 1. Light samples
//! are taken only where the BSDF has a smooth lobe. No indirect light, no Russian roulette.
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `shading_samples` | 1 | sets both counts (not with either of them) |
//! | `emitter_samples` | `shading_samples` | light samples per hit |
//! | `bsdf_samples` | `shading_samples` | BSDF samples per hit |
//! | `hide_emitters` | false | hide directly visible emitters |

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{IntegratorDesc, IntegratorKind};
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};

const SHADING_SAMPLES: ParamSpec = ParamSpec::new(
    "shading_samples",
    ParamType::Integer,
    DefaultValue::Int(1),
    "sets both `emitter_samples` and `bsdf_samples` (an error together with either)",
);
const EMITTER_SAMPLES: ParamSpec = ParamSpec::new(
    "emitter_samples",
    ParamType::Integer,
    DefaultValue::Derived("shading_samples"),
    "light samples per hit (taken where the BSDF has a smooth lobe)",
);
const BSDF_SAMPLES: ParamSpec = ParamSpec::new(
    "bsdf_samples",
    ParamType::Integer,
    DefaultValue::Derived("shading_samples"),
    "BSDF samples per hit",
);
const HIDE_EMITTERS: ParamSpec = ParamSpec::new(
    "hide_emitters",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "hide directly visible emitters",
);

/// Largest sample count per hit we accept (a bound against a typo such as 1e9 samples).
const MAX_SAMPLES: i64 = 1 << 16;

/// The `direct` plugin.
pub static PLUGIN: Plugin<IntegratorDesc> = Plugin {
    name: "direct",
    summary: "Direct illumination: emitters seen directly plus light and BSDF samples at the first hit, combined by MIS (power heuristic with the sample counts).",
    params: &[SHADING_SAMPLES, EMITTER_SAMPLES, BSDF_SAMPLES, HIDE_EMITTERS],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    if p.has(SHADING_SAMPLES.name) && (p.has(EMITTER_SAMPLES.name) || p.has(BSDF_SAMPLES.name)) {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            "<integrator type=\"direct\">: give either shading_samples or emitter_samples/bsdf_samples, not both",
        ));
    }
    let shading = p.int_in(
        SHADING_SAMPLES.name,
        SHADING_SAMPLES.default.int(),
        0,
        MAX_SAMPLES,
    )?;
    let emitter_samples = p.int_in(EMITTER_SAMPLES.name, shading, 0, MAX_SAMPLES)? as u32;
    let bsdf_samples = p.int_in(BSDF_SAMPLES.name, shading, 0, MAX_SAMPLES)? as u32;
    if emitter_samples + bsdf_samples == 0 {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            "<integrator type=\"direct\"> needs at least one emitter or BSDF sample (emitter_samples = bsdf_samples = 0)",
        ));
    }
    let hide_emitters = p.bool(HIDE_EMITTERS.name, HIDE_EMITTERS.default.bool())?;
    Ok(IntegratorDesc {
        max_depth: 2,
        hide_emitters,
        kind: IntegratorKind::Direct {
            emitter_samples,
            bsdf_samples,
        },
        ..IntegratorDesc::mitsuba_estimators()
    })
}
