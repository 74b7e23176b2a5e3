//! `perspective`: Mitsuba 3's pinhole camera (`src/sensors/perspective.cpp`), with its nested
//! film and sampler; the runtime camera is [`crate::camera`].

use crate::plugins::{DefaultValue, FILM_PLUGINS, ParamSpec, ParamType, Plugin, SAMPLER_PLUGINS};
use crate::scene::{FilmDesc, Projection, SamplerDesc, SensorDesc};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};
use glam::Affine3A;
use gonio_core::sensor_response::{SensorResponse, SpectralBands};
use gonio_core::spectra::RgbKind;
use std::sync::Arc;

pub(crate) const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "camera to world (+z forward, +y up); scale factors are refused, a mirror flip is allowed",
);
pub(crate) const FOV: ParamSpec = ParamSpec::new(
    "fov",
    ParamType::Float,
    DefaultValue::None,
    "field of view in degrees, in (0, 180), along `fov_axis` (instead of `focal_length`)",
);
pub(crate) const FOCAL_LENGTH: ParamSpec = ParamSpec::new(
    "focal_length",
    ParamType::String,
    DefaultValue::Str("50mm"),
    "focal length of a 35 mm film camera, e.g. \"50mm\" (instead of `fov`)",
);
pub(crate) const FOV_AXIS: ParamSpec = ParamSpec::new(
    "fov_axis",
    ParamType::String,
    DefaultValue::Str("x"),
    "the axis `fov` is measured along: `x`, `y`, `diagonal`, `smaller`, `larger`",
);
pub(crate) const NEAR_CLIP: ParamSpec = ParamSpec::new(
    "near_clip",
    ParamType::Float,
    DefaultValue::Float(0.01),
    "near clipping distance (positive)",
);
pub(crate) const FAR_CLIP: ParamSpec = ParamSpec::new(
    "far_clip",
    ParamType::Float,
    DefaultValue::Float(10000.0),
    "far clipping distance (above `near_clip`)",
);
pub(crate) const PRINCIPAL_POINT_OFFSET_X: ParamSpec = ParamSpec::new(
    "principal_point_offset_x",
    ParamType::Float,
    DefaultValue::Float(0.0),
    "principal point offset; only 0 is supported",
);
pub(crate) const PRINCIPAL_POINT_OFFSET_Y: ParamSpec = ParamSpec::new(
    "principal_point_offset_y",
    ParamType::Float,
    DefaultValue::Float(0.0),
    "principal point offset; only 0 is supported",
);
pub(crate) const FOCUS_DISTANCE: ParamSpec = ParamSpec::new(
    "focus_distance",
    ParamType::Float,
    DefaultValue::None,
    "accepted and ignored, as in Mitsuba (a pinhole is in focus at every distance; `thinlens` uses it)",
);
pub(crate) const SHUTTER_OPEN: ParamSpec = ParamSpec::new(
    "shutter_open",
    ParamType::Float,
    DefaultValue::Float(0.0),
    "accepted and ignored (no motion blur)",
);
pub(crate) const SHUTTER_CLOSE: ParamSpec = ParamSpec::new(
    "shutter_close",
    ParamType::Float,
    DefaultValue::Float(0.0),
    "accepted and ignored (no motion blur)",
);
pub(crate) const FILM: ParamSpec = ParamSpec::new(
    "(nested film)",
    ParamType::Film,
    DefaultValue::Str("hdrfilm"),
    "at most one nested film",
);
pub(crate) const MEDIUM: ParamSpec = ParamSpec::new(
    "(nested medium)",
    ParamType::Medium,
    DefaultValue::None,
    "the `<medium>` the sensor is in (its rays start in it); none: vacuum",
);
pub(crate) const SAMPLER: ParamSpec = ParamSpec::new(
    "(nested sampler)",
    ParamType::Sampler,
    DefaultValue::Str("independent"),
    "at most one nested sampler",
);

pub(crate) const SRF: ParamSpec = ParamSpec::new(
    "srf",
    ParamType::Spectrum,
    DefaultValue::None,
    "spectral response function S(λ): the image is the colour of S·L, the wavelengths drawn ∝ S (Mitsuba's spectral variants); not with a `specfilm`, whose bands are its own",
);

/// The `perspective` plugin.
pub static PLUGIN: Plugin<SensorDesc> = Plugin {
    name: "perspective",
    summary: "Perspective pinhole camera looking down +z of `to_world`, with its film and sampler.",
    params: &[
        TO_WORLD,
        FOV,
        FOCAL_LENGTH,
        FOV_AXIS,
        NEAR_CLIP,
        FAR_CLIP,
        PRINCIPAL_POINT_OFFSET_X,
        PRINCIPAL_POINT_OFFSET_Y,
        FOCUS_DISTANCE,
        SHUTTER_OPEN,
        SHUTTER_CLOSE,
        FILM,
        SAMPLER,
        MEDIUM,
        SRF,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<SensorDesc, SceneError> {
    build_projective(b, p, true)
}

/// A sensor's nested film and sampler (rows [`FILM`], [`SAMPLER`]; their defaults when absent).
pub(crate) fn film_and_sampler<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
) -> Result<(FilmDesc, SamplerDesc), SceneError> {
    let mut film: FilmDesc = b
        .nested_one(p, Tag::Film, FILM_PLUGINS, "sensor")?
        .unwrap_or_default();
    // A spectral response function (row [`SRF`]) filters what the film records.
    if let Some(loc) = p.get(SRF.name).map(|prop| prop.value_loc.clone()) {
        let srf = b.spectrum_param(p, SRF.name, RgbKind::Albedo, 0.0)?;
        if !matches!(film.response, SensorResponse::Srgb) {
            return Err(err(
                &loc,
                ErrorKind::BadValue,
                "a spectral response function (srf) in a sensor whose film (specfilm) has its own bands (Mitsuba refuses it too)",
            ));
        }
        let bands = SpectralBands::new(vec![(SRF.name.to_string(), srf)])
            .map_err(|e| err(&loc, ErrorKind::BadValue, format!("srf: {e}")))?;
        film.response = SensorResponse::Filtered(Arc::new(bands));
    }
    let sampler = b
        .nested_one(p, Tag::Sampler, SAMPLER_PLUGINS, "sensor")?
        .unwrap_or_default();
    // The medium the sensor is in (row [`MEDIUM`]), which the scene takes with the sensor.
    b.sensor_medium = match p.objects(Tag::Medium)?.as_slice() {
        [] => None,
        [(i, prop)] => Some(b.medium(*i, &prop.value_loc)?),
        [_, (_, extra), ..] => {
            return Err(crate::xml::err(
                &extra.loc,
                crate::xml::ErrorKind::Grammar,
                "more than one <medium> in a sensor",
            ));
        }
    };
    // A sensor of a `batch` takes its share of the batch's film and the batch's sampler (its
    // own, read and checked above, are superseded, as in Mitsuba).
    match &b.batch_film {
        Some((film, sampler)) => Ok((film.clone(), sampler.clone())),
        None => Ok((film, sampler)),
    }
}

/// What `perspective`, `thinlens` (`has_fov = true`) and `orthographic` (`has_fov = false`, scale allowed
/// in `to_world`) share: film, sampler, `to_world`, field of view, clipping, ignored shutter and
/// principal point; the caller sets [`SensorDesc::projection`].
pub(crate) fn build_projective<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    has_fov: bool,
) -> Result<SensorDesc, SceneError> {
    let obj = p.obj;
    let (film, sampler) = film_and_sampler(b, p)?;
    let tw_loc = obj
        .props
        .iter()
        .find(|x| x.name == TO_WORLD.name)
        .map(|x| x.loc.clone());
    let to_world = p.affine(TO_WORLD.name)?;
    // Mitsuba: "Scale factors in the camera-to-world transformation are not allowed!"
    // (a mirror flip, scale −1, keeps unit axes and is allowed).
    let m = to_world.matrix3;
    if has_fov
        && [m.x_axis, m.y_axis, m.z_axis]
            .iter()
            .any(|a| (a.length() - 1.0).abs() > 1e-3)
    {
        return Err(err(
            tw_loc.as_ref().unwrap_or(&obj.loc),
            ErrorKind::BadValue,
            format!(
                "scale factors in the sensor's to_world are not allowed (axis lengths {}, {}, {})",
                m.x_axis.length(),
                m.y_axis.length(),
                m.z_axis.length()
            ),
        ));
    }
    let aspect = film.width as f64 / film.height as f64;
    let (fov, focal, axis) = if has_fov {
        (
            p.float_opt(FOV.name)?,
            p.string_opt(FOCAL_LENGTH.name)?,
            p.choice(
                FOV_AXIS.name,
                FOV_AXIS.default.str(),
                &["x", "y", "diagonal", "smaller", "larger"],
            )?,
        )
    } else {
        // An orthographic camera has no field of view; its width is to_world's scale.
        (None, Some(("50mm", &obj.loc)), "x")
    };
    let fov_x = match (fov, focal) {
        (Some(_), Some((_, loc))) => {
            return Err(err(
                loc,
                ErrorKind::Grammar,
                "give either fov or focal_length, not both",
            ));
        }
        (Some((v, loc)), None) => {
            if !(v > 0.0 && v < 180.0) {
                return Err(err(
                    loc,
                    ErrorKind::BadValue,
                    format!("invalid fov {v} (must be in (0, 180) degrees)"),
                ));
            }
            fov_to_x(v, axis, aspect)
        }
        (None, f) => {
            let (s, loc) = f
                .map(|(s, l)| (s, Some(l)))
                .unwrap_or((FOCAL_LENGTH.default.str(), None));
            let mm = focal_length_mm(s).ok_or_else(|| {
                err(
                    loc.unwrap_or(&obj.loc),
                    ErrorKind::BadValue,
                    format!("invalid focal_length \"{s}\" (expected e.g. \"50mm\")"),
                )
            })?;
            fov_x_of_focal_length(mm, aspect)
        }
    };
    let positive = |v: f64| v > 0.0;
    let near_clip = p.float_checked(
        NEAR_CLIP.name,
        NEAR_CLIP.default.float(),
        positive,
        "must be positive",
    )?;
    let far_clip = p.float_checked(
        FAR_CLIP.name,
        FAR_CLIP.default.float(),
        positive,
        "must be positive",
    )?;
    if far_clip <= near_clip {
        return Err(err(
            &obj.loc,
            ErrorKind::BadValue,
            format!("far_clip {far_clip} must exceed near_clip {near_clip}"),
        ));
    }
    let offsets: &[&str] = if has_fov {
        &[PRINCIPAL_POINT_OFFSET_X.name, PRINCIPAL_POINT_OFFSET_Y.name]
    } else {
        &[]
    };
    for &name in offsets {
        if let Some((v, loc)) = p.float_opt(name)?
            && v != 0.0
        {
            return Err(err(
                loc,
                ErrorKind::BadValue,
                format!("{name} {v} is not supported (only 0)"),
            ));
        }
    }
    // Mitsuba's projective cameras all read it (default: far_clip); the pinhole never uses it.
    p.float_opt(FOCUS_DISTANCE.name)?;
    p.float(SHUTTER_OPEN.name, SHUTTER_OPEN.default.float())?;
    p.float(SHUTTER_CLOSE.name, SHUTTER_CLOSE.default.float())?;
    Ok(SensorDesc {
        to_world,
        fov_x_deg: fov_x as f32,
        projection: Projection::Perspective,
        near_clip: near_clip as f32,
        far_clip: far_clip as f32,
        film,
        sampler,
        children: Vec::new(),
        target_shape: None,
    })
}

/// "50mm" (or "50") in millimetres; `None` unless positive and finite.
pub(crate) fn focal_length_mm(s: &str) -> Option<f64> {
    let num = s.trim().strip_suffix("mm").unwrap_or(s.trim());
    num.trim()
        .parse()
        .ok()
        .filter(|v: &f64| *v > 0.0 && v.is_finite())
}

/// The horizontal field of view of a 35 mm film camera (36 × 24 mm, diagonal
/// sqrt(36² + 24²) mm) with focal length `mm`, on a film of the given aspect ratio.
pub(crate) fn fov_x_of_focal_length(mm: f64, aspect: f64) -> f64 {
    let diag = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
    let fov_diag = 2.0 * (diag / (2.0 * mm)).atan().to_degrees();
    fov_to_x(fov_diag, "diagonal", aspect)
}

/// Mitsuba's sensor for a scene without one: this plugin with every default and the default
/// film and sampler.
pub(crate) fn default_sensor() -> SensorDesc {
    let film = FilmDesc::default();
    let aspect = film.width as f64 / film.height as f64;
    let mm = focal_length_mm(FOCAL_LENGTH.default.str()).expect("the default focal length parses");
    SensorDesc {
        to_world: Affine3A::IDENTITY,
        fov_x_deg: fov_x_of_focal_length(mm, aspect) as f32,
        projection: Projection::Perspective,
        near_clip: NEAR_CLIP.default.float() as f32,
        far_clip: FAR_CLIP.default.float() as f32,
        film,
        sampler: SamplerDesc::default(),
        children: Vec::new(),
        target_shape: None,
    }
}

/// Converts a field of view along `axis` into the horizontal one, as Mitsuba 3 does
/// (`src/sensors/perspective.cpp`, `fov_axis`).
pub(crate) fn fov_to_x(fov_deg: f64, axis: &str, aspect: f64) -> f64 {
    let t = (fov_deg.to_radians() / 2.0).tan();
    let axis = match axis {
        "smaller" => {
            if aspect > 1.0 {
                "y"
            } else {
                "x"
            }
        }
        "larger" => {
            if aspect > 1.0 {
                "x"
            } else {
                "y"
            }
        }
        a => a,
    };
    match axis {
        "y" => 2.0 * (t * aspect).atan().to_degrees(),
        "diagonal" => {
            let width = 2.0 * t / (1.0 + 1.0 / (aspect * aspect)).sqrt();
            2.0 * (width / 2.0).atan().to_degrees()
        }
        _ => fov_deg,
    }
}
