//! `cylinder`: Mitsuba 3's open cylinder (`src/shapes/cylinder.cpp`), as a fine triangle mesh.
//!
//! The lateral surface of radius r between the points p0 and p1 (no caps): in object space the
//! unit cylinder x² + y² = 1, 0 ≤ z ≤ 1, normals pointing away from the axis, texture coordinates
//! (u, v) = (φ/2π, z) with φ = atan2(y, x) ∈ [0, 2π), placed by
//! `to_world · translate(p0) · [s, t, d] · scale(r, r, |p1 − p0|)`, where d = (p1 − p0)/|p1 − p0|
//! and (s, t) complete d to Mitsuba's orthonormal frame (`coordinate_system`, Duff et al. 2017,
//! "Building an orthonormal basis, revisited").
//!
//! Mitsuba intersects the quadric; ours is [`SEGMENTS`] quads around the axis with the exact
//! vertex normals and texture coordinates (interpolated in between): the silhouette departs from
//! the circle by at most r·(1 − cos(π/N)) = 7.5·10⁻⁵ r, below a pixel in any reasonable view.
//!
//! | parameter | default |
//! |---|---|
//! | `p0`, `p1` | (0, 0, 0), (0, 0, 1) |
//! | `radius` | 1 (positive) |
//! | `to_world`, `flip_normals`, nested `bsdf` and `emitter` | as every shape |

use super::{BSDF, EMITTER, FLIP_NORMALS, MEDIA, TO_WORLD, assemble, common};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{Geometry, ShapeDesc, TriangleMesh};
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use glam::{Affine3A, DVec3, Vec2, Vec3};
use std::sync::Arc;

const P0: ParamSpec = ParamSpec::new(
    "p0",
    ParamType::Point,
    DefaultValue::Derived("(0, 0, 0)"),
    "centre of the bottom end, in object space",
);
const P1: ParamSpec = ParamSpec::new(
    "p1",
    ParamType::Point,
    DefaultValue::Derived("(0, 0, 1)"),
    "centre of the top end, in object space (≠ p0)",
);
const RADIUS: ParamSpec = ParamSpec::new(
    "radius",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "radius, in object space (positive)",
);

/// Quads around the axis.
pub const SEGMENTS: u32 = 256;

/// The `cylinder` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "cylinder",
    summary: "Open cylinder (no caps) of the given radius from p0 to p1 (ours: 512 triangles with exact normals and uv).",
    params: &[TO_WORLD, FLIP_NORMALS, P0, P1, RADIUS, BSDF, EMITTER, MEDIA],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let mut c = common(p)?;
    let p0 = p.point_opt(P0.name)?.map_or(DVec3::ZERO, |(v, _)| v);
    let (p1, p1_loc) = match p.point_opt(P1.name)? {
        Some((v, loc)) => (v, Some(loc)),
        None => (DVec3::Z, None),
    };
    let radius = p.float_checked(
        RADIUS.name,
        RADIUS.default.float(),
        |r| r > 0.0,
        "must be positive",
    )?;
    let axis = p1 - p0;
    let length = axis.length();
    if !(length > 0.0 && length.is_finite()) {
        return Err(err(
            p1_loc.unwrap_or(&p.obj.loc),
            ErrorKind::BadValue,
            format!(
                "<shape type=\"cylinder\">: p0 ({}, {}, {}) and p1 ({}, {}, {}) must differ",
                p0.x, p0.y, p0.z, p1.x, p1.y, p1.z
            ),
        ));
    }
    let local = placement(
        p0.as_vec3(),
        axis.as_vec3() / length as f32,
        radius as f32,
        length as f32,
    );
    c.to_world *= local;
    assemble(b, p, c, Geometry::Mesh(Arc::new(unit_cylinder(SEGMENTS))), false)
}

/// Mitsuba's `coordinate_system(n)`: two unit vectors completing the unit `n` to a right-handed
/// orthonormal frame.
fn coordinate_system(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// Unit cylinder → the cylinder of radius `r` from `p0` along the unit `d` for `length`.
pub fn placement(p0: Vec3, d: Vec3, r: f32, length: f32) -> Affine3A {
    let (s, t) = coordinate_system(d);
    Affine3A::from_cols((s * r).into(), (t * r).into(), (d * length).into(), p0.into())
}

/// The unit cylinder (radius 1, 0 ≤ z ≤ 1) as `segments` quads, counter-clockwise seen from
/// outside, with its seam at φ = 0 duplicated so that u runs from 0 to 1.
pub fn unit_cylinder(segments: u32) -> TriangleMesh {
    let n = segments.max(3);
    let mut m = TriangleMesh {
        positions: Vec::with_capacity(2 * (n as usize + 1)),
        normals: Vec::new(),
        uvs: Vec::new(),
        indices: Vec::with_capacity(2 * n as usize),
    };
    for i in 0..=n {
        let u = i as f32 / n as f32;
        let (s, c) = (std::f32::consts::TAU * u).sin_cos();
        // The seam's second copy sits exactly on the first.
        let (s, c) = if i == n { (0.0, 1.0) } else { (s, c) };
        for z in [0.0f32, 1.0] {
            m.positions.push(Vec3::new(c, s, z));
            m.normals.push(Vec3::new(c, s, 0.0));
            m.uvs.push(Vec2::new(u, z));
        }
    }
    for i in 0..n {
        let (a, b) = (2 * i, 2 * (i + 1));
        // a: (φ_i, 0), a+1: (φ_i, 1), b: (φ_i+1, 0), b+1: (φ_i+1, 1).
        m.indices.push([a, b, b + 1]);
        m.indices.push([a, b + 1, a + 1]);
    }
    m
}
