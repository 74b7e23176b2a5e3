//! `roughdielectric`: a rough dielectric interface (ground or etched glass), microfacet reflection
//! and refraction (core model [`gonio_core::bsdfs::RoughDielectric`]; Mitsuba 3
//! `src/bsdfs/roughdielectric.cpp`).
//!
//! The indices and tints are `dielectric`'s (its table rows and reader: numbers, Mitsuba's named
//! materials and, ours, dispersive glasses and spectra), the roughness parameters
//! `roughconductor`'s: `alpha` (or `alpha_u` and `alpha_v`) may be textures, looked up per hit
//! (`eval_1`: a bitmap's luminance), α_u along the shading frame's first tangent (dp/du). As in
//! Mitsuba, the two indices must differ.

use super::dielectric::{EXT_IOR, INT_IOR, SPECULAR_REFLECTANCE, SPECULAR_TRANSMITTANCE, interface};
use super::roughconductor::{
    ALPHA, ALPHA_U, ALPHA_V, DISTRIBUTION, MULTIPLE_SCATTERING, SAMPLE_VISIBLE, distribution_kind, roughness,
};
use super::{BsdfPlugin, Material, SurfaceMaterial, model_value, retint_at};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, RoughDielectric, SurfaceBsdf};
use gonio_core::microfacet::{MicrofacetDistribution, MicrofacetKind};
use gonio_core::{Bsdf, BsdfFlags, Ior, SampledWavelengths};

/// The `roughdielectric` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "roughdielectric",
    summary: "Rough dielectric interface (ground glass): single-scattering microfacet reflection and refraction (Walter et al. 2007; Beckmann or GGX, isotropic or anisotropic); dispersive indices (ours) terminate the secondary wavelengths on refraction.",
    params: &[
        INT_IOR,
        EXT_IOR,
        SPECULAR_REFLECTANCE,
        SPECULAR_TRANSMITTANCE,
        DISTRIBUTION,
        ALPHA,
        ALPHA_U,
        ALPHA_V,
        SAMPLE_VISIBLE,
        MULTIPLE_SCATTERING,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let (int_ior, ext_ior, r, t) = interface(b, p)?;
    if int_ior == ext_ior {
        let obj = b.object(p);
        let loc = [INT_IOR.name, EXT_IOR.name]
            .iter()
            .find_map(|n| obj.props.iter().find(|x| x.name == *n))
            .map_or(&obj.loc, |x| &x.value_loc);
        return Err(SceneError::new(
            loc.clone(),
            ErrorKind::BadValue,
            format!(
                "roughdielectric: the interior and exterior indices of refraction must differ (both are {})",
                int_ior.nominal()
            ),
        ));
    }
    let kind = distribution_kind(p)?;
    let (alpha_u, alpha_v) = roughness(b, p)?;
    let sample_visible = p.bool(SAMPLE_VISIBLE.name, SAMPLE_VISIBLE.default.bool())?;
    let multiple_scattering = p.bool(MULTIPLE_SCATTERING.name, MULTIPLE_SCATTERING.default.bool())?;
    let mut m = RoughDielectricMaterial::new(int_ior, ext_ior, r, t, kind, alpha_u, alpha_v, sample_visible);
    m.model.multiple_scattering = multiple_scattering;
    Ok(Material::new(m))
}

/// `roughdielectric` in a scene.
#[derive(Clone, Debug)]
pub struct RoughDielectricMaterial {
    /// Multiplier on reflection, default 1.
    pub specular_reflectance: Texture,
    /// Multiplier on transmission, default 1.
    pub specular_transmittance: Texture,
    /// Roughness along the tangent.
    pub alpha_u: Texture,
    /// Roughness along the bitangent.
    pub alpha_v: Texture,
    /// The model with constant tints and roughness (their values when untextured).
    pub model: RoughDielectric,
}

impl RoughDielectricMaterial {
    /// A rough interface between `int_ior` and `ext_ior` with its tints and microfacet parameters.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        int_ior: Ior,
        ext_ior: Ior,
        specular_reflectance: Texture,
        specular_transmittance: Texture,
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
        let model = RoughDielectric {
            int_ior,
            ext_ior,
            specular_reflectance: model_value(&specular_reflectance),
            specular_transmittance: model_value(&specular_transmittance),
            distribution,
            multiple_scattering: false,
        };
        Self {
            specular_reflectance,
            specular_transmittance,
            alpha_u,
            alpha_v,
            model,
        }
    }

    fn rough_textured(&self) -> bool {
        self.alpha_u.is_textured() || self.alpha_v.is_textured()
    }

    fn tint_textured(&self) -> bool {
        self.specular_reflectance.is_textured() || self.specular_transmittance.is_textured()
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

impl SurfaceMaterial for RoughDielectricMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.tint_textured() || self.rough_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.specular_reflectance, &self.specular_reflectance, uv, wl);
        retint_at(
            &mut m.specular_transmittance,
            &self.specular_transmittance,
            uv,
            wl,
        );
        m.distribution = self.distribution_at(uv);
        tree.push_leaf(LeafBsdf::RoughDielectric(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if !self.is_textured() {
            return f(&self.model);
        }
        let mut m = self.model.clone();
        m.specular_reflectance = self.specular_reflectance.eval(uv);
        m.specular_transmittance = self.specular_transmittance.eval(uv);
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
        let m = load(r#"<bsdf type="roughdielectric"/>"#).unwrap();
        let rd = m.get::<RoughDielectricMaterial>().unwrap();
        let d = rd.model.distribution;
        assert_eq!(d.kind, MicrofacetKind::Beckmann);
        assert_eq!((d.alpha_u, d.alpha_v, d.sample_visible), (0.1, 0.1, true));
        assert_eq!(rd.model.int_ior, Ior::Constant(1.5046));
        assert_eq!(rd.model.ext_ior, Ior::Constant(1.000277));
        assert!(!m.is_textured());
        assert_eq!(
            m.flags(),
            BsdfFlags::GLOSSY_REFLECTION | RoughDielectric::TRANSMISSION_FLAGS
        );
        assert!(
            !rd.model.multiple_scattering,
            "Mitsuba's single scattering by default"
        );
        let ms =
            load(r#"<bsdf type="roughdielectric"><boolean name="multiple_scattering" value="true"/></bsdf>"#)
                .unwrap();
        assert!(
            ms.get::<RoughDielectricMaterial>()
                .unwrap()
                .model
                .multiple_scattering
        );
    }

    #[test]
    fn parameters_are_read() {
        let m = load(
            r#"<bsdf type="roughdielectric">
                 <string name="int_ior" value="water"/>
                 <float name="ext_ior" value="1.1"/>
                 <string name="distribution" value="ggx"/>
                 <float name="alpha_u" value="0.05"/>
                 <float name="alpha_v" value="0.3"/>
                 <boolean name="sample_visible" value="false"/>
                 <spectrum name="specular_transmittance" value="0.5"/>
               </bsdf>"#,
        )
        .unwrap();
        let rd = m.get::<RoughDielectricMaterial>().unwrap();
        let d = rd.model.distribution;
        assert_eq!(d.kind, MicrofacetKind::Ggx);
        assert_eq!((d.alpha_u, d.alpha_v, d.sample_visible), (0.05, 0.3, false));
        assert_eq!(rd.model.int_ior, Ior::Constant(1.333));
        assert_eq!(rd.model.ext_ior, Ior::Constant(1.1));
        assert!(m.flags().contains(BsdfFlags::ANISOTROPIC));
        // A dispersive glass (ours), and α = 0 clamped as in Mitsuba.
        let m = load(r#"<bsdf type="roughdielectric"><string name="int_ior" value="SF11"/><float name="alpha" value="0"/></bsdf>"#)
            .unwrap();
        let rd = m.get::<RoughDielectricMaterial>().unwrap();
        assert!(rd.model.int_ior.is_dispersive());
        assert_eq!(rd.model.distribution.alpha_u, gonio_core::microfacet::MIN_ALPHA);
    }

    #[test]
    fn mitsuba_errors() {
        for (xml, needle) in [
            (
                r#"<bsdf type="roughdielectric"><float name="int_ior" value="1.333"/><string name="ext_ior" value="water"/></bsdf>"#,
                "must differ",
            ),
            (
                r#"<bsdf type="roughdielectric"><float name="int_ior" value="1.000277"/></bsdf>"#,
                "must differ",
            ),
            (
                r#"<bsdf type="roughdielectric"><float name="alpha" value="0.1"/><float name="alpha_u" value="0.2"/></bsdf>"#,
                "either alpha or alpha_u/alpha_v",
            ),
            (
                r#"<bsdf type="roughdielectric"><float name="alpha_u" value="0.2"/></bsdf>"#,
                "both alpha_u and alpha_v",
            ),
            (
                r#"<bsdf type="roughdielectric"><string name="distribution" value="phong"/></bsdf>"#,
                "beckmann, ggx",
            ),
            (
                r#"<bsdf type="roughdielectric"><float name="int_ior" value="-1.5"/></bsdf>"#,
                "positive",
            ),
            (
                r#"<bsdf type="roughdielectric"><string name="int_ior" value="unobtainium"/></bsdf>"#,
                "unobtainium",
            ),
            (
                r#"<bsdf type="roughdielectric"><float name="roughness" value="0.2"/></bsdf>"#,
                "roughness",
            ),
        ] {
            let e = load(xml).unwrap_err().to_string();
            assert!(e.contains(needle), "{xml}: {e}");
        }
        // The error names the line and the value.
        let e = load("<bsdf type=\"roughdielectric\">\n<float name=\"int_ior\" value=\"1.000277\"/></bsdf>")
            .unwrap_err()
            .to_string();
        assert!(e.contains(":2:") && e.contains("1.000277"), "{e}");
    }

    #[test]
    fn textured_roughness_is_looked_up_per_hit() {
        let m = load(
            r#"<bsdf type="roughdielectric">
                 <texture type="checkerboard" name="alpha">
                   <float name="color0" value="0.05"/>
                   <float name="color1" value="0.5"/>
                 </texture>
               </bsdf>"#,
        )
        .unwrap();
        assert!(m.is_textured());
        let wl = SampledWavelengths::fixed(550.0);
        let ctx = gonio_core::BsdfContext::radiance();
        let eta = 1.5046f32 / 1.000277;
        let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
        let mut alphas = Vec::new();
        for uv in [Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.25)] {
            let tree = m.bsdf_at(uv, &wl);
            // The reflection peak at normal incidence is F(1)/(4π α²) for Beckmann.
            let peak = tree.eval(&ctx, glam::Vec3::Z, glam::Vec3::Z, &wl)[0];
            alphas.push((f0 / (4.0 * std::f32::consts::PI * peak)).sqrt());
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
