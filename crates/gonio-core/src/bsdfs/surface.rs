//! The BSDF a material becomes at one hit: a small `Copy` value, closed over the models.
//!
//! As in pbrt-v4 (`Material::GetBSDF` returning a `BSDF` over a closed `BxDF` variant), a
//! renderer turns its material into a [`SurfaceBsdf`] once per hit: textures looked up and every
//! spectrum evaluated at the path's four wavelengths ([`SpectralValue`] for
//! [`crate::SampledSpectrum`], [`crate::ior::SampledIor`]). The value holds no
//! `Arc`, allocates nothing, and can be kept (in a queue of a wavefront renderer, say) for as long
//! as the scene it borrows from (a measured table is borrowed, not copied).
//!
//! `blendbsdf` and `twosided` are nodes of a small tree stored in a fixed array (children before
//! parents, the root last); they are evaluated by the very same code as the core
//! [`BlendBsdf`] and [`TwoSided`] adapters, so a material gives the same numbers whether it is
//! evaluated here or through the adapters (what the battery checks).
//!
//! **Validity**: a value built for wavelengths `wl` answers only for those wavelengths (a
//! dispersive refraction may terminate the secondaries; their λ, and so these values, stay the
//! same).
//!
//! [`SpectralValue`]: crate::spectra::SpectralValue

use super::roughplastic::{RoughCoat, RoughPlastic};
use super::{
    BlendBsdf, Conductor, Dielectric, Diffuse, LambertSphere, Measured, MeasuredPolarized, Plastic,
    Principled, PrincipledThin, RoughConductor, RoughDielectric, Tabulated, ThinDielectric, TwoSided,
};
use super::{CircularPolarizer, Polarizer, Retarder};
use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, LobeSplit};
use crate::ior::SampledIor;
use crate::microfacet::MicrofacetDistribution;
use crate::mueller::Mueller;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};
use std::mem::MaybeUninit;

/// The most nodes (models, blends, two-sided wrappers) one material may have.
pub const MAX_NODES: usize = 8;

/// One reflection model specialised at a hit. To add a model: a variant here and one arm in
/// `with_leaf!`'s match.
#[derive(Clone, Copy, Debug)]
pub enum LeafBsdf<'a> {
    /// `diffuse`.
    Diffuse(Diffuse<SampledSpectrum>),
    /// `conductor`.
    Conductor(Conductor<SampledSpectrum, SampledIor>),
    /// `dielectric`.
    Dielectric(Dielectric<SampledSpectrum, SampledIor>),
    /// `thindielectric`.
    ThinDielectric(ThinDielectric<SampledSpectrum, SampledIor>),
    /// `plastic`.
    Plastic(Plastic<SampledSpectrum>),
    /// `roughconductor`.
    RoughConductor(RoughConductor<SampledSpectrum, SampledIor>),
    /// `roughdiffuse`.
    RoughDiffuse(super::RoughDiffuse<SampledSpectrum>),
    /// `roughplastic` (its coat's tables borrowed from the scene).
    RoughPlastic(RoughPlastic<SampledSpectrum, &'a RoughCoat>),
    /// `pplastic`.
    PPlastic(super::PPlastic<SampledSpectrum>),
    /// `roughdielectric`.
    RoughDielectric(RoughDielectric<SampledSpectrum, SampledIor>),
    /// `principled`.
    Principled(Principled<SampledSpectrum>),
    /// `principledthin`.
    PrincipledThin(PrincipledThin<SampledSpectrum>),
    /// `lambertsphere`.
    LambertSphere(LambertSphere<SampledSpectrum>),
    /// `tabulated` (a measured table, borrowed from the scene).
    Tabulated(&'a Tabulated),
    /// `measured` (an RGL measured BRDF, borrowed from the scene).
    Measured(&'a Measured),
    /// `measured_polarized` (a measured pBRDF table, borrowed from the scene).
    MeasuredPolarized(&'a MeasuredPolarized),
    /// `polarizer`.
    Polarizer(Polarizer<SampledSpectrum>),
    /// `retarder`.
    Retarder(Retarder<SampledSpectrum>),
    /// `circular`.
    CircularPolarizer(CircularPolarizer<SampledSpectrum>),
    /// `null` (and the pass-through of `mask`).
    Null(super::NullBsdf),
    /// `hair`.
    Hair(super::Hair<SampledSpectrum>),
}

/// Calls `$body` with `$b: &dyn Bsdf` bound to the model inside a [`LeafBsdf`] (static dispatch
/// per arm).
macro_rules! with_leaf {
    ($leaf:expr, $b:ident => $body:expr) => {
        match $leaf {
            LeafBsdf::Diffuse($b) => $body,
            LeafBsdf::Conductor($b) => $body,
            LeafBsdf::Dielectric($b) => $body,
            LeafBsdf::ThinDielectric($b) => $body,
            LeafBsdf::Plastic($b) => $body,
            LeafBsdf::RoughConductor($b) => $body,
            LeafBsdf::RoughDiffuse($b) => $body,
            LeafBsdf::RoughPlastic($b) => $body,
            LeafBsdf::PPlastic($b) => $body,
            LeafBsdf::RoughDielectric($b) => $body,
            LeafBsdf::Principled($b) => $body,
            LeafBsdf::PrincipledThin($b) => $body,
            LeafBsdf::LambertSphere($b) => $body,
            LeafBsdf::Tabulated($b) => {
                let $b: &Tabulated = $b;
                $body
            }
            LeafBsdf::Measured($b) => {
                let $b: &Measured = $b;
                $body
            }
            LeafBsdf::MeasuredPolarized($b) => {
                let $b: &MeasuredPolarized = $b;
                $body
            }
            LeafBsdf::Polarizer($b) => $body,
            LeafBsdf::Retarder($b) => $body,
            LeafBsdf::CircularPolarizer($b) => $body,
            LeafBsdf::Null($b) => $body,
            LeafBsdf::Hair($b) => $body,
        }
    };
}

impl Bsdf for LeafBsdf<'_> {
    #[inline]
    fn flags(&self) -> BsdfFlags {
        with_leaf!(self, b => b.flags())
    }
    #[inline]
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        with_leaf!(self, b => b.eval(ctx, wi, wo, wl))
    }

    fn pdf_is_exact(&self) -> bool {
        with_leaf!(self, b => b.pdf_is_exact())
    }
    #[inline]
    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        with_leaf!(self, b => b.pdf(ctx, wi, wo, wl))
    }
    #[inline]
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        with_leaf!(self, b => b.sample(ctx, wi, u1, u2, wl))
    }
    #[inline]
    fn null_transmission(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        with_leaf!(self, b => b.null_transmission(wi, wl))
    }
    #[inline]
    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        with_leaf!(self, b => b.eval_pdf(ctx, wi, wo, wl))
    }
    #[inline]
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        with_leaf!(self, b => b.eval_mueller(ctx, wi, wo, wl))
    }
    #[inline]
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        with_leaf!(self, b => b.sample_mueller(ctx, wi, u1, u2, wl))
    }
    #[inline]
    fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        with_leaf!(self, b => b.null_transmission_mueller(wi, wl))
    }
}

/// A node of a material's tree.
#[derive(Clone, Copy, Debug)]
enum Node<'a> {
    /// A model.
    Leaf(LeafBsdf<'a>),
    /// `blendbsdf`: (1 − weight)·node a + weight·node b.
    Blend {
        weight: f32,
        a: u8,
        b: u8,
        mitsuba_delta_pdf: bool,
    },
    /// `twosided`: node `front` for cos θi ≥ 0, node `back` mirrored below.
    TwoSided { front: u8, back: u8 },
    /// `normalmap`/`bumpmap`: node `child` in a perturbed shading frame.
    Perturbed {
        perturbation: super::Perturbation,
        child: u8,
    },
}

/// The tree has no room for another node: the material nests more than [`MAX_NODES`] BSDFs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TooManyNodes;

impl std::fmt::Display for TooManyNodes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "a material may nest at most {MAX_NODES} BSDFs (models, blends and two-sided wrappers)"
        )
    }
}

impl std::error::Error for TooManyNodes {}

/// A material at one hit: a tree of at most [`MAX_NODES`] nodes whose root is the last one
/// pushed. Implements [`Bsdf`]; see the module docs.
///
/// The slots past `len` are left uninitialized, so that making one (once per camera path, or
/// per hit) costs nothing whatever `MAX_NODES` is: a `[Node; MAX_NODES]` would be written whole
/// (912 bytes) each time, which measured as 2–4 % more instructions per rendered sample. This is
/// `arrayvec::ArrayVec`'s technique, written out because an `ArrayVec` is not `Copy`.
#[derive(Clone, Copy)]
pub struct SurfaceBsdf<'a> {
    /// Invariant: slots `0..len` are initialized (written by `push`; `len` grows only there,
    /// after the write, and `clear` only lowers it).
    nodes: [MaybeUninit<Node<'a>>; MAX_NODES],
    len: u8,
}

impl std::fmt::Debug for SurfaceBsdf<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list()
            .entries((0..self.len).filter_map(|i| self.node(i)))
            .finish()
    }
}

impl Default for SurfaceBsdf<'_> {
    fn default() -> Self {
        Self::new()
    }
}

impl<'a> SurfaceBsdf<'a> {
    /// An empty tree (black until a node is pushed).
    pub const fn new() -> Self {
        Self {
            nodes: [const { MaybeUninit::uninit() }; MAX_NODES],
            len: 0,
        }
    }

    /// A tree of one model.
    pub fn leaf(leaf: LeafBsdf<'a>) -> Self {
        let mut t = Self::new();
        let _ = t.push(Node::Leaf(leaf));
        t
    }

    fn push(&mut self, node: Node<'a>) -> Result<u8, TooManyNodes> {
        let i = self.len as usize;
        if i >= MAX_NODES {
            return Err(TooManyNodes);
        }
        self.nodes[i] = MaybeUninit::new(node);
        self.len += 1;
        Ok(i as u8)
    }

    /// Node `i`, if the tree has it.
    #[inline]
    fn node(&self, i: u8) -> Option<&Node<'a>> {
        // SAFETY: slots below `len` were written by `push` (the struct's invariant).
        (i < self.len).then(|| unsafe { self.nodes[i as usize].assume_init_ref() })
    }

    /// Adds a model; returns its node index.
    pub fn push_leaf(&mut self, leaf: LeafBsdf<'a>) -> Result<u8, TooManyNodes> {
        self.push(Node::Leaf(leaf))
    }

    /// Adds `(1 − weight)·a + weight·b` of two nodes pushed before; returns its index.
    pub fn push_blend(&mut self, weight: f32, a: u8, b: u8) -> Result<u8, TooManyNodes> {
        self.push_blend_with(weight, a, b, false)
    }

    /// [`push_blend`](Self::push_blend), with Mitsuba 3.9.1's estimator for delta outcomes when
    /// `mitsuba_delta_pdf` ([`BlendBsdf::mitsuba_delta_pdf`]).
    pub fn push_blend_with(
        &mut self,
        weight: f32,
        a: u8,
        b: u8,
        mitsuba_delta_pdf: bool,
    ) -> Result<u8, TooManyNodes> {
        debug_assert!(a < self.len && b < self.len);
        self.push(Node::Blend {
            weight,
            a,
            b,
            mitsuba_delta_pdf,
        })
    }

    /// Adds a two-sided wrapper of nodes pushed before; returns its index.
    pub fn push_two_sided(&mut self, front: u8, back: u8) -> Result<u8, TooManyNodes> {
        debug_assert!(front < self.len && back < self.len);
        self.push(Node::TwoSided { front, back })
    }

    /// Adds node `child` (pushed before) seen through the perturbed normal `perturbation`
    /// ([`super::PerturbedFrame`]); returns its index.
    pub fn push_perturbed(
        &mut self,
        perturbation: super::Perturbation,
        child: u8,
    ) -> Result<u8, TooManyNodes> {
        debug_assert!(child < self.len);
        self.push(Node::Perturbed { perturbation, child })
    }

    /// Lobe splitting ([`LobeSplit`]) when the tree is one single-scattering `roughdielectric`
    /// ([`RoughDielectric::sample_split`]), one smooth `dielectric`
    /// ([`Dielectric::sample_split`]), one `thindielectric` ([`ThinDielectric::sample_split`]) or
    /// one `plastic` ([`Plastic::sample_split`]); `None` for
    /// every other material (the path tracer then samples it as usual).
    pub fn sample_split(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<LobeSplit> {
        if self.len != 1 {
            return None;
        }
        match self.node(0) {
            Some(Node::Leaf(LeafBsdf::RoughDielectric(rd))) => rd.sample_split(ctx, wi, u2, wl),
            Some(Node::Leaf(LeafBsdf::Dielectric(d))) => d.sample_split(ctx, wi, wl),
            Some(Node::Leaf(LeafBsdf::ThinDielectric(d))) => d.sample_split(ctx, wi, wl),
            // Plastic's coin is between its coat's mirror and its base (radiance, both lobes).
            Some(Node::Leaf(LeafBsdf::Plastic(p))) if *ctx == BsdfContext::radiance() => {
                p.sample_split(wi, u2, wl)
            }
            _ => None,
        }
    }

    /// The microfacet distribution of the lobe that reflects light arriving from `wi` when that
    /// lobe is one single-scattering `roughconductor` (f = F·D·G/(4 cos θi cos θo), reflection
    /// only), and whether it lies below the surface: the tree's lone conductor, seen from its
    /// front (cos θi > 0; `false`), or the side of a `twosided` that `wi` faces when that side is
    /// such a conductor (`true` for the back, cos θi < 0, which the tree evaluates with both
    /// directions mirrored, z ↦ −z; the other side may be anything). `None` for every other material and at grazing
    /// incidence. Resampled next-event estimation draws its candidates from it, in the
    /// mirrored frame for the back.
    pub fn single_rough_conductor(&self, wi: Vec3) -> Option<(MicrofacetDistribution, bool)> {
        let conductor = |i: u8| match self.node(i) {
            Some(Node::Leaf(LeafBsdf::RoughConductor(c))) if !c.multiple_scattering => Some(c.distribution),
            _ => None,
        };
        match (self.len, self.node(self.len.wrapping_sub(1))) {
            (1, _) if wi.z > 0.0 => conductor(0).map(|d| (d, false)),
            (_, Some(Node::TwoSided { front, back })) if wi.z != 0.0 => {
                let back_side = wi.z < 0.0;
                conductor(if back_side { *back } else { *front }).map(|d| (d, back_side))
            }
            _ => None,
        }
    }

    /// The largest density max L/∫L dω of a light at infinity that BSDF sampling resolves alone
    /// here ([`MicrofacetDistribution::resolved_light_density`](crate::microfacet::MicrofacetDistribution::resolved_light_density))
    /// when the tree is one single-scattering `roughconductor` or `roughdielectric`, or a
    /// `twosided` whose side facing `wi` is such a conductor ([`Self::single_rough_conductor`]),
    /// whose samples' weights f·|cos θo|/p are bounded; 0 for every other material (a wide or
    /// mixed lobe, a delta lobe, a random walk).
    pub fn resolved_light_density(&self, wi: Vec3) -> f32 {
        match (self.len, self.node(0)) {
            (1, Some(Node::Leaf(LeafBsdf::RoughConductor(c)))) if !c.multiple_scattering => {
                c.distribution.resolved_light_density()
            }
            (1, Some(Node::Leaf(LeafBsdf::RoughDielectric(d)))) if !d.multiple_scattering => {
                d.distribution.resolved_light_density()
            }
            _ => self
                .single_rough_conductor(wi)
                .map_or(0.0, |(d, _)| d.resolved_light_density()),
        }
    }

    /// Empties the tree (keeping its storage): the next push is the first node.
    #[inline]
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.len as usize
    }

    /// True before the first push.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The root: the last node pushed (an empty tree is black).
    #[inline]
    fn root(&self) -> NodeRef<'_, 'a> {
        NodeRef {
            tree: self,
            i: self.len.wrapping_sub(1),
        }
    }
}

/// One node of a tree, as a [`Bsdf`] (children are `NodeRef`s too, so blends and two-sided
/// wrappers run the core adapters' code).
#[derive(Clone, Copy)]
struct NodeRef<'t, 'a> {
    tree: &'t SurfaceBsdf<'a>,
    i: u8,
}

impl NodeRef<'_, '_> {
    /// Runs `f` on this node as a `&dyn Bsdf`.
    #[inline]
    fn with<R>(&self, f: impl FnOnce(&dyn Bsdf) -> R) -> R {
        let at = |i: u8| NodeRef { tree: self.tree, i };
        match self.tree.node(self.i) {
            None => f(&Empty),
            Some(Node::Leaf(l)) => with_leaf!(l, b => f(b)),
            Some(Node::Blend {
                weight,
                a,
                b,
                mitsuba_delta_pdf,
            }) => f(&BlendBsdf::new(*weight, &at(*a), &at(*b)).with_mitsuba_delta_pdf(*mitsuba_delta_pdf)),
            Some(Node::TwoSided { front, back }) => f(&TwoSided::with_back(&at(*front), &at(*back))),
            Some(Node::Perturbed { perturbation, child }) => {
                f(&super::PerturbedFrame::new(*perturbation, &at(*child)))
            }
        }
    }
}

/// The BSDF of an empty tree: black, never sampled.
struct Empty;

impl Bsdf for Empty {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::NONE
    }
    fn eval(&self, _: &BsdfContext, _: Vec3, _: Vec3, _: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::ZERO
    }
    fn pdf(&self, _: &BsdfContext, _: Vec3, _: Vec3, _: &SampledWavelengths) -> f32 {
        0.0
    }
    fn sample(
        &self,
        _: &BsdfContext,
        _: Vec3,
        _: f32,
        _: Vec2,
        _: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        None
    }
}

impl Bsdf for NodeRef<'_, '_> {
    #[inline]
    fn flags(&self) -> BsdfFlags {
        self.with(|b| b.flags())
    }
    #[inline]
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.with(|b| b.eval(ctx, wi, wo, wl))
    }
    #[inline]
    fn pdf_is_exact(&self) -> bool {
        self.with(|b| b.pdf_is_exact())
    }
    #[inline]
    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        self.with(|b| b.pdf(ctx, wi, wo, wl))
    }
    #[inline]
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        self.with(|b| b.sample(ctx, wi, u1, u2, wl))
    }
    #[inline]
    fn null_transmission(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        self.with(|b| b.null_transmission(wi, wl))
    }
    #[inline]
    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        self.with(|b| b.eval_pdf(ctx, wi, wo, wl))
    }
    #[inline]
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        self.with(|b| b.eval_mueller(ctx, wi, wo, wl))
    }
    #[inline]
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        self.with(|b| b.sample_mueller(ctx, wi, u1, u2, wl))
    }
    #[inline]
    fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        self.with(|b| b.null_transmission_mueller(wi, wl))
    }
}

impl Bsdf for SurfaceBsdf<'_> {
    #[inline]
    fn flags(&self) -> BsdfFlags {
        self.root().flags()
    }
    #[inline]
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.root().eval(ctx, wi, wo, wl)
    }
    #[inline]
    fn pdf_is_exact(&self) -> bool {
        self.root().pdf_is_exact()
    }
    #[inline]
    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        self.root().pdf(ctx, wi, wo, wl)
    }
    #[inline]
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        self.root().sample(ctx, wi, u1, u2, wl)
    }
    #[inline]
    fn null_transmission(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        self.root().null_transmission(wi, wl)
    }
    #[inline]
    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        self.root().eval_pdf(ctx, wi, wo, wl)
    }
    #[inline]
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        self.root().eval_mueller(ctx, wi, wo, wl)
    }
    #[inline]
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        self.root().sample_mueller(ctx, wi, u1, u2, wl)
    }
    #[inline]
    fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        self.root().null_transmission_mueller(wi, wl)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Ior;
    use crate::rng::Pcg32;
    use crate::spectra::Spectrum;

    /// The per-hit tree and the core adapters over the unspecialised models give the same
    /// values, bit for bit, for eval, pdf and sample (blend of a two-sided plastic and a
    /// dispersive dielectric; a conductor).
    #[test]
    fn surface_bsdf_matches_the_adapters_bit_for_bit() {
        let plastic = Plastic::new(
            Spectrum::rgb_albedo([0.8, 0.3, 0.1]),
            1.49,
            1.0,
            true,
            Spectrum::Constant(1.0),
        );
        let glass = Dielectric::new(
            Ior::from_spectrum(Spectrum::sellmeier([1.04, 0.23, 1.01], [0.006, 0.02, 103.5])),
            Ior::Constant(1.0),
        );
        let gold = Conductor::new(Spectrum::Constant(0.2), Spectrum::Constant(3.1));
        let mut rng = Pcg32::new(7, 3);
        for _ in 0..2000 {
            let wl = SampledWavelengths::sample_visible(rng.next_f32());
            let two = TwoSided::new(&plastic);
            let reference = BlendBsdf::new(0.3, &two, &glass);
            let mut tree = SurfaceBsdf::new();
            let p = tree.push_leaf(LeafBsdf::Plastic(plastic.at(&wl))).unwrap();
            let t = tree.push_two_sided(p, p).unwrap();
            let g = tree.push_leaf(LeafBsdf::Dielectric(glass.at(&wl))).unwrap();
            tree.push_blend(0.3, t, g).unwrap();
            let single = SurfaceBsdf::leaf(LeafBsdf::Conductor(gold.at(&wl)));
            let dir = |r: &mut Pcg32| {
                let z = 2.0 * r.next_f32() - 1.0;
                let phi = std::f32::consts::TAU * r.next_f32();
                let s = (1.0 - z * z).max(0.0).sqrt();
                Vec3::new(s * phi.cos(), s * phi.sin(), z)
            };
            let (wi, wo) = (dir(&mut rng), dir(&mut rng));
            let (u1, u2) = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
            for (a, b) in [(&tree as &dyn Bsdf, &reference as &dyn Bsdf), (&single, &gold)] {
                for ctx in [BsdfContext::radiance(), BsdfContext::importance()] {
                    assert_eq!(a.flags(), b.flags());
                    assert_eq!(a.eval(&ctx, wi, wo, &wl), b.eval(&ctx, wi, wo, &wl));
                    assert_eq!(a.pdf(&ctx, wi, wo, &wl), b.pdf(&ctx, wi, wo, &wl));
                    let (mut wa, mut wb) = (wl, wl);
                    assert_eq!(
                        a.sample(&ctx, wi, u1, u2, &mut wa),
                        b.sample(&ctx, wi, u1, u2, &mut wb)
                    );
                    assert_eq!(wa, wb);
                }
            }
        }
    }

    #[test]
    fn an_empty_or_cleared_tree_is_black() {
        let wl = SampledWavelengths::fixed(550.0);
        let mut tree = SurfaceBsdf::leaf(LeafBsdf::Diffuse(Diffuse::default().at(&wl)));
        let (wi, wo) = (Vec3::Z, Vec3::new(0.6, 0.0, 0.8));
        let ctx = BsdfContext::radiance();
        assert!(!tree.eval(&ctx, wi, wo, &wl).is_black());
        tree.clear();
        for t in [tree, SurfaceBsdf::new()] {
            assert_eq!(t.flags(), BsdfFlags::NONE);
            assert!(t.eval(&ctx, wi, wo, &wl).is_black());
            assert_eq!(t.pdf(&ctx, wi, wo, &wl), 0.0);
            assert!(
                t.sample(&ctx, wi, 0.5, Vec2::splat(0.5), &mut wl.clone())
                    .is_none()
            );
        }
    }

    #[test]
    fn a_ninth_node_is_refused() {
        let d = Diffuse::default().at(&SampledWavelengths::fixed(550.0));
        let mut tree = SurfaceBsdf::new();
        for _ in 0..MAX_NODES {
            tree.push_leaf(LeafBsdf::Diffuse(d)).unwrap();
        }
        assert_eq!(tree.push_leaf(LeafBsdf::Diffuse(d)), Err(TooManyNodes));
        assert_eq!(tree.len(), MAX_NODES);
    }

    /// `single_rough_conductor` names the lobe that reflects light from `wi` only where it is one
    /// single-scattering rough conductor: a lone one from its front, and the side of a
    /// `twosided` that `wi` faces (the back flagged, for the mirrored frame); nothing from a lone
    /// conductor's back, a `twosided` side of another model, a blend, or at grazing incidence.
    /// `resolved_light_density` follows it for a `twosided` (a lone conductor's does not depend
    /// on the side).
    #[test]
    fn single_rough_conductor_finds_the_side_wi_faces() {
        use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
        let wl = SampledWavelengths::sample_visible(0.4);
        let lobe = |a: f32| MicrofacetDistribution::new(MicrofacetKind::Beckmann, a, a, true);
        let copper = |a: f32| RoughConductor::new(Spectrum::Constant(0.2), Spectrum::Constant(3.1), lobe(a));
        let (front, back, grazing) = (Vec3::new(0.3, 0.1, 0.9), Vec3::new(0.3, 0.1, -0.9), Vec3::X);
        let (c1, c2) = (copper(0.1), copper(0.2));
        let diffuse = Diffuse::new(Spectrum::Constant(0.5));

        let mut lone = SurfaceBsdf::new();
        lone.push_leaf(LeafBsdf::RoughConductor(c1.at(&wl))).unwrap();
        assert_eq!(lone.single_rough_conductor(front), Some((lobe(0.1), false)));
        assert_eq!(lone.single_rough_conductor(back), None);

        let mut two = SurfaceBsdf::new();
        let f = two.push_leaf(LeafBsdf::RoughConductor(c1.at(&wl))).unwrap();
        let b = two.push_leaf(LeafBsdf::RoughConductor(c2.at(&wl))).unwrap();
        two.push_two_sided(f, b).unwrap();
        assert_eq!(two.single_rough_conductor(front), Some((lobe(0.1), false)));
        assert_eq!(two.single_rough_conductor(back), Some((lobe(0.2), true)));
        assert_eq!(two.single_rough_conductor(grazing), None);
        // `narrow_lobes` reads the same side.
        assert_eq!(
            two.resolved_light_density(back),
            lobe(0.2).resolved_light_density()
        );
        assert_eq!(
            two.resolved_light_density(front),
            lobe(0.1).resolved_light_density()
        );
        assert_eq!(
            lone.resolved_light_density(back),
            lobe(0.1).resolved_light_density()
        );

        let mut half = SurfaceBsdf::new();
        let f = half.push_leaf(LeafBsdf::RoughConductor(c1.at(&wl))).unwrap();
        let b = half.push_leaf(LeafBsdf::Diffuse(diffuse.at(&wl))).unwrap();
        half.push_two_sided(f, b).unwrap();
        assert_eq!(half.single_rough_conductor(front), Some((lobe(0.1), false)));
        assert_eq!(half.single_rough_conductor(back), None);

        let mut blend = SurfaceBsdf::new();
        let a = blend.push_leaf(LeafBsdf::RoughConductor(c1.at(&wl))).unwrap();
        let d = blend.push_leaf(LeafBsdf::Diffuse(diffuse.at(&wl))).unwrap();
        blend.push_blend(0.5, a, d).unwrap();
        assert_eq!(blend.single_rough_conductor(front), None);
    }
}
