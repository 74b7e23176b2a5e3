//! `sggx`: the SGGX microflake phase function (Mitsuba 3 `src/phase/sggx.cpp`; the model, its
//! formulas and source in [`gonio_core::sggx`]).
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `S` | (required) | a six-channel `gridvolume` of the matrix entries S_xx, S_yy, S_zz, S_xy, S_xz, S_yz, interpolated entry by entry (Mitsuba 3.9.1 reads it through `eval_6`, which only `gridvolume` has: a `constvolume` is refused there and here) |
//!
//! A medium with this phase function has the extinction σt·σ(ω) along a direction ω, σ the
//! flakes' projected area (Mitsuba's media do the same for its "microflake" phase functions).
//! Its majorant here bounds that product, σ̄·max σ (max σ ≤ √(largest eigenvalue of S) over the
//! grid's samples): Mitsuba's heterogeneous medium keeps σ̄ (its `max_projected_area` is 1), so
//! matrices with an eigenvalue above 1 make its null collisions negative, and its homogeneous
//! medium reads S once at the ray's origin for the whole flight; both agree with ours where S
//! has eigenvalues at most 1 and is the same everywhere. A sample that is not a positive
//! semi-definite matrix (Mitsuba leaves that to the user) is refused with its index and values;
//! a singular one (ideal flakes, S = diag(0, 0, 1)) has no density to sample (D = 0), so its
//! flakes only absorb, as in Mitsuba, whose phase samples there have pdf 0. Nested in a `blendphase` it is refused
//! (a blend has no projected area to scale the extinction by). Mitsuba 3.9.1's directions do not
//! follow its own density except for ωi along z (its renders then depend on the estimator); the
//! values and densities are the same as gonio's, whose samples follow them (`tests/sggx.rs`).

use crate::medium::Phase;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::volume::{GridVolume, Volume};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};
use glam::{Vec2, Vec3};
use gonio_core::phase::PhaseSample;
use gonio_core::sggx::Sggx;
use std::sync::Arc;

const S: ParamSpec = ParamSpec::new(
    "S",
    ParamType::Volume,
    DefaultValue::None,
    "the matrix S_xx, S_yy, S_zz, S_xy, S_xz, S_yz: a six-channel `gridvolume` (required)",
);

/// The `sggx` plugin.
pub static PLUGIN: Plugin<Phase> = Plugin {
    name: "sggx",
    summary: "SGGX microflake phase function (specular flakes), its matrix S read from a six-channel grid.",
    params: &[S],
    build,
};

/// The SGGX phase function of a medium: the matrix at each point from a six-channel grid.
#[derive(Clone, Debug, PartialEq)]
pub struct SggxPhase {
    grid: Arc<GridVolume>,
    /// The distribution, when every sample of the grid holds the same matrix.
    uniform: Option<Sggx>,
    /// A bound of σ(ω) over every direction and point.
    max_projected_area: f32,
}

impl SggxPhase {
    /// The phase function of a six-channel `grid`; the index and entries of the first sample
    /// that is not a positive semi-definite matrix, if any.
    pub fn new(grid: Arc<GridVolume>) -> Result<Self, (usize, [f32; 6])> {
        let samples: Vec<[f32; 6]> = grid
            .data
            .chunks_exact(6)
            .map(|c| std::array::from_fn(|i| c[i]))
            .collect();
        if let Some(i) = samples.iter().position(|s| !Sggx::new(*s).is_semi_definite()) {
            return Err((i, samples[i]));
        }
        let uniform = samples
            .first()
            .filter(|first| samples.iter().all(|s| s == *first))
            .map(|s| Sggx::new(*s));
        // σ² = ωᵀSω is linear in S and a lookup is a convex combination of samples (trilinear
        // or nearest, every wrap mode): σ² at any point is at most the samples' largest.
        let max_projected_area = samples
            .iter()
            .map(|s| Sggx::new(*s).max_projected_area())
            .fold(0.0, f32::max);
        Ok(Self {
            grid,
            uniform,
            max_projected_area,
        })
    }

    /// The distribution at world point `p`.
    #[inline]
    pub fn at(&self, p: Vec3) -> Sggx {
        self.uniform
            .unwrap_or_else(|| Sggx::new(self.grid.eval6_local(self.grid.to_local.transform_point3(p))))
    }

    /// p(ωi, ωo) at `p`.
    #[inline]
    pub fn eval(&self, p: Vec3, wi: Vec3, wo: Vec3) -> f32 {
        self.at(p).phase(wi, wo)
    }

    /// ωo drawn at `p` (density [`Self::eval`]).
    #[inline]
    pub fn sample(&self, p: Vec3, wi: Vec3, u: Vec2) -> PhaseSample {
        self.at(p).sample_phase(wi, u)
    }

    /// σ(ω) at `p`: the factor of the medium's extinction along ±ω.
    #[inline]
    pub fn projected_area(&self, p: Vec3, w: Vec3) -> f32 {
        self.at(p).projected_area(w)
    }

    /// σ(ω) where it is the same at every point.
    #[inline]
    pub fn uniform_projected_area(&self, w: Vec3) -> Option<f32> {
        self.uniform.map(|s| s.projected_area(w))
    }

    /// A bound of σ over every direction and point.
    pub fn max_projected_area(&self) -> f32 {
        self.max_projected_area
    }
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Phase, SceneError> {
    let what = p.what();
    let volumes = p.objects(Tag::Volume)?;
    let mut grid = None;
    for (i, prop) in volumes {
        if prop.name != S.name {
            return Err(err(
                &prop.loc,
                ErrorKind::UnusedParameter,
                format!(
                    "a <volume> named \"{}\" in {what} (it takes only \"S\")",
                    prop.name
                ),
            ));
        }
        grid = Some(match b.build_plugin(crate::plugins::VOLUME_PLUGINS, i)? {
            Volume::Grid(g) if g.channels == 6 => g,
            Volume::Grid(g) => {
                return Err(err(
                    &prop.loc,
                    ErrorKind::BadValue,
                    format!(
                        "the \"S\" volume of {what} has {} channels (the matrix needs 6: S_xx, S_yy, S_zz, S_xy, S_xz, S_yz)",
                        g.channels
                    ),
                ));
            }
            Volume::Constant(..) => {
                return Err(err(
                    &prop.loc,
                    ErrorKind::BadValue,
                    format!(
                        "the \"S\" volume of {what} is a constvolume (Mitsuba 3.9.1 reads S only from a six-channel gridvolume)"
                    ),
                ));
            }
        });
    }
    let Some(grid) = grid else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            format!("{what} needs a six-channel <volume name=\"S\">"),
        ));
    };
    if grid.data.iter().any(|v| !v.is_finite()) {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            format!("the \"S\" volume of {what} holds non-finite values"),
        ));
    }
    let phase = SggxPhase::new(grid).map_err(|(i, s)| {
        err(
            &p.obj.loc,
            ErrorKind::BadValue,
            format!(
                "the \"S\" volume of {what}: sample {i} ({s:?} as S_xx, S_yy, S_zz, S_xy, S_xz, S_yz) is not a positive semi-definite matrix"
            ),
        )
    })?;
    if !phase.max_projected_area.is_finite() {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            format!("the \"S\" volume of {what} holds values whose projected area overflows"),
        ));
    }
    Ok(Phase::Sggx(Box::new(phase)))
}
