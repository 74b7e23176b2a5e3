//! `principledthin`: the thin-sheet Disney BSDF (core model
//! [`gonio_core::bsdfs::PrincipledThin`]; Mitsuba 3 `src/bsdfs/principledthin.cpp`).
//!
//! As in Mitsuba, every parameter but the sampling rates may be a texture, looked up per hit
//! (`base_color` as a spectrum, the others, `eta` included, with `eval_1`).

use super::principled::{
    ANISOTROPIC, BASE_COLOR, DIFFUSE_RATE, FLATNESS, ROUGHNESS, SHEEN, SHEEN_TINT, SPEC_TINT, bad_value,
    has_lobe, scalar_texture,
};
use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::principledthin::PrincipledThinRates;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, PrincipledThin, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const SPEC_TRANS: ParamSpec = ParamSpec::new(
    "spec_trans",
    ParamType::Texture,
    DefaultValue::Float(0.0),
    "∈ [0, 1]: blend of the diffuse response (0) towards the specular reflection and transmission (1)",
);
const ETA: ParamSpec = ParamSpec::new(
    "eta",
    ParamType::Texture,
    DefaultValue::Float(1.5),
    "η of the sheet (> 0): its Fresnel reflectance and the transmission's roughness (0.65 η − 0.35) r",
);
const DIFF_TRANS: ParamSpec = ParamSpec::new(
    "diff_trans",
    ParamType::Texture,
    DefaultValue::Float(0.0),
    "∈ [0, 2]: diff_trans/2 of the diffuse response leaves on the far side (Lambertian)",
);
const SPEC_REFL_RATE: ParamSpec = ParamSpec::new(
    "specular_reflectance_sampling_rate",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "relative rate of sampling the specular reflection (≥ 0)",
);
const SPEC_TRANS_RATE: ParamSpec = ParamSpec::new(
    "specular_transmittance_sampling_rate",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "relative rate of sampling the specular transmission (≥ 0)",
);
const DIFF_TRANS_RATE: ParamSpec = ParamSpec::new(
    "diffuse_transmittance_sampling_rate",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "relative rate of sampling the diffuse transmission (≥ 0)",
);

/// The `principledthin` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "principledthin",
    summary: "The thin-sheet Disney BSDF (Burley 2015): both sides alike, specular reflection and unbent rough transmission, diffuse with retro-reflection and sheen, Lambertian transmission; Mitsuba's lobes and sampling.",
    params: &[
        BASE_COLOR,
        ROUGHNESS,
        ANISOTROPIC,
        SPEC_TRANS,
        ETA,
        SPEC_TINT,
        SHEEN,
        SHEEN_TINT,
        FLATNESS,
        DIFF_TRANS,
        DIFFUSE_RATE,
        SPEC_REFL_RATE,
        SPEC_TRANS_RATE,
        DIFF_TRANS_RATE,
    ],
    build,
};

fn rate(p: &mut Params<'_>, spec: &ParamSpec) -> Result<f32, SceneError> {
    Ok(p.float_checked(spec.name, spec.default.float(), |v| v >= 0.0, "must be ≥ 0")? as f32)
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let name = PLUGIN.name;
    let textures = PrincipledThinTextures {
        base_color: b.texture(p, &BASE_COLOR, RgbKind::Albedo)?,
        roughness: scalar_texture(b, p, &ROUGHNESS, None, name)?,
        anisotropic: scalar_texture(b, p, &ANISOTROPIC, Some(1.0), name)?,
        spec_trans: scalar_texture(b, p, &SPEC_TRANS, Some(1.0), name)?,
        eta: scalar_texture(b, p, &ETA, None, name)?,
        spec_tint: scalar_texture(b, p, &SPEC_TINT, Some(1.0), name)?,
        sheen: scalar_texture(b, p, &SHEEN, None, name)?,
        sheen_tint: scalar_texture(b, p, &SHEEN_TINT, Some(1.0), name)?,
        flatness: scalar_texture(b, p, &FLATNESS, Some(1.0), name)?,
        diff_trans: scalar_texture(b, p, &DIFF_TRANS, Some(2.0), name)?,
    };
    if !textures.eta.is_textured() && textures.eta.eval_1(Vec2::ZERO) <= 0.0 {
        return Err(bad_value(
            b,
            p,
            ETA.name,
            "invalid eta 0 in principledthin (must be > 0)".into(),
        ));
    }
    let rates = PrincipledThinRates {
        diffuse_reflectance: rate(p, &DIFFUSE_RATE)?,
        specular_reflectance: rate(p, &SPEC_REFL_RATE)?,
        specular_transmittance: rate(p, &SPEC_TRANS_RATE)?,
        diffuse_transmittance: rate(p, &DIFF_TRANS_RATE)?,
    };
    Ok(Material::new(PrincipledThinMaterial::new(textures, rates)))
}

/// The textured parameters of `principledthin`.
#[derive(Clone, Debug)]
pub struct PrincipledThinTextures {
    /// c.
    pub base_color: Texture,
    /// r.
    pub roughness: Texture,
    /// Anisotropy.
    pub anisotropic: Texture,
    /// s.
    pub spec_trans: Texture,
    /// η of the sheet.
    pub eta: Texture,
    /// Specular tint.
    pub spec_tint: Texture,
    /// Sheen weight.
    pub sheen: Texture,
    /// Sheen tint.
    pub sheen_tint: Texture,
    /// Fake-subsurface blend.
    pub flatness: Texture,
    /// Diffuse transmission, [0, 2].
    pub diff_trans: Texture,
}

impl PrincipledThinTextures {
    fn scalars(&self) -> [&Texture; 9] {
        [
            &self.roughness,
            &self.anisotropic,
            &self.spec_trans,
            &self.eta,
            &self.spec_tint,
            &self.sheen,
            &self.sheen_tint,
            &self.flatness,
            &self.diff_trans,
        ]
    }

    /// True when a float parameter varies over the surface.
    fn scalars_textured(&self) -> bool {
        self.scalars().iter().any(|t| t.is_textured())
    }

    /// The float parameters of `m` at `uv` (`eval_1`).
    fn set_scalars<S>(&self, m: &mut PrincipledThin<S>, uv: Vec2) {
        [
            m.roughness,
            m.anisotropic,
            m.spec_trans,
            m.eta,
            m.spec_tint,
            m.sheen,
            m.sheen_tint,
            m.flatness,
            m.diff_trans,
        ] = self.scalars().map(|t| t.eval_1(uv));
    }
}

/// `principledthin` in a scene.
#[derive(Clone, Debug)]
pub struct PrincipledThinMaterial {
    /// The parameters as given.
    pub textures: PrincipledThinTextures,
    /// The model with the parameters' values (textured ones at uv = 0, replaced per hit).
    pub model: PrincipledThin,
    flags: BsdfFlags,
}

impl PrincipledThinMaterial {
    /// The material of these parameters and sampling rates.
    pub fn new(textures: PrincipledThinTextures, rates: PrincipledThinRates) -> Self {
        let mut model = PrincipledThin::new(model_value(&textures.base_color));
        textures.set_scalars(&mut model, Vec2::ZERO);
        model.rates = rates;
        let mut flags = BsdfFlags::DIFFUSE_REFLECTION | BsdfFlags::GLOSSY_REFLECTION;
        if has_lobe(&textures.spec_trans) {
            flags = flags | BsdfFlags::GLOSSY_TRANSMISSION;
        }
        if has_lobe(&textures.diff_trans) {
            flags = flags | BsdfFlags::DIFFUSE_TRANSMISSION;
        }
        if has_lobe(&textures.anisotropic) {
            flags = flags | BsdfFlags::ANISOTROPIC;
        }
        Self {
            textures,
            model,
            flags,
        }
    }
}

impl SurfaceMaterial for PrincipledThinMaterial {
    fn flags(&self) -> BsdfFlags {
        self.flags
    }
    fn is_textured(&self) -> bool {
        self.textures.base_color.is_textured() || self.textures.scalars_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.base_color, &self.textures.base_color, uv, wl);
        if self.textures.scalars_textured() {
            self.textures.set_scalars(&mut m, uv);
        }
        tree.push_leaf(LeafBsdf::PrincipledThin(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if !self.is_textured() {
            return f(&self.model);
        }
        let mut m = self.model.clone();
        m.base_color = self.textures.base_color.eval(uv);
        self.textures.set_scalars(&mut m, uv);
        f(&m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xml::load_bsdf_str;

    #[test]
    fn mitsuba_defaults_and_flags() {
        let m = load_bsdf_str(r#"<bsdf type="principledthin"/>"#).unwrap();
        let pm = m.get::<PrincipledThinMaterial>().unwrap();
        assert_eq!(pm.model, PrincipledThin::default());
        assert_eq!(
            m.flags(),
            BsdfFlags::DIFFUSE_REFLECTION | BsdfFlags::GLOSSY_REFLECTION
        );
        let t = load_bsdf_str(
            r#"<bsdf type="principledthin"><float name="diff_trans" value="1.5"/><float name="spec_trans" value="0.5"/></bsdf>"#,
        )
        .unwrap();
        assert!(
            t.flags()
                .contains(BsdfFlags::DIFFUSE_TRANSMISSION | BsdfFlags::GLOSSY_TRANSMISSION)
        );
        assert_eq!(t.get::<PrincipledThinMaterial>().unwrap().model.diff_trans, 1.5);
    }

    #[test]
    fn mitsuba_errors() {
        for (xml, needle) in [
            (
                r#"<bsdf type="principledthin"><float name="diff_trans" value="2.5"/></bsdf>"#,
                "invalid diff_trans 2.5",
            ),
            (
                r#"<bsdf type="principledthin"><float name="eta" value="0"/></bsdf>"#,
                "invalid eta",
            ),
            (
                r#"<bsdf type="principledthin"><float name="metallic" value="0.5"/></bsdf>"#,
                "metallic",
            ),
        ] {
            let e = load_bsdf_str(xml).unwrap_err().to_string();
            assert!(e.contains(needle), "{xml}: {e}");
        }
    }
}
