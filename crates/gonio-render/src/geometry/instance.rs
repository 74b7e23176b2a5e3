//! Geometry instancing: Mitsuba 3's `shapegroup` and `instance` (`src/shapes/shapegroup.cpp`,
//! `src/shapes/instance.cpp`) as a two-level BVH.
//!
//! A [`ShapeGroup`] holds its shapes once, in the group's own space; each member gets its own
//! [`Accel`] there, built the first time an instance needs it and shared (`Arc`) by every
//! instance. An instance of a group with k members becomes k top-level shapes
//! ([`ShapeKind::Instance`](super::ShapeKind::Instance)), one per member, so that each keeps its own material: the scene's
//! BVH is the top level over their world bounds, and a candidate ray is carried into the group's
//! space and traced through the member's BVH:
//!
//! ```text
//! o' = M⁻¹ o,   d' = M⁻¹ d / |M⁻¹ d|,   t = t' / |M⁻¹ d|
//! ```
//!
//! Hit points map back with `M`, tangents with `M`, normals with the inverse transpose `M⁻ᵀ`
//! (renormalized), as Mitsuba's instance does. Mitsuba refuses emitters, sensors and nested
//! instances inside a group; so does the reader. The area of an instance is the member's area
//! scaled by |det M|^(2/3), exact for similarities (it only enters the scene-area statistics, as
//! instances cannot emit).
//!
//! Any-hit queries ([`crate::accel::Intersect::for_each_hit`], shadow rays through thin sheets)
//! visit every hit inside an instance ([`Instance::for_each_hit`]).

use super::shape::{GeometryError, PrimHit};
use super::{Ray, SurfaceInteraction, WorldShape};
use crate::accel::{Accel, Intersect};
use crate::scene::ShapeDesc;
use glam::{Affine3A, Mat3, Vec3};
use gonio_core::Frame;
use std::sync::{Arc, OnceLock};

/// The shapes of a `shapegroup`, in the group's space, each with its acceleration structure
/// built once on first use.
#[derive(Debug)]
pub struct ShapeGroup {
    /// The group's `id`.
    pub id: String,
    /// The member shapes (group space).
    pub shapes: Vec<ShapeDesc>,
    members: Vec<OnceLock<Arc<Accel>>>,
}

impl ShapeGroup {
    /// A group of `shapes`.
    pub fn new(id: String, shapes: Vec<ShapeDesc>) -> Self {
        let members = shapes.iter().map(|_| OnceLock::new()).collect();
        Self { id, shapes, members }
    }

    /// Member `i` placed in the group's space inside its own BVH, built once.
    pub fn member(&self, i: usize) -> Result<Arc<Accel>, GeometryError> {
        let cell = self.members.get(i).ok_or_else(|| GeometryError::BadMesh {
            name: self.id.clone(),
            message: format!("shapegroup has no member {i} (it has {})", self.shapes.len()),
        })?;
        if let Some(a) = cell.get() {
            return Ok(a.clone());
        }
        let name = format!("{}[{i}]", self.id);
        let shape = WorldShape::from_scene(&self.shapes[i], &name)?;
        let accel = Arc::new(Accel::new(vec![shape]));
        Ok(cell.get_or_init(|| accel).clone())
    }
}

/// One member of a group placed in the world by an instance's `to_world`.
#[derive(Clone, Debug)]
pub struct Instance {
    /// The member in group space (one shape), shared by every instance of the group.
    pub inner: Arc<Accel>,
    /// Group → world.
    pub to_world: Affine3A,
    /// World → group.
    pub to_object: Affine3A,
    /// The normal matrix, the inverse transpose of `to_world`'s linear part.
    pub normal: Mat3,
    /// World-space bounds.
    pub bounds: (Vec3, Vec3),
    /// World-space area (exact under similarities, see the module documentation).
    pub area: f32,
}

impl Instance {
    /// Places `inner` (one shape in group space) by `to_world`.
    pub fn new(inner: Arc<Accel>, to_world: Affine3A) -> Self {
        let shape = &inner.shapes()[0];
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for prim in 0..shape.prim_count() {
            let (a, b) = shape.prim_bounds(prim);
            lo = lo.min(a);
            hi = hi.max(b);
        }
        let (mut wlo, mut whi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        if lo.cmple(hi).all() {
            for i in 0..8 {
                let c = Vec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                );
                let w = to_world.transform_point3(c);
                wlo = wlo.min(w);
                whi = whi.max(w);
            }
        }
        let linear = Mat3::from(to_world.matrix3);
        let area = shape.area() * linear.determinant().abs().powf(2.0 / 3.0);
        Self {
            inner,
            to_world,
            to_object: to_world.inverse(),
            normal: linear.inverse().transpose(),
            bounds: (wlo, whi),
            area,
        }
    }

    /// The ray in group space with unit direction, and the factor `|M⁻¹ d|` with t = t'/factor.
    #[inline]
    fn local_ray(&self, ray: &Ray) -> Option<(Ray, f32)> {
        let o = self.to_object.transform_point3(ray.o);
        let d = self.to_object.transform_vector3(ray.d);
        let len = d.length();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        Some((
            Ray {
                o,
                d: d / len,
                tmax: ray.tmax * len,
            },
            len,
        ))
    }

    /// The closest hit of the member in `(0, ray.tmax)`.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<PrimHit> {
        let (local, len) = self.local_ray(ray)?;
        let si = self.inner.intersect(&local)?;
        let t = si.t / len;
        (t > 0.0 && t < ray.tmax).then_some(PrimHit { t, a: 0.0, b: 0.0 })
    }

    /// The world-space record of the hit [`Instance::intersect`] found on `ray` (the member's
    /// closest hit, traced again), without `shape`; `prim` is the member's primitive.
    pub fn interaction(&self, ray: &Ray, t: f32) -> SurfaceInteraction {
        let local = self
            .local_ray(ray)
            .and_then(|(local, _)| self.inner.intersect(&local));
        match local {
            Some(si) => self.to_world_record(&si, t),
            // Unreachable for a hit `intersect` reported; a point without a frame otherwise.
            None => SurfaceInteraction {
                p: ray.at(t),
                t,
                n: -ray.d,
                shading: Frame::from_normal(-ray.d),
                uv: glam::Vec2::ZERO,
                dpdu: Vec3::ZERO,
                dpdv: Vec3::ZERO,
                shape: 0,
                prim: 0,
                bary: glam::Vec2::ZERO,
            },
        }
    }

    /// Calls `f` with the world record of every hit of the member in `(0, ray.tmax)` (shape
    /// index `shape`) until it returns `true`; returns whether it stopped.
    pub fn for_each_hit(
        &self,
        ray: &Ray,
        shape: u32,
        f: &mut dyn FnMut(&SurfaceInteraction) -> bool,
    ) -> bool {
        let Some((local, len)) = self.local_ray(ray) else {
            return false;
        };
        self.inner.for_each_hit(&local, &mut |si| {
            let t = si.t / len;
            if !(t > 0.0 && t < ray.tmax) {
                return false;
            }
            let mut w = self.to_world_record(si, t);
            w.shape = shape;
            f(&w)
        })
    }

    /// A group-space record carried to the world.
    pub fn to_world_record(&self, si: &SurfaceInteraction, t: f32) -> SurfaceInteraction {
        let n = (self.normal * si.n).normalize_or_zero();
        let ns = (self.normal * si.shading.n).normalize_or_zero();
        let ns = if ns == Vec3::ZERO { n } else { ns };
        let dpdu = self.to_world.transform_vector3(si.dpdu);
        let dpdv = self.to_world.transform_vector3(si.dpdv);
        let tangent = if dpdu == Vec3::ZERO {
            self.to_world.transform_vector3(si.shading.s)
        } else {
            dpdu
        };
        SurfaceInteraction {
            p: self.to_world.transform_point3(si.p),
            t,
            n,
            shading: Frame::from_normal_tangent(ns, tangent),
            uv: si.uv,
            dpdu,
            dpdv,
            shape: 0,
            prim: si.prim,
            bary: si.bary,
        }
    }
}
