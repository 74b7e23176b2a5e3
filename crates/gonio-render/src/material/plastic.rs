//! `plastic`: a Lambertian base under a smooth dielectric coat (core model
//! [`gonio_core::bsdfs::Plastic`]; Mitsuba 3 `src/bsdfs/plastic.cpp`). Addition over Mitsuba:
//! `coat_averages` (`exact`, gonio's default, or `mitsuba`: Mitsuba 3.9.1's fits of r̃, whose
//! albedo at ρ = 1 exceeds 1, for comparisons).

use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
    retinted,
};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{CoatAverages, LeafBsdf, Plastic, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, Ior, SampledWavelengths};

pub(crate) const DIFFUSE_REFLECTANCE: ParamSpec = ParamSpec::new(
    "diffuse_reflectance",
    ParamType::Texture,
    DefaultValue::Float(0.5),
    "ρ, the albedo of the base",
);
pub(crate) const NONLINEAR: ParamSpec = ParamSpec::new(
    "nonlinear",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "true: the physical series of internal reflections 1/(1 − ρ r̃) (colours saturate); false: 1/(1 − r̃)",
);
pub(crate) const INT_IOR: ParamSpec = ParamSpec::new(
    "int_ior",
    ParamType::Ior,
    DefaultValue::Str("polypropylene"),
    "index of the coat (a number or a named material; not dispersive)",
);
pub(crate) const EXT_IOR: ParamSpec = ParamSpec::new(
    "ext_ior",
    ParamType::Ior,
    DefaultValue::Str("air"),
    "exterior index",
);
pub(crate) const SPECULAR_REFLECTANCE: ParamSpec = ParamSpec::new(
    "specular_reflectance",
    ParamType::Texture,
    DefaultValue::Float(1.0),
    "tint of the coat's reflection (not physical)",
);

const COAT_AVERAGES: ParamSpec = ParamSpec::ours_or_mitsuba(
    "coat_averages",
    "exact",
    "(ours) the coat's internal and external diffuse reflectances r̃: `exact` (energy ≤ 1) or `mitsuba` (Mitsuba 3.9.1's polynomial fits, whose albedo at ρ = 1 exceeds 1)",
);

/// The `plastic` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "plastic",
    summary: "Coated diffuse: a Lambertian base under a smooth dielectric coat, with the internal reflections between them.",
    params: &[
        DIFFUSE_REFLECTANCE,
        NONLINEAR,
        INT_IOR,
        EXT_IOR,
        SPECULAR_REFLECTANCE,
        COAT_AVERAGES,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let d = b.texture(p, &DIFFUSE_REFLECTANCE, RgbKind::Albedo)?;
    let nonlinear = p.bool(NONLINEAR.name, NONLINEAR.default.bool())?;
    let int_ior = constant_ior(b, p, &INT_IOR, "plastic")?;
    let ext_ior = constant_ior(b, p, &EXT_IOR, "plastic")?;
    let s = b.texture(p, &SPECULAR_REFLECTANCE, RgbKind::Albedo)?;
    let mut m = PlasticMaterial::new(d, int_ior, ext_ior, nonlinear, s);
    if p.mitsuba_way(&COAT_AVERAGES)? {
        m.model = m.model.with_coat_averages(CoatAverages::Mitsuba);
    }
    Ok(Material::new(m))
}

/// An index that must not be dispersive (the coat's r̃ is precomputed once); `plugin` names the
/// plugin in the error.
pub(crate) fn constant_ior<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    spec: &ParamSpec,
    plugin: &str,
) -> Result<f32, SceneError> {
    match b.ior(p, spec)? {
        Ior::Constant(v) => Ok(v),
        Ior::Dispersive(_) => {
            let obj = b.object(p);
            let loc = obj
                .props
                .iter()
                .find(|x| x.name == spec.name)
                .map_or(&obj.loc, |x| &x.value_loc);
            Err(SceneError::new(
                loc.clone(),
                ErrorKind::BadValue,
                format!("{plugin} needs a constant {}, not a dispersive one", spec.name),
            ))
        }
    }
}

/// `plastic` in a scene.
#[derive(Clone, Debug)]
pub struct PlasticMaterial {
    /// Base reflectance, default 0.5.
    pub diffuse_reflectance: Texture,
    /// Coating reflectance multiplier, default 1.
    pub specular_reflectance: Texture,
    /// The model, precomputed with the texture means (indices, `nonlinear`, Fdr, weights).
    pub model: Plastic,
}

impl PlasticMaterial {
    /// The material; the specular sampling weight uses the texture means (Mitsuba).
    pub fn new(
        diffuse_reflectance: Texture,
        int_ior: f32,
        ext_ior: f32,
        nonlinear: bool,
        specular_reflectance: Texture,
    ) -> Self {
        let model = Plastic::new(
            model_value(&diffuse_reflectance),
            int_ior,
            ext_ior,
            nonlinear,
            model_value(&specular_reflectance),
        );
        Self {
            diffuse_reflectance,
            specular_reflectance,
            model,
        }
    }
}

impl SurfaceMaterial for PlasticMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.diffuse_reflectance.is_textured() || self.specular_reflectance.is_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.diffuse_reflectance, &self.diffuse_reflectance, uv, wl);
        retint_at(&mut m.specular_reflectance, &self.specular_reflectance, uv, wl);
        tree.push_leaf(LeafBsdf::Plastic(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        let (d, r) = (&self.diffuse_reflectance, &self.specular_reflectance);
        retinted(
            &self.model,
            d.is_textured() || r.is_textured(),
            |m| (m.diffuse_reflectance, m.specular_reflectance) = (d.eval(uv), r.eval(uv)),
            f,
        )
    }
}
