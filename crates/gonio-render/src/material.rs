//! Materials as the scene describes them, and the per-hit construction of the core BSDF model
//! ([`Material::with_bsdf`]: textures evaluated at the hit's uv, the model built on the stack).
//!
//! Each leaf material keeps a core model prebuilt at load (`model`): when no parameter is
//! textured the model is used as is, with no work per hit; otherwise it is cloned and the textured
//! fields are replaced by their values at the hit. `plastic` precomputes its Fresnel integrals
//! and sampling weight once (from the texture means, as Mitsuba does).

use crate::texture::Texture;
use glam::Vec2;
use gonio_core::bsdfs::{BlendBsdf, Conductor, Dielectric, Diffuse, Plastic, ThinDielectric, TwoSided};
use gonio_core::{Bsdf, Ior, Spectrum};

/// A surface material: one of Mitsuba's BSDF plugins with its parameters.
#[derive(Clone, Debug)]
pub enum Material {
    /// `diffuse` (reflectance, default 0.5).
    Diffuse {
        /// ρ.
        reflectance: Texture,
        /// The model (ρ's mean when textured).
        model: Diffuse,
    },
    /// `conductor`: smooth metal from the complex index η + ik (`eta`, `k`, `ext_ior` in the
    /// model; Mitsuba's default `material="none"` is the ideal mirror η = 0, k = 1).
    Conductor {
        /// Multiplier, default 1.
        specular_reflectance: Texture,
        /// The model with a constant `specular_reflectance` (its value when untextured).
        model: Conductor,
    },
    /// `dielectric`: smooth interface between two media (indices in the model).
    Dielectric {
        /// Multiplier on reflection, default 1.
        specular_reflectance: Texture,
        /// Multiplier on transmission, default 1.
        specular_transmittance: Texture,
        /// The model (untextured parameters).
        model: Dielectric,
    },
    /// `thindielectric`: a thin sheet, light passes straight through.
    ThinDielectric {
        /// Multiplier on reflection, default 1.
        specular_reflectance: Texture,
        /// Multiplier on transmission, default 1.
        specular_transmittance: Texture,
        /// The model (untextured parameters).
        model: ThinDielectric,
    },
    /// `plastic`: diffuse base under a smooth dielectric coating.
    Plastic {
        /// Base reflectance, default 0.5.
        diffuse_reflectance: Texture,
        /// Coating reflectance multiplier, default 1.
        specular_reflectance: Texture,
        /// The model, precomputed with the texture means (indices, `nonlinear`, Fdr, weights).
        model: Plastic,
    },
    /// `twosided`: `front` on both sides, or `front`/`back`.
    TwoSided {
        /// Front (and back if `back` is none).
        front: Box<Material>,
        /// Back side, if different.
        back: Option<Box<Material>>,
    },
    /// `blendbsdf`: (1 − weight)·bsdf0 + weight·bsdf1.
    Blend {
        /// Weight in [0, 1], evaluated as a scalar (clamped).
        weight: Texture,
        /// First child.
        bsdf0: Box<Material>,
        /// Second child.
        bsdf1: Box<Material>,
    },
    /// `tabulated` (ours): a measured isotropic BRDF table played back (`gonio measure`).
    Tabulated {
        /// The interpolated, reciprocity-enforced, importance-sampled table.
        model: std::sync::Arc<gonio_core::bsdfs::Tabulated>,
    },
}

/// The constant value of a texture for a prebuilt model (the mean when textured).
fn model_value(t: &Texture) -> Spectrum {
    match t {
        Texture::Spectrum(s) => s.clone(),
        _ => Spectrum::Constant(t.mean()),
    }
}

impl Material {
    /// Mitsuba's default material for a shape without a BSDF: diffuse with ρ = 0.5, or ρ = 0 if
    /// the shape emits.
    pub fn default_for_shape(emitter: bool) -> Self {
        Material::diffuse(Texture::constant(if emitter { 0.0 } else { 0.5 }))
    }

    /// `diffuse`.
    pub fn diffuse(reflectance: Texture) -> Self {
        let model = Diffuse::new(model_value(&reflectance));
        Material::Diffuse { reflectance, model }
    }

    /// `conductor` from η, k, the exterior index and the tint.
    pub fn conductor(eta: Spectrum, k: Spectrum, ext_ior: Ior, specular_reflectance: Texture) -> Self {
        let model = Conductor {
            eta,
            k,
            ext_ior,
            specular_reflectance: model_value(&specular_reflectance),
        };
        Material::Conductor {
            specular_reflectance,
            model,
        }
    }

    /// `dielectric`.
    pub fn dielectric(
        int_ior: Ior,
        ext_ior: Ior,
        specular_reflectance: Texture,
        specular_transmittance: Texture,
    ) -> Self {
        let model = Dielectric {
            int_ior,
            ext_ior,
            specular_reflectance: model_value(&specular_reflectance),
            specular_transmittance: model_value(&specular_transmittance),
        };
        Material::Dielectric {
            specular_reflectance,
            specular_transmittance,
            model,
        }
    }

    /// `thindielectric`.
    pub fn thin_dielectric(
        int_ior: Ior,
        ext_ior: Ior,
        specular_reflectance: Texture,
        specular_transmittance: Texture,
    ) -> Self {
        let model = ThinDielectric {
            int_ior,
            ext_ior,
            specular_reflectance: model_value(&specular_reflectance),
            specular_transmittance: model_value(&specular_transmittance),
        };
        Material::ThinDielectric {
            specular_reflectance,
            specular_transmittance,
            model,
        }
    }

    /// `plastic`; the specular sampling weight uses the texture means (Mitsuba).
    pub fn plastic(
        diffuse_reflectance: Texture,
        int_ior: f32,
        ext_ior: f32,
        nonlinear: bool,
        specular_reflectance: Texture,
    ) -> Self {
        let model = Plastic::new(
            model_value(&diffuse_reflectance),
            int_ior,
            ext_ior,
            nonlinear,
            model_value(&specular_reflectance),
        );
        Material::Plastic {
            diffuse_reflectance,
            specular_reflectance,
            model,
        }
    }

    /// True when the material transmits light (dielectric, thindielectric, or a blend with one).
    pub fn has_transmission(&self) -> bool {
        match self {
            Material::Dielectric { .. } | Material::ThinDielectric { .. } => true,
            Material::TwoSided { front, back } => {
                front.has_transmission() || back.as_ref().is_some_and(|b| b.has_transmission())
            }
            Material::Blend { bsdf0, bsdf1, .. } => bsdf0.has_transmission() || bsdf1.has_transmission(),
            _ => false,
        }
    }

    /// True when some parameter varies over the surface.
    pub fn is_textured(&self) -> bool {
        match self {
            Material::Diffuse { reflectance, .. } => reflectance.is_textured(),
            Material::Conductor {
                specular_reflectance, ..
            } => specular_reflectance.is_textured(),
            Material::Dielectric {
                specular_reflectance,
                specular_transmittance,
                ..
            }
            | Material::ThinDielectric {
                specular_reflectance,
                specular_transmittance,
                ..
            } => specular_reflectance.is_textured() || specular_transmittance.is_textured(),
            Material::Plastic {
                diffuse_reflectance,
                specular_reflectance,
                ..
            } => diffuse_reflectance.is_textured() || specular_reflectance.is_textured(),
            Material::TwoSided { front, back } => {
                front.is_textured() || back.as_ref().is_some_and(|b| b.is_textured())
            }
            Material::Blend { weight, bsdf0, bsdf1 } => {
                weight.is_textured() || bsdf0.is_textured() || bsdf1.is_textured()
            }
            Material::Tabulated { .. } => false,
        }
    }

    /// Builds the core BSDF at surface coordinates `uv` and hands it to `f`. Nothing is allocated:
    /// the model lives on the stack (or is the prebuilt one), `twosided`/`blendbsdf` children are
    /// borrowed.
    pub fn with_bsdf<R>(&self, uv: Vec2, f: impl FnOnce(&dyn Bsdf) -> R) -> R {
        let mut f = Some(f);
        let mut out = None;
        self.visit(uv, &mut |b| {
            if let Some(f) = f.take() {
                out = Some(f(b));
            }
        });
        out.expect("Material::visit calls its callback exactly once")
    }

    /// Calls `f` exactly once with the BSDF at `uv` (dynamic callback so nested materials do not
    /// instantiate an unbounded chain of closure types).
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        match self {
            Material::Diffuse { reflectance, model } => {
                if reflectance.is_textured() {
                    f(&Diffuse::new(reflectance.eval(uv)))
                } else {
                    f(model)
                }
            }
            Material::Conductor {
                specular_reflectance: r,
                model,
            } => retinted(model, r.is_textured(), |m| m.specular_reflectance = r.eval(uv), f),
            Material::Dielectric {
                specular_reflectance: r,
                specular_transmittance: t,
                model,
            } => retinted(
                model,
                r.is_textured() || t.is_textured(),
                |m| (m.specular_reflectance, m.specular_transmittance) = (r.eval(uv), t.eval(uv)),
                f,
            ),
            Material::ThinDielectric {
                specular_reflectance: r,
                specular_transmittance: t,
                model,
            } => retinted(
                model,
                r.is_textured() || t.is_textured(),
                |m| (m.specular_reflectance, m.specular_transmittance) = (r.eval(uv), t.eval(uv)),
                f,
            ),
            Material::Plastic {
                diffuse_reflectance: d,
                specular_reflectance: r,
                model,
            } => retinted(
                model,
                d.is_textured() || r.is_textured(),
                |m| (m.diffuse_reflectance, m.specular_reflectance) = (d.eval(uv), r.eval(uv)),
                f,
            ),
            Material::TwoSided { front, back } => front.visit(uv, &mut |fb: &dyn Bsdf| match back {
                Some(back) => back.visit(uv, &mut |bb: &dyn Bsdf| f(&TwoSided { front: fb, back: bb })),
                None => f(&TwoSided { front: fb, back: fb }),
            }),
            Material::Blend { weight, bsdf0, bsdf1 } => {
                let w = weight.eval_1(uv);
                let w = if w.is_nan() { 0.0 } else { w.clamp(0.0, 1.0) };
                bsdf0.visit(uv, &mut |b0: &dyn Bsdf| {
                    bsdf1.visit(uv, &mut |b1: &dyn Bsdf| {
                        f(&BlendBsdf {
                            weight: w,
                            bsdf0: b0,
                            bsdf1: b1,
                        })
                    })
                })
            }
            Material::Tabulated { model } => f(model.as_ref()),
        }
    }
}

/// Hands `f` the prebuilt `model`, or, when some of its tints are textured, a copy on the stack
/// with the tints at this point set by `retint`.
fn retinted<M: Bsdf + Clone>(
    model: &M,
    textured: bool,
    retint: impl FnOnce(&mut M),
    f: &mut dyn FnMut(&dyn Bsdf),
) {
    if textured {
        let mut m = model.clone();
        retint(&mut m);
        f(&m)
    } else {
        f(model)
    }
}
