//! Caustic light paths (beyond Mitsuba): light subpaths through specular chains, connected to
//! the camera and to every vertex of the camera path, combined with the path tracer by multiple
//! importance sampling.
//!
//! A path tracer finds the light that reaches a smooth surface through a chain of delta
//! scatterings (the ceiling lit by the light's reflection in a mirror sphere, the bright spot
//! under a glass ball: `L S⁺ D` in Heckbert's notation) only when a BSDF sample happens to leave
//! through the chain and hit the light. With a small light that is rare and each find is a
//! firefly, wherever the surface is seen: directly (`L S⁺ D E`), lighting other surfaces
//! (`L S⁺ D D⁺ E`), or seen through the glass by yet another surface (`L S⁺ D S⁺ D E`, the floor
//! caustic lighting the room through the ball). Traced from the light the same paths are easy:
//! emit, follow the delta bounces, and connect a smooth vertex to the camera or to a vertex of
//! the camera path (Veach 1997 ch. 10: a subset of bidirectional path tracing's strategies).
//!
//! # Light subpaths and the two strategies per path
//!
//! A light subpath starts on an area light and alternates: one or more delta vertices, then a
//! smooth vertex, then again one or more delta vertices, … (`L (S⁺ D)⁺`; two smooth vertices in
//! a row end it: such paths are the path tracer's). Every smooth vertex `z` it reaches is kept.
//! A full path `… x → z → (S⁺ D)* S⁺ → l`, where `x` is a smooth vertex of the camera path or the
//! camera itself, is then produced by exactly two strategies:
//!
//! 1. the path tracer ([`super::PathTracer::li`]): `x` samples the direction to `z`, and so on
//!    until the light is hit;
//! 2. the connection: the light subpath `l → … → z` is traced from the light and `z` is joined
//!    to `x`.
//!
//! It cannot have a second connection: `z` is the smooth vertex nearest the light whose
//! neighbour on the camera side is smooth (or the camera), and the light subpath of any vertex
//! nearer the camera would contain two smooth vertices in a row. Paths whose last segment
//! leaves a smooth vertex are next-event estimation's and the path tracer's, as before.
//!
//! # The MIS ratio from local quantities
//!
//! Per unit area at `z`, at the smooth vertices `d` after it and at `l` (the delta vertices are
//! fixed by their neighbours), the two densities share every factor but these:
//!
//! * path tracer: `p_x(z) · p_z(ω_z) · Π_d p_d(ω_d) · Π_chains |dω_a/dA_b|`,
//! * connection: `p_sel·p_A(l) · (cos θ_l/π) · Π_d p_d,rev · Π_chains |dω_b/dA_a|`,
//!
//! with `p_x(z)` the density of `z` from `x` per unit area (the BSDF pdf at `x` times
//! `|cos θ_z|/d²`; from the camera, the film density `1/(cos³θ·A)` of one uniformly placed camera
//! sample times the same: light subpaths and camera samples are equally many), `p_v` the BSDF pdf
//! of the direction taken towards the light, `p_d,rev` the light tracer's pdf of the reverse
//! direction, `p_sel` the light's selection probability and `p_A = 1/area`; each chain runs from
//! its smooth end `a` on the camera side to `b` on the light side. The delta-lobe choices have the
//! same probability both ways for all our BSDFs (Fresnel of a mirror or refraction pair is
//! symmetric) and cancel. Conservation of étendue through a chain,
//! `η_a²·cos θ_a·|dω_a/dA_b| = η_b²·cos θ_b·|dω_b/dA_a|`, turns the Jacobians into cosines, so
//!
//! `r = p₁/p₂ = p_x(z)·p_z(ω_z) / |cos θ_z| · Π_d [p_d·|cos θ_d,cam| / (p_d,rev·|cos θ_d,light|)] · π·(η_l/η_z)² / (p_sel·p_A)`
//!
//! (geometric cosines of the directions towards each neighbour). The path tracer accumulates it
//! while walking away from the camera ([`ChainState`]), the light tracer while walking towards it
//! ([`LightVertex`]). The power heuristic gives the path tracer `r²/(1 + r²)` and the connection
//! `1/(1 + r²)`. Where `x` sampled a delta lobe there is no connection and the path tracer keeps
//! weight 1. Where the chain next to the light is all refraction, refracted next-event estimation
//! (`integrator/refracted.rs`) is a third strategy for the same path; the three share it by the
//! power heuristic (`refracted::shares`), from `r` and that strategy's ratio `s = p₃/p₁` at the
//! smooth vertex nearest the light.
//!
//! Both sides count the same vertices: with `thin_shadows` a straight pass through a
//! `thindielectric` sheet is not a vertex (connections cross sheets with their transmittance, as
//! shadow rays do); without it, it is a delta vertex on both sides. `max_depth` counts the
//! segments of the whole path on both sides, and light subpaths with more than [`MAX_CHAIN`]
//! delta vertices are the path tracer's alone.
//!
//! # Estimators
//!
//! A light subpath starts on an area light chosen by power, at a uniformly sampled point in a
//! cosine-distributed direction: `β = Lₑ·π/(p_sel·p_A)`. Each vertex multiplies β by the sampled
//! weight in importance mode (no η² scaling: that belongs to radiance transport) and by the
//! shading-normal correction `|ωᵢ·n_s||ωₒ·n_g| / (|ωᵢ·n_g||ωₒ·n_s|)` (Veach 1997 §5.3). A kept
//! vertex `z` is connected to the camera: the contribution to the pixel under it is
//!
//! `β · f_z(ω_cam, ω_in) · |ω_in·n_s|/|ω_in·n_g| · |ω_cam·n_g| / d² · 1/(cos³θ·A_pix) · V · w`,
//!
//! with `f` evaluated exactly as the path tracer would (radiance mode, `wi` towards the camera),
//! `1/(cos³θ·A_pix)` the pinhole's importance ([`Camera::connect`](crate::camera::Camera::connect)), `V` the visibility (or sheet
//! transmittance) and `w` the MIS weight; the render divides the splatted sums by the number of
//! light subpaths. A camera-path vertex `x` joins each kept `z` with
//!
//! `β_x · f_x(ωᵢ, ω_xz) · |ω_xz·n_s,x| · |ω_xz·n_g,z| / d² · f_z(−ω_xz, ω_in) · |ω_in·n_s,z|/|ω_in·n_g,z| · β_z · V · w`.
//!
//! The light subpath uses the camera sample's wavelengths; a dispersive refraction in it leaves
//! only the hero wavelength alive for the whole sample.

mod trace;

use super::PathTracer;
use super::refracted::shares;
use crate::emitter::{AreaLight, BoundingSphere, Distribution1D, Light, Lights};
use crate::geometry::{ShapeKind, SurfaceInteraction, WorldShape, spawn_ray_between};
use crate::material::Material;
use arrayvec::ArrayVec;
use glam::{Vec2, Vec3};
use gonio_core::bsdfs::SurfaceBsdf;
use gonio_core::frame::Frame;
use gonio_core::mueller::Mueller;
use gonio_core::weight::{BsdfWeight, Weight};
use gonio_core::{BsdfContext, BsdfSample, SampledSpectrum, SampledWavelengths, warp};

/// Most delta vertices a light subpath crosses (longer ones are the path tracer's alone).
pub const MAX_CHAIN: u32 = 8;

/// The area lights light paths start from, chosen by emitted power.
#[derive(Clone, Debug)]
pub struct EmissionSampler {
    /// Light index (in [`Lights::lights`]) of each area light.
    lights: Vec<usize>,
    selection: Distribution1D,
    /// Selection probability by light index (zero for other lights).
    pmf: Vec<f32>,
    /// Per material: true when it has a delta lobe (a light subpath can only go on through one).
    delta: Vec<bool>,
    /// Where emitted directions are aimed.
    targets: DeltaTargets,
    /// Fraction of camera samples that trace a light subpath.
    rate: f32,
}

impl EmissionSampler {
    /// The sampler, or `None` when light tracing cannot contribute: no area light with power,
    /// or no material with a delta lobe on any shape.
    pub fn new(
        lights: &Lights,
        materials: &[Material],
        shape_material: &[usize],
        shapes: &[WorldShape],
    ) -> Option<Self> {
        let delta: Vec<bool> = materials.iter().map(|m| m.flags().is_delta()).collect();
        let any_delta = shape_material
            .iter()
            .any(|&m| delta.get(m).copied().unwrap_or(false));
        if !any_delta {
            return None;
        }
        let (index, power): (Vec<usize>, Vec<f32>) = lights
            .lights()
            .iter()
            .enumerate()
            .filter_map(|(i, l)| match l {
                Light::Area(a) => Some((i, a.power())),
                _ => None,
            })
            .unzip();
        if !(power.iter().sum::<f32>() > 0.0) {
            return None;
        }
        let selection = Distribution1D::new(&power);
        let mut pmf = vec![0.0; lights.lights().len()];
        for (k, &i) in index.iter().enumerate() {
            pmf[i] = selection.pmf(k);
        }
        let targets = DeltaTargets::new(shapes, shape_material, &delta);
        Some(Self {
            lights: index,
            selection,
            pmf,
            delta,
            targets,
            rate: LIGHT_PATH_RATE,
        })
    }

    /// `p_sel·p_A·p_ω(ω)/|cos θ_l|` for direction `w` leaving point `p` (geometric normal `n`)
    /// of light `li`: the light-side density of the MIS ratio (see the module documentation);
    /// zero for a light that is never chosen or a direction never emitted.
    fn light_density(&self, li: usize, area: &AreaLight, p: Vec3, n: Vec3, w: Vec3) -> f32 {
        let p_sel = self.pmf.get(li).copied().unwrap_or(0.0) * self.rate;
        let cos = n.dot(w);
        if !(area.area > 0.0 && cos > 0.0) {
            return 0.0;
        }
        p_sel / area.area * self.targets.pdf(p, n, w) / cos
    }
}

/// Fraction of camera samples that also trace a light subpath. Aimed at the delta shapes, most
/// light subpaths yield vertices, and each vertex costs a connection (a shadow ray and two BSDF
/// evaluations) at every smooth vertex of the camera path. Measured at 64 spp (render time ×
/// relMSE against the Mitsuba references, lower is better; path tracing alone = 1): cornell-spheres
/// 0.23 at 0.1, 0.24 at 0.25, 0.34 at 1; materials 0.87 / 0.99; thin-vs-thick 0.96 / 0.98.
pub const LIGHT_PATH_RATE: f32 = 0.1;

/// Most shapes with a delta lobe that emitted directions are aimed at; with more, light subpaths
/// leave in a cosine distribution.
pub const MAX_TARGETS: usize = 16;

/// The bounding spheres of the shapes with a delta lobe. A light subpath only counts when its
/// first hit is such a shape, so it is emitted towards one: from a light point `p`, a target is
/// chosen with probability ∝ its cone's solid angle times an upper bound of the emission cosine
/// over the cone, and the direction uniformly inside the cone. Every direction that can hit a
/// target has a positive density (the cones cover the shapes), so the estimator keeps its full
/// support; the density is the mixture over all cones containing the direction. When `p` lies
/// inside a target's sphere, or there are no or too many targets, the direction is
/// cosine-distributed instead. Both are functions of `p`, so the path tracer evaluates the same
/// density for the MIS ratio.
#[derive(Clone, Debug, Default)]
struct DeltaTargets {
    spheres: Vec<(Vec3, f32)>,
}

/// A target cone from a point: unit axis, cos of the half-angle, 1 − that cos, selection weight.
#[derive(Clone, Copy, Debug, Default)]
struct Cone {
    axis: Vec3,
    cos_max: f32,
    one_minus_cos: f32,
    weight: f32,
}

impl DeltaTargets {
    fn new(shapes: &[WorldShape], shape_material: &[usize], delta: &[bool]) -> Self {
        let mut spheres = Vec::new();
        for (shape, &m) in shapes.iter().zip(shape_material) {
            if !delta.get(m).copied().unwrap_or(false) {
                continue;
            }
            if spheres.len() == MAX_TARGETS {
                return Self::default();
            }
            let sphere = match &shape.kind {
                ShapeKind::Sphere { center, radius, .. } => (*center, radius.abs()),
                _ => {
                    let b = BoundingSphere::of_shapes([shape]);
                    // A little margin: the surface may touch the box.
                    (b.center, b.radius * 1.001)
                }
            };
            spheres.push(sphere);
        }
        Self { spheres }
    }

    /// The cones seen from `p` (normal `n`) and their total weight; `None` when directions are
    /// cosine-distributed from `p`.
    fn cones(&self, p: Vec3, n: Vec3) -> Option<([Cone; MAX_TARGETS], f32)> {
        if self.spheres.is_empty() {
            return None;
        }
        let mut cones = [Cone::default(); MAX_TARGETS];
        let mut total = 0.0;
        for (cone, &(c, r)) in cones.iter_mut().zip(&self.spheres) {
            let v = c - p;
            let d2 = v.length_squared();
            if !(d2 > r * r) {
                return None;
            }
            let d = d2.sqrt();
            let axis = v / d;
            let sin2 = (r * r / d2).min(1.0);
            let cos_max = (1.0 - sin2).max(0.0).sqrt();
            // 1 − cos α without cancellation.
            let one_minus_cos = sin2 / (1.0 + cos_max);
            // Upper bound of cos θ_l over the cone: cos(max(θ_axis − α, 0)).
            let cos_axis = n.dot(axis).clamp(-1.0, 1.0);
            let sin_axis = (1.0 - cos_axis * cos_axis).max(0.0).sqrt();
            let sin_max = sin2.sqrt();
            let cos_bound = if cos_axis >= cos_max {
                1.0
            } else {
                cos_axis * cos_max + sin_axis * sin_max
            };
            let weight = if cos_bound > 0.0 && one_minus_cos > 0.0 {
                one_minus_cos * cos_bound
            } else {
                0.0
            };
            *cone = Cone {
                axis,
                cos_max,
                one_minus_cos,
                weight,
            };
            total += weight;
        }
        Some((cones, total))
    }

    /// A direction from `p` (normal `n`) and its density per solid angle; `u_pick` chooses the
    /// target, `u` the direction.
    fn sample(&self, p: Vec3, n: Vec3, u_pick: f32, u: Vec2) -> Option<(Vec3, f32)> {
        let Some((cones, total)) = self.cones(p, n) else {
            let local = warp::square_to_cosine_hemisphere(u);
            return Some((
                Frame::from_normal(n).to_world(local),
                local.z * std::f32::consts::FRAC_1_PI,
            ));
        };
        if !(total > 0.0) {
            return None;
        }
        let mut target = u_pick * total;
        let mut chosen = None;
        for cone in &cones[..self.spheres.len()] {
            if cone.weight > 0.0 {
                chosen = Some(cone);
                if target < cone.weight {
                    break;
                }
                target -= cone.weight;
            }
        }
        let cone = chosen?;
        // Uniform in the cone: cos θ = 1 − u·(1 − cos α).
        let cos_t = 1.0 - u.x * cone.one_minus_cos;
        let sin_t = (u.x * cone.one_minus_cos * (1.0 + cos_t)).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * u.y;
        let local = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
        let dir = Frame::from_normal(cone.axis).to_world(local).normalize();
        let pdf = Self::mixture(&cones[..self.spheres.len()], total, dir);
        (pdf > 0.0).then_some((dir, pdf))
    }

    /// Density per solid angle of [`Self::sample`] producing `w` from `p`.
    fn pdf(&self, p: Vec3, n: Vec3, w: Vec3) -> f32 {
        match self.cones(p, n) {
            None => n.dot(w).max(0.0) * std::f32::consts::FRAC_1_PI,
            Some((cones, total)) if total > 0.0 => Self::mixture(&cones[..self.spheres.len()], total, w),
            Some(_) => 0.0,
        }
    }

    fn mixture(cones: &[Cone], total: f32, w: Vec3) -> f32 {
        let mut pdf = 0.0;
        for cone in cones {
            if cone.weight > 0.0 && w.dot(cone.axis) >= cone.cos_max {
                pdf += cone.weight / (total * 2.0 * std::f32::consts::PI * cone.one_minus_cos);
            }
        }
        pdf
    }
}

/// A vertex of a light subpath that camera-path vertices connect to: a point with a smooth lobe
/// whose neighbour towards the light is a delta vertex. `L` is what the subpath carries: a
/// spectrum, or in polarized mode a Mueller matrix (the emitter's depolarizer followed by the
/// importance-mode matrices of the delta vertices, in light order, so its first column is the
/// Stokes vector of the light arriving here, in the implicit basis of its direction).
#[derive(Clone, Copy, Debug)]
pub struct LightVertex<L = SampledSpectrum> {
    p: Vec3,
    /// Geometric normal.
    n: Vec3,
    shading: Frame,
    /// The hit as its material reads it (uv, derivatives).
    at: crate::material::ShadingPoint,
    shape: u32,
    /// Direction towards the chain, in the shading frame.
    wi: Vec3,
    /// |ω_in·n_g|.
    cos_chain: f32,
    /// Throughput arriving at the vertex (emitted radiance over the sampling densities, times
    /// the chain's weights).
    beta: L,
    /// `p_sel·p_A/π` of the light the subpath started from, times Π over the smooth vertices `d`
    /// between the light and this vertex of `p_d,light·cos_d,light / (p_d,eye·cos_d,eye)`.
    light_density: f32,
    /// (η_l/η_y)²: the squared ratio of the indices at the light and at the vertex.
    eta2: f32,
    /// Segments from the light to this vertex.
    segments: u32,
    /// Refracted next-event estimation's density of the paths joined here.
    refracted: RefractedDensity,
}

impl<L> LightVertex<L> {
    /// The connection's MIS weight for a camera-side density `arrival` = `p_x(z)` per unit area,
    /// the BSDF density `pdf_z` at this vertex of the direction towards the light and `wi_z` the
    /// direction towards the camera side in its shading frame: `1/(1 + r²)` (the ratio `r` of the
    /// module documentation, from this end), or with refracted next-event estimation its share
    /// of three ([`super::refracted::shares`]).
    fn connection_weight(&self, arrival: f32, pdf_z: f32, wi_z: Vec3) -> f32 {
        let r = arrival * pdf_z * self.eta2 / (self.light_density * self.cos_chain);
        let s = match self.refracted {
            RefractedDensity::None => 0.0,
            RefractedDensity::Here(num) => num[usize::from(wi_z.z < 0.0)] / pdf_z,
            RefractedDensity::Earlier(s) => s,
        };
        shares(r, s)[1]
    }
}

/// What a light vertex knows of refracted next-event estimation ([`super::refracted`]) at the
/// smooth vertex nearest the light of the paths it joins: that vertex is this one when no smooth
/// vertex lies between it and the light, an earlier one of the subpath otherwise.
#[derive(Clone, Copy, Debug)]
pub(super) enum RefractedDensity {
    /// The strategy cannot produce the paths (a reflection or another material in the chain
    /// from the light, or the strategy off).
    None,
    /// The light-selection × straight-line density of the direction towards the chain from
    /// this vertex, for a camera side along +n_s ([0]) or −n_s ([1]) of its shading normal.
    Here([f32; 2]),
    /// The ratio `s = p₃/p₁` at the earlier vertex.
    Earlier(f32),
}

/// The kept vertices of one light subpath (at most [`MAX_CHAIN`]: each follows its own delta
/// vertex), on the stack. An `ArrayVec`, so that making an empty one per camera sample costs
/// nothing (no initialization of the unused slots).
///
/// `L` is what the subpath carries ([`LightVertex`]): a spectrum (the default) or a Mueller
/// matrix in polarized mode.
#[derive(Clone, Debug)]
pub struct LightSubpath<L = SampledSpectrum> {
    vertices: ArrayVec<LightVertex<L>, { MAX_CHAIN as usize }>,
}

impl<L> Default for LightSubpath<L> {
    fn default() -> Self {
        Self::empty()
    }
}

impl LightSubpath {
    /// A spectral subpath with no vertices (see [`LightSubpath::empty`]).
    #[inline]
    pub fn new() -> Self {
        Self::empty()
    }
}

impl<L> LightSubpath<L> {
    /// No vertices. A function, not a constant: a constant's unused slots are materialized as
    /// zeros (a 1 KB memset per camera sample), a fresh `ArrayVec` writes nothing.
    #[inline]
    pub fn empty() -> Self {
        Self {
            vertices: ArrayVec::new(),
        }
    }

    /// Number of kept vertices.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// True when the subpath left nothing to connect to.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// Forgets the vertices.
    pub fn clear(&mut self) {
        self.vertices.clear();
    }

    /// Keeps a vertex (beyond [`MAX_CHAIN`] vertices, drops it).
    fn push(&mut self, v: LightVertex<L>) {
        let _ = self.vertices.try_push(v);
    }

    fn iter(&self) -> impl Iterator<Item = &LightVertex<L>> {
        self.vertices.iter()
    }
}

/// The path tracer's record of the connection candidate `z` (the last smooth vertex reached
/// straight from a smooth vertex or the camera) and of the path after it, for the MIS weight of
/// an area light hit at the end of a delta chain.
#[derive(Clone, Copy, Debug)]
pub struct ChainState {
    /// How `z` was reached (gives `p_x(z)`).
    arrival: Arrival,
    /// BSDF density at `z` of the direction taken.
    pdf_z: f32,
    /// |ω_z·n_g| at `z`.
    cos_z: f32,
    /// Π over the smooth vertices `d` after `z` of `p_d·cos_d,eye / (p_d,rev·cos_d,light)`.
    ratio: f32,
    /// Product of the relative indices crossed since `z` (η_l/η_z).
    eta: f32,
    /// Delta vertices since `z`.
    deltas: u32,
}

/// How the path tracer reached a vertex, for `p_x(z)`: resolved only when an MIS weight needs it
/// (most candidates never meet a light), so the camera's projection is not computed per hit.
#[derive(Clone, Copy, Debug)]
pub enum Arrival {
    /// After a delta lobe: no connection strategy.
    Delta,
    /// Straight from the camera, at point `p` with |cos θ_z| = `cos`.
    Camera {
        /// The vertex.
        p: Vec3,
        /// |ω·n_g| at the vertex.
        cos: f32,
    },
    /// From a smooth vertex: the density per unit area.
    Density(f32),
}

impl ChainState {
    /// The state after a real scattering event at a vertex reached by `arrival`, `cos_in`/`cos_out` = |ω·n_g| of the incoming and the sampled
    /// direction, `reverse_pdf` the light tracer's density of the reverse of a smooth sample.
    pub fn after_sample<W>(
        state: Option<Self>,
        bs: &BsdfSample<W>,
        arrival: Arrival,
        cos_in: f32,
        cos_out: f32,
        reverse_pdf: f32,
    ) -> Option<Self> {
        if bs.flags.is_delta() {
            return state.map(|s| s.after_delta(bs.eta));
        }
        Self::after_smooth(state, bs.pdf, arrival, cos_in, cos_out, reverse_pdf)
    }

    /// The state after a delta vertex of relative index `eta`.
    #[inline]
    pub fn after_delta(self, eta: f32) -> Self {
        self.after_deltas(1, eta)
    }

    /// The state after `count` delta vertices whose relative indices multiply to `eta`.
    #[inline]
    pub fn after_deltas(self, count: u32, eta: f32) -> Self {
        Self {
            eta: self.eta * eta,
            deltas: self.deltas + count,
            ..self
        }
    }

    /// The state after a smooth sample of density `pdf` ([`ChainState::after_sample`]).
    pub fn after_smooth(
        state: Option<Self>,
        pdf: f32,
        arrival: Arrival,
        cos_in: f32,
        cos_out: f32,
        reverse_pdf: f32,
    ) -> Option<Self> {
        if !matches!(arrival, Arrival::Delta) {
            // Reached from a smooth vertex or the camera: the new candidate.
            return Some(Self {
                arrival,
                pdf_z: pdf,
                cos_z: cos_out,
                ratio: 1.0,
                eta: 1.0,
                deltas: 0,
            });
        }
        // A smooth vertex after a delta one (so `deltas` > 0: the vertices since `z` alternate):
        // part of the candidate's light subpath.
        state.map(|s| {
            let denom = reverse_pdf * cos_out;
            Self {
                ratio: if denom > 0.0 {
                    s.ratio * pdf * cos_in / denom
                } else {
                    f32::INFINITY
                },
                ..s
            }
        })
    }
}

impl PathTracer<'_> {
    /// How the vertex `si` was reached along `d` from `prev` = (point, BSDF pdf, delta?) of the
    /// previous real vertex, or from the camera when `None`.
    pub(super) fn arrival(prev: Option<(Vec3, f32, bool)>, si: &SurfaceInteraction, d: Vec3) -> Arrival {
        let cos = si.n.dot(d).abs();
        match prev {
            None => Arrival::Camera { p: si.p, cos },
            Some((_, _, true)) => Arrival::Delta,
            Some((p, pdf, false)) => {
                let d2 = (si.p - p).length_squared();
                Arrival::Density(if d2 > 0.0 { pdf * cos / d2 } else { 0.0 })
            }
        }
    }

    /// `p_x(z)` per unit area (zero where no connection can produce the path).
    fn arrival_density(&self, arrival: Arrival) -> f32 {
        match arrival {
            Arrival::Delta => 0.0,
            Arrival::Camera { p, cos } => self
                .camera
                .and_then(|c| c.connect(p))
                .map_or(0.0, |c| c.film_pdf * cos / c.dist2),
            Arrival::Density(d) => d,
        }
    }

    /// The ratio `r = p₁/p₂` of the path tracer's density to the connection's for area light
    /// `li` hit at the end of `chain` (infinite where no connection can produce the path).
    /// `l`, `n_l`: the point hit on the light and its geometric normal; `w_l`: the direction from
    /// it back along the path.
    pub(super) fn caustic_ratio(
        &self,
        chain: Option<&ChainState>,
        li: usize,
        area: &AreaLight,
        l: Vec3,
        n_l: Vec3,
        w_l: Vec3,
    ) -> f32 {
        let (Some(c), Some(emission)) = (chain, &self.caustics) else {
            return f32::INFINITY;
        };
        if c.deltas == 0 || c.deltas > MAX_CHAIN {
            return f32::INFINITY;
        }
        let arrival = self.arrival_density(c.arrival);
        if !(arrival > 0.0) {
            return f32::INFINITY;
        }
        let p2 = emission.light_density(li, area, l, n_l, w_l) * c.cos_z;
        arrival * c.pdf_z * c.ratio * c.eta * c.eta / p2
    }

    /// Σ over the light subpath's vertices of the connection from camera-path vertex `si`
    /// (BSDF `bsdf_x`, incoming `wi_x` in its shading frame, `depth` real vertices before it),
    /// MIS-weighted, not yet multiplied by the camera path's throughput. In light order the
    /// connection is `f_x · T · f_z · β_z` (T: the sheets crossed between the two vertices), each
    /// factor in the implicit world bases of its beams.
    pub(super) fn connect_light_vertices<W: Weight, L: LightWeight<W>>(
        &self,
        bsdf_x: &SurfaceBsdf<'_>,
        si: &SurfaceInteraction,
        wi_x: Vec3,
        depth: u32,
        light: &LightSubpath<L>,
        wl: &SampledWavelengths,
    ) -> W
    where
        for<'b> SurfaceBsdf<'b>: BsdfWeight<W>,
    {
        let radiance = BsdfContext::radiance();
        let mut sum = W::ZERO;
        for y in light.iter() {
            // Segments: depth + 1 to x, one to y, the light subpath's to the light.
            if depth as u64 + y.segments as u64 + 2 > self.max_depth as u64 {
                continue;
            }
            let v = y.p - si.p;
            let d2 = v.length_squared();
            if !(d2 > 0.0) {
                continue;
            }
            let dir = v / d2.sqrt();
            let wo_x = si.shading.to_local(dir);
            let (f_x, pdf_x): (W, f32) = bsdf_x.eval_pdf_weight(&radiance, wi_x, wo_x, wl);
            let f_x = f_x.local_to_world(&si.shading);
            if f_x.is_black() {
                continue;
            }
            let wi_y = y.shading.to_local(-dir);
            let Some((f_y, pdf_y)) = self.bsdf_at(y.shape, &y.at, &{ *wl }, |b: &SurfaceBsdf<'_>| {
                let (f, pdf): (W, f32) = b.eval_pdf_weight(&radiance, wi_y, y.wi, wl);
                (f.local_to_world(&y.shading), pdf)
            }) else {
                continue;
            };
            if f_y.is_black() {
                continue;
            }
            let cos_y = y.n.dot(dir).abs();
            let g = wo_x.z.abs() * cos_y / d2 * y.wi.z.abs() / y.cos_chain;
            // Light order: the light subpath, then f at y, (the sheets,) then f at x.
            let c = f_y * y.beta.into_weight() * g;
            if c.is_black() || !c.intensity().is_finite() || (f_x * c).is_black() {
                continue;
            }
            let w = y.connection_weight(pdf_x * cos_y / d2, pdf_y, wi_y);
            if !(w > 0.0) {
                continue;
            }
            // The shadow ray leaves x; light travels along it backwards, towards x.
            let vis: W = self.visibility(spawn_ray_between(si.p, si.n, y.p, Some(y.n)), wl, false);
            if !vis.is_black() {
                sum += f_x * vis * c * w;
            }
        }
        sum
    }
}

/// What a light subpath carries, as the weight `W` of the camera path it joins: a spectrum
/// enters any path depolarized ([`Weight::from_spectrum`]); a Mueller matrix joins a polarized
/// path as it is.
pub trait LightWeight<W: Weight>: Copy {
    /// The subpath's throughput as a camera-path weight.
    fn into_weight(self) -> W;
}

impl<W: Weight> LightWeight<W> for SampledSpectrum {
    #[inline]
    fn into_weight(self) -> W {
        W::from_spectrum(self)
    }
}

impl LightWeight<Mueller> for Mueller {
    #[inline]
    fn into_weight(self) -> Mueller {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gonio_core::rng::Pcg32;

    fn targets() -> DeltaTargets {
        DeltaTargets {
            spheres: vec![
                (Vec3::new(0.0, -2.0, 0.5), 0.5),
                (Vec3::new(1.5, -1.0, 0.0), 0.3),
                // Mostly behind the emitting side (normal −y): weighted by its visible part.
                (Vec3::new(-1.0, 0.1, 0.0), 0.4),
            ],
        }
    }

    /// The emitted-direction density integrates to one over the sphere (stratified quadrature)
    /// and agrees with what `sample` reports; every sample lies in a target's cone.
    #[test]
    fn aimed_emission_density_is_normalized_and_matches_sampling() {
        let t = targets();
        let (p, n) = (Vec3::ZERO, Vec3::new(0.0, -1.0, 0.0));
        let steps = 1500;
        let mut integral = 0.0f64;
        for i in 0..steps {
            for j in 0..steps {
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / steps as f32;
                let phi = 2.0 * std::f32::consts::PI * (j as f32 + 0.5) / steps as f32;
                let s = (1.0 - z * z).max(0.0).sqrt();
                let w = Vec3::new(s * phi.cos(), s * phi.sin(), z);
                integral += t.pdf(p, n, w) as f64;
            }
        }
        integral *= 4.0 * std::f64::consts::PI / (steps * steps) as f64;
        assert!((integral - 1.0).abs() < 5e-3, "∫ pdf = {integral}");

        let mut rng = Pcg32::new(5, 9);
        for _ in 0..10_000 {
            let (w, pdf) = t
                .sample(p, n, rng.next_f32(), rng.next_vec2())
                .expect("a direction");
            assert!((w.length() - 1.0).abs() < 1e-4);
            let q = t.pdf(p, n, w);
            assert!((pdf / q - 1.0).abs() < 1e-4, "sample pdf {pdf}, pdf() {q}");
            let inside = t.spheres.iter().any(|&(c, r)| {
                let v = c - p;
                w.dot(v) > 0.0 && (v - w * w.dot(v)).length() <= r * 1.0001
            });
            assert!(inside, "direction {w:?} misses every target");
        }
    }

    /// From inside a target (or with no targets) emission is cosine-distributed.
    #[test]
    fn inside_a_target_emission_is_cosine() {
        let t = targets();
        let (p, n) = (Vec3::new(0.0, -2.0, 0.5), Vec3::Y);
        let w = Vec3::new(0.6, 0.8, 0.0);
        assert!((t.pdf(p, n, w) - 0.8 / std::f32::consts::PI).abs() < 1e-6);
        let none = DeltaTargets::default();
        assert!((none.pdf(Vec3::ZERO, n, w) - 0.8 / std::f32::consts::PI).abs() < 1e-6);
        assert_eq!(none.pdf(Vec3::ZERO, n, -w), 0.0);
    }

    /// The path tracer's weight is the power heuristic r²/(1 + r²): a number in [0, 1] for every
    /// ratio (it was NaN for r = 1e20 once), increasing, 0 where only the connection can produce
    /// the path, 1 where only the path tracer can, ½ at r = 1.
    #[test]
    fn path_tracer_weight_is_the_power_heuristic_for_every_ratio() {
        let rs = [0.0, 1e-6, 0.3, 1.0, 7.0, 1e15, 1e20, f32::MAX, f32::INFINITY];
        let mut last = -1.0;
        for r in rs {
            let w = shares(r, 0.0)[0];
            assert!((0.0..=1.0).contains(&w), "r = {r}: weight {w}");
            assert!(w >= last, "not increasing at r = {r}");
            if r < 1e15 {
                let r2 = (r as f64) * (r as f64);
                assert!((w as f64 - r2 / (1.0 + r2)).abs() < 1e-6, "r = {r}: {w}");
            }
            last = w;
        }
        assert_eq!(shares(0.0, 0.0)[0], 0.0);
        assert_eq!(shares(f32::INFINITY, 0.0)[0], 1.0);
        assert_eq!(shares(f32::NAN, 0.0)[0], 1.0);
        assert!((shares(1.0, 0.0)[0] - 0.5).abs() < 1e-7);
    }
}
