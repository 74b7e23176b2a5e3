//! `blendbsdf`: (1 − w)·bsdf0 + w·bsdf1 with a scalar or textured weight (core adapter
//! [`gonio_core::bsdfs::BlendBsdf`]; Mitsuba 3 `src/bsdfs/blendbsdf.cpp`).

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, ShadingPoint, SurfaceMaterial};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{BlendBsdf, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const WEIGHT: ParamSpec = ParamSpec::new(
    "weight",
    ParamType::Texture,
    DefaultValue::None,
    "w in [0, 1], the share of the second BSDF (required, as in Mitsuba 3.9.1)",
);
const DELTA_PDF: ParamSpec = ParamSpec::ours_or_mitsuba(
    "delta_pdf",
    "exact",
    "(ours) a delta child's sampled outcome: `exact` (weight f_δ/P(select)) or `mitsuba` (Mitsuba 3.9.1's estimator, which adds the discrete probability to the other child's density: biased for delta + smooth mixes, for comparisons)",
);
const NESTED: ParamSpec = ParamSpec::new(
    "(nested bsdf)",
    ParamType::Bsdf,
    DefaultValue::None,
    "exactly two nested BSDFs, in document order (as Mitsuba 3.9.1 reads them, whatever their names)",
);

/// The `blendbsdf` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "blendbsdf",
    summary: "Linear blend of two BSDFs, (1 − w)·bsdf0 + w·bsdf1; the weight may be a texture.",
    params: &[WEIGHT, DELTA_PDF, NESTED],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let obj = b.object(p);
    let Some(wprop) = obj.props.iter().find(|x| x.name == WEIGHT.name) else {
        return Err(SceneError::new(
            obj.loc.clone(),
            ErrorKind::Grammar,
            "blendbsdf needs a \"weight\" (float or texture)",
        ));
    };
    let weight = b.texture(p, &WEIGHT, RgbKind::Albedo)?;
    if let Texture::Spectrum(s) = &weight {
        let w = s.as_constant().unwrap_or(f32::NAN);
        if !(0.0..=1.0).contains(&w) {
            return Err(SceneError::new(
                wprop.value_loc.clone(),
                ErrorKind::BadValue,
                format!("blendbsdf weight {w} must be a number in [0, 1]"),
            ));
        }
    }
    let mitsuba_delta_pdf = p.mitsuba_way(&DELTA_PDF)?;
    let kids = p.objects(Tag::Bsdf)?;
    if kids.len() != 2 {
        return Err(SceneError::new(
            obj.loc.clone(),
            ErrorKind::Grammar,
            format!("blendbsdf needs exactly two nested BSDFs, found {}", kids.len()),
        ));
    }
    let bsdf0 = b.bsdf(kids[0].0, &kids[0].1.value_loc)?;
    let bsdf1 = b.bsdf(kids[1].0, &kids[1].1.value_loc)?;
    Ok(Material::new(BlendMaterial {
        weight,
        bsdf0,
        bsdf1,
        mitsuba_delta_pdf,
    }))
}

/// `blendbsdf` in a scene.
#[derive(Clone, Debug)]
pub struct BlendMaterial {
    /// Weight in [0, 1], evaluated as a scalar (clamped).
    pub weight: Texture,
    /// First child.
    pub bsdf0: Material,
    /// Second child.
    pub bsdf1: Material,
    /// `delta_pdf="mitsuba"`: Mitsuba 3.9.1's estimator for delta outcomes
    /// ([`BlendBsdf::mitsuba_delta_pdf`]).
    pub mitsuba_delta_pdf: bool,
}

impl BlendMaterial {
    /// The weight at `uv`, clamped to [0, 1] (NaN counts as 0).
    fn weight_at(&self, uv: Vec2) -> f32 {
        let w = self.weight.eval_1(uv);
        if w.is_nan() { 0.0 } else { w.clamp(0.0, 1.0) }
    }
}

impl SurfaceMaterial for BlendMaterial {
    fn flags(&self) -> BsdfFlags {
        self.bsdf0.flags() | self.bsdf1.flags()
    }
    fn is_textured(&self) -> bool {
        self.weight.is_textured() || self.bsdf0.is_textured() || self.bsdf1.is_textured()
    }
    fn node_count(&self) -> usize {
        1 + self.bsdf0.as_surface().node_count() + self.bsdf1.as_surface().node_count()
    }
    fn asks_for_polarization(&self) -> bool {
        self.bsdf0.as_surface().asks_for_polarization() || self.bsdf1.as_surface().asks_for_polarization()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let a = self.bsdf0.as_surface().push(uv, wl, tree)?;
        let b = self.bsdf1.as_surface().push(uv, wl, tree)?;
        tree.push_blend_with(self.weight_at(uv), a, b, self.mitsuba_delta_pdf)
    }
    fn push_at<'a>(
        &'a self,
        at: &ShadingPoint,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let a = self.bsdf0.as_surface().push_at(at, wl, tree)?;
        let b = self.bsdf1.as_surface().push_at(at, wl, tree)?;
        tree.push_blend_with(self.weight_at(at.uv), a, b, self.mitsuba_delta_pdf)
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        let w = self.weight_at(uv);
        self.bsdf0.as_surface().visit(uv, &mut |b0: &dyn Bsdf| {
            self.bsdf1.as_surface().visit(uv, &mut |b1: &dyn Bsdf| {
                f(&BlendBsdf::new(w, b0, b1).with_mitsuba_delta_pdf(self.mitsuba_delta_pdf))
            })
        })
    }
}
