//! `normalmap`: a nested BSDF seen through a shading frame read from a normal map (Mitsuba 3
//! `src/bsdfs/normalmap.cpp`; core adapter [`gonio_core::bsdfs::PerturbedFrame`]).
//!
//! At a hit with texture coordinates uv, the map's RGB (read `raw`, as tangent-space normals are
//! stored) is decoded from [0, 1] to [−1, 1] and taken **in the local coordinates of the
//! unperturbed shading frame** (x along its tangent s, z along its normal):
//!
//! ```text
//!     n' = normalize(2·rgb − 1)
//!     s' = normalize(∂p/∂u − n'·(n'·∂p/∂u)),    t' = n' × s'
//! ```
//!
//! As in Mitsuba, the tangent is built from the world-space ∂p/∂u used as if it were local: it
//! only turns the frame about n', which no isotropic nested BSDF sees. The nested BSDF is
//! evaluated with ωi, ωo expressed in (s', t', n'), and a direction ωo that lies on opposite
//! sides of the shading normal and of n' is black (see [`gonio_core::bsdfs::perturbed`]).
//! A degenerate map texel (2·rgb − 1 = 0) leaves the frame unperturbed.
//!
//! | parameter       | type    | default |
//! |-----------------|---------|---------|
//! | `normalmap`     | texture | required (a bitmap with `raw="true"`, or a constant) |
//! | (nested plugin) | bsdf    | required, exactly one |

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, ShadingPoint, SurfaceMaterial};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag};
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{PerturbedFrame, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, Frame, SampledWavelengths};

const NORMALMAP: ParamSpec = ParamSpec::new(
    "normalmap",
    ParamType::Texture,
    DefaultValue::None,
    "the tangent-space normals, RGB in [0, 1] ↦ [−1, 1] (a bitmap read with raw=\"true\")",
);
const NESTED: ParamSpec = ParamSpec::new(
    "(nested bsdf)",
    ParamType::Bsdf,
    DefaultValue::None,
    "exactly one nested BSDF, evaluated in the mapped frame",
);

/// The `normalmap` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "normalmap",
    summary: "Normal mapping: the nested BSDF in a shading frame whose normal is read from an RGB texture.",
    params: &[NORMALMAP, NESTED],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let obj = b.object(p);
    if !obj.props.iter().any(|x| x.name == NORMALMAP.name) {
        return Err(SceneError::new(
            obj.loc.clone(),
            ErrorKind::Grammar,
            "normalmap needs a \"normalmap\" texture",
        ));
    }
    let map = b.texture(p, &NORMALMAP, RgbKind::Unbounded)?;
    if map.eval_3(Vec2::ZERO).is_none() {
        let prop = obj
            .props
            .iter()
            .find(|x| x.name == NORMALMAP.name)
            .expect("checked above");
        return Err(SceneError::new(
            prop.value_loc.clone(),
            ErrorKind::BadValue,
            "normalmap's \"normalmap\" must be a bitmap or a constant (it is read as RGB)",
        ));
    }
    let nested = one_nested(b, p, "normalmap")?;
    Ok(Material::new(NormalMapMaterial { map, nested }))
}

/// The one nested BSDF of a frame-perturbing wrapper (`what` names it in errors).
pub(crate) fn one_nested<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    what: &str,
) -> Result<Material, SceneError> {
    let kids = p.objects(Tag::Bsdf)?;
    let obj = b.object(p);
    match kids.len() {
        1 => b.bsdf(kids[0].0, &kids[0].1.value_loc),
        0 => Err(SceneError::new(
            obj.loc.clone(),
            ErrorKind::Grammar,
            format!("{what} needs exactly one nested BSDF, found none"),
        )),
        n => Err(SceneError::new(
            kids[1].1.loc.clone(),
            ErrorKind::Grammar,
            format!("{what} takes exactly one nested BSDF, found {n}"),
        )),
    }
}

/// Mitsuba's normal-map frame from the map's `rgb` and ∂p/∂u (see the module docs), in the local
/// coordinates of the shading frame. A degenerate texel gives the unperturbed frame.
pub fn normalmap_frame(rgb: [f32; 3], dpdu: Vec3) -> Frame {
    let n = (Vec3::from(rgb) * 2.0 - Vec3::ONE).normalize_or_zero();
    if n == Vec3::ZERO || !n.is_finite() {
        return Frame::from_normal_tangent(Vec3::Z, Vec3::X);
    }
    tangent_frame(n, dpdu)
}

/// The frame of normal `n` with its tangent from `dpdu` by Gram–Schmidt; any tangent when
/// `dpdu` is zero or (numerically) along `n`.
pub(crate) fn tangent_frame(n: Vec3, dpdu: Vec3) -> Frame {
    let s = dpdu - n * n.dot(dpdu);
    if !(s.length_squared() > 1e-10 * dpdu.length_squared()) {
        return Frame::from_normal(n);
    }
    Frame::from_normal_tangent(n, dpdu)
}

/// `normalmap` in a scene.
#[derive(Clone, Debug)]
pub struct NormalMapMaterial {
    /// The normal map.
    pub map: Texture,
    /// The BSDF seen through the mapped frame.
    pub nested: Material,
}

impl NormalMapMaterial {
    fn frame(&self, uv: Vec2, dpdu: Vec3) -> Frame {
        normalmap_frame(self.map.eval_3(uv).unwrap_or([0.5, 0.5, 1.0]), dpdu)
    }
}

impl FramePerturbation for NormalMapMaterial {
    fn nested(&self) -> &Material {
        &self.nested
    }
    fn frame_at(&self, at: &ShadingPoint) -> Frame {
        self.frame(at.uv, at.dpdu)
    }
}

/// A material that shows its nested BSDF through a perturbed shading frame (`normalmap`,
/// `bumpmap`): the frame at a shading point is all that differs.
pub(super) trait FramePerturbation: Send + Sync + std::fmt::Debug + 'static {
    /// The BSDF seen through the frame.
    fn nested(&self) -> &Material;
    /// The perturbed shading frame at `at`.
    fn frame_at(&self, at: &ShadingPoint) -> Frame;
}

impl<T: FramePerturbation> SurfaceMaterial for T {
    fn flags(&self) -> BsdfFlags {
        self.nested().flags()
    }
    fn is_textured(&self) -> bool {
        true
    }
    fn node_count(&self) -> usize {
        1 + self.nested().as_surface().node_count()
    }
    fn asks_for_polarization(&self) -> bool {
        self.nested().as_surface().asks_for_polarization()
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        self.push_at(&ShadingPoint::flat(uv), wl, tree)
    }
    fn push_at<'a>(
        &'a self,
        at: &ShadingPoint,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let child = self.nested().as_surface().push_at(at, wl, tree)?;
        tree.push_perturbed(self.frame_at(at), child)
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        let frame = self.frame_at(&ShadingPoint::flat(uv));
        self.nested()
            .as_surface()
            .visit(uv, &mut |b: &dyn Bsdf| f(&PerturbedFrame::new(frame, b)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::FRAC_1_SQRT_2;

    #[test]
    fn a_flat_texel_leaves_the_frame_unperturbed() {
        let f = normalmap_frame([0.5, 0.5, 1.0], Vec3::X);
        assert!((f.n - Vec3::Z).length() < 1e-6 && (f.s - Vec3::X).length() < 1e-6);
        // A degenerate texel (the map's 2·rgb − 1 = 0) too.
        let f = normalmap_frame([0.5, 0.5, 0.5], Vec3::X);
        assert_eq!(f.n, Vec3::Z);
    }

    #[test]
    fn rgb_decodes_to_a_tilted_normal_with_a_gram_schmidt_tangent() {
        // rgb (1, ½, 1) ↦ (1, 0, 1)/√2; s = normalize(x − n (n·x)) = (1, 0, −1)/√2; t = n × s = y.
        let f = normalmap_frame([1.0, 0.5, 1.0], Vec3::X);
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-6;
        assert!(close(f.n, Vec3::new(FRAC_1_SQRT_2, 0.0, FRAC_1_SQRT_2)), "{f:?}");
        assert!(close(f.s, Vec3::new(FRAC_1_SQRT_2, 0.0, -FRAC_1_SQRT_2)), "{f:?}");
        assert!(close(f.t, Vec3::Y), "{f:?}");
        // Without a usable ∂p/∂u (zero, or along n) the tangent is any one orthogonal to n.
        for dpdu in [Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0)] {
            let f = normalmap_frame([1.0, 0.5, 1.0], dpdu);
            assert!(
                f.s.dot(f.n).abs() < 1e-6 && (f.s.length() - 1.0).abs() < 1e-6,
                "{f:?}"
            );
        }
    }
}
