//! The accelerator of scenes with a handful of primitives: a flat list, with no tree.
//!
//! Spheres, and planes (rectangles and disks), are tested exactly, four spheres or four planes
//! at a time, one lane each (the arithmetic of
//! [`intersect_sphere`](crate::geometry::shape::intersect_sphere) and of the planar test,
//! operation for operation, so a lane finds the distance the scalar test finds, bit for bit). The other primitives (triangles, instances, grids) have their bounding boxes
//! tested four at a time with one slab test per lane (Kay and Kajiya 1986), then the exact
//! primitive test for the boxes the ray enters.
//!
//! For the shared reference scenes (7 to 16 primitives: spheres, rectangles, a 12-triangle cube)
//! a BVH has one or two levels and its per-ray set-up (obvhs' CWBVH: octant, a 32-entry stack,
//! decoding quantized child boxes) cost more than all the box tests together: callgrind counted
//! about 720 instructions per closest-hit query of thin-vs-thick in obvhs' traversal alone.
//! Testing each primitive exactly one at a time (no boxes) was slower still, since an analytic
//! shape's scalar test costs several box tests; in lanes the exact test of four spheres or
//! planes costs about what the four box tests did, and replaces them and the scalar tests behind
//! them (callgrind, furnace: 6.5 % fewer estimated cycles per sample, materials 2 % fewer
//! instructions). Triangles in lanes (the watertight test four at a time) were measured and not
//! kept: thin-vs-thick's cube ran no faster, the boxes culling most of its triangles for fewer
//! instructions. Above [`MAX_PRIMS`] the BVH takes over.
//!
//! Boxes are the same padded boxes the BVH is built from, so a primitive is tested whenever its
//! box is entered; the far distance gets a slack of a few ulps (Ize 2013, "Robust BVH Ray
//! Traversal") so that rounding in the slab test never culls a box a ray grazes.
//!
//! Closest-hit and any-hit queries take the lanes; the query that visits every hit
//! ([`FlatList::each`]) tests the boxes of all primitives in list order. A closest hit met by two
//! primitives at exactly the same distance goes to the first tested (spheres, then planes, then
//! the rest), not to the first in scene order; and an `sdfgrid` behind them is searched up to the
//! nearer distance they leave (its root search clips its interval there), so its hit may move by
//! a few ulps against a search up to a farther one.

use super::{Prim, prim_ids, prim_test, slab_inverse};
use crate::geometry::shape::{PrimHit, TriRay};
use crate::geometry::{Ray, ShapeKind, SurfaceInteraction, WorldShape};
use glam::{BVec4A, Vec3, Vec4};
use obvhs::aabb::Aabb;

/// The most primitives a scene may have for the flat list to be used instead of the BVH.
pub(super) const MAX_PRIMS: usize = 16;

/// Relative slack on a box's far distance: 1 + 2γ₃ rounded up (γₙ = nε/(1 − nε), ε = 2⁻²⁴).
const FAR_SLACK: f32 = 1.0 + 4.0 * f32::EPSILON;

/// Four boxes, structure-of-arrays.
#[derive(Clone, Copy, Debug)]
struct Boxes {
    lo: [Vec4; 3],
    hi: [Vec4; 3],
    /// Bit `i` set when lane `i` holds a box (the last chunk may be partly empty).
    valid: u32,
    /// The primitive (index in the list) of each lane.
    ids: [u32; 4],
}

/// Four spheres, structure-of-arrays.
#[derive(Clone, Copy, Debug)]
struct Spheres {
    /// Centres, component by component.
    center: [Vec4; 3],
    /// Squared radii.
    r2: Vec4,
    /// The lanes that hold a sphere (the last chunk may be partly empty).
    valid: BVec4A,
    /// The primitive (index in the list) of each lane.
    ids: [u32; 4],
}

/// Four rectangles or disks, structure-of-arrays: their world → object transforms (the columns
/// of the linear part, component by component, and the translation) and which lanes are disks.
#[derive(Clone, Copy, Debug)]
struct Planes {
    /// `m[j][k]`: component `k` of column `j` of the linear part.
    m: [[Vec4; 3]; 3],
    /// The translation, component by component.
    t: [Vec4; 3],
    /// The lanes that are disks (the others rectangles).
    disk: BVec4A,
    /// The lanes that hold a plane.
    valid: BVec4A,
    /// The primitive (index in the list) of each lane.
    ids: [u32; 4],
}

/// The primitives of a small scene: spheres and planes in lanes, boxes for the rest.
#[derive(Clone, Debug)]
pub(super) struct FlatList {
    spheres: Vec<Spheres>,
    planes: Vec<Planes>,
    /// The boxes of the other primitives (closest-hit and any-hit queries).
    rest: Vec<Boxes>,
    /// The boxes of all primitives, in list order (the query that visits every hit).
    all: Vec<Boxes>,
    /// Some primitive is a triangle: queries prepare the ray for the triangle test.
    triangles: bool,
}

/// A ray prepared for the lane tests: origin and direction splatted over four lanes.
struct LaneRay {
    o: [Vec4; 3],
    d: [Vec4; 3],
}

/// `v`'s components, each splatted over four lanes.
#[inline(always)]
fn splat3(v: Vec3) -> [Vec4; 3] {
    [Vec4::splat(v.x), Vec4::splat(v.y), Vec4::splat(v.z)]
}

impl LaneRay {
    #[inline(always)]
    fn new(ray: &Ray) -> Self {
        Self {
            o: splat3(ray.o),
            d: splat3(ray.d),
        }
    }
}

/// `ray`'s inverse direction for the slab test, splatted (made only where boxes are tested: its
/// three divisions are a sphere-only scene's largest cost per query after the sphere test).
#[inline(always)]
fn inverse_direction(ray: &Ray) -> [Vec4; 3] {
    splat3(Vec3::new(
        slab_inverse(ray.d.x),
        slab_inverse(ray.d.y),
        slab_inverse(ray.d.z),
    ))
}

/// Groups `items` (lane payload, primitive index) four by four into chunks made by `make`.
fn chunks_of<T, C>(items: &[(T, u32)], make: impl Fn(&[(T, u32)], u32, [u32; 4]) -> C) -> Vec<C> {
    items
        .chunks(4)
        .map(|c| {
            let mut ids = [0u32; 4];
            for (lane, &(_, id)) in c.iter().enumerate() {
                ids[lane] = id;
            }
            make(c, (1u32 << c.len()) - 1, ids)
        })
        .collect()
}

/// The lane of the smallest `t` among the lanes of `hit` (the first of equals), and that `t`.
/// Some lane must be set (the callers ask `hit.any()` first; a NaN distance never is one).
#[inline(always)]
fn nearest_lane(hit: BVec4A, t: Vec4) -> (usize, f32) {
    debug_assert!(hit.any());
    let t = Vec4::select(hit, t, Vec4::INFINITY);
    let m = t.min_element();
    (
        (t.cmpeq(Vec4::splat(m)) & hit).bitmask().trailing_zeros() as usize,
        m,
    )
}

/// A chunk's bit mask of valid lanes (bit `i` for lane `i`) as a lane mask.
fn lane_mask(valid: u32) -> BVec4A {
    BVec4A::new(valid & 1 != 0, valid & 2 != 0, valid & 4 != 0, valid & 8 != 0)
}

impl FlatList {
    /// The list of `prims` (over `shapes`) with their `boxes` (one per primitive, same order).
    pub(super) fn new(shapes: &[WorldShape], prims: &[Prim], boxes: &[Aabb]) -> Self {
        let triangles = prims.iter().any(|p| match *p {
            Prim::Tri { .. } => true,
            Prim::Analytic { shape } => matches!(shapes[shape as usize].kind, ShapeKind::Mesh(_)),
        });
        let mut spheres = Vec::new();
        let mut planes = Vec::new();
        let mut rest = Vec::new();
        for (i, p) in prims.iter().enumerate() {
            let id = i as u32;
            let kind = match *p {
                Prim::Analytic { shape } => Some(&shapes[shape as usize].kind),
                Prim::Tri { .. } => None,
            };
            match kind {
                Some(ShapeKind::Sphere { center, radius, .. }) => {
                    spheres.push(((*center, *radius * *radius), id));
                }
                Some(ShapeKind::Rectangle { to_object, .. }) => planes.push(((*to_object, false), id)),
                Some(ShapeKind::Disk { to_object, .. }) => planes.push(((*to_object, true), id)),
                _ => rest.push((boxes[i], id)),
            }
        }
        let spheres = chunks_of(&spheres, |c, valid, ids| {
            let (mut center, mut r2) = ([[0.0f32; 4]; 3], [0.0f32; 4]);
            for (lane, &((at, rr), _)) in c.iter().enumerate() {
                for k in 0..3 {
                    center[k][lane] = at[k];
                }
                r2[lane] = rr;
            }
            Spheres {
                center: center.map(Vec4::from_array),
                r2: Vec4::from_array(r2),
                valid: lane_mask(valid),
                ids,
            }
        });
        let planes = chunks_of(&planes, |c, valid, ids| {
            let (mut m, mut t, mut disk) = ([[[0.0f32; 4]; 3]; 3], [[0.0f32; 4]; 3], [false; 4]);
            for (lane, &((a, is_disk), _)) in c.iter().enumerate() {
                let cols = [a.matrix3.x_axis, a.matrix3.y_axis, a.matrix3.z_axis];
                for j in 0..3 {
                    for k in 0..3 {
                        m[j][k][lane] = cols[j][k];
                    }
                }
                for k in 0..3 {
                    t[k][lane] = a.translation[k];
                }
                disk[lane] = is_disk;
            }
            Planes {
                m: m.map(|col| col.map(Vec4::from_array)),
                t: t.map(Vec4::from_array),
                disk: BVec4A::from_array(disk),
                valid: lane_mask(valid),
                ids,
            }
        });
        let all: Vec<(Aabb, u32)> = boxes.iter().enumerate().map(|(i, b)| (*b, i as u32)).collect();
        Self {
            spheres,
            planes,
            rest: box_chunks(&rest),
            all: box_chunks(&all),
            triangles,
        }
    }

    /// The triangle test's set-up of `ray`, made only when a primitive needs it.
    #[inline(always)]
    fn tri_ray(&self, ray: &Ray) -> TriRay {
        if self.triangles {
            TriRay::new(ray)
        } else {
            TriRay::none(ray)
        }
    }

    /// Lanes of chunk `c` whose box the ray enters within `(0, tmax]` (bit `i` for lane `i`).
    #[inline(always)]
    fn entered(c: &Boxes, r: &LaneRay, inv: &[Vec4; 3], tmax: f32) -> u32 {
        let t0x = (c.lo[0] - r.o[0]) * inv[0];
        let t1x = (c.hi[0] - r.o[0]) * inv[0];
        let t0y = (c.lo[1] - r.o[1]) * inv[1];
        let t1y = (c.hi[1] - r.o[1]) * inv[1];
        let t0z = (c.lo[2] - r.o[2]) * inv[2];
        let t1z = (c.hi[2] - r.o[2]) * inv[2];
        let near = t0x.min(t1x).max(t0y.min(t1y)).max(t0z.min(t1z)).max(Vec4::ZERO);
        let far = t0x
            .max(t1x)
            .min(t0y.max(t1y))
            .min(t0z.max(t1z))
            .min(Vec4::splat(tmax));
        near.cmple(far * FAR_SLACK).bitmask() & c.valid
    }

    /// The lanes of `s` the ray hits in `(0, tmax)` and each lane's distance: `intersect_sphere`
    /// in four lanes (`f = o − c`, `b = f·d`, `c = |f|² − r²`, `disc = r² − |f − b d|²`, the
    /// stable root `q = −b − sign(b)·√disc`, roots `c/q` and `q`, the nearer one in range). Where
    /// the scalar test returns early (`disc < 0`), √disc is NaN and so are both roots, which no
    /// range check passes.
    #[inline(always)]
    fn sphere_hits(s: &Spheres, r: &LaneRay, tmax: f32) -> (BVec4A, Vec4) {
        let f = [r.o[0] - s.center[0], r.o[1] - s.center[1], r.o[2] - s.center[2]];
        let dot = |a: &[Vec4; 3], b: &[Vec4; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let b = dot(&f, &r.d);
        let c = dot(&f, &f) - s.r2;
        let l = [f[0] - b * r.d[0], f[1] - b * r.d[1], f[2] - b * r.d[2]];
        let disc = s.r2 - dot(&l, &l);
        let q = -b - disc.sqrt().copysign(b);
        let nonzero = q.cmpne(Vec4::ZERO);
        let t0 = Vec4::select(nonzero, c / q, Vec4::ZERO);
        let t1 = Vec4::select(nonzero, q, Vec4::ZERO);
        let swap = t0.cmpgt(t1);
        let (near, far) = (Vec4::select(swap, t1, t0), Vec4::select(swap, t0, t1));
        let tmax = Vec4::splat(tmax);
        let near_in = near.cmpgt(Vec4::ZERO) & near.cmplt(tmax);
        let far_in = far.cmpgt(Vec4::ZERO) & far.cmplt(tmax);
        let t = Vec4::select(near_in, near, far);
        ((near_in | far_in) & s.valid, t)
    }

    /// The lanes of `p` the ray hits in `(0, tmax)`, with each lane's distance and object-space
    /// `(x, y)`: the planar test in four lanes (the ray to object space as `Affine3A` maps it,
    /// `t = −o_z/d_z`, inside |x|, |y| ≤ 1 or x² + y² ≤ 1).
    #[inline(always)]
    fn plane_hits(p: &Planes, r: &LaneRay, tmax: f32) -> (BVec4A, Vec4, Vec4, Vec4) {
        // `Mat3A * v`: ((x_axis·v.x + y_axis·v.y) + z_axis·v.z), component by component.
        let linear = |v: &[Vec4; 3], k: usize| p.m[0][k] * v[0] + p.m[1][k] * v[1] + p.m[2][k] * v[2];
        let (oz, dz) = (linear(&r.o, 2) + p.t[2], linear(&r.d, 2));
        let t = -oz / dz;
        let tmax = Vec4::splat(tmax);
        let ahead = dz.cmpne(Vec4::ZERO) & t.cmpgt(Vec4::ZERO) & t.cmplt(tmax);
        let ahead = ahead & p.valid;
        if !ahead.any() {
            return (ahead, t, t, t);
        }
        let x = (linear(&r.o, 0) + p.t[0]) + t * linear(&r.d, 0);
        let y = (linear(&r.o, 1) + p.t[1]) + t * linear(&r.d, 1);
        let square = x.abs().cmple(Vec4::ONE) & y.abs().cmple(Vec4::ONE);
        let round = (x * x + y * y).cmple(Vec4::ONE);
        (ahead & ((p.disk & round) | (!p.disk & square)), t, x, y)
    }

    /// The closest primitive hit in `(0, ray.tmax)` and its index in `prims`.
    #[inline]
    pub(super) fn closest(
        &self,
        shapes: &[WorldShape],
        prims: &[Prim],
        ray: &Ray,
    ) -> Option<(PrimHit, usize)> {
        let lanes = LaneRay::new(ray);
        let mut q = *ray;
        let mut best = None;
        for s in &self.spheres {
            let (hit, t) = Self::sphere_hits(s, &lanes, q.tmax);
            if hit.any() {
                let (lane, t) = nearest_lane(hit, t);
                q.tmax = t;
                best = Some((PrimHit { t, a: 0.0, b: 0.0 }, s.ids[lane] as usize));
            }
        }
        for p in &self.planes {
            let (hit, t, x, y) = Self::plane_hits(p, &lanes, q.tmax);
            if hit.any() {
                let (lane, t) = nearest_lane(hit, t);
                q.tmax = t;
                let (a, b) = (x[lane], y[lane]);
                best = Some((PrimHit { t, a, b }, p.ids[lane] as usize));
            }
        }
        if self.rest.is_empty() {
            return best;
        }
        let (tri, inv) = (self.tri_ray(ray), inverse_direction(ray));
        for c in &self.rest {
            let mut m = Self::entered(c, &lanes, &inv, q.tmax);
            while m != 0 {
                let id = c.ids[m.trailing_zeros() as usize] as usize;
                m &= m - 1;
                if let Some(h) = prim_test(shapes, &prims[id], &q, &tri) {
                    q.tmax = h.t;
                    best = Some((h, id));
                }
            }
        }
        best
    }

    /// Whether any primitive is hit in `(0, ray.tmax)`.
    #[inline]
    pub(super) fn any(&self, shapes: &[WorldShape], prims: &[Prim], ray: &Ray) -> bool {
        let lanes = LaneRay::new(ray);
        if self
            .spheres
            .iter()
            .any(|s| Self::sphere_hits(s, &lanes, ray.tmax).0.any())
            || self
                .planes
                .iter()
                .any(|p| Self::plane_hits(p, &lanes, ray.tmax).0.any())
        {
            return true;
        }
        if self.rest.is_empty() {
            return false;
        }
        let (tri, inv) = (self.tri_ray(ray), inverse_direction(ray));
        for c in &self.rest {
            let mut m = Self::entered(c, &lanes, &inv, ray.tmax);
            while m != 0 {
                let id = c.ids[m.trailing_zeros() as usize] as usize;
                m &= m - 1;
                if prim_test(shapes, &prims[id], ray, &tri).is_some() {
                    return true;
                }
            }
        }
        false
    }

    /// Calls `f` for every hit in `(0, ray.tmax)` until it returns `true`; whether it stopped.
    pub(super) fn each(
        &self,
        shapes: &[WorldShape],
        prims: &[Prim],
        ray: &Ray,
        f: &mut dyn FnMut(&SurfaceInteraction) -> bool,
    ) -> bool {
        let (tri, lanes, inv) = (self.tri_ray(ray), LaneRay::new(ray), inverse_direction(ray));
        for c in &self.all {
            let mut m = Self::entered(c, &lanes, &inv, ray.tmax);
            while m != 0 {
                let id = c.ids[m.trailing_zeros() as usize] as usize;
                m &= m - 1;
                // An instance: every hit inside it, as the BVH's any-hit query visits them.
                if let Some((shape, inst)) = super::instance_prim(shapes, &prims[id]) {
                    if inst.for_each_hit(ray, shape, f) {
                        return true;
                    }
                    continue;
                }
                if let Some(h) = prim_test(shapes, &prims[id], ray, &tri) {
                    let (shape, prim) = prim_ids(&prims[id]);
                    if f(&shapes[shape as usize].interaction(shape, prim as usize, ray, h)) {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// Boxes (with their primitive indices) in chunks of four.
fn box_chunks(boxes: &[(Aabb, u32)]) -> Vec<Boxes> {
    chunks_of(boxes, |c, valid, ids| {
        let mut lo = [[0.0f32; 4]; 3];
        let mut hi = [[0.0f32; 4]; 3];
        for (lane, (b, _)) in c.iter().enumerate() {
            for axis in 0..3 {
                lo[axis][lane] = b.min[axis];
                hi[axis][lane] = b.max[axis];
            }
        }
        Boxes {
            lo: lo.map(Vec4::from_array),
            hi: hi.map(Vec4::from_array),
            valid,
            ids,
        }
    })
}
