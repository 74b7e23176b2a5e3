//! `polarizer`: an ideal linear polarizer that light crosses without deviation (core model
//! [`gonio_core::bsdfs::Polarizer`]; Mitsuba 3 `src/bsdfs/polarizer.cpp`). Unpolarized renders
//! see a filter of transmittance t/2.

use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, Polarizer, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

pub(crate) const THETA: ParamSpec = ParamSpec::new(
    "theta",
    ParamType::Float,
    DefaultValue::Float(0.0),
    "angle of the transmission (polarizer) or fast (retarder) axis, degrees (a constant here)",
);
pub(crate) const TRANSMITTANCE: ParamSpec = ParamSpec::new(
    "transmittance",
    ParamType::Texture,
    DefaultValue::Float(1.0),
    "t, the transmittance of the transmitted component",
);
const POLARIZING: ParamSpec = ParamSpec::new(
    "polarizing",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "false: a non-polarizing absorber of t/2",
);

/// The `polarizer` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "polarizer",
    summary: "Ideal linear polarizer, light passes straight through (unpolarized renders: a filter of t/2).",
    params: &[THETA, TRANSMITTANCE, POLARIZING],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let theta = p.float_checked(
        THETA.name,
        THETA.default.float(),
        f64::is_finite,
        "a finite angle",
    )? as f32;
    let transmittance = b.texture(p, &TRANSMITTANCE, RgbKind::Albedo)?;
    let polarizing = p.bool(POLARIZING.name, POLARIZING.default.bool())?;
    let model = Polarizer {
        theta,
        transmittance: model_value(&transmittance),
        polarizing,
    };
    Ok(Material::new(PolarizerMaterial { transmittance, model }))
}

/// `polarizer` in a scene.
#[derive(Clone, Debug)]
pub struct PolarizerMaterial {
    /// t.
    pub transmittance: Texture,
    /// The model (t's mean when textured).
    pub model: Polarizer,
}

impl SurfaceMaterial for PolarizerMaterial {
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
        tree.push_leaf(LeafBsdf::Polarizer(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if self.transmittance.is_textured() {
            f(&Polarizer {
                transmittance: self.transmittance.eval(uv),
                ..self.model.clone()
            })
        } else {
            f(&self.model)
        }
    }
}
