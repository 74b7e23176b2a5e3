//! `box` filter: every sample within `radius` weighs the same (Mitsuba 3 `src/rfilters/box.cpp`).

use super::positive;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::FilterDesc;
use crate::xml::{Builder, Params, SceneError};

const RADIUS: ParamSpec = ParamSpec::new(
    "radius",
    ParamType::Float,
    DefaultValue::Float(0.5),
    "half width in pixels",
);

/// The `box` plugin.
pub static PLUGIN: Plugin<FilterDesc> = Plugin {
    name: "box",
    summary: "Box filter: every sample within `radius` weighs the same (Mitsuba 3 `src/rfilters/box.cpp`).",
    params: &[RADIUS],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<FilterDesc, SceneError> {
    Ok(FilterDesc::Box {
        radius: positive(p, &RADIUS)?,
    })
}
