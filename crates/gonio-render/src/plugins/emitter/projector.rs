//! `projector`: a texture projected from a pinhole, the reciprocal of the `perspective` camera
//! (Mitsuba 3 `src/emitters/projector.cpp`; runtime [`crate::emitter::ProjectorLight`], whose
//! docs give the mapping and the radiance). The field of view is given as for `perspective`
//! (`fov` along `fov_axis`, or `focal_length`), with the texture's resolution as the film's
//! (a constant texture is 1 × 1). A bitmap is uplifted as a reflectance (Mitsuba's `bitmap`), a
//! colour given in place as an unbounded spectrum; both are multiplied by scale·D65, so that a
//! texel projects its own colour. `whitepoint="mitsuba"` drops D65 where Mitsuba 3.9.1 drops it:
//! for a nested or referenced texture or a `<spectrum>` (its `texture_d65` wraps only a number or
//! an `<rgb>` given in place), so that its white texels project an equal-energy spectrum.

use crate::plugins::sensor::perspective::{focal_length_mm, fov_to_x, fov_x_of_focal_length};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::EmitterDesc;
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, Value, err};
use gonio_core::spectra::RgbKind;

const IRRADIANCE: ParamSpec = ParamSpec::new(
    "irradiance",
    ParamType::Texture,
    DefaultValue::None,
    "E, the image projected (required): the irradiance/π on the plane z = 1 before `scale`",
);
const SCALE: ParamSpec = ParamSpec::new(
    "scale",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "multiplies E",
);
const FOV: ParamSpec = ParamSpec::new(
    "fov",
    ParamType::Float,
    DefaultValue::None,
    "field of view in degrees, in (0, 180), along `fov_axis` (instead of `focal_length`)",
);
const FOCAL_LENGTH: ParamSpec = ParamSpec::new(
    "focal_length",
    ParamType::String,
    DefaultValue::Str("50mm"),
    "35 mm-equivalent focal length (when no `fov` is given)",
);
const FOV_AXIS: ParamSpec = ParamSpec::new(
    "fov_axis",
    ParamType::String,
    DefaultValue::Str("x"),
    "the image axis `fov` applies to: x, y, diagonal, smaller, larger",
);
const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "light to world: the pinhole, projecting along +z",
);

const WHITEPOINT: ParamSpec = ParamSpec::ours_or_mitsuba(
    "whitepoint",
    "d65",
    "(ours) `d65` (E × D65: a texel projects its colour) or `mitsuba` (Mitsuba 3.9.1: no D65 for a texture object or spectrum)",
);

/// The `projector` plugin.
pub static PLUGIN: Plugin<EmitterDesc> = Plugin {
    name: "projector",
    summary: "Projects a texture from a pinhole along +z of `to_world` (the reciprocal of `perspective`).",
    params: &[
        IRRADIANCE,
        SCALE,
        FOV,
        FOCAL_LENGTH,
        FOV_AXIS,
        TO_WORLD,
        WHITEPOINT,
        super::MEDIUM,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<EmitterDesc, SceneError> {
    let obj = b.object(p);
    if !obj.props.iter().any(|x| x.name == IRRADIANCE.name) {
        return Err(err(
            &obj.loc,
            ErrorKind::Grammar,
            "projector needs an \"irradiance\" texture",
        ));
    }
    // A texture object (a bitmap) is uplifted as Mitsuba's bitmap uplifts it (a reflectance-like
    // spectrum per texel); a colour given in place is unbounded (Mitsuba's values exceed 1).
    let nested = p.objects(Tag::Texture)?;
    if let Some((_, other)) = nested.iter().find(|(_, x)| x.name != IRRADIANCE.name) {
        return Err(err(
            &other.loc,
            ErrorKind::UnusedParameter,
            format!(
                "projector takes one texture, \"irradiance\"; \"{}\" is not used",
                other.name
            ),
        ));
    }
    let kind = if nested.is_empty() {
        RgbKind::Unbounded
    } else {
        RgbKind::Albedo
    };
    // Mitsuba's `texture_d65` wraps a number or an `<rgb>` given in place in D65, nothing else.
    let given_in_place = matches!(
        obj.props
            .iter()
            .find(|x| x.name == IRRADIANCE.name)
            .map(|x| &x.value),
        Some(Value::Float(_) | Value::Int(_) | Value::Rgb(_))
    );
    let mitsuba_whitepoint = p.mitsuba_way(&WHITEPOINT)?;
    let irradiance = b.texture(p, &IRRADIANCE, kind)?;
    let scale = p.float(SCALE.name, SCALE.default.float())?;
    let (w, h) = match &irradiance {
        Texture::Bitmap(bm) => (bm.width(), bm.height()),
        _ => (1, 1),
    };
    let aspect = w as f64 / h as f64;
    let fov = p.float_opt(FOV.name)?;
    let focal = p.string_opt(FOCAL_LENGTH.name)?;
    let axis = p.choice(
        FOV_AXIS.name,
        FOV_AXIS.default.str(),
        &["x", "y", "diagonal", "smaller", "larger"],
    )?;
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
            let s = f.map_or(FOCAL_LENGTH.default.str(), |(s, _)| s);
            let mm = focal_length_mm(s).ok_or_else(|| {
                err(
                    f.map_or(&obj.loc, |(_, l)| l),
                    ErrorKind::BadValue,
                    format!("invalid focal_length \"{s}\" (expected e.g. \"50mm\")"),
                )
            })?;
            fov_x_of_focal_length(mm, aspect)
        }
    };
    if !(scale.is_finite() && scale >= 0.0) {
        let loc = obj
            .props
            .iter()
            .find(|x| x.name == SCALE.name)
            .map_or(&obj.loc, |x| &x.value_loc);
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!("projector scale {scale} must be a finite number ≥ 0"),
        ));
    }
    let to_world = p.affine(TO_WORLD.name)?;
    Ok(EmitterDesc::Projector {
        to_world,
        irradiance,
        scale: scale as f32,
        fov_x_deg: fov_x as f32,
        aspect: aspect as f32,
        whitepoint: given_in_place || !mitsuba_whitepoint,
    })
}
