//! Sample warps: maps from the unit square to directions and points, each with its density.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI};

/// Shirley–Chiu concentric map of [0,1)² onto the unit disk (area-preserving up to a constant).
#[inline]
pub fn square_to_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y))
    };
    let (s, c) = theta.sin_cos();
    Vec2::new(r * c, r * s)
}

/// Cosine-weighted hemisphere (Malley's method on the concentric disk), z ≥ 0.
#[inline]
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_uniform_disk_concentric(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Density of [`square_to_cosine_hemisphere`]: cos θ/π for z > 0, else 0.
#[inline]
pub fn square_to_cosine_hemisphere_pdf(w: Vec3) -> f32 {
    if w.z > 0.0 { w.z * FRAC_1_PI } else { 0.0 }
}

/// Uniform direction on the unit sphere.
#[inline]
pub fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.y;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = (2.0 * PI * u.x).sin_cos();
    Vec3::new(r * c, r * s, z)
}

/// Density of [`square_to_uniform_sphere`]: 1/(4π).
#[inline]
pub fn square_to_uniform_sphere_pdf() -> f32 {
    0.25 * FRAC_1_PI
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cosine_warp_reference_value() {
        // Mitsuba 3's square_to_cosine_hemisphere (core/warp.h): ξ = (0.3, 0.7) →
        // (−0.282843, 0.282843, 0.916515).
        let w = square_to_cosine_hemisphere(Vec2::new(0.3, 0.7));
        assert!(
            (w - Vec3::new(-0.282843, 0.282843, 0.916515)).length() < 1e-5,
            "{w}"
        );
    }
}
