//! The polarized mode of the path tracer (Mitsuba 3's `*_polarized` variants; Wilkie & Weidlich
//! 2012, "Polarised light in computer graphics"), and the `stokes` integrator's output.
//!
//! The estimators are the spectral ones, run with `W = Mueller` ([`PathTracer::li`],
//! [`PathTracer::li_direct`] are generic): a path's throughput is the product of the Mueller
//! matrices of its vertices in path order, β = M₁ M₂ ⋯ Mₖ (M₁ nearest the camera), and the
//! light that reaches the camera is β·s_e for an emitter's Stokes vector s_e. Emitters are
//! unpolarized, s_e = (Lₑ, 0, 0, 0), so a path's contribution enters as β·D(Lₑ) with the
//! depolarizer D, and the measured Stokes vector is the first column of the accumulated matrix.
//!
//! # Frames
//!
//! A BSDF answers in its local shading frame, from the implicit basis of the light's incoming
//! beam to that of its outgoing one ([`gonio_core::bsdf::light_directions`]). At each vertex the
//! matrix is mapped to world space and re-expressed in the implicit world bases of the same two
//! beams ([`gonio_core::weight::Weight::local_to_world`]). The beam leaving vertex k+1 towards
//! vertex k is the beam arriving at k, so Mₖ's input basis is Mₖ₊₁'s output basis and every
//! product type-checks its frames (a mismatch panics in debug builds). The same holds for
//! next-event estimation (β·f·T·D(Lᵢ): the source, then the sheets the shadow ray crosses
//! (`null_transmission` for light along the shadow ray towards the vertex, sheets nearest the
//! vertex first in the product), then f), for the BSDF-sampled emission and MIS (the densities
//! are the spectral ones: polarization changes weights, never densities), and for the straight
//! passes through sheets.
//!
//! The light subpaths for caustics are spectral and are not traced in polarized mode: their
//! paths are left to the path tracer alone (weight 1), unbiased and noisier.
//!
//! # What the camera reads
//!
//! The image (`R`, `G`, `B`) is the intensity S0 = M₀₀ of the accumulated matrix, exactly what
//! the unpolarized renderer estimates (with the polarizing effects of the scene included).
//! With `stokes`, the first column (S0, S1, S2, S3) is also written, re-expressed from the
//! camera ray's implicit basis into Mitsuba's sensor-aligned one (beam −d, x-axis d × up), each
//! component through the same wavelength estimator into the layers `S0.R` … `S3.B`.

use super::{CameraSample, PathTracer};
use crate::film::Channels;
use glam::Vec3;
use gonio_core::SampledSpectrum;
use gonio_core::color::linear_srgb_from_sampled;
use gonio_core::mueller::{Mueller, Stokes, StokesBasis, StokesComponents};
use gonio_core::weight::Weight;

use super::caustics::LightSubpath;
use crate::scene::IntegratorKind;

/// The channels of the `stokes` integrator, with Mitsuba 3's names: `R, G, B`, then
/// `S0.R, S0.G, S0.B, S1.R, …, S3.B`.
pub fn stokes_channels() -> Channels {
    let mut c = Channels::rgb();
    for layer in ["S0", "S1", "S2", "S3"] {
        c = c.with_layer(layer, &["R", "G", "B"]);
    }
    c
}

/// The Stokes vector measured along the camera ray `d` from a path's accumulated matrix `l`
/// (whose output basis is the implicit basis of −d), in Mitsuba's sensor basis: beam −d,
/// x-axis normalize(d × up). Where d ∥ up the implicit basis is kept.
pub fn stokes_at_sensor(l: &Mueller, d: Vec3, up: Vec3) -> StokesComponents {
    let s = [l.get(0, 0), l.get(1, 0), l.get(2, 0), l.get(3, 0)];
    let Some((_, out)) = l.frames() else {
        // A frame-free product (depolarizers, circular elements): S1 = S2 = 0 in every basis.
        return s;
    };
    let d = d.normalize();
    let x = d.cross(up);
    if !(x.length_squared() > 1e-12) {
        return s;
    }
    // The output basis is the implicit basis of −d (up to round-off).
    Stokes::new(s, out)
        .in_basis(StokesBasis::new(-d, x.normalize()))
        .components()
}

impl PathTracer<'_> {
    /// One camera sample in polarized mode: the image is S0; with `stokes`, S0..S3 follow.
    pub(super) fn sample_polarized(&self, sample: &mut CameraSample<'_>, value: &mut [f32]) {
        let l: Mueller = match self.kind {
            IntegratorKind::Path => {
                let light = LightSubpath::new();
                self.li(sample.ray, &mut sample.sampler, &mut sample.wavelengths, &light)
            }
            IntegratorKind::Direct {
                emitter_samples,
                bsdf_samples,
            } => self.li_direct(sample, emitter_samples, bsdf_samples),
            IntegratorKind::Depth => Mueller::from_spectrum(SampledSpectrum::splat(self.depth(&sample.ray))),
            // Never polarized (`PathTracer::new`).
            IntegratorKind::PTracer => Mueller::from_spectrum(SampledSpectrum::ZERO),
        };
        let wl = &sample.wavelengths;
        value[..3].copy_from_slice(&linear_srgb_from_sampled(l.intensity(), wl).to_array());
        if self.stokes {
            let s = stokes_at_sensor(&l, sample.ray.d, self.sensor_up);
            for (k, sk) in s.iter().enumerate() {
                let rgb = if sk.is_finite() {
                    linear_srgb_from_sampled(*sk, wl)
                } else {
                    Vec3::ZERO
                };
                value[3 + 3 * k..6 + 3 * k].copy_from_slice(&rgb.to_array());
            }
        }
    }
}
