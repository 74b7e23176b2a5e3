//! `tabulated` (ours): a measured isotropic BRDF table played back, as written by
//! `gonio measure` (core model [`gonio_core::bsdfs::Tabulated`]; format in `docs/instruments.md`).

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial};
use crate::xml::{Builder, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, SurfaceBsdf, Tabulated};
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};
use std::sync::Arc;

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the table (required), relative to the scene file or a `<path>` folder",
);

/// The `tabulated` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "tabulated",
    summary: "(ours) A measured isotropic BRDF table, interpolated, made reciprocal and importance-sampled.",
    params: &[FILENAME],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let data = super::read_filename(b, p, PLUGIN.name, crate::tabulated_io::read_tabulated)?;
    Ok(Material::new(TabulatedMaterial {
        model: Arc::new(Tabulated::new(data)),
    }))
}

/// `tabulated` in a scene.
#[derive(Clone, Debug)]
pub struct TabulatedMaterial {
    /// The interpolated, reciprocity-enforced, importance-sampled table.
    pub model: Arc<Tabulated>,
}

impl SurfaceMaterial for TabulatedMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        false
    }
    fn push<'a>(
        &'a self,
        _uv: Vec2,
        _wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        tree.push_leaf(LeafBsdf::Tabulated(&self.model))
    }
    fn visit(&self, _uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        f(self.model.as_ref())
    }
}
