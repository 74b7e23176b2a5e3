//! The lecture's BRDF instruments as pure computations (no I/O): 2D slices of the BRDF over the
//! hemisphere, lobes in the plane of incidence, directional albedo curves, Fresnel curves and a
//! virtual gonioreflectometer. The `gonio plot`, `gonio measure` commands and the plots in
//! `gonio-render::plot` are thin layers over these functions.
//!
//! Direction names: an instrument speaks of the *light* (where the light comes from) and the
//! *view* (where the light goes to). With the BSDF trait's Mitsuba naming in radiance mode, the
//! value an instrument reports is `f = eval(radiance, wi = view, wo = light)`, which is also
//! `eval(importance, wi = light, wo = view)`: the light flows from `light` to `view`.

pub mod albedo;
pub mod fresnel;
pub mod gonioreflectometer;
pub mod microfacet_albedo;
pub mod polar;
pub mod slice;

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// The unit direction with polar angle `theta` and azimuth `phi` (radians) in the local frame.
#[inline]
pub fn spherical_direction(theta: f32, phi: f32) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(st * cp, st * sp, ct)
}

/// A Dirac lobe found by sampling: where it points and how much of the light it carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeltaLobe {
    /// The direction the delta lobe sends light to (unit, local frame).
    pub direction: Vec3,
    /// Throughput of the lobe (sample weight × selection probability), e.g. F for a mirror
    /// reflection off a dielectric.
    pub throughput: SampledSpectrum,
    /// The lobe's flags (`reflection|delta`, `transmission|delta`, ...).
    pub flags: BsdfFlags,
}

/// Finds the Dirac lobes of `bsdf` seen from `wi` in the given transport mode, by sweeping the
/// lobe-selection number `u1` through the delta lobes only. Duplicates (same direction) are
/// merged; the throughput of each is `weight · pdf` (the selection probability cancels).
pub fn find_delta_lobes<B: Bsdf + ?Sized>(
    bsdf: &B,
    ctx: BsdfContext,
    wi: Vec3,
    wl: &SampledWavelengths,
) -> Vec<DeltaLobe> {
    let mut out: Vec<DeltaLobe> = Vec::new();
    if !bsdf.flags().is_delta() {
        return out;
    }
    let ctx = ctx.with_lobes(BsdfFlags(
        BsdfFlags::REFLECTION.0 | BsdfFlags::TRANSMISSION.0 | BsdfFlags::DELTA.0 | BsdfFlags::NULL.0,
    ));
    const SWEEP: usize = 256;
    for k in 0..SWEEP {
        let u1 = (k as f32 + 0.5) / SWEEP as f32;
        let mut w = *wl;
        let Some(s) = bsdf.sample(&ctx, wi, u1, Vec2::splat(0.5), &mut w) else {
            continue;
        };
        if !s.flags.is_delta() {
            continue;
        }
        let throughput = s.weight * s.pdf;
        if out.iter().any(|d| d.direction.dot(s.wo) > 0.99999) {
            continue;
        }
        out.push(DeltaLobe {
            direction: s.wo,
            throughput,
            flags: s.flags,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spherical_direction_is_unit_and_has_its_angles() {
        let w = spherical_direction(0.7, 2.0);
        assert!((w.length() - 1.0).abs() < 1e-6);
        assert!((w.z.acos() - 0.7).abs() < 1e-5);
        assert!((w.y.atan2(w.x) - 2.0).abs() < 1e-5);
    }

    #[test]
    fn a_diffuse_surface_has_no_delta_lobe() {
        let d = crate::bsdfs::Diffuse::default();
        let wl = SampledWavelengths::fixed(550.0);
        assert!(find_delta_lobes(&d, BsdfContext::radiance(), Vec3::Z, &wl).is_empty());
    }
}
