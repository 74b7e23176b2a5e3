//! `roughplastic`: a Lambertian base under a rough dielectric coat (core model
//! [`gonio_core::bsdfs::RoughPlastic`]; Mitsuba 3 `src/bsdfs/roughplastic.cpp`).
//!
//! As in Mitsuba, `alpha` is a number (the coat's averages are precomputed for it, so it cannot
//! be a texture) and the roughness must be isotropic (`alpha_u` = `alpha_v` if given); the indices
//! must differ. `diffuse_reflectance` and `specular_reflectance` may be textures, looked up per
//! hit. Addition over Mitsuba: `coat_averages` (`exact`, gonio's default, or `mitsuba`, which
//! reproduces Mitsuba 3.9.1's tables for comparisons; see the core model's docs).

use super::plastic::{DIFFUSE_REFLECTANCE, EXT_IOR, INT_IOR, NONLINEAR, SPECULAR_REFLECTANCE, constant_ior};
use super::roughconductor::{DISTRIBUTION, SAMPLE_VISIBLE, distribution_kind};
use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::roughplastic::{CoatAverages, RoughCoat};
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, RoughPlastic, SurfaceBsdf};
use gonio_core::microfacet::MicrofacetDistribution;
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const ALPHA: ParamSpec = ParamSpec::new(
    "alpha",
    ParamType::Float,
    DefaultValue::Float(0.1),
    "roughness α of the coat (RMS slope for Beckmann); a number, not a texture; clamped to ≥ 1e-4",
);
const ALPHA_U: ParamSpec = ParamSpec::new(
    "alpha_u",
    ParamType::Float,
    DefaultValue::Float(0.1),
    "with `alpha_v`, instead of `alpha`: accepted only when equal (anisotropic coats are an error, as in Mitsuba)",
);
const ALPHA_V: ParamSpec = ParamSpec::new(
    "alpha_v",
    ParamType::Float,
    DefaultValue::Float(0.1),
    "see `alpha_u`",
);
const COAT_AVERAGES: ParamSpec = ParamSpec::ours_or_mitsuba(
    "coat_averages",
    "exact",
    "(ours) the coat's transmittance table and internal reflectance: `exact` (energy ≤ 1) or `mitsuba` (Mitsuba 3.9.1's 64-node tables)",
);

/// The `roughplastic` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "roughplastic",
    summary: "Rough coated diffuse: a Lambertian base under a rough dielectric coat (Beckmann or GGX, isotropic), with the internal reflections between them.",
    params: &[
        DIFFUSE_REFLECTANCE,
        NONLINEAR,
        INT_IOR,
        EXT_IOR,
        SPECULAR_REFLECTANCE,
        DISTRIBUTION,
        ALPHA,
        ALPHA_U,
        ALPHA_V,
        SAMPLE_VISIBLE,
        COAT_AVERAGES,
    ],
    build,
};

fn error(p: &mut Params<'_>, name: &str, msg: String) -> SceneError {
    let loc = p.get(name).expect("present").value_loc.clone();
    SceneError::new(loc, ErrorKind::BadValue, msg)
}

/// The isotropic roughness, with Mitsuba's rules: `alpha`, or both `alpha_u` and `alpha_v` (then
/// equal), never a mix; a finite number ≥ 0.
fn roughness(p: &mut Params<'_>) -> Result<f32, SceneError> {
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
        if u != v {
            return Err(error(
                p,
                ALPHA_V.name,
                format!(
                    "{what} does not support anisotropic microfacet distributions (alpha_u {u} ≠ alpha_v {v}), as in Mitsuba"
                ),
            ));
        }
        return Ok(u as f32);
    }
    Ok(p.float_checked(ALPHA.name, ALPHA.default.float(), ok, rule)? as f32)
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let d = b.texture(p, &DIFFUSE_REFLECTANCE, RgbKind::Albedo)?;
    let nonlinear = p.bool(NONLINEAR.name, NONLINEAR.default.bool())?;
    let int_ior = constant_ior(b, p, &INT_IOR, "roughplastic")?;
    let ext_ior = constant_ior(b, p, &EXT_IOR, "roughplastic")?;
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
    let s = b.texture(p, &SPECULAR_REFLECTANCE, RgbKind::Albedo)?;
    let kind = distribution_kind(p)?;
    let alpha = roughness(p)?;
    let sample_visible = p.bool(SAMPLE_VISIBLE.name, SAMPLE_VISIBLE.default.bool())?;
    let averages = if p.mitsuba_way(&COAT_AVERAGES)? {
        CoatAverages::Mitsuba
    } else {
        CoatAverages::Exact
    };
    let distribution = MicrofacetDistribution::new(kind, alpha, alpha, sample_visible);
    let coat = RoughCoat::new(distribution, int_ior / ext_ior, averages);
    Ok(Material::new(RoughPlasticMaterial::new(d, s, nonlinear, coat)))
}

/// `roughplastic` in a scene.
#[derive(Clone, Debug)]
pub struct RoughPlasticMaterial {
    /// Base reflectance, default 0.5.
    pub diffuse_reflectance: Texture,
    /// Coat reflectance multiplier, default 1.
    pub specular_reflectance: Texture,
    /// The model with the coat's precomputed averages and the texture means (sampling weight).
    pub model: RoughPlastic,
}

impl RoughPlasticMaterial {
    /// The material; the specular sampling weight uses the texture means (Mitsuba).
    pub fn new(
        diffuse_reflectance: Texture,
        specular_reflectance: Texture,
        nonlinear: bool,
        coat: RoughCoat,
    ) -> Self {
        let model = RoughPlastic::new(
            model_value(&diffuse_reflectance),
            model_value(&specular_reflectance),
            nonlinear,
            coat,
        );
        Self {
            diffuse_reflectance,
            specular_reflectance,
            model,
        }
    }
}

impl SurfaceMaterial for RoughPlasticMaterial {
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
        tree.push_leaf(LeafBsdf::RoughPlastic(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if !self.is_textured() {
            return f(&self.model);
        }
        // The per-wavelength spectra at uv over the prebuilt coat (borrowed, not rebuilt).
        let mut m = self.model.borrowed();
        m.diffuse_reflectance = self.diffuse_reflectance.eval(uv);
        m.specular_reflectance = self.specular_reflectance.eval(uv);
        f(&m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xml::load_bsdf_str;
    use gonio_core::microfacet::MicrofacetKind;

    fn load(xml: &str) -> Result<Material, SceneError> {
        load_bsdf_str(xml)
    }

    #[test]
    fn mitsuba_defaults() {
        let m = load(r#"<bsdf type="roughplastic"/>"#).unwrap();
        let rp = m.get::<RoughPlasticMaterial>().unwrap();
        let coat = &rp.model.coat;
        let d = coat.distribution();
        assert_eq!(d.kind, MicrofacetKind::Beckmann);
        assert_eq!((d.alpha_u, d.alpha_v, d.sample_visible), (0.1, 0.1, true));
        assert!((coat.eta() - 1.489_587).abs() < 1e-6);
        assert_eq!(coat.averages(), CoatAverages::Exact);
        assert!(!rp.model.nonlinear);
        assert!((rp.model.specular_sampling_weight() - 2.0 / 3.0).abs() < 1e-6);
        assert!(!m.is_textured());
        assert_eq!(
            m.flags(),
            BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::DIFFUSE_REFLECTION
        );
    }

    #[test]
    fn parameters_are_read() {
        let m = load(
            r#"<bsdf type="roughplastic">
                 <string name="distribution" value="ggx"/>
                 <float name="alpha_u" value="0.3"/>
                 <float name="alpha_v" value="0.3"/>
                 <boolean name="sample_visible" value="false"/>
                 <boolean name="nonlinear" value="true"/>
                 <string name="int_ior" value="bk7"/>
                 <float name="ext_ior" value="1.33"/>
                 <string name="coat_averages" value="mitsuba"/>
               </bsdf>"#,
        )
        .unwrap();
        let rp = m.get::<RoughPlasticMaterial>().unwrap();
        let d = rp.model.coat.distribution();
        assert_eq!(
            (d.kind, d.alpha_u, d.sample_visible),
            (MicrofacetKind::Ggx, 0.3, false)
        );
        assert!(rp.model.nonlinear);
        assert!((rp.model.coat.eta() - 1.5046 / 1.33).abs() < 1e-4);
        assert_eq!(rp.model.coat.averages(), CoatAverages::Mitsuba);
        let tiny = load(r#"<bsdf type="roughplastic"><float name="alpha" value="0"/></bsdf>"#).unwrap();
        let rp = tiny.get::<RoughPlasticMaterial>().unwrap();
        assert_eq!(
            rp.model.coat.distribution().alpha_u,
            gonio_core::microfacet::MIN_ALPHA
        );
    }

    #[test]
    fn mitsuba_errors() {
        for (xml, needle) in [
            (
                r#"<bsdf type="roughplastic"><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.3"/></bsdf>"#,
                "anisotropic",
            ),
            (
                r#"<bsdf type="roughplastic"><float name="alpha" value="0.1"/><float name="alpha_u" value="0.2"/></bsdf>"#,
                "either alpha or alpha_u/alpha_v",
            ),
            (
                r#"<bsdf type="roughplastic"><float name="alpha_u" value="0.2"/></bsdf>"#,
                "both alpha_u and alpha_v",
            ),
            (
                r#"<bsdf type="roughplastic"><texture type="checkerboard" name="alpha"/></bsdf>"#,
                "alpha",
            ),
            (
                r#"<bsdf type="roughplastic"><float name="alpha" value="-0.1"/></bsdf>"#,
                "invalid alpha -0.1",
            ),
            (
                r#"<bsdf type="roughplastic"><float name="int_ior" value="1.2"/><float name="ext_ior" value="1.2"/></bsdf>"#,
                "must be positive and differ",
            ),
            (
                r#"<bsdf type="roughplastic"><string name="distribution" value="phong"/></bsdf>"#,
                "beckmann, ggx",
            ),
            (
                r#"<bsdf type="roughplastic"><string name="coat_averages" value="fitted"/></bsdf>"#,
                "exact, mitsuba",
            ),
            (
                r#"<bsdf type="roughplastic"><float name="roughness" value="0.2"/></bsdf>"#,
                "roughness",
            ),
        ] {
            let e = load(xml).unwrap_err().to_string();
            assert!(e.contains(needle), "{xml}: {e}");
            assert!(
                e.starts_with("<bsdf>:1:"),
                "{xml}: the error names the place: {e}"
            );
        }
    }

    #[test]
    fn textured_diffuse_reflectance_is_looked_up_per_hit() {
        let m = load(
            r#"<bsdf type="roughplastic">
                 <texture type="checkerboard" name="diffuse_reflectance">
                   <float name="color0" value="0.2"/>
                   <float name="color1" value="0.9"/>
                 </texture>
               </bsdf>"#,
        )
        .unwrap();
        assert!(m.is_textured());
        let wl = SampledWavelengths::fixed(550.0);
        let ctx = gonio_core::BsdfContext::radiance().with_lobes(BsdfFlags::DIFFUSE_REFLECTION);
        let (wi, wo) = (glam::Vec3::Z, glam::Vec3::new(0.6, 0.0, 0.8));
        let mut values = Vec::new();
        for uv in [Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.25)] {
            let f = m.bsdf_at(uv, &wl).eval(&ctx, wi, wo, &wl)[0];
            let any = m.with_bsdf(uv, |b| b.eval(&ctx, wi, wo, &wl)[0]);
            assert_eq!(any, f);
            values.push(f);
        }
        // Linear mode: the diffuse value is proportional to ρ.
        assert!((values[1] / values[0] - 4.5).abs() < 1e-4, "{values:?}");
    }
}
