//! The accelerator of scenes with a handful of primitives: their bounding boxes in a flat list,
//! tested four at a time with one slab test per lane (Kay and Kajiya 1986), then the exact
//! primitive test for the boxes the ray enters.
//!
//! For the shared reference scenes (7 to 16 primitives: spheres, rectangles, a 12-triangle cube)
//! a BVH has one or two levels and its per-ray set-up (obvhs' CWBVH: octant, a 32-entry stack,
//! decoding quantized child boxes) cost more than all the box tests together: callgrind counted
//! about 720 instructions per closest-hit query of thin-vs-thick in obvhs' traversal alone.
//! Testing each primitive exactly (no boxes) was slower still, since an analytic shape's test
//! costs several box tests. Above [`MAX_PRIMS`] the BVH takes over.
//!
//! Boxes are the same padded boxes the BVH is built from, so a primitive is tested whenever its
//! box is entered; the far distance gets a slack of a few ulps (Ize 2013, "Robust BVH Ray
//! Traversal") so that rounding in the slab test never culls a box a ray grazes.

use super::{Prim, prim_ids, prim_test, slab_inverse};
use crate::geometry::shape::{PrimHit, TriRay};
use crate::geometry::{Ray, SurfaceInteraction, WorldShape};
use glam::{Vec3, Vec4};
use obvhs::aabb::Aabb;

/// The most primitives a scene may have for the flat list to be used instead of the BVH.
pub(super) const MAX_PRIMS: usize = 16;

/// Relative slack on a box's far distance: 1 + 2γ₃ rounded up (γₙ = nε/(1 − nε), ε = 2⁻²⁴).
const FAR_SLACK: f32 = 1.0 + 4.0 * f32::EPSILON;

/// Four boxes, structure-of-arrays.
#[derive(Clone, Copy, Debug)]
struct Chunk {
    lo: [Vec4; 3],
    hi: [Vec4; 3],
    /// Bit `i` set when lane `i` holds a box (the last chunk may be partly empty).
    valid: u32,
}

/// Primitive boxes in chunks of four, in the order of the primitive list they were built from.
#[derive(Clone, Debug)]
pub(super) struct FlatBoxes {
    chunks: Vec<Chunk>,
    /// Some primitive is a triangle: queries prepare the ray for the triangle test.
    triangles: bool,
}

/// A ray prepared for the slab test: origin and inverse direction splatted over four lanes.
struct SlabRay {
    o: [Vec4; 3],
    inv: [Vec4; 3],
}

impl SlabRay {
    fn new(ray: &Ray) -> Self {
        let inv = Vec3::new(
            slab_inverse(ray.d.x),
            slab_inverse(ray.d.y),
            slab_inverse(ray.d.z),
        );
        Self {
            o: [Vec4::splat(ray.o.x), Vec4::splat(ray.o.y), Vec4::splat(ray.o.z)],
            inv: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
        }
    }
}

impl FlatBoxes {
    /// The list of `boxes` (one per primitive, same order); `triangles` when some primitive is
    /// tested as a triangle.
    pub(super) fn new(boxes: &[Aabb], triangles: bool) -> Self {
        let chunks = boxes
            .chunks(4)
            .map(|c| {
                let mut lo = [[0.0f32; 4]; 3];
                let mut hi = [[0.0f32; 4]; 3];
                for (lane, b) in c.iter().enumerate() {
                    for axis in 0..3 {
                        lo[axis][lane] = b.min[axis];
                        hi[axis][lane] = b.max[axis];
                    }
                }
                Chunk {
                    lo: lo.map(Vec4::from_array),
                    hi: hi.map(Vec4::from_array),
                    valid: (1u32 << c.len()) - 1,
                }
            })
            .collect();
        Self { chunks, triangles }
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
    fn entered(&self, c: &Chunk, r: &SlabRay, tmax: f32) -> u32 {
        let t0x = (c.lo[0] - r.o[0]) * r.inv[0];
        let t1x = (c.hi[0] - r.o[0]) * r.inv[0];
        let t0y = (c.lo[1] - r.o[1]) * r.inv[1];
        let t1y = (c.hi[1] - r.o[1]) * r.inv[1];
        let t0z = (c.lo[2] - r.o[2]) * r.inv[2];
        let t1z = (c.hi[2] - r.o[2]) * r.inv[2];
        let near = t0x.min(t1x).max(t0y.min(t1y)).max(t0z.min(t1z)).max(Vec4::ZERO);
        let far = t0x
            .max(t1x)
            .min(t0y.max(t1y))
            .min(t0z.max(t1z))
            .min(Vec4::splat(tmax));
        near.cmple(far * FAR_SLACK).bitmask() & c.valid
    }

    /// The closest primitive hit in `(0, ray.tmax)` and its index in `prims`.
    #[inline]
    pub(super) fn closest(
        &self,
        shapes: &[WorldShape],
        prims: &[Prim],
        ray: &Ray,
    ) -> Option<(PrimHit, usize)> {
        let tri = self.tri_ray(ray);
        let slab = SlabRay::new(ray);
        let mut q = *ray;
        let mut best = None;
        for (ci, c) in self.chunks.iter().enumerate() {
            let mut m = self.entered(c, &slab, q.tmax);
            while m != 0 {
                let id = 4 * ci + m.trailing_zeros() as usize;
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
        let tri = self.tri_ray(ray);
        let slab = SlabRay::new(ray);
        for (ci, c) in self.chunks.iter().enumerate() {
            let mut m = self.entered(c, &slab, ray.tmax);
            while m != 0 {
                let id = 4 * ci + m.trailing_zeros() as usize;
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
        let tri = self.tri_ray(ray);
        let slab = SlabRay::new(ray);
        for (ci, c) in self.chunks.iter().enumerate() {
            let mut m = self.entered(c, &slab, ray.tmax);
            while m != 0 {
                let id = 4 * ci + m.trailing_zeros() as usize;
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
