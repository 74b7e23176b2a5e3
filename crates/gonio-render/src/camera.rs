//! Mitsuba's `perspective` sensor, exactly (notes: mitsuba-xml.md §1.5, §2.2).
//!
//! Camera space: +z forward, +y up, **+x left** (Mitsuba's `lookat` builds the columns
//! `[left, up, dir, origin]`). A camera-space point (x, y, z) lands at film coordinates
//! `s = (1 − x/(z·T))/2`, `t = (1 − aspect·y/(z·T))/2` with `T = tan(fov_x/2)` and
//! `aspect = width/height`; pixel = `(s·width, t·height)`. So image x grows to the camera's right
//! and image y grows downwards. Rays start on the near plane and end on the far plane.

use crate::geometry::Ray;
use crate::scene::Sensor;
use glam::{Affine3A, Vec2, Vec3};

/// A pinhole perspective camera.
#[derive(Clone, Debug)]
pub struct Camera {
    to_world: Affine3A,
    to_camera: Affine3A,
    /// tan(fov_x / 2).
    tan_half: f32,
    aspect: f32,
    width: f32,
    height: f32,
    near: f32,
    far: f32,
}

impl Camera {
    /// The camera of a scene sensor (fov already converted to the horizontal axis).
    pub fn new(sensor: &Sensor) -> Self {
        Self::from_parts(
            sensor.to_world,
            sensor.fov_x_deg,
            sensor.film.width,
            sensor.film.height,
            sensor.near_clip,
            sensor.far_clip,
        )
    }

    /// A camera from its parameters: `to_world` (camera → world), horizontal field of view in
    /// degrees, film size in pixels, near and far clip distances.
    pub fn from_parts(
        to_world: Affine3A,
        fov_x_deg: f32,
        width: u32,
        height: u32,
        near: f32,
        far: f32,
    ) -> Self {
        Self {
            to_world,
            to_camera: to_world.inverse(),
            tan_half: (fov_x_deg.to_radians() * 0.5).tan(),
            aspect: width as f32 / height as f32,
            width: width as f32,
            height: height as f32,
            near,
            far,
        }
    }

    /// The camera ray through film position `film` (in pixels: x ∈ [0, width) to the right,
    /// y ∈ [0, height) downwards; pixel (i, j) covers [i, i+1) × [j, j+1)). The ray starts on the
    /// near plane; `tmax` reaches the far plane; `d` is unit length in world space.
    pub fn generate_ray(&self, film: Vec2) -> Ray {
        let s = film.x / self.width;
        let t = film.y / self.height;
        let dc = Vec3::new(
            (1.0 - 2.0 * s) * self.tan_half,
            (1.0 - 2.0 * t) * self.tan_half / self.aspect,
            1.0,
        )
        .normalize();
        let inv_z = 1.0 / dc.z;
        let (near_t, far_t) = (self.near * inv_z, self.far * inv_z);
        // Mitsuba forbids scale in a camera's to_world but allows mirrors; normalizing after the
        // transform keeps distances in world units either way.
        let dw = self.to_world.transform_vector3(dc);
        let len = dw.length();
        let d = dw / len;
        let o = self.to_world.transform_point3(Vec3::ZERO) + dw * near_t;
        Ray {
            o,
            d,
            tmax: (far_t - near_t) * len,
        }
    }

    /// Where a world point appears on the film (pixels), or `None` behind the camera.
    pub fn project(&self, p: Vec3) -> Option<Vec2> {
        let c = self.to_camera.transform_point3(p);
        if c.z <= 0.0 {
            return None;
        }
        let s = 0.5 * (1.0 - c.x / (c.z * self.tan_half));
        let t = 0.5 * (1.0 - self.aspect * c.y / (c.z * self.tan_half));
        Some(Vec2::new(s * self.width, t * self.height))
    }

    /// Camera position (world).
    pub fn position(&self) -> Vec3 {
        self.to_world.transform_point3(Vec3::ZERO)
    }
}

/// Mitsuba's `lookat` transform: camera → world with columns `[left, up, dir, origin]`, where
/// `dir = normalize(target − origin)`, `left = normalize(up × dir)`, `up' = dir × left`.
pub fn look_at(origin: Vec3, target: Vec3, up: Vec3) -> Affine3A {
    let dir = (target - origin).normalize();
    let left = up.normalize().cross(dir).normalize();
    let new_up = dir.cross(left);
    Affine3A::from_cols(left.into(), new_up.into(), dir.into(), origin.into())
}
