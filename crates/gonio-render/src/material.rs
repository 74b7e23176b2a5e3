//! Materials as the scene describes them, and the per-hit construction of the core BSDF model
//! (textures evaluated at the hit's uv).

use crate::texture::Texture;
use gonio_core::{Ior, Spectrum};

/// A surface material: one of Mitsuba's BSDF plugins with its parameters (textures unevaluated).
#[derive(Clone, Debug)]
pub enum Material {
    /// `diffuse` (reflectance, default 0.5).
    Diffuse {
        /// ρ.
        reflectance: Texture,
    },
    /// `conductor`: smooth metal from complex IOR η + ik (default `material="none"`: a perfect
    /// mirror, η = 0, k = 1).
    Conductor {
        /// Real part of the metal's index.
        eta: Spectrum,
        /// Imaginary part (absorption).
        k: Spectrum,
        /// Ours: index of the medium outside (Mitsuba has none; default 1).
        ext_ior: Ior,
        /// Multiplier, default 1.
        specular_reflectance: Texture,
    },
    /// `dielectric`: smooth interface between two media.
    Dielectric {
        /// Interior index (default bk7 = 1.5046), possibly dispersive.
        int_ior: Ior,
        /// Exterior index (default air = 1.000277), possibly dispersive.
        ext_ior: Ior,
        /// Multiplier on reflection, default 1.
        specular_reflectance: Texture,
        /// Multiplier on transmission, default 1.
        specular_transmittance: Texture,
    },
    /// `thindielectric`: a thin sheet, light passes straight through.
    ThinDielectric {
        /// Interior index (default bk7).
        int_ior: Ior,
        /// Exterior index (default air).
        ext_ior: Ior,
        /// Multiplier on reflection, default 1.
        specular_reflectance: Texture,
        /// Multiplier on transmission, default 1.
        specular_transmittance: Texture,
    },
    /// `plastic`: diffuse base under a smooth dielectric coating.
    Plastic {
        /// Base reflectance, default 0.5.
        diffuse_reflectance: Texture,
        /// Coating reflectance multiplier, default 1.
        specular_reflectance: Texture,
        /// Coating index (default polypropylene 1.49).
        int_ior: f32,
        /// Outside index (default air 1.000277).
        ext_ior: f32,
        /// Account for the colour shift of inner scattering (default false).
        nonlinear: bool,
    },
    /// `twosided`: `front` on both sides, or `front`/`back`.
    TwoSided {
        /// Front (and back if `back` is none).
        front: Box<Material>,
        /// Back side, if different.
        back: Option<Box<Material>>,
    },
    /// `blendbsdf`: (1 − weight)·bsdf0 + weight·bsdf1.
    Blend {
        /// Weight in [0, 1] (default 0.5), evaluated as a scalar.
        weight: Texture,
        /// First child.
        bsdf0: Box<Material>,
        /// Second child.
        bsdf1: Box<Material>,
    },
}

impl Material {
    /// Mitsuba's default material for a shape without a BSDF: diffuse with ρ = 0.5, or ρ = 0 if
    /// the shape emits.
    pub fn default_for_shape(emitter: bool) -> Self {
        Material::Diffuse {
            reflectance: Texture::constant(if emitter { 0.0 } else { 0.5 }),
        }
    }
}
