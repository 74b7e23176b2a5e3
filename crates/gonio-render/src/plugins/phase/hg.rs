//! `hg`: the Henyey–Greenstein phase function (Mitsuba 3 `src/phase/hg.cpp`),
//! p(θ) = (1 − g²) / (4π (1 + g² + 2g cos θ)^{3/2}) with cos θ = ωi · ωo (both directions
//! away from the scattering point), so g > 0 scatters forwards.
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `g` | 0.8 | mean cosine of the deflection, in (−1, 1) |

use crate::medium::Phase;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use gonio_core::phase::PhaseFunction;

const G: ParamSpec = ParamSpec::new(
    "g",
    ParamType::Float,
    DefaultValue::Float(0.8),
    "asymmetry: the mean cosine of the deflection, in (−1, 1); > 0 scatters forwards",
);

/// The `hg` plugin.
pub static PLUGIN: Plugin<Phase> = Plugin {
    name: "hg",
    summary: "Henyey–Greenstein phase function with asymmetry g.",
    params: &[G],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Phase, SceneError> {
    let (g, loc) = match p.float_opt(G.name)? {
        Some((g, loc)) => (g, loc),
        None => (G.default.float(), &p.obj.loc),
    };
    if !(g > -1.0 && g < 1.0) {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "invalid value {g} for \"g\" of <phase type=\"hg\"> (must lie strictly between -1 and 1)"
            ),
        ));
    }
    Ok(Phase::Model(PhaseFunction::HenyeyGreenstein { g: g as f32 }))
}
