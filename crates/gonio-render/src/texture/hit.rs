//! Textures that read the hit beyond its uv: `mesh_attribute` (Mitsuba 3
//! `src/textures/mesh_attribute.cpp` over `Mesh::eval_attribute`, `src/render/mesh.cpp`) and
//! `volume` (`src/textures/volume.cpp`, a grid evaluated at the surface point).
//!
//! * `mesh_attribute`: value = scale · A(hit). A vertex attribute is interpolated with the hit's
//!   barycentric coordinates (b₀, b₁, b₂) on its triangle (i₀, i₁, i₂): A = Σ bₖ·`A[iₖ]`, the
//!   coordinates the intersection found (so a mesh placed by an `instance` reads the same values
//!   as the mesh placed directly; Mitsuba 3.9.1 recomputes them from the world-space point and
//!   the group-space vertices, which is wrong under any instance transform but the identity); a face
//!   attribute is the triangle's own value. In Mitsuba's spectral variants a 3-value attribute
//!   whose name contains `color` is an sRGB reflectance (clamped to [0, 1], uplifted with Jakob &
//!   Hanika's sigmoid polynomials); a 3-value attribute without `color` in its name is read as the
//!   polynomial's three coefficients as Mitsuba 3.9.1 does; a 1-value attribute is a constant
//!   spectrum. gonio interpolates a colour's RGB and uplifts the result (Mitsuba interpolates the
//!   three vertex spectra: the two agree at the vertices, as the bilinear `bitmap` lookups do).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `name` | string | (required) | `vertex_…` or `face_…`, an attribute of the mesh |
//! | `scale` | float | 1 | factor applied to the value |
//!
//! How the hit reaches the texture, at no cost for the other materials: the reader wraps the
//! material of each shape whose BSDF holds such a texture in a [`HitBound`] material (one per
//! shape, holding that mesh's named attributes; the instances of a shape group share it). At a hit,
//! [`HitBound::push_at`] makes the point known to this thread's texture lookups for the time its
//! inner material builds its BSDF ([`with_hit`]); outside that scope these textures are 0 (the
//! instruments, which know no surface, see black). Materials without such textures are not
//! wrapped and never look at the hit. An area emitter whose `radiance` is such a texture holds
//! its shape's binding the same way and evaluates its radiance inside [`with_hit_point`]
//! (`crate::emitter::area`).

use crate::material::{Material, ShadingPoint, SurfaceMaterial};
use crate::mesh::attributes::{AttributeKind, MeshAttribute, MeshAttributes};
use crate::scene::TriangleMesh;
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::spectra::{RgbKind, RgbSpectrum};
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths, Spectrum};
use std::cell::RefCell;
use std::sync::Arc;

/// What a shape gives the textures of its material (or of its emitter) at a hit: its mesh (if
/// it is one) with the attributes they name.
#[derive(Debug)]
pub struct HitBinding {
    /// The shape's mesh (object space) and the attributes the textures name.
    pub mesh: Option<(Arc<TriangleMesh>, MeshAttributes)>,
}

/// The hit being shaded on this thread, while a [`HitBound`] material builds its BSDF.
struct HitContext {
    binding: Arc<HitBinding>,
    p: Vec3,
    prim: u32,
    bary: Vec2,
}

thread_local! {
    static HIT: RefCell<Option<HitContext>> = const { RefCell::new(None) };
}

/// Runs `f` with the hit `at` on the shape `binding` known to this thread's texture lookups.
pub fn with_hit<R>(binding: &Arc<HitBinding>, at: &ShadingPoint, f: impl FnOnce() -> R) -> R {
    with_hit_point(binding, at.p, at.prim, at.bary, f)
}

/// Runs `f` with the point `p` (world), on triangle `prim` at barycentrics `bary` of the shape
/// `binding`, known to this thread's texture lookups (what an emitter's radiance reads).
pub fn with_hit_point<R>(
    binding: &Arc<HitBinding>,
    p: Vec3,
    prim: u32,
    bary: Vec2,
    f: impl FnOnce() -> R,
) -> R {
    struct Reset;
    impl Drop for Reset {
        fn drop(&mut self) {
            HIT.with_borrow_mut(|h| *h = None);
        }
    }
    HIT.with_borrow_mut(|h| {
        *h = Some(HitContext {
            binding: binding.clone(),
            p,
            prim,
            bary,
        })
    });
    let _reset = Reset;
    f()
}

/// The world-space point of the hit being shaded, if any (for `volume` textures).
pub fn hit_point() -> Option<Vec3> {
    HIT.with_borrow(|h| h.as_ref().map(|c| c.p))
}

/// A `mesh_attribute` texture.
#[derive(Clone, Debug, PartialEq)]
pub struct AttributeTexture {
    /// The attribute's name (`vertex_…` or `face_…`).
    pub name: String,
    /// Factor applied to the value.
    pub scale: f32,
}

/// `dim` (1 or 3) values of `attr` at the hit `ctx`.
fn values(attr: &MeshAttribute, mesh: &TriangleMesh, ctx: &HitContext) -> Option<[f32; 3]> {
    let prim = ctx.prim as usize;
    let dim = attr.dim;
    let at = |i: usize| -> Option<[f32; 3]> {
        let s = attr.data.get(i * dim..(i + 1) * dim)?;
        Some(if dim == 1 { [s[0]; 3] } else { [s[0], s[1], s[2]] })
    };
    match attr.kind {
        AttributeKind::Face => at(prim),
        AttributeKind::Vertex => {
            let tri = *mesh.indices.get(prim)?;
            let b = [1.0 - ctx.bary.x - ctx.bary.y, ctx.bary.x, ctx.bary.y];
            let mut v = [0.0f32; 3];
            for k in 0..3 {
                let x = at(tri[k] as usize)?;
                for c in 0..3 {
                    v[c] += b[k] * x[c];
                }
            }
            Some(v)
        }
    }
}

impl AttributeTexture {
    /// The attribute's values at the hit being shaded (`None` outside one) and its dimension.
    fn lookup(&self) -> Option<([f32; 3], usize)> {
        HIT.with_borrow(|h| {
            let ctx = h.as_ref()?;
            let (mesh, attrs) = ctx.binding.mesh.as_ref()?;
            let attr = attrs.get(&self.name)?;
            values(attr, mesh, ctx).map(|v| (v, attr.dim))
        })
    }

    /// The spectrum at the hit being shaded (0 outside one).
    pub fn eval(&self) -> Spectrum {
        match self.lookup() {
            None => Spectrum::Constant(0.0),
            Some((v, 1)) => Spectrum::Constant(self.scale * v[0]),
            Some((v, _)) => {
                let sigmoid = if self.name.contains("color") {
                    let rgb = v.map(|x| if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) });
                    gonio_core::rgb2spec::srgb_to_sigmoid(rgb)
                } else {
                    gonio_core::rgb2spec::RgbSigmoid {
                        c0: v[0],
                        c1: v[1],
                        c2: v[2],
                    }
                };
                Spectrum::Rgb(RgbSpectrum {
                    sigmoid,
                    scale: self.scale,
                    kind: RgbKind::Albedo,
                })
            }
        }
    }

    /// A scalar at the hit (a 1-value attribute; the mean of three values).
    pub fn eval_1(&self) -> f32 {
        match self.lookup() {
            None => 0.0,
            Some((v, 1)) => self.scale * v[0],
            Some((v, _)) => self.scale * (v[0] + v[1] + v[2]) / 3.0,
        }
    }

    /// Three values at the hit, as Mitsuba's `eval_3` reads them (unconverted).
    pub fn eval_3(&self) -> [f32; 3] {
        self.lookup()
            .map(|(v, _)| v.map(|x| self.scale * x))
            .unwrap_or([0.0; 3])
    }
}

/// A material whose textures read the hit: `inner`, with the hit on one shape made known to its
/// texture lookups while it builds its BSDF (see the module documentation).
#[derive(Debug)]
pub struct HitBound {
    inner: Material,
    binding: Arc<HitBinding>,
}

impl HitBound {
    /// `inner` on the shape described by `binding`.
    pub fn new(inner: Material, binding: HitBinding) -> Self {
        Self {
            inner,
            binding: Arc::new(binding),
        }
    }
}

impl SurfaceMaterial for HitBound {
    fn flags(&self) -> BsdfFlags {
        self.inner.flags()
    }

    fn is_textured(&self) -> bool {
        true
    }

    fn node_count(&self) -> usize {
        self.inner.as_surface().node_count()
    }

    fn asks_for_polarization(&self) -> bool {
        self.inner.as_surface().asks_for_polarization()
    }

    fn push<'a>(
        &'a self,
        uv: glam::Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        self.inner.as_surface().push(uv, wl, tree)
    }

    fn push_at<'a>(
        &'a self,
        at: &ShadingPoint,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        with_hit(&self.binding, at, || {
            self.inner.as_surface().push_at(at, wl, tree)
        })
    }

    fn visit(&self, uv: glam::Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        self.inner.as_surface().visit(uv, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::DiffuseMaterial;
    use crate::texture::Texture;
    use gonio_core::BsdfContext;

    /// The unit quad as two triangles, with a grey per vertex and one per triangle.
    fn quad() -> (Arc<TriangleMesh>, MeshAttributes) {
        let mesh = TriangleMesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            ..Default::default()
        };
        let grey = |v: &[f32]| v.iter().flat_map(|&g| [g, g, g]).collect::<Vec<f32>>();
        let attrs = MeshAttributes {
            list: vec![
                MeshAttribute {
                    name: "vertex_color".into(),
                    kind: AttributeKind::Vertex,
                    dim: 3,
                    data: grey(&[0.1, 0.3, 0.5, 0.7]),
                },
                MeshAttribute {
                    name: "face_weight".into(),
                    kind: AttributeKind::Face,
                    dim: 1,
                    data: vec![0.25, 0.75],
                },
            ],
        };
        (Arc::new(mesh), attrs)
    }

    /// π·f of a diffuse material textured by `name` at barycentrics `bary` on triangle `prim`
    /// of the quad, at four wavelengths.
    fn albedo(name: &str, scale: f32, bary: Vec2, prim: u32) -> [f32; 4] {
        let (mesh, attrs) = quad();
        let tex = Texture::MeshAttribute(Arc::new(AttributeTexture {
            name: name.into(),
            scale,
        }));
        let m = HitBound::new(
            Material::new(DiffuseMaterial::new(tex)),
            HitBinding {
                mesh: Some((mesh, attrs)),
            },
        );
        let at = ShadingPoint {
            prim,
            bary,
            ..ShadingPoint::flat(glam::Vec2::ZERO)
        };
        let wl = SampledWavelengths::sample_visible(0.3);
        let mut tree = SurfaceBsdf::new();
        m.push_at(&at, &wl, &mut tree).unwrap();
        let f = tree.eval(&BsdfContext::radiance(), Vec3::Z, Vec3::Z, &wl);
        std::array::from_fn(|i| f[i] * std::f32::consts::PI)
    }

    #[test]
    fn vertex_attributes_interpolate_and_face_attributes_do_not() {
        // Barycentrics (0.2, 0.3, 0.5) on triangle 0 (vertices 0, 1, 2): grey 0.2·0.1 + 0.3·0.3
        // + 0.5·0.5 = 0.36, a flat spectrum (the uplift of a grey, within its table's 2e-3).
        let b = Vec2::new(0.3, 0.5);
        for v in albedo("vertex_color", 1.0, b, 0) {
            assert!((v - 0.36).abs() < 3e-3, "{v}");
        }
        // Scale 2 doubles it.
        for v in albedo("vertex_color", 2.0, b, 0) {
            assert!((v - 0.72).abs() < 6e-3, "{v}");
        }
        // A face attribute is the triangle's own, wherever on it.
        // (exactly, up to the rounding of ρ/π·π)
        for v in albedo("face_weight", 1.0, Vec2::new(0.6, 0.1), 1) {
            assert!((v - 0.75).abs() < 1e-6, "{v}");
        }
        // Outside a hit (the instruments) the texture is black.
        let t = AttributeTexture {
            name: "face_weight".into(),
            scale: 1.0,
        };
        assert_eq!(t.eval_1(), 0.0);
    }
}
