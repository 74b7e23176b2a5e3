//! Directional albedo, exact for delta lobes.
//!
//! The lecture's reflectance ρ = Φ_o/Φ_i for light arriving from one direction ω_i is the
//! directional albedo
//!
//! ```text
//!     a(ω_i) = ∫ f(ω_i, ω_o) |cos θ_o| dω_o ,
//! ```
//!
//! split here into R (light that leaves on ω_i's side) and T (the other side).
//!
//! * **Delta lobes** are integrated exactly: with only one delta lobe enabled in the context, a
//!   model's `sample` returns that lobe's whole throughput with probability 1 (Mitsuba's single-lobe
//!   convention, which every gonio model follows), so one call per lobe gives its albedo. A mixture
//!   that chooses between children with ξ₁ is averaged over stratified ξ₁, which is exact for the
//!   piecewise-constant choice.
//! * **Smooth lobes** (diffuse, glossy) are estimated by importance sampling their weights on a
//!   stratified (jittered) grid of ξ₂, which is exact for a Lambertian lobe (weight = ρ for every
//!   sample) and converges as 1/N^(3/4) or better for smooth integrands.
//!
//! `gonio bsdf albedo` and the instruments' albedo curves use this function.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, TransportMode};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// Directional albedo split by side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalAlbedo {
    /// Scattering that leaves on the side of `wi`.
    pub r: SampledSpectrum,
    /// Scattering that leaves on the other side.
    pub t: SampledSpectrum,
}

/// Number of stratified ξ₁ values used to average a delta lobe's throughput.
const DELTA_STRATA: usize = 64;

/// Directional albedo of `bsdf` for light from (radiance mode: towards) `wi`, with delta lobes
/// exact and smooth lobes from `samples_sqrt²` stratified importance samples (a deterministic
/// jitter from a fixed hash, so results are reproducible).
///
/// Evaluation happens at the given wavelengths; a dispersive refraction terminating the
/// secondaries changes a copy of them only.
pub fn directional_albedo(
    bsdf: &dyn Bsdf,
    mode: TransportMode,
    wi: Vec3,
    wl: &SampledWavelengths,
    samples_sqrt: usize,
) -> DirectionalAlbedo {
    let base = BsdfContext {
        mode,
        lobes: BsdfFlags::ALL,
    };
    let mut r = SampledSpectrum::ZERO;
    let mut t = SampledSpectrum::ZERO;
    let flags = bsdf.flags();

    if flags.is_delta() {
        for lobe in [BsdfFlags::DELTA_REFLECTION, BsdfFlags::DELTA_TRANSMISSION] {
            let ctx = base.with_lobes(lobe);
            for k in 0..DELTA_STRATA {
                let u1 = (k as f32 + 0.5) / DELTA_STRATA as f32;
                let mut wl2 = *wl;
                if let Some(s) = bsdf.sample(&ctx, wi, u1, Vec2::splat(0.5), &mut wl2) {
                    let w = rescale_terminated(s.weight, wl, &wl2) / DELTA_STRATA as f32;
                    if s.wo.z * wi.z > 0.0 { r += w } else { t += w }
                }
            }
        }
    }

    if flags.has_smooth() {
        let ctx = base.with_lobes(BsdfFlags::SMOOTH | BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION);
        let n = samples_sqrt.max(1);
        let inv = 1.0 / (n * n) as f32;
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for i in 0..n {
            for j in 0..n {
                let jitter = Vec2::new(next_unit(&mut state), next_unit(&mut state));
                let u2 = (Vec2::new(i as f32, j as f32) + jitter) / n as f32;
                let u1 = next_unit(&mut state);
                let mut wl2 = *wl;
                if let Some(s) = bsdf.sample(&ctx, wi, u1, u2.min(Vec2::splat(1.0 - f32::EPSILON)), &mut wl2)
                {
                    let w = rescale_terminated(s.weight, wl, &wl2) * inv;
                    if s.wo.z * wi.z > 0.0 {
                        r += w;
                    } else {
                        t += w;
                    }
                }
            }
        }
    }
    DirectionalAlbedo { r, t }
}

/// A dispersive refraction terminates the secondary wavelengths of a *copy*; for a per-wavelength
/// albedo the hero's value stands for the terminated slots (the caller asked about fixed λ).
fn rescale_terminated(
    w: SampledSpectrum,
    before: &SampledWavelengths,
    after: &SampledWavelengths,
) -> SampledSpectrum {
    if after.secondary_terminated() && !before.secondary_terminated() {
        SampledSpectrum::splat(w[0])
    } else {
        w
    }
}

/// SplitMix64 → [0, 1): a fixed jitter sequence, so albedos are reproducible run to run.
fn next_unit(state: &mut u64) -> f32 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::Diffuse;
    use crate::spectra::Spectrum;

    #[test]
    fn lambertian_albedo_is_rho_exactly() {
        let d = Diffuse::new(Spectrum::Constant(0.3));
        let wl = SampledWavelengths::fixed(550.0);
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let a = directional_albedo(&d, TransportMode::Radiance, wi, &wl, 16);
        assert!((a.r[0] - 0.3).abs() < 1e-6, "{:?}", a.r);
        assert_eq!(a.t, SampledSpectrum::ZERO);
        // From below a one-sided Lambertian reflects nothing.
        let b = directional_albedo(&d, TransportMode::Radiance, -wi, &wl, 16);
        assert_eq!(b.r, SampledSpectrum::ZERO);
    }
}
