//! `envmap`: an environment map in the equirectangular (latitude-longitude) layout (Mitsuba 3
//! `src/emitters/envmap.cpp`; runtime [`crate::emitter::EnvMapLight`], whose docs give the texel
//! layout and the lookup). `lookup="mitsuba"` is ours: Mitsuba 3.9.1's lookup (rows from pole to
//! pole, texel shapes and scales interpolated separately). `mis_compensation` is Mitsuba's, but on
//! by default here: it changes the noise, never the expected image. So does `product_sampling`,
//! ours: next-event directions × the clamped cosine at the shading point
//! (`crate::emitter::envmap_product`).

use crate::image::RgbImage;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::EmitterDesc;
use crate::xml::{Builder, ErrorKind, Params, SceneError, err, image_error};
use std::sync::Arc;

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the image (EXR, Radiance HDR, PNG or JPEG), relative to the scene file (required)",
);
const SCALE: ParamSpec = ParamSpec::new(
    "scale",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "factor on the radiance (non-negative)",
);
const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "orientation of the environment (+y up in its own frame)",
);
const MIS_COMPENSATION: ParamSpec = ParamSpec::new(
    "mis_compensation",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "next-event samples ∝ max(L − mean, 0), leaving the dimmer directions to BSDF sampling (Karlík et al. 2019): less noise, the same image",
)
.mitsuba(DefaultValue::Bool(false));
const PRODUCT_SAMPLING: ParamSpec = ParamSpec::new(
    "product_sampling",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) next-event samples at a reflecting surface ∝ that density × the clamped cosine at its shading normal: less noise, the same image",
)
.mitsuba(DefaultValue::Bool(false));

const LOOKUP: ParamSpec = ParamSpec::ours_or_mitsuba(
    "lookup",
    "bilinear",
    "(ours) `bilinear` (texels as areas, bilinear in their spectra) or `mitsuba` (Mitsuba 3.9.1: rows from pole to pole, shapes and scales interpolated separately)",
);

/// The `envmap` plugin.
pub static PLUGIN: Plugin<EmitterDesc> = Plugin {
    name: "envmap",
    summary: "Environment map: radiance from every direction read from an equirectangular image.",
    params: &[
        FILENAME,
        SCALE,
        TO_WORLD,
        MIS_COMPENSATION,
        PRODUCT_SAMPLING,
        LOOKUP,
        super::MEDIUM,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<EmitterDesc, SceneError> {
    let Some((name, loc)) = p.string_opt(FILENAME.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "<emitter type=\"envmap\"> needs a filename",
        ));
    };
    let path = b.resolve_file(p, name);
    let image = RgbImage::read(&path).map_err(|e| image_error(loc, name, e))?;
    let scale = p.float_checked(
        SCALE.name,
        SCALE.default.float(),
        |v| v >= 0.0,
        "must be non-negative",
    )? as f32;
    let to_world = p.affine(TO_WORLD.name)?;
    let mis_compensation = p.bool(MIS_COMPENSATION.name, p.default_of(&MIS_COMPENSATION).bool())?;
    let product_sampling = p.bool(PRODUCT_SAMPLING.name, p.default_of(&PRODUCT_SAMPLING).bool())?;
    let mitsuba_lookup = p.mitsuba_way(&LOOKUP)?;
    Ok(EmitterDesc::EnvMap {
        image: Arc::new(image),
        scale,
        to_world,
        mitsuba_lookup,
        mis_compensation,
        product_sampling,
    })
}
