//! `mitchell` and `catmullrom`: the cubic filters of Mitchell and Netravali, "Reconstruction
//! Filters in Computer Graphics" (SIGGRAPH 1988), radius 2 (Mitsuba 3 `src/rfilters/mitchell.cpp`,
//! `catmullrom.cpp`); the formula is in [`crate::film`].

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::FilterDesc;
use crate::xml::{Builder, Params, SceneError};

const B: ParamSpec = ParamSpec::new(
    "B",
    ParamType::Float,
    DefaultValue::Float(1.0 / 3.0),
    "the cubic's B",
);
const C: ParamSpec = ParamSpec::new(
    "C",
    ParamType::Float,
    DefaultValue::Float(1.0 / 3.0),
    "the cubic's C",
);

/// The `mitchell` plugin.
pub static PLUGIN: Plugin<FilterDesc> = Plugin {
    name: "mitchell",
    summary: "Mitchell–Netravali cubic, radius 2, B = C = 1/3 by default (Mitsuba 3 `src/rfilters/mitchell.cpp`).",
    params: &[B, C],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<FilterDesc, SceneError> {
    let finite = |v: f64| v.is_finite();
    let b = p.float_checked(B.name, B.default.float(), finite, "must be finite")? as f32;
    let c = p.float_checked(C.name, C.default.float(), finite, "must be finite")? as f32;
    Ok(FilterDesc::Mitchell { b, c })
}

/// The `catmullrom` plugin.
pub static CATMULLROM: Plugin<FilterDesc> = Plugin {
    name: "catmullrom",
    summary: "Catmull–Rom spline: the Mitchell–Netravali cubic with B = 0, C = ½, radius 2 (Mitsuba 3 `src/rfilters/catmullrom.cpp`).",
    params: &[],
    build: build_catmullrom,
};

fn build_catmullrom<'d>(_: &mut Builder<'d>, _: &mut Params<'d>) -> Result<FilterDesc, SceneError> {
    Ok(FilterDesc::Mitchell { b: 0.0, c: 0.5 })
}
