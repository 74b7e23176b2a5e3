//! `tabphase`: a phase function given as a table over the cosine of the deflection (Mitsuba 3
//! `src/phase/tabphase.cpp`; the model is [`gonio_core::phase::TabulatedPhase`]).
//!
//! p(ωi, ωo) = p̂(μ)/(2π), μ = −ωi · ωo (the physics convention: μ = 1 scatters forwards), p̂
//! linear between the table's nodes, which are spread evenly over [−1, 1], and normalized to
//! ∫₋₁¹ p̂ dμ = 1. Sampled exactly.
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `values` | (required) | the nodes p̂(−1), …, p̂(1): a string of at least two non-negative numbers, separated by commas or spaces, not all zero |

use crate::medium::Phase;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use gonio_core::phase::{PhaseFunction, TabulatedPhase};
use std::sync::Arc;

const VALUES: ParamSpec = ParamSpec::new(
    "values",
    ParamType::String,
    DefaultValue::None,
    "the phase function at cosines of the deflection spread evenly from −1 (backwards) to 1 (forwards), separated by commas or spaces; normalized (required)",
);

/// The `tabphase` plugin.
pub static PLUGIN: Plugin<Phase> = Plugin {
    name: "tabphase",
    summary: "Phase function tabulated over the cosine of the deflection (linear between nodes, normalized).",
    params: &[VALUES],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Phase, SceneError> {
    let what = p.what();
    let Some((text, loc)) = p.string_opt(VALUES.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            format!("{what} needs \"values\": the table, a string of numbers"),
        ));
    };
    let mut values = Vec::new();
    for token in text.split([',', ' ', '\t', '\n', '\r']).filter(|t| !t.is_empty()) {
        match token.parse::<f32>() {
            Ok(v) if v.is_finite() && v >= 0.0 => values.push(v),
            _ => {
                return Err(err(
                    loc,
                    ErrorKind::BadValue,
                    format!(
                        "invalid value \"{token}\" in \"values\" of {what} (must be a non-negative number)"
                    ),
                ));
            }
        }
    }
    match TabulatedPhase::new(&values) {
        Some(t) => Ok(Phase::Model(PhaseFunction::Tabulated(Arc::new(t)))),
        None => Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "invalid \"values\" of {what}: {} (the table needs at least two values, not all zero)",
                if values.len() < 2 {
                    format!("{} value(s)", values.len())
                } else {
                    "all zero".into()
                }
            ),
        )),
    }
}
