//! `principled`: the Disney BSDF (core model [`gonio_core::bsdfs::Principled`]; Mitsuba 3
//! `src/bsdfs/principled.cpp`).
//!
//! As in Mitsuba, every parameter but `eta`, `specular` and the sampling rates may be a texture,
//! looked up per hit (`base_color` as a spectrum, the others with `eval_1`); `eta` and `specular`
//! are exclusive. A lobe is present (in the flags) when its parameter is given and is not the
//! number 0 (Mitsuba's `get_flag`).

use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::principled::{PrincipledRates, eta_from_specular};
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, Principled, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const fn weight(name: &'static str, default: f64, doc: &'static str) -> ParamSpec {
    ParamSpec::new(name, ParamType::Texture, DefaultValue::Float(default), doc)
}

pub(crate) const BASE_COLOR: ParamSpec = weight("base_color", 0.5, "c, the base colour");
pub(crate) const ROUGHNESS: ParamSpec = weight(
    "roughness",
    0.5,
    "r ∈ [0, 1]: GGX α = r² (at least 10⁻³) of the main lobes, and the diffuse retro-reflection",
);
pub(crate) const ANISOTROPIC: ParamSpec = weight(
    "anisotropic",
    0.0,
    "∈ [0, 1]: α_x = r²/a, α_y = r² a with a = √(1 − 0.9 anisotropic) (x along the tangent)",
);
const METALLIC: ParamSpec = weight(
    "metallic",
    0.0,
    "∈ [0, 1]: blend towards a Schlick metal of colour c",
);
pub(crate) const SPEC_TRANS: ParamSpec = weight(
    "spec_trans",
    0.0,
    "∈ [0, 1]: blend of the dielectric BRDF towards the rough dielectric BSDF (transmission)",
);
pub(crate) const ETA: ParamSpec = ParamSpec::new(
    "eta",
    ParamType::Float,
    DefaultValue::Derived("from `specular`"),
    "η = n_int/n_ext (> 0); not with `specular`",
);
pub(crate) const SPECULAR: ParamSpec = ParamSpec::new(
    "specular",
    ParamType::Float,
    DefaultValue::Float(0.5),
    "∈ [0, 12.5): η = 2/(1 − √(0.08 specular)) − 1 (0.5 gives η = 1.5); not with `eta`",
);
pub(crate) const SPEC_TINT: ParamSpec = weight(
    "spec_tint",
    0.0,
    "∈ [0, 1]: fraction of the dielectric reflection tinted towards c",
);
pub(crate) const SHEEN: ParamSpec = weight(
    "sheen",
    0.0,
    "weight of the sheen lobe (grazing retro-reflection of cloth)",
);
pub(crate) const SHEEN_TINT: ParamSpec = weight("sheen_tint", 0.0, "∈ [0, 1]: tint of the sheen towards c");
pub(crate) const FLATNESS: ParamSpec = weight(
    "flatness",
    0.0,
    "∈ [0, 1]: blend of diffuse + retro-reflection towards the Hanrahan–Krueger fake subsurface",
);
const CLEARCOAT: ParamSpec = weight(
    "clearcoat",
    0.0,
    "weight of the clearcoat (GTR1, Schlick R0 = 0.04)",
);
const CLEARCOAT_GLOSS: ParamSpec = weight(
    "clearcoat_gloss",
    0.0,
    "∈ [0, 1]: clearcoat roughness α = 0.1 (gloss 0) … 0.001 (gloss 1)",
);
pub(crate) const DIFFUSE_RATE: ParamSpec = ParamSpec::new(
    "diffuse_reflectance_sampling_rate",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "relative rate of sampling the diffuse lobe (≥ 0)",
);
const SPECULAR_RATE: ParamSpec = ParamSpec::new(
    "main_specular_sampling_rate",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "relative rate of sampling the main specular lobes (≥ 0)",
);
pub(crate) const CLEARCOAT_RATE: ParamSpec = ParamSpec::new(
    "clearcoat_sampling_rate",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "relative rate of sampling the clearcoat (≥ 0; Mitsuba's docs say 0, its code uses 1)",
);

/// The `principled` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "principled",
    summary: "The Disney principled BSDF (Burley 2012, 2015): diffuse with retro-reflection, sheen, GGX specular reflection and transmission, metallic, clearcoat; Mitsuba's lobes and sampling.",
    params: &[
        BASE_COLOR,
        ROUGHNESS,
        ANISOTROPIC,
        METALLIC,
        SPEC_TRANS,
        ETA,
        SPECULAR,
        SPEC_TINT,
        SHEEN,
        SHEEN_TINT,
        FLATNESS,
        CLEARCOAT,
        CLEARCOAT_GLOSS,
        DIFFUSE_RATE,
        SPECULAR_RATE,
        CLEARCOAT_RATE,
    ],
    build,
};

/// An error at the value of parameter `name` (or at the object when it is absent).
pub(crate) fn bad_value(b: &Builder<'_>, p: &Params<'_>, name: &str, msg: String) -> SceneError {
    let obj = b.object(p);
    let loc = obj
        .props
        .iter()
        .find(|x| x.name == name)
        .map_or(&obj.loc, |x| &x.value_loc);
    SceneError::new(loc.clone(), ErrorKind::BadValue, msg)
}

/// A float-or-texture parameter of plugin `plugin`; a constant must be at most `max` when given
/// (a blend weight beyond its range would make another lobe's weight negative).
pub(crate) fn scalar_texture<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    spec: &ParamSpec,
    max: Option<f32>,
    plugin: &str,
) -> Result<Texture, SceneError> {
    let t = b.texture(p, spec, RgbKind::Unbounded)?;
    if let Some(max) = max {
        let v = t.eval_1(Vec2::ZERO);
        if !t.is_textured() && v > max {
            return Err(bad_value(
                b,
                p,
                spec.name,
                format!("invalid {} {v} in {plugin} (must be in [0, {max}])", spec.name),
            ));
        }
    }
    Ok(t)
}

/// Mitsuba's `get_flag`: the parameter is given and is not the number 0.
pub(crate) fn has_lobe(t: &Texture) -> bool {
    t.is_textured() || t.eval_1(Vec2::ZERO) != 0.0
}

/// η from `eta` or `specular` (exclusive), with Mitsuba's guard for a transmitting surface
/// (η = 1 becomes 1.001, `specular` = 0 becomes 10⁻³).
pub(crate) fn read_eta<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    transmits: bool,
    plugin: &str,
) -> Result<f32, SceneError> {
    if p.has(ETA.name) && p.has(SPECULAR.name) {
        return Err(bad_value(
            b,
            p,
            SPECULAR.name,
            format!("{plugin}: specify either eta or specular, not both"),
        ));
    }
    if p.has(ETA.name) {
        let eta = p.float_checked(ETA.name, 1.5, |v| v > 0.0, "must be > 0")? as f32;
        return Ok(if transmits && eta == 1.0 { 1.001 } else { eta });
    }
    let specular = p.float_checked(
        SPECULAR.name,
        SPECULAR.default.float(),
        |v| (0.0..12.5).contains(&v),
        "must be in [0, 12.5)",
    )? as f32;
    let specular = if transmits && specular == 0.0 {
        1e-3
    } else {
        specular
    };
    Ok(eta_from_specular(specular))
}

fn rate(p: &mut Params<'_>, spec: &ParamSpec) -> Result<f32, SceneError> {
    Ok(p.float_checked(spec.name, spec.default.float(), |v| v >= 0.0, "must be ≥ 0")? as f32)
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let textures = PrincipledTextures {
        base_color: b.texture(p, &BASE_COLOR, RgbKind::Albedo)?,
        roughness: scalar_texture(b, p, &ROUGHNESS, None, PLUGIN.name)?,
        anisotropic: scalar_texture(b, p, &ANISOTROPIC, Some(1.0), PLUGIN.name)?,
        metallic: scalar_texture(b, p, &METALLIC, Some(1.0), PLUGIN.name)?,
        spec_trans: scalar_texture(b, p, &SPEC_TRANS, Some(1.0), PLUGIN.name)?,
        spec_tint: scalar_texture(b, p, &SPEC_TINT, Some(1.0), PLUGIN.name)?,
        sheen: scalar_texture(b, p, &SHEEN, None, PLUGIN.name)?,
        sheen_tint: scalar_texture(b, p, &SHEEN_TINT, Some(1.0), PLUGIN.name)?,
        flatness: scalar_texture(b, p, &FLATNESS, Some(1.0), PLUGIN.name)?,
        clearcoat: scalar_texture(b, p, &CLEARCOAT, None, PLUGIN.name)?,
        clearcoat_gloss: scalar_texture(b, p, &CLEARCOAT_GLOSS, Some(1.0), PLUGIN.name)?,
    };
    let eta = read_eta(b, p, has_lobe(&textures.spec_trans), "principled")?;
    let rates = PrincipledRates {
        diffuse: rate(p, &DIFFUSE_RATE)?,
        main_specular: rate(p, &SPECULAR_RATE)?,
        clearcoat: rate(p, &CLEARCOAT_RATE)?,
    };
    Ok(Material::new(PrincipledMaterial::new(textures, eta, rates)))
}

/// The textured parameters of `principled`.
#[derive(Clone, Debug)]
pub struct PrincipledTextures {
    /// c.
    pub base_color: Texture,
    /// r.
    pub roughness: Texture,
    /// Anisotropy.
    pub anisotropic: Texture,
    /// Metallic blend.
    pub metallic: Texture,
    /// Transmission blend.
    pub spec_trans: Texture,
    /// Specular tint.
    pub spec_tint: Texture,
    /// Sheen weight.
    pub sheen: Texture,
    /// Sheen tint.
    pub sheen_tint: Texture,
    /// Fake-subsurface blend.
    pub flatness: Texture,
    /// Clearcoat weight.
    pub clearcoat: Texture,
    /// Clearcoat gloss.
    pub clearcoat_gloss: Texture,
}

impl PrincipledTextures {
    /// True when a float parameter (not the base colour) varies over the surface.
    fn scalars_textured(&self) -> bool {
        [
            &self.roughness,
            &self.anisotropic,
            &self.metallic,
            &self.spec_trans,
            &self.spec_tint,
            &self.sheen,
            &self.sheen_tint,
            &self.flatness,
            &self.clearcoat,
            &self.clearcoat_gloss,
        ]
        .iter()
        .any(|t| t.is_textured())
    }

    /// The float parameters of `m` at `uv` (`eval_1`).
    fn set_scalars<S>(&self, m: &mut Principled<S>, uv: Vec2) {
        m.roughness = self.roughness.eval_1(uv);
        m.anisotropic = self.anisotropic.eval_1(uv);
        m.metallic = self.metallic.eval_1(uv);
        m.spec_trans = self.spec_trans.eval_1(uv);
        m.spec_tint = self.spec_tint.eval_1(uv);
        m.sheen = self.sheen.eval_1(uv);
        m.sheen_tint = self.sheen_tint.eval_1(uv);
        m.flatness = self.flatness.eval_1(uv);
        m.clearcoat = self.clearcoat.eval_1(uv);
        m.clearcoat_gloss = self.clearcoat_gloss.eval_1(uv);
    }
}

/// `principled` in a scene.
#[derive(Clone, Debug)]
pub struct PrincipledMaterial {
    /// The parameters as given.
    pub textures: PrincipledTextures,
    /// The model with the parameters' values (textured ones at uv = 0, replaced per hit).
    pub model: Principled,
    flags: BsdfFlags,
}

impl PrincipledMaterial {
    /// The material of these parameters, index and sampling rates.
    pub fn new(textures: PrincipledTextures, eta: f32, rates: PrincipledRates) -> Self {
        let mut model = Principled::new(model_value(&textures.base_color));
        // Untextured parameters are their values; textured ones are looked up per hit.
        textures.set_scalars(&mut model, Vec2::ZERO);
        model.eta = eta;
        model.rates = rates;
        let mut flags = BsdfFlags::DIFFUSE_REFLECTION | BsdfFlags::GLOSSY_REFLECTION;
        if has_lobe(&textures.spec_trans) {
            flags = flags | BsdfFlags::GLOSSY_TRANSMISSION | BsdfFlags::NON_SYMMETRIC;
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

impl SurfaceMaterial for PrincipledMaterial {
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
        tree.push_leaf(LeafBsdf::Principled(m))
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
    fn mitsuba_defaults() {
        let m = load_bsdf_str(r#"<bsdf type="principled"/>"#).unwrap();
        let pm = m.get::<PrincipledMaterial>().unwrap();
        assert_eq!(pm.model, Principled::default());
        assert!((pm.model.eta - 1.5).abs() < 1e-6);
        assert_eq!(
            m.flags(),
            BsdfFlags::DIFFUSE_REFLECTION | BsdfFlags::GLOSSY_REFLECTION
        );
        assert!(!m.is_textured());
    }

    #[test]
    fn parameters_and_flags() {
        let m = load_bsdf_str(
            r#"<bsdf type="principled">
                 <rgb name="base_color" value="0.8, 0.2, 0.1"/>
                 <float name="spec_trans" value="0.4"/>
                 <float name="anisotropic" value="0.5"/>
                 <float name="eta" value="1"/>
                 <float name="clearcoat_sampling_rate" value="0.5"/>
               </bsdf>"#,
        )
        .unwrap();
        let pm = m.get::<PrincipledMaterial>().unwrap();
        assert_eq!(
            pm.model.eta, 1.001,
            "η = 1 is moved off 1 for a transmitting surface"
        );
        assert_eq!(pm.model.rates.clearcoat, 0.5);
        assert!(
            m.flags()
                .contains(BsdfFlags::GLOSSY_TRANSMISSION | BsdfFlags::ANISOTROPIC)
        );
        let zero =
            load_bsdf_str(r#"<bsdf type="principled"><float name="spec_trans" value="0"/></bsdf>"#).unwrap();
        assert!(
            !zero.flags().is_transmission(),
            "a zero parameter is no lobe (get_flag)"
        );
    }

    #[test]
    fn mitsuba_errors() {
        for (xml, needle) in [
            (
                r#"<bsdf type="principled"><float name="eta" value="1.3"/><float name="specular" value="0.4"/></bsdf>"#,
                "either eta or specular",
            ),
            (
                r#"<bsdf type="principled"><float name="metallic" value="1.5"/></bsdf>"#,
                "invalid metallic 1.5",
            ),
            (
                r#"<bsdf type="principled"><float name="eta" value="-1"/></bsdf>"#,
                "invalid eta",
            ),
            (
                r#"<bsdf type="principled"><float name="diff_trans" value="0.5"/></bsdf>"#,
                "diff_trans",
            ),
        ] {
            let e = load_bsdf_str(xml).unwrap_err().to_string();
            assert!(e.contains(needle), "{xml}: {e}");
        }
    }

    #[test]
    fn textured_parameters_are_looked_up_per_hit() {
        let m = load_bsdf_str(
            r#"<bsdf type="principled">
                 <texture type="checkerboard" name="roughness">
                   <float name="color0" value="0.1"/><float name="color1" value="0.9"/>
                 </texture>
                 <texture type="checkerboard" name="base_color"/>
               </bsdf>"#,
        )
        .unwrap();
        assert!(m.is_textured());
        let wl = SampledWavelengths::fixed(550.0);
        let ctx = gonio_core::BsdfContext::radiance();
        let mut peaks = Vec::new();
        for uv in [Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.25)] {
            let tree = m.bsdf_at(uv, &wl);
            let peak = tree.eval(&ctx, glam::Vec3::Z, glam::Vec3::Z, &wl)[0];
            let any = m.with_bsdf(uv, |b| b.eval(&ctx, glam::Vec3::Z, glam::Vec3::Z, &wl)[0]);
            assert_eq!(any, peak);
            peaks.push(peak);
        }
        assert!(
            peaks[0] > 10.0 * peaks[1] || peaks[1] > 10.0 * peaks[0],
            "{peaks:?}"
        );
    }
}
