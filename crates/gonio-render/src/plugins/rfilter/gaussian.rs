//! `gaussian`: Gaussian filter truncated at 4 standard deviations (Mitsuba 3 `src/rfilters/gaussian.cpp`).

use super::positive;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::FilterDesc;
use crate::xml::{Builder, Params, SceneError};

const STDDEV: ParamSpec = ParamSpec::new(
    "stddev",
    ParamType::Float,
    DefaultValue::Float(0.5),
    "standard deviation in pixels; the support is 4σ",
);

/// The `gaussian` plugin.
pub static PLUGIN: Plugin<FilterDesc> = Plugin {
    name: "gaussian",
    summary: "Gaussian filter truncated at 4 standard deviations (Mitsuba 3 `src/rfilters/gaussian.cpp`).",
    params: &[STDDEV],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<FilterDesc, SceneError> {
    Ok(FilterDesc::Gaussian {
        stddev: positive(p, &STDDEV)?,
    })
}
