//! `area`: a shape's surface emitting on its front side (Mitsuba 3 `src/emitters/area.cpp`).
//!
//! A number or an `<rgb>` given in place is an illuminant colour, × D65 (so `1, 1, 1` is the
//! sRGB white), and so are the colours of a texture object (a `bitmap`, a `checkerboard`): a
//! texel emits its own colour. `whitepoint="mitsuba"` drops D65 where Mitsuba 3.9.1 drops it, for
//! a nested or referenced texture (its `texture_d65` wraps only a value given in place), so that
//! white texels emit the equal-energy spectrum, about sRGB (1.19, 0.95, 0.88) (test
//! `area_texture_emits_its_own_colour_unless_whitepoint_mitsuba`).

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{AreaEmitterDesc, SurfaceEmission};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError, Tag};
use gonio_core::spectra::RgbKind;

pub(super) const RADIANCE: ParamSpec = ParamSpec::new(
    "radiance",
    ParamType::Texture,
    DefaultValue::Float(1.0),
    "emitted radiance (numbers and colours × D65); may be a texture",
);

pub(super) const WHITEPOINT: ParamSpec = ParamSpec::ours_or_mitsuba(
    "whitepoint",
    "d65",
    "(ours) `d65` (a texture's colours × D65, as a colour given in place: a texel emits its colour) or `mitsuba` (Mitsuba 3.9.1: no D65 for a texture object)",
);

/// The `area` plugin.
pub static PLUGIN: Plugin<AreaEmitterDesc> = Plugin {
    name: "area",
    summary: "Area light: the shape it is nested in emits `radiance` on the side its normal points to.",
    params: &[RADIANCE, WHITEPOINT, super::MEDIUM],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<AreaEmitterDesc, SceneError> {
    Ok(AreaEmitterDesc {
        radiance: radiance(b, p)?,
        hit: None,
        emission: SurfaceEmission::Diffuse,
    })
}

/// The rows [`RADIANCE`] and [`WHITEPOINT`], which `directionalarea` shares.
pub(super) fn radiance<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let mitsuba_whitepoint = p.mitsuba_way(&WHITEPOINT)?;
    let texture_object = p
        .objects(Tag::Texture)?
        .iter()
        .any(|(_, x)| x.name == RADIANCE.name);
    let kind = if texture_object && mitsuba_whitepoint {
        RgbKind::Unbounded
    } else {
        RgbKind::Illuminant
    };
    b.texture(p, &RADIANCE, kind)
}
