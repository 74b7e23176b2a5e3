//! Materials: the BSDF plugins of a scene, one module each.
//!
//! A BSDF plugin is one file in this folder holding
//! 1. its **parameter table** ([`ParamSpec`]s: Mitsuba's names, types, defaults and meaning),
//!    from which the reader takes every default, the "unused parameter" check its list of accepted
//!    names, and `docs/plugins.md` its text ([`crate::plugins::plugins_markdown`], with the
//!    plugins of every other kind);
//! 2. its **builder** from parsed parameters (a [`BsdfPlugin`] registered in [`BSDF_PLUGINS`]);
//! 3. its **scene-side material** (textures and the prebuilt core model), a [`SurfaceMaterial`]
//!    that at each hit becomes a `Copy` [`SurfaceBsdf`]: textures looked up at the hit's uv and
//!    spectra evaluated at the path's wavelengths.
//!
//! The physics stays in `gonio_core::bsdfs` (one file per model). To add a BSDF: write the core
//! model (and its [`LeafBsdf`](gonio_core::bsdfs::LeafBsdf) variant), write its plugin file here,
//! add it to [`BSDF_PLUGINS`], and add it to the battery (`crates/gonio-core/tests/battery.rs`);
//! `docs/adding-a-plugin.md` walks through one.

pub mod blendbsdf;
pub mod bumpmap;
pub mod circular;
pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod hair;
pub mod lambertsphere;
pub mod mask;
pub mod measured;
pub mod measured_polarized;
pub mod normalmap;
pub mod null;
pub mod plastic;
pub mod polarizer;
pub mod pplastic;
pub mod principled;
pub mod principledthin;
pub mod retarder;
pub mod roughconductor;
pub mod roughdielectric;
pub mod roughdiffuse;
pub mod roughplastic;
pub mod tabulated;
pub mod thindielectric;
pub mod twosided;

pub use crate::xml::{BsdfPlugin, DefaultValue, ParamSpec, ParamType};
pub use blendbsdf::BlendMaterial;
pub use bumpmap::BumpMapMaterial;
pub use circular::CircularMaterial;
pub use conductor::ConductorMaterial;
pub use dielectric::DielectricMaterial;
pub use diffuse::DiffuseMaterial;
pub use hair::HairMaterial;
pub use lambertsphere::LambertSphereMaterial;
pub use mask::MaskMaterial;
pub use measured::MeasuredMaterial;
pub use measured_polarized::MeasuredPolarizedMaterial;
pub use normalmap::NormalMapMaterial;
pub use null::NullMaterial;
pub use plastic::PlasticMaterial;
pub use polarizer::PolarizerMaterial;
pub use principled::PrincipledMaterial;
pub use principledthin::PrincipledThinMaterial;
pub use retarder::RetarderMaterial;
pub use roughconductor::RoughConductorMaterial;
pub use roughdielectric::RoughDielectricMaterial;
pub use roughdiffuse::RoughDiffuseMaterial;
pub use roughplastic::RoughPlasticMaterial;
pub use tabulated::TabulatedMaterial;
pub use thindielectric::ThinDielectricMaterial;
pub use twosided::TwoSidedMaterial;

use crate::geometry::SurfaceInteraction;
use crate::texture::Texture;
use glam::{Vec2, Vec3};
use gonio_core::Frame;
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths, Spectrum};
use std::any::Any;
use std::fmt::Debug;
use std::sync::Arc;

/// Every BSDF plugin the reader knows, in the order the documentation lists them.
pub static BSDF_PLUGINS: &[&BsdfPlugin] = &[
    &diffuse::PLUGIN,
    &conductor::PLUGIN,
    &dielectric::PLUGIN,
    &thindielectric::PLUGIN,
    &plastic::PLUGIN,
    &roughconductor::PLUGIN,
    &roughdiffuse::PLUGIN,
    &roughplastic::PLUGIN,
    &pplastic::PLUGIN,
    &roughdielectric::PLUGIN,
    &principled::PLUGIN,
    &principledthin::PLUGIN,
    &hair::PLUGIN,
    &lambertsphere::PLUGIN,
    &twosided::PLUGIN,
    &blendbsdf::PLUGIN,
    &tabulated::PLUGIN,
    &measured::PLUGIN,
    &measured_polarized::PLUGIN,
    &polarizer::PLUGIN,
    &retarder::PLUGIN,
    &circular::PLUGIN,
    &null::PLUGIN,
    &mask::PLUGIN,
    &normalmap::PLUGIN,
    &bumpmap::PLUGIN,
];

/// The registered plugin called `name`.
pub fn bsdf_plugin(name: &str) -> Option<&'static BsdfPlugin> {
    crate::xml::Plugin::find(BSDF_PLUGINS, name)
}

/// A material as the scene holds it: one BSDF plugin with its textures and prebuilt model.
pub trait SurfaceMaterial: Send + Sync + Debug + Any {
    /// Union of the lobe flags of every BSDF this material can become (null transmission,
    /// delta lobes, transmission... are read from here, not by walking materials).
    fn flags(&self) -> BsdfFlags;

    /// True when some parameter varies over the surface.
    fn is_textured(&self) -> bool;

    /// Number of [`SurfaceBsdf`] nodes [`SurfaceMaterial::push`] adds (1 for a model).
    fn node_count(&self) -> usize {
        1
    }

    /// True when a scene holding this material (at any depth of its wrappers) asks to be
    /// rendered polarized, as Mitsuba users expect of `polarizer`, `retarder`, `circular`,
    /// `pplastic` and `measured_polarized`; wrappers answer for their children.
    fn asks_for_polarization(&self) -> bool {
        false
    }

    /// Adds this material at surface coordinates `uv` and wavelengths `wl` to `tree`; returns
    /// the index of its root node.
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes>;

    /// [`SurfaceMaterial::push`] at a hit whose geometry the material may read beyond its uv
    /// (the frame-perturbing `normalmap` and `bumpmap`, and wrappers that may hold them). The
    /// default is `push` at `at.uv`.
    fn push_at<'a>(
        &'a self,
        at: &ShadingPoint,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        self.push(at.uv, wl, tree)
    }

    /// Calls `f` exactly once with the BSDF at `uv`, valid for every wavelength (what the
    /// instruments and the battery use). Nothing is allocated.
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf));
}

/// The differential geometry of a hit, as a material sees it ([`SurfaceMaterial::push_at`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPoint {
    /// Texture coordinates.
    pub uv: Vec2,
    /// Geometric normal (world).
    pub n: Vec3,
    /// The unperturbed shading frame (world).
    pub shading: Frame,
    /// ∂p/∂u (world; zero when degenerate).
    pub dpdu: Vec3,
    /// ∂p/∂v (world; zero when degenerate).
    pub dpdv: Vec3,
    /// The point (world), for textures defined in space (`volume`).
    pub p: Vec3,
    /// The triangle hit on a mesh (0 otherwise), for `mesh_attribute` textures.
    pub prim: u32,
    /// The barycentric coordinates (b₁, b₂) of the hit on that triangle (zero otherwise), for
    /// `mesh_attribute` textures (see [`SurfaceInteraction::bary`]).
    pub bary: Vec2,
}

impl ShadingPoint {
    /// A point known only by its uv: flat, shading frame = world axes, ∂p/∂u = x, ∂p/∂v = y
    /// (what the instruments and `Material::bsdf_at` use).
    pub fn flat(uv: Vec2) -> Self {
        Self {
            uv,
            n: Vec3::Z,
            shading: Frame::from_normal_tangent(Vec3::Z, Vec3::X),
            dpdu: Vec3::X,
            dpdv: Vec3::Y,
            p: Vec3::ZERO,
            prim: 0,
            bary: Vec2::ZERO,
        }
    }
}

impl From<&SurfaceInteraction> for ShadingPoint {
    fn from(si: &SurfaceInteraction) -> Self {
        Self {
            uv: si.uv,
            n: si.n,
            shading: si.shading,
            dpdu: si.dpdu,
            dpdv: si.dpdv,
            p: si.p,
            prim: si.prim,
            bary: si.bary,
        }
    }
}

/// A scene material: a shared [`SurfaceMaterial`].
#[derive(Clone, Debug)]
pub struct Material(Arc<dyn SurfaceMaterial>);

impl Material {
    /// Wraps a plugin's material.
    pub fn new(m: impl SurfaceMaterial) -> Self {
        Material(Arc::new(m))
    }

    /// Mitsuba's default material for a shape without a BSDF: diffuse with ρ = 0.5, or ρ = 0 if
    /// the shape emits.
    pub fn default_for_shape(emitter: bool) -> Self {
        Material::new(DiffuseMaterial::new(Texture::constant(if emitter {
            0.0
        } else {
            0.5
        })))
    }

    /// The plugin's own type, when it is a `T` (for inspection and tests).
    pub fn get<T: SurfaceMaterial>(&self) -> Option<&T> {
        let any: &dyn Any = self.0.as_ref();
        any.downcast_ref::<T>()
    }

    /// The plugin's material.
    pub fn as_surface(&self) -> &dyn SurfaceMaterial {
        self.0.as_ref()
    }

    /// The `Copy` BSDF value at a hit: textures at `uv`, spectra at `wl`. Valid for `wl` only.
    #[inline]
    pub fn bsdf_at(&self, uv: Vec2, wl: &SampledWavelengths) -> SurfaceBsdf<'_> {
        let mut tree = SurfaceBsdf::new();
        self.fill_bsdf(uv, wl, &mut tree);
        tree
    }

    /// [`Material::bsdf_at`] into an existing value (a path's buffer, reused from vertex to vertex).
    #[inline]
    pub fn fill_bsdf<'a>(&'a self, uv: Vec2, wl: &SampledWavelengths, tree: &mut SurfaceBsdf<'a>) {
        tree.clear();
        // The reader refuses materials of more than MAX_NODES nodes (`Builder::bsdf`), so this
        // cannot fail; an empty tree would be black.
        let _ = self.0.push(uv, wl, tree);
    }

    /// [`Material::fill_bsdf`] at a hit: the material may read its geometry beyond the uv
    /// ([`SurfaceMaterial::push_at`]; normal and bump maps perturb the shading frame).
    #[inline]
    pub fn fill_bsdf_at<'a>(
        &'a self,
        at: &ShadingPoint,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) {
        tree.clear();
        // As in `fill_bsdf`: the reader bounds the node count.
        let _ = self.0.push_at(at, wl, tree);
    }

    /// [`Material::bsdf_at`] at a hit ([`Material::fill_bsdf_at`]).
    #[inline]
    pub fn bsdf_at_point(&self, at: &ShadingPoint, wl: &SampledWavelengths) -> SurfaceBsdf<'_> {
        let mut tree = SurfaceBsdf::new();
        self.fill_bsdf_at(at, wl, &mut tree);
        tree
    }

    /// Union of the lobe flags.
    pub fn flags(&self) -> BsdfFlags {
        self.0.flags()
    }

    /// True when the material transmits light.
    pub fn has_transmission(&self) -> bool {
        self.flags().is_transmission()
    }

    /// True when some lobe passes straight through without changing the medium (a thin sheet).
    pub fn has_null_transmission(&self) -> bool {
        self.flags().contains(BsdfFlags::NULL)
    }

    /// True when some parameter varies over the surface.
    pub fn is_textured(&self) -> bool {
        self.0.is_textured()
    }

    /// Builds the BSDF at `uv`, valid for every wavelength, and hands it to `f` (instruments).
    pub fn with_bsdf<R>(&self, uv: Vec2, f: impl FnOnce(&dyn Bsdf) -> R) -> R {
        let mut f = Some(f);
        let mut out = None;
        self.0.visit(uv, &mut |b| {
            if let Some(f) = f.take() {
                out = Some(f(b));
            }
        });
        out.expect("SurfaceMaterial::visit calls its callback exactly once")
    }
}

/// The constant value of a texture for a prebuilt model (the mean when textured).
/// A material that is one measured table, untextured (`tabulated`, `measured`,
/// `measured_polarized`): the model, shared by every hit, is borrowed into the per-hit BSDF.
#[derive(Clone, Debug)]
pub struct TableMaterial<M> {
    /// The table and what was built from it.
    pub model: Arc<M>,
}

/// A table model's place in [`LeafBsdf`](gonio_core::bsdfs::LeafBsdf), and whether a scene
/// holding it renders polarized.
pub trait TableModel: Bsdf + Debug + 'static {
    /// Asks for a polarized render (a polarimetric table).
    const POLARIZED: bool = false;
    /// The model as a leaf of a [`SurfaceBsdf`].
    fn leaf(&self) -> gonio_core::bsdfs::LeafBsdf<'_>;
}

impl<M: TableModel> SurfaceMaterial for TableMaterial<M> {
    fn asks_for_polarization(&self) -> bool {
        M::POLARIZED
    }
    fn flags(&self) -> BsdfFlags {
        self.model.flags()
    }
    fn is_textured(&self) -> bool {
        false
    }
    fn push<'a>(
        &'a self,
        _uv: Vec2,
        _wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        tree.push_leaf(self.model.leaf())
    }
    fn visit(&self, _uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        f(self.model.as_ref())
    }
}

/// The required `filename` of a plugin that reads a table (`tabulated`, `measured`,
/// `measured_polarized`), resolved against the scene's folders and read by `read`: a missing
/// parameter is an error at the element, a failed read one at the value, naming the file.
pub(crate) fn read_filename<'d, T, E: std::fmt::Display>(
    b: &mut crate::xml::Builder<'d>,
    p: &mut crate::xml::Params<'d>,
    plugin: &str,
    read: impl FnOnce(&std::path::Path) -> Result<T, E>,
) -> Result<T, crate::xml::SceneError> {
    use crate::xml::{ErrorKind, SceneError};
    let Some((name, floc)) = p.string_opt("filename")? else {
        return Err(SceneError::new(
            b.object(p).loc.clone(),
            ErrorKind::Grammar,
            format!("<bsdf type=\"{plugin}\"> needs a filename"),
        ));
    };
    let path = b.resolve_file(p, name);
    read(&path).map_err(|e| {
        SceneError::new(
            floc.clone(),
            ErrorKind::BadValue,
            format!("filename \"{name}\": {e}"),
        )
    })
}

pub(crate) fn model_value(t: &Texture) -> Spectrum {
    match t {
        Texture::Spectrum(s) => s.clone(),
        _ => Spectrum::Constant(t.mean()),
    }
}

/// Replaces `value`, a parameter of a model already evaluated at `wl` by its `at(wl)`, with the
/// texture's value at `uv` when the parameter is textured. An untextured parameter is the model's
/// own spectrum ([`model_value`]), so it is left as evaluated: one evaluation per hit.
#[inline]
pub(crate) fn retint_at(
    value: &mut gonio_core::SampledSpectrum,
    t: &Texture,
    uv: Vec2,
    wl: &SampledWavelengths,
) {
    if t.is_textured() {
        *value = t.eval(uv).sample(wl);
    }
}

/// Hands `f` the prebuilt `model`, or, when some of its tints are textured, a copy on the stack
/// with the tints at this point set by `retint`.
pub(crate) fn retinted<M: Bsdf + Clone>(
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
