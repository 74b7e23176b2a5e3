//! `directionalarea` emitter: a shape whose surface emits only along its normal.
//!
//! # Radiometry
//!
//! The emitted radiance is `L(y)·δ(ω − n(y))`: a point y sends the power `L(y)·dA` along its
//! normal n and nothing elsewhere (Mitsuba 3 `src/emitters/directionalarea.cpp`, whose
//! `sample_ray` weight is `A·L` for a uniformly drawn point). The light's flux is `A·mean(L)`.
//!
//! # Next-event estimation (beyond Mitsuba)
//!
//! A point x receives this light only from the emitter points whose normal passes through it.
//! On a plane (a `rectangle` or a `disk`, normal n, on the emitting side at height
//! h = (x − o)·n > 0) that is the one point y = x − h·n, if y lies on the shape: the incident
//! light is a delta from −n with irradiance `L(y)` on a surface facing it (the beam neither
//! spreads nor narrows), exactly a `directional` light limited to the emitter's footprint. On a
//! sphere (centre c, radius R) the beam through x at distance r from c leaves the point
//! c + R·(x − c)/r, radially (outwards, or inwards with `flip_normals`), and the power of an
//! emitter patch spreads over the patch scaled by r/R: irradiance `L·(R/r)²`. An inward sphere
//! (`flip_normals`) focuses every beam at its centre: a point inside it at distance r receives
//! two, from the near point (distance R − r) and from the antipode through the centre (R + r),
//! each with `L·(R/r)²`, and a point outside only the latter; one is chosen with probability ½.
//! A planar mesh of at most [`MAX_FOOTPRINT_TRIANGLES`] triangles facing one way (an `obj`
//! quad) is a plane whose outline is its triangles. Other meshes, cylinders and other shapes are
//! left to light paths (`ptracer`), as Mitsuba leaves every shape.

use super::area::{AreaLight, LightPoint};
use super::{LightRef, LightSample};
use crate::geometry::sampling::sample_area;
use crate::geometry::shape::WorldMesh;
use crate::geometry::{Ray, ShapeKind, WorldShape, offset_ray_origin};
use glam::{Affine3A, Vec2, Vec3};
use gonio_core::{SampledSpectrum, SampledWavelengths};
use std::sync::Arc;

/// A `directionalarea` light on shape `surface.shape`.
#[derive(Clone, Debug)]
pub struct DirectionalAreaLight {
    /// The surface and its radiance, as an `area` light's (`le` is read along the normal).
    pub surface: AreaLight,
    /// The geometry next-event estimation follows beams back through (`None`: a shape without
    /// one, see [`Footprint`], or `next_event` off).
    pub footprint: Option<Footprint>,
}

/// The geometry next-event estimation follows the beam back through: a plane and its outline
/// (a rectangle, a disk, a planar mesh), or a sphere.
#[derive(Clone, Debug)]
pub enum Footprint {
    /// A `rectangle` or `disk`.
    Plane {
        /// A point of the plane (the object-space origin).
        origin: Vec3,
        /// Unit normal on the emitting side (after `flip_normals`).
        n: Vec3,
        /// World → object space, where the shape is [−1, 1]² or the unit disk in z = 0.
        to_object: Affine3A,
        /// The unit disk (else the square).
        disk: bool,
    },
    /// A planar triangle mesh of at most [`MAX_FOOTPRINT_TRIANGLES`] triangles, all facing
    /// one way (an `obj` or `ply` quad, the usual form of an area light).
    Mesh {
        /// The mesh (world space).
        mesh: Arc<WorldMesh>,
        /// A point of its plane.
        origin: Vec3,
        /// Unit normal on the emitting side (after `flip_normals`).
        n: Vec3,
        /// Shade with face normals (the shape's `face_normals`).
        face_normals: bool,
    },
    /// A `sphere`, emitting outwards (or inwards, with `flip_normals`).
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
        /// Normals point outwards (no `flip_normals`).
        outward: bool,
    },
}

/// Most triangles of a planar mesh next-event estimation projects onto (each light sample
/// looks for the triangle under the point among all of them).
pub const MAX_FOOTPRINT_TRIANGLES: usize = 64;

/// Where a beam reaching a point comes from: the emitting point, its emission direction (the
/// normal there), the distance to it, the beam's concentration there (irradiance / `L`) and
/// how many beams reach the point (one of them chosen uniformly).
#[derive(Clone, Copy, Debug)]
pub struct BeamOrigin {
    /// The emitting point (object coordinates (x, y) on a plane; barycentrics (b₁, b₂) of
    /// triangle `prim` on a mesh; the world point on a sphere).
    at: Vec3,
    /// The mesh triangle (0 elsewhere).
    prim: u32,
    /// Unit emission direction at `at`.
    pub n: Vec3,
    /// Distance from `at` to the receiving point.
    pub dist: f32,
    /// Irradiance on a surface facing the beam per unit `L`: 1 on a plane, (R/r)² on a sphere.
    pub gain: f32,
    /// Beams through the point: 1, or 2 inside an inward sphere (each with the same gain).
    pub count: u32,
}

impl Footprint {
    /// The footprint of a `rectangle`, `disk`, `sphere` or planar mesh (`None` for other
    /// shapes).
    pub fn of(shape: &WorldShape) -> Option<Self> {
        let flip = shape.flip_normals;
        if let ShapeKind::Mesh(mesh) = &shape.kind {
            return Self::of_mesh(mesh, flip, shape.face_normals);
        }
        let (to_world, to_object, n, disk) = match &shape.kind {
            ShapeKind::Rectangle {
                to_world,
                to_object,
                n,
                ..
            } => (to_world, to_object, *n, false),
            ShapeKind::Disk {
                to_world,
                to_object,
                n,
                ..
            } => (to_world, to_object, *n, true),
            ShapeKind::Sphere { center, radius, .. } => {
                return Some(Self::Sphere {
                    center: *center,
                    radius: *radius,
                    outward: !flip,
                });
            }
            _ => return None,
        };
        Some(Self::Plane {
            origin: to_world.translation.into(),
            n: if flip { -n } else { n },
            to_object: *to_object,
            disk,
        })
    }

    /// A mesh's footprint, when it has at most [`MAX_FOOTPRINT_TRIANGLES`] triangles lying in
    /// one plane (within 10⁻⁵ of its size or of its distance from the origin, whichever is
    /// larger: the rounding of its coordinates) and facing one way, and its vertex normals, if
    /// it has them and shades with them, are all that plane's normal or all its opposite (the
    /// beams leave along them, as Mitsuba's `sample_ray` sends them).
    fn of_mesh(mesh: &Arc<WorldMesh>, flip: bool, face_normals: bool) -> Option<Self> {
        if mesh.indices.is_empty() || mesh.indices.len() > MAX_FOOTPRINT_TRIANGLES {
            return None;
        }
        let normal = |i: usize| {
            let [a, b, c] = mesh.tri(i);
            (b - a).cross(c - a).normalize_or_zero()
        };
        let first = (0..mesh.indices.len()).find(|&i| normal(i) != Vec3::ZERO)?;
        let n = normal(first);
        let origin = mesh.tri(first)[0];
        let scale = mesh
            .positions
            .iter()
            .map(|&p| (p - origin).abs().max_element().max(p.abs().max_element()))
            .fold(0.0, f32::max);
        let planar = (0..mesh.indices.len()).all(|i| {
            let flat = mesh
                .tri(i)
                .iter()
                .all(|&v| (v - origin).dot(n).abs() <= 1e-5 * scale);
            flat && normal(i).dot(n) >= 0.0
        });
        // The side the vertex normals give (all of them along ±n, one sign), else the winding's.
        let side = if mesh.normals.is_empty() || face_normals {
            1.0
        } else {
            let first = mesh.normals[0].dot(n);
            let parallel = mesh.normals.iter().all(|m| (m.dot(n) - first).abs() < 1e-4);
            if !(parallel && first.abs() > 1.0 - 1e-4) {
                return None;
            }
            first.signum()
        };
        let n = (if flip { -n } else { n }) * side;
        planar.then(|| Self::Mesh {
            mesh: mesh.clone(),
            origin,
            n,
            face_normals,
        })
    }

    /// An emitter point whose beam passes through `p`, if any: on a plane the orthogonal
    /// projection (when `p` lies on the emitting side and the projection on the shape); on a
    /// sphere the points on the line through the centre whose beam reaches `p`: outside an
    /// outward sphere the near one, inside an inward sphere the near one and the far one (its
    /// beam crosses the centre first), outside an inward sphere the far one. Where there are
    /// two, `u` ∈ [0, 1) chooses.
    #[inline]
    pub fn beam_through(&self, p: Vec3, u: f32) -> Option<BeamOrigin> {
        match *self {
            Self::Plane {
                origin,
                n,
                to_object,
                disk,
            } => {
                let h = (p - origin).dot(n);
                if !(h > 0.0) {
                    return None;
                }
                let local = to_object.transform_point3(p - h * n);
                let inside = if disk {
                    local.x * local.x + local.y * local.y <= 1.0
                } else {
                    local.x.abs() <= 1.0 && local.y.abs() <= 1.0
                };
                inside.then_some(BeamOrigin {
                    at: local.with_z(0.0),
                    prim: 0,
                    n,
                    dist: h,
                    gain: 1.0,
                    count: 1,
                })
            }
            Self::Mesh {
                ref mesh, origin, n, ..
            } => {
                let h = (p - origin).dot(n);
                if !(h > 0.0) {
                    return None;
                }
                let y = p - h * n;
                (0..mesh.indices.len()).find_map(|i| {
                    let [a, b, c] = mesh.tri(i);
                    let (e1, e2, v) = (b - a, c - a, y - a);
                    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
                    let (v1, v2) = (v.dot(e1), v.dot(e2));
                    let det = d11 * d22 - d12 * d12;
                    if !(det > 0.0) {
                        return None;
                    }
                    let b1 = (d22 * v1 - d12 * v2) / det;
                    let b2 = (d11 * v2 - d12 * v1) / det;
                    (b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0).then_some(BeamOrigin {
                        at: Vec3::new(b1, b2, 0.0),
                        prim: i as u32,
                        n,
                        dist: h,
                        gain: 1.0,
                        count: 1,
                    })
                })
            }
            Self::Sphere {
                center,
                radius,
                outward,
            } => {
                let d = p - center;
                let r = d.length();
                let gain = (radius / r) * (radius / r);
                if !(r > 0.0 && gain.is_finite()) {
                    return None;
                }
                let w = d / r;
                // The beam of the point on p's side (c + R·w, along ±w) and of the antipode
                // (c − R·w, which an inward sphere sends through the centre towards p).
                let near = if outward { r > radius } else { r < radius };
                let far = !outward;
                let count = near as u32 + far as u32;
                let beam = |at: Vec3, n: Vec3, dist: f32| BeamOrigin {
                    at,
                    prim: 0,
                    n,
                    dist,
                    gain,
                    count,
                };
                match (near, far) {
                    (true, far) if !far || u < 0.5 => {
                        let n = if outward { w } else { -w };
                        Some(beam(center + radius * w, n, (r - radius).abs()))
                    }
                    (_, true) => Some(beam(center - radius * w, w, radius + r)),
                    _ => None,
                }
            }
        }
    }

    /// The light point of `beam` (found by [`Self::beam_through`]) on `shape`, this footprint's.
    fn light_point(&self, shape: &WorldShape, beam: &BeamOrigin) -> LightPoint {
        let si = match self {
            Self::Plane { .. } => shape.planar_point(beam.at.x, beam.at.y),
            Self::Mesh {
                mesh, face_normals, ..
            } => mesh.point(beam.prim as usize, beam.at.x, beam.at.y, *face_normals),
            Self::Sphere { .. } => shape.sphere_point(beam.at),
        };
        LightPoint {
            n: beam.n,
            ..LightPoint::from(&si)
        }
    }
}

impl DirectionalAreaLight {
    /// Flux A·mean(L): the power estimate light selection weighs.
    pub fn power(&self) -> f32 {
        self.surface.area * self.surface.mean_radiance
    }

    /// The emitted `L(y)` at a point of the surface (along its normal).
    #[inline]
    fn le(&self, at: &LightPoint, wl: &SampledWavelengths) -> SampledSpectrum {
        self.surface.le(at, at.n, wl)
    }

    /// The light arriving at `r` (see the module docs): a delta from an emitting point whose
    /// normal passes through `r.p`, irradiance `L` there times the beam's concentration, with
    /// probability 1 or ½ where two beams cross `r.p` (`u` chooses); `None` where no such
    /// point exists (and always without a footprint). `shape` is this light's shape.
    pub fn sample_li(
        &self,
        shape: &WorldShape,
        r: &LightRef,
        u: f32,
        wl: &SampledWavelengths,
    ) -> Option<LightSample> {
        let footprint = self.footprint.as_ref()?;
        let beam = footprint.beam_through(r.p, u)?;
        let li = self.le(&footprint.light_point(shape, &beam), wl) * beam.gain;
        (!li.is_black()).then_some(LightSample {
            wi: -beam.n,
            dist: beam.dist,
            li,
            pdf: 1.0 / beam.count as f32,
            delta: true,
            normal: Some(beam.n),
        })
    }

    /// A bound of the irradiance at `r` for light selection: `mean` times the beams'
    /// concentration where the emitter's light reaches `r.p` (from above the surface, when `r`
    /// is one-sided and one beam does), else 0.
    pub fn local_importance(&self, r: &LightRef, mean: f32) -> f32 {
        let Some(beam) = self.footprint.as_ref().and_then(|f| f.beam_through(r.p, 0.0)) else {
            return 0.0;
        };
        // Two beams come from opposite sides: one of them lights any one-sided point.
        if beam.count == 1 && r.hemisphere && r.n.dot(beam.n) >= 0.0 {
            return 0.0;
        }
        mean * beam.gain * beam.count as f32
    }

    /// A ray leaving the light: a uniform point of `shape` (this light's), along its shading
    /// normal (a mesh's interpolated vertex normal, as Mitsuba's position samples carry),
    /// weight `L/p_A`.
    pub fn sample_ray(
        &self,
        shape: &WorldShape,
        u_pos: Vec2,
        wl: &SampledWavelengths,
    ) -> Option<(Ray, SampledSpectrum)> {
        let s = sample_area(shape, u_pos);
        if !(s.pdf > 0.0) {
            return None;
        }
        let at = LightPoint {
            n: s.ns,
            ..LightPoint::from(&s)
        };
        let le = self.le(&at, wl);
        Some((Ray::new(offset_ray_origin(s.p, s.n, s.ns), s.ns), le / s.pdf))
    }
}
