//! `d65`: the CIE standard illuminant D65 (Mitsuba 3 `src/spectra/d65.cpp`), optionally tinted by
//! a colour: D65(λ)·s(λ) with s the colour's spectral uplift, D65 of unit luminance, so that
//! white renders as linear sRGB (1, 1, 1) (Mitsuba's RGB emitters are this spectrum).
//!
//! | parameter | type | default |
//! |---|---|---|
//! | `color` | rgb | white (1, 1, 1) |
//! | `scale` | float | 1 |

use super::{SCALE, scale};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use gonio_core::spectra::Spectrum;

const COLOR: ParamSpec = ParamSpec::new(
    "color",
    ParamType::Rgb,
    DefaultValue::Float(1.0),
    "linear sRGB tint of the illuminant (finite, non-negative; above 1 allowed)",
);

/// The `d65` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "d65",
    summary: "CIE illuminant D65 (the white of sRGB) tinted by `color`, times `scale`.",
    params: &[COLOR, SCALE],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let color = match p.rgb_opt(COLOR.name)? {
        None => [COLOR.default.float(); 3],
        Some((c, loc)) => {
            if !c.iter().all(|v| (*v as f32).is_finite() && *v >= 0.0) {
                return Err(err(
                    loc,
                    ErrorKind::BadValue,
                    format!(
                        "invalid color ({}, {}, {}) (finite, non-negative components)",
                        c[0], c[1], c[2]
                    ),
                ));
            }
            c
        }
    };
    let scale = scale(p)?;
    let tinted = color.map(|v| (v * scale) as f32);
    if !tinted.iter().all(|v| v.is_finite()) {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            format!("color × scale {scale} is beyond single precision"),
        ));
    }
    Ok(Texture::Spectrum(Spectrum::rgb_illuminant(tinted)))
}
