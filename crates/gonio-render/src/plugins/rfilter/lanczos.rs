//! `lanczos`: the windowed sinc sinc(πx)·sinc(πx/a) with a = `lobes`, radius a (Mitsuba 3
//! `src/rfilters/lanczos.cpp`); the formula is in [`crate::film`].

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::FilterDesc;
use crate::xml::{Builder, Params, SceneError};

const LOBES: ParamSpec = ParamSpec::new(
    "lobes",
    ParamType::Integer,
    DefaultValue::Int(3),
    "number of lobes a (the radius in pixels), in [1, 16]",
);

/// The `lanczos` plugin.
pub static PLUGIN: Plugin<FilterDesc> = Plugin {
    name: "lanczos",
    summary: "Lanczos windowed sinc with `lobes` lobes (radius = lobes) (Mitsuba 3 `src/rfilters/lanczos.cpp`).",
    params: &[LOBES],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<FilterDesc, SceneError> {
    let lobes = p.int_in(LOBES.name, LOBES.default.int(), 1, 16)? as u32;
    Ok(FilterDesc::Lanczos { lobes })
}
