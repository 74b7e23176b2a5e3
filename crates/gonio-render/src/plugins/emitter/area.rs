//! `area`: a shape's surface emitting on its front side (Mitsuba 3 `src/emitters/area.cpp`).

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::AreaEmitterDesc;
use crate::xml::{Builder, Params, SceneError};
use gonio_core::spectra::RgbKind;

const RADIANCE: ParamSpec = ParamSpec::new(
    "radiance",
    ParamType::Texture,
    DefaultValue::Float(1.0),
    "emitted radiance (numbers and colours × D65); may be a texture",
);

/// The `area` plugin.
pub static PLUGIN: Plugin<AreaEmitterDesc> = Plugin {
    name: "area",
    summary: "Area light: the shape it is nested in emits `radiance` on the side its normal points to.",
    params: &[RADIANCE],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<AreaEmitterDesc, SceneError> {
    let radiance = b.texture(p, &RADIANCE, RgbKind::Illuminant)?;
    Ok(AreaEmitterDesc { radiance, hit: None })
}
