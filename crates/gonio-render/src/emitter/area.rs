//! `area` emitter: a shape that emits radiance from its front side.
//!
//! # Mitsuba parameters
//!
//! * `radiance`: spectrum or texture (default 1; an RGB or float value is uplifted as an
//!   illuminant, × D65, by the scene reader). Evaluated at the surface's uv; a texture that reads
//!   the hit (`mesh_attribute`, `volume`, or one nesting them) is evaluated with the point's
//!   triangle, barycentrics and position on the light's shape made known to it
//!   ([`crate::texture::hit::with_hit_point`]), on every path that evaluates emission (camera and
//!   BSDF-sampled hits, next-event estimation's sampled points, light paths' origins).
//! * One-sided: light leaves on the side the (possibly flipped, `flip_normals`) geometric normal
//!   points to; seen from behind the shape is dark.
//!
//! # Sampling (beyond Mitsuba)
//!
//! Points are drawn by the shape ([`crate::geometry::sampling`]): solid-angle (cone) sampling of
//! spheres, spherical-rectangle sampling of rectangles that subtend more than
//! [`SPHERICAL_RECTANGLE_MIN_SOLID_ANGLE`], area sampling converted to solid angle otherwise.
//! The choice is a function of the light and the reference point only, so
//! [`AreaLight::sample_li`] and [`AreaLight::pdf_li`] (the density MIS needs for a point found by
//! BSDF sampling) always agree. This file also evaluates emission at ray hits.

use super::{LightRef, LightSample};
use crate::geometry::sampling::{ShapeSample, pdf_solid_angle, sample_area, sample_solid_angle};
use crate::geometry::{ShapeKind, SurfaceInteraction, WorldShape};
use crate::texture::Texture;
use crate::texture::hit::{HitBinding, with_hit_point};
use glam::{Vec2, Vec3};
use gonio_core::{SampledSpectrum, SampledWavelengths};
use std::sync::Arc;

/// Below this solid angle (estimated as A/d² from the light's bounding-sphere centre) a rectangle
/// light is sampled uniformly by area: spherical-rectangle sampling (Ureña et al. 2013) costs a
/// dozen transcendental functions and gains little when the light subtends a small angle, where
/// the area density is nearly proportional to solid angle anyway. Measured (`bench/RESULTS.md`):
/// 0.5 sr saves 28 % of thin-vs-thick's time at equal error and costs materials 8 % more error at
/// equal time.
pub const SPHERICAL_RECTANGLE_MIN_SOLID_ANGLE: f32 = 0.5;

/// An area density at `p` (normal `n`) seen from `r`, per unit solid angle: p_A·d²/|cos|.
#[inline]
fn area_pdf_to_solid_angle(pdf_area: f32, r: Vec3, p: Vec3, n: Vec3) -> f32 {
    let v = p - r;
    let d2 = v.length_squared();
    let cos = (n.dot(v) / d2.sqrt()).abs();
    if cos > 0.0 && d2 > 0.0 {
        pdf_area * d2 / cos
    } else {
        0.0
    }
}

/// A point of an area light's surface, as its radiance reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightPoint {
    /// The point (world).
    pub p: Vec3,
    /// Geometric normal (after `flip_normals`): light leaves on its side.
    pub n: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
    /// The mesh triangle the point lies on (0 for other shapes).
    pub prim: u32,
    /// Barycentric coordinates (b₁, b₂) on that triangle (zero for other shapes).
    pub bary: Vec2,
}

impl From<&SurfaceInteraction> for LightPoint {
    fn from(si: &SurfaceInteraction) -> Self {
        Self {
            p: si.p,
            n: si.n,
            uv: si.uv,
            prim: si.prim,
            bary: si.bary,
        }
    }
}

impl From<&ShapeSample> for LightPoint {
    fn from(s: &ShapeSample) -> Self {
        Self {
            p: s.p,
            n: s.n,
            uv: s.uv,
            prim: s.prim,
            bary: s.bary,
        }
    }
}

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
    /// The shape's mesh attributes when `radiance` reads the hit (`mesh_attribute`, `volume`).
    pub hit: Option<Arc<HitBinding>>,
}

/// Mean of a `radiance` that reads the hit (`mesh_attribute`, `volume`) over a mesh light's
/// surface, for light selection: the area-weighted mean of its values at the centroids of at
/// most [`SURFACE_MEAN_TRIANGLES`] triangles spread evenly over the mesh (a selection weight
/// moves noise between lights, never an image's expectation). `None` for other shapes, whose
/// texture mean then stands in.
pub(crate) fn surface_mean(radiance: &Texture, hit: &Arc<HitBinding>, shape: &WorldShape) -> Option<f32> {
    let ShapeKind::Mesh(mesh) = &shape.kind else {
        return None;
    };
    let n = mesh.indices.len();
    let step = n.div_ceil(SURFACE_MEAN_TRIANGLES).max(1);
    let (mut sum, mut area) = (0.0f64, 0.0f64);
    for i in (0..n).step_by(step) {
        let [a, b, c] = mesh.tri(i);
        let w = 0.5 * (b - a).cross(c - a).length() as f64;
        if !(w > 0.0) {
            continue;
        }
        let bary = Vec2::splat(1.0 / 3.0);
        let si = mesh.point(i, bary.x, bary.y, shape.face_normals);
        let value = with_hit_point(hit, si.p, i as u32, bary, || radiance.eval(si.uv).mean());
        if value.is_finite() {
            sum += w * value as f64;
            area += w;
        }
    }
    (area > 0.0).then(|| (sum / area) as f32)
}

/// Triangles [`surface_mean`] visits at most.
const SURFACE_MEAN_TRIANGLES: usize = 4096;

impl AreaLight {
    /// Power estimate π·A·mean(L).
    pub fn power(&self) -> f32 {
        std::f32::consts::PI * self.area * self.mean_radiance
    }

    /// Radiance leaving the point `at` towards `w` (a unit direction away from the surface):
    /// zero behind the surface.
    #[inline]
    pub fn le(&self, at: &LightPoint, w: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if at.n.dot(w) <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        match (&self.radiance, &self.hit) {
            (Texture::Spectrum(s), _) => s.sample(wl),
            (t, None) => t.eval(at.uv).sample(wl),
            (t, Some(b)) => with_hit_point(b, at.p, at.prim, at.bary, || t.eval(at.uv).sample(wl)),
        }
    }

    /// True when the light is sampled by area from `p` (rectangles subtending a small angle).
    /// A function of the light and the point only, so sampling and the MIS density agree.
    #[inline]
    fn by_area(&self, shape: &WorldShape, p: Vec3) -> bool {
        matches!(shape.kind, ShapeKind::Rectangle { .. })
            && self.area < SPHERICAL_RECTANGLE_MIN_SOLID_ANGLE * (self.center - p).length_squared()
    }

    /// Draws a direction towards the light (on `shape`, this light's shape) from `r`: solid-angle
    /// density, selection not included.
    pub fn sample_li(
        &self,
        shape: &WorldShape,
        r: &LightRef,
        u: Vec2,
        wl: &SampledWavelengths,
    ) -> Option<LightSample> {
        if self.by_area(shape, r.p) {
            let s = sample_area(shape, u);
            let pdf = area_pdf_to_solid_angle(s.pdf, r.p, s.p, s.n);
            self.sample_from_point(r.p, &LightPoint::from(&s), pdf, wl)
        } else {
            let s = sample_solid_angle(shape, r.p, u)?;
            self.sample_from_point(r.p, &LightPoint::from(&s), s.pdf, wl)
        }
    }

    /// The solid-angle density at `r` with which [`Self::sample_li`] produces the point of `hit`
    /// (a ray hit on `shape`, this light's shape).
    #[inline]
    pub fn pdf_li(&self, shape: &WorldShape, r: Vec3, hit: &SurfaceInteraction) -> f32 {
        if self.by_area(shape, r) {
            area_pdf_to_solid_angle(1.0 / self.area, r, hit.p, hit.n)
        } else {
            pdf_solid_angle(shape, r, hit)
        }
    }

    /// The light sample for a point `at` drawn on the shape from reference point `p_ref` with
    /// solid-angle density `pdf`.
    pub fn sample_from_point(
        &self,
        p_ref: Vec3,
        at: &LightPoint,
        pdf: f32,
        wl: &SampledWavelengths,
    ) -> Option<LightSample> {
        let d = at.p - p_ref;
        let dist = d.length();
        if !(dist > 0.0) || !(pdf > 0.0) || !pdf.is_finite() {
            return None;
        }
        let wi = d / dist;
        let li = self.le(at, -wi, wl);
        if li.is_black() {
            return None;
        }
        Some(LightSample {
            wi,
            dist,
            li,
            pdf,
            delta: false,
            normal: Some(at.n),
        })
    }
}
