//! Mitsuba 3's curves, `linearcurve` and `bsplinecurve` (`src/shapes/linearcurve.cpp`,
//! `src/shapes/bsplinecurve.cpp`, traced there by Embree's round curves), as fine triangle
//! meshes with their exact normals and Mitsuba's texture coordinates.
//!
//! A curve is a tube swept by a sphere of varying radius along a centre line c(s) with radius
//! r(s): the envelope of the spheres. At parameter s the envelope touches the sphere along the
//! circle of centre and radius
//!
//! ```text
//! c(s) − r r′ c′/|c′|²,    r √(1 − r′²/|c′|²),
//! ```
//!
//! whose points p have the outward normal (p − c(s))/r(s) (for a constant radius, a cylinder of
//! radius r around c).
//!
//! * `linearcurve`: straight segments between consecutive control points (c and r linear in s),
//!   joined and ended by spheres of the control points' radii (Embree's round linear curve).
//! * `bsplinecurve`: uniform cubic B-spline segments over each four consecutive control points
//!   (c and r both B-splines), open at both ends: no end caps, as Mitsuba 3.9.1 renders them.
//!
//! Texture coordinates are Mitsuba's: u = φ/2π around the centre line, measured from
//! v_rad = v_rot × a in the frame v_rot = normalize(z − a(a·z)) (y when the unit tangent a is ±z);
//! v = (s + segment)/segments along the curve. The joint spheres of a linear curve take the
//! v of their control point. Positions are transformed by `to_world`, radii are not (Mitsuba:
//! "the control points' radii are invariant to this transformation").
//!
//! Mitsuba intersects the exact surface; ours is [`RING`] quads around the centre line,
//! [`BSPLINE_STEPS`] rings per B-spline segment and [`SPHERE_RINGS`] latitude rings per joint
//! sphere. The silhouette departs from the circle by at most r·(1 − cos(π/N)) ≈ 1.2·10⁻³ r.
//!
//! The file format: one control point per line, "x y z radius" (further text on the line is
//! ignored, as Mitsuba's `strtof` parsing does), an empty line starts a new curve; a linear
//! curve needs two control points, a B-spline four.

use crate::scene::TriangleMesh;
use glam::{Affine3A, Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// Quads around the centre line.
pub const RING: u32 = 64;
/// Rings per B-spline segment (the centre line between them is straight).
pub const BSPLINE_STEPS: u32 = 48;
/// Latitude rings of a joint sphere.
pub const SPHERE_RINGS: u32 = 32;

/// The kind of curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveKind {
    /// Straight segments with spherical joints and end caps.
    Linear,
    /// Uniform cubic B-spline segments, open ends.
    BSpline,
}

impl CurveKind {
    fn min_points(self) -> usize {
        match self {
            CurveKind::Linear => 2,
            CurveKind::BSpline => 4,
        }
    }
}

/// Control points `(position, radius)` of each curve of a curve file, positions already in world
/// space.
pub type Curves = Vec<Vec<(Vec3, f32)>>;

/// Parses a curve file (see the module documentation); `line N: ...` errors.
pub fn parse_curves(text: &str, kind: CurveKind, to_world: &Affine3A) -> Result<Curves, String> {
    let mut curves: Curves = Vec::new();
    let mut current: Vec<(Vec3, f32)> = Vec::new();
    let finish = |current: &mut Vec<(Vec3, f32)>, curves: &mut Curves, line: usize| {
        if current.is_empty() {
            return Ok(());
        }
        if current.len() < kind.min_points() {
            return Err(format!(
                "line {line}: a curve has {} control point(s); a {} curve needs at least {}",
                current.len(),
                match kind {
                    CurveKind::Linear => "linear",
                    CurveKind::BSpline => "B-spline",
                },
                kind.min_points()
            ));
        }
        curves.push(std::mem::take(current));
        Ok(())
    };
    let mut last = 0;
    for (i, line) in text.split('\n').enumerate() {
        let n = i + 1;
        last = n;
        if line.len() >= 1024 {
            return Err(format!(
                "line {n}: excessively long line ({} characters)",
                line.len()
            ));
        }
        let trimmed = line.trim_matches([' ', '\t', '\r']);
        if trimmed.is_empty() {
            finish(&mut current, &mut curves, n)?;
            continue;
        }
        let mut fields = trimmed.split_ascii_whitespace();
        let mut v = [0f32; 4];
        for (k, slot) in v.iter_mut().enumerate() {
            let f = fields
                .next()
                .ok_or_else(|| format!("line {n}: \"{trimmed}\" has {k} numbers, expected x y z radius"))?;
            *slot = f
                .parse::<f32>()
                .map_err(|_| format!("line {n}: cannot parse \"{f}\" as a number in \"{trimmed}\""))?;
        }
        let p = to_world.transform_point3(Vec3::new(v[0], v[1], v[2]));
        if !p.is_finite() {
            return Err(format!("line {n}: invalid position in \"{trimmed}\""));
        }
        if !v[3].is_finite() || v[3] < 0.0 {
            return Err(format!("line {n}: invalid radius {} in \"{trimmed}\"", v[3]));
        }
        current.push((p, v[3]));
    }
    finish(&mut current, &mut curves, last)?;
    if curves.is_empty() {
        return Err("empty curve file: no control points were read".into());
    }
    Ok(curves)
}

/// Mitsuba's `local_frame(a)`: `(v_rot, v_rad)`.
fn local_frame(a: Vec3) -> (Vec3, Vec3) {
    let guide = Vec3::Z;
    let v_rot = if a.dot(guide).abs() == 1.0 {
        Vec3::Y
    } else {
        (guide - a * a.dot(guide)).normalize()
    };
    (v_rot, v_rot.cross(a))
}

/// A mesh under construction.
#[derive(Default)]
struct Builder {
    mesh: TriangleMesh,
}

impl Builder {
    fn vertex(&mut self, p: Vec3, n: Vec3, uv: Vec2) -> u32 {
        self.mesh.positions.push(p);
        self.mesh.normals.push(n);
        self.mesh.uvs.push(uv);
        self.mesh.positions.len() as u32 - 1
    }

    /// A triangle wound so that its face normal agrees with its vertices' normals; degenerate
    /// ones are dropped.
    fn tri(&mut self, a: u32, b: u32, c: u32) {
        let [pa, pb, pc] = [a, b, c].map(|i| self.mesh.positions[i as usize]);
        let f = (pb - pa).cross(pc - pa);
        if f.length_squared() == 0.0 || !f.is_finite() {
            return;
        }
        let n = self.mesh.normals[a as usize] + self.mesh.normals[b as usize] + self.mesh.normals[c as usize];
        if f.dot(n) >= 0.0 {
            self.mesh.indices.push([a, b, c]);
        } else {
            self.mesh.indices.push([a, c, b]);
        }
    }

    /// One ring of `RING + 1` vertices (the seam duplicated) at centre `c`, radius `r`, unit
    /// tangent `a`, radius derivative ratio `k = r′/|c′|`, texture v `v`; returns the first index.
    fn ring(&mut self, c: Vec3, r: f32, a: Vec3, k: f32, v: f32) -> u32 {
        let (v_rot, v_rad) = local_frame(a);
        let k = k.clamp(-0.999, 0.999);
        let cos_k = (1.0 - k * k).sqrt();
        let first = self.mesh.positions.len() as u32;
        for i in 0..=RING {
            let u = i as f32 / RING as f32;
            let (s, co) = (TAU * u).sin_cos();
            let radial = v_rad * co + v_rot * s;
            // The envelope normal leans back along the tangent where the radius grows.
            let n = (radial * cos_k - a * k).normalize();
            self.vertex(c + n * r, n, Vec2::new(u, v));
        }
        first
    }

    /// Quads between two rings.
    fn strip(&mut self, r0: u32, r1: u32) {
        for i in 0..RING {
            let (a, b, c, d) = (r0 + i, r0 + i + 1, r1 + i, r1 + i + 1);
            self.tri(a, b, d);
            self.tri(a, d, c);
        }
    }

    /// A sphere of centre `c` and radius `r`, its u measured in the frame of tangent `a`.
    fn sphere(&mut self, c: Vec3, r: f32, a: Vec3, v: f32) {
        if r <= 0.0 {
            return;
        }
        let (v_rot, v_rad) = local_frame(a);
        let mut prev: Option<u32> = None;
        for j in 0..=SPHERE_RINGS {
            let theta = PI * j as f32 / SPHERE_RINGS as f32;
            let (st, ct) = theta.sin_cos();
            let first = self.mesh.positions.len() as u32;
            for i in 0..=RING {
                let u = i as f32 / RING as f32;
                let (s, co) = (TAU * u).sin_cos();
                let n = (a * ct + (v_rad * co + v_rot * s) * st).normalize();
                self.vertex(c + n * r, n, Vec2::new(u, v));
            }
            if let Some(p) = prev {
                self.strip(p, first);
            }
            prev = Some(first);
        }
    }
}

/// The uniform cubic B-spline of the four values at `t`, and its derivative.
fn bspline<T>(p: [T; 4], t: f32) -> (T, T)
where
    T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
{
    let s = 1.0 - t;
    let b = [
        s * s * s / 6.0,
        (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
        (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
        t * t * t / 6.0,
    ];
    let d = [
        -s * s / 2.0,
        (3.0 * t * t - 4.0 * t) / 2.0,
        (-3.0 * t * t + 2.0 * t + 1.0) / 2.0,
        t * t / 2.0,
    ];
    (
        p[0] * b[0] + p[1] * b[1] + p[2] * b[2] + p[3] * b[3],
        p[0] * d[0] + p[1] * d[1] + p[2] * d[2] + p[3] * d[3],
    )
}

/// The curves as one world-space triangle mesh (see the module documentation).
pub fn tessellate(curves: &Curves, kind: CurveKind) -> TriangleMesh {
    let segments: usize = curves.iter().map(|c| c.len() + 1 - kind.min_points()).sum();
    let mut b = Builder::default();
    let mut seg = 0usize;
    for curve in curves {
        match kind {
            CurveKind::Linear => {
                for (i, w) in curve.windows(2).enumerate() {
                    let ((p0, r0), (p1, r1)) = (w[0], w[1]);
                    let d = p1 - p0;
                    let len = d.length();
                    let v0 = (seg + i) as f32 / segments as f32;
                    let v1 = (seg + i + 1) as f32 / segments as f32;
                    if len > 0.0 && (r1 - r0).abs() < len {
                        let a = d / len;
                        let k = (r1 - r0) / len;
                        let ring0 = b.ring(p0, r0, a, k, v0);
                        let ring1 = b.ring(p1, r1, a, k, v1);
                        b.strip(ring0, ring1);
                    }
                    let a = if len > 0.0 { d / len } else { Vec3::X };
                    b.sphere(p0, r0, a, v0);
                    if i + 2 == curve.len() {
                        b.sphere(p1, r1, a, v1);
                    }
                }
                seg += curve.len() - 1;
            }
            CurveKind::BSpline => {
                for (i, w) in curve.windows(4).enumerate() {
                    let pos = [w[0].0, w[1].0, w[2].0, w[3].0];
                    let rad = [w[0].1, w[1].1, w[2].1, w[3].1];
                    let mut prev: Option<u32> = None;
                    // Rings at the segment's ends are shared by value with the neighbours.
                    for j in 0..=BSPLINE_STEPS {
                        let t = j as f32 / BSPLINE_STEPS as f32;
                        let (c, dc) = bspline(pos, t);
                        let (r, dr) = bspline(rad, t);
                        let l = dc.length();
                        if !(l > 0.0) {
                            prev = None;
                            continue;
                        }
                        let v = (t + (seg + i) as f32) / segments as f32;
                        let ring = b.ring(c, r, dc / l, dr / l, v);
                        if let Some(p) = prev {
                            b.strip(p, ring);
                        }
                        prev = Some(ring);
                    }
                }
                seg += curve.len() - 3;
            }
        }
    }
    b.mesh
}
