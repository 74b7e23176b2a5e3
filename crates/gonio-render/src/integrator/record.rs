//! What the film records of a path: the film's channels estimated from a path's radiance at its
//! wavelengths, through the film's [`SensorResponse`] (linear sRGB, a `specfilm`'s bands, or the
//! colour of the radiance filtered by a sensor's `srf`). Camera paths write their value, light
//! paths splat theirs, both through here.

use super::PathTracer;
use glam::Vec2;
use gonio_core::color::linear_srgb_from_sampled;
use gonio_core::sensor_response::{MAX_BANDS, SensorResponse};
use gonio_core::{SampledSpectrum, SampledWavelengths};

impl PathTracer<'_> {
    /// What the film records (default linear sRGB): its channels, and the estimate of each from
    /// a path's radiance at its wavelengths.
    pub fn with_response(mut self, response: SensorResponse) -> Self {
        self.response = response;
        self
    }

    /// Writes the film's channels for radiance `l` at the wavelengths `wl` into `out`.
    #[inline]
    pub(super) fn record(&self, l: SampledSpectrum, wl: &SampledWavelengths, out: &mut [f32]) {
        self.response.record(l, wl, out);
    }

    /// Splats radiance `l` at the film position `p`, in the film's channels.
    pub(super) fn splat_radiance(
        &self,
        splat: &mut dyn FnMut(Vec2, &[f32]),
        p: Vec2,
        l: SampledSpectrum,
        wl: &SampledWavelengths,
    ) {
        match &self.response {
            // Colour, the common case, without the bands' buffer to clear.
            SensorResponse::Srgb => splat(p, &linear_srgb_from_sampled(l, wl).to_array()),
            SensorResponse::Filtered(_) => {
                let mut rgb = [0.0f32; 3];
                self.record(l, wl, &mut rgb);
                splat(p, &rgb);
            }
            SensorResponse::Bands(bands) => {
                let mut buf = [0.0f32; MAX_BANDS];
                let n = bands.len();
                bands.record(l, wl, &mut buf[..n]);
                splat(p, &buf[..n]);
            }
        }
    }
}
