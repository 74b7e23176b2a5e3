//! Textures: spatially varying spectra (`checkerboard`, `bitmap`) and constants, evaluated at a
//! surface's uv.

use glam::Affine2;
use gonio_core::Spectrum;
use std::sync::Arc;

/// A reflectance or radiance that may vary over a surface.
#[derive(Clone, Debug)]
pub enum Texture {
    /// The same spectrum everywhere.
    Spectrum(Spectrum),
    /// Mitsuba `checkerboard`: `color0` where (u mod 1 > ½) == (v mod 1 > ½), else `color1`.
    Checkerboard {
        /// Default 0.4.
        color0: Box<Texture>,
        /// Default 0.2.
        color1: Box<Texture>,
        /// uv transform applied before the lookup.
        to_uv: Affine2,
    },
    /// Mitsuba `bitmap`.
    Bitmap(Arc<Bitmap>),
}

/// Texel lookup for [`Bitmap`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterType {
    /// Bilinear interpolation (default).
    Bilinear,
    /// Nearest texel.
    Nearest,
}

/// What happens outside [0, 1]².
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrapMode {
    /// Tile (default).
    Repeat,
    /// Tile, mirroring every other copy.
    Mirror,
    /// Clamp to the edge texel.
    Clamp,
}

/// A decoded bitmap texture: linear RGB texels (row 0 at the top, v = 1 − y as in Mitsuba).
#[derive(Clone, Debug)]
pub struct Bitmap {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Linear RGB texels, row-major, top row first.
    pub rgb: Vec<[f32; 3]>,
    /// Interpolation.
    pub filter: FilterType,
    /// Wrapping.
    pub wrap: WrapMode,
    /// `raw`: values are used as they are (no sRGB decoding at load; uplifted as unbounded).
    pub raw: bool,
    /// uv transform applied before the lookup.
    pub to_uv: Affine2,
}

impl Texture {
    /// A constant texture.
    pub fn constant(v: f32) -> Self {
        Texture::Spectrum(Spectrum::Constant(v))
    }

    /// The constant spectrum, if the texture does not vary over the surface.
    pub fn as_spectrum(&self) -> Option<&Spectrum> {
        match self {
            Texture::Spectrum(s) => Some(s),
            _ => None,
        }
    }

    /// True when the texture varies over the surface.
    pub fn is_textured(&self) -> bool {
        !matches!(self, Texture::Spectrum(_))
    }
}
