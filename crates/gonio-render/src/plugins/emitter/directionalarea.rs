//! `directionalarea`: a shape's surface emitting only along its normal (Mitsuba 3
//! `src/emitters/directionalarea.cpp`).
//!
//! `radiance` is read as `area`'s (numbers and colours × D65, textures with the same
//! `whitepoint` rule: checked against Mitsuba 3.9.1's `sample_ray` weights); here it is the
//! power per unit area leaving along the normal, L·δ(ω − n), so a surface facing a planar
//! emitter across any gap receives the irradiance `radiance` (a sphere's beams spread or
//! focus: L·(R/r)² at distance r from its centre). Mitsuba's path tracers cannot see such a
//! light (a camera or a surface point meets its one direction with probability zero) and render
//! it black; only `ptracer` shows it. gonio's next-event estimation finds, for a point in front
//! of a planar emitter (`rectangle`, `disk`), the one emitter point whose normal passes through
//! it (its orthogonal projection), as for a `directional` light limited to the emitter's
//! footprint (a planar mesh of at most 64 triangles, an `obj` quad, counts as a plane), and on
//! a `sphere` the points on the line through the centre whose beams reach the point (outside an
//! outward sphere one; inside one with `flip_normals` two, one drawn; outside it one, through
//! the centre): `path`, `direct` and `volpath` then render the direct light too (the
//! image `ptracer` converges to, test `directionalarea_path_matches_mitsuba_ptracer`;
//! `next_event` = false, the default under `--mitsuba-estimators`, restores Mitsuba's black).
//! Other shapes, and light reflected by a mirror or refracted by glass on its way, stay
//! `ptracer`'s, as for `directional`.

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{AreaEmitterDesc, SurfaceEmission};
use crate::xml::{Builder, Params, SceneError};

const NEXT_EVENT: ParamSpec = ParamSpec::new(
    "next_event",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) next-event estimation along the beam through the shading point, on a `rectangle`, `disk`, `sphere` or planar mesh of at most 64 triangles: `path`, `direct` and `volpath` render its direct light (Mitsuba 3.9.1: only `ptracer` does)",
)
.mitsuba(DefaultValue::Bool(false));

/// The `directionalarea` plugin.
pub static PLUGIN: Plugin<AreaEmitterDesc> = Plugin {
    name: "directionalarea",
    summary: "Directional area light: the shape it is nested in emits `radiance` only along its normal (seen by `ptracer`; by next-event estimation on rectangles, disks, spheres and planar meshes).",
    params: &[
        super::area::RADIANCE,
        super::area::WHITEPOINT,
        NEXT_EVENT,
        super::MEDIUM,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<AreaEmitterDesc, SceneError> {
    let radiance = super::area::radiance(b, p)?;
    let next_event = p.bool(NEXT_EVENT.name, p.default_of(&NEXT_EVENT).bool())?;
    Ok(AreaEmitterDesc {
        radiance,
        hit: None,
        emission: SurfaceEmission::Directional { next_event },
    })
}
