//! `lambertsphere` (ours): a half-space of sparse Lambertian spheres, d'Eon 2021, "An Analytic
//! BRDF for Materials with Spherical Lambertian Scatterers" (core model
//! [`gonio_core::bsdfs::LambertSphere`]). Neither Mitsuba 3 nor pbrt-v4 has it; the author's
//! Mitsuba 0.6 fork calls it `lambert_sphere`, with one `reflectance`.
//!
//! `reflectance` is the material's albedo k_d (so `diffuse` can be swapped for
//! `lambertsphere` keeping its number), mapped per wavelength to the sphere albedo c by the
//! paper's Eq. 46; `sphere_albedo` gives c instead (one or the other). Either may be a texture,
//! looked up per hit.

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::lambertsphere::{AlbedoParameter, LambertSphereModel};
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LambertSphere, LeafBsdf, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const REFLECTANCE: ParamSpec = ParamSpec::new(
    "reflectance",
    ParamType::Texture,
    DefaultValue::Float(0.5),
    "k_d, the material's albedo (≈ its bihemispherical reflectance), mapped to the sphere albedo by d'Eon's Eq. 46",
);
const SPHERE_ALBEDO: ParamSpec = ParamSpec::new(
    "sphere_albedo",
    ParamType::Texture,
    DefaultValue::None,
    "c, the spheres' own (single-scattering) albedo, instead of `reflectance`",
);
const MODEL: ParamSpec = ParamSpec::new(
    "model",
    ParamType::String,
    DefaultValue::Str("exact"),
    "`exact` (tabulated H-functions: white stays white, within 0.1 % of the true half-space) or `practical` (the paper's fits: no table, 2 % low near c = 1)",
);

/// The `lambertsphere` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "lambertsphere",
    summary: "(ours) A half-space of sparse Lambertian spheres (d'Eon 2021): strong retro-reflection at grazing angles and saturated colours; one-sided.",
    params: &[REFLECTANCE, SPHERE_ALBEDO, MODEL],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let (albedo, albedo_is) = if p.has(SPHERE_ALBEDO.name) {
        if p.has(REFLECTANCE.name) {
            let loc = p.get(REFLECTANCE.name).expect("present").loc.clone();
            return Err(SceneError::new(
                loc,
                ErrorKind::Grammar,
                "lambertsphere: specify either reflectance or sphere_albedo, not both".to_string(),
            ));
        }
        (
            b.texture(p, &SPHERE_ALBEDO, RgbKind::Albedo)?,
            AlbedoParameter::Sphere,
        )
    } else {
        (
            b.texture(p, &REFLECTANCE, RgbKind::Albedo)?,
            AlbedoParameter::Reflectance,
        )
    };
    let name = p.choice(MODEL.name, MODEL.default.str(), &["exact", "practical"])?;
    let model = LambertSphereModel::from_name(name).expect("one of the choices");
    Ok(Material::new(LambertSphereMaterial::new(
        albedo, albedo_is, model,
    )))
}

/// `lambertsphere` in a scene.
#[derive(Clone, Debug)]
pub struct LambertSphereMaterial {
    /// k_d or c (as the model's `albedo_is` says).
    pub albedo: Texture,
    /// The model (the albedo's mean when textured).
    pub model: LambertSphere,
}

impl LambertSphereMaterial {
    /// A Lambert-sphere material of albedo `albedo`, read as `albedo_is` says.
    pub fn new(albedo: Texture, albedo_is: AlbedoParameter, model: LambertSphereModel) -> Self {
        let model = LambertSphere::new(model_value(&albedo), albedo_is, model);
        Self { albedo, model }
    }
}

impl SurfaceMaterial for LambertSphereMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.albedo.is_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let m = if self.albedo.is_textured() {
            let mut textured = self.model.clone();
            textured.albedo = self.albedo.eval(uv);
            textured.at(wl)
        } else {
            self.model.at(wl)
        };
        tree.push_leaf(LeafBsdf::LambertSphere(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if self.albedo.is_textured() {
            let mut m = self.model.clone();
            m.albedo = self.albedo.eval(uv);
            f(&m)
        } else {
            f(&self.model)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xml::load_bsdf_str;
    use gonio_core::{BsdfContext, Spectrum};

    #[test]
    fn defaults_and_parameters() {
        let m = load_bsdf_str(r#"<bsdf type="lambertsphere"/>"#).unwrap();
        let ls = m.get::<LambertSphereMaterial>().unwrap();
        assert_eq!(ls.model.albedo, Spectrum::Constant(0.5));
        assert_eq!(ls.model.albedo_is, AlbedoParameter::Reflectance);
        assert_eq!(ls.model.model, LambertSphereModel::Exact);
        assert_eq!(m.flags(), BsdfFlags::DIFFUSE_REFLECTION);
        let m = load_bsdf_str(
            r#"<bsdf type="lambertsphere"><float name="sphere_albedo" value="0.9"/><string name="model" value="practical"/></bsdf>"#,
        )
        .unwrap();
        let ls = m.get::<LambertSphereMaterial>().unwrap();
        assert_eq!(ls.model.albedo, Spectrum::Constant(0.9));
        assert_eq!(ls.model.albedo_is, AlbedoParameter::Sphere);
        assert_eq!(ls.model.model, LambertSphereModel::Practical);
    }

    #[test]
    fn errors_name_the_parameter() {
        for (xml, needle) in [
            (
                r#"<bsdf type="lambertsphere"><float name="reflectance" value="0.5"/><float name="sphere_albedo" value="0.9"/></bsdf>"#,
                "not both",
            ),
            (
                r#"<bsdf type="lambertsphere"><string name="model" value="fast"/></bsdf>"#,
                "exact, practical",
            ),
            (
                r#"<bsdf type="lambertsphere"><float name="albedo" value="0.5"/></bsdf>"#,
                "albedo",
            ),
        ] {
            let e = load_bsdf_str(xml).unwrap_err().to_string();
            assert!(e.contains(needle) && e.contains(":1:"), "{xml}: {e}");
        }
    }

    #[test]
    fn textured_reflectance_is_looked_up_per_hit() {
        let m = load_bsdf_str(
            r#"<bsdf type="lambertsphere">
                 <texture type="checkerboard" name="reflectance">
                   <float name="color0" value="0.1"/>
                   <float name="color1" value="0.9"/>
                 </texture>
               </bsdf>"#,
        )
        .unwrap();
        assert!(m.is_textured());
        let wl = SampledWavelengths::fixed(550.0);
        let ctx = BsdfContext::radiance();
        let wo = glam::Vec3::new(0.6, 0.0, 0.8);
        let values: Vec<f32> = [Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.25)]
            .iter()
            .map(|uv| m.bsdf_at(*uv, &wl).eval(&ctx, glam::Vec3::Z, wo, &wl)[0])
            .collect();
        let expect = |kd: f32| {
            LambertSphere::new(
                Spectrum::Constant(kd),
                AlbedoParameter::Reflectance,
                LambertSphereModel::Exact,
            )
            .eval(&ctx, glam::Vec3::Z, wo, &wl)[0]
        };
        let mut want = [expect(0.1), expect(0.9)];
        let mut got = [values[0], values[1]];
        want.sort_by(f32::total_cmp);
        got.sort_by(f32::total_cmp);
        assert_eq!(got, want);
        assert!(want[1] > 3.0 * want[0]);
    }
}
