//! `hdrfilm`: Mitsuba 3's high-dynamic-range film (`src/films/hdrfilm.cpp`) with its nested
//! reconstruction filter; the runtime film is [`crate::film`]. The output settings are honoured as
//! Mitsuba honours them: `pixel_format` chooses the channels (alpha is the fraction of the pixel's
//! camera rays that hit a surface or see an environment), `component_format` the EXR number type,
//! and `file_format` the default output's format and extension (an explicit `-o name.ext` wins).
//! A crop window renders and writes only its part of the film, seen as the full film sees it.
//! `sample_border` also samples the band of ⌈radius − ½⌉ pixels around the image (around the
//! crop window), whose samples reach the edge pixels through the filter, as Mitsuba's
//! `SamplingIntegrator::render` does; without it an edge pixel's filter sees the samples inside
//! the image only.

use super::{
    COMPONENT_FORMAT, CROP_HEIGHT, CROP_OFFSET_X, CROP_OFFSET_Y, CROP_WIDTH, HEIGHT, RFILTER, SAMPLE_BORDER,
    WIDTH, film_base,
};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{FileFormat, FilmDesc, PixelFormat};
use crate::xml::{Builder, Params, SceneError};

const FILE_FORMAT: ParamSpec = ParamSpec::new(
    "file_format",
    ParamType::String,
    DefaultValue::Str("openexr"),
    "`openexr` (or `exr`), `rgbe` (Radiance `.hdr`), `pfm`: the default output's format",
);
const PIXEL_FORMAT: ParamSpec = ParamSpec::new(
    "pixel_format",
    ParamType::String,
    DefaultValue::Str("rgb"),
    "`rgb`, `rgba`, `luminance`, `luminance_alpha`, `xyz`, `xyza`: the image's channels (EXR and PFM; RGBE holds RGB)",
);
const BANNER: ParamSpec = ParamSpec::new(
    "banner",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "Mitsuba 0.6's banner on the image; accepted (Mitsuba 3 accepts it too) and ignored: gonio draws none",
);
const COMPENSATE: ParamSpec = ParamSpec::new(
    "compensate",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "accepted and ignored",
);
/// The `hdrfilm` plugin.
pub static PLUGIN: Plugin<FilmDesc> = Plugin {
    name: "hdrfilm",
    summary: "High-dynamic-range film: the image size and the reconstruction filter.",
    params: &[
        WIDTH,
        HEIGHT,
        FILE_FORMAT,
        PIXEL_FORMAT,
        COMPONENT_FORMAT,
        SAMPLE_BORDER,
        BANNER,
        COMPENSATE,
        CROP_OFFSET_X,
        CROP_OFFSET_Y,
        CROP_WIDTH,
        CROP_HEIGHT,
        RFILTER,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<FilmDesc, SceneError> {
    let mut film = film_base(b, p)?;
    film.output.file_format = match p.choice(
        FILE_FORMAT.name,
        FILE_FORMAT.default.str(),
        &["openexr", "exr", "rgbe", "pfm"],
    )? {
        "rgbe" => FileFormat::Rgbe,
        "pfm" => FileFormat::Pfm,
        _ => FileFormat::OpenExr,
    };
    film.output.pixel_format = match p.choice(
        PIXEL_FORMAT.name,
        PIXEL_FORMAT.default.str(),
        &["rgb", "rgba", "luminance", "luminance_alpha", "xyz", "xyza"],
    )? {
        "rgba" => PixelFormat::Rgba,
        "luminance" => PixelFormat::Luminance,
        "luminance_alpha" => PixelFormat::LuminanceAlpha,
        "xyz" => PixelFormat::Xyz,
        "xyza" => PixelFormat::Xyza,
        _ => PixelFormat::Rgb,
    };
    p.bool(BANNER.name, BANNER.default.bool())?;
    p.bool(COMPENSATE.name, COMPENSATE.default.bool())?;
    Ok(film)
}
