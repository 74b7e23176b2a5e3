//! `heterogeneous`: a participating medium whose extinction varies in space (Mitsuba 3
//! `src/media/heterogeneous.cpp`; runtime [`crate::medium::Medium`]).
//!
//! σt(p, λ) = `scale`·`sigma_t`(p, λ), read from a `<volume>` (`gridvolume`: one channel, or
//! linear RGB read as Mitsuba's spectral variants read it, `texture/volume.rs`) and zero outside
//! the grid's box, as in Mitsuba
//! (whose medium samples only inside it); `sigma_t` may also be a number or spectrum, or a
//! `constvolume`: that extinction inside the box of the volume, the axis-aligned bounds of the
//! unit cube under its `to_world` (the unit cube for a number), and none outside (free flights
//! there drawn exactly, as in a homogeneous medium), as Mitsuba's medium is where its extinction
//! volume is (test `a_heterogeneous_constant_extinction_fills_its_volumes_box`). The albedo is a spectrum or a volume, the phase function the nested
//! `<phase>`. gonio tracks it under the majorant σ̄ = `scale`·max σt (times a bound of the
//! flakes' projected area with an `sggx` phase function): delta tracking along paths,
//! ratio tracking along shadow rays (Mitsuba's shadow rays use delta tracking: 0 or 1, the same
//! mean).
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `sigma_t` | 1 | extinction (1/length), before `scale`: a `<volume>`, a number or a spectrum |
//! | `albedo` | 0.75 | single-scattering albedo σs/σt in [0, 1]: a spectrum or a `<volume>` |
//! | `scale` | 1 | multiplier of σt (a change of length unit) |
//! | `sample_emitters` | true | next-event estimation at scattering events in the medium |
//! | `has_spectral_extinction` | true | accepted: gonio's tracking is exact for any σt |
//! | (nested phase) | isotropic | the phase function |

use super::homogeneous::{ALBEDO, PHASE, SAMPLE_EMITTERS, SCALE, SPECTRAL_EXTINCTION, build_medium};
use crate::medium::Medium;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::xml::{Builder, Params, SceneError};

const SIGMA_T: ParamSpec = ParamSpec::new(
    "sigma_t",
    ParamType::Texture,
    DefaultValue::Float(1.0),
    "extinction (1/length), before `scale`: a nested or referenced `<volume>`, a number or a spectrum",
);

/// The `heterogeneous` plugin.
pub static PLUGIN: Plugin<Medium> = Plugin {
    name: "heterogeneous",
    summary: "A participating medium whose extinction (and albedo) are read from volumes, tracked under a majorant.",
    params: &[
        SIGMA_T,
        ALBEDO,
        SCALE,
        SAMPLE_EMITTERS,
        SPECTRAL_EXTINCTION,
        PHASE,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Medium, SceneError> {
    build_medium(b, p, true)
}
