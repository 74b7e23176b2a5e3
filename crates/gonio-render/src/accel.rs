//! Ray–scene intersection: [`Accel`], a compressed wide BVH (CWBVH, Ylitie et al. 2017) built and
//! traversed by the `obvhs` crate, over our own primitives.
//!
//! `obvhs` only sees boxes and calls back with a primitive number, so analytic spheres,
//! rectangles and disks sit in the same tree as triangles and keep their exact intersections.
//! Primitive records are stored in BVH leaf order (`primitive_indices`), which saves one
//! indirection per candidate; triangles carry their three vertices inline. The choice of crate and
//! its measured speed are in `ARCHITECTURE.md` and `benches/accel.rs`.
//!
//! Scenes of at most 16 primitives skip the BVH: a flat list (`accel/flat.rs`, where the
//! measurements that chose it are) tests their spheres, rectangles and disks exactly, four at a
//! time in lanes, and the boxes of the other primitives four at a time.
//!
//! [`Intersect`] is the interface the integrator uses; [`BruteForce`] implements it by testing
//! every primitive and serves as the test oracle for [`Accel`].

use crate::geometry::shape::{PrimHit, TriRay, intersect_triangle};
use crate::geometry::{Ray, ShapeKind, SurfaceInteraction, WorldShape};
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::node::Bvh2Node;
use obvhs::cwbvh::CwBvh;
use std::time::Duration;

mod cwbvh;
pub mod embree;
mod flat;

/// Ray queries against a set of shapes.
pub trait Intersect {
    /// The closest hit in `(0, ray.tmax)`.
    fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction>;
    /// Whether anything is hit in `(0, ray.tmax)`.
    fn occluded(&self, ray: &Ray) -> bool;
    /// Calls `f` for every hit in `(0, ray.tmax)`, in no particular order, until `f` returns
    /// `true` (stop: e.g. an opaque surface); returns whether it stopped. A shadow ray through
    /// thin dielectric sheets multiplies their transmittance inside `f`.
    fn for_each_hit(&self, ray: &Ray, f: &mut dyn FnMut(&SurfaceInteraction) -> bool) -> bool;
    /// The shapes, indexed by [`SurfaceInteraction::shape`].
    fn shapes(&self) -> &[WorldShape];
}

/// One primitive in leaf order.
#[derive(Clone, Copy, Debug)]
enum Prim {
    /// A triangle with its vertices inline.
    Tri { p: [Vec3; 3], shape: u32, prim: u32 },
    /// An analytic shape.
    Analytic { shape: u32 },
}

/// A closest hit from [`Accel::intersect_lazy`]: its distance known, its interaction built on
/// demand by [`Accel::complete`].
#[derive(Clone, Copy, Debug)]
pub enum LazyHit {
    /// Built already (scenes whose queries re-trace past inside hits).
    Built(SurfaceInteraction),
    /// The primitive hit and where.
    Pending {
        /// Distance and the primitive's coordinates.
        hit: PrimHit,
        /// Shape index.
        shape: u32,
        /// Primitive within the shape.
        prim: u32,
    },
}

impl LazyHit {
    /// The distance along the ray.
    #[inline]
    pub fn t(&self) -> f32 {
        match self {
            LazyHit::Built(si) => si.t,
            LazyHit::Pending { hit, .. } => hit.t,
        }
    }
}

/// The BVH over a list of [`WorldShape`]s.
pub struct Accel {
    shapes: Vec<WorldShape>,
    /// The triangles, when Embree traces them (`accel/embree.rs`); `bvh`, `flat` and `prims`
    /// then hold the analytic shapes only.
    embree: Option<embree::Triangles>,
    bvh: Option<CwBvh>,
    /// Used instead of `bvh` for a few primitives (then `prims` are in scene order).
    flat: Option<flat::FlatList>,
    prims: Vec<Prim>,
    build_time: Duration,
    /// Some shape is hit only from outside (the curves: [`WorldShape::outside_only`]).
    outside_only: bool,
}

impl std::fmt::Debug for Accel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Accel")
            .field("shapes", &self.shapes.len())
            .field("primitives", &self.prims.len())
            .field("build_time", &self.build_time)
            .finish()
    }
}

/// How many primitives `shape` contributes: its triangles, or 1 for an analytic shape.
fn prim_count(shape: &WorldShape) -> usize {
    match &shape.kind {
        ShapeKind::Mesh(m) => m.indices.len(),
        _ => 1,
    }
}

/// Whether Embree is the tracer of these shapes' triangles where the process has it: some shapes
/// are meshes, and there are more primitives than the flat list holds.
fn embree_applies(shapes: &[WorldShape]) -> bool {
    shapes.iter().map(prim_count).sum::<usize>() > flat::MAX_PRIMS
        && shapes.iter().any(|s| matches!(s.kind, ShapeKind::Mesh(_)))
}

/// [`prim_count`] in our own structure: none for a mesh when Embree holds the triangles.
fn own_prim_count(shape: &WorldShape, meshes_elsewhere: bool) -> usize {
    match &shape.kind {
        ShapeKind::Mesh(_) if meshes_elsewhere => 0,
        _ => prim_count(shape),
    }
}

/// Primitive `i` of shape `s`.
fn make_prim(shapes: &[WorldShape], s: usize, i: usize) -> Prim {
    match &shapes[s].kind {
        ShapeKind::Mesh(m) => Prim::Tri {
            p: m.tri(i),
            shape: s as u32,
            prim: i as u32,
        },
        _ => Prim::Analytic { shape: s as u32 },
    }
}

/// The primitives of all shapes in scene order, made on the fly.
struct PrimIter<'a> {
    shapes: &'a [WorldShape],
    shape: usize,
    prim: usize,
    meshes_elsewhere: bool,
}

impl<'a> PrimIter<'a> {
    fn new(shapes: &'a [WorldShape], meshes_elsewhere: bool) -> Self {
        Self {
            shapes,
            shape: 0,
            prim: 0,
            meshes_elsewhere,
        }
    }
}

impl Iterator for PrimIter<'_> {
    type Item = Prim;
    fn next(&mut self) -> Option<Prim> {
        while self.shape < self.shapes.len() {
            if self.prim < own_prim_count(&self.shapes[self.shape], self.meshes_elsewhere) {
                let p = make_prim(self.shapes, self.shape, self.prim);
                self.prim += 1;
                return Some(p);
            }
            self.shape += 1;
            self.prim = 0;
        }
        None
    }
}

fn all_prims(shapes: &[WorldShape], meshes_elsewhere: bool) -> Vec<Prim> {
    let mut prims = Vec::with_capacity(shapes.iter().map(|s| own_prim_count(s, meshes_elsewhere)).sum());
    prims.extend(PrimIter::new(shapes, meshes_elsewhere));
    prims
}

fn prim_aabb(shapes: &[WorldShape], p: &Prim) -> Aabb {
    let (lo, hi) = match *p {
        Prim::Tri { p, .. } => (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2])),
        Prim::Analytic { shape } => shapes[shape as usize].prim_bounds(0),
    };
    // Pad flat boxes (axis-aligned rectangles, triangles) so slab tests never see zero width.
    let pad = (hi - lo).max_element().max(hi.abs().max(lo.abs()).max_element()) * 1e-6 + 1e-12;
    Aabb::new(Vec3A::from(lo - pad), Vec3A::from(hi + pad))
}

#[inline]
fn prim_test(shapes: &[WorldShape], p: &Prim, ray: &Ray, tri: &TriRay) -> Option<PrimHit> {
    match *p {
        Prim::Tri { p, .. } => {
            intersect_triangle(p[0], p[1], p[2], tri, ray.tmax).map(|(t, a, b)| PrimHit { t, a, b })
        }
        Prim::Analytic { shape } => shapes[shape as usize].intersect_prim(0, ray, tri),
    }
}

/// The instance behind a primitive, if it is one: any-hit queries visit every hit inside it.
#[inline]
fn instance_prim<'a>(
    shapes: &'a [WorldShape],
    p: &Prim,
) -> Option<(u32, &'a crate::geometry::instance::Instance)> {
    match *p {
        Prim::Analytic { shape } => match &shapes[shape as usize].kind {
            ShapeKind::Instance(i) => Some((shape, i)),
            _ => None,
        },
        Prim::Tri { .. } => None,
    }
}

#[inline]
fn prim_ids(p: &Prim) -> (u32, u32) {
    match *p {
        Prim::Tri { shape, prim, .. } => (shape, prim),
        Prim::Analytic { shape } => (shape, 0),
    }
}

/// The smallest direction component magnitude the slab test divides by; smaller ones (zeros
/// included) are replaced by this magnitude with the sign the traversal's octant sees. A ray
/// moving `t·1e-20` sideways stays far inside the boxes' padding for any distance a scene has,
/// and `extent · 1e20` stays finite for any node extent below 1e18 (no `0 · ∞` = NaN).
const MIN_DIR_COMPONENT: f32 = 1e-20;

/// `1 / d` for the slab test, with the sign of the octant obvhs picks the box faces by
/// (`d < 0.0`): `-0.0` counts as positive there, so its inverse must be positive too.
/// (`obvhs::ray::Ray::new` returns `-1/ε` for `-0.0`, which flips that slab, so rays such as
/// the shadow ray `-(0, 0, -1)` towards a straight-down directional light missed every box;
/// it also replaces components below `f32::EPSILON` by `±ε`, which narrows their slabs.)
#[inline]
fn slab_inverse(d: f32) -> f32 {
    if d.abs() >= MIN_DIR_COMPONENT {
        1.0 / d
    } else if d < 0.0 {
        -1.0 / MIN_DIR_COMPONENT
    } else {
        1.0 / MIN_DIR_COMPONENT
    }
}

/// The obvhs ray for `ray`, its inverse direction made consistent with the octant
/// ([`slab_inverse`]).
fn to_obvhs(ray: &Ray) -> obvhs::ray::Ray {
    obvhs::ray::Ray {
        origin: Vec3A::from(ray.o),
        direction: Vec3A::from(ray.d),
        inv_direction: Vec3A::new(
            slab_inverse(ray.d.x),
            slab_inverse(ray.d.y),
            slab_inverse(ray.d.z),
        ),
        tmin: 0.0,
        tmax: ray.tmax,
    }
}

impl Accel {
    /// Builds the BVH (obvhs PLOC with reinsertion, `medium_build` settings, then CWBVH), as
    /// `accel/cwbvh.rs` describes: the tree of `obvhs::cwbvh::builder::build_cwbvh`, built
    /// for peak memory, which a 1M-triangle mesh makes matter (bench/RESULTS.md), on the
    /// rayon pool's threads; the primitive records are made only after the tree, directly in
    /// leaf order.
    ///
    /// Past the flat list's size, the triangles of meshes go to Embree when the process has it
    /// ([`embree::available`]; `accel/embree.rs`), the analytic shapes to our own structure.
    pub fn new(shapes: Vec<WorldShape>) -> Self {
        Self::with_embree(shapes, true)
    }

    /// [`Self::new`], with Embree allowed or not (`false`: our BVH for everything, the
    /// structure the Embree path is compared with).
    pub fn with_embree(shapes: Vec<WorldShape>, allow_embree: bool) -> Self {
        let start = std::time::Instant::now();
        let embree = (allow_embree && embree_applies(&shapes))
            .then(|| embree::Triangles::new(&shapes))
            .flatten();
        let meshes_elsewhere = embree.is_some();
        let outside_only = shapes.iter().any(|s| s.outside_only);
        let count: usize = shapes.iter().map(|s| own_prim_count(s, meshes_elsewhere)).sum();
        let mut build_time = start.elapsed();
        if count <= flat::MAX_PRIMS {
            let prims = all_prims(&shapes, meshes_elsewhere);
            let flat = (!prims.is_empty()).then(|| {
                let aabbs: Vec<Aabb> = prims.iter().map(|p| prim_aabb(&shapes, p)).collect();
                flat::FlatList::new(&shapes, &prims, &aabbs)
            });
            return Self {
                shapes,
                embree,
                bvh: None,
                flat,
                prims,
                build_time,
                outside_only,
            };
        }
        let start = std::time::Instant::now();
        let bvh = cwbvh::build(
            PrimIter::new(&shapes, meshes_elsewhere)
                .enumerate()
                .map(|(i, p)| Bvh2Node::new(prim_aabb(&shapes, &p), 1, i as u32)),
            count,
        );
        build_time += start.elapsed();
        // Primitive records in leaf order, from each leaf's scene-order number.
        let firsts: Vec<usize> = shapes
            .iter()
            .scan(0, |n, s| {
                let first = *n;
                *n += own_prim_count(s, meshes_elsewhere);
                Some(first)
            })
            .collect();
        let prims = bvh
            .primitive_indices
            .iter()
            .map(|&i| {
                let i = i as usize;
                let s = firsts.partition_point(|&f| f <= i) - 1;
                make_prim(&shapes, s, i - firsts[s])
            })
            .collect();
        Self {
            shapes,
            embree,
            bvh: Some(bvh),
            flat: None,
            prims,
            build_time,
            outside_only,
        }
    }

    /// Time spent building the BVH.
    pub fn build_time(&self) -> Duration {
        self.build_time
    }

    /// Number of primitives (triangles plus analytic shapes).
    pub fn prim_count(&self) -> usize {
        self.shapes.iter().map(prim_count).sum()
    }

    /// Whether Embree traces this structure's triangles.
    pub fn uses_embree(&self) -> bool {
        self.embree.is_some()
    }

    /// Whether Embree would trace this structure's triangles had the process loaded it: it has
    /// triangle meshes, more primitives than the flat list holds, and Embree is not available
    /// (not installed, or `GONIO_EMBREE=off`), so the meshes went to our own BVH.
    pub fn misses_embree(&self) -> bool {
        self.embree.is_none() && !embree::available() && embree_applies(&self.shapes)
    }

    /// [`Intersect::intersect`] of many rays: `out[i]` for `rays[i]`, the same surfaces. With
    /// Embree, the triangles of every 16 rays are one packet query (`rtcIntersect16`, what a
    /// renderer that traces its paths in lanes would call); the analytic shapes are then tested
    /// ray by ray up to the packet's answer, as in `intersect`. Without Embree it is
    /// `intersect` per ray.
    ///
    /// # Panics
    /// If `out` and `rays` differ in length.
    pub fn intersect_packet(&self, rays: &[Ray], out: &mut [Option<SurfaceInteraction>]) {
        assert_eq!(rays.len(), out.len(), "one answer per ray");
        let Some(tris) = &self.embree else {
            for (o, ray) in out.iter_mut().zip(rays) {
                *o = self.intersect(ray);
            }
            return;
        };
        let mut tri_hits = [None; embree::PACKET];
        for (rays, out) in rays.chunks(embree::PACKET).zip(out.chunks_mut(embree::PACKET)) {
            let tri_hits = &mut tri_hits[..rays.len()];
            tris.closest_packet(rays, tri_hits);
            for ((o, ray), &tri) in out.iter_mut().zip(rays).zip(tri_hits.iter()) {
                *o = self.closest_beside(ray, tri);
                if self.outside_only && o.as_ref().is_some_and(|h| from_inside(&self.shapes, h, ray)) {
                    *o = self.intersect(ray);
                }
            }
        }
    }

    /// The closest hit of `ray` given Embree's answer for the triangles (`tri`: shape, triangle,
    /// hit; `None` also without Embree): our own structure's up to that distance, or else
    /// Embree's.
    #[inline]
    fn closest_beside(&self, ray: &Ray, tri: Option<(u32, u32, PrimHit)>) -> Option<SurfaceInteraction> {
        let (h, shape, prim) = self.closest_record_beside(ray, tri)?;
        Some(self.shapes[shape as usize].interaction(shape, prim as usize, ray, h))
    }

    /// [`Self::closest_beside`] before the interaction is built: (hit, shape, primitive).
    #[inline]
    fn closest_record_beside(
        &self,
        ray: &Ray,
        tri: Option<(u32, u32, PrimHit)>,
    ) -> Option<(PrimHit, u32, u32)> {
        let mut q = *ray;
        if let Some((_, _, h)) = tri {
            q.tmax = h.t;
        }
        self.own_closest(&q)
            .or(tri.map(|(shape, prim, h)| (h, shape, prim)))
    }

    /// The closest hit of `ray` with its interaction left to build ([`Self::complete`]): a free
    /// flight through a medium needs only the distance, and in a dense medium most flights end
    /// before the surface (building the interaction costs the mesh's loads and the frame).
    pub fn intersect_lazy(&self, ray: &Ray) -> Option<LazyHit> {
        if self.outside_only {
            return self.intersect(ray).map(LazyHit::Built);
        }
        let tri = self.embree.as_ref().and_then(|tris| tris.closest(ray));
        let (hit, shape, prim) = self.closest_record_beside(ray, tri)?;
        Some(LazyHit::Pending { hit, shape, prim })
    }

    /// The interaction of a hit found by [`Self::intersect_lazy`] along the same `ray`.
    pub fn complete(&self, ray: &Ray, hit: LazyHit) -> SurfaceInteraction {
        match hit {
            LazyHit::Built(si) => si,
            LazyHit::Pending { hit, shape, prim } => {
                self.shapes[shape as usize].interaction(shape, prim as usize, ray, hit)
            }
        }
    }

    /// The closest hit in our own structure (all primitives, or the analytic ones beside
    /// Embree): (hit, shape, primitive).
    #[inline]
    fn own_closest(&self, ray: &Ray) -> Option<(PrimHit, u32, u32)> {
        let (h, id) = if let Some(flat) = &self.flat {
            flat.closest(&self.shapes, &self.prims, ray)?
        } else {
            let bvh = self.bvh.as_ref()?;
            let tri = TriRay::new(ray);
            let mut best: Option<(PrimHit, usize)> = None;
            let mut hit = obvhs::ray::RayHit::none();
            bvh.ray_traverse(to_obvhs(ray), &mut hit, |r, id| {
                let q = Ray {
                    o: ray.o,
                    d: ray.d,
                    tmax: r.tmax,
                };
                match prim_test(&self.shapes, &self.prims[id], &q, &tri) {
                    Some(h) => {
                        best = Some((h, id));
                        h.t
                    }
                    None => f32::INFINITY,
                }
            });
            best?
        };
        let (shape, prim) = prim_ids(&self.prims[id]);
        Some((h, shape, prim))
    }
}

impl Accel {
    fn closest(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        let tri = self.embree.as_ref().and_then(|tris| tris.closest(ray));
        self.closest_beside(ray, tri)
    }

    fn any(&self, ray: &Ray) -> bool {
        if let Some(tris) = &self.embree
            && tris.any(ray)
        {
            return true;
        }
        if let Some(flat) = &self.flat {
            return flat.any(&self.shapes, &self.prims, ray);
        }
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        let tri = TriRay::new(ray);
        !bvh.ray_traverse_miss(to_obvhs(ray), |_, id| {
            match prim_test(&self.shapes, &self.prims[id], ray, &tri) {
                Some(h) => h.t,
                None => f32::INFINITY,
            }
        })
    }

    fn each(&self, ray: &Ray, f: &mut dyn FnMut(&SurfaceInteraction) -> bool) -> bool {
        if let Some(tris) = &self.embree
            && tris.each(ray, &mut |shape, prim, h| {
                f(&self.shapes[shape as usize].interaction(shape, prim as usize, ray, h))
            })
        {
            return true;
        }
        if let Some(flat) = &self.flat {
            return flat.each(&self.shapes, &self.prims, ray, f);
        }
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        let tri = TriRay::new(ray);
        let mut stopped = false;
        // obvhs' any-hit traversal cannot stop early; after a stop we skip the remaining tests.
        bvh.ray_traverse_anyhit(to_obvhs(ray), |_, id| {
            if stopped {
                return;
            }
            if let Some((shape, inst)) = instance_prim(&self.shapes, &self.prims[id]) {
                stopped = inst.for_each_hit(ray, shape, f);
                return;
            }
            if let Some(h) = prim_test(&self.shapes, &self.prims[id], ray, &tri) {
                let (shape, prim) = prim_ids(&self.prims[id]);
                let si = self.shapes[shape as usize].interaction(shape, prim as usize, ray, h);
                stopped = f(&si);
            }
        });
        stopped
    }
}

/// Whether `h` is the inside of a surface hit only from outside (its geometric normal, outward
/// on the curves' tubes, faces along the ray).
#[inline]
fn from_inside(shapes: &[WorldShape], h: &SurfaceInteraction, ray: &Ray) -> bool {
    shapes[h.shape as usize].outside_only && h.n.dot(ray.d) > 0.0
}

/// Surfaces hit from inside that one query passes before it gives up (a ray starts inside at
/// most the few fibres that overlap there).
const MAX_INSIDES: usize = 64;

/// The closest hit along `ray` that is not the inside of an outside-only surface: `closest`
/// again from just past each such hit (its distance then counted from the ray's origin).
fn closest_outside(
    shapes: &[WorldShape],
    ray: &Ray,
    closest: impl Fn(&Ray) -> Option<SurfaceInteraction>,
) -> Option<SurfaceInteraction> {
    let mut q = *ray;
    let mut travelled = 0.0;
    for _ in 0..MAX_INSIDES {
        let mut h = closest(&q)?;
        if !from_inside(shapes, &h, ray) {
            h.t += travelled;
            return Some(h);
        }
        let o = crate::geometry::offset_ray_origin(h.p, h.n, ray.d);
        let step = (o - q.o).dot(ray.d);
        travelled += step;
        q = Ray {
            o,
            d: ray.d,
            tmax: q.tmax - step,
        };
        if !(q.tmax > 0.0) {
            return None;
        }
    }
    None
}

/// `each` with the insides of outside-only surfaces left out.
fn each_outside(
    shapes: &[WorldShape],
    ray: &Ray,
    f: &mut dyn FnMut(&SurfaceInteraction) -> bool,
    each: impl Fn(&Ray, &mut dyn FnMut(&SurfaceInteraction) -> bool) -> bool,
) -> bool {
    each(ray, &mut |h: &SurfaceInteraction| {
        !from_inside(shapes, h, ray) && f(h)
    })
}

/// Every query past the insides of outside-only surfaces (the curves), when the scene has them.
impl Intersect for Accel {
    fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        if self.outside_only {
            closest_outside(&self.shapes, ray, |q| self.closest(q))
        } else {
            self.closest(ray)
        }
    }

    fn occluded(&self, ray: &Ray) -> bool {
        if self.outside_only {
            each_outside(&self.shapes, ray, &mut |_| true, |r, f| self.each(r, f))
        } else {
            self.any(ray)
        }
    }

    fn for_each_hit(&self, ray: &Ray, f: &mut dyn FnMut(&SurfaceInteraction) -> bool) -> bool {
        if self.outside_only {
            each_outside(&self.shapes, ray, f, |r, g| self.each(r, g))
        } else {
            self.each(ray, f)
        }
    }

    fn shapes(&self) -> &[WorldShape] {
        &self.shapes
    }
}

/// Tests every primitive of every shape: slow, simple, the oracle for [`Accel`] in tests.
#[derive(Debug)]
pub struct BruteForce {
    shapes: Vec<WorldShape>,
    prims: Vec<Prim>,
}

impl BruteForce {
    /// Wraps the shapes.
    pub fn new(shapes: Vec<WorldShape>) -> Self {
        let prims = all_prims(&shapes, false);
        Self { shapes, prims }
    }
}

impl BruteForce {
    fn closest(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        let tri = TriRay::new(ray);
        let mut q = *ray;
        let mut best = None;
        for (i, p) in self.prims.iter().enumerate() {
            if let Some(h) = prim_test(&self.shapes, p, &q, &tri) {
                q.tmax = h.t;
                best = Some((h, i));
            }
        }
        let (h, i) = best?;
        let (shape, prim) = prim_ids(&self.prims[i]);
        Some(self.shapes[shape as usize].interaction(shape, prim as usize, ray, h))
    }

    fn each(&self, ray: &Ray, f: &mut dyn FnMut(&SurfaceInteraction) -> bool) -> bool {
        let tri = TriRay::new(ray);
        for p in &self.prims {
            if let Some((shape, inst)) = instance_prim(&self.shapes, p) {
                if inst.for_each_hit(ray, shape, f) {
                    return true;
                }
                continue;
            }
            if let Some(h) = prim_test(&self.shapes, p, ray, &tri) {
                let (shape, prim) = prim_ids(p);
                if f(&self.shapes[shape as usize].interaction(shape, prim as usize, ray, h)) {
                    return true;
                }
            }
        }
        false
    }
}

impl Intersect for BruteForce {
    fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        closest_outside(&self.shapes, ray, |q| self.closest(q))
    }

    fn occluded(&self, ray: &Ray) -> bool {
        each_outside(&self.shapes, ray, &mut |_| true, |r, f| self.each(r, f))
    }

    fn for_each_hit(&self, ray: &Ray, f: &mut dyn FnMut(&SurfaceInteraction) -> bool) -> bool {
        each_outside(&self.shapes, ray, f, |r, g| self.each(r, g))
    }

    fn shapes(&self) -> &[WorldShape] {
        &self.shapes
    }
}
