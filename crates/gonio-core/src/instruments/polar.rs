//! Lobes in the plane of incidence (Disney BRDF Explorer's "Polar Plot"): the light arrives at
//! polar angle θi from the left (azimuth 180°), the view sweeps the whole plane of incidence.
//!
//! Angles are signed: α ∈ [−180°, 180°], 0 = the normal, positive towards +x (the side of the
//! mirror direction), |α| > 90° below the surface (transmission). The light is at α = −θi.

use super::{DeltaLobe, find_delta_lobes};
use crate::bsdf::{Bsdf, BsdfContext};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// The in-plane direction at signed angle `alpha` (radians): (sin α, 0, cos α).
#[inline]
pub fn in_plane_direction(alpha: f32) -> Vec3 {
    let (s, c) = alpha.sin_cos();
    Vec3::new(s, 0.0, c)
}

/// The lobe of one BSDF in the plane of incidence.
#[derive(Clone, Debug, PartialEq)]
pub struct PolarLobe {
    /// Incident (light) polar angle, degrees.
    pub theta_i_deg: f32,
    /// Signed view angles, degrees, from −180 to 180.
    pub angles_deg: Vec<f32>,
    /// f(light → view) at each angle, times |cos α| when `cosine` was asked.
    pub values: Vec<SampledSpectrum>,
    /// Whether the values include |cos α|.
    pub cosine: bool,
    /// The delta lobes (their directions lie in the plane of incidence).
    pub deltas: Vec<DeltaLobe>,
}

/// Computes the in-plane lobe with `samples` angles over the full circle.
pub fn compute_polar<B: Bsdf + ?Sized>(
    bsdf: &B,
    theta_i_deg: f32,
    samples: usize,
    cosine: bool,
    wl: &SampledWavelengths,
) -> PolarLobe {
    let light = in_plane_direction(-theta_i_deg.to_radians());
    let ctx = BsdfContext::radiance();
    let samples = samples.max(3);
    let mut angles_deg = Vec::with_capacity(samples);
    let mut values = Vec::with_capacity(samples);
    for k in 0..samples {
        let a = -180.0 + 360.0 * k as f32 / (samples - 1) as f32;
        let view = in_plane_direction(a.to_radians());
        let f = bsdf.eval(&ctx, view, light, wl);
        angles_deg.push(a);
        values.push(if cosine { f * view.z.abs() } else { f });
    }
    let deltas = find_delta_lobes(bsdf, BsdfContext::importance(), light, wl);
    PolarLobe {
        theta_i_deg,
        angles_deg,
        values,
        cosine,
        deltas,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::Diffuse;

    #[test]
    fn lambertian_lobe_is_a_half_circle_of_radius_rho_over_pi() {
        let d = Diffuse::default();
        let wl = SampledWavelengths::fixed(550.0);
        let lobe = compute_polar(&d, 30.0, 361, false, &wl);
        for (a, v) in lobe.angles_deg.iter().zip(&lobe.values) {
            if a.abs() < 89.5 {
                assert!((v[0] - 0.5 / std::f32::consts::PI).abs() < 1e-6, "{a}");
            } else if a.abs() > 90.5 {
                assert_eq!(v[0], 0.0, "{a}: a BRDF is zero below the surface");
            }
        }
        let cos = compute_polar(&d, 30.0, 361, true, &wl);
        assert!((cos.values[180 + 60][0] - 0.5 / std::f32::consts::PI * 0.5).abs() < 1e-5);
    }
}
