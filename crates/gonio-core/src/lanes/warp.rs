//! Sampling warps on lanes ([`crate::warp`]).

use super::math::sin_cos;
use super::{F32s, Isa, Vec3s};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};

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
    // The ratio of the minor to the major coordinate (0/0 at the centre: masked below).
    let theta = x_major.select(FRAC_PI_4 * (oy / ox), FRAC_PI_2 - FRAC_PI_4 * (ox / oy));
    let (s, c) = sin_cos(theta);
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
