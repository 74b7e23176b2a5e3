//! `thindielectric`: a thin dielectric sheet, Stokes-summed delta reflection and straight-through transmission (core model [`gonio_core::bsdfs::ThinDielectric`]; Mitsuba 3 `src/bsdfs/thindielectric.cpp`).

use super::dielectric::{EXT_IOR, INT_IOR, SPECULAR_REFLECTANCE, SPECULAR_TRANSMITTANCE, interface};
use super::{BsdfPlugin, Material, SurfaceMaterial, model_value, retint_at, retinted};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, SurfaceBsdf, ThinDielectric};
use gonio_core::{Bsdf, BsdfFlags, Ior, SampledWavelengths};

/// The `thindielectric` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "thindielectric",
    summary: "Thin dielectric sheet (a window pane): the Stokes sums of the slab's inter-reflections; light passes straight through.",
    params: &[INT_IOR, EXT_IOR, SPECULAR_REFLECTANCE, SPECULAR_TRANSMITTANCE],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let (int_ior, ext_ior, r, t) = interface(b, p)?;
    Ok(Material::new(ThinDielectricMaterial::new(int_ior, ext_ior, r, t)))
}

/// `thindielectric` in a scene.
#[derive(Clone, Debug)]
pub struct ThinDielectricMaterial {
    /// Multiplier on reflection, default 1.
    pub specular_reflectance: Texture,
    /// Multiplier on transmission, default 1.
    pub specular_transmittance: Texture,
    /// The model (untextured parameters).
    pub model: ThinDielectric,
}

impl ThinDielectricMaterial {
    /// The material between `int_ior` and `ext_ior` with its tints.
    pub fn new(
        int_ior: Ior,
        ext_ior: Ior,
        specular_reflectance: Texture,
        specular_transmittance: Texture,
    ) -> Self {
        let model = ThinDielectric {
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

impl SurfaceMaterial for ThinDielectricMaterial {
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
        tree.push_leaf(LeafBsdf::ThinDielectric(m))
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
