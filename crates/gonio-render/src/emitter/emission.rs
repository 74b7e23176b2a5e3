//! Emission sampling: a ray leaving a light, with the weight `Lₑ·|cos θ|/(p_pos·p_dir)` that
//! light tracing starts from (Mitsuba 3's `Emitter::sample_ray`, pbrt-v4's `Light::SampleLe`).
//!
//! The expected weight of [`Light::sample_ray`] is the light's emitted power at the sampled
//! wavelengths, `Φ = ∫∫ Lₑ |cos θ| dA dω` (for delta lights `∫ I dω`), the quantity its tests
//! check against closed forms:
//!
//! | light | position | direction | weight |
//! |---|---|---|---|
//! | `area` | uniform on the shape (p = 1/A) | cosine about the front normal | π·A·Lₑ(uv, ω) |
//! | `directionalarea` | uniform on the shape (p = 1/A) | the normal there | A·L(uv) |
//! | `point` | the point | uniform sphere | 4π·I |
//! | `spot` | the apex | uniform in the cutoff cone | 2π(1 − cos γ)·I·falloff·texture |
//! | `projector` | the pinhole | uniform on the image rectangle at z = 1 | π·scale·D65·E(uv)·A_img |
//! | `directional` | uniform on the disk of the scene's bounding sphere, facing the light | the light's | π r²·E |
//! | `constant` | the same disk, facing the direction | uniform sphere | 4π·π r²·L |
//! | `envmap` | the same disk | ∝ luminance·sin θ ([`EnvMapLight::sample_dir`]) | π r²·L(ω)/p(ω) |
//! | `sunsky` | the same disk | sky table or sun cone ([`super::SunSkyLight::sample_dir_le`]) | π r²·L(ω)/p(ω) |
//!
//! Lights at infinity enter the scene through the disk of its bounding sphere perpendicular to
//! the direction, a radius `r` in front of the centre, as Mitsuba's `constant`, `envmap` and
//! `directional` do: every ray that can meet the scene crosses it, so their "power" is the flux
//! through that disk.

use super::{BoundingSphere, EnvMapLight, Light};
use crate::geometry::sampling::sample_area;
use crate::geometry::{Ray, WorldShape, offset_ray_origin};
use glam::{Vec2, Vec3};
use gonio_core::frame::Frame;
use gonio_core::{SampledSpectrum, SampledWavelengths, warp};
use std::f32::consts::PI;

/// A ray leaving a light ([`Light::sample_ray`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmittedRay {
    /// Origin (offset off an area light's surface) and unit direction.
    pub ray: Ray,
    /// `Lₑ·|cos θ|/(p_pos·p_dir)` (intensity over the direction density for delta positions);
    /// light selection not included.
    pub weight: SampledSpectrum,
}

/// A point on the disk of `bounds` facing unit direction `d` (rays travel along `d`), a radius
/// behind the centre, and the disk's area.
fn disk_origin(bounds: &BoundingSphere, d: Vec3, u: Vec2) -> (Vec3, f32) {
    let r = bounds.radius.max(1e-4);
    let o = warp::square_to_uniform_disk_concentric(u) * r;
    let f = Frame::from_normal(d);
    (bounds.center + f.s * o.x + f.t * o.y - d * r, PI * r * r)
}

impl Light {
    /// Draws a ray leaving the light: `u_pos` places its origin, `u_dir` its direction (see the
    /// module docs for each light's densities). `shapes` are the scene's shapes in the world
    /// (area lights sample theirs), `bounds` the scene's bounding sphere (lights at infinity
    /// enter through its disk). `None` when the sample carries no light.
    pub fn sample_ray(
        &self,
        shapes: &[WorldShape],
        bounds: &BoundingSphere,
        u_pos: Vec2,
        u_dir: Vec2,
        wl: &SampledWavelengths,
    ) -> Option<EmittedRay> {
        let (ray, weight) = match self {
            Light::Area(a) => {
                let shape = shapes.get(a.shape)?;
                let s = sample_area(shape, u_pos);
                let local = warp::square_to_cosine_hemisphere(u_dir);
                let d = Frame::from_normal(s.n).to_world(local).normalize();
                if !(s.pdf > 0.0 && local.z > 0.0) {
                    return None;
                }
                // Lₑ·cos/(p_A·cos/π).
                let le = a.le(&(&s).into(), d, wl);
                (Ray::new(offset_ray_origin(s.p, s.n, d), d), le * (PI / s.pdf))
            }
            Light::DirectionalArea(l) => l.sample_ray(shapes.get(l.surface.shape)?, u_pos, wl)?,
            Light::Point(l) => {
                let d = warp::square_to_uniform_sphere(u_dir);
                (Ray::new(l.position, d), l.intensity.sample(wl) * (4.0 * PI))
            }
            Light::Spot(l) => {
                let cos_cutoff = l.cos_cutoff();
                let cos = 1.0 - u_dir.x * (1.0 - cos_cutoff);
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let (sp, cp) = (2.0 * PI * u_dir.y).sin_cos();
                let local = Vec3::new(sin * cp, sin * sp, cos);
                let d = l.to_world.transform_vector3(local).normalize_or_zero();
                let solid = 2.0 * PI * (1.0 - cos_cutoff);
                (Ray::new(l.position(), d), l.intensity_towards(d, wl) * solid)
            }
            Light::Projector(l) => {
                let (d, w) = l.sample_direction(u_dir, wl)?;
                (Ray::new(l.position(), d), w)
            }
            Light::Directional(l) => {
                let (o, area) = disk_origin(bounds, l.direction, u_pos);
                (Ray::new(o, l.direction), l.irradiance.sample(wl) * area)
            }
            Light::Constant(c) => {
                let d = warp::square_to_uniform_sphere(u_dir);
                let (o, area) = disk_origin(bounds, d, u_pos);
                (Ray::new(o, d), c.le(wl) * (4.0 * PI * area))
            }
            Light::EnvMap(e) => Self::envmap_ray(e, bounds, u_pos, u_dir, wl)?,
            Light::SunSky(s) => {
                // `wi` points towards the light; the ray travels the other way.
                let (wi, pdf, le) = s.sample_dir_le(u_dir, wl)?;
                let (o, area) = disk_origin(bounds, -wi, u_pos);
                (Ray::new(o, -wi), le * (area / pdf))
            }
        };
        (ray.d.is_normalized() && weight.is_finite() && !weight.is_black())
            .then_some(EmittedRay { ray, weight })
    }

    fn envmap_ray(
        e: &EnvMapLight,
        bounds: &BoundingSphere,
        u_pos: Vec2,
        u_dir: Vec2,
        wl: &SampledWavelengths,
    ) -> Option<(Ray, SampledSpectrum)> {
        // `wi` points towards the light; the ray travels the other way.
        let (wi, pdf) = e.sample_dir(u_dir)?;
        let (o, area) = disk_origin(bounds, -wi, u_pos);
        Some((Ray::new(o, -wi), e.le(wi, wl) * (area / pdf)))
    }
}
