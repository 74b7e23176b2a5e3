//! Delta lights: `point`, `spot` and `directional`. They illuminate only through smooth BSDF
//! lobes (a mirror or a glass pane can never connect to them) and are never hit by a ray.
//!
//! # Mitsuba parameters
//!
//! * `point`: `intensity` (W/sr, default 1), `position` or `to_world` (translation).
//! * `spot`: `intensity` (default 1), `cutoff_angle` (degrees, default 20), `beam_width`
//!   (degrees, default 3/4 of the cutoff), `to_world` (the spot shines along its local +z).
//!   Falloff (Mitsuba 3 `spot.cpp`): 1 inside the beam width, then linear in angle down to 0 at
//!   the cutoff: (cutoff − θ)/(cutoff − beam_width).
//! * `directional`: `irradiance` (W/m², default 1), `direction` (the direction light travels) or
//!   `to_world` (travelling along local +z).
//!
//! Emission spectra come uplifted from the scene reader (an RGB or float value is × D65).

use crate::texture::Texture;
use glam::{Affine3A, Vec2, Vec3};
use gonio_core::{SampledSpectrum, SampledWavelengths, Spectrum};
use std::f32::consts::PI;

/// `point`: isotropic intensity I (W/sr); irradiance I·cos/d².
#[derive(Clone, Debug)]
pub struct PointLight {
    /// World position.
    pub position: Vec3,
    /// Radiant intensity.
    pub intensity: Spectrum,
}

impl PointLight {
    /// Total power 4π·mean(I).
    pub fn power(&self) -> f32 {
        4.0 * PI * self.intensity.mean()
    }
}

/// `spot`: a cone along local +z.
#[derive(Clone, Debug)]
pub struct SpotLight {
    /// Light to world.
    pub to_world: Affine3A,
    to_local: Affine3A,
    position: Vec3,
    /// Intensity along the axis.
    pub intensity: Spectrum,
    cutoff: f32,
    beam_width: f32,
    cos_cutoff: f32,
    cos_beam_width: f32,
    /// Mitsuba's projected `texture` and tan(cutoff), its uv scale.
    texture: Option<Texture>,
    uv_factor: f32,
}

impl SpotLight {
    /// From the transform, intensity and angles in degrees (beam width clamped to the cutoff).
    pub fn new(to_world: Affine3A, intensity: Spectrum, cutoff_deg: f32, beam_width_deg: f32) -> Self {
        let cutoff = cutoff_deg.to_radians().clamp(1e-6, PI);
        let beam_width = beam_width_deg.to_radians().clamp(0.0, cutoff);
        Self {
            to_world,
            to_local: to_world.inverse(),
            position: to_world.transform_point3(Vec3::ZERO),
            intensity,
            cutoff,
            beam_width,
            cos_cutoff: cutoff.cos(),
            cos_beam_width: beam_width.cos(),
            texture: None,
            uv_factor: cutoff.tan(),
        }
    }

    /// The same light with Mitsuba's `texture` projected over the cone (`None`: untextured).
    pub fn with_texture(mut self, texture: Option<Texture>) -> Self {
        self.texture = texture;
        self
    }

    /// The texture coordinates Mitsuba's `spot` looks its texture up at for the local
    /// direction `local` (cone along +z): ½ + ½·(x, y)/(z·tan γ).
    pub fn texture_uv(&self, local: Vec3) -> Vec2 {
        Vec2::new(local.x, local.y) / (local.z * self.uv_factor) * 0.5 + Vec2::splat(0.5)
    }

    /// World position.
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// cos γ of the cutoff angle γ (no light leaves outside that cone).
    pub fn cos_cutoff(&self) -> f32 {
        self.cos_cutoff
    }

    /// Falloff towards world direction `d` (leaving the light): 1 in the beam, linear in angle to 0
    /// at the cutoff.
    pub fn falloff(&self, d: Vec3) -> f32 {
        let local = self.to_local.transform_vector3(d).normalize_or_zero();
        let cos_theta = local.z;
        if cos_theta <= self.cos_cutoff {
            return 0.0;
        }
        if cos_theta >= self.cos_beam_width {
            return 1.0;
        }
        let width = self.cutoff - self.beam_width;
        if width <= 0.0 {
            return 1.0;
        }
        ((self.cutoff - cos_theta.clamp(-1.0, 1.0).acos()) / width).clamp(0.0, 1.0)
    }

    /// Intensity towards world direction `d` (leaving the light).
    pub fn intensity_towards(&self, d: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let f = self.falloff(d);
        if f == 0.0 {
            return SampledSpectrum::ZERO;
        }
        let i = self.intensity.sample(wl) * f;
        match &self.texture {
            None => i,
            Some(t) => {
                let local = self.to_local.transform_vector3(d).normalize_or_zero();
                i * t.eval(self.texture_uv(local)).sample(wl)
            }
        }
    }

    /// Total power: mean(I)·∫ falloff dω, the integral done exactly in θ
    /// (2π[(1 − cos β)] + 2π ∫_β^γ (γ − θ)/(γ − β) sin θ dθ).
    pub fn power(&self) -> f32 {
        let (b, g) = (self.beam_width, self.cutoff);
        let mut solid = 2.0 * PI * (1.0 - b.cos());
        if g > b {
            // ∫_b^g (g − θ) sin θ dθ = [−(g − θ)cos θ − sin θ]_b^g ... = (g − b)cos b + sin b − sin g
            let integral = (g - b) * b.cos() + b.sin() - g.sin();
            solid += 2.0 * PI * integral / (g - b);
        }
        // A texture scales it by about its mean (a selection weight, not an exact power).
        let texture = self.texture.as_ref().map_or(1.0, Texture::mean);
        self.intensity.mean() * solid * texture
    }
}

/// `directional`: parallel light of irradiance E travelling along `direction`.
#[derive(Clone, Debug)]
pub struct DirectionalLight {
    /// Unit direction in which light travels.
    pub direction: Vec3,
    /// Irradiance on a surface facing the light.
    pub irradiance: Spectrum,
}

impl DirectionalLight {
    /// Power falling on a disk of the scene's bounding radius: π r²·mean(E).
    pub fn power(&self, scene_radius: f32) -> f32 {
        PI * scene_radius * scene_radius * self.irradiance.mean()
    }
}
