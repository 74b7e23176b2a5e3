//! `dielectric`: a smooth dielectric interface, Fresnel-weighted delta reflection and refraction (core model [`gonio_core::bsdfs::Dielectric`]; Mitsuba 3 `src/bsdfs/dielectric.cpp`).

use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
    retinted,
};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{Dielectric, LeafBsdf, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, Ior, SampledWavelengths};

pub(super) const INT_IOR: ParamSpec = ParamSpec::new(
    "int_ior",
    ParamType::Ior,
    DefaultValue::Str("bk7"),
    "interior index: a number, a named material, or (ours) a dispersive glass (`SF11`, `N-BK7`, ...) or a spectrum",
);
pub(super) const EXT_IOR: ParamSpec = ParamSpec::new(
    "ext_ior",
    ParamType::Ior,
    DefaultValue::Str("air"),
    "exterior index, as `int_ior`",
);
pub(super) const SPECULAR_REFLECTANCE: ParamSpec = ParamSpec::new(
    "specular_reflectance",
    ParamType::Texture,
    DefaultValue::Float(1.0),
    "tint of the reflection (not physical)",
);
pub(super) const SPECULAR_TRANSMITTANCE: ParamSpec = ParamSpec::new(
    "specular_transmittance",
    ParamType::Texture,
    DefaultValue::Float(1.0),
    "tint of the transmission (not physical)",
);

/// The `dielectric` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "dielectric",
    summary: "Smooth dielectric interface (glass, water): Fresnel-weighted mirror reflection and refraction; dispersive indices (ours) terminate the secondary wavelengths.",
    params: &[INT_IOR, EXT_IOR, SPECULAR_REFLECTANCE, SPECULAR_TRANSMITTANCE],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let (int_ior, ext_ior, r, t) = interface(b, p)?;
    Ok(Material::new(DielectricMaterial::new(int_ior, ext_ior, r, t)))
}

/// The parameters `dielectric` and `thindielectric` share: interior and exterior indices, tints.
pub(super) fn interface<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
) -> Result<(Ior, Ior, Texture, Texture), SceneError> {
    Ok((
        b.ior(p, &INT_IOR)?,
        b.ior(p, &EXT_IOR)?,
        b.texture(p, &SPECULAR_REFLECTANCE, RgbKind::Albedo)?,
        b.texture(p, &SPECULAR_TRANSMITTANCE, RgbKind::Albedo)?,
    ))
}

/// `dielectric` in a scene.
#[derive(Clone, Debug)]
pub struct DielectricMaterial {
    /// Multiplier on reflection, default 1.
    pub specular_reflectance: Texture,
    /// Multiplier on transmission, default 1.
    pub specular_transmittance: Texture,
    /// The model (untextured parameters).
    pub model: Dielectric,
}

impl DielectricMaterial {
    /// The material between `int_ior` and `ext_ior` with its tints.
    pub fn new(
        int_ior: Ior,
        ext_ior: Ior,
        specular_reflectance: Texture,
        specular_transmittance: Texture,
    ) -> Self {
        let model = Dielectric {
            int_ior,
            ext_ior,
            specular_reflectance: model_value(&specular_reflectance),
            specular_transmittance: model_value(&specular_transmittance),
        };
        Self {
            specular_reflectance,
            specular_transmittance,
            model,
        }
    }
}

impl SurfaceMaterial for DielectricMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.specular_reflectance.is_textured() || self.specular_transmittance.is_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.specular_reflectance, &self.specular_reflectance, uv, wl);
        retint_at(
            &mut m.specular_transmittance,
            &self.specular_transmittance,
            uv,
            wl,
        );
        tree.push_leaf(LeafBsdf::Dielectric(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        let (r, t) = (&self.specular_reflectance, &self.specular_transmittance);
        retinted(
            &self.model,
            r.is_textured() || t.is_textured(),
            |m| (m.specular_reflectance, m.specular_transmittance) = (r.eval(uv), t.eval(uv)),
            f,
        )
    }
}
