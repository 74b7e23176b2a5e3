//! `bitmap`: an image file as a texture (Mitsuba 3 `src/textures/bitmap.cpp`).

use crate::image::{Encoding, RgbImage};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::{Bitmap, FilterType, Texture, WrapMode};
use crate::xml::{Builder, ErrorKind, Params, SceneError, err, image_error};
use std::sync::Arc;

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the image (EXR, Radiance HDR, PNG or JPEG), relative to the scene file (required)",
);
const FILTER_TYPE: ParamSpec = ParamSpec::new(
    "filter_type",
    ParamType::String,
    DefaultValue::Str("bilinear"),
    "`bilinear` or `nearest` lookups",
);
const WRAP_MODE: ParamSpec = ParamSpec::new(
    "wrap_mode",
    ParamType::String,
    DefaultValue::Str("repeat"),
    "outside [0, 1]²: `repeat`, `mirror` or `clamp`",
);
const RAW: ParamSpec = ParamSpec::new(
    "raw",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "read 8-bit values as they are, without sRGB decoding",
);
const TO_UV: ParamSpec = ParamSpec::new(
    "to_uv",
    ParamType::Transform,
    DefaultValue::None,
    "transform of the texture coordinates (rows and columns 0, 1, 3 of the 4 × 4)",
);
const FORMAT: ParamSpec = ParamSpec::new(
    "format",
    ParamType::String,
    DefaultValue::Str("auto"),
    "`auto`, `variant`, `fp16`; accepted and ignored",
);
const ACCEL: ParamSpec = ParamSpec::new(
    "accel",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "accepted and ignored",
);

/// The `bitmap` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "bitmap",
    summary: "Image texture: RGB values uplifted to spectra in the role of the parameter it fills.",
    params: &[FILENAME, FILTER_TYPE, WRAP_MODE, RAW, TO_UV, FORMAT, ACCEL],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let obj = p.obj;
    let Some((name, loc)) = p.string_opt(FILENAME.name)? else {
        return Err(err(
            &obj.loc,
            ErrorKind::Grammar,
            "<texture type=\"bitmap\"> needs a filename",
        ));
    };
    let filter = match p.choice(
        FILTER_TYPE.name,
        FILTER_TYPE.default.str(),
        &["bilinear", "nearest"],
    )? {
        "nearest" => FilterType::Nearest,
        _ => FilterType::Bilinear,
    };
    let wrap = match p.choice(
        WRAP_MODE.name,
        WRAP_MODE.default.str(),
        &["repeat", "mirror", "clamp"],
    )? {
        "mirror" => WrapMode::Mirror,
        "clamp" => WrapMode::Clamp,
        _ => WrapMode::Repeat,
    };
    let raw = p.bool(RAW.name, RAW.default.bool())?;
    let to_uv = p.to_uv()?;
    p.choice(FORMAT.name, FORMAT.default.str(), &["auto", "variant", "fp16"])?;
    p.bool(ACCEL.name, ACCEL.default.bool())?;
    let path = b.resolve_file(p, name);
    let img = RgbImage::read_with(&path, if raw { Encoding::Raw } else { Encoding::Srgb })
        .map_err(|e| image_error(loc, name, e))?;
    let (w, h) = (img.width, img.height);
    let bitmap = Bitmap::new(w, h, img.data, filter, wrap, b.role(), to_uv).ok_or_else(|| {
        err(
            loc,
            ErrorKind::Image,
            format!("image \"{name}\" is empty ({w}x{h})"),
        )
    })?;
    Ok(Texture::Bitmap(Arc::new(bitmap)))
}
