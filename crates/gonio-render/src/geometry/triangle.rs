//! The watertight ray/triangle test (Woop, Benthin and Wald, "Watertight Ray/Triangle
//! Intersection", JCGT 2(1), 2013), compiled once per axis permutation.

use super::Ray;
use glam::Vec3;

/// A ray prepared for the watertight triangle test (Woop, Benthin and Wald 2013): the axis
/// permutation that makes |d.z| largest and the shear constants.
///
/// The permutation is kept as one of its six cases (`TriRay::perm`) so that the test is
/// compiled once per case with constant component indices: indexing a `Vec3` by a run-time axis
/// number cost more than the rest of the test (a bounds-checked `match` per component).
#[derive(Clone, Copy, Debug)]
pub struct TriRay {
    o: Vec3,
    /// Which `(kx, ky, kz)` of [`PERMUTATIONS`] this ray uses.
    perm: u8,
    s: Vec3,
}

/// The six axis permutations `(kx, ky, kz)` of the watertight test: `kz` the dominant axis of
/// the direction, `kx`, `ky` the next two in cyclic order, swapped when `d[kz] < 0` (keeps the
/// winding).
const PERMUTATIONS: [[usize; 3]; 6] = [[1, 2, 0], [2, 1, 0], [2, 0, 1], [0, 2, 1], [0, 1, 2], [1, 0, 2]];

impl TriRay {
    /// A stand-in for a query that tests no triangle (a scene of analytic shapes alone): the
    /// set-up's three divisions skipped. Never valid for [`intersect_triangle`].
    #[inline]
    pub fn none(ray: &Ray) -> Self {
        Self {
            o: ray.o,
            perm: 0,
            s: Vec3::ZERO,
        }
    }

    /// Prepares `ray`.
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let a = ray.d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let d = ray.d.to_array();
        let perm = 2 * kz + usize::from(d[kz] < 0.0);
        let [kx, ky, _] = PERMUTATIONS[perm];
        let dz = d[kz];
        Self {
            o: ray.o,
            perm: perm as u8,
            s: Vec3::new(d[kx] / dz, d[ky] / dz, 1.0 / dz),
        }
    }
}

/// Watertight ray/triangle intersection (Woop, Benthin and Wald, JCGT 2013): edges shared by two
/// triangles are never missed by both, which matters for closed meshes in furnace tests. Returns
/// `(t, b1, b2)` with `p = (1 − b1 − b2)·p0 + b1·p1 + b2·p2`, for `0 < t < tmax`.
#[inline]
pub fn intersect_triangle(p0: Vec3, p1: Vec3, p2: Vec3, r: &TriRay, tmax: f32) -> Option<(f32, f32, f32)> {
    match r.perm {
        0 => woop::<1, 2, 0>(p0, p1, p2, r, tmax),
        1 => woop::<2, 1, 0>(p0, p1, p2, r, tmax),
        2 => woop::<2, 0, 1>(p0, p1, p2, r, tmax),
        3 => woop::<0, 2, 1>(p0, p1, p2, r, tmax),
        4 => woop::<0, 1, 2>(p0, p1, p2, r, tmax),
        _ => woop::<1, 0, 2>(p0, p1, p2, r, tmax),
    }
}

/// [`intersect_triangle`] for the permutation `(KX, KY, KZ)`.
#[inline(always)]
fn woop<const KX: usize, const KY: usize, const KZ: usize>(
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    r: &TriRay,
    tmax: f32,
) -> Option<(f32, f32, f32)> {
    let a = (p0 - r.o).to_array();
    let b = (p1 - r.o).to_array();
    let c = (p2 - r.o).to_array();
    let (ax, ay) = (a[KX] - r.s.x * a[KZ], a[KY] - r.s.y * a[KZ]);
    let (bx, by) = (b[KX] - r.s.x * b[KZ], b[KY] - r.s.y * b[KZ]);
    let (cx, cy) = (c[KX] - r.s.x * c[KZ], c[KY] - r.s.y * c[KZ]);
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        // Fall back to double precision on edges, as the paper prescribes.
        u = (cx as f64 * by as f64 - cy as f64 * bx as f64) as f32;
        v = (ax as f64 * cy as f64 - ay as f64 * cx as f64) as f32;
        w = (bx as f64 * ay as f64 - by as f64 * ax as f64) as f32;
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let (az, bz, cz) = (r.s.z * a[KZ], r.s.z * b[KZ], r.s.z * c[KZ]);
    let t_scaled = u * az + v * bz + w * cz;
    if det < 0.0 {
        if t_scaled >= 0.0 || t_scaled < tmax * det {
            return None;
        }
    } else if t_scaled <= 0.0 || t_scaled > tmax * det {
        return None;
    }
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    if !(t > 0.0 && t < tmax) {
        return None;
    }
    // u weighs p0 (opposite edge p1–p2), v weighs p1, w weighs p2.
    Some((t, v * inv, w * inv))
}
