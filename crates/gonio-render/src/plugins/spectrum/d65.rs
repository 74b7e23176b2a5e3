//! `d65`: the CIE standard illuminant D65 (Mitsuba 3 `src/spectra/d65.cpp`).

use super::{SCALE, scale};
use crate::plugins::Plugin;
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};
use gonio_core::spectra::Spectrum;

/// The `d65` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "d65",
    summary: "CIE illuminant D65 (the white of sRGB), times `scale`.",
    params: &[SCALE],
    build,
};

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let scale = scale(p)?;
    Ok(Texture::Spectrum(Spectrum::rgb_illuminant([scale as f32; 3])))
}
