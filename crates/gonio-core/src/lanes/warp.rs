//! Sampling warps on lanes ([`crate::warp`]).

use super::math::sin_cos_quarter;
use super::{F32s, Isa, Vec3s};
use std::f32::consts::FRAC_PI_4;

/// Shirley & Chiu's concentric map of [0, 1)² onto the unit disk per lane
/// ([`crate::warp::square_to_uniform_disk_concentric`]).
#[inline(always)]
pub fn square_to_uniform_disk_concentric<const N: usize, X: Isa>(
    u: [F32s<N, X>; 2],
) -> (F32s<N, X>, F32s<N, X>) {
    let ox = 2.0 * u[0] - 1.0;
    let oy = 2.0 * u[1] - 1.0;
    let x_major = ox.abs().gt(oy.abs());
    let r = x_major.select(ox, oy);
    // The ratio of the minor to the major coordinate (0/0 at the centre: masked below), one
    // division for both branches of the scalar map. Its angle θ is φ = π/4 · ratio where x is
    // the major coordinate and π/2 − φ where y is: (sin θ, cos θ) = (cos φ, sin φ) there, so
    // one polynomial on |φ| ≤ π/4 serves both, with no range reduction.
    let ratio = x_major.select(oy, ox) / r;
    let (sp, cp) = sin_cos_quarter(FRAC_PI_4 * ratio);
    let (s, c) = (x_major.select(sp, cp), x_major.select(cp, sp));
    let centre = ox.eq(0.0) & oy.eq(0.0);
    (centre.select(F32s::ZERO, r * c), centre.select(F32s::ZERO, r * s))
}

/// Cosine-weighted hemisphere per lane ([`crate::warp::square_to_cosine_hemisphere`]).
#[inline(always)]
pub fn square_to_cosine_hemisphere<const N: usize, X: Isa>(u: [F32s<N, X>; 2]) -> Vec3s<N, X> {
    let (x, y) = square_to_uniform_disk_concentric(u);
    let z = (F32s::ONE - (x * x + y * y)).safe_sqrt();
    Vec3s::new(x, y, z)
}
