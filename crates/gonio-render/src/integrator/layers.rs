//! Mitsuba 3's `aov` and `moment` integrators (`src/integrators/aov.cpp`, `moment.cpp`): nested
//! integrators whose images, and values read at the first hit, are written as film layers
//! beside the image ([`crate::film::Channels`]).
//!
//! # `aov`
//!
//! Channels, in Mitsuba 3.9.1's order (checked on its renders):
//!
//! 1. `R, G, B`: the first nested integrator's image (black with none);
//! 2. per nested integrator (in document order, unnamed ones `_arg_N`): `name.R, name.G, name.B`,
//!    its image, and `name.A`, its alpha (`path`: the ray hits a surface or sees a visible
//!    environment; `direct`, `depth`: it hits a surface);
//! 3. per nested integrator: its own layers as `name.<channel>` (a nested `stokes` gives
//!    `name.S0.R` …, a nested `moment` `name.p.X` …);
//! 4. per entry `name:type` of `aovs`, in the order written, the values at the first surface the
//!    camera ray hits (all 0 where it escapes):
//!
//! | type | channels | value |
//! |---|---|---|
//! | `depth` | `name.T` | distance t along the unit camera ray |
//! | `position` | `name.X, .Y, .Z` | hit point, world space |
//! | `uv` | `name.U, .V` | texture coordinates |
//! | `geo_normal` | `name.X, .Y, .Z` | geometric normal |
//! | `sh_normal` | `name.X, .Y, .Z` | shading normal (interpolated, before any normal or bump map) |
//! | `dp_du`, `dp_dv` | `name.X, .Y, .Z` | ∂p/∂u, ∂p/∂v |
//! | `duv_dx`, `duv_dy` | `name.U, .V` | ∂uv per pixel step in x (y), times 1/√spp |
//! | `prim_index` | `name.I` | triangle index within its mesh; 0 for analytic shapes |
//! | `shape_index` | `name.I` | index of the shape in the scene's shapes (document order) |
//!
//! `duv_dx`, `duv_dy` follow Mitsuba's `SurfaceInteraction::compute_uv_partials`: the ray
//! differentials (the directions of the camera rays one pixel to the right and one pixel down,
//! leaving from the ray's own origin on the near plane as Mitsuba's do, or for the orthographic
//! camera its shifted origins; scaled towards the ray by 1/√spp as Mitsuba's `render_sample`
//! scales them) are intersected with the tangent
//! plane at the hit, p_x − p = dp/dx, and dp/dx = ∂p/∂u·du/dx + ∂p/∂v·dv/dx is solved in the least-squares
//! sense. For a thin lens the differentials of the lens centre are added to the sampled ray.
//!
//! Where gonio differs from Mitsuba 3.9.1 on purpose: Mitsuba's `duv_dy` is 0 unless `duv_dx`
//! comes first in the list (it computes both partials only for `duv_dx`), gonio computes it
//! always; Mitsuba's `shape_index` in its scalar variants is the low bits of a pointer and its
//! `prim_index` counts a `rectangle` as two triangles, gonio writes the indices its table names.
//!
//! # `moment`
//!
//! Channels: `R, G, B` (the first nested integrator's image), then per nested integrator its own
//! layers (`name.<channel>`) and its image in CIE XYZ (`name.X, .Y, .Z`), then `m2_<c>` for every
//! one of those channels `c`: the sample's value squared. The film filters both alike, so per
//! pixel `m2_c − c²` is the (filter-weighted) variance of one sample's estimate. The nested
//! integrators trace no light subpaths for caustics (a splat lands in another pixel and has no
//! per-sample square): the estimate whose moments are written is the path tracer's alone.
//!
//! Every nested integrator evaluates the same camera sample in turn, with the sample's
//! wavelengths as drawn; their random numbers follow each other in the sample's sequence.

use super::{CameraSample, Integrator};
use crate::accel::Intersect;
use crate::camera::Camera;
use crate::film::Channels;
use crate::geometry::{Ray, SurfaceInteraction};
use crate::render::PreparedScene;
use crate::scene::{AovType, IntegratorDesc, IntegratorKind, LayersDesc, Projection};
use glam::{Vec2, Vec3};
use gonio_core::color::xyz_from_linear_srgb;

/// When a nested integrator's sample counts as covering its pixel (its `.A` channel).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum AlphaRule {
    /// The ray hits a surface, or an environment light is seen and not hidden (`path`).
    HitOrEnvironment { hide_emitters: bool },
    /// The ray hits a surface (`direct`, `depth`).
    Hit,
    /// Never (a wrapper without nested integrators).
    Never,
}

impl AlphaRule {
    fn of(desc: &IntegratorDesc) -> Self {
        if let Some(layers) = &desc.layers {
            let nested = match layers.as_ref() {
                LayersDesc::Aov { nested, .. } | LayersDesc::Moment { nested } => nested,
            };
            return nested.first().map_or(AlphaRule::Never, |n| Self::of(&n.desc));
        }
        match desc.kind {
            IntegratorKind::Path => AlphaRule::HitOrEnvironment {
                hide_emitters: desc.hide_emitters,
            },
            _ => AlphaRule::Hit,
        }
    }
}

/// A nested integrator and what the wrapper needs of it.
struct Nested<'a> {
    integrator: Box<dyn Integrator + 'a>,
    /// Its channel count (`R, G, B` and its own layers).
    len: usize,
    alpha: AlphaRule,
}

/// What the wrapper adds after the nested integrators' channels.
enum Kind {
    Aov(Vec<AovType>),
    Moment,
}

/// Mitsuba's `aov` or `moment` integrator over nested integrators (see the module docs).
pub struct Layered<'a> {
    kind: Kind,
    nested: Vec<Nested<'a>>,
    channels: Channels,
    prepared: &'a PreparedScene,
    /// 1/√spp: Mitsuba's scale of the ray differentials.
    diff_scale: f32,
    /// The camera is orthographic (its ray differentials are in the origin).
    orthographic: bool,
}

/// `desc` with the light subpaths for caustics off, at every depth of wrappers.
fn without_splats(desc: &IntegratorDesc) -> IntegratorDesc {
    let mut d = desc.clone();
    d.caustic_paths = false;
    if let Some(layers) = &mut d.layers {
        let nested = match layers.as_mut() {
            LayersDesc::Aov { nested, .. } | LayersDesc::Moment { nested } => nested,
        };
        for n in nested {
            n.desc = without_splats(&n.desc);
        }
    }
    d
}

impl<'a> Layered<'a> {
    /// The wrapper `layers` over `prepared`, for renders of `spp` samples per pixel.
    pub fn new(prepared: &'a PreparedScene, layers: &LayersDesc, spp: u32) -> Self {
        let build = |desc: &IntegratorDesc| -> Nested<'a> {
            let integrator: Box<dyn Integrator + 'a> = match &desc.layers {
                Some(inner) => Box::new(Layered::new(prepared, inner, spp)),
                None => Box::new(prepared.integrator_for(desc)),
            };
            Nested {
                len: integrator.channels().len(),
                integrator,
                alpha: AlphaRule::of(desc),
            }
        };
        let mut channels = Channels::rgb();
        let (kind, nested) = match layers {
            LayersDesc::Aov { nested, aovs } => {
                let built: Vec<Nested<'a>> = nested.iter().map(|n| build(&n.desc)).collect();
                for n in nested {
                    channels = channels.with_layer(&n.name, &["R", "G", "B", "A"]);
                }
                for (n, b) in nested.iter().zip(&built) {
                    for c in &b.integrator.channels().names()[3..] {
                        channels = channels.with_channel(&format!("{}.{c}", n.name));
                    }
                }
                for (name, ty) in aovs {
                    channels = channels.with_layer(name, ty.channels());
                }
                (Kind::Aov(aovs.iter().map(|a| a.1).collect()), built)
            }
            LayersDesc::Moment { nested } => {
                let built: Vec<Nested<'a>> = nested.iter().map(|n| build(&without_splats(&n.desc))).collect();
                let mut first = Vec::new();
                for (n, b) in nested.iter().zip(&built) {
                    for c in &b.integrator.channels().names()[3..] {
                        first.push(format!("{}.{c}", n.name));
                    }
                    for c in ["X", "Y", "Z"] {
                        first.push(format!("{}.{c}", n.name));
                    }
                }
                for c in &first {
                    channels = channels.with_channel(c);
                }
                for c in &first {
                    channels = channels.with_channel(&format!("m2_{c}"));
                }
                (Kind::Moment, built)
            }
        };
        Self {
            kind,
            nested,
            channels,
            prepared,
            diff_scale: 1.0 / (spp.max(1) as f32).sqrt(),
            orthographic: prepared.scene.sensor.projection == Projection::Orthographic,
        }
    }

    fn alpha(&self, rule: AlphaRule, ray: &Ray) -> f32 {
        let covered = match rule {
            AlphaRule::Never => false,
            AlphaRule::Hit => self.prepared.accel().occluded(ray),
            AlphaRule::HitOrEnvironment { hide_emitters } => {
                (!hide_emitters && !self.prepared.lights().infinite().is_empty())
                    || self.prepared.accel().occluded(ray)
            }
        };
        if covered { 1.0 } else { 0.0 }
    }

    /// Writes the AOV values of the first hit `si` into `out` (one value per channel).
    fn write_aovs(&self, aovs: &[AovType], sample: &CameraSample<'_>, out: &mut [f32]) {
        let si = self.prepared.accel().intersect(&sample.ray);
        let Some(si) = si else {
            out.fill(0.0);
            return;
        };
        let (duv_dx, duv_dy) = if aovs.iter().any(|a| matches!(a, AovType::DuvDx | AovType::DuvDy)) {
            self.uv_partials(&si, sample)
        } else {
            (Vec2::ZERO, Vec2::ZERO)
        };
        let mut k = 0;
        let mut put = |v: &[f32]| {
            out[k..k + v.len()].copy_from_slice(v);
            k += v.len();
        };
        for a in aovs {
            match a {
                AovType::Depth => put(&[si.t * sample.ray.d.length()]),
                AovType::Position => put(&si.p.to_array()),
                AovType::Uv => put(&si.uv.to_array()),
                AovType::GeoNormal => put(&si.n.to_array()),
                AovType::ShNormal => put(&si.shading.n.to_array()),
                AovType::DpDu => put(&si.dpdu.to_array()),
                AovType::DpDv => put(&si.dpdv.to_array()),
                AovType::DuvDx => put(&duv_dx.to_array()),
                AovType::DuvDy => put(&duv_dy.to_array()),
                AovType::PrimIndex => put(&[si.prim as f32]),
                AovType::ShapeIndex => put(&[si.shape as f32]),
            }
        }
    }

    /// (∂uv/∂x, ∂uv/∂y) at `si` from the camera's ray differentials, as Mitsuba's
    /// `compute_uv_partials` (zero where the system is degenerate).
    fn uv_partials(&self, si: &SurfaceInteraction, sample: &CameraSample<'_>) -> (Vec2, Vec2) {
        let camera: &dyn Camera = self.prepared.camera();
        let ray = &sample.ray;
        let centre = camera.generate_ray(sample.film);
        let differential = |step: Vec2| -> Option<Vec3> {
            let shifted = camera.generate_ray(sample.film + step);
            // Mitsuba's differential rays leave from the ray's own origin (on the near plane)
            // except for the orthographic camera, whose rays differ by their origins.
            let o = if self.orthographic {
                ray.o + (shifted.o - centre.o) * self.diff_scale
            } else {
                ray.o
            };
            let d = ray.d + (shifted.d - centre.d) * self.diff_scale;
            let t = (si.n.dot(si.p) - si.n.dot(o)) / si.n.dot(d);
            t.is_finite().then(|| o + d * t - si.p)
        };
        let (a00, a01, a11) = (si.dpdu.dot(si.dpdu), si.dpdu.dot(si.dpdv), si.dpdv.dot(si.dpdv));
        let inv_det = 1.0 / (a00 * a11 - a01 * a01);
        if !inv_det.is_finite() {
            return (Vec2::ZERO, Vec2::ZERO);
        }
        let solve = |dp: Option<Vec3>| -> Vec2 {
            let Some(dp) = dp else { return Vec2::ZERO };
            let (b0, b1) = (si.dpdu.dot(dp), si.dpdv.dot(dp));
            Vec2::new(a11 * b0 - a01 * b1, a00 * b1 - a01 * b0) * inv_det
        };
        (solve(differential(Vec2::X)), solve(differential(Vec2::Y)))
    }
}

impl Integrator for Layered<'_> {
    fn channels(&self) -> Channels {
        self.channels.clone()
    }

    fn splats(&self) -> bool {
        self.nested.iter().any(|n| n.integrator.splats())
    }

    fn sample(&self, sample: &mut CameraSample<'_>, value: &mut [f32], splat: &mut dyn FnMut(Vec2, &[f32])) {
        value.fill(0.0);
        let total = value.len();
        let wavelengths = sample.wavelengths;
        match &self.kind {
            Kind::Aov(aovs) => {
                let n_nested = self.nested.len();
                // Offsets: the nested images (4 each), then their own layers, then the AOVs.
                let mut extra = 3 + 4 * n_nested;
                let mut scratch = vec![0.0f32; total];
                for (k, n) in self.nested.iter().enumerate() {
                    let mut buf = vec![0.0f32; n.len];
                    sample.wavelengths = wavelengths;
                    let rgba = 3 + 4 * k;
                    let own = extra;
                    let mut to_outer = |p: Vec2, v: &[f32]| {
                        scratch.fill(0.0);
                        if k == 0 {
                            scratch[..3].copy_from_slice(&v[..3]);
                        }
                        scratch[rgba..rgba + 3].copy_from_slice(&v[..3]);
                        scratch[own..own + v.len() - 3].copy_from_slice(&v[3..]);
                        splat(p, &scratch);
                    };
                    n.integrator.sample(sample, &mut buf, &mut to_outer);
                    if k == 0 {
                        value[..3].copy_from_slice(&buf[..3]);
                    }
                    value[rgba..rgba + 3].copy_from_slice(&buf[..3]);
                    value[rgba + 3] = self.alpha(n.alpha, &sample.ray);
                    value[own..own + n.len - 3].copy_from_slice(&buf[3..]);
                    extra += n.len - 3;
                }
                self.write_aovs(aovs, sample, &mut value[extra..]);
            }
            Kind::Moment => {
                let half = (total - 3) / 2;
                let mut at = 3;
                for (k, n) in self.nested.iter().enumerate() {
                    let mut buf = vec![0.0f32; n.len];
                    sample.wavelengths = wavelengths;
                    // No splats: the nested integrators were built without light subpaths.
                    n.integrator.sample(sample, &mut buf, &mut |_, _| {});
                    if k == 0 {
                        value[..3].copy_from_slice(&buf[..3]);
                    }
                    let xyz = xyz_from_linear_srgb(Vec3::new(buf[0], buf[1], buf[2]));
                    let own = buf[3..].iter().copied().chain(xyz.to_array());
                    for v in own {
                        value[at] = v;
                        value[at + half] = v * v;
                        at += 1;
                    }
                }
            }
        }
    }
}
