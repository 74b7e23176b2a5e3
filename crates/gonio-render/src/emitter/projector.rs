//! `projector`: a pinhole that projects a texture into the scene, the reciprocal of a perspective
//! camera (Mitsuba 3 `src/emitters/projector.cpp`).
//!
//! A point p in the light's frame (looking along +z, x and y as Mitsuba's camera) maps to the
//! texture's
//!
//! ```text
//!     u = ½ − x/(2 z tan(φx/2)),     v = ½ − a·y/(2 z tan(φx/2))
//! ```
//!
//! (φx the horizontal field of view, a the texture's aspect ratio, width/height); outside
//! [0, 1]² or behind the light (z ≤ 0) it is dark. The radiance arriving at p from the pinhole,
//! as a delta light's Lᵢ (the 1/d² included), is
//!
//! ```text
//!     Lᵢ = π · scale · D65(λ) · E(u, v)(λ) / (z² cos θ)
//! ```
//!
//! with θ the angle between the projector's axis and p: a plane facing the projector at z = 1
//! then receives π·scale·E·D65 wherever the texture is constant (Mitsuba's normalization, with
//! its π). The plugin decides how E's colours become spectra (a bitmap as a reflectance, a
//! colour given in place unbounded).
//!
//! The D65 factor makes a texel of colour c project light of colour c (a white texel projects
//! D65, the white of sRGB), as a colour given in place does. Mitsuba 3.9.1 applies D65 only to a
//! colour or number given in place (its `texture_d65`), not to a nested texture: its white
//! texels project an equal-energy spectrum, which renders as linear sRGB ≈ (1.21, 0.95, 0.91).
//! [`ProjectorLight::without_whitepoint`] reproduces that (the plugin's `whitepoint="mitsuba"`).

use crate::texture::Texture;
use glam::{Affine3A, Vec2, Vec3};
use gonio_core::{SampledSpectrum, SampledWavelengths, Spectrum};
use std::f32::consts::PI;

/// `projector`: a textured pinhole light.
#[derive(Clone, Debug)]
pub struct ProjectorLight {
    to_world: Affine3A,
    to_local: Affine3A,
    position: Vec3,
    axis: Vec3,
    /// E, the texture projected.
    pub irradiance: Texture,
    /// scale · D65 (Mitsuba's intensity).
    intensity: Spectrum,
    tan_half_fov_x: f32,
    aspect: f32,
    scale: f32,
}

impl ProjectorLight {
    /// From light-to-world, the texture, its scale, the horizontal field of view (degrees) and
    /// the texture's aspect ratio (width/height).
    pub fn new(to_world: Affine3A, irradiance: Texture, scale: f32, fov_x_deg: f32, aspect: f32) -> Self {
        let intensity = match Spectrum::d65() {
            Spectrum::Rgb(mut s) => {
                s.scale *= scale;
                Spectrum::Rgb(s)
            }
            other => other,
        };
        Self {
            to_world,
            to_local: to_world.inverse(),
            position: to_world.transform_point3(Vec3::ZERO),
            axis: to_world.transform_vector3(Vec3::Z).normalize_or_zero(),
            irradiance,
            intensity,
            tan_half_fov_x: (fov_x_deg.to_radians() * 0.5).tan(),
            aspect,
            scale,
        }
    }

    /// The same light with Lᵢ = π·scale·E/(z² cos θ), without D65: Mitsuba 3.9.1's weighting
    /// of a nested texture (module docs).
    pub fn without_whitepoint(mut self) -> Self {
        self.intensity = Spectrum::Constant(self.scale);
        self
    }

    /// World position of the pinhole.
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// The texture coordinates a point at light-frame position `local` receives (`None` behind
    /// the light or outside the image).
    pub fn texture_uv(&self, local: Vec3) -> Option<Vec2> {
        if !(local.z > 0.0) {
            return None;
        }
        let k = 0.5 / (local.z * self.tan_half_fov_x);
        let uv = Vec2::new(0.5 - local.x * k, 0.5 - self.aspect * local.y * k);
        ((0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y)).then_some(uv)
    }

    /// Lᵢ at world point `p` (see the module docs), zero outside the projected image.
    pub fn li_at(&self, p: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let local = self.to_local.transform_point3(p);
        let Some(uv) = self.texture_uv(local) else {
            return SampledSpectrum::ZERO;
        };
        let to_p = p - self.position;
        let dist = to_p.length();
        let cos = self.axis.dot(to_p) / dist;
        if !(cos > 0.0) {
            return SampledSpectrum::ZERO;
        }
        let e = self.irradiance.eval(uv).sample(wl);
        e * self.intensity.sample(wl) * (PI / (local.z * local.z * cos))
    }

    /// A direction leaving the pinhole, uniform over the image rectangle on the plane z = 1
    /// (x ∈ ±tan(φx/2), y ∈ ±tan(φx/2)/a, area `A_img`), and its weight I(ω)/p(ω). The plane
    /// element dA at direction θ off the axis spans dω = cos³θ·dA, so p(ω) = 1/(cos³θ·A_img),
    /// and I(ω) = Lᵢ·d² = π·scale·D65·E/cos³θ (module docs): the weight
    /// π·scale·D65·E(uv)·A_img has no angular factor left. `None` where the texture is black.
    pub fn sample_direction(&self, u: Vec2, wl: &SampledWavelengths) -> Option<(Vec3, SampledSpectrum)> {
        let t = self.tan_half_fov_x;
        let aspect = self.aspect.max(1e-6);
        let local = Vec3::new((2.0 * u.x - 1.0) * t, (2.0 * u.y - 1.0) * t / aspect, 1.0);
        let d = self.to_world.transform_vector3(local).normalize_or_zero();
        let uv = self.texture_uv(local)?;
        let area = 4.0 * t * t / aspect;
        let w = self.irradiance.eval(uv).sample(wl) * self.intensity.sample(wl) * (PI * area);
        (d != Vec3::ZERO && !w.is_black()).then_some((d, w))
    }

    /// Mean of scale·D65·E over 360–830 nm (selection weights).
    pub fn mean_emission(&self) -> f32 {
        self.intensity.mean() * self.irradiance.mean()
    }

    /// A power estimate for light selection: π·mean(scale·D65·E) times the image's area on the
    /// plane z = 1 (4 tan²(φx/2)/a), the power that plane receives.
    pub fn power(&self) -> f32 {
        let area = 4.0 * self.tan_half_fov_x * self.tan_half_fov_x / self.aspect.max(1e-6);
        PI * self.mean_emission() * area
    }
}
