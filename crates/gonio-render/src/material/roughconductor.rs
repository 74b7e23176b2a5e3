//! `roughconductor`: a rough metal, the microfacet BRDF over complex-index mirrors (core model
//! [`gonio_core::bsdfs::RoughConductor`]; Mitsuba 3 `src/bsdfs/roughconductor.cpp`).
//!
//! As in Mitsuba, `alpha` (or `alpha_u` and `alpha_v`) may be textures, looked up per hit
//! (`eval_1`: a bitmap's luminance); α_u runs along the shading frame's first tangent, which
//! follows the surface's dp/du.

use super::conductor::{ETA, EXT_IOR, K, MATERIAL, SPECULAR_REFLECTANCE, complex_index};
use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, RoughConductor, SurfaceBsdf};
use gonio_core::microfacet::{MicrofacetDistribution, MicrofacetKind};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, Ior, SampledWavelengths, Spectrum};

pub(crate) const DISTRIBUTION: ParamSpec = ParamSpec::new(
    "distribution",
    ParamType::String,
    DefaultValue::Str("beckmann"),
    "microfacet normal distribution: `beckmann` or `ggx`",
);
pub(crate) const ALPHA: ParamSpec = ParamSpec::new(
    "alpha",
    ParamType::Texture,
    DefaultValue::Float(0.1),
    "roughness α (RMS slope for Beckmann), both directions; clamped to ≥ 1e-4",
);
pub(crate) const ALPHA_U: ParamSpec = ParamSpec::new(
    "alpha_u",
    ParamType::Texture,
    DefaultValue::Float(0.1),
    "roughness along the tangent (with `alpha_v`, instead of `alpha`)",
);
pub(crate) const ALPHA_V: ParamSpec = ParamSpec::new(
    "alpha_v",
    ParamType::Texture,
    DefaultValue::Float(0.1),
    "roughness along the bitangent (with `alpha_u`, instead of `alpha`)",
);
pub(crate) const SAMPLE_VISIBLE: ParamSpec = ParamSpec::new(
    "sample_visible",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "sample the distribution of visible normals (fewer wasted samples) instead of all normals",
);

pub(crate) const MULTIPLE_SCATTERING: ParamSpec = ParamSpec::new(
    "multiple_scattering",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "follow the inter-reflections between facets (Heitz et al. 2016: random-walk sampling, stochastic eval; not in Mitsuba 3)",
);

/// The `roughconductor` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "roughconductor",
    summary: "Rough conductor: single-scattering microfacet reflection (Beckmann or GGX, isotropic or anisotropic) with the Fresnel reflectance of the complex index η + ik.",
    params: &[
        MATERIAL,
        ETA,
        K,
        SPECULAR_REFLECTANCE,
        DISTRIBUTION,
        ALPHA,
        ALPHA_U,
        ALPHA_V,
        SAMPLE_VISIBLE,
        EXT_IOR,
        MULTIPLE_SCATTERING,
    ],
    build,
};

/// The roughness textures (α_u, α_v) of a microfacet plugin, with Mitsuba's rules: `alpha`, or
/// both of `alpha_u` and `alpha_v`, never a mix.
pub(crate) fn roughness<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
) -> Result<(Texture, Texture), SceneError> {
    let (has_u, has_v) = (p.has(ALPHA_U.name), p.has(ALPHA_V.name));
    let conflict = |p: &mut Params<'d>, name: &str, msg: &str| {
        let loc = p.get(name).expect("present").loc.clone();
        Err(SceneError::new(loc, ErrorKind::Grammar, msg.to_string()))
    };
    if p.has(ALPHA.name) {
        if has_u || has_v {
            let which = if has_u { ALPHA_U.name } else { ALPHA_V.name };
            return conflict(p, which, "specify either alpha or alpha_u/alpha_v, not both");
        }
        let a = b.texture(p, &ALPHA, RgbKind::Unbounded)?;
        return Ok((a.clone(), a));
    }
    if has_u != has_v {
        let which = if has_u { ALPHA_U.name } else { ALPHA_V.name };
        return conflict(p, which, "both alpha_u and alpha_v must be specified");
    }
    if has_u {
        let u = b.texture(p, &ALPHA_U, RgbKind::Unbounded)?;
        let v = b.texture(p, &ALPHA_V, RgbKind::Unbounded)?;
        return Ok((u, v));
    }
    let a = b.texture(p, &ALPHA, RgbKind::Unbounded)?;
    Ok((a.clone(), a))
}

/// The `distribution` parameter.
pub(crate) fn distribution_kind(p: &mut Params<'_>) -> Result<MicrofacetKind, SceneError> {
    let name = p.choice(
        DISTRIBUTION.name,
        DISTRIBUTION.default.str(),
        &["beckmann", "ggx"],
    )?;
    Ok(MicrofacetKind::from_name(name).expect("one of the choices"))
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let (eta, k) = complex_index(b, p)?;
    let specular = b.texture(p, &SPECULAR_REFLECTANCE, RgbKind::Albedo)?;
    let kind = distribution_kind(p)?;
    let (alpha_u, alpha_v) = roughness(b, p)?;
    let sample_visible = p.bool(SAMPLE_VISIBLE.name, SAMPLE_VISIBLE.default.bool())?;
    let ext_ior = b.ior(p, &EXT_IOR)?;
    let multiple_scattering = p.bool(MULTIPLE_SCATTERING.name, MULTIPLE_SCATTERING.default.bool())?;
    let mut m =
        RoughConductorMaterial::new(eta, k, ext_ior, specular, kind, alpha_u, alpha_v, sample_visible);
    m.model.multiple_scattering = multiple_scattering;
    Ok(Material::new(m))
}

/// `roughconductor` in a scene.
#[derive(Clone, Debug)]
pub struct RoughConductorMaterial {
    /// Multiplier, default 1.
    pub specular_reflectance: Texture,
    /// Roughness along the tangent.
    pub alpha_u: Texture,
    /// Roughness along the bitangent.
    pub alpha_v: Texture,
    /// The model with constant tint and roughness (their values when untextured).
    pub model: RoughConductor,
}

impl RoughConductorMaterial {
    /// A rough conductor from η, k, the exterior index, the tint and the microfacet parameters.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        eta: Spectrum,
        k: Spectrum,
        ext_ior: Ior,
        specular_reflectance: Texture,
        kind: MicrofacetKind,
        alpha_u: Texture,
        alpha_v: Texture,
        sample_visible: bool,
    ) -> Self {
        let distribution = MicrofacetDistribution::new(
            kind,
            alpha_u.eval_1(Vec2::ZERO),
            alpha_v.eval_1(Vec2::ZERO),
            sample_visible,
        );
        let model = RoughConductor {
            eta,
            k,
            ext_ior,
            specular_reflectance: model_value(&specular_reflectance),
            distribution,
            multiple_scattering: false,
        };
        Self {
            specular_reflectance,
            alpha_u,
            alpha_v,
            model,
        }
    }

    fn rough_textured(&self) -> bool {
        self.alpha_u.is_textured() || self.alpha_v.is_textured()
    }

    /// The distribution at `uv` (the roughness textures looked up there).
    #[inline]
    fn distribution_at(&self, uv: Vec2) -> MicrofacetDistribution {
        if !self.rough_textured() {
            return self.model.distribution;
        }
        let d = &self.model.distribution;
        MicrofacetDistribution::new(
            d.kind,
            self.alpha_u.eval_1(uv),
            self.alpha_v.eval_1(uv),
            d.sample_visible,
        )
    }
}

impl SurfaceMaterial for RoughConductorMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.specular_reflectance.is_textured() || self.rough_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.specular_reflectance, &self.specular_reflectance, uv, wl);
        m.distribution = self.distribution_at(uv);
        tree.push_leaf(LeafBsdf::RoughConductor(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if !self.is_textured() {
            return f(&self.model);
        }
        let mut m = self.model.clone();
        m.specular_reflectance = self.specular_reflectance.eval(uv);
        m.distribution = self.distribution_at(uv);
        f(&m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xml::load_bsdf_str;

    fn load(xml: &str) -> Result<Material, SceneError> {
        load_bsdf_str(xml)
    }

    #[test]
    fn mitsuba_defaults() {
        let m = load(r#"<bsdf type="roughconductor"/>"#).unwrap();
        let rc = m.get::<RoughConductorMaterial>().unwrap();
        let d = rc.model.distribution;
        assert_eq!(d.kind, MicrofacetKind::Beckmann);
        assert_eq!((d.alpha_u, d.alpha_v, d.sample_visible), (0.1, 0.1, true));
        assert_eq!(rc.model.eta, Spectrum::Constant(0.0));
        assert_eq!(rc.model.k, Spectrum::Constant(1.0));
        assert!(!m.is_textured());
        assert_eq!(m.flags(), BsdfFlags::GLOSSY_REFLECTION);
        assert!(
            !rc.model.multiple_scattering,
            "Mitsuba's single scattering by default"
        );
        let ms =
            load(r#"<bsdf type="roughconductor"><boolean name="multiple_scattering" value="true"/></bsdf>"#)
                .unwrap();
        assert!(
            ms.get::<RoughConductorMaterial>()
                .unwrap()
                .model
                .multiple_scattering
        );
    }

    #[test]
    fn parameters_are_read() {
        let m = load(
            r#"<bsdf type="roughconductor">
                 <string name="material" value="Au"/>
                 <string name="distribution" value="ggx"/>
                 <float name="alpha_u" value="0.05"/>
                 <float name="alpha_v" value="0.3"/>
                 <boolean name="sample_visible" value="false"/>
               </bsdf>"#,
        )
        .unwrap();
        let d = m.get::<RoughConductorMaterial>().unwrap().model.distribution;
        assert_eq!(d.kind, MicrofacetKind::Ggx);
        assert_eq!((d.alpha_u, d.alpha_v, d.sample_visible), (0.05, 0.3, false));
        let tiny = load(r#"<bsdf type="roughconductor"><float name="alpha" value="0"/></bsdf>"#).unwrap();
        let d = tiny.get::<RoughConductorMaterial>().unwrap().model.distribution;
        assert_eq!(
            d.alpha_u,
            gonio_core::microfacet::MIN_ALPHA,
            "clamped as in Mitsuba"
        );
    }

    #[test]
    fn mitsuba_errors() {
        for (xml, needle) in [
            (
                r#"<bsdf type="roughconductor"><float name="alpha" value="0.1"/><float name="alpha_u" value="0.2"/></bsdf>"#,
                "either alpha or alpha_u/alpha_v",
            ),
            (
                r#"<bsdf type="roughconductor"><float name="alpha_v" value="0.2"/></bsdf>"#,
                "both alpha_u and alpha_v",
            ),
            (
                r#"<bsdf type="roughconductor"><string name="distribution" value="phong"/></bsdf>"#,
                "beckmann, ggx",
            ),
            (
                r#"<bsdf type="roughconductor"><string name="material" value="Au"/><float name="eta" value="1"/></bsdf>"#,
                "not both",
            ),
            (
                r#"<bsdf type="roughconductor"><float name="roughness" value="0.2"/></bsdf>"#,
                "roughness",
            ),
        ] {
            let e = load(xml).unwrap_err().to_string();
            assert!(e.contains(needle), "{xml}: {e}");
        }
    }

    #[test]
    fn textured_roughness_is_looked_up_per_hit() {
        let m = load(
            r#"<bsdf type="roughconductor">
                 <texture type="checkerboard" name="alpha">
                   <float name="color0" value="0.05"/>
                   <float name="color1" value="0.5"/>
                 </texture>
               </bsdf>"#,
        )
        .unwrap();
        assert!(m.is_textured());
        let wl = SampledWavelengths::fixed(550.0);
        let mut alphas = Vec::new();
        for uv in [Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.25)] {
            let tree = m.bsdf_at(uv, &wl);
            let ctx = gonio_core::BsdfContext::radiance();
            // The peak value at normal incidence is 1/(4π α²) for a white Beckmann mirror.
            let peak = tree.eval(&ctx, glam::Vec3::Z, glam::Vec3::Z, &wl)[0];
            alphas.push((1.0 / (4.0 * std::f32::consts::PI * peak)).sqrt());
            // The any-wavelength BSDF agrees with the per-hit value.
            let any = m.with_bsdf(uv, |b| b.eval(&ctx, glam::Vec3::Z, glam::Vec3::Z, &wl)[0]);
            assert_eq!(any, peak);
        }
        alphas.sort_by(f32::total_cmp);
        assert!(
            (alphas[0] - 0.05).abs() < 1e-4 && (alphas[1] - 0.5).abs() < 1e-4,
            "{alphas:?}"
        );
    }
}
