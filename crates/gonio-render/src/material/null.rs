//! `null`: a surface invisible to light, every ray passing straight through (core model
//! [`gonio_core::bsdfs::NullBsdf`]; Mitsuba 3 `src/bsdfs/null.cpp`). No parameters.
//!
//! The path tracer crosses it as it crosses a thin sheet (a `NULL` lobe): with `thin_shadows`
//! (the default) the crossing is no path vertex and shadow rays pass it with transmittance 1;
//! without, it is a delta vertex and blocks shadow rays, as in Mitsuba's `path` integrator.

use super::{BsdfPlugin, Material, SurfaceMaterial};
use crate::xml::{Builder, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, NullBsdf, SurfaceBsdf};
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

/// The `null` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "null",
    summary: "Pass-through: light continues unchanged (an emitter with no surface, an invisible shape).",
    params: &[],
    build,
};

fn build<'d>(_b: &mut Builder<'d>, _p: &mut Params<'d>) -> Result<Material, SceneError> {
    Ok(Material::new(NullMaterial))
}

/// `null` in a scene.
#[derive(Clone, Copy, Debug, Default)]
pub struct NullMaterial;

impl SurfaceMaterial for NullMaterial {
    fn flags(&self) -> BsdfFlags {
        NullBsdf::FLAGS
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
        tree.push_leaf(LeafBsdf::Null(NullBsdf))
    }
    fn visit(&self, _uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        f(&NullBsdf)
    }
}
