//! `specfilm`: Mitsuba 3's spectral film (`src/films/specfilm.cpp`). Each nested spectrum is a
//! band, a sensor response function Sⱼ(λ) (any name, any range, not normalized), and the film
//! records one channel per band, named after it: cⱼ = ∫ Sⱼ(λ) L(λ) dλ. The wavelengths are drawn
//! from the sum of the bands, as Mitsuba draws them (the estimator:
//! [`gonio_core::sensor_response`]). The output is always OpenEXR with the bands as its
//! channels (Mitsuba writes no other format); size, crop window, border sampling, number type and
//! filter are read as `hdrfilm` reads them.
//!
//! A band is a `<spectrum>` (values `λ:v, ...` or an `.spd` file: 0 outside its wavelengths, as
//! Mitsuba's `irregular` spectra), a nested or referenced `<spectrum type="...">` object, or an
//! `<rgb>` colour (its reflectance spectrum over 360–830 nm).

use super::{
    COMPONENT_FORMAT, CROP_HEIGHT, CROP_OFFSET_X, CROP_OFFSET_Y, CROP_WIDTH, HEIGHT, RFILTER, SAMPLE_BORDER,
    WIDTH, film_base,
};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{FileFormat, FilmDesc, IntegratorDesc, PixelFormat};
use crate::xml::{Builder, ErrorKind, Location, Params, SceneError, Tag, Value, err, resolve_ref};
use gonio_core::sensor_response::{SensorResponse, SpectralBands};
use gonio_core::spectra::RgbKind;
use std::sync::Arc;

const BANDS: ParamSpec = ParamSpec::new(
    "(nested spectra)",
    ParamType::Spectrum,
    DefaultValue::None,
    "one or more sensor response functions, each a channel under its own name (at most 64; at least one)",
);

/// The `specfilm` plugin.
pub static PLUGIN: Plugin<FilmDesc> = Plugin {
    name: "specfilm",
    summary: "Spectral film: one channel per spectral band (sensor response function), written as OpenEXR.",
    params: &[
        WIDTH,
        HEIGHT,
        COMPONENT_FORMAT,
        SAMPLE_BORDER,
        CROP_OFFSET_X,
        CROP_OFFSET_Y,
        CROP_WIDTH,
        CROP_HEIGHT,
        RFILTER,
        BANDS,
    ],
    build,
};

/// The names of the properties that are bands: spectra, colours and spectrum objects.
fn band_names<'d>(p: &Params<'d>) -> Result<Vec<&'d str>, SceneError> {
    let mut names = Vec::new();
    for prop in &p.obj.props {
        let is_band = match &prop.value {
            Value::Spectrum(_) | Value::Rgb(_) => true,
            Value::Object(i) => p.doc.objs[*i].tag == Tag::Spectrum,
            Value::Ref(id) => p.doc.objs[resolve_ref(p.doc, id, &prop.value_loc)?].tag == Tag::Spectrum,
            _ => false,
        };
        if is_band {
            names.push(prop.name.as_str());
        }
    }
    Ok(names)
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<FilmDesc, SceneError> {
    let mut film = film_base(b, p)?;
    let names = band_names(p)?;
    let mut srfs = Vec::with_capacity(names.len());
    for name in &names {
        if name.is_empty() {
            return Err(err(
                &p.obj.loc,
                ErrorKind::Grammar,
                "a band of <film type=\"specfilm\"> needs a name (it names the channel)",
            ));
        }
        srfs.push((name.to_string(), b.spectrum_param(p, name, RgbKind::Albedo, 0.0)?));
    }
    let bands = SpectralBands::new(srfs)
        .map_err(|e| err(&p.obj.loc, ErrorKind::BadValue, format!("specfilm: {e}")))?;
    film.response = SensorResponse::Bands(Arc::new(bands));
    film.output.pixel_format = PixelFormat::Bands;
    film.output.file_format = FileFormat::OpenExr;
    Ok(film)
}

/// The `aov` and `moment` wrappers read their nested integrators' colour (`R, G, B`): with a
/// film of bands they are an error, at the integrator's location `at`.
pub(crate) fn check_integrator(
    film: &FilmDesc,
    integrator: &IntegratorDesc,
    at: &Location,
) -> Result<(), SceneError> {
    if integrator.layers.is_some() && matches!(film.response, SensorResponse::Bands(_)) {
        return Err(err(
            at,
            ErrorKind::BadValue,
            "the aov and moment integrators need a colour film (hdrfilm): this sensor's specfilm records spectral bands",
        ));
    }
    Ok(())
}
