//! Points on shapes for area lights.
//!
//! | shape | `sample_solid_angle` | why |
//! |---|---|---|
//! | sphere, reference outside | uniform in the cone of directions it subtends (pbrt-v4 `Sphere::Sample`) | pdf constant over the visible cap: no 1/cos or distance² spikes |
//! | sphere, reference inside | uniform area | the cone is the whole sphere of directions |
//! | rectangle (orthogonal edges) | spherical rectangle (Ureña, Fajardo and King, EGSR 2013) | uniform in solid angle: the geometric term's variance disappears; Mitsuba samples by area |
//! | parallelogram, or solid angle < 3·10⁻⁴ sr or > 6.22 sr | uniform area | numerical safety (pbrt-v4's thresholds) |
//! | disk | uniform area (concentric map) | |
//! | mesh | triangle by area, then uniform in it | uniform over the mesh's area |
//!
//! `pdf_solid_angle` repeats the sampling decision from the reference point alone, so the pdf it
//! returns for a hit point is exactly the density `sample_solid_angle` draws it with (for MIS).

use super::SurfaceInteraction;
use super::shape::{ShapeKind, WorldShape, flip_frame};
use glam::{DVec3, Vec2, Vec3};
use gonio_core::Frame;
use gonio_core::warp::square_to_uniform_disk_concentric;
use std::f32::consts::TAU;

/// A sampled point on a shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSample {
    /// The point (world).
    pub p: Vec3,
    /// Geometric normal at the point (after `flip_normals`).
    pub n: Vec3,
    /// Shading normal at the point (after `flip_normals`; interpolated for meshes).
    pub ns: Vec3,
    /// Texture coordinates (for textured emitters).
    pub uv: Vec2,
    /// The triangle of a mesh the point lies on (0 for other shapes).
    pub prim: u32,
    /// The point's barycentric coordinates (b₁, b₂) on that triangle (zero for other shapes):
    /// with `prim`, what an emitter's `mesh_attribute` radiance reads.
    pub bary: Vec2,
    /// Density: per unit area for [`sample_area`], per unit solid angle at the reference point for
    /// [`sample_solid_angle`].
    pub pdf: f32,
}

fn finish(shape: &WorldShape, mut si: SurfaceInteraction, pdf: f32) -> ShapeSample {
    if shape.flip_normals {
        si.n = -si.n;
        si.shading = flip_frame(si.shading);
    }
    ShapeSample {
        p: si.p,
        n: si.n,
        ns: si.shading.n,
        uv: si.uv,
        prim: si.prim,
        bary: si.bary,
        pdf,
    }
}

/// A point uniformly distributed over the shape's area; `pdf` = 1 / area.
pub fn sample_area(shape: &WorldShape, u: Vec2) -> ShapeSample {
    let pdf = 1.0 / shape.area();
    match &shape.kind {
        ShapeKind::Sphere { center, radius, .. } => {
            let d = gonio_core::warp::square_to_uniform_sphere(u);
            finish(shape, shape.sphere_point(*center + d * *radius), pdf)
        }
        ShapeKind::Rectangle { .. } => {
            finish(shape, shape.planar_point(2.0 * u.x - 1.0, 2.0 * u.y - 1.0), pdf)
        }
        ShapeKind::Disk { .. } => {
            let d = square_to_uniform_disk_concentric(u);
            finish(shape, shape.planar_point(d.x, d.y), pdf)
        }
        ShapeKind::Mesh(m) => {
            // Choose the triangle by area and reuse u.x, rescaled inside its cell.
            let (i, _, ux) = m.triangles().sample_discrete(u.x);
            let su = ux.sqrt();
            let (b1, b2) = (u.y * su, 1.0 - su);
            // b0 = 1 − b1 − b2 = su·(1 − u.y): uniform on the triangle.
            finish(shape, m.point(i, b1, b2, shape.face_normals), pdf)
        }
        ShapeKind::Instance(inst) => {
            // The member's point carried to the world; uniform in area under a similarity
            // (instances cannot emit, so this serves only callers outside the renderer).
            let local = sample_area(&crate::accel::Intersect::shapes(inst.inner.as_ref())[0], u);
            let si = SurfaceInteraction {
                p: local.p,
                t: 0.0,
                n: local.n,
                shading: Frame::from_normal(local.ns),
                uv: local.uv,
                dpdu: Vec3::ZERO,
                dpdv: Vec3::ZERO,
                shape: 0,
                prim: local.prim,
                bary: local.bary,
            };
            let w = inst.to_world_record(&si, 0.0);
            finish(shape, w, pdf)
        }
        // No area and no sampling, as in Mitsuba (an SDF grid cannot emit): a zero density.
        ShapeKind::SdfGrid { to_world, .. } => ShapeSample {
            p: to_world.transform_point3(Vec3::splat(0.5)),
            n: Vec3::Z,
            ns: Vec3::Z,
            uv: Vec2::ZERO,
            prim: 0,
            bary: Vec2::ZERO,
            pdf: 0.0,
        },
    }
}

/// Converts an area density at `p` (normal `n`) into a solid-angle density at `r`.
#[inline]
fn area_to_solid_angle(pdf_area: f32, r: Vec3, p: Vec3, n: Vec3) -> f32 {
    let v = p - r;
    let d2 = v.length_squared();
    let cos = (n.dot(v) / d2.sqrt()).abs();
    if cos == 0.0 || d2 == 0.0 {
        0.0
    } else {
        pdf_area * d2 / cos
    }
}

/// sin²(1.5°): below it the cone is sampled with a Taylor expansion (pbrt-v4).
const SMALL_CONE: f32 = 0.000_685_23;

/// A point on the shape as seen from `r`, with its solid-angle density at `r`. `None` when the
/// density is not finite (the reference point lies in a planar shape's plane, for example).
pub fn sample_solid_angle(shape: &WorldShape, r: Vec3, u: Vec2) -> Option<ShapeSample> {
    match &shape.kind {
        ShapeKind::Sphere { center, radius, .. } => {
            let dc2 = (*center - r).length_squared();
            if dc2 <= radius * radius * 1.0001 {
                return area_fallback(shape, r, u);
            }
            let dc = dc2.sqrt();
            let sin_max = *radius / dc;
            let sin2_max = sin_max * sin_max;
            let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
            let mut one_minus_cos_max = 1.0 - cos_max;
            let mut cos_t = (cos_max - 1.0) * u.x + 1.0;
            let mut sin2_t = 1.0 - cos_t * cos_t;
            if sin2_max < SMALL_CONE {
                sin2_t = sin2_max * u.x;
                cos_t = (1.0 - sin2_t).sqrt();
                one_minus_cos_max = sin2_max / 2.0;
            }
            // The angle α at the centre between −w_c and the point, from the law of sines.
            let cos_a = sin2_t / sin_max + cos_t * (1.0 - sin2_t / sin2_max).max(0.0).sqrt();
            let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
            let phi = u.y * TAU;
            let frame = Frame::from_normal((*center - r) / dc);
            let w = Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a);
            let n = frame.to_world(-w);
            let si = shape.sphere_point(*center + n * *radius);
            Some(finish(shape, si, 1.0 / (TAU * one_minus_cos_max)))
        }
        ShapeKind::Rectangle { n, .. } => match SphericalRectangle::new(shape, r) {
            Some(q) => {
                let (p, uv) = q.sample(u);
                let n = if shape.flip_normals { -*n } else { *n };
                Some(ShapeSample {
                    p,
                    n,
                    ns: n,
                    uv: uv.clamp(Vec2::ZERO, Vec2::ONE),
                    prim: 0,
                    bary: Vec2::ZERO,
                    pdf: q.pdf(),
                })
            }
            None => area_fallback(shape, r, u),
        },
        _ => area_fallback(shape, r, u),
    }
}

fn area_fallback(shape: &WorldShape, r: Vec3, u: Vec2) -> Option<ShapeSample> {
    let mut s = sample_area(shape, u);
    s.pdf = area_to_solid_angle(s.pdf, r, s.p, s.n);
    (s.pdf.is_finite() && s.pdf > 0.0).then_some(s)
}

/// The solid-angle density at `r` with which [`sample_solid_angle`] would produce the point of
/// `hit` (a hit on this shape, seen from `r`).
pub fn pdf_solid_angle(shape: &WorldShape, r: Vec3, hit: &SurfaceInteraction) -> f32 {
    match &shape.kind {
        ShapeKind::Sphere { center, radius, .. } => {
            let dc2 = (*center - r).length_squared();
            if dc2 <= radius * radius * 1.0001 {
                return area_to_solid_angle(1.0 / shape.area(), r, hit.p, hit.n);
            }
            let sin2_max = radius * radius / dc2;
            let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
            let one_minus_cos_max = if sin2_max < SMALL_CONE {
                sin2_max / 2.0
            } else {
                1.0 - cos_max
            };
            1.0 / (TAU * one_minus_cos_max)
        }
        ShapeKind::Rectangle { .. } => match SphericalRectangle::new(shape, r) {
            Some(q) => q.pdf(),
            None => area_to_solid_angle(1.0 / shape.area(), r, hit.p, hit.n),
        },
        _ => area_to_solid_angle(1.0 / shape.area(), r, hit.p, hit.n),
    }
}

/// Solid angles outside this range fall back to area sampling (pbrt-v4's bilinear-patch limits).
const MIN_SPHERICAL_SOLID_ANGLE: f64 = 3e-4;
const MAX_SPHERICAL_SOLID_ANGLE: f64 = 6.22;

/// The spherical rectangle of Ureña et al. 2013 for a rectangle seen from `o`; set up and sampled
/// in double precision (the solid angle is a difference of angles near 2π and loses digits in
/// `f32`).
struct SphericalRectangle {
    o: DVec3,
    x: DVec3,
    y: DVec3,
    z: DVec3,
    z0: f64,
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    b0: f64,
    b1: f64,
    k: f64,
    s: f64,
}

impl SphericalRectangle {
    fn new(shape: &WorldShape, r: Vec3) -> Option<Self> {
        let ShapeKind::Rectangle { basis: Some(b), .. } = &shape.kind else {
            return None;
        };
        let o = r.as_dvec3();
        let d = b.corner - o;
        let mut z = b.z;
        let mut z0 = d.dot(z);
        if z0 > 0.0 {
            z0 = -z0;
            z = -z;
        }
        if z0.abs() < 1e-9 * (b.exl + b.eyl) {
            return None;
        }
        let (x0, y0) = (d.dot(b.x), d.dot(b.y));
        let (x1, y1) = (x0 + b.exl, y0 + b.eyl);
        // The edge-plane normals n_i = normalize(v_i × v_{i+1}) of the paper have closed forms
        // in the rectangle's frame: n0 ∝ (0, z0, −y0), n1 ∝ (−z0, 0, x1), n2 ∝ (0, −z0, y1),
        // n3 ∝ (z0, 0, −x0); so only their lengths and pairwise products are needed.
        let z2 = z0 * z0;
        let (l0, l1) = ((z2 + y0 * y0).sqrt(), (z2 + x1 * x1).sqrt());
        let (l2, l3) = ((z2 + y1 * y1).sqrt(), (z2 + x0 * x0).sqrt());
        let g0 = (y0 * x1 / (l0 * l1)).clamp(-1.0, 1.0).acos();
        let g1 = (-x1 * y1 / (l1 * l2)).clamp(-1.0, 1.0).acos();
        let g2 = (x0 * y1 / (l2 * l3)).clamp(-1.0, 1.0).acos();
        let g3 = (-x0 * y0 / (l3 * l0)).clamp(-1.0, 1.0).acos();
        let k = std::f64::consts::TAU - g2 - g3;
        let s = g0 + g1 - k;
        if !(MIN_SPHERICAL_SOLID_ANGLE..=MAX_SPHERICAL_SOLID_ANGLE).contains(&s) {
            return None;
        }
        Some(Self {
            o,
            x: b.x,
            y: b.y,
            z,
            z0,
            x0,
            y0,
            x1,
            y1,
            b0: -y0 / l0,
            b1: y1 / l2,
            k,
            s,
        })
    }

    fn pdf(&self) -> f32 {
        (1.0 / self.s) as f32
    }

    /// The sampled point (world) and its (u, v) on the rectangle.
    fn sample(&self, u: Vec2) -> (Vec3, Vec2) {
        let (u, v) = (u.x as f64, u.y as f64);
        let au = u * self.s + self.k;
        let fu = (au.cos() * self.b0 - self.b1) / au.sin();
        let cu = ((fu * fu + self.b0 * self.b0).sqrt().recip().copysign(fu)).clamp(-1.0, 1.0);
        let xu = (-(cu * self.z0) / (1.0 - cu * cu).max(1e-300).sqrt()).clamp(self.x0, self.x1);
        let d = (xu * xu + self.z0 * self.z0).sqrt();
        let h0 = self.y0 / (d * d + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d * d + self.y1 * self.y1).sqrt();
        let hv = h0 + v * (h1 - h0);
        let hv2 = hv * hv;
        let yv = if hv2 < 1.0 - 1e-12 {
            (hv * d) / (1.0 - hv2).sqrt()
        } else {
            self.y1
        };
        let yv = yv.clamp(self.y0, self.y1);
        let p = (self.o + xu * self.x + yv * self.y + self.z0 * self.z).as_vec3();
        let uv = Vec2::new(
            ((xu - self.x0) / (self.x1 - self.x0)) as f32,
            ((yv - self.y0) / (self.y1 - self.y0)) as f32,
        );
        (p, uv)
    }
}
