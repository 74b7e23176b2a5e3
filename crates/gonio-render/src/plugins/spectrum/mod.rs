//! `<spectrum type="...">` plugins (Mitsuba 3 `src/spectra/`): spectra that do not vary over a
//! surface, usable wherever a spectrum or texture is (as [`crate::texture::Texture::Spectrum`]).

pub mod blackbody;
pub mod d65;
pub mod irregular;
pub mod regular;
pub mod srgb;
pub mod uniform;

use crate::plugins::{DefaultValue, ParamSpec, ParamType};
use crate::xml::parse_list;
use crate::xml::{ErrorKind, Location, Params, SceneError, err};
use gonio_core::spectra::{Extrapolation, PiecewiseLinear, Spectrum};

/// `scale`, shared by the illuminant spectra.
pub const SCALE: ParamSpec = ParamSpec::new(
    "scale",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "factor on the spectrum (non-negative)",
);

/// The `scale` parameter.
fn scale(p: &mut Params<'_>) -> Result<f64, SceneError> {
    p.float_checked(
        SCALE.name,
        SCALE.default.float(),
        |v| v >= 0.0,
        "must be non-negative",
    )
}

/// A wavelength range `[min, max]` (nm) from two parameters: finite, non-negative, in order.
fn wavelength_range(p: &mut Params<'_>, min: &ParamSpec, max: &ParamSpec) -> Result<[f32; 2], SceneError> {
    let mut read = |spec: &ParamSpec| -> Result<(f64, Option<Location>), SceneError> {
        Ok(match (p.float_opt(spec.name)?, spec.default) {
            (Some((v, loc)), _) => (v, Some(loc.clone())),
            (None, DefaultValue::Float(v)) => (v, None),
            (None, _) => {
                return Err(err(
                    &p.obj.loc,
                    ErrorKind::Grammar,
                    format!("{} needs \"{}\"", p.what(), spec.name),
                ));
            }
        })
    };
    let (lo, lo_loc) = read(min)?;
    let (hi, hi_loc) = read(max)?;
    for (v, loc, name) in [(lo, &lo_loc, min.name), (hi, &hi_loc, max.name)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(err(
                loc.as_ref().unwrap_or(&p.obj.loc),
                ErrorKind::BadValue,
                format!("invalid {name} {v} nm (must be finite and non-negative)"),
            ));
        }
    }
    if lo >= hi {
        return Err(err(
            hi_loc.as_ref().or(lo_loc.as_ref()).unwrap_or(&p.obj.loc),
            ErrorKind::BadValue,
            format!("{} {hi} nm must exceed {} {lo} nm", max.name, min.name),
        ));
    }
    Ok([lo as f32, hi as f32])
}

/// A list of numbers written as a string (`"0.1, 0.2 0.4"`), each finite and non-negative, at
/// least `at_least` of them.
fn number_list(
    p: &mut Params<'_>,
    spec: &ParamSpec,
    at_least: usize,
) -> Result<(Vec<f64>, Location), SceneError> {
    let Some((s, loc)) = p.string_opt(spec.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            format!("{} needs \"{}\"", p.what(), spec.name),
        ));
    };
    let v = parse_list(s, loc)?;
    if v.len() < at_least {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "\"{}\" needs at least {at_least} numbers, found {} in \"{s}\"",
                spec.name,
                v.len()
            ),
        ));
    }
    // Finite in single precision, as the spectrum stores them.
    if let Some(x) = v.iter().find(|x| !((**x as f32).is_finite() && **x >= 0.0)) {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "invalid value {x} in \"{}\" (must be finite and non-negative)",
                spec.name
            ),
        ));
    }
    Ok((v, loc.clone()))
}

/// Samples at `lambda` (strictly increasing) with `values`, linearly interpolated and 0 outside:
/// Mitsuba's `regular` and `irregular`.
fn sampled(lambda: Vec<f32>, values: Vec<f32>, loc: &Location) -> Result<Spectrum, SceneError> {
    let n = (lambda.len(), values.len());
    PiecewiseLinear::new(lambda, values, Extrapolation::Zero)
        .map(Spectrum::piecewise)
        .ok_or_else(|| {
            err(
                loc,
                ErrorKind::BadValue,
                format!("{} wavelengths and {} values do not make a spectrum (same count, wavelengths increasing)", n.0, n.1),
            )
        })
}
