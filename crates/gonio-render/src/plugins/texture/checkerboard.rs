//! `checkerboard`: two alternating values on a 2 × 2 grid of uv squares (Mitsuba 3
//! `src/textures/checkerboard.cpp`).
//!
//! Mitsuba 3.9.1 looks a checkerboard up as a float (`eval_1`: a roughness, a blend weight, an
//! opacity, a `principled` parameter) with `color0` and `color1` exchanged against its colour
//! lookup (`eval`). gonio shows one pattern to both; `float_cells="mitsuba"` (the default under
//! `--mitsuba-estimators`) restores Mitsuba's exchange, so that its scenes render as in Mitsuba.

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};

const COLOR0: ParamSpec = ParamSpec::new(
    "color0",
    ParamType::Texture,
    DefaultValue::Float(0.4),
    "value on the uv squares [0, ½)² and [½, 1)² (and their repeats)",
);
const COLOR1: ParamSpec = ParamSpec::new(
    "color1",
    ParamType::Texture,
    DefaultValue::Float(0.2),
    "value of the other squares",
);
const FLOAT_CELLS: ParamSpec = ParamSpec::ours_or_mitsuba(
    "float_cells",
    "same",
    "(ours) the cells a float lookup (a roughness, a blend weight, an opacity, a `principled` parameter) sees: `same` (those of the colour lookup) or `mitsuba` (Mitsuba 3.9.1, whose `eval_1` exchanges `color0` and `color1`)",
);
const TO_UV: ParamSpec = ParamSpec::new(
    "to_uv",
    ParamType::Transform,
    DefaultValue::None,
    "transform of the texture coordinates (rows and columns 0, 1, 3 of the 4 × 4)",
);

/// The `checkerboard` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "checkerboard",
    summary: "Checkerboard: `color0` and `color1` alternating over the uv square.",
    params: &[COLOR0, COLOR1, TO_UV, FLOAT_CELLS],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let role = b.role();
    let color0 = b.texture(p, &COLOR0, role)?;
    let color1 = b.texture(p, &COLOR1, role)?;
    let to_uv = p.to_uv()?;
    let float_cells_swapped = p.mitsuba_way(&FLOAT_CELLS)?;
    Ok(Texture::Checkerboard {
        color0: Box::new(color0),
        color1: Box::new(color1),
        to_uv,
        float_cells_swapped,
    })
}
