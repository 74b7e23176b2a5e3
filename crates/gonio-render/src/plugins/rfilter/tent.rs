//! `tent` filter: weight falling linearly to 0 at `radius` (Mitsuba 3 `src/rfilters/tent.cpp`).

use super::positive;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::FilterDesc;
use crate::xml::{Builder, Params, SceneError};

const RADIUS: ParamSpec = ParamSpec::new(
    "radius",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "half width in pixels",
);

/// The `tent` plugin.
pub static PLUGIN: Plugin<FilterDesc> = Plugin {
    name: "tent",
    summary: "Tent filter: weight falling linearly to 0 at `radius` (Mitsuba 3 `src/rfilters/tent.cpp`).",
    params: &[RADIUS],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<FilterDesc, SceneError> {
    Ok(FilterDesc::Tent {
        radius: positive(p, &RADIUS)?,
    })
}
