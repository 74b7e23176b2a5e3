//! `irradiancemeter`: the irradiance over a shape (Mitsuba 3 `src/sensors/irradiancemeter.cpp`),
//! the incident power per unit area averaged over the shape it is nested in. Every camera sample
//! draws a point uniformly over the shape's area and a cosine-weighted direction about its normal,
//! and records π times the radiance arriving from there, so that each pixel estimates
//! E = (1/A) ∫ ∫ L(x, ω) cos θ dω dA. The runtime camera is [`crate::camera::IrradianceMeter`].
//!
//! Nested in a `<shape>`, never on its own, and without `to_world` (it takes the shape's), as
//! Mitsuba requires. Mitsuba means it for films of 1 × 1 pixels (each pixel of a larger film is
//! the same estimate) and warns about filters wider than a box; so does gonio. Light tracing
//! (`ptracer`, the caustic light subpaths) does not connect to it here (Mitsuba's `ptracer` does).
//!
//! | parameter | default |
//! |---|---|
//! | nested `film`, `sampler` | hdrfilm, independent |

use super::perspective::{FILM, MEDIUM, SAMPLER, SRF, film_and_sampler};
use crate::plugins::Plugin;
use crate::scene::{Projection, SensorDesc};
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use glam::Affine3A;

/// The `irradiancemeter` plugin.
pub static PLUGIN: Plugin<SensorDesc> = Plugin {
    name: "irradiancemeter",
    summary: "Irradiance meter: the irradiance averaged over the shape it is nested in (π × the radiance of cosine-weighted rays from uniform points); films of 1 × 1 pixels.",
    params: &[FILM, SAMPLER, MEDIUM, SRF],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SensorDesc, SceneError> {
    if p.has("to_world") {
        let loc = p.get("to_world").expect("present").loc.clone();
        return Err(SceneError::new(
            loc,
            ErrorKind::Grammar,
            "an irradiancemeter has no to_world: it measures over the shape it is nested in, whose transform it takes (as in Mitsuba)".to_string(),
        ));
    }
    if !b.in_shape {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "an irradiancemeter must be nested in the <shape> it measures over (Mitsuba: it is \"not instantiated on its own\")",
        ));
    }
    let (film, sampler) = film_and_sampler(b, p)?;
    if film.filter.radius() > 0.5 + 1e-4 {
        b.warnings.push(format!(
            "{}: an irradiancemeter is meant for a box filter (Mitsuba warns about filters wider than half a pixel)",
            p.obj.loc
        ));
    }
    Ok(SensorDesc {
        to_world: Affine3A::IDENTITY,
        fov_x_deg: 0.0,
        // The shape's index is set when the shape is placed in the scene.
        projection: Projection::IrradianceMeter { shape: usize::MAX },
        near_clip: 0.0,
        far_clip: f32::INFINITY,
        film,
        sampler,
        children: Vec::new(),
        target_shape: None,
    })
}
