//! `normalmap`: a nested BSDF seen through a shading frame read from a normal map (Mitsuba 3
//! `src/bsdfs/normalmap.cpp`; core adapter [`gonio_core::bsdfs::PerturbedFrame`]).
//!
//! At a hit with texture coordinates uv, the map's RGB (read `raw`, as tangent-space normals are
//! stored) is decoded from [0, 1] to [−1, 1] and taken **in the local coordinates of the
//! unperturbed shading frame** (x along its tangent s, z along its normal): n = 2·rgb − 1, the
//! perturbed normal the adapter [`gonio_core::bsdfs::PerturbedFrame`] builds Mitsuba 3.9.1's
//! frame from (n' = normalize(n), flipped towards the viewer where it faces away, tangent x made
//! orthogonal to n') and whose terminator it shadows (Conty Estevez et al. 2019). A degenerate
//! texel (2·rgb − 1 = 0) leaves the frame unperturbed.
//!
//! | parameter       | type    | default |
//! |-----------------|---------|---------|
//! | `normalmap`     | texture | required (a bitmap with `raw="true"`, an `rgb`, an `srgb` spectrum or a constant) |
//! | `flip_invalid_normals` | boolean | true |
//! | `use_shadowing_function` | boolean | true |
//! | (nested plugin) | bsdf    | required, exactly one |

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, ShadingPoint, SurfaceMaterial};
use crate::texture::Texture;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag};
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{Perturbation, PerturbedFrame, SurfaceBsdf};
use gonio_core::spectra::RgbKind;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const NORMALMAP: ParamSpec = ParamSpec::new(
    "normalmap",
    ParamType::Texture,
    DefaultValue::None,
    "the tangent-space normals, RGB in [0, 1] ↦ [−1, 1] (a bitmap read with raw=\"true\", or a constant: an `rgb` or an `srgb` spectrum)",
);
const NESTED: ParamSpec = ParamSpec::new(
    "(nested bsdf)",
    ParamType::Bsdf,
    DefaultValue::None,
    "exactly one nested BSDF, evaluated in the mapped frame",
);

pub(super) const FLIP_INVALID_NORMALS: ParamSpec = ParamSpec::new(
    "flip_invalid_normals",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "mirror the perturbed normal's tangential part where the viewer sees the surface from behind it (Schüssler et al. 2017)",
);
pub(super) const USE_SHADOWING_FUNCTION: ParamSpec = ParamSpec::new(
    "use_shadowing_function",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "shadow grazing directions as a microfacet surface as rough as the perturbation (Conty Estevez et al. 2019), softening the terminator",
);

/// The `normalmap` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "normalmap",
    summary: "Normal mapping: the nested BSDF in a shading frame whose normal is read from an RGB texture.",
    params: &[NORMALMAP, FLIP_INVALID_NORMALS, USE_SHADOWING_FUNCTION, NESTED],
    build,
};

/// Mitsuba's `flip_invalid_normals` and `use_shadowing_function` of a frame-perturbing wrapper.
pub(super) fn perturbation_options(p: &mut Params<'_>) -> Result<(bool, bool), SceneError> {
    Ok((
        p.bool(FLIP_INVALID_NORMALS.name, FLIP_INVALID_NORMALS.default.bool())?,
        p.bool(USE_SHADOWING_FUNCTION.name, USE_SHADOWING_FUNCTION.default.bool())?,
    ))
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let obj = b.object(p);
    let Some(prop) = obj.props.iter().find(|x| x.name == NORMALMAP.name) else {
        return Err(SceneError::new(
            obj.loc.clone(),
            ErrorKind::Grammar,
            "normalmap needs a \"normalmap\" texture",
        ));
    };
    let texture = b.texture(p, &NORMALMAP, RgbKind::Unbounded)?;
    let map = match raw_color(b, &prop.value) {
        // An `<rgb>` constant, or an `srgb` spectrum object, is its three values, as Mitsuba's
        // RGB variants read it (its spectral variants read the uplifted spectrum's coefficients
        // instead).
        Some(c) => Texture::raw_rgb(c),
        _ => texture,
    };
    if map.eval_3(Vec2::ZERO).is_none() {
        return Err(SceneError::new(
            prop.value_loc.clone(),
            ErrorKind::BadValue,
            "normalmap's \"normalmap\" must be a bitmap or a constant (it is read as RGB)",
        ));
    }
    let (flip_invalid_normals, use_shadowing_function) = perturbation_options(p)?;
    let nested = one_nested(b, p, "normalmap")?;
    Ok(Material::new(NormalMapMaterial {
        map,
        nested,
        flip_invalid_normals,
        use_shadowing_function,
    }))
}

/// The colour a normal map given as a constant stands for: an `<rgb>` value, or the `color` of
/// a nested or referenced `<spectrum type="srgb">` (Mitsuba's test scenes write the identity map
/// so). The object itself was built, and so checked, by the caller.
fn raw_color(b: &Builder<'_>, value: &crate::xml::Value) -> Option<[f64; 3]> {
    use crate::xml::Value;
    let idx = match value {
        Value::Rgb(c) => return Some(*c),
        Value::Object(i) => *i,
        Value::Ref(id) => *b.doc.ids.get(id)?,
        _ => return None,
    };
    let obj = &b.doc.objs[idx];
    if obj.tag != Tag::Spectrum || obj.ty != "srgb" {
        return None;
    }
    obj.props.iter().find_map(|p| match (p.name.as_str(), &p.value) {
        ("color", Value::Rgb(c)) => Some(*c),
        ("color", Value::Float(v)) => Some([*v; 3]),
        ("color", Value::Int(v)) => Some([*v as f64; 3]),
        _ => None,
    })
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

/// The perturbed normal of a map texel `rgb`, 2·rgb − 1, in the local coordinates of the shading
/// frame (unnormalized; see the module docs).
pub fn normalmap_normal(rgb: [f32; 3]) -> Vec3 {
    Vec3::from(rgb) * 2.0 - Vec3::ONE
}

/// `normalmap` in a scene.
#[derive(Clone, Debug)]
pub struct NormalMapMaterial {
    /// The normal map.
    pub map: Texture,
    /// The BSDF seen through the mapped frame.
    pub nested: Material,
    /// Mitsuba's `flip_invalid_normals`.
    pub flip_invalid_normals: bool,
    /// Mitsuba's `use_shadowing_function`.
    pub use_shadowing_function: bool,
}

impl FramePerturbation for NormalMapMaterial {
    fn nested(&self) -> &Material {
        &self.nested
    }
    fn perturbation_at(&self, at: &ShadingPoint) -> Perturbation {
        Perturbation {
            n: normalmap_normal(self.map.eval_3(at.uv).unwrap_or([0.5, 0.5, 1.0])),
            flip_invalid_normals: self.flip_invalid_normals,
            use_shadowing_function: self.use_shadowing_function,
        }
    }
}

/// A material that shows its nested BSDF through a perturbed shading frame (`normalmap`,
/// `bumpmap`): the perturbed normal at a shading point is all that differs.
pub(super) trait FramePerturbation: Send + Sync + std::fmt::Debug + 'static {
    /// The BSDF seen through the perturbed frame.
    fn nested(&self) -> &Material;
    /// The perturbed normal at `at` and its options.
    fn perturbation_at(&self, at: &ShadingPoint) -> Perturbation;
}

impl<T: FramePerturbation> SurfaceMaterial for T {
    /// The nested material's lobes, and what a tilted normal makes of them anywhere on the
    /// surface ([`PerturbedFrame`]'s flags): not the nested model's symmetry, isotropy or
    /// geometry (a normal-mapped mirror sphere is no mirror sphere).
    fn flags(&self) -> BsdfFlags {
        self.nested().flags() | BsdfFlags::NON_SYMMETRIC | BsdfFlags::ANISOTROPIC
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
        tree.push_perturbed(self.perturbation_at(at), child)
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        let perturbation = self.perturbation_at(&ShadingPoint::flat(uv));
        self.nested()
            .as_surface()
            .visit(uv, &mut |b: &dyn Bsdf| f(&PerturbedFrame::new(perturbation, b)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texels_decode_to_normals_in_the_shading_frame() {
        assert_eq!(normalmap_normal([0.5, 0.5, 1.0]), Vec3::Z);
        assert_eq!(normalmap_normal([1.0, 0.5, 1.0]), Vec3::new(1.0, 0.0, 1.0));
        // The adapter's frame: a degenerate texel leaves it unperturbed; a tilted one gets the
        // tangent x made orthogonal to n' (Mitsuba 3.9.1), whatever ∂p/∂u.
        let wi = Vec3::new(0.0, 0.3, 0.95).normalize();
        let flat = Perturbation::new(normalmap_normal([0.5, 0.5, 0.5])).frame(wi);
        assert_eq!((flat.s, flat.t, flat.n), (Vec3::X, Vec3::Y, Vec3::Z));
        let f = Perturbation::new(normalmap_normal([1.0, 0.5, 1.0])).frame(wi);
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-6;
        assert!(
            close(f.n, Vec3::new(h, 0.0, h)) && close(f.s, Vec3::new(h, 0.0, -h)) && close(f.t, Vec3::Y),
            "{f:?}"
        );
    }
}
