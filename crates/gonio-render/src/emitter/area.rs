//! `area` emitter: a shape that emits radiance from its front side.
//!
//! # Mitsuba parameters
//!
//! * `radiance`: spectrum or texture (default 1; an RGB or float value is uplifted as an
//!   illuminant, × D65, by the scene reader). Evaluated at the surface's uv.
//! * One-sided: light leaves on the side the (possibly flipped, `flip_normals`) geometric normal
//!   points to; seen from behind the shape is dark.
//!
//! Sampling is done by the shape (solid-angle sampling of spheres and rectangles where the
//! geometry offers it, area sampling converted to solid angle otherwise); this file turns a
//! sampled point into a [`LightSample`] and evaluates emission at ray hits.

use super::LightSample;
use crate::texture::Texture;
use glam::{Vec2, Vec3};
use gonio_core::{SampledSpectrum, SampledWavelengths};

/// An area light on shape `shape`.
#[derive(Clone, Debug)]
pub struct AreaLight {
    /// Index of the shape in the scene.
    pub shape: usize,
    /// Emitted radiance.
    pub radiance: Texture,
    /// Surface area of the shape (world space).
    pub area: f32,
    /// Mean of the radiance over 360–830 nm and over the surface (for selection).
    pub mean_radiance: f32,
    /// Centre of a sphere bounding the shape (for selection by position).
    pub center: Vec3,
    /// Radius of that sphere.
    pub radius: f32,
}

impl AreaLight {
    /// Power estimate π·A·mean(L).
    pub fn power(&self) -> f32 {
        std::f32::consts::PI * self.area * self.mean_radiance
    }

    /// Radiance leaving a point with geometric normal `n` and texture coordinates `uv` towards
    /// `w` (a unit direction away from the surface): zero behind the surface.
    #[inline]
    pub fn le(&self, n: Vec3, uv: Vec2, w: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if n.dot(w) <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        match &self.radiance {
            Texture::Spectrum(s) => s.sample(wl),
            t => t.eval(uv).sample(wl),
        }
    }

    /// The light sample for a point `p_light` (normal `n`, uv) drawn on the shape from reference
    /// point `p_ref` with solid-angle density `pdf`.
    pub fn sample_from_point(
        &self,
        p_ref: Vec3,
        p_light: Vec3,
        n: Vec3,
        uv: Vec2,
        pdf: f32,
        wl: &SampledWavelengths,
    ) -> Option<LightSample> {
        let d = p_light - p_ref;
        let dist = d.length();
        if !(dist > 0.0) || !(pdf > 0.0) || !pdf.is_finite() {
            return None;
        }
        let wi = d / dist;
        let li = self.le(n, uv, -wi, wl);
        if li.is_black() {
            return None;
        }
        Some(LightSample {
            wi,
            dist,
            li,
            pdf,
            delta: false,
            normal: Some(n),
        })
    }
}
