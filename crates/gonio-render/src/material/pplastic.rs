//! `pplastic`: polarized plastic, a rough specular reflection plus a diffuse lobe refracted in and
//! out through a smooth interface (core model [`gonio_core::bsdfs::PPlastic`]; Mitsuba 3
//! `src/bsdfs/pplastic.cpp`, after Baek et al. 2018).
//!
//! As in Mitsuba, `alpha` (or `alpha_u` and `alpha_v`, which may differ) are numbers, and the
//! indices must be positive and differ. `diffuse_reflectance` and `specular_reflectance` may be
//! textures, looked up per hit; the lobe-selection weight uses their means.

use super::plastic::{DIFFUSE_REFLECTANCE, EXT_IOR, INT_IOR, SPECULAR_REFLECTANCE, constant_ior};
use super::roughconductor::{DISTRIBUTION, SAMPLE_VISIBLE, distribution_kind};
use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
    retinted,
};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, PPlastic, SurfaceBsdf};
use gonio_core::microfacet::MicrofacetDistribution;
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const ALPHA: ParamSpec = ParamSpec::new(
    "alpha",
    ParamType::Float,
    DefaultValue::Float(0.1),
    "roughness α of the specular lobe (RMS slope for Beckmann), both directions; a number; clamped to ≥ 1e-4",
);
const ALPHA_U: ParamSpec = ParamSpec::new(
    "alpha_u",
    ParamType::Float,
    DefaultValue::Float(0.1),
    "roughness along the tangent (with `alpha_v`, instead of `alpha`)",
);
const ALPHA_V: ParamSpec = ParamSpec::new(
    "alpha_v",
    ParamType::Float,
    DefaultValue::Float(0.1),
    "roughness along the bitangent (with `alpha_u`, instead of `alpha`)",
);

/// The `pplastic` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "pplastic",
    summary: "Polarized plastic (Baek et al. 2018): rough specular reflection plus a depolarized diffuse lobe refracted in and out through a smooth interface, both with their Fresnel Mueller matrices.",
    params: &[
        DIFFUSE_REFLECTANCE,
        SPECULAR_REFLECTANCE,
        INT_IOR,
        EXT_IOR,
        DISTRIBUTION,
        ALPHA,
        ALPHA_U,
        ALPHA_V,
        SAMPLE_VISIBLE,
    ],
    build,
};

fn error(p: &mut Params<'_>, name: &str, msg: String) -> SceneError {
    let loc = p.get(name).expect("present").value_loc.clone();
    SceneError::new(loc, ErrorKind::BadValue, msg)
}

/// (α_u, α_v) with Mitsuba's rules: `alpha`, or both `alpha_u` and `alpha_v`, never a mix;
/// finite numbers ≥ 0.
fn roughness(p: &mut Params<'_>) -> Result<(f32, f32), SceneError> {
    let (has_u, has_v) = (p.has(ALPHA_U.name), p.has(ALPHA_V.name));
    let what = p.what();
    if p.has(ALPHA.name) && (has_u || has_v) {
        let which = if has_u { ALPHA_U.name } else { ALPHA_V.name };
        return Err(error(
            p,
            which,
            format!("specify either alpha or alpha_u/alpha_v in {what}, not both"),
        ));
    }
    if has_u != has_v {
        let which = if has_u { ALPHA_U.name } else { ALPHA_V.name };
        return Err(error(
            p,
            which,
            format!("both alpha_u and alpha_v must be specified in {what}"),
        ));
    }
    let ok = |a: f64| a >= 0.0;
    let rule = "must be a finite number ≥ 0";
    if has_u {
        let u = p.float_checked(ALPHA_U.name, 0.1, ok, rule)?;
        let v = p.float_checked(ALPHA_V.name, 0.1, ok, rule)?;
        return Ok((u as f32, v as f32));
    }
    let a = p.float_checked(ALPHA.name, ALPHA.default.float(), ok, rule)? as f32;
    Ok((a, a))
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let d = b.texture(p, &DIFFUSE_REFLECTANCE, RgbKind::Albedo)?;
    let s = b.texture(p, &SPECULAR_REFLECTANCE, RgbKind::Albedo)?;
    let int_ior = constant_ior(b, p, &INT_IOR, "pplastic")?;
    let ext_ior = constant_ior(b, p, &EXT_IOR, "pplastic")?;
    if !(int_ior > 0.0 && ext_ior > 0.0) || int_ior == ext_ior {
        let obj = b.object(p);
        let loc = obj
            .props
            .iter()
            .find(|x| x.name == INT_IOR.name || x.name == EXT_IOR.name)
            .map_or(&obj.loc, |x| &x.value_loc);
        return Err(SceneError::new(
            loc.clone(),
            ErrorKind::BadValue,
            format!(
                "the interior and exterior indices of refraction of {} must be positive and differ (int_ior {int_ior}, ext_ior {ext_ior})",
                p.what()
            ),
        ));
    }
    let kind = distribution_kind(p)?;
    let (alpha_u, alpha_v) = roughness(p)?;
    let sample_visible = p.bool(SAMPLE_VISIBLE.name, SAMPLE_VISIBLE.default.bool())?;
    let distribution = MicrofacetDistribution::new(kind, alpha_u, alpha_v, sample_visible);
    Ok(Material::new(PPlasticMaterial::new(
        d,
        s,
        distribution,
        int_ior / ext_ior,
    )))
}

/// `pplastic` in a scene.
#[derive(Clone, Debug)]
pub struct PPlasticMaterial {
    /// Diffuse albedo, default 0.5.
    pub diffuse_reflectance: Texture,
    /// Specular tint, default 1.
    pub specular_reflectance: Texture,
    /// The model with the texture means (sampling weight) or the constant spectra.
    pub model: PPlastic,
}

impl PPlasticMaterial {
    /// The material of relative index `eta` = int_ior/ext_ior.
    pub fn new(
        diffuse_reflectance: Texture,
        specular_reflectance: Texture,
        distribution: MicrofacetDistribution,
        eta: f32,
    ) -> Self {
        let model = PPlastic::new(
            model_value(&diffuse_reflectance),
            model_value(&specular_reflectance),
            distribution,
            eta,
        );
        Self {
            diffuse_reflectance,
            specular_reflectance,
            model,
        }
    }
}

impl SurfaceMaterial for PPlasticMaterial {
    fn asks_for_polarization(&self) -> bool {
        true
    }
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
        tree.push_leaf(LeafBsdf::PPlastic(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        retinted(
            &self.model,
            self.is_textured(),
            |m| {
                m.diffuse_reflectance = self.diffuse_reflectance.eval(uv);
                m.specular_reflectance = self.specular_reflectance.eval(uv);
            },
            f,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xml::load_bsdf_str;
    use gonio_core::microfacet::MicrofacetKind;

    #[test]
    fn mitsuba_defaults() {
        let m = load_bsdf_str(r#"<bsdf type="pplastic"/>"#).unwrap();
        let pp = m.get::<PPlasticMaterial>().unwrap();
        let d = pp.model.distribution;
        assert_eq!(d.kind, MicrofacetKind::Beckmann);
        assert_eq!((d.alpha_u, d.alpha_v, d.sample_visible), (0.1, 0.1, true));
        assert!((pp.model.eta - 1.489_587).abs() < 1e-6);
        assert!((pp.model.specular_sampling_weight() - 2.0 / 3.0).abs() < 1e-6);
        assert_eq!(
            m.flags(),
            BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::DIFFUSE_REFLECTION
        );
    }

    #[test]
    fn parameters_are_read() {
        let m = load_bsdf_str(
            r#"<bsdf type="pplastic">
                 <string name="distribution" value="ggx"/>
                 <float name="alpha_u" value="0.3"/>
                 <float name="alpha_v" value="0.05"/>
                 <boolean name="sample_visible" value="false"/>
                 <float name="int_ior" value="1.6"/>
                 <rgb name="diffuse_reflectance" value="0.05, 0.03, 0.1"/>
               </bsdf>"#,
        )
        .unwrap();
        let pp = m.get::<PPlasticMaterial>().unwrap();
        let d = pp.model.distribution;
        assert_eq!(
            (d.kind, d.alpha_u, d.alpha_v, d.sample_visible),
            (MicrofacetKind::Ggx, 0.3, 0.05, false)
        );
        assert!((pp.model.eta - 1.6 / 1.000277).abs() < 1e-6);
        assert!(m.flags().contains(BsdfFlags::ANISOTROPIC));
    }

    #[test]
    fn mitsuba_errors() {
        for (xml, needle) in [
            (
                r#"<bsdf type="pplastic"><float name="alpha" value="0.1"/><float name="alpha_u" value="0.2"/></bsdf>"#,
                "either alpha or alpha_u/alpha_v",
            ),
            (
                r#"<bsdf type="pplastic"><float name="alpha_v" value="0.2"/></bsdf>"#,
                "both alpha_u and alpha_v",
            ),
            (
                r#"<bsdf type="pplastic"><float name="alpha" value="-1"/></bsdf>"#,
                "invalid alpha -1",
            ),
            (
                r#"<bsdf type="pplastic"><float name="int_ior" value="1.3"/><float name="ext_ior" value="1.3"/></bsdf>"#,
                "must be positive and differ",
            ),
            (
                r#"<bsdf type="pplastic"><string name="distribution" value="phong"/></bsdf>"#,
                "beckmann, ggx",
            ),
            (
                r#"<bsdf type="pplastic"><boolean name="nonlinear" value="true"/></bsdf>"#,
                "nonlinear",
            ),
        ] {
            let e = load_bsdf_str(xml).unwrap_err().to_string();
            assert!(e.contains(needle), "{xml}: {e}");
            assert!(e.starts_with("<bsdf>:1:"), "{xml}: {e}");
        }
    }
}
