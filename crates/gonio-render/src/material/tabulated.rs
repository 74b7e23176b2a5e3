//! `tabulated` (ours): a measured isotropic BRDF table played back, as written by
//! `gonio measure` (core model [`gonio_core::bsdfs::Tabulated`]; format in `docs/instruments.md`).

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, TableMaterial, TableModel};
use crate::xml::{Builder, Params, SceneError};
use gonio_core::bsdfs::{LeafBsdf, Tabulated};
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
    Ok(Material::new(TableMaterial {
        model: Arc::new(Tabulated::new(data)),
    }))
}

/// `tabulated` in a scene.
pub type TabulatedMaterial = TableMaterial<Tabulated>;

impl TableModel for Tabulated {
    fn leaf(&self) -> LeafBsdf<'_> {
        LeafBsdf::Tabulated(self)
    }
}
