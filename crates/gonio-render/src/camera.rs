//! Mitsuba's `perspective` sensor, exactly (Mitsuba 3 `src/sensors/perspective.cpp`,
//! `src/render/sensor.cpp`).
//!
//! It is the one implementation ([`PerspectiveCamera`]) of the [`Camera`] trait the render loop
//! and the integrators use. A camera answers the questions of both directions of transport:
//! [`Camera::generate_ray`] for paths traced from the camera, [`Camera::connect`] (and
//! [`Camera::project`]) for light tracing, which joins a point to the camera and needs the
//! camera's importance and the density with which a camera sample would have produced the
//! direction. Mitsuba's `orthographic` ([`OrthographicCamera`]), `thinlens`
//! ([`ThinLensCamera`]) and `radiancemeter` ([`RadianceMeter`]) sensors implement the same trait;
//! they do not connect (light tracing of caustics is then off, [`Camera::connects`]).
//!
//! Camera space: +z forward, +y up, **+x left** (Mitsuba's `lookat` builds the columns
//! `[left, up, dir, origin]`). A camera-space point (x, y, z) lands at film coordinates
//! `s = (1 − x/(z·T))/2`, `t = (1 − aspect·y/(z·T))/2` with `T = tan(fov_x/2)` and
//! `aspect = width/height`; pixel = `(s·width, t·height)`. So image x grows to the camera's right
//! and image y grows downwards. Rays start on the near plane and end on the far plane.

use crate::emitter::BoundingSphere;
use crate::geometry::{Ray, WorldShape};
use crate::scene::{Projection, SensorDesc};
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

    /// [`Camera::connect`] through the lens point `u_lens` ∈ [0, 1)² (uniform on a thin lens's
    /// aperture; cameras without a lens ignore it): light tracing's connection to the sensor
    /// (Mitsuba's `Sensor::sample_direction`). The contribution of a point to the pixel at
    /// [`CameraConnection::film`] is its radiance towards the camera times
    /// `|cos θ_p|/d²·`[`CameraConnection::importance`].
    fn connect_lens(&self, p: Vec3, u_lens: Vec2) -> Option<CameraConnection> {
        let _ = u_lens;
        self.connect(p)
    }

    /// True when rays depend on a lens sample ([`Camera::generate_ray_lens`]): the render loop
    /// then draws one for each camera sample.
    fn needs_lens_sample(&self) -> bool {
        false
    }

    /// The camera ray through film position `film` and lens position `u_lens` ∈ [0, 1)² (a thin
    /// lens); cameras without a lens ignore `u_lens`.
    fn generate_ray_lens(&self, film: Vec2, u_lens: Vec2) -> Ray {
        let _ = u_lens;
        self.generate_ray(film)
    }

    /// True for a sensor whose rays do not come from the film position but from two samples of
    /// its own ([`Camera::generate_ray_sampled`]: a point and a direction on a shape).
    fn needs_ray_samples(&self) -> bool {
        false
    }

    /// The ray of a sensor that draws it from uniform samples `u_pos`, `u_dir` ∈ [0, 1)², and its
    /// weight (the factor on the radiance it brings back). Sensors that map film positions
    /// ([`Camera::needs_ray_samples`] false) give `generate_ray(film)` with weight 1.
    fn generate_ray_sampled(&self, film: Vec2, u_pos: Vec2, u_dir: Vec2) -> (Ray, f32) {
        let _ = (u_pos, u_dir);
        (self.generate_ray(film), 1.0)
    }

    /// False when [`Camera::connect`] cannot join a point to the film (the orthographic camera
    /// sees each point along one direction only; the thin lens would need a lens sample): the
    /// integrator then finds every path from the camera side.
    fn connects(&self) -> bool {
        true
    }
}

/// The camera of a scene's sensor: [`PerspectiveCamera`], [`OrthographicCamera`],
/// [`ThinLensCamera`], [`RadianceMeter`], [`IrradianceMeter`] (over `shapes[i]`, the scene's
/// shapes in world space), [`BatchCamera`] or [`DistantSensor`] (outside `bounds`, the scene's
/// bounding sphere).
///
/// # Panics
/// If an irradiance meter's shape is not in `shapes` (the scene reader sets a valid index).
pub fn from_sensor(sensor: &SensorDesc, shapes: &[WorldShape], bounds: BoundingSphere) -> Box<dyn Camera> {
    match sensor.projection {
        Projection::Distant { target_point } => Box::new(DistantSensor::new(sensor, target_point, bounds)),
        Projection::IrradianceMeter { shape } => Box::new(IrradianceMeter {
            shape: shapes[shape].clone(),
        }),
        Projection::Batch => Box::new(BatchCamera {
            cameras: sensor
                .children
                .iter()
                .map(|c| from_sensor(c, shapes, bounds))
                .collect(),
            share: (sensor.film.width / sensor.children.len().max(1) as u32) as f32,
        }),
        Projection::Perspective => Box::new(PerspectiveCamera::new(sensor)),
        Projection::Orthographic => Box::new(OrthographicCamera::new(sensor)),
        Projection::ThinLens {
            aperture_radius,
            focus_distance,
        } => Box::new(ThinLensCamera::new(sensor, aperture_radius, focus_distance)),
        Projection::RadianceMeter => Box::new(RadianceMeter::new(sensor)),
    }
}

/// Mitsuba's `radiancemeter`: every film position gives the one ray from the sensor's origin
/// along its +z, unbounded. Light tracing cannot reach a point seen along one direction
/// ([`Camera::connect`] is `None`, [`Camera::connects`] false).
#[derive(Clone, Debug)]
pub struct RadianceMeter {
    o: Vec3,
    d: Vec3,
}

impl RadianceMeter {
    /// The meter of a scene sensor: `to_world`'s origin and normalized +z.
    pub fn new(sensor: &SensorDesc) -> Self {
        Self {
            o: sensor.to_world.transform_point3(Vec3::ZERO),
            d: sensor.to_world.transform_vector3(Vec3::Z).normalize(),
        }
    }
}

impl Camera for RadianceMeter {
    fn generate_ray(&self, _film: Vec2) -> Ray {
        Ray {
            o: self.o,
            d: self.d,
            tmax: f32::INFINITY,
        }
    }

    fn project(&self, _p: Vec3) -> Option<Vec2> {
        None
    }

    fn position(&self) -> Vec3 {
        self.o
    }

    fn connect(&self, _p: Vec3) -> Option<CameraConnection> {
        None
    }

    fn connects(&self) -> bool {
        false
    }
}

/// Mitsuba's `distant`: rays along `d` from two bounding-sphere radii before their target (a
/// point, a point uniform over a shape's area, or a point uniform over the bounding sphere's
/// cross-section, drawn from the lens sample). Light tracing does not connect to it.
#[derive(Clone, Debug)]
pub struct DistantSensor {
    d: Vec3,
    to_world: Affine3A,
    target_point: Option<Vec3>,
    target_shape: Option<WorldShape>,
    bounds: BoundingSphere,
}

impl DistantSensor {
    /// The sensor of a scene's `distant` (its target shape placed in the world).
    ///
    /// # Panics
    /// If the target shape cannot be placed (the scene reader checked it).
    pub fn new(sensor: &SensorDesc, target_point: Option<Vec3>, bounds: BoundingSphere) -> Self {
        // Mitsuba: max(ε, r(1 + ε)).
        let eps = 1e-4;
        let bounds = BoundingSphere {
            center: bounds.center,
            radius: (bounds.radius * (1.0 + eps)).max(eps),
        };
        Self {
            d: sensor.to_world.transform_vector3(Vec3::Z).normalize(),
            to_world: sensor.to_world,
            target_point,
            target_shape: sensor
                .target_shape
                .as_ref()
                .map(|s| WorldShape::from_scene(&s.0, "distant target").expect("a placeable target")),
            bounds,
        }
    }
}

impl Camera for DistantSensor {
    fn generate_ray(&self, film: Vec2) -> Ray {
        self.generate_ray_lens(film, Vec2::splat(0.5))
    }

    fn needs_lens_sample(&self) -> bool {
        self.target_point.is_none()
    }

    fn generate_ray_lens(&self, _film: Vec2, u: Vec2) -> Ray {
        let r = self.bounds.radius;
        let o = if let Some(t) = self.target_point {
            t - 2.0 * r * self.d
        } else if let Some(shape) = &self.target_shape {
            crate::geometry::sampling::sample_area(shape, u).p - 2.0 * r * self.d
        } else {
            let q = gonio_core::warp::square_to_uniform_disk_concentric(u);
            let across = self.to_world.transform_vector3(Vec3::new(q.x, q.y, 0.0));
            self.bounds.center + (across - self.d) * r
        };
        Ray {
            o,
            d: self.d,
            tmax: f32::INFINITY,
        }
    }

    fn project(&self, _p: Vec3) -> Option<Vec2> {
        None
    }

    fn position(&self) -> Vec3 {
        self.bounds.center - 2.0 * self.bounds.radius * self.d
    }

    fn connect(&self, _p: Vec3) -> Option<CameraConnection> {
        None
    }

    fn connects(&self) -> bool {
        false
    }
}

/// Mitsuba's `batch`: its cameras side by side, each on `share` pixels of the film's width (a
/// film position goes to the camera whose share holds it, moved into that share). Light tracing
/// does not connect to it ([`Camera::connects`] false).
#[derive(Debug)]
pub struct BatchCamera {
    cameras: Vec<Box<dyn Camera>>,
    share: f32,
}

impl BatchCamera {
    /// The camera whose share holds `film`, and the position in that share.
    fn route(&self, film: Vec2) -> (&dyn Camera, Vec2) {
        let i = ((film.x / self.share).max(0.0) as usize).min(self.cameras.len() - 1);
        (
            self.cameras[i].as_ref(),
            film - Vec2::new(i as f32 * self.share, 0.0),
        )
    }
}

impl Camera for BatchCamera {
    fn generate_ray(&self, film: Vec2) -> Ray {
        let (c, f) = self.route(film);
        c.generate_ray(f)
    }

    fn needs_lens_sample(&self) -> bool {
        self.cameras.iter().any(|c| c.needs_lens_sample())
    }

    fn generate_ray_lens(&self, film: Vec2, u_lens: Vec2) -> Ray {
        let (c, f) = self.route(film);
        c.generate_ray_lens(f, u_lens)
    }

    fn project(&self, _p: Vec3) -> Option<Vec2> {
        None
    }

    fn position(&self) -> Vec3 {
        self.cameras[0].position()
    }

    fn connect(&self, _p: Vec3) -> Option<CameraConnection> {
        None
    }

    fn connects(&self) -> bool {
        false
    }
}

/// Mitsuba's `irradiancemeter`: a point uniform over the shape's area, a cosine-weighted
/// direction about its (shading) normal, weight π, so that a sample's mean is the irradiance
/// averaged over the shape. Light tracing does not connect to it ([`Camera::connects`] false).
#[derive(Clone, Debug)]
pub struct IrradianceMeter {
    shape: WorldShape,
}

impl Camera for IrradianceMeter {
    fn generate_ray(&self, _film: Vec2) -> Ray {
        self.generate_ray_sampled(Vec2::ZERO, Vec2::splat(0.5), Vec2::splat(0.5))
            .0
    }

    fn needs_ray_samples(&self) -> bool {
        true
    }

    fn generate_ray_sampled(&self, _film: Vec2, u_pos: Vec2, u_dir: Vec2) -> (Ray, f32) {
        let ps = crate::geometry::sampling::sample_area(&self.shape, u_pos);
        let d = gonio_core::Frame::from_normal(ps.ns)
            .to_world(gonio_core::warp::square_to_cosine_hemisphere(u_dir));
        let ray = Ray {
            o: crate::geometry::offset_ray_origin(ps.p, ps.n, d),
            d,
            tmax: f32::INFINITY,
        };
        (ray, std::f32::consts::PI)
    }

    fn project(&self, _p: Vec3) -> Option<Vec2> {
        None
    }

    fn position(&self) -> Vec3 {
        crate::geometry::sampling::sample_area(&self.shape, Vec2::splat(0.5)).p
    }

    fn connect(&self, _p: Vec3) -> Option<CameraConnection> {
        None
    }

    fn connects(&self) -> bool {
        false
    }
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

/// Mitsuba's `orthographic` sensor (`src/sensors/orthographic.cpp`): film position (s, t) ∈
/// [0, 1]² starts its ray at the camera-space point (1 − 2s, (1 − 2t)/aspect, near), mapped by
/// `to_world` (scale included), and the ray runs `far − near` along normalize(to_world · +z).
#[derive(Clone, Debug)]
pub struct OrthographicCamera {
    to_world: Affine3A,
    to_camera: Affine3A,
    /// normalize(to_world · +z).
    forward: Vec3,
    aspect: f32,
    width: f32,
    height: f32,
    near: f32,
    far: f32,
}

impl OrthographicCamera {
    /// The camera of a scene sensor.
    pub fn new(sensor: &SensorDesc) -> Self {
        Self::from_parts(
            sensor.to_world,
            sensor.film.width,
            sensor.film.height,
            sensor.near_clip,
            sensor.far_clip,
        )
    }

    /// A camera from `to_world` (camera → world, scale allowed), film size in pixels and the
    /// clip distances.
    pub fn from_parts(to_world: Affine3A, width: u32, height: u32, near: f32, far: f32) -> Self {
        Self {
            to_world,
            to_camera: to_world.inverse(),
            forward: to_world.transform_vector3(Vec3::Z).normalize(),
            aspect: width as f32 / height as f32,
            width: width as f32,
            height: height as f32,
            near,
            far,
        }
    }
}

impl Camera for OrthographicCamera {
    fn generate_ray(&self, film: Vec2) -> Ray {
        let s = film.x / self.width;
        let t = film.y / self.height;
        let pc = Vec3::new(1.0 - 2.0 * s, (1.0 - 2.0 * t) / self.aspect, self.near);
        Ray {
            o: self.to_world.transform_point3(pc),
            d: self.forward,
            tmax: self.far - self.near,
        }
    }

    fn project(&self, p: Vec3) -> Option<Vec2> {
        let c = self.to_camera.transform_point3(p);
        if c.z < self.near {
            return None;
        }
        let s = 0.5 * (1.0 - c.x);
        let t = 0.5 * (1.0 - self.aspect * c.y);
        Some(Vec2::new(s * self.width, t * self.height))
    }

    fn position(&self) -> Vec3 {
        self.to_world.transform_point3(Vec3::ZERO)
    }

    /// The film position straight along the camera axis. A pixel's value is the mean radiance
    /// over its footprint `A_pix` on the near plane (world area, `to_world`'s scale included),
    /// and each footprint point sees along the axis only, so a surface element contributes
    /// `L·|cos θ_p|·dA/A_pix`: [`CameraConnection::importance`] is `d²/A_pix` (the caller's
    /// `1/d²` cancels). `film_pdf` is 0: the direction is a delta, which the caustic light paths'
    /// MIS cannot weigh ([`Camera::connects`] stays false).
    fn connect(&self, p: Vec3) -> Option<CameraConnection> {
        let c = self.to_camera.transform_point3(p);
        if !(c.z >= self.near && c.z <= self.far) {
            return None;
        }
        let film = Vec2::new(
            0.5 * (1.0 - c.x) * self.width,
            0.5 * (1.0 - self.aspect * c.y) * self.height,
        );
        if !(film.x >= 0.0 && film.x < self.width && film.y >= 0.0 && film.y < self.height) {
            return None;
        }
        let m = self.to_world.matrix3;
        let film_area = Vec3::from(m.x_axis).cross(Vec3::from(m.y_axis)).length() * 4.0 / self.aspect;
        let pixel_area = film_area / (self.width * self.height);
        let near_point = self.to_world.transform_point3(Vec3::new(c.x, c.y, self.near));
        let dist2 = (p - near_point).length_squared().max(f32::MIN_POSITIVE);
        (pixel_area > 0.0).then_some(CameraConnection {
            film,
            near_point,
            dir: -self.forward,
            dist2,
            importance: dist2 / pixel_area,
            film_pdf: 0.0,
        })
    }

    fn connects(&self) -> bool {
        false
    }
}

/// Mitsuba's `thinlens` sensor (`src/sensors/thinlens.cpp`): the pinhole camera's ray through a
/// film position meets the plane z = `focus_distance` at F; the ray goes from the lens point
/// A = r·concentric(u_lens) (z = 0) towards F, starting on the near plane and ending on the far
/// plane (distances along the camera's z axis).
#[derive(Clone, Debug)]
pub struct ThinLensCamera {
    pinhole: PerspectiveCamera,
    aperture_radius: f32,
    focus_distance: f32,
}

impl ThinLensCamera {
    /// The camera of a scene sensor with its lens.
    pub fn new(sensor: &SensorDesc, aperture_radius: f32, focus_distance: f32) -> Self {
        Self {
            pinhole: PerspectiveCamera::new(sensor),
            aperture_radius,
            focus_distance,
        }
    }

    /// A thin lens of radius `aperture_radius` focused at `focus_distance` on the pinhole
    /// camera `pinhole` (its position is the lens centre).
    pub fn from_pinhole(pinhole: PerspectiveCamera, aperture_radius: f32, focus_distance: f32) -> Self {
        Self {
            pinhole,
            aperture_radius,
            focus_distance,
        }
    }
}

impl Camera for ThinLensCamera {
    /// The ray through the lens centre (the pinhole's).
    fn generate_ray(&self, film: Vec2) -> Ray {
        self.generate_ray_lens(film, Vec2::splat(0.5))
    }

    fn needs_lens_sample(&self) -> bool {
        true
    }

    fn generate_ray_lens(&self, film: Vec2, u_lens: Vec2) -> Ray {
        let c = &self.pinhole;
        let s = film.x / c.width;
        let t = film.y / c.height;
        // The pinhole direction with z = 1, scaled to the focus plane.
        let focus = Vec3::new(
            (1.0 - 2.0 * s) * c.tan_half,
            (1.0 - 2.0 * t) * c.tan_half / c.aspect,
            1.0,
        ) * self.focus_distance;
        let a = gonio_core::warp::square_to_uniform_disk_concentric(u_lens) * self.aperture_radius;
        let lens = Vec3::new(a.x, a.y, 0.0);
        let dc = (focus - lens).normalize();
        let inv_z = 1.0 / dc.z;
        let (near_t, far_t) = (c.near * inv_z, c.far * inv_z);
        let dw = c.to_world.transform_vector3(dc);
        let len = dw.length();
        let d = dw / len;
        let o = c.to_world.transform_point3(lens) + dw * near_t;
        Ray {
            o,
            d,
            tmax: (far_t - near_t) * len,
        }
    }

    /// Where the point appears when in focus (through the lens centre).
    fn project(&self, p: Vec3) -> Option<Vec2> {
        self.pinhole.project(p)
    }

    fn position(&self) -> Vec3 {
        self.pinhole.position()
    }

    /// Not without a lens sample ([`Camera::connect_lens`]).
    fn connect(&self, _p: Vec3) -> Option<CameraConnection> {
        None
    }

    /// The connection to the lens point A = r·concentric(`u_lens`) (uniform on the aperture,
    /// density 1/(πr²)). The ray from A through `p` meets the focus plane at F, and the film
    /// position is the pinhole's projection of F (the inverse of [`Camera::generate_ray_lens`]).
    /// A pixel's value is the mean over the pixel and the aperture of the radiance along these
    /// rays; from a fixed A, an image-plane element dA spans dω = cos³θ·dA (θ the ray's angle to
    /// the axis) exactly as for the pinhole, so with A sampled uniformly the importance is the
    /// pinhole's `1/(cos³θ·A_pix)` seen from A (the aperture's density and area cancel).
    fn connect_lens(&self, p: Vec3, u_lens: Vec2) -> Option<CameraConnection> {
        let c = &self.pinhole;
        let pc = c.to_camera.transform_point3(p);
        if !(pc.z >= c.near && pc.z <= c.far) {
            return None;
        }
        let a = gonio_core::warp::square_to_uniform_disk_concentric(u_lens) * self.aperture_radius;
        let lens = Vec3::new(a.x, a.y, 0.0);
        let v = pc - lens;
        let f = lens + v * (self.focus_distance / v.z);
        let s = 0.5 * (1.0 - f.x / (f.z * c.tan_half));
        let t = 0.5 * (1.0 - c.aspect * f.y / (f.z * c.tan_half));
        let film = Vec2::new(s * c.width, t * c.height);
        if !(film.x >= 0.0 && film.x < c.width && film.y >= 0.0 && film.y < c.height) {
            return None;
        }
        let cos = v.z / v.length();
        let plane_area = 4.0 * c.tan_half * c.tan_half / c.aspect;
        let pixel_area = plane_area / (c.width * c.height);
        let origin = c.to_world.transform_point3(lens);
        let to_p = p - origin;
        let world_dist = to_p.length();
        Some(CameraConnection {
            film,
            near_point: origin + to_p * (c.near / v.z),
            dir: -to_p / world_dist,
            dist2: world_dist * world_dist,
            importance: 1.0 / (cos * cos * cos * pixel_area),
            film_pdf: 1.0 / (cos * cos * cos * plane_area),
        })
    }

    fn connects(&self) -> bool {
        false
    }
}
