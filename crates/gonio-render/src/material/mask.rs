//! `mask`: an opacity mask over a nested BSDF (Mitsuba 3 `src/bsdfs/mask.cpp`),
//!
//! ```text
//!     f = α·f_nested + (1 − α)·δ(ωo + ωi)/|cos θo|,      null transmittance 1 − α·(1 − T_nested)
//! ```
//!
//! with α = clamp(opacity, 0, 1) at the hit (1 = opaque). This is a `blendbsdf` of weight 1 − α
//! between the nested BSDF and `null` ([`gonio_core::bsdfs::NullBsdf`]), and it is built as one
//! in the per-hit tree: sampling passes straight through with probability 1 − α (weight 1) and
//! samples the nested BSDF otherwise; eval and pdf are α times the nested ones.
//!
//! | parameter       | type              | default |
//! |-----------------|-------------------|---------|
//! | `opacity`       | float or texture  | 0.5     |
//! | (nested plugin) | bsdf              | required, exactly one |

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, ShadingPoint, SurfaceMaterial};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{BlendBsdf, LeafBsdf, NullBsdf, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const OPACITY: ParamSpec = ParamSpec::new(
    "opacity",
    ParamType::Texture,
    DefaultValue::Float(0.5),
    "α, the opacity (1 = opaque; clamped to [0, 1]), a float or a texture read as one value",
);
const NESTED: ParamSpec = ParamSpec::new(
    "(nested bsdf)",
    ParamType::Bsdf,
    DefaultValue::None,
    "exactly one nested BSDF, the opaque part",
);

/// The `mask` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "mask",
    summary: "Opacity mask: α·nested BSDF + (1 − α)·pass-through; α may be a texture (a cut-out leaf).",
    params: &[OPACITY, NESTED],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let opacity = b.texture(p, &OPACITY, RgbKind::Albedo)?;
    let kids = p.objects(Tag::Bsdf)?;
    let obj = b.object(p);
    match kids.len() {
        0 => {
            return Err(SceneError::new(
                obj.loc.clone(),
                ErrorKind::Grammar,
                "mask needs a nested BSDF (the opaque part), found none",
            ));
        }
        1 => {}
        n => {
            return Err(SceneError::new(
                kids[1].1.loc.clone(),
                ErrorKind::Grammar,
                format!("mask takes exactly one nested BSDF, found {n}"),
            ));
        }
    }
    let nested = b.bsdf(kids[0].0, &kids[0].1.value_loc)?;
    Ok(Material::new(MaskMaterial { opacity, nested }))
}

/// `mask` in a scene.
#[derive(Clone, Debug)]
pub struct MaskMaterial {
    /// α (evaluated as one value, clamped to [0, 1]).
    pub opacity: Texture,
    /// The opaque part.
    pub nested: Material,
}

impl MaskMaterial {
    /// α at `uv`, clamped to [0, 1] (NaN counts as 0, transparent).
    pub fn opacity_at(&self, uv: Vec2) -> f32 {
        let a = self.opacity.eval_1(uv);
        if a.is_nan() { 0.0 } else { a.clamp(0.0, 1.0) }
    }
}

impl SurfaceMaterial for MaskMaterial {
    fn flags(&self) -> BsdfFlags {
        self.nested.flags() | NullBsdf::FLAGS
    }
    fn is_textured(&self) -> bool {
        self.opacity.is_textured() || self.nested.is_textured()
    }
    fn node_count(&self) -> usize {
        2 + self.nested.as_surface().node_count()
    }
    fn asks_for_polarization(&self) -> bool {
        self.nested.as_surface().asks_for_polarization()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let nested = self.nested.as_surface().push(uv, wl, tree)?;
        let null = tree.push_leaf(LeafBsdf::Null(NullBsdf))?;
        tree.push_blend(1.0 - self.opacity_at(uv), nested, null)
    }
    fn push_at<'a>(
        &'a self,
        at: &ShadingPoint,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let nested = self.nested.as_surface().push_at(at, wl, tree)?;
        let null = tree.push_leaf(LeafBsdf::Null(NullBsdf))?;
        tree.push_blend(1.0 - self.opacity_at(at.uv), nested, null)
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        let w = 1.0 - self.opacity_at(uv);
        self.nested
            .as_surface()
            .visit(uv, &mut |b: &dyn Bsdf| f(&BlendBsdf::new(w, b, &NullBsdf)))
    }
}
