//! World-space shapes: construction from the scene, bounds, intersection, hit records.

pub use super::triangle::{TriRay, intersect_triangle};
use super::{Ray, SurfaceInteraction};
use crate::scene::{Geometry, ShapeDesc, TriangleMesh};
use glam::{Affine3A, DVec3, Mat3, Vec2, Vec3, Vec3A};
use gonio_core::Frame;
use gonio_core::sampling::Distribution1D;
use std::f32::consts::{PI, TAU};
use std::sync::{Arc, OnceLock};

/// Shapes that cannot be placed as asked.
#[derive(Debug, thiserror::Error)]
pub enum GeometryError {
    /// A sphere's `to_world` is not a similarity (rotation, uniform scale, translation, mirror).
    #[error("shape {name}: a sphere's to_world must not scale non-uniformly or shear")]
    NonUniformSphere {
        /// The shape's id, or its index.
        name: String,
    },
    /// The transform collapses the shape (zero scale) or is not finite.
    #[error("shape {name}: degenerate or non-finite to_world")]
    Degenerate {
        /// The shape's id, or its index.
        name: String,
    },
    /// A sphere whose radius or world-space size is not a finite positive number.
    #[error("shape {name}: {message}")]
    BadSphere {
        /// The shape's id, or its index.
        name: String,
        /// What is wrong, with the value.
        message: String,
    },
    /// A triangle refers to a vertex that does not exist, or attribute arrays have wrong lengths.
    #[error("shape {name}: {message}")]
    BadMesh {
        /// The shape's id, or its index.
        name: String,
        /// What is wrong.
        message: String,
    },
}

/// A triangle mesh in world space, with the distribution of its triangles by area.
#[derive(Clone, Debug)]
pub struct WorldMesh {
    /// Vertex positions (world).
    pub positions: Vec<Vec3>,
    /// Vertex normals (world, unit), empty when the mesh has none.
    pub normals: Vec<Vec3>,
    /// Vertex texture coordinates, empty when the mesh has none.
    pub uvs: Vec<Vec2>,
    /// Triangles.
    pub indices: Vec<[u32; 3]>,
    /// Triangles with probability ∝ area (for area sampling), made on first use: only meshes
    /// that emit are sampled, and the table costs 8 bytes per triangle.
    triangles: OnceLock<Distribution1D>,
    /// Total area.
    pub area: f32,
}

/// A rectangle's corner and orthonormal edge frame in double precision (Ureña et al. 2013's
/// setup that does not depend on the reference point).
#[derive(Clone, Copy, Debug)]
pub struct RectBasis {
    /// The corner at object (−1, −1).
    pub corner: DVec3,
    /// Unit vector along the object x edge.
    pub x: DVec3,
    /// Unit vector along the object y edge.
    pub y: DVec3,
    /// `x × y`.
    pub z: DVec3,
    /// Length of the x edge.
    pub exl: f64,
    /// Length of the y edge.
    pub eyl: f64,
}

impl RectBasis {
    fn new(m: &Affine3A) -> Option<Self> {
        let ex = m.matrix3.x_axis.as_dvec3() * 2.0;
        let ey = m.matrix3.y_axis.as_dvec3() * 2.0;
        let (exl, eyl) = (ex.length(), ey.length());
        if ex.dot(ey).abs() > 1e-5 * exl * eyl {
            return None; // a parallelogram: no spherical-rectangle parameterization
        }
        let (x, y) = (ex / exl, ey / eyl);
        let corner = m.transform_point3(Vec3::new(-1.0, -1.0, 0.0)).as_dvec3();
        Some(Self {
            corner,
            x,
            y,
            z: x.cross(y),
            exl,
            eyl,
        })
    }
}

/// The world-space geometry of a [`WorldShape`].
#[derive(Clone, Debug)]
pub enum ShapeKind {
    /// An analytic sphere.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
        /// World → object space in which the sphere is the unit sphere at the origin (for uv).
        to_object: Affine3A,
        /// Object → world linear part (for ∂p/∂u).
        to_world: Mat3,
    },
    /// The image of [−1, 1]² × {0} under `to_world` (a parallelogram in general).
    Rectangle {
        /// Object → world.
        to_world: Affine3A,
        /// World → object.
        to_object: Affine3A,
        /// Unit normal: `to_world` applied to +z as a normal (inverse transpose).
        n: Vec3,
        /// Area.
        area: f32,
        /// The orthonormal edge frame for spherical-rectangle sampling (`None` for a
        /// parallelogram).
        basis: Option<RectBasis>,
        /// The shading frame of every point (`n` and ∂p/∂u), made once.
        frame: Frame,
    },
    /// The image of the unit disk in z = 0 under `to_world` (an ellipse in general).
    Disk {
        /// Object → world.
        to_world: Affine3A,
        /// World → object.
        to_object: Affine3A,
        /// Unit normal, as for the rectangle.
        n: Vec3,
        /// Area.
        area: f32,
    },
    /// A triangle mesh.
    Mesh(Arc<WorldMesh>),
    /// One member of a `shapegroup` placed by an `instance` (the two-level BVH's lower level).
    Instance(Box<super::instance::Instance>),
    /// An `sdfgrid`: the zero set of a trilinearly interpolated grid over the object unit cube.
    SdfGrid {
        /// The grid (shared by every shape that reads the same file).
        grid: Arc<super::sdfgrid::SdfGrid>,
        /// Object → world.
        to_world: Affine3A,
        /// World → object.
        to_object: Affine3A,
        /// Normal matrix (inverse transpose of `to_world`'s linear part).
        normal: Mat3,
    },
}

/// A shape in world space.
#[derive(Clone, Debug)]
pub struct WorldShape {
    /// The geometry.
    pub kind: ShapeKind,
    /// Normals negated (`flip_normals`).
    pub flip_normals: bool,
    /// Meshes: shade with face normals even where vertex normals exist.
    pub face_normals: bool,
    /// Hit only from outside (see [`crate::scene::ShapeDesc::outside_only`]): the acceleration
    /// structures pass a ray through the inside of this surface.
    pub outside_only: bool,
    /// Spheres: give hits their uv (an `atan2` and an `acos` per hit). True unless the renderer
    /// finds that nothing reads it (`render::PreparedScene`: no texture on the shape's material
    /// or emitter, no AOVs); the frame and the derivatives do not need it.
    pub uv: bool,
}

/// What a primitive intersection records before the full [`SurfaceInteraction`] is built:
/// the distance and two shape-specific coordinates (triangle barycentrics b1, b2; object-space
/// x, y for rectangles and disks; unused for spheres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimHit {
    /// Ray parameter.
    pub t: f32,
    /// First coordinate.
    pub a: f32,
    /// Second coordinate.
    pub b: f32,
}

fn check_affine(m: &Affine3A, name: &str) -> Result<(), GeometryError> {
    let det = m.matrix3.determinant();
    if !det.is_finite() || det.abs() < 1e-30 || !m.translation.is_finite() {
        return Err(GeometryError::Degenerate {
            name: name.to_owned(),
        });
    }
    Ok(())
}

/// Checks a shape's transform; for a sphere also its radius and that the whole transform is a
/// similarity, and returns that transform (object unit sphere → world).
fn sphere_placement(shape: &ShapeDesc, name: &str) -> Result<Option<Affine3A>, GeometryError> {
    let m = shape.to_world;
    check_affine(&m, name)?;
    let Geometry::Sphere { center, radius } = &shape.geometry else {
        return Ok(None);
    };
    if !(center.is_finite() && radius.is_finite() && *radius > 0.0) {
        return Err(GeometryError::BadSphere {
            name: name.to_owned(),
            message: format!(
                "radius {radius:e} and center {center} must be finite (in single precision) and the radius positive"
            ),
        });
    }
    let full = m * Affine3A::from_translation(*center) * Affine3A::from_scale(Vec3::splat(*radius));
    if check_affine(&full, name).is_err() {
        return Err(GeometryError::BadSphere {
            name: name.to_owned(),
            message: format!("radius {radius:e} under to_world gives a degenerate or non-finite sphere"),
        });
    }
    let l = Mat3::from(full.matrix3);
    let (cx, cy, cz) = (l.x_axis, l.y_axis, l.z_axis);
    let s = cx.length();
    let tol = 1e-4 * s;
    if (cy.length() - s).abs() > tol
        || (cz.length() - s).abs() > tol
        || cx.dot(cy).abs() > tol * s
        || cx.dot(cz).abs() > tol * s
        || cy.dot(cz).abs() > tol * s
    {
        return Err(GeometryError::NonUniformSphere {
            name: name.to_owned(),
        });
    }
    Ok(Some(full))
}

/// The unit normal of the object's +z under `m` (inverse transpose): `sign(det)·(ex × ey)`.
fn plane_normal(m: &Affine3A) -> Vec3 {
    let ex = Vec3::from(m.matrix3.x_axis);
    let ey = Vec3::from(m.matrix3.y_axis);
    let n = ex.cross(ey).normalize();
    if m.matrix3.determinant() < 0.0 { -n } else { n }
}

impl WorldShape {
    /// Checks that a scene shape can be placed in world space (finite, non-degenerate
    /// transform; a sphere's finite positive radius and similarity transform) without building
    /// it: the scene reader calls it where it still knows the shape's file and line.
    pub fn check_placement(shape: &ShapeDesc, name: &str) -> Result<(), GeometryError> {
        sphere_placement(shape, name).map(|_| ())
    }

    /// Places a scene shape in world space. `name` identifies it in errors.
    pub fn from_scene(shape: &ShapeDesc, name: &str) -> Result<Self, GeometryError> {
        Self::place(shape, None, name)
    }

    /// [`WorldShape::from_scene`], moving a mesh's vertex data out of `shape` when nothing else
    /// shares it (then `shape` is left with an empty mesh): a large mesh is not held twice.
    pub fn from_scene_moving_mesh(shape: &mut ShapeDesc, name: &str) -> Result<Self, GeometryError> {
        sphere_placement(shape, name)?;
        let owned = match &mut shape.geometry {
            Geometry::Mesh(mesh) => Arc::get_mut(mesh).map(std::mem::take),
            _ => None,
        };
        Self::place(shape, owned, name)
    }

    /// Places `shape`, whose mesh (if it is one) is `owned` when given.
    fn place(shape: &ShapeDesc, owned: Option<TriangleMesh>, name: &str) -> Result<Self, GeometryError> {
        let m = shape.to_world;
        let sphere = sphere_placement(shape, name)?;
        let kind = match (&shape.geometry, sphere) {
            (Geometry::Sphere { .. }, Some(full)) => {
                let l = Mat3::from(full.matrix3);
                ShapeKind::Sphere {
                    center: full.transform_point3(Vec3::ZERO),
                    radius: l.x_axis.length(),
                    to_object: full.inverse(),
                    to_world: l,
                }
            }
            (Geometry::Sphere { .. }, None) => unreachable!("sphere_placement returns a sphere's transform"),
            (Geometry::Rectangle, _) => {
                let ex = Vec3::from(m.matrix3.x_axis);
                let ey = Vec3::from(m.matrix3.y_axis);
                let n = plane_normal(&m);
                ShapeKind::Rectangle {
                    basis: RectBasis::new(&m),
                    to_world: m,
                    to_object: m.inverse(),
                    n,
                    area: 4.0 * ex.cross(ey).length(),
                    frame: Frame::from_normal_tangent(n, ex * 2.0),
                }
            }
            (Geometry::Disk, _) => {
                let ex = Vec3::from(m.matrix3.x_axis);
                let ey = Vec3::from(m.matrix3.y_axis);
                ShapeKind::Disk {
                    to_world: m,
                    to_object: m.inverse(),
                    n: plane_normal(&m),
                    area: PI * ex.cross(ey).length(),
                }
            }
            (Geometry::Mesh(mesh), _) => ShapeKind::Mesh(Arc::new(match owned {
                Some(owned) => WorldMesh::from_owned(owned, &m, name)?,
                None => WorldMesh::new(mesh, &m, name)?,
            })),
            (
                Geometry::Instance {
                    group,
                    member: Some(i),
                },
                _,
            ) => ShapeKind::Instance(Box::new(super::instance::Instance::new(group.member(*i)?, m))),
            (Geometry::Instance { member: None, .. } | Geometry::Group(_), _) => {
                return Err(GeometryError::BadMesh {
                    name: name.to_owned(),
                    message: "a shapegroup or an unexpanded instance is not a shape to place \
                              (the scene reader expands instances into their members)"
                        .into(),
                });
            }
            (Geometry::SdfGrid(grid), _) => ShapeKind::SdfGrid {
                grid: grid.clone(),
                to_world: m,
                to_object: m.inverse(),
                normal: Mat3::from(m.matrix3).inverse().transpose(),
            },
        };
        Ok(Self {
            kind,
            flip_normals: shape.flip_normals,
            face_normals: shape.face_normals,
            outside_only: shape.outside_only,
            uv: true,
        })
    }

    /// Number of primitives (triangles for meshes, 1 otherwise).
    pub fn prim_count(&self) -> usize {
        match &self.kind {
            ShapeKind::Mesh(m) => m.indices.len(),
            _ => 1,
        }
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        match &self.kind {
            ShapeKind::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            ShapeKind::Rectangle { area, .. } | ShapeKind::Disk { area, .. } => *area,
            ShapeKind::Mesh(m) => m.area,
            ShapeKind::Instance(i) => i.area,
            // Mitsuba gives an SDF grid no area (it cannot emit).
            ShapeKind::SdfGrid { .. } => 0.0,
        }
    }

    /// Axis-aligned bounds `(min, max)` of primitive `prim`.
    pub fn prim_bounds(&self, prim: usize) -> (Vec3, Vec3) {
        match &self.kind {
            ShapeKind::Sphere { center, radius, .. } => (*center - *radius, *center + *radius),
            ShapeKind::Rectangle { to_world, .. } => {
                let c = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .map(|(x, y)| to_world.transform_point3(Vec3::new(x, y, 0.0)));
                let lo = c.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
                let hi = c.iter().fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
                (lo, hi)
            }
            ShapeKind::Disk { to_world, .. } => {
                let c = Vec3::from(to_world.translation);
                let ex = Vec3::from(to_world.matrix3.x_axis);
                let ey = Vec3::from(to_world.matrix3.y_axis);
                // The extent of c + cos φ·ex + sin φ·ey along each axis is √(ex_i² + ey_i²).
                let half = (ex * ex + ey * ey).map(f32::sqrt);
                (c - half, c + half)
            }
            ShapeKind::Mesh(m) => {
                let [a, b, c] = m.tri(prim);
                (a.min(b).min(c), a.max(b).max(c))
            }
            ShapeKind::Instance(i) => i.bounds,
            ShapeKind::SdfGrid { to_world, .. } => {
                let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
                for i in 0..8 {
                    let c = Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32);
                    let w = to_world.transform_point3(c);
                    lo = lo.min(w);
                    hi = hi.max(w);
                }
                (lo, hi)
            }
        }
    }

    /// Intersects primitive `prim` with `ray` in `(0, ray.tmax)`; `tri` is `TriRay::new(ray)`.
    #[inline]
    pub fn intersect_prim(&self, prim: usize, ray: &Ray, tri: &TriRay) -> Option<PrimHit> {
        match &self.kind {
            ShapeKind::Sphere { center, radius, .. } => {
                intersect_sphere(*center, *radius, ray).map(|t| PrimHit { t, a: 0.0, b: 0.0 })
            }
            ShapeKind::Rectangle { to_object, .. } => {
                let (t, x, y) = intersect_plane(to_object, ray)?;
                (x.abs() <= 1.0 && y.abs() <= 1.0).then_some(PrimHit { t, a: x, b: y })
            }
            ShapeKind::Disk { to_object, .. } => {
                let (t, x, y) = intersect_plane(to_object, ray)?;
                (x * x + y * y <= 1.0).then_some(PrimHit { t, a: x, b: y })
            }
            ShapeKind::Mesh(m) => {
                let [p0, p1, p2] = m.tri(prim);
                intersect_triangle(p0, p1, p2, tri, ray.tmax).map(|(t, a, b)| PrimHit { t, a, b })
            }
            ShapeKind::Instance(i) => i.intersect(ray),
            ShapeKind::SdfGrid { grid, to_object, .. } => {
                // Object space with the direction unnormalized: t is the same in both spaces.
                let o = to_object.transform_point3(ray.o);
                let d = to_object.transform_vector3(ray.d);
                let (t, voxel) = grid.intersect(o, d, ray.tmax)?;
                Some(PrimHit {
                    t,
                    a: f32::from_bits(voxel),
                    b: 0.0,
                })
            }
        }
    }

    /// The full hit record for a [`PrimHit`] of primitive `prim` on shape number `shape`.
    pub fn interaction(&self, shape: u32, prim: usize, ray: &Ray, hit: PrimHit) -> SurfaceInteraction {
        let mut si = match &self.kind {
            ShapeKind::Sphere { center, radius, .. } => {
                let p = *center + (ray.at(hit.t) - *center).normalize() * *radius;
                self.sphere_point(p)
            }
            ShapeKind::Rectangle { .. } | ShapeKind::Disk { .. } => self.planar_point(hit.a, hit.b),
            ShapeKind::Mesh(m) => m.point(prim, hit.a, hit.b, self.face_normals),
            ShapeKind::Instance(i) => i.interaction(ray, hit.t),
            ShapeKind::SdfGrid {
                grid,
                to_world,
                to_object,
                normal,
            } => sdf_point(grid, to_world, to_object, normal, ray.at(hit.t), hit.a.to_bits()),
        };
        si.t = hit.t;
        si.shape = shape;
        si.prim = match &self.kind {
            // The member's primitive, as Mitsuba reports it for an instance.
            ShapeKind::Instance(_) => si.prim,
            _ => prim as u32,
        };
        if self.flip_normals {
            si.n = -si.n;
            si.shading = flip_frame(si.shading);
        }
        si
    }

    /// The record (without `t`, `shape`, flip) of a point `p` on a sphere.
    pub(crate) fn sphere_point(&self, p: Vec3) -> SurfaceInteraction {
        let ShapeKind::Sphere {
            center,
            to_object,
            to_world,
            ..
        } = &self.kind
        else {
            unreachable!()
        };
        let n = (p - *center).normalize();
        let local = to_object.transform_point3(p).normalize();
        let uv = if self.uv {
            let mut phi = local.y.atan2(local.x);
            if phi < 0.0 {
                phi += TAU;
            }
            let theta = local.z.clamp(-1.0, 1.0).acos();
            Vec2::new(phi / TAU, theta / PI)
        } else {
            Vec2::ZERO
        };
        let dpdu = *to_world * Vec3::new(-local.y, local.x, 0.0) * TAU;
        // ∂p/∂v = π (cos θ cos φ, cos θ sin φ, −sin θ); at the poles, where φ is undefined,
        // π (1, 0, 0) (Mitsuba's `sphere`).
        let sin_theta = (local.x * local.x + local.y * local.y).sqrt();
        let dpdv = if sin_theta > 0.0 {
            *to_world
                * Vec3::new(
                    local.z * local.x / sin_theta,
                    local.z * local.y / sin_theta,
                    -sin_theta,
                )
                * PI
        } else {
            *to_world * Vec3::X * PI
        };
        SurfaceInteraction {
            p,
            t: 0.0,
            n,
            shading: Frame::from_normal_tangent(n, dpdu),
            uv,
            dpdu,
            dpdv,
            shape: 0,
            prim: 0,
            bary: Vec2::ZERO,
        }
    }

    /// The record (without `t`, `shape`, flip) of object-space point `(x, y, 0)` on a rectangle
    /// or disk.
    pub(crate) fn planar_point(&self, x: f32, y: f32) -> SurfaceInteraction {
        match &self.kind {
            ShapeKind::Rectangle {
                to_world, n, frame, ..
            } => {
                let p = to_world.transform_point3(Vec3::new(x, y, 0.0));
                let dpdu = Vec3::from(to_world.matrix3.x_axis) * 2.0;
                SurfaceInteraction {
                    p,
                    t: 0.0,
                    n: *n,
                    shading: *frame,
                    uv: Vec2::new(0.5 * (x + 1.0), 0.5 * (y + 1.0)),
                    dpdu,
                    dpdv: Vec3::from(to_world.matrix3.y_axis) * 2.0,
                    shape: 0,
                    prim: 0,
                    bary: Vec2::ZERO,
                }
            }
            ShapeKind::Disk { to_world, n, .. } => {
                let p = to_world.transform_point3(Vec3::new(x, y, 0.0));
                let r = (x * x + y * y).sqrt();
                let mut v = y.atan2(x) / TAU;
                if v < 0.0 {
                    v += 1.0;
                }
                // Mitsuba's disk: uv = (r, φ/2π); its ∂p/∂u and ∂p/∂v are the unit radial and
                // tangential directions (∂p/∂v is not the derivative 2πr·(−sin φ, cos φ)), at
                // the centre those of φ = 0: bump maps and the dp_dv AOV then match Mitsuba's.
                let (cos_phi, sin_phi) = if r > 0.0 { (x / r, y / r) } else { (1.0, 0.0) };
                let dpdu = to_world.transform_vector3(Vec3::new(cos_phi, sin_phi, 0.0));
                let dpdv = to_world.transform_vector3(Vec3::new(-sin_phi, cos_phi, 0.0));
                SurfaceInteraction {
                    p,
                    t: 0.0,
                    n: *n,
                    shading: Frame::from_normal_tangent(*n, dpdu),
                    uv: Vec2::new(r, v),
                    dpdu,
                    dpdv,
                    shape: 0,
                    prim: 0,
                    bary: Vec2::ZERO,
                }
            }
            _ => unreachable!("planar_point on a non-planar shape"),
        }
    }
}

/// The record (without `t`, `shape`, flip) of the world point `p` found in voxel `voxel` of an
/// `sdfgrid`: geometric normal from the voxel's gradient, shading normal by the grid's method.
fn sdf_point(
    grid: &super::sdfgrid::SdfGrid,
    to_world: &Affine3A,
    to_object: &Affine3A,
    normal: &Mat3,
    p: Vec3,
    voxel: u32,
) -> SurfaceInteraction {
    let local = to_object.transform_point3(p);
    let n = (*normal * grid.gradient(voxel, local)).normalize_or_zero();
    let ns = match grid.normals {
        super::sdfgrid::SdfNormals::Analytic => n,
        super::sdfgrid::SdfNormals::Smooth => (*normal * grid.smooth_normal(local)).normalize_or_zero(),
    };
    let ns = if ns == Vec3::ZERO { n } else { ns };
    SurfaceInteraction {
        p: to_world.transform_point3(local),
        t: 0.0,
        n,
        shading: Frame::from_normal(ns),
        uv: Vec2::ZERO,
        dpdu: Vec3::ZERO,
        dpdv: Vec3::ZERO,
        shape: 0,
        prim: voxel,
        bary: Vec2::ZERO,
    }
}

pub(crate) fn flip_frame(f: Frame) -> Frame {
    // Keep the frame right-handed: negate n and t.
    Frame {
        s: f.s,
        t: -f.t,
        n: -f.n,
    }
}

/// Closest sphere hit in `(0, tmax)`, with the numerically careful quadratic of Haines et al.,
/// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems ch. 7): the
/// discriminant from |f − (f·d)d|², and the smaller root from c/q.
#[inline]
pub fn intersect_sphere(center: Vec3, radius: f32, ray: &Ray) -> Option<f32> {
    let f = ray.o - center;
    let b = f.dot(ray.d);
    let c = f.length_squared() - radius * radius;
    let l = f - b * ray.d;
    let disc = radius * radius - l.length_squared();
    if disc < 0.0 {
        return None;
    }
    let q = -b - disc.sqrt().copysign(b);
    let (mut t0, mut t1) = if q != 0.0 { (c / q, q) } else { (0.0, 0.0) };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    if t0 > 0.0 && t0 < ray.tmax {
        Some(t0)
    } else if t1 > 0.0 && t1 < ray.tmax {
        Some(t1)
    } else {
        None
    }
}

/// Ray against the object-space plane z = 0: `(t, x, y)`.
#[inline]
fn intersect_plane(to_object: &Affine3A, ray: &Ray) -> Option<(f32, f32, f32)> {
    let o = to_object.transform_point3a(Vec3A::from(ray.o));
    let d = to_object.transform_vector3a(Vec3A::from(ray.d));
    if d.z == 0.0 {
        return None;
    }
    let t = -o.z / d.z;
    if !(t > 0.0 && t < ray.tmax) {
        return None;
    }
    Some((t, o.x + t * d.x, o.y + t * d.y))
}

impl WorldMesh {
    /// Transforms a scene mesh to world space (a copy of its vertex data).
    pub fn new(mesh: &TriangleMesh, to_world: &Affine3A, name: &str) -> Result<Self, GeometryError> {
        Self::check(mesh, name)?;
        Self::from_owned(mesh.clone(), to_world, name)
    }

    /// Checks vertex counts, indices and finiteness.
    fn check(mesh: &TriangleMesh, name: &str) -> Result<(), GeometryError> {
        let bad = |message: String| GeometryError::BadMesh {
            name: name.to_owned(),
            message,
        };
        let nv = mesh.positions.len();
        if !mesh.normals.is_empty() && mesh.normals.len() != nv {
            return Err(bad(format!("{} normals for {nv} vertices", mesh.normals.len())));
        }
        if !mesh.uvs.is_empty() && mesh.uvs.len() != nv {
            return Err(bad(format!(
                "{} texture coordinates for {nv} vertices",
                mesh.uvs.len()
            )));
        }
        if let Some((i, t)) = mesh
            .indices
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&v| v as usize >= nv))
        {
            return Err(bad(format!("triangle {i} refers to vertex {:?} of {nv}", t)));
        }
        if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(bad(format!("vertex {i} is not finite: {:?}", mesh.positions[i])));
        }
        Ok(())
    }

    /// Transforms a scene mesh to world space in place, reusing its arrays (for a mesh nothing
    /// else holds: the 1M-triangle bench mesh then exists once, not twice, while the BVH is
    /// built).
    pub fn from_owned(mesh: TriangleMesh, to_world: &Affine3A, name: &str) -> Result<Self, GeometryError> {
        Self::check(&mesh, name)?;
        let TriangleMesh {
            mut positions,
            mut normals,
            uvs,
            indices,
        } = mesh;
        for p in &mut positions {
            *p = to_world.transform_point3(*p);
        }
        let normal_m = Mat3::from(to_world.matrix3).inverse().transpose();
        for n in &mut normals {
            *n = (normal_m * *n).normalize_or_zero();
        }
        let mut m = Self {
            positions,
            normals,
            uvs,
            indices,
            triangles: OnceLock::new(),
            area: 0.0,
        };
        let total: f64 = (0..m.indices.len()).map(|i| m.tri_area(i) as f64).sum();
        m.area = total as f32;
        Ok(m)
    }

    /// The area of triangle `i`.
    fn tri_area(&self, i: usize) -> f32 {
        let [a, b, c] = self.tri(i);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Triangles with probability ∝ area (for area sampling).
    pub fn triangles(&self) -> &Distribution1D {
        self.triangles.get_or_init(|| {
            let areas: Vec<f32> = (0..self.indices.len()).map(|i| self.tri_area(i)).collect();
            Distribution1D::new(&areas)
        })
    }

    /// The vertices of triangle `i`.
    #[inline]
    pub fn tri(&self, i: usize) -> [Vec3; 3] {
        self.indices[i].map(|v| self.positions[v as usize])
    }

    /// The record (without `t`, `shape`, flip) at barycentrics `(b1, b2)` of triangle `i`.
    pub(crate) fn point(&self, i: usize, b1: f32, b2: f32, face_normals: bool) -> SurfaceInteraction {
        let idx = self.indices[i].map(|v| v as usize);
        let [p0, p1, p2] = idx.map(|v| self.positions[v]);
        let b0 = 1.0 - b1 - b2;
        let p = b0 * p0 + b1 * p1 + b2 * p2;
        let n = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        let (uv, dpdu, dpdv) = if self.uvs.is_empty() {
            // Mitsuba's convention without texture coordinates: uv = (b1, b2).
            (Vec2::new(b1, b2), p1 - p0, p2 - p0)
        } else {
            let [t0, t1, t2] = idx.map(|v| self.uvs[v]);
            let uv = b0 * t0 + b1 * t1 + b2 * t2;
            let (d02, d12) = (t0 - t2, t1 - t2);
            let det = d02.x * d12.y - d02.y * d12.x;
            if det.abs() > 1e-12 {
                let dpdu = (d12.y * (p0 - p2) - d02.y * (p1 - p2)) / det;
                let dpdv = (d02.x * (p1 - p2) - d12.x * (p0 - p2)) / det;
                (uv, dpdu, dpdv)
            } else {
                (uv, Vec3::ZERO, Vec3::ZERO)
            }
        };
        let ns = if self.normals.is_empty() || face_normals {
            n
        } else {
            let [n0, n1, n2] = idx.map(|v| self.normals[v]);
            let s = (b0 * n0 + b1 * n1 + b2 * n2).normalize_or_zero();
            if s == Vec3::ZERO { n } else { s }
        };
        SurfaceInteraction {
            p,
            t: 0.0,
            n,
            shading: Frame::from_normal_tangent(ns, dpdu),
            uv,
            dpdu,
            dpdv,
            shape: 0,
            prim: i as u32,
            bary: Vec2::new(b1, b2),
        }
    }
}
