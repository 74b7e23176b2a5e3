//! `retarder`: an ideal linear retarder (wave plate) that light crosses without deviation (core
//! model [`gonio_core::bsdfs::Retarder`]; Mitsuba 3 `src/bsdfs/retarder.cpp`). Unpolarized
//! renders see a clear filter of transmittance t.

use super::polarizer::{THETA, TRANSMITTANCE, angle};
use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, Retarder, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const DELTA: ParamSpec = ParamSpec::new(
    "delta",
    ParamType::Texture,
    DefaultValue::Float(90.0),
    "phase difference between the fast and slow axes at normal incidence, degrees (90: quarter-wave plate; a number, a constant spectrum or a texture); falls off with |cos θi|",
);

/// The `retarder` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "retarder",
    summary: "Ideal linear retarder (wave plate), light passes straight through (unpolarized renders: a filter of t).",
    params: &[THETA, DELTA, TRANSMITTANCE],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let theta = angle(b, p, &THETA)?;
    let delta = angle(b, p, &DELTA)?;
    let transmittance = b.texture(p, &TRANSMITTANCE, RgbKind::Albedo)?;
    let model = Retarder {
        transmittance: model_value(&transmittance),
        ..Retarder::new(theta.eval_1(Vec2::ZERO), delta.eval_1(Vec2::ZERO))
    };
    Ok(Material::new(RetarderMaterial {
        transmittance,
        theta,
        delta,
        model,
    }))
}

/// `retarder` in a scene.
#[derive(Clone, Debug)]
pub struct RetarderMaterial {
    /// t.
    pub transmittance: Texture,
    /// θ, degrees.
    pub theta: Texture,
    /// δ, degrees.
    pub delta: Texture,
    /// The model (t's mean when textured; θ and δ at uv = 0 when textured).
    pub model: Retarder,
}

impl SurfaceMaterial for RetarderMaterial {
    fn asks_for_polarization(&self) -> bool {
        true
    }
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.transmittance.is_textured() || self.theta.is_textured() || self.delta.is_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.transmittance, &self.transmittance, uv, wl);
        if self.theta.is_textured() {
            m.theta = self.theta.eval_1(uv);
        }
        if self.delta.is_textured() {
            m.delta = self.delta.eval_1(uv);
        }
        tree.push_leaf(LeafBsdf::Retarder(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if self.is_textured() {
            f(&Retarder {
                transmittance: self.transmittance.eval(uv),
                theta: self.theta.eval_1(uv),
                delta: self.delta.eval_1(uv),
            })
        } else {
            f(&self.model)
        }
    }
}
