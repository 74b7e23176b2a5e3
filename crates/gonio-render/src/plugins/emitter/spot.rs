//! `spot`: a point light restricted to a cone, with a linear falloff at its edge (Mitsuba 3
//! `src/emitters/spot.cpp`), optionally multiplied by a texture projected over the cone: the
//! local direction d (cone along +z, cutoff γ) looks up
//! uv = (½ + ½·d_x/(d_z·tan γ), ½ + ½·d_y/(d_z·tan γ)), so the texture's square spans the
//! cutoff's tangent plane.

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::EmitterDesc;
use crate::xml::{Builder, Params, SceneError};
use gonio_core::spectra::RgbKind;

const INTENSITY: ParamSpec = ParamSpec::new(
    "intensity",
    ParamType::Spectrum,
    DefaultValue::Float(1.0),
    "radiant intensity at the cone's centre, W/sr (numbers and colours × D65)",
);
const CUTOFF_ANGLE: ParamSpec = ParamSpec::new(
    "cutoff_angle",
    ParamType::Float,
    DefaultValue::Float(20.0),
    "half-angle of the cone in degrees, in (0, 90]",
);
const BEAM_WIDTH: ParamSpec = ParamSpec::new(
    "beam_width",
    ParamType::Float,
    DefaultValue::Derived("¾ · `cutoff_angle`"),
    "half-angle in degrees of the full-intensity core, in (0, `cutoff_angle`]",
);
const TEXTURE: ParamSpec = ParamSpec::new(
    "texture",
    ParamType::Texture,
    DefaultValue::None,
    "optional pattern (a reflectance-like texture) multiplying the intensity, projected over the cone",
);
const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "light to world: position, and the cone along +z",
);

/// The `spot` plugin.
pub static PLUGIN: Plugin<EmitterDesc> = Plugin {
    name: "spot",
    summary: "Spot light along +z of `to_world`: full intensity within `beam_width`, then linear in angle down to 0 at `cutoff_angle`.",
    params: &[
        INTENSITY,
        CUTOFF_ANGLE,
        BEAM_WIDTH,
        TEXTURE,
        TO_WORLD,
        super::MEDIUM,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<EmitterDesc, SceneError> {
    let intensity = b.spectrum(p, &INTENSITY, RgbKind::Illuminant)?;
    let cutoff = p.float_checked(
        CUTOFF_ANGLE.name,
        CUTOFF_ANGLE.default.float(),
        |v| v > 0.0 && v <= 90.0,
        "must be in (0, 90]",
    )?;
    let beam = p.float_checked(
        BEAM_WIDTH.name,
        cutoff * 0.75,
        |v| v > 0.0 && v <= cutoff,
        "must be in (0, cutoff_angle]",
    )?;
    let to_world = p.affine(TO_WORLD.name)?;
    let has_texture = b.object(p).props.iter().any(|x| x.name == TEXTURE.name);
    let texture = if has_texture {
        Some(b.texture(p, &TEXTURE, RgbKind::Albedo)?)
    } else {
        None
    };
    Ok(EmitterDesc::Spot {
        to_world,
        intensity,
        cutoff_angle_deg: cutoff as f32,
        beam_width_deg: beam as f32,
        texture,
    })
}
