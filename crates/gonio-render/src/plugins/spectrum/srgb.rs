//! `srgb`: a reflectance given as a linear sRGB colour, uplifted to a smooth spectrum (Mitsuba 3
//! `src/spectra/srgb.cpp`; Jakob and Hanika 2019, [`gonio_core::Spectrum::rgb_albedo`]). The same
//! spectrum as `<rgb name="reflectance" value="…"/>`.
//!
//! | parameter | type | default |
//! |---|---|---|
//! | `color` | rgb | required: each component in [0, 1] (unless `unbounded`) |
//! | `unbounded` | boolean | false: true accepts components above 1, fitted as the colour
//! clamped to [0, 1] (what Mitsuba 3.9.1 does with them) |

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use gonio_core::spectra::Spectrum;

const COLOR: ParamSpec = ParamSpec::new(
    "color",
    ParamType::Rgb,
    DefaultValue::None,
    "linear sRGB reflectance (required; each component in [0, 1])",
);

const UNBOUNDED: ParamSpec = ParamSpec::new(
    "unbounded",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "accept components above 1, fitted as the colour clamped to [0, 1] (as Mitsuba 3.9.1 does)",
);

/// The `srgb` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "srgb",
    summary: "A linear sRGB reflectance `color` as a smooth spectrum (Jakob and Hanika's uplift).",
    params: &[COLOR, UNBOUNDED],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let Some((c, loc)) = p.rgb_opt(COLOR.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "<spectrum type=\"srgb\"> needs a color",
        ));
    };
    let unbounded = p.bool(UNBOUNDED.name, UNBOUNDED.default.bool())?;
    let top = if unbounded { f64::MAX } else { 1.0 };
    if !c
        .iter()
        .all(|v| (0.0..=top).contains(v) && (*v as f32).is_finite())
    {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "invalid color ({}, {}, {}) (a reflectance: each component in [0, 1], or finite and non-negative with unbounded)",
                c[0], c[1], c[2]
            ),
        ));
    }
    Ok(Texture::Spectrum(Spectrum::rgb_albedo(c.map(|v| v as f32))))
}
