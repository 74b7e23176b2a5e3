//! 2D slices of the BSDF (lecture slides "2D Slices of the BRDF: Eye" and "... : Lighting"):
//! fix the light and vary the view over the sphere, or fix the view and vary the light.
//!
//! The varying direction is drawn on a disk through an azimuthal [`Projection`]: the centre is
//! the normal (θ = 0), the rim the horizon (θ = 90°), x to the right is φ = 0, y up is φ = 90°.
//! The side of the surface the fixed direction is on is drawn as one disk ("upper", z > 0); when
//! the BSDF transmits, a second disk shows the other side (z < 0, seen through the surface, same
//! x and y). Delta lobes have no value to draw: they are found by sampling
//! ([`super::find_delta_lobes`]) and returned for the plot to mark.

use super::{DeltaLobe, find_delta_lobes, spherical_direction};
use crate::bsdf::{Bsdf, BsdfContext};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// Which direction a slice keeps fixed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fixed {
    /// Fix the light, vary the view ("2D Slices of the BRDF: Eye").
    Light,
    /// Fix the view, vary the light ("2D Slices of the BRDF: Lighting").
    View,
}

/// Maps between the unit disk and a hemisphere of directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projection {
    /// Lambert azimuthal equal-area: ρ = √2 sin(θ/2). Equal areas on the disk are equal solid
    /// angles, so the picture's "amount of colour" is the integral over the hemisphere.
    EqualArea,
    /// Parabolic (paraboloid map, Heidrich & Seidel 1998): ρ = tan(θ/2). Conformal: lobe shapes
    /// keep their angles.
    Parabolic,
}

impl Projection {
    /// The direction (z ≥ 0) at disk point `p` (|p| ≤ 1), or `None` outside the disk.
    pub fn to_direction(self, p: Vec2) -> Option<Vec3> {
        let r2 = p.length_squared();
        if r2 > 1.0 {
            return None;
        }
        Some(match self {
            Projection::EqualArea => {
                let s = (2.0 - r2).max(0.0).sqrt();
                Vec3::new(p.x * s, p.y * s, 1.0 - r2)
            }
            Projection::Parabolic => {
                let d = 1.0 + r2;
                Vec3::new(2.0 * p.x / d, 2.0 * p.y / d, (1.0 - r2) / d)
            }
        })
    }

    /// The disk point of a direction, using |z| (so a lower-hemisphere direction lands where its
    /// mirror image through the surface does).
    pub fn to_disk(self, w: Vec3) -> Vec2 {
        let z = w.z.abs();
        let xy = Vec2::new(w.x, w.y);
        match self {
            Projection::EqualArea => xy / (1.0 + z).sqrt(),
            Projection::Parabolic => xy / (1.0 + z),
        }
    }

    /// Disk radius of the circle θ = `theta` (radians).
    pub fn ring_radius(self, theta: f32) -> f32 {
        match self {
            Projection::EqualArea => std::f32::consts::SQRT_2 * (0.5 * theta).sin(),
            Projection::Parabolic => (0.5 * theta).tan(),
        }
    }

    /// The name printed on plots.
    pub fn description(self) -> &'static str {
        match self {
            Projection::EqualArea => "Lambert equal-area projection",
            Projection::Parabolic => "parabolic projection",
        }
    }
}

/// What to compute.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliceSettings {
    /// The direction kept fixed.
    pub fixed: Fixed,
    /// Polar angle of the fixed direction, degrees (> 90 puts it below the surface).
    pub theta_deg: f32,
    /// Azimuth of the fixed direction, degrees.
    pub phi_deg: f32,
    /// Multiply by |cos θ| of the varying direction (the integrand of the albedo: where the
    /// scattered power goes, or where incident power comes from).
    pub cosine: bool,
    /// Pixels across each disk.
    pub resolution: usize,
    /// The disk mapping.
    pub projection: Projection,
}

impl Default for SliceSettings {
    fn default() -> Self {
        Self {
            fixed: Fixed::Light,
            theta_deg: 30.0,
            phi_deg: 0.0,
            cosine: false,
            resolution: 256,
            projection: Projection::EqualArea,
        }
    }
}

/// One hemisphere of a slice as a `resolution²` image, row-major, row 0 at the top (+y).
#[derive(Clone, Debug, PartialEq)]
pub struct Disk {
    /// +1 for the side of the fixed direction, −1 for the other side.
    pub side: f32,
    /// Pixel values; `None` outside the disk.
    pub pixels: Vec<Option<SampledSpectrum>>,
}

/// A computed slice.
#[derive(Clone, Debug, PartialEq)]
pub struct Slice {
    /// The settings used.
    pub settings: SliceSettings,
    /// The fixed direction (local frame).
    pub fixed_direction: Vec3,
    /// The fixed direction's side, then (for transmitting BSDFs) the other side.
    pub disks: Vec<Disk>,
    /// The delta lobes, with the varying direction they point to.
    pub deltas: Vec<DeltaLobe>,
}

impl Slice {
    /// Largest channel-0 value over all pixels (0 if none).
    pub fn max_value(&self) -> f32 {
        self.disks
            .iter()
            .flat_map(|d| d.pixels.iter().flatten())
            .map(|v| v[0])
            .fold(0.0, f32::max)
    }
}

/// The varying direction at pixel (`row`, `col`) of a disk on side `side`.
pub fn pixel_direction(settings: &SliceSettings, side: f32, row: usize, col: usize) -> Option<Vec3> {
    let n = settings.resolution as f32;
    let p = Vec2::new(
        (col as f32 + 0.5) / n * 2.0 - 1.0,
        1.0 - (row as f32 + 0.5) / n * 2.0,
    );
    let w = settings.projection.to_direction(p)?;
    Some(Vec3::new(w.x, w.y, w.z * side))
}

/// Computes the slice of `bsdf` at the wavelengths `wl` (use [`SampledWavelengths::fixed`] for a
/// single wavelength: each channel then holds the same λ).
pub fn compute_slice<B: Bsdf + ?Sized>(bsdf: &B, settings: &SliceSettings, wl: &SampledWavelengths) -> Slice {
    let fixed = spherical_direction(settings.theta_deg.to_radians(), settings.phi_deg.to_radians());
    let side0 = if fixed.z >= 0.0 { 1.0 } else { -1.0 };
    let mut sides = vec![side0];
    if bsdf.flags().is_transmission() {
        sides.push(-side0);
    }
    let ctx = BsdfContext::radiance();
    let n = settings.resolution;
    let disks = sides
        .iter()
        .map(|&side| {
            let mut pixels = Vec::with_capacity(n * n);
            for row in 0..n {
                for col in 0..n {
                    pixels.push(pixel_direction(settings, side, row, col).map(|w| {
                        let (view, light) = match settings.fixed {
                            Fixed::Light => (w, fixed),
                            Fixed::View => (fixed, w),
                        };
                        let f = bsdf.eval(&ctx, view, light, wl);
                        if settings.cosine { f * w.z.abs() } else { f }
                    }));
                }
            }
            Disk { side, pixels }
        })
        .collect();
    // Light flows light → view. With the light fixed, the views its delta lobes reach are the
    // importance-mode samples from the light; with the view fixed, the radiance-mode samples.
    let deltas = match settings.fixed {
        Fixed::Light => find_delta_lobes(bsdf, BsdfContext::importance(), fixed, wl),
        Fixed::View => find_delta_lobes(bsdf, BsdfContext::radiance(), fixed, wl),
    };
    Slice {
        settings: *settings,
        fixed_direction: fixed,
        disks,
        deltas,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::Diffuse;
    use crate::spectra::Spectrum;

    #[test]
    fn projections_round_trip_and_map_rim_to_horizon() {
        for proj in [Projection::EqualArea, Projection::Parabolic] {
            for &(x, y) in &[(0.0, 0.0), (0.3, -0.2), (0.7, 0.7), (-0.99, 0.05)] {
                let p = Vec2::new(x, y);
                let w = proj.to_direction(p).unwrap();
                assert!((w.length() - 1.0).abs() < 1e-5, "{proj:?} {p}");
                assert!((proj.to_disk(w) - p).length() < 1e-5, "{proj:?} {p}");
            }
            let rim = proj.to_direction(Vec2::new(1.0, 0.0)).unwrap();
            assert!(rim.z.abs() < 1e-6);
            assert!((proj.ring_radius(std::f32::consts::FRAC_PI_2) - 1.0).abs() < 1e-6);
            let w = spherical_direction(1.0, 0.0);
            assert!((proj.to_disk(w).length() - proj.ring_radius(1.0)).abs() < 1e-5);
        }
    }

    #[test]
    fn equal_area_projection_preserves_solid_angle() {
        // The fraction of disk pixels with θ < 60° must be the solid-angle fraction
        // (1 − cos 60°) = 1/2 of the hemisphere.
        let s = SliceSettings {
            resolution: 400,
            ..Default::default()
        };
        let (mut inside, mut below60) = (0usize, 0usize);
        for r in 0..400 {
            for c in 0..400 {
                if let Some(w) = pixel_direction(&s, 1.0, r, c) {
                    inside += 1;
                    below60 += (w.z > 0.5) as usize;
                }
            }
        }
        let frac = below60 as f64 / inside as f64;
        assert!((frac - 0.5).abs() < 0.01, "{frac}");
    }

    #[test]
    fn lambertian_slice_is_flat_at_rho_over_pi() {
        let d = Diffuse::new(Spectrum::Constant(0.8));
        let wl = SampledWavelengths::fixed(550.0);
        for fixed in [Fixed::Light, Fixed::View] {
            let s = SliceSettings {
                fixed,
                theta_deg: 40.0,
                resolution: 64,
                ..Default::default()
            };
            let slice = compute_slice(&d, &s, &wl);
            assert_eq!(slice.disks.len(), 1, "a BRDF has no transmission disk");
            let mut count = 0;
            for v in slice.disks[0].pixels.iter().flatten() {
                assert!((v[0] - 0.8 / std::f32::consts::PI).abs() < 1e-6);
                count += 1;
            }
            assert!(count > 3000);
            assert!(slice.deltas.is_empty());
        }
    }

    #[test]
    fn cosine_weighting_darkens_the_rim() {
        let d = Diffuse::default();
        let wl = SampledWavelengths::fixed(550.0);
        let s = SliceSettings {
            cosine: true,
            resolution: 33,
            ..Default::default()
        };
        let slice = compute_slice(&d, &s, &wl);
        let centre = slice.disks[0].pixels[16 * 33 + 16].unwrap()[0];
        let edge = slice.disks[0].pixels[16 * 33 + 32].unwrap()[0];
        assert!((centre - 0.5 / std::f32::consts::PI).abs() < 2e-3);
        assert!(edge < 0.3 * centre, "{edge} vs {centre}");
    }
}
