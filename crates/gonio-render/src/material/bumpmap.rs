//! `bumpmap`: a nested BSDF seen through the shading frame of a displaced surface (Mitsuba 3
//! `src/bsdfs/bumpmap.cpp`; core adapter [`gonio_core::bsdfs::PerturbedFrame`]).
//!
//! The surface is displaced along its shading normal n by `scale`·h(u, v), h a scalar texture;
//! with ∇h = (∂h/∂u, ∂h/∂v) from the texture (Mitsuba's `eval_1_grad`: the derivative of the
//! bilinear lookup), Mitsuba replaces the normal components of the surface derivatives:
//!
//! ```text
//!     ∂p'/∂u = ∂p/∂u + n·(scale·∂h/∂u − n·∂p/∂u)
//!     ∂p'/∂v = ∂p/∂v + n·(scale·∂h/∂v − n·∂p/∂v)
//!     n'     = normalize(∂p'/∂u × ∂p'/∂v),  negated when it faces away from the geometric normal
//! ```
//!
//! then expresses n' in the local coordinates of the shading frame: the perturbed normal the
//! adapter [`gonio_core::bsdfs::PerturbedFrame`] builds Mitsuba 3.9.1's frame from (flipped
//! towards the viewer where it faces away, tangent x made orthogonal to n') and whose terminator
//! it shadows, as `normalmap` does. The nested BSDF is evaluated in that frame; a direction ωo
//! on opposite sides of the shading normal and of n' is black.
//!
//! | parameter        | type    | default |
//! |------------------|---------|---------|
//! | (nested texture) | texture | required: the height h, any name, read as one value |
//! | `scale`          | float   | 1       |
//! | `flip_invalid_normals` | boolean | true |
//! | `use_shadowing_function` | boolean | true |
//! | (nested plugin)  | bsdf    | required, exactly one |

use super::normalmap::{FramePerturbation, one_nested};
use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, ShadingPoint};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag};
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::Perturbation;
use gonio_core::spectra::RgbKind;

const SCALE: ParamSpec = ParamSpec::new(
    "scale",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "multiplies the height texture (the bump's depth in scene units per unit of h)",
);
const TEXTURE: ParamSpec = ParamSpec::new(
    "(nested texture)",
    ParamType::Texture,
    DefaultValue::None,
    "exactly one nested texture, the height h (any name; a bitmap usually with raw=\"true\")",
);
const NESTED: ParamSpec = ParamSpec::new(
    "(nested bsdf)",
    ParamType::Bsdf,
    DefaultValue::None,
    "exactly one nested BSDF, evaluated in the bumped frame",
);

/// The `bumpmap` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "bumpmap",
    summary: "Bump mapping: the nested BSDF in the shading frame of the surface displaced by scale·h(u, v).",
    params: &[
        SCALE,
        TEXTURE,
        super::normalmap::FLIP_INVALID_NORMALS,
        super::normalmap::USE_SHADOWING_FUNCTION,
        NESTED,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let scale = p.float(SCALE.name, SCALE.default.float())? as f32;
    let textures = p.objects(Tag::Texture)?;
    let obj = b.object(p);
    let height = match textures.len() {
        1 => b.texture_object(textures[0].0, RgbKind::Unbounded, &textures[0].1.value_loc)?,
        0 => {
            return Err(SceneError::new(
                obj.loc.clone(),
                ErrorKind::Grammar,
                "bumpmap needs a nested texture (the height), found none",
            ));
        }
        n => {
            return Err(SceneError::new(
                textures[1].1.loc.clone(),
                ErrorKind::Grammar,
                format!("bumpmap takes exactly one nested texture, found {n}"),
            ));
        }
    };
    if !scale.is_finite() {
        let loc = obj
            .props
            .iter()
            .find(|x| x.name == SCALE.name)
            .map_or(obj.loc.clone(), |x| x.value_loc.clone());
        return Err(SceneError::new(
            loc,
            ErrorKind::BadValue,
            format!("bumpmap scale {scale} must be a finite number"),
        ));
    }
    let (flip_invalid_normals, use_shadowing_function) = super::normalmap::perturbation_options(p)?;
    let nested = one_nested(b, p, "bumpmap")?;
    Ok(Material::new(BumpMapMaterial {
        height,
        scale,
        nested,
        flip_invalid_normals,
        use_shadowing_function,
    }))
}

/// Mitsuba's bump-mapped normal at `at` for the scaled height gradient `grad` = scale·∇h (see
/// the module docs), in the local coordinates of the shading frame, unnormalized; zero where the
/// displaced parameterization degenerates (∂p'/∂u × ∂p'/∂v = 0: the adapter then keeps the
/// unperturbed frame).
pub fn bumpmap_normal(at: &ShadingPoint, grad: Vec2) -> Vec3 {
    let n = at.shading.n;
    let dpdu = at.dpdu + n * (grad.x - n.dot(at.dpdu));
    let dpdv = at.dpdv + n * (grad.y - n.dot(at.dpdv));
    let mut nb = dpdu.cross(dpdv);
    if !nb.is_finite() {
        return Vec3::ZERO;
    }
    if at.n.dot(nb) < 0.0 {
        nb = -nb;
    }
    at.shading.to_local(nb)
}

/// `bumpmap` in a scene.
#[derive(Clone, Debug)]
pub struct BumpMapMaterial {
    /// The height h.
    pub height: Texture,
    /// Multiplies h.
    pub scale: f32,
    /// The BSDF seen through the bumped frame.
    pub nested: Material,
    /// Mitsuba's `flip_invalid_normals`.
    pub flip_invalid_normals: bool,
    /// Mitsuba's `use_shadowing_function`.
    pub use_shadowing_function: bool,
}

impl FramePerturbation for BumpMapMaterial {
    fn nested(&self) -> &Material {
        &self.nested
    }
    fn perturbation_at(&self, at: &ShadingPoint) -> Perturbation {
        Perturbation {
            n: bumpmap_normal(at, self.scale * self.height.eval_1_grad(at.uv)),
            flip_invalid_normals: self.flip_invalid_normals,
            use_shadowing_function: self.use_shadowing_function,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gonio_core::Frame;

    /// The unit normal the adapter makes of the bumped normal (seen from above it, no flip).
    fn unit(at: &ShadingPoint, g: Vec2) -> Vec3 {
        Perturbation::new(bumpmap_normal(at, g)).frame(Vec3::Z).n
    }

    fn plane(dpdu: Vec3, dpdv: Vec3, n: Vec3) -> ShadingPoint {
        ShadingPoint {
            uv: Vec2::ZERO,
            n,
            shading: Frame::from_normal_tangent(Vec3::Z, Vec3::X),
            dpdu,
            dpdv,
            ..ShadingPoint::flat(Vec2::ZERO)
        }
    }

    #[test]
    fn a_height_field_gets_the_normal_of_its_graph() {
        // p(u, v) = (a u, b v, scale·h): n ∝ (−∂z/∂x, −∂z/∂y, 1) = (−g_u/a, −g_v/b, 1).
        let (a, b) = (2.0, 0.5);
        let g = Vec2::new(0.3, -0.2);
        let n = unit(&plane(Vec3::X * a, Vec3::Y * b, Vec3::Z), g);
        let expected = Vec3::new(-g.x / a, -g.y / b, 1.0).normalize();
        assert!((n - expected).length() < 1e-6, "{n:?} vs {expected:?}");
        // No gradient: the shading normal itself.
        let n = unit(&plane(Vec3::X * a, Vec3::Y * b, Vec3::Z), Vec2::ZERO);
        assert!((n - Vec3::Z).length() < 1e-6);
        // A degenerate parameterization (∂p/∂u ∥ ∂p/∂v, flat): a zero normal, which the adapter
        // reads as no perturbation.
        let degenerate = plane(Vec3::X, Vec3::X, Vec3::Z);
        assert_eq!(bumpmap_normal(&degenerate, Vec2::ZERO), Vec3::ZERO);
        assert_eq!(unit(&degenerate, Vec2::ZERO), Vec3::Z);
    }

    #[test]
    fn the_bumped_normal_follows_the_geometric_side_and_the_shading_frame() {
        // ∂p/∂u × ∂p/∂v points along −z when the parameterization is mirrored; the normal is
        // turned to the geometric normal's side (+z here).
        let n = bumpmap_normal(&plane(Vec3::Y, Vec3::X, Vec3::Z), Vec2::new(0.1, 0.0));
        assert!(n.z > 0.0, "{n:?}");
        // A shading frame tilted from the world axes: the result is expressed in it.
        let shading = Frame::from_normal_tangent(Vec3::new(0.0, 0.6, 0.8), Vec3::X);
        let at = ShadingPoint {
            uv: Vec2::ZERO,
            n: shading.n,
            shading,
            dpdu: shading.s,
            dpdv: shading.t,
            ..ShadingPoint::flat(Vec2::ZERO)
        };
        let n = unit(&at, Vec2::new(0.25, 0.0));
        let expected = Vec3::new(-0.25, 0.0, 1.0).normalize();
        assert!((n - expected).length() < 1e-6, "{n:?} vs {expected:?}");
    }
}
