//! `roughdiffuse`: a rough diffuse surface (core model [`gonio_core::bsdfs::RoughDiffuse`]),
//! Mitsuba 0.6's plugin of that name (`src/bsdfs/roughdiffuse.cpp`): Oren–Nayar, full model by
//! default, the qualitative one with `useFastApprox`. Mitsuba 3 has no such plugin. Ours adds
//! `model="microfacet"`: Lambertian facets on the Smith microsurface of `distribution` with
//! every bounce between them (Heitz et al. 2016).
//!
//! As in Mitsuba 0.6, `alpha` is the RMS slope (Oren–Nayar's σ = α/√2) and may be a texture
//! (looked up per hit; a bitmap's luminance), and `reflectance` a spectrum or texture.

use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::roughdiffuse::RoughDiffuseModel;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, RoughDiffuse, SurfaceBsdf};
use gonio_core::microfacet::MicrofacetKind;
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const REFLECTANCE: ParamSpec = ParamSpec::new(
    "reflectance",
    ParamType::Texture,
    DefaultValue::Float(0.5),
    "ρ, the albedo of the facets",
);
const ALPHA: ParamSpec = ParamSpec::new(
    "alpha",
    ParamType::Texture,
    DefaultValue::Float(0.2),
    "roughness α, the facets' RMS slope (Oren–Nayar's σ = α/√2); 0 is Lambert",
);
const USE_FAST_APPROX: ParamSpec = ParamSpec::new(
    "useFastApprox",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "Oren–Nayar's qualitative model (no interreflections) instead of the full one",
);
const MODEL: ParamSpec = ParamSpec::new(
    "model",
    ParamType::String,
    DefaultValue::Str("orennayar"),
    "`orennayar` (V-grooves, closed form) or `microfacet` (Lambertian facets on a Smith microsurface, all bounces: Heitz et al. 2016; stochastic eval, white stays white)",
);
const DISTRIBUTION: ParamSpec = ParamSpec::new(
    "distribution",
    ParamType::String,
    DefaultValue::Str("beckmann"),
    "microfacet normal distribution of `model=\"microfacet\"`: `beckmann` or `ggx`",
);

/// The `roughdiffuse` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "roughdiffuse",
    summary: "(Mitsuba 0.6) Rough diffuse reflection: Oren–Nayar's V-groove model, flatter than Lambert with retro-reflection at grazing angles; one-sided.",
    params: &[REFLECTANCE, ALPHA, USE_FAST_APPROX, MODEL, DISTRIBUTION],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let reflectance = b.texture(p, &REFLECTANCE, RgbKind::Albedo)?;
    let alpha = b.texture(p, &ALPHA, RgbKind::Unbounded)?;
    let name = p.choice(MODEL.name, MODEL.default.str(), &["orennayar", "microfacet"])?;
    let only_with = |p: &mut Params<'d>, param: &str, model: &str| -> Result<(), SceneError> {
        match p.get(param) {
            Some(v) => Err(SceneError::new(
                v.loc.clone(),
                ErrorKind::Grammar,
                format!("roughdiffuse: {param} applies to model=\"{model}\" only"),
            )),
            None => Ok(()),
        }
    };
    let model = if name == "microfacet" {
        only_with(p, USE_FAST_APPROX.name, "orennayar")?;
        let kind = p.choice(
            DISTRIBUTION.name,
            DISTRIBUTION.default.str(),
            &["beckmann", "ggx"],
        )?;
        RoughDiffuseModel::Microfacet(MicrofacetKind::from_name(kind).expect("one of the choices"))
    } else {
        only_with(p, DISTRIBUTION.name, "microfacet")?;
        if p.bool(USE_FAST_APPROX.name, USE_FAST_APPROX.default.bool())? {
            RoughDiffuseModel::OrenNayarFast
        } else {
            RoughDiffuseModel::OrenNayar
        }
    };
    Ok(Material::new(RoughDiffuseMaterial::new(
        reflectance,
        alpha,
        model,
    )))
}

/// `roughdiffuse` in a scene.
#[derive(Clone, Debug)]
pub struct RoughDiffuseMaterial {
    /// ρ.
    pub reflectance: Texture,
    /// α (RMS slope).
    pub alpha: Texture,
    /// The model with constant albedo and roughness (their values when untextured).
    pub model: RoughDiffuse,
}

impl RoughDiffuseMaterial {
    /// A rough diffuse material of albedo `reflectance`, roughness `alpha` and the given model.
    pub fn new(reflectance: Texture, alpha: Texture, model: RoughDiffuseModel) -> Self {
        let model = RoughDiffuse::new(model_value(&reflectance), alpha.eval_1(Vec2::ZERO), model);
        Self {
            reflectance,
            alpha,
            model,
        }
    }

    /// α at `uv`.
    #[inline]
    fn alpha_at(&self, uv: Vec2) -> f32 {
        if self.alpha.is_textured() {
            self.alpha.eval_1(uv).max(0.0)
        } else {
            self.model.alpha
        }
    }
}

impl SurfaceMaterial for RoughDiffuseMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.reflectance.is_textured() || self.alpha.is_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.reflectance, &self.reflectance, uv, wl);
        m.alpha = self.alpha_at(uv);
        tree.push_leaf(LeafBsdf::RoughDiffuse(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if !self.is_textured() {
            return f(&self.model);
        }
        let mut m = self.model.clone();
        m.reflectance = self.reflectance.eval(uv);
        m.alpha = self.alpha_at(uv);
        f(&m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xml::load_bsdf_str;
    use gonio_core::{BsdfContext, Spectrum};

    #[test]
    fn mitsuba_defaults_and_parameters() {
        let m = load_bsdf_str(r#"<bsdf type="roughdiffuse"/>"#).unwrap();
        let rd = m.get::<RoughDiffuseMaterial>().unwrap();
        assert_eq!(rd.model, RoughDiffuse::default());
        assert_eq!(rd.model.reflectance, Spectrum::Constant(0.5));
        assert_eq!(rd.model.alpha, 0.2);
        assert_eq!(rd.model.model, RoughDiffuseModel::OrenNayar);
        assert_eq!(m.flags(), BsdfFlags::DIFFUSE_REFLECTION);
        assert!(!m.is_textured());
        let m = load_bsdf_str(
            r#"<bsdf type="roughdiffuse"><float name="alpha" value="0.7"/><boolean name="useFastApprox" value="true"/><float name="reflectance" value="0.3"/></bsdf>"#,
        )
        .unwrap();
        let rd = m.get::<RoughDiffuseMaterial>().unwrap();
        assert_eq!(rd.model.alpha, 0.7);
        assert_eq!(rd.model.model, RoughDiffuseModel::OrenNayarFast);
        assert_eq!(rd.model.reflectance, Spectrum::Constant(0.3));
        for (xml, want) in [
            (
                r#"<bsdf type="roughdiffuse"><string name="model" value="microfacet"/></bsdf>"#,
                MicrofacetKind::Beckmann,
            ),
            (
                r#"<bsdf type="roughdiffuse"><string name="model" value="microfacet"/><string name="distribution" value="ggx"/></bsdf>"#,
                MicrofacetKind::Ggx,
            ),
        ] {
            let m = load_bsdf_str(xml).unwrap();
            let rd = m.get::<RoughDiffuseMaterial>().unwrap();
            assert_eq!(rd.model.model, RoughDiffuseModel::Microfacet(want), "{xml}");
            assert!(!rd.model.pdf_is_exact());
        }
    }

    #[test]
    fn errors_name_the_parameter() {
        for (xml, needle) in [
            (
                r#"<bsdf type="roughdiffuse"><float name="sigma" value="0.5"/></bsdf>"#,
                "sigma",
            ),
            (
                r#"<bsdf type="roughdiffuse"><string name="useFastApprox" value="yes"/></bsdf>"#,
                "useFastApprox",
            ),
            (
                r#"<bsdf type="roughdiffuse"><string name="model" value="vgroove"/></bsdf>"#,
                "orennayar, microfacet",
            ),
            (
                r#"<bsdf type="roughdiffuse"><string name="distribution" value="ggx"/></bsdf>"#,
                "distribution applies to model=\"microfacet\"",
            ),
            (
                r#"<bsdf type="roughdiffuse"><string name="model" value="microfacet"/><boolean name="useFastApprox" value="true"/></bsdf>"#,
                "useFastApprox applies to model=\"orennayar\"",
            ),
            (
                r#"<bsdf type="roughdiffuse"><string name="model" value="microfacet"/><string name="distribution" value="phong"/></bsdf>"#,
                "beckmann, ggx",
            ),
        ] {
            let e = load_bsdf_str(xml).unwrap_err().to_string();
            assert!(e.contains(needle) && e.contains(":1:"), "{xml}: {e}");
        }
    }

    #[test]
    fn textured_roughness_is_looked_up_per_hit() {
        let m = load_bsdf_str(
            r#"<bsdf type="roughdiffuse">
                 <texture type="checkerboard" name="alpha">
                   <float name="color0" value="0"/>
                   <float name="color1" value="1"/>
                 </texture>
               </bsdf>"#,
        )
        .unwrap();
        assert!(m.is_textured());
        let wl = SampledWavelengths::fixed(550.0);
        let ctx = BsdfContext::radiance();
        let (wi, wo) = (glam::Vec3::new(0.8, 0.0, 0.6), glam::Vec3::new(0.6, 0.0, 0.8));
        let mut got: Vec<f32> = [Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.25)]
            .iter()
            .map(|uv| m.bsdf_at(*uv, &wl).eval(&ctx, wi, wo, &wl)[0])
            .collect();
        let expect = |alpha: f32| {
            RoughDiffuse::new(Spectrum::Constant(0.5), alpha, RoughDiffuseModel::OrenNayar)
                .eval(&ctx, wi, wo, &wl)[0]
        };
        let mut want = [expect(0.0), expect(1.0)];
        got.sort_by(f32::total_cmp);
        want.sort_by(f32::total_cmp);
        assert_eq!(got, want);
        assert!(want[0] != want[1]);
    }
}
