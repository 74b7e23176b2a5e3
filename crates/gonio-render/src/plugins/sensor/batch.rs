//! `batch`: several sensors rendered side by side into one film (Mitsuba 3
//! `src/sensors/batch.cpp`). The film's width is shared equally, left to right in the order the
//! sensors are nested; each sensor takes its share (width / n × height, the batch film's filter)
//! and the batch's sampler, superseding its own (as in Mitsuba, which resizes the sub-sensors'
//! films, so that a field of view given along `y` or `smaller` is converted at the share's
//! aspect ratio). The runtime camera is [`crate::camera::BatchCamera`]; light tracing does not
//! connect to it (Mitsuba's documentation: "incompatible with the particle tracer").
//!
//! | parameter | default |
//! |---|---|
//! | nested `sensor`s | at least one |
//! | nested `film`, `sampler` | hdrfilm (width a multiple of the number of sensors), independent |

use super::perspective::{FILM, MEDIUM, SAMPLER, SRF, film_and_sampler};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin, SENSOR_PLUGINS};
use crate::scene::{Projection, SensorDesc};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};
use glam::Affine3A;

const SENSOR: ParamSpec = ParamSpec::new(
    "(nested sensors)",
    ParamType::Sensor,
    DefaultValue::None,
    "the sensors, left to right on the film (at least one)",
);

/// The `batch` plugin.
pub static PLUGIN: Plugin<SensorDesc> = Plugin {
    name: "batch",
    summary: "Batch sensor: its nested sensors side by side on one film, each on an equal share of the width.",
    params: &[SENSOR, FILM, SAMPLER, MEDIUM, SRF],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SensorDesc, SceneError> {
    if b.batch_film.is_some() {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "a batch sensor cannot be nested in a batch",
        ));
    }
    let (film, sampler) = film_and_sampler(b, p)?;
    let sensors = p.objects(Tag::Sensor)?;
    if sensors.is_empty() {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "a batch sensor needs at least one nested <sensor> (as in Mitsuba)",
        ));
    }
    let n = sensors.len() as u32;
    if film.width % n != 0 {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            format!(
                "the batch's film width {} is not a multiple of its {n} sensors (Mitsuba requires it)",
                film.width
            ),
        ));
    }
    let mut share = film.clone();
    share.width = film.width / n;
    share.crop = None;
    b.batch_film = Some((share, sampler.clone()));
    let children: Result<Vec<SensorDesc>, SceneError> = sensors
        .iter()
        .map(|(i, _)| b.build_plugin(SENSOR_PLUGINS, *i))
        .collect();
    b.batch_film = None;
    Ok(SensorDesc {
        to_world: Affine3A::IDENTITY,
        fov_x_deg: 0.0,
        projection: Projection::Batch,
        near_clip: 0.0,
        far_clip: f32::INFINITY,
        film,
        sampler,
        children: children?,
        target_shape: None,
    })
}
