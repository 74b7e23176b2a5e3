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

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin, RFILTER_PLUGINS};
use crate::scene::{ComponentFormat, CropWindow, FileFormat, FilmDesc, FilmOutput, PixelFormat};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};

const WIDTH: ParamSpec = ParamSpec::new(
    "width",
    ParamType::Integer,
    DefaultValue::Int(768),
    "image width in pixels, in [1, 65536]",
);
const HEIGHT: ParamSpec = ParamSpec::new(
    "height",
    ParamType::Integer,
    DefaultValue::Int(576),
    "image height in pixels, in [1, 65536]",
);
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
const COMPONENT_FORMAT: ParamSpec = ParamSpec::new(
    "component_format",
    ParamType::String,
    DefaultValue::Str("float16"),
    "`float16`, `float32`, `uint32`: the number type of an EXR file's values",
);
const SAMPLE_BORDER: ParamSpec = ParamSpec::new(
    "sample_border",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "also sample the pixels outside the image that the filter reaches (⌈radius − ½⌉ of them), so edge pixels get samples from both sides",
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
const CROP_OFFSET_X: ParamSpec = ParamSpec::new(
    "crop_offset_x",
    ParamType::Integer,
    DefaultValue::Int(0),
    "left edge of the crop window (pixels), in [0, `width` − 1]",
);
const CROP_OFFSET_Y: ParamSpec = ParamSpec::new(
    "crop_offset_y",
    ParamType::Integer,
    DefaultValue::Int(0),
    "top edge of the crop window (pixels), in [0, `height` − 1]",
);
const CROP_WIDTH: ParamSpec = ParamSpec::new(
    "crop_width",
    ParamType::Integer,
    DefaultValue::Derived("`width`"),
    "width of the crop window: only that part of the film is rendered and written",
);
const CROP_HEIGHT: ParamSpec = ParamSpec::new(
    "crop_height",
    ParamType::Integer,
    DefaultValue::Derived("`height`"),
    "height of the crop window",
);
const RFILTER: ParamSpec = ParamSpec::new(
    "(nested rfilter)",
    ParamType::Rfilter,
    DefaultValue::Str("gaussian"),
    "at most one nested reconstruction filter",
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
    let width = p.int_in(WIDTH.name, WIDTH.default.int(), 1, 1 << 16)? as u32;
    let height = p.int_in(HEIGHT.name, HEIGHT.default.int(), 1, 1 << 16)? as u32;
    let filter = b
        .nested_one(p, Tag::Rfilter, RFILTER_PLUGINS, "film")?
        .unwrap_or_default();
    let file_format = match p.choice(
        FILE_FORMAT.name,
        FILE_FORMAT.default.str(),
        &["openexr", "exr", "rgbe", "pfm"],
    )? {
        "rgbe" => FileFormat::Rgbe,
        "pfm" => FileFormat::Pfm,
        _ => FileFormat::OpenExr,
    };
    let pixel_format = match p.choice(
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
    let component_format = match p.choice(
        COMPONENT_FORMAT.name,
        COMPONENT_FORMAT.default.str(),
        &["float16", "float32", "uint32"],
    )? {
        "float32" => ComponentFormat::Float32,
        "uint32" => ComponentFormat::Uint32,
        _ => ComponentFormat::Float16,
    };
    let sample_border = p.bool(SAMPLE_BORDER.name, SAMPLE_BORDER.default.bool())?;
    p.bool(BANNER.name, BANNER.default.bool())?;
    p.bool(COMPENSATE.name, COMPENSATE.default.bool())?;
    let (w, h) = (width as i64, height as i64);
    let x = p.int_in(CROP_OFFSET_X.name, CROP_OFFSET_X.default.int(), 0, w - 1)?;
    let y = p.int_in(CROP_OFFSET_Y.name, CROP_OFFSET_Y.default.int(), 0, h - 1)?;
    // As in Mitsuba, the window defaults to the film size and must lie inside the film.
    let mut window = |size: &ParamSpec, offset: &ParamSpec, full: i64, start: i64| {
        let explicit = p.int_opt(size.name)?.is_some();
        let at = p.int_opt(offset.name)?.map(|(_, l)| l.clone());
        match (explicit, at) {
            (false, Some(loc)) if start > 0 => Err(err(
                &loc,
                ErrorKind::BadValue,
                format!(
                    "the crop window leaves the film: {} {start} with the default {} {full} (give {} ≤ {})",
                    offset.name,
                    size.name,
                    size.name,
                    full - start
                ),
            )),
            _ => p.int_in(size.name, full, 1, full - start),
        }
    };
    let cw = window(&CROP_WIDTH, &CROP_OFFSET_X, w, x)?;
    let ch = window(&CROP_HEIGHT, &CROP_OFFSET_Y, h, y)?;
    let crop = ((x, y, cw, ch) != (0, 0, w, h)).then_some(CropWindow {
        offset: (x as u32, y as u32),
        size: (cw as u32, ch as u32),
    });
    Ok(FilmDesc {
        width,
        height,
        filter,
        output: FilmOutput {
            pixel_format,
            component_format,
            file_format,
        },
        crop,
        sample_border,
    })
}
