//! Mitsuba's `perspective` sensor, exactly (Mitsuba 3 `src/sensors/perspective.cpp`,
//! `src/render/sensor.cpp`).
//!
//! It is the one implementation ([`PerspectiveCamera`]) of the [`Camera`] trait the render loop
//! and the integrators use. A camera answers the questions of both directions of transport:
//! [`Camera::generate_ray`] for paths traced from the camera, [`Camera::connect`] (and
//! [`Camera::project`]) for light tracing, which joins a point to the camera and needs the
//! camera's importance and the density with which a camera sample would have produced the
//! direction. Mitsuba's `thinlens` and `orthographic` sensors fit the same trait (a thin lens
//! samples its aperture in `connect`).
//!
//! Camera space: +z forward, +y up, **+x left** (Mitsuba's `lookat` builds the columns
//! `[left, up, dir, origin]`). A camera-space point (x, y, z) lands at film coordinates
//! `s = (1 − x/(z·T))/2`, `t = (1 − aspect·y/(z·T))/2` with `T = tan(fov_x/2)` and
//! `aspect = width/height`; pixel = `(s·width, t·height)`. So image x grows to the camera's right
//! and image y grows downwards. Rays start on the near plane and end on the far plane.

use crate::geometry::Ray;
use crate::scene::SensorDesc;
use glam::{Affine3A, Vec2, Vec3};

/// A camera: rays for film positions, and the connection of world points to the film.
///
/// Film positions are in pixels: x ∈ [0, width) to the right, y ∈ [0, height) downwards; pixel
/// (i, j) covers [i, i+1) × [j, j+1).
pub trait Camera: std::fmt::Debug + Send + Sync {
    /// The camera ray through film position `film`; `d` is unit length in world space and `tmax`
    /// ends the ray where the camera stops seeing (the far clip plane).
    fn generate_ray(&self, film: Vec2) -> Ray;

    /// Where a world point appears on the film (pixels), or `None` when the camera cannot see it
    /// (behind it).
    fn project(&self, p: Vec3) -> Option<Vec2>;

    /// Camera position (world): the pinhole, or the centre of a lens.
    fn position(&self) -> Vec3;

    /// The camera's side of a light-tracing connection from world point `p` ([`CameraConnection`]:
    /// film position, importance, density), or `None` when `p` cannot be seen (behind the camera,
    /// outside the clip range, off the film).
    fn connect(&self, p: Vec3) -> Option<CameraConnection>;
}

/// The camera of a scene's sensor (today always [`PerspectiveCamera`]).
pub fn from_sensor(sensor: &SensorDesc) -> Box<dyn Camera> {
    Box::new(PerspectiveCamera::new(sensor))
}

/// A pinhole perspective camera (Mitsuba's `perspective`).
#[derive(Clone, Debug)]
pub struct PerspectiveCamera {
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

impl PerspectiveCamera {
    /// The camera of a scene sensor (fov already converted to the horizontal axis).
    pub fn new(sensor: &SensorDesc) -> Self {
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
}

impl Camera for PerspectiveCamera {
    /// The camera ray through film position `film` (in pixels: x ∈ [0, width) to the right,
    /// y ∈ [0, height) downwards; pixel (i, j) covers [i, i+1) × [j, j+1)). The ray starts on the
    /// near plane; `tmax` reaches the far plane; `d` is unit length in world space.
    fn generate_ray(&self, film: Vec2) -> Ray {
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
    fn project(&self, p: Vec3) -> Option<Vec2> {
        let c = self.to_camera.transform_point3(p);
        if c.z <= 0.0 {
            return None;
        }
        let s = 0.5 * (1.0 - c.x / (c.z * self.tan_half));
        let t = 0.5 * (1.0 - self.aspect * c.y / (c.z * self.tan_half));
        Some(Vec2::new(s * self.width, t * self.height))
    }

    /// Camera position (world).
    fn position(&self) -> Vec3 {
        self.to_world.transform_point3(Vec3::ZERO)
    }

    /// The camera's side of a connection from a world point `p` (light tracing), or `None` when
    /// `p` is behind the camera, outside the near–far range or off the film.
    ///
    /// A pixel's value is the mean radiance over its footprint on the image plane at distance 1
    /// (area `A_pix = A/(W·H)`, `A = 4·tan²(fov_x/2)/aspect`). An image-plane element `du` sees
    /// the solid angle `cos³θ·du` (θ off the optical axis) and a surface element `dA` at distance
    /// `d` the solid angle `|cos θ_p|·dA/d²`, so
    /// `∫_pixel L du / A_pix = ∫ L·|cos θ_p| / (d²·cos³θ·A_pix) dA`. The factor
    /// [`CameraConnection::importance`] is `1/(cos³θ·A_pix)`; the caller multiplies by
    /// `|cos θ_p|/d²` and by its path throughput.
    fn connect(&self, p: Vec3) -> Option<CameraConnection> {
        let c = self.to_camera.transform_point3(p);
        if !(c.z >= self.near && c.z <= self.far) {
            return None;
        }
        let s = 0.5 * (1.0 - c.x / (c.z * self.tan_half));
        let t = 0.5 * (1.0 - self.aspect * c.y / (c.z * self.tan_half));
        let film = Vec2::new(s * self.width, t * self.height);
        if !(film.x >= 0.0 && film.x < self.width && film.y >= 0.0 && film.y < self.height) {
            return None;
        }
        let dist = c.length();
        let cos = c.z / dist;
        let plane_area = 4.0 * self.tan_half * self.tan_half / self.aspect;
        let pixel_area = plane_area / (self.width * self.height);
        // The camera ray through `p` starts on the near plane: occluders only count beyond it.
        let origin = self.position();
        let to_p = p - origin;
        let world_dist = to_p.length();
        let near_point = origin + to_p * (self.near / c.z);
        Some(CameraConnection {
            film,
            near_point,
            dir: -to_p / world_dist,
            dist2: world_dist * world_dist,
            importance: 1.0 / (cos * cos * cos * pixel_area),
            film_pdf: 1.0 / (cos * cos * cos * plane_area),
        })
    }
}

/// See [`Camera::connect`].
#[derive(Clone, Copy, Debug)]
pub struct CameraConnection {
    /// Film position of the point (pixels).
    pub film: Vec2,
    /// Where the camera ray through the point starts (on the near plane).
    pub near_point: Vec3,
    /// Unit direction from the point towards the camera.
    pub dir: Vec3,
    /// Squared distance from the point to the camera.
    pub dist2: f32,
    /// `1/(cos³θ·A_pix)`: the pinhole's importance per unit pixel value.
    pub importance: f32,
    /// `1/(cos³θ·A)`: the density per unit solid angle of the direction towards the point when
    /// the film position is uniform over the whole film (one camera sample anywhere).
    pub film_pdf: f32,
}

/// Mitsuba's `lookat` transform: camera → world with columns `[left, up, dir, origin]`, where
/// `dir = normalize(target − origin)`, `left = normalize(up × dir)`, `up' = dir × left`.
pub fn look_at(origin: Vec3, target: Vec3, up: Vec3) -> Affine3A {
    let dir = (target - origin).normalize();
    let left = up.normalize().cross(dir).normalize();
    let new_up = dir.cross(left);
    Affine3A::from_cols(left.into(), new_up.into(), dir.into(), origin.into())
}
