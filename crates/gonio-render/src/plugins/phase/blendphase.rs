//! `blendphase`: the mixture of two phase functions (Mitsuba 3 `src/phase/blendphase.cpp`),
//!
//! p(x, ωi, ωo) = (1 − w(x))·p₀(ωi, ωo) + w(x)·p₁(ωi, ωo),
//!
//! w clamped to [0, 1], a number or a one-channel `gridvolume` read at the scattering point x (a
//! `constvolume` gives its mean).
//! The two nested phase functions are taken in document order, as Mitsuba 3.9.1 takes them
//! (its documentation says the order of their names; its loader keeps the order of the file);
//! either may be a blend itself.
//!
//! A direction is drawn from p₀ with probability 1 − w and from p₁ with probability w, the
//! uniform number that chose reused for the component (Mitsuba's split of `sample1`), and carries
//! the mixture's density, so its weight p/pdf is 1 and multiple importance sampling sees the
//! density the direction was really drawn with. (Mitsuba's `sample` returns the chosen
//! component's density, and its `eval_pdf` the mixture's; in the test fog of
//! `tests/media.rs` the two renderers agree within the noise all the same.)
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `weight` | 0.5 | w in [0, 1]: 0 is the first phase function, 1 the second; a number or a one-channel `<volume>` |
//! | (two nested phases) | (required) | the phase functions mixed, in document order |

use crate::medium::Phase;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::volume::{GridVolume, Volume};
use crate::xml::{Builder, ErrorKind, Location, Params, SceneError, Tag, err};
use glam::{Vec2, Vec3};
use gonio_core::phase::PhaseSample;
use std::sync::Arc;

const WEIGHT: ParamSpec = ParamSpec::new(
    "weight",
    ParamType::Float,
    DefaultValue::Float(0.5),
    "w in [0, 1]: 0 is the first phase function, 1 the second; a number or a one-channel `<volume>` (clamped)",
);

const PHASES: ParamSpec = ParamSpec::new(
    "(two nested phases)",
    ParamType::Phase,
    DefaultValue::None,
    "the phase functions mixed, in document order (required)",
);

/// The `blendphase` plugin.
pub static PLUGIN: Plugin<Phase> = Plugin {
    name: "blendphase",
    summary: "Mixture of two phase functions, with a weight that may vary in space.",
    params: &[WEIGHT, PHASES],
    build,
};

/// The mixing weight w.
#[derive(Clone, Debug, PartialEq)]
pub enum BlendWeight {
    /// The same everywhere (in [0, 1]).
    Constant(f32),
    /// A one-channel grid read at the scattering point (clamped to [0, 1]).
    Volume(Arc<GridVolume>),
}

/// (1 − w)·p₀ + w·p₁ (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct BlendPhase {
    /// w.
    pub weight: BlendWeight,
    /// p₀ and p₁.
    pub phases: [Phase; 2],
}

impl BlendPhase {
    /// w at world point `p`, in [0, 1].
    #[inline]
    pub fn weight_at(&self, p: Vec3) -> f32 {
        match &self.weight {
            BlendWeight::Constant(w) => *w,
            BlendWeight::Volume(g) => g.eval(p)[0].clamp(0.0, 1.0),
        }
    }

    /// The mixture's density at world point `p`.
    #[inline]
    pub fn eval(&self, p: Vec3, wi: Vec3, wo: Vec3) -> f32 {
        let w = self.weight_at(p);
        let p0 = if w < 1.0 {
            self.phases[0].eval(p, wi, wo)
        } else {
            0.0
        };
        let p1 = if w > 0.0 {
            self.phases[1].eval(p, wi, wo)
        } else {
            0.0
        };
        (1.0 - w) * p0 + w * p1
    }

    /// A direction from one component, chosen with probability 1 − w or w, carrying the
    /// mixture's density.
    #[inline]
    pub fn sample(&self, p: Vec3, wi: Vec3, u: Vec2) -> PhaseSample {
        // The weight is read once (a grid lookup), the chosen component's density comes with
        // its sample, and only the other component is evaluated.
        let w = self.weight_at(p);
        if u.x < w {
            let s = self.phases[1].sample(p, wi, Vec2::new(u.x / w, u.y));
            let p0 = if w < 1.0 {
                self.phases[0].eval(p, wi, s.wo)
            } else {
                0.0
            };
            PhaseSample {
                wo: s.wo,
                pdf: (1.0 - w) * p0 + w * s.pdf,
            }
        } else {
            let v = ((u.x - w) / (1.0 - w)).min(1.0 - f32::EPSILON / 2.0);
            let s = self.phases[0].sample(p, wi, Vec2::new(v, u.y));
            let p1 = if w > 0.0 {
                self.phases[1].eval(p, wi, s.wo)
            } else {
                0.0
            };
            PhaseSample {
                wo: s.wo,
                pdf: (1.0 - w) * s.pdf + w * p1,
            }
        }
    }
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Phase, SceneError> {
    let what = p.what();
    let mut weight = None;
    for (i, prop) in p.objects(Tag::Volume)? {
        if prop.name != WEIGHT.name {
            return Err(err(
                &prop.loc,
                ErrorKind::UnusedParameter,
                format!(
                    "a <volume> named \"{}\" in {what} (only \"weight\" may be a volume)",
                    prop.name
                ),
            ));
        }
        weight = Some(match b.build_plugin(crate::plugins::VOLUME_PLUGINS, i)? {
            // Mitsuba's `eval_1` of a constant: its mean over the wavelengths.
            Volume::Constant(w, _) => BlendWeight::Constant(w.mean().clamp(0.0, 1.0)),
            Volume::Grid(g) if g.channels == 1 => BlendWeight::Volume(g),
            Volume::Grid(g) => {
                return Err(err(
                    &prop.loc,
                    ErrorKind::BadValue,
                    format!(
                        "the \"weight\" volume of {what} has {} channels (a weight is one number: give a one-channel grid)",
                        g.channels
                    ),
                ));
            }
        });
    }
    let weight = match weight {
        Some(w) => w,
        None => BlendWeight::Constant(p.float_checked(
            WEIGHT.name,
            WEIGHT.default.float(),
            |w| (0.0..=1.0).contains(&w),
            "in [0, 1]",
        )? as f32),
    };
    let nested = p.objects(Tag::Phase)?;
    let [first, second] = nested.as_slice() else {
        let loc = nested.get(2).map_or(&p.obj.loc, |(_, prop)| &prop.loc);
        return Err(err(
            loc,
            ErrorKind::Grammar,
            format!("{what} needs two nested phase functions, not {}", nested.len()),
        ));
    };
    // Guarded like every nested object reached through references (a cycle is an error, not a
    // recursion without end).
    let mut child = |i: usize, loc: &Location| {
        b.enter(i, loc)?;
        let phase = b.build_plugin(crate::plugins::PHASE_PLUGINS, i);
        b.leave();
        match phase? {
            // A blend has no projected area to scale the medium's extinction by.
            Phase::Sggx(_) => Err(err(
                loc,
                ErrorKind::BadValue,
                format!(
                    "{what} blends an sggx phase function (microflakes scale the extinction of their medium; a blend cannot)"
                ),
            )),
            phase => Ok(phase),
        }
    };
    let phases = [child(first.0, &first.1.loc)?, child(second.0, &second.1.loc)?];
    Ok(Phase::Blend(Box::new(BlendPhase { weight, phases })))
}
