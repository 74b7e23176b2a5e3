//! `hair`: Chiang et al.'s near-field hair fibre (core model [`gonio_core::bsdfs::Hair`]; Mitsuba 3
//! `src/bsdfs/hair.cpp`).
//!
//! Meant for the curve shapes (`bsplinecurve`, `linearcurve`), whose shading frame runs its
//! second tangent along the fibre (the model's y axis) and which, as in Mitsuba, cannot be hit
//! from inside: the light a fibre transmits (TT) leaves through it unhindered. On other shapes the
//! frame's tangent stands in for the fibre's direction.
//!
//! The model is a near-field one made for path tracing: light that reaches the camera through a
//! fibre enters and leaves where the camera ray meets it. A light tracer (`ptracer`, and the
//! `path` integrator's caustic light subpaths that end on a fibre) meets the fibre where the
//! *light* does and connects that point to the camera through the fibre, a different
//! approximation of the same walk: on the test strands (`bsdf_hair_strands`) `ptracer` renders
//! them at 0.6–0.9 of the path tracer, whose image is Mitsuba's. (The open ends of `bsplinecurve`
//! let light into a tube that then leaves it through the wall, which makes a light tracer differ
//! a little on any material: +5 % for diffuse strands there, 1.00 with the capped `linearcurve`.)
//!
//! (On `linearcurve` Mitsuba 3.9.1's shading
//! frame is `coordinate_system(n)`, not along the fibre, so its hair there lies at an arbitrary
//! angle; later Mitsuba versions follow the fibre, as gonio does on both curves.)

use super::dielectric::EXT_IOR;
use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{Hair, HairAbsorption, HairLobes, LeafBsdf, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const EUMELANIN: ParamSpec = ParamSpec::new(
    "eumelanin",
    ParamType::Float,
    DefaultValue::Float(1.3),
    "eumelanin concentration (dark brown pigment); with `pheomelanin`, instead of `sigma_a`",
);
const PHEOMELANIN: ParamSpec = ParamSpec::new(
    "pheomelanin",
    ParamType::Float,
    DefaultValue::Float(0.2),
    "pheomelanin concentration (red-yellow pigment)",
);
const SIGMA_A: ParamSpec = ParamSpec::new(
    "sigma_a",
    ParamType::Texture,
    DefaultValue::None,
    "absorption coefficient per unit fibre radius, instead of the pigments",
);
const SCALE: ParamSpec = ParamSpec::new(
    "scale",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "factor on `sigma_a`",
);
const INT_IOR: ParamSpec = ParamSpec::new(
    "int_ior",
    ParamType::Ior,
    DefaultValue::Str("amber"),
    "the fibre's index (a number or a named material; its value at 589.3 nm when dispersive)",
);
const LONGITUDINAL_ROUGHNESS: ParamSpec = ParamSpec::new(
    "longitudinal_roughness",
    ParamType::Float,
    DefaultValue::Float(0.3),
    "βm in [0, 1]: width of the lobes along the fibre",
);
const AZIMUTHAL_ROUGHNESS: ParamSpec = ParamSpec::new(
    "azimuthal_roughness",
    ParamType::Float,
    DefaultValue::Float(0.3),
    "βn in [0, 1]: width of the lobes about the fibre",
);
const SCALE_TILT: ParamSpec = ParamSpec::new(
    "scale_tilt",
    ParamType::Float,
    DefaultValue::Float(2.0),
    "α, the tilt of the cuticle's scales in degrees",
);

/// The `hair` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "hair",
    summary: "Hair fibre (Chiang et al. 2016): R, TT, TRT and the rest, pigments or an absorption coefficient; for the curve shapes.",
    params: &[
        EUMELANIN,
        PHEOMELANIN,
        SIGMA_A,
        SCALE,
        INT_IOR,
        EXT_IOR,
        LONGITUDINAL_ROUGHNESS,
        AZIMUTHAL_ROUGHNESS,
        SCALE_TILT,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    if p.has(SIGMA_A.name) {
        for pigment in [EUMELANIN.name, PHEOMELANIN.name] {
            if p.has(pigment) {
                let loc = p.get(pigment).expect("present").loc.clone();
                return Err(SceneError::new(
                    loc,
                    ErrorKind::Grammar,
                    format!(
                        "{} takes either the pigments or `sigma_a`, not both (`{pigment}` given with `sigma_a`)",
                        p.what()
                    ),
                ));
            }
        }
    }
    let non_negative = |v: f64| v >= 0.0;
    let unit = |v: f64| (0.0..=1.0).contains(&v);
    let eumelanin = p.float_checked(
        EUMELANIN.name,
        EUMELANIN.default.float(),
        non_negative,
        "must be ≥ 0",
    )?;
    let pheomelanin = p.float_checked(
        PHEOMELANIN.name,
        PHEOMELANIN.default.float(),
        non_negative,
        "must be ≥ 0",
    )?;
    let scale = p.float_checked(SCALE.name, SCALE.default.float(), non_negative, "must be ≥ 0")? as f32;
    let beta_m = p.float_checked(
        LONGITUDINAL_ROUGHNESS.name,
        LONGITUDINAL_ROUGHNESS.default.float(),
        unit,
        "must be in [0, 1]",
    )?;
    let beta_n = p.float_checked(
        AZIMUTHAL_ROUGHNESS.name,
        AZIMUTHAL_ROUGHNESS.default.float(),
        unit,
        "must be in [0, 1]",
    )?;
    let tilt = p.float_checked(
        SCALE_TILT.name,
        SCALE_TILT.default.float(),
        |v| v.abs() <= 90.0,
        "must be in [−90°, 90°]",
    )?;
    let int_ior = b.ior(p, &INT_IOR)?.nominal();
    let ext_ior = b.ior(p, &EXT_IOR)?.nominal();
    if int_ior == ext_ior {
        let loc = p
            .get(INT_IOR.name)
            .or_else(|| p.get(EXT_IOR.name))
            .map(|prop| prop.loc.clone())
            .unwrap_or_else(|| b.object(p).loc.clone());
        return Err(SceneError::new(
            loc,
            ErrorKind::BadValue,
            format!(
                "{}: the interior and exterior indices must differ (both {int_ior})",
                p.what()
            ),
        ));
    }
    let sigma_a = if p.has(SIGMA_A.name) {
        Some(b.texture(p, &SIGMA_A, RgbKind::Albedo)?)
    } else {
        None
    };
    let lobes = HairLobes::new(beta_m as f32, beta_n as f32, tilt as f32);
    Ok(Material::new(HairMaterial::new(
        sigma_a,
        scale,
        eumelanin as f32,
        pheomelanin as f32,
        int_ior / ext_ior,
        lobes,
    )))
}

/// `scale`·σa (a spectrum `Spectrum::scaled` cannot scale, a dispersion formula, absorbs nothing).
fn scaled_sigma(sigma_a: gonio_core::Spectrum, scale: f32) -> HairAbsorption {
    HairAbsorption::Sigma(
        sigma_a
            .scaled(scale)
            .unwrap_or(gonio_core::Spectrum::Constant(0.0)),
    )
}

/// `hair` in a scene.
#[derive(Clone, Debug)]
pub struct HairMaterial {
    /// σa when given (else the pigments of `model`), and its factor.
    pub sigma_a: Option<(Texture, f32)>,
    /// The model (σa's mean when textured).
    pub model: Hair,
}

impl HairMaterial {
    /// A fibre of absorption `scale`·σa, or of the pigments when `sigma_a` is `None`.
    pub fn new(
        sigma_a: Option<Texture>,
        scale: f32,
        eumelanin: f32,
        pheomelanin: f32,
        eta: f32,
        lobes: HairLobes,
    ) -> Self {
        let absorption = match &sigma_a {
            Some(t) => scaled_sigma(super::model_value(t), scale),
            None => HairAbsorption::pigments(eumelanin, pheomelanin),
        };
        Self {
            sigma_a: sigma_a.map(|t| (t, scale)),
            model: Hair {
                sigma_a: absorption,
                eta,
                lobes,
            },
        }
    }

    fn textured_sigma_a(&self) -> Option<&(Texture, f32)> {
        self.sigma_a.as_ref().filter(|(t, _)| t.is_textured())
    }
}

impl SurfaceMaterial for HairMaterial {
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.textured_sigma_a().is_some()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        if let Some((t, scale)) = self.textured_sigma_a() {
            m.sigma_a = t.eval(uv).sample(wl) * *scale;
        }
        tree.push_leaf(LeafBsdf::Hair(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        match self.textured_sigma_a() {
            Some((t, scale)) => f(&Hair {
                sigma_a: scaled_sigma(t.eval(uv), *scale),
                eta: self.model.eta,
                lobes: self.model.lobes,
            }),
            None => f(&self.model),
        }
    }
}
