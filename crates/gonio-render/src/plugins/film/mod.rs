//! `<film>` plugins (nested in a sensor): `hdrfilm` (colour) and `specfilm` (spectral bands).
//! Both read the film's size, crop window, border sampling, number type and reconstruction
//! filter the same way (`film_base`); each adds what it records.

pub mod hdrfilm;
pub mod specfilm;

use crate::plugins::{DefaultValue, ParamSpec, ParamType, RFILTER_PLUGINS};
use crate::scene::{ComponentFormat, CropWindow, FilmDesc, FilmOutput};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};

pub(super) const WIDTH: ParamSpec = ParamSpec::new(
    "width",
    ParamType::Integer,
    DefaultValue::Int(768),
    "image width in pixels, in [1, 65536]",
);
pub(super) const HEIGHT: ParamSpec = ParamSpec::new(
    "height",
    ParamType::Integer,
    DefaultValue::Int(576),
    "image height in pixels, in [1, 65536]",
);
pub(super) const COMPONENT_FORMAT: ParamSpec = ParamSpec::new(
    "component_format",
    ParamType::String,
    DefaultValue::Str("float16"),
    "`float16`, `float32`, `uint32`: the number type of an EXR file's values",
);
pub(super) const SAMPLE_BORDER: ParamSpec = ParamSpec::new(
    "sample_border",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "also sample the pixels outside the image that the filter reaches (⌈radius − ½⌉ of them), so edge pixels get samples from both sides",
);
pub(super) const CROP_OFFSET_X: ParamSpec = ParamSpec::new(
    "crop_offset_x",
    ParamType::Integer,
    DefaultValue::Int(0),
    "left edge of the crop window (pixels), in [0, `width` − 1]",
);
pub(super) const CROP_OFFSET_Y: ParamSpec = ParamSpec::new(
    "crop_offset_y",
    ParamType::Integer,
    DefaultValue::Int(0),
    "top edge of the crop window (pixels), in [0, `height` − 1]",
);
pub(super) const CROP_WIDTH: ParamSpec = ParamSpec::new(
    "crop_width",
    ParamType::Integer,
    DefaultValue::Derived("`width`"),
    "width of the crop window: only that part of the film is rendered and written",
);
pub(super) const CROP_HEIGHT: ParamSpec = ParamSpec::new(
    "crop_height",
    ParamType::Integer,
    DefaultValue::Derived("`height`"),
    "height of the crop window",
);
pub(super) const RFILTER: ParamSpec = ParamSpec::new(
    "(nested rfilter)",
    ParamType::Rfilter,
    DefaultValue::Str("gaussian"),
    "at most one nested reconstruction filter",
);

/// The parameters every film shares, read into a [`FilmDesc`] with the default output (the
/// `component_format` read; the caller sets what it records).
pub(super) fn film_base<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<FilmDesc, SceneError> {
    let width = p.int_in(WIDTH.name, WIDTH.default.int(), 1, 1 << 16)? as u32;
    let height = p.int_in(HEIGHT.name, HEIGHT.default.int(), 1, 1 << 16)? as u32;
    let filter = b
        .nested_one(p, Tag::Rfilter, RFILTER_PLUGINS, "film")?
        .unwrap_or_default();
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
            component_format,
            ..FilmOutput::default()
        },
        crop,
        sample_border,
        ..FilmDesc::default()
    })
}
