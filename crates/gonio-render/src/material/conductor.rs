//! `conductor`: a smooth metal, delta reflection weighted by the complex-index Fresnel term
//! (core model [`gonio_core::bsdfs::Conductor`]; Mitsuba 3 `src/bsdfs/conductor.cpp`).

use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
    retinted,
};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{Conductor, LeafBsdf, SurfaceBsdf};
use gonio_core::named;
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, Ior, SampledWavelengths, Spectrum};

pub(crate) const MATERIAL: ParamSpec = ParamSpec::new(
    "material",
    ParamType::String,
    DefaultValue::Str("none"),
    "a measured metal (every preset of Mitsuba's `data/ior`: `Au`, `Ag`, `Cu`, `Al`, `Cr`, `a-C`, ...; and `CuZn`) giving η and k; `none` is the ideal mirror",
);
pub(crate) const ETA: ParamSpec = ParamSpec::new(
    "eta",
    ParamType::Spectrum,
    DefaultValue::Float(0.0),
    "real part η of the complex index (instead of `material`)",
);
pub(crate) const K: ParamSpec = ParamSpec::new(
    "k",
    ParamType::Spectrum,
    DefaultValue::Float(1.0),
    "imaginary part k, the extinction coefficient (instead of `material`)",
);
pub(crate) const SPECULAR_REFLECTANCE: ParamSpec = ParamSpec::new(
    "specular_reflectance",
    ParamType::Texture,
    DefaultValue::Float(1.0),
    "tint multiplying the Fresnel term (not physical)",
);
pub(crate) const EXT_IOR: ParamSpec = ParamSpec::new(
    "ext_ior",
    ParamType::Ior,
    DefaultValue::Str("vacuum"),
    "(ours) index of the dielectric the metal is immersed in",
);

/// The `conductor` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "conductor",
    summary: "Smooth conductor: mirror reflection with the Fresnel reflectance of the complex index η + ik.",
    params: &[MATERIAL, ETA, K, SPECULAR_REFLECTANCE, EXT_IOR],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let (eta, k) = complex_index(b, p)?;
    let specular = b.texture(p, &SPECULAR_REFLECTANCE, RgbKind::Albedo)?;
    let ext_ior = b.ior(p, &EXT_IOR)?;
    Ok(Material::new(ConductorMaterial::new(eta, k, ext_ior, specular)))
}

/// η and k from `material` (a preset) or from `eta` and `k` (not both), as Mitsuba's
/// `conductor` and `roughconductor` read them.
pub(crate) fn complex_index<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
) -> Result<(Spectrum, Spectrum), SceneError> {
    Ok(match p.string_opt(MATERIAL.name)? {
        Some((m, mloc)) if !m.eq_ignore_ascii_case("none") => {
            if p.has(ETA.name) || p.has(K.name) {
                let which = if p.has(ETA.name) { ETA.name } else { K.name };
                let bad = p.get(which).expect("checked above");
                return Err(SceneError::new(
                    bad.loc.clone(),
                    ErrorKind::Grammar,
                    format!("give either material=\"{m}\" or eta and k, not both"),
                ));
            }
            named::conductor(m).ok_or_else(|| {
                SceneError::new(
                    mloc.clone(),
                    ErrorKind::UnknownPreset,
                    format!(
                        "unknown conductor material \"{m}\" (known: {})",
                        named::conductor_names().join(", ")
                    ),
                )
            })?
        }
        _ => (
            b.spectrum(p, &ETA, RgbKind::Unbounded)?,
            b.spectrum(p, &K, RgbKind::Unbounded)?,
        ),
    })
}

/// `conductor` in a scene.
#[derive(Clone, Debug)]
pub struct ConductorMaterial {
    /// Multiplier, default 1.
    pub specular_reflectance: Texture,
    /// The model with a constant `specular_reflectance` (its value when untextured).
    pub model: Conductor,
}

impl ConductorMaterial {
    /// A conductor from η, k, the exterior index and the tint.
    pub fn new(eta: Spectrum, k: Spectrum, ext_ior: Ior, specular_reflectance: Texture) -> Self {
        let model = Conductor {
            eta,
            k,
            ext_ior,
            specular_reflectance: model_value(&specular_reflectance),
        };
        Self {
            specular_reflectance,
            model,
        }
    }
}

impl SurfaceMaterial for ConductorMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.specular_reflectance.is_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.specular_reflectance, &self.specular_reflectance, uv, wl);
        tree.push_leaf(LeafBsdf::Conductor(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        let r = &self.specular_reflectance;
        retinted(
            &self.model,
            r.is_textured(),
            |m| m.specular_reflectance = r.eval(uv),
            f,
        )
    }
}
