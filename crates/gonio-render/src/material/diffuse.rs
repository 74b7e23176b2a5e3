//! `diffuse`: the ideal diffuse (Lambertian) reflector, f = ρ/π (core model
//! [`gonio_core::bsdfs::Diffuse`]; Mitsuba 3 `src/bsdfs/diffuse.cpp`).

use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{Diffuse, LeafBsdf, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const REFLECTANCE: ParamSpec = ParamSpec::new(
    "reflectance",
    ParamType::Texture,
    DefaultValue::Float(0.5),
    "ρ, the albedo (directional and hemispherical reflectance)",
);

/// The `diffuse` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "diffuse",
    summary: "Ideal diffuse (Lambertian) reflection, f = ρ/π; one-sided (wrap it in `twosided` for back faces).",
    params: &[REFLECTANCE],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    Ok(Material::new(DiffuseMaterial::new(b.texture(
        p,
        &REFLECTANCE,
        RgbKind::Albedo,
    )?)))
}

/// `diffuse` in a scene.
#[derive(Clone, Debug)]
pub struct DiffuseMaterial {
    /// ρ.
    pub reflectance: Texture,
    /// The model (ρ's mean when textured).
    pub model: Diffuse,
}

impl DiffuseMaterial {
    /// A Lambertian material of albedo `reflectance`.
    pub fn new(reflectance: Texture) -> Self {
        let model = Diffuse::new(model_value(&reflectance));
        Self { reflectance, model }
    }
}

impl SurfaceMaterial for DiffuseMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.reflectance.is_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.reflectance, &self.reflectance, uv, wl);
        tree.push_leaf(LeafBsdf::Diffuse(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if self.reflectance.is_textured() {
            f(&Diffuse::new(self.reflectance.eval(uv)))
        } else {
            f(&self.model)
        }
    }
}
