//! `circular`: an ideal circular polarizer that light crosses without deviation (core model
//! [`gonio_core::bsdfs::CircularPolarizer`]; Mitsuba 3 `src/bsdfs/circular.cpp`). Unpolarized
//! renders see a filter of transmittance t/2.

use super::polarizer::TRANSMITTANCE;
use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{CircularPolarizer, LeafBsdf, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const LEFT_HANDED: ParamSpec = ParamSpec::new(
    "left_handed",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "true: a left circular polarizer; false: right",
);

/// The `circular` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "circular",
    summary: "Ideal circular polarizer, light passes straight through (unpolarized renders: a filter of t/2).",
    params: &[TRANSMITTANCE, LEFT_HANDED],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let transmittance = b.texture(p, &TRANSMITTANCE, RgbKind::Albedo)?;
    let left_handed = p.bool(LEFT_HANDED.name, LEFT_HANDED.default.bool())?;
    let model = CircularPolarizer {
        transmittance: model_value(&transmittance),
        left_handed,
    };
    Ok(Material::new(CircularMaterial { transmittance, model }))
}

/// `circular` in a scene.
#[derive(Clone, Debug)]
pub struct CircularMaterial {
    /// t.
    pub transmittance: Texture,
    /// The model (t's mean when textured).
    pub model: CircularPolarizer,
}

impl SurfaceMaterial for CircularMaterial {
    fn asks_for_polarization(&self) -> bool {
        true
    }
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.transmittance.is_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.transmittance, &self.transmittance, uv, wl);
        tree.push_leaf(LeafBsdf::CircularPolarizer(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if self.transmittance.is_textured() {
            f(&CircularPolarizer {
                transmittance: self.transmittance.eval(uv),
                ..self.model.clone()
            })
        } else {
            f(&self.model)
        }
    }
}
