//! The polarized mode of the path tracer (Mitsuba 3's `*_polarized` variants; Wilkie & Weidlich
//! 2012, "Polarised light in computer graphics"), and the `stokes` integrator's output.
//!
//! The estimators are the spectral ones, run with `W = Mueller` ([`PathTracer::li`],
//! `PathTracer::li_direct` are generic): a path's throughput is the product of the Mueller
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
//! The light subpaths for caustics ([`super::caustics`]) carry Mueller matrices in polarized
//! mode: the emitter's depolarizer D(Lₑ), then at each vertex the BSDF's importance-mode matrix
//! (light arriving along −ωᵢ, leaving along ωₒ), mapped to world and applied after what came
//! before, β_z = M_k ⋯ M₁ D(Lₑ). A camera-path vertex x joins a light vertex z as
//! β_x · f_x · T · f_z · β_z (f in radiance mode, T the sheets between them, light along the
//! connection towards x); a connection to the camera is f_z·β_z followed by the sheets towards
//! the camera, read in the sensor basis like any camera sample. The MIS weights are the
//! spectral ones (densities do not depend on polarization).
//!
//! # What the camera reads
//!
//! The image (`R`, `G`, `B`) is the intensity S0 = M₀₀ of the accumulated matrix, exactly what
//! the unpolarized renderer estimates (with the polarizing effects of the scene included).
//! With `stokes`, the first column (S0, S1, S2, S3) is also written, re-expressed from the
//! camera ray's implicit basis into Mitsuba's sensor-aligned one (beam −d, x-axis d × up), each
//! component through the same wavelength estimator into the layers `S0.R` … `S3.B`.

use super::{CameraSample, LIGHT_PATH_KEY, PathTracer};
use crate::film::Channels;
use crate::sampler::Pcg32;
use glam::{Vec2, Vec3};
use gonio_core::mueller::{Mueller, Stokes, StokesBasis, StokesComponents};
use gonio_core::sensor_response::{MAX_BANDS, SensorResponse};
use gonio_core::weight::Weight;
use gonio_core::{SampledSpectrum, SampledWavelengths};

use super::caustics::LightSubpath;
use crate::scene::IntegratorKind;

/// The channels of the `stokes` integrator, with Mitsuba 3's names: `R, G, B`, then
/// `S0.R, S0.G, S0.B, S1.R, …, S3.B`. On a spectral film the bands' names take the place of
/// `R, G, B`, in the layers too (`S0.<band>`, …): Mitsuba 3.9.1 keeps `S0.R` … there and fills
/// them with colour estimated as if the wavelengths had been drawn for colour (its `stokes`
/// integrator divides by `pdf_rgb_spectrum`), which a spectral film's wavelengths are not.
pub fn stokes_channels(response: &SensorResponse) -> Channels {
    let main = Channels::for_response(response);
    let names: Vec<&str> = main.names().iter().map(String::as_str).collect();
    let mut c = main.clone();
    for layer in ["S0", "S1", "S2", "S3"] {
        c = c.with_layer(layer, &names);
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
    /// One camera sample in polarized mode: the image is S0; with `stokes`, S0..S3 follow. With
    /// caustic light paths, the light subpath carries Mueller matrices too and its connections
    /// to the camera are splatted in the same channels.
    pub(super) fn sample_polarized(
        &self,
        sample: &mut CameraSample<'_>,
        value: &mut [f32],
        splat: &mut dyn FnMut(Vec2, &[f32]),
    ) {
        let l: Mueller = match self.kind {
            IntegratorKind::Path => {
                let mut light = LightSubpath::<Mueller>::empty();
                if self.traces_caustics() {
                    // As the spectral sample does: the same independent stream, traced first.
                    let key = sample.sampler.key();
                    let mut rng = Pcg32::new(key ^ LIGHT_PATH_KEY, key.rotate_left(29));
                    let n = value.len();
                    let mut to_film = |p: Vec2, m: Mueller, wl: &SampledWavelengths| {
                        // The beam arrives at the camera along the matrix's output direction.
                        let d = m.frames().map_or(Vec3::Z, |(_, out)| -out.forward());
                        // A colour film's 15 channels without the bands' larger buffer to clear.
                        let (mut small, mut large);
                        let buf: &mut [f32] = if n <= STOKES_RGB {
                            small = [0.0f32; STOKES_RGB];
                            &mut small[..n]
                        } else {
                            large = [0.0f32; STOKES_CHANNELS];
                            &mut large[..n]
                        };
                        self.write_channels(&m, d, wl, buf);
                        splat(p, buf);
                    };
                    self.trace_light_path(&mut rng, &mut sample.wavelengths, &mut to_film, &mut light);
                }
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
        self.write_channels(&l, sample.ray.d, &sample.wavelengths, value);
    }

    /// The channels of a path's accumulated matrix `l` seen along the camera ray `d`: S0 in the
    /// film's channels, and with `stokes` S0..S3 in the sensor basis, each in those channels.
    fn write_channels(&self, l: &Mueller, d: Vec3, wl: &SampledWavelengths, value: &mut [f32]) {
        let n = self.response.len();
        self.response.record(l.intensity(), wl, &mut value[..n]);
        if self.stokes {
            let s = stokes_at_sensor(l, d, self.sensor_up);
            for (k, sk) in s.iter().enumerate() {
                let layer = &mut value[n * (k + 1)..n * (k + 2)];
                if sk.is_finite() {
                    self.response.record(*sk, wl, layer);
                } else {
                    layer.fill(0.0);
                }
            }
        }
    }
}

/// Most channels of the `stokes` integrator: the film's and four layers of them.
const STOKES_CHANNELS: usize = 5 * MAX_BANDS;
/// Channels of the `stokes` integrator on a colour film (`R, G, B` and four layers of three).
const STOKES_RGB: usize = 15;
