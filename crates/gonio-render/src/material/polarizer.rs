//! `polarizer`: an ideal linear polarizer that light crosses without deviation (core model
//! [`gonio_core::bsdfs::Polarizer`]; Mitsuba 3 `src/bsdfs/polarizer.cpp`). Unpolarized renders
//! see a filter of transmittance t/2.

use super::{
    BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, SurfaceMaterial, model_value, retint_at,
};
use crate::texture::Texture;
use crate::xml::{Builder, Params, SceneError, SpecValue, Value};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{LeafBsdf, Polarizer, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

pub(crate) const THETA: ParamSpec = ParamSpec::new(
    "theta",
    ParamType::Texture,
    DefaultValue::Float(0.0),
    "angle of the transmission (polarizer) or fast (retarder) axis, degrees (a number, a constant spectrum or a texture: its scalar value per hit)",
);
pub(crate) const TRANSMITTANCE: ParamSpec = ParamSpec::new(
    "transmittance",
    ParamType::Texture,
    DefaultValue::Float(1.0),
    "t, the transmittance of the transmitted component",
);
const POLARIZING: ParamSpec = ParamSpec::new(
    "polarizing",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "false: a non-polarizing absorber of t/2",
);

/// The `polarizer` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "polarizer",
    summary: "Ideal linear polarizer, light passes straight through (unpolarized renders: a filter of t/2).",
    params: &[THETA, TRANSMITTANCE, POLARIZING],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let theta = angle(b, p, &THETA)?;
    let transmittance = b.texture(p, &TRANSMITTANCE, RgbKind::Albedo)?;
    let polarizing = p.bool(POLARIZING.name, POLARIZING.default.bool())?;
    let model = Polarizer {
        theta: theta.eval_1(Vec2::ZERO),
        transmittance: model_value(&transmittance),
        polarizing,
    };
    Ok(Material::new(PolarizerMaterial {
        transmittance,
        theta,
        model,
    }))
}

/// An angle parameter in degrees (`theta`, `delta`) as Mitsuba accepts it: a float, a
/// `<spectrum>` of one value, or a texture (read per hit as a scalar, Mitsuba's `eval_1`).
/// A constant must be finite; the error names the file, line and value.
pub(crate) fn angle<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    spec: &ParamSpec,
) -> Result<Texture, SceneError> {
    let loc = p.obj.loc.clone();
    // A plain number may be negative (an angle, unlike every quantity the shared spectrum reader
    // serves, which rejects negatives as mistakes): read it here.
    if let Some(prop) = p.get(spec.name) {
        let v = match &prop.value {
            Value::Float(v) => Some(*v),
            Value::Int(v) => Some(*v as f64),
            Value::Spectrum(SpecValue::Uniform(v)) => Some(*v),
            _ => None,
        };
        if let Some(v) = v {
            if !v.is_finite() {
                return Err(crate::xml::err(
                    &prop.value_loc,
                    crate::xml::ErrorKind::BadValue,
                    format!("\"{}\" = {v}: expected a finite angle in degrees", spec.name),
                ));
            }
            return Ok(Texture::Spectrum(gonio_core::spectra::Spectrum::Constant(
                v as f32,
            )));
        }
    }
    let t = b.texture(p, spec, RgbKind::Unbounded)?;
    if !t.is_textured() {
        let v = t.eval_1(Vec2::ZERO);
        if !v.is_finite() {
            return Err(crate::xml::err(
                &loc,
                crate::xml::ErrorKind::BadValue,
                format!("\"{}\" = {v}: expected a finite angle in degrees", spec.name),
            ));
        }
    }
    Ok(t)
}

/// `polarizer` in a scene.
#[derive(Clone, Debug)]
pub struct PolarizerMaterial {
    /// t.
    pub transmittance: Texture,
    /// θ, degrees.
    pub theta: Texture,
    /// The model (t's mean when textured; θ at uv = 0 when textured).
    pub model: Polarizer,
}

impl SurfaceMaterial for PolarizerMaterial {
    fn asks_for_polarization(&self) -> bool {
        true
    }
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        self.transmittance.is_textured() || self.theta.is_textured()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let mut m = self.model.at(wl);
        retint_at(&mut m.transmittance, &self.transmittance, uv, wl);
        if self.theta.is_textured() {
            m.theta = self.theta.eval_1(uv);
        }
        tree.push_leaf(LeafBsdf::Polarizer(m))
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        if self.is_textured() {
            f(&Polarizer {
                transmittance: self.transmittance.eval(uv),
                theta: self.theta.eval_1(uv),
                ..self.model.clone()
            })
        } else {
            f(&self.model)
        }
    }
}
