//! `<spectrum type="...">` plugins (Mitsuba 3 `src/spectra/`): spectra that do not vary over a
//! surface, usable wherever a spectrum or texture is (as [`crate::texture::Texture::Spectrum`]).

pub mod blackbody;
pub mod d65;
pub mod uniform;

use crate::plugins::{DefaultValue, ParamSpec, ParamType};
use crate::xml::{Params, SceneError};

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
