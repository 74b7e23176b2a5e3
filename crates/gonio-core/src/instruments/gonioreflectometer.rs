//! A virtual gonioreflectometer (lecture slides "Stanford Gonioreflectometer", "EPFL
//! Gonioreflectometer"). It simulates the instrument, not the formula:
//!
//! 1. a collimated source lights the specimen from polar angle θi (azimuth 0);
//! 2. photons are traced to the specimen and scattered by it ([`Sample::scatter`]: for a BSDF,
//!    importance-mode sampling, i.e. the photon's power; for explicit geometry, a random walk
//!    over its facets);
//! 3. a detector of finite aperture (a cone of half-angle α) is moved over the hemisphere to
//!    the grid positions (θo, ±φd) and counts the power of the photons that land in it;
//! 4. optional detector noise multiplies each reading by (1 + σ·g), g a standard normal.
//!
//! **Calibration.** With N photons of total power Φ on a sample of area A, the irradiance is
//! E = Φ/A; a detector of projected solid angle Ω⊥ = ∫_cone cos θ dω receiving power Φ_d reads
//! radiance L = Φ_d/(A Ω⊥), so f = L/E = (Φ_d/Φ)/Ω⊥ = (Σ photon weights in the cone)/(N Ω⊥).
//! The reading is the cosine-weighted average of f over the cone: a finite aperture blurs the
//! BRDF over α, exactly as the real instrument does (a mirror's delta lobe reads as a tall
//! bump of height F/Ω⊥ centred on the mirror direction).
//!
//! The specimen is assumed isotropic: both detectors at +φd and −φd are read and averaged. The
//! standard error of every reading (photon counting plus detector noise) is reported with it.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags};
use crate::bsdfs::tabulated::TabulatedData;
use crate::frame::Frame;
use crate::rng::Pcg32;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use std::f32::consts::PI;
use std::sync::Arc;

/// A specimen on the instrument's stage: anything that scatters photons.
///
/// The stage's normal is +z. A specimen that is a piece of geometry (a microfacet heightfield,
/// a half-space of spheres) is traced by its own intersector; later work plugs in more kinds by
/// implementing this trait.
pub trait Sample: Send + Sync {
    /// Scatters one photon that arrives travelling along `-to_source` (`to_source` is the unit
    /// direction from the specimen to the source, z > 0). Returns the direction the photon
    /// leaves in and the fraction of its power that leaves with it (per wavelength), or `None`
    /// when it is absorbed. `wl` may have its secondaries terminated by a dispersive event.
    fn scatter(
        &self,
        to_source: Vec3,
        rng: &mut Pcg32,
        wl: &mut SampledWavelengths,
    ) -> Option<(Vec3, SampledSpectrum)>;

    /// A one-line description, written into the measured table's header.
    fn describe(&self) -> String;
}

/// A BSDF as a specimen: one scattering event, sampled in importance mode (photons carry
/// power, so no radiance η² factor).
pub struct BsdfSpecimen<'a> {
    bsdf: &'a dyn Bsdf,
    name: String,
}

impl<'a> BsdfSpecimen<'a> {
    /// Wraps a BSDF; `name` goes into the table header.
    pub fn new(bsdf: &'a dyn Bsdf, name: impl Into<String>) -> Self {
        Self {
            bsdf,
            name: name.into(),
        }
    }
}

impl Sample for BsdfSpecimen<'_> {
    fn scatter(
        &self,
        to_source: Vec3,
        rng: &mut Pcg32,
        wl: &mut SampledWavelengths,
    ) -> Option<(Vec3, SampledSpectrum)> {
        let u1 = rng.next_f32();
        let u2 = rng.next_vec2();
        let s = self
            .bsdf
            .sample(&BsdfContext::importance(), to_source, u1, u2, wl)?;
        Some((s.wo, s.weight))
    }
    fn describe(&self) -> String {
        format!("bsdf {}", self.name)
    }
}

/// Correlation length (standard deviation of the blur kernel, in cells) of
/// [`HeightfieldSpecimen::gaussian`]: long enough that the flat triangles follow the smooth
/// surface, short enough that a grid holds many independent patches.
pub const GAUSSIAN_CORRELATION_CELLS: f64 = 4.0;

/// A periodic heightfield of microfacets: an n × n grid of heights over the unit square, each
/// cell split into two triangles, every facet made of the same BSDF, repeated without end in x
/// and y. Photons arrive at a uniformly random point and bounce between facets (multiple
/// scattering and shadowing included) until they escape upwards or are absorbed.
pub struct HeightfieldSpecimen<'a> {
    n: usize,
    heights: Vec<f32>,
    z_max: f32,
    facet: Arc<dyn Bsdf + 'a>,
    max_bounces: u32,
    name: String,
}

impl<'a> HeightfieldSpecimen<'a> {
    /// A heightfield from `n × n` heights (row-major, `heights[j * n + i]` at x = i/n, y = j/n;
    /// periodic). `None` when the sizes disagree or a height is not finite.
    pub fn new(
        n: usize,
        heights: Vec<f32>,
        facet: Arc<dyn Bsdf + 'a>,
        name: impl Into<String>,
    ) -> Option<Self> {
        if n == 0 || heights.len() != n * n || heights.iter().any(|h| !h.is_finite()) {
            return None;
        }
        let z_max = heights.iter().copied().fold(f32::MIN, f32::max);
        Some(Self {
            n,
            heights,
            z_max,
            facet,
            max_bounces: 100,
            name: name.into(),
        })
    }

    /// Random heights, uniform in [0, `amplitude`] (seeded), for a rough surface of facets.
    pub fn random(
        n: usize,
        amplitude: f32,
        seed: u64,
        facet: Arc<dyn Bsdf + 'a>,
        name: impl Into<String>,
    ) -> Option<Self> {
        let mut rng = Pcg32::new(seed, 0x6e17);
        let heights = (0..n * n).map(|_| amplitude * rng.next_f32()).collect();
        Self::new(n, heights, facet, name)
    }

    /// A Gaussian random surface whose facet slopes follow Beckmann's distribution of roughness
    /// `alpha`: the microsurface that Beckmann's D and Smith's masking describe (a Gaussian
    /// process; Smith's uncorrelated-heights assumption is known to be accurate for it, Heitz
    /// 2014, "Understanding the Masking-Shadowing Function", §6).
    ///
    /// White Gaussian noise on the n × n vertices is blurred by a periodic Gaussian kernel of
    /// standard deviation [`GAUSSIAN_CORRELATION_CELLS`] cells (a stationary, isotropic Gaussian
    /// process; every facet's slope, a difference of vertex heights, is then exactly Gaussian),
    /// and the heights are scaled so that the mean square facet slope per axis is α²/2,
    /// Beckmann's slope variance (D(m) ∝ exp(−tan²θm/α²)). The surface holds about
    /// (n/4)² independent patches: give n ≥ 256 for the slopes to fill their distribution's
    /// tails. `None` when n < 32 or α is not finite and positive.
    pub fn gaussian(
        n: usize,
        alpha: f32,
        seed: u64,
        facet: Arc<dyn Bsdf + 'a>,
        name: impl Into<String>,
    ) -> Option<Self> {
        if n < 32 || !(alpha > 0.0 && alpha.is_finite()) {
            return None;
        }
        let mut rng = Pcg32::new(seed, 0x9a55);
        // Box–Muller pairs.
        let mut noise = Vec::with_capacity(n * n + 1);
        while noise.len() < n * n {
            let (u1, u2) = (1.0 - rng.next_f64(), rng.next_f64());
            let r = (-2.0 * u1.ln()).sqrt();
            let (s, c) = (std::f64::consts::TAU * u2).sin_cos();
            noise.push(r * c);
            noise.push(r * s);
        }
        noise.truncate(n * n);
        // Separable periodic Gaussian blur.
        let sigma = GAUSSIAN_CORRELATION_CELLS;
        let radius = (4.0 * sigma).ceil() as i64;
        let kernel: Vec<f64> = (-radius..=radius)
            .map(|d| (-(d * d) as f64 / (2.0 * sigma * sigma)).exp())
            .collect();
        let ni = n as i64;
        let wrap = |k: i64| k.rem_euclid(ni) as usize;
        let mut rows = vec![0.0f64; n * n];
        for j in 0..n {
            for i in 0..n {
                rows[j * n + i] = kernel
                    .iter()
                    .enumerate()
                    .map(|(k, w)| w * noise[j * n + wrap(i as i64 + k as i64 - radius)])
                    .sum();
            }
        }
        let mut h = vec![0.0f64; n * n];
        for j in 0..n {
            for i in 0..n {
                h[j * n + i] = kernel
                    .iter()
                    .enumerate()
                    .map(|(k, w)| w * rows[wrap(j as i64 + k as i64 - radius) * n + i])
                    .sum();
            }
        }
        // Mean square slope per axis over both triangles of every cell (cell size 1/n).
        let at = |i: usize, j: usize| h[(j % n) * n + (i % n)];
        let mut ms = 0.0;
        for j in 0..n {
            for i in 0..n {
                let (h00, h10, h01, h11) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
                ms += (h10 - h00).powi(2) + (h11 - h10).powi(2) + (h11 - h01).powi(2) + (h01 - h00).powi(2);
            }
        }
        let ms = ms / (4 * n * n) as f64 * (n * n) as f64; // slopes = differences × n
        let scale = ((alpha as f64).powi(2) / 2.0 / ms).sqrt();
        let heights = h.iter().map(|v| (v * scale) as f32).collect();
        Self::new(n, heights, facet, name)
    }

    fn height(&self, i: i64, j: i64) -> f32 {
        let n = self.n as i64;
        self.heights[(j.rem_euclid(n) * n + i.rem_euclid(n)) as usize]
    }

    /// The two triangles of cell (i, j) (unwrapped coordinates).
    fn cell_triangles(&self, i: i64, j: i64) -> [[Vec3; 3]; 2] {
        let s = 1.0 / self.n as f32;
        let p = |a: i64, b: i64| Vec3::new(a as f32 * s, b as f32 * s, self.height(a, b));
        let (p00, p10, p01, p11) = (p(i, j), p(i + 1, j), p(i, j + 1), p(i + 1, j + 1));
        [[p00, p10, p11], [p00, p11, p01]]
    }

    /// Closest hit along the ray (origin, dir): (t, upward unit normal). Walks the grid cells
    /// the ray's xy projection crosses (Amanatides & Woo) while the ray is below `z_max`.
    fn intersect(&self, o: Vec3, d: Vec3) -> Option<(f32, Vec3)> {
        let s = 1.0 / self.n as f32;
        let mut i = (o.x / s).floor() as i64;
        let mut j = (o.y / s).floor() as i64;
        let step_i = if d.x > 0.0 { 1 } else { -1 };
        let step_j = if d.y > 0.0 { 1 } else { -1 };
        let next_boundary = |c: i64, step: i64| (c + (step > 0) as i64) as f32 * s;
        let mut t_max_x = if d.x != 0.0 {
            (next_boundary(i, step_i) - o.x) / d.x
        } else {
            f32::INFINITY
        };
        let mut t_max_y = if d.y != 0.0 {
            (next_boundary(j, step_j) - o.y) / d.y
        } else {
            f32::INFINITY
        };
        let t_dx = if d.x != 0.0 { s / d.x.abs() } else { f32::INFINITY };
        let t_dy = if d.y != 0.0 { s / d.y.abs() } else { f32::INFINITY };
        let mut t_enter = 0.0f32;
        for _ in 0..200_000 {
            // Leave the slab above the surface: no more hits possible.
            if d.z > 0.0 && o.z + d.z * t_enter > self.z_max + 1e-4 {
                return None;
            }
            let t_exit = t_max_x.min(t_max_y);
            let mut best: Option<(f32, Vec3)> = None;
            for tri in self.cell_triangles(i, j) {
                if let Some((t, nrm)) = ray_triangle(o, d, tri)
                    && t > 1e-5
                    && t <= t_exit + 1e-5
                    && best.is_none_or(|(bt, _)| t < bt)
                {
                    best = Some((t, nrm));
                }
            }
            if best.is_some() {
                return best;
            }
            if t_exit.is_infinite() {
                return None;
            }
            t_enter = t_exit;
            if t_max_x < t_max_y {
                i += step_i;
                t_max_x += t_dx;
            } else {
                j += step_j;
                t_max_y += t_dy;
            }
        }
        None
    }
}

/// Möller–Trumbore; returns t and the triangle's unit normal flipped to face up (+z).
fn ray_triangle(o: Vec3, d: Vec3, [a, b, c]: [Vec3; 3]) -> Option<(f32, Vec3)> {
    let e1 = b - a;
    let e2 = c - a;
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let tv = o - a;
    let u = tv.dot(p) * inv;
    if !(-1e-6..=1.0 + 1e-6).contains(&u) {
        return None;
    }
    let q = tv.cross(e1);
    let v = d.dot(q) * inv;
    if v < -1e-6 || u + v > 1.0 + 1e-6 {
        return None;
    }
    let t = e2.dot(q) * inv;
    let mut n = e1.cross(e2).normalize();
    if n.z < 0.0 {
        n = -n;
    }
    Some((t, n))
}

impl Sample for HeightfieldSpecimen<'_> {
    fn scatter(
        &self,
        to_source: Vec3,
        rng: &mut Pcg32,
        wl: &mut SampledWavelengths,
    ) -> Option<(Vec3, SampledSpectrum)> {
        let ctx = BsdfContext::importance();
        let mut d = -to_source;
        let start = rng.next_vec2();
        // Start on the plane just above the highest point, at a uniformly random footprint.
        let mut o = Vec3::new(start.x, start.y, self.z_max + 1e-3);
        let mut throughput = SampledSpectrum::ONE;
        for _ in 0..self.max_bounces {
            let Some((t, n)) = self.intersect(o, d) else {
                return (d.z > 0.0).then_some((d, throughput));
            };
            let p = o + d * t;
            let frame = Frame::from_normal(n);
            let wi = frame.to_local(-d);
            if wi.z <= 0.0 {
                return None;
            }
            let s = self.facet.sample(&ctx, wi, rng.next_f32(), rng.next_vec2(), wl)?;
            if s.wo.z <= 0.0 || s.flags.contains(BsdfFlags::TRANSMISSION) {
                return None; // opaque facets: transmitted light is lost in the bulk
            }
            throughput *= s.weight;
            d = frame.to_world(s.wo).normalize();
            o = p + n * 1e-4;
            // Keep coordinates small (periodicity) to preserve precision.
            o.x -= o.x.floor();
            o.y -= o.y.floor();
        }
        None
    }
    fn describe(&self) -> String {
        format!("heightfield {}x{} of {}", self.n, self.n, self.name)
    }
}

/// A half-space (z < 0) sparsely filled with randomly placed opaque spheres whose surfaces are
/// made of a BSDF (d'Eon 2021, "An analytic BRDF for materials with spherical Lambertian
/// scatterers"). Sparse,
/// uncorrelated spheres make classical transport: exponential free paths (unit mean free path)
/// between collisions; at a collision the photon meets a sphere at a point uniform in projected
/// area, i.e. with a normal n distributed ∝ max(0, −d·n) about its travel direction d, and
/// scatters off that point of the surface by the surface BSDF. Photons that climb back above
/// z = 0 escape. With Lambertian surfaces of albedo c this is the half-space of Lambert spheres
/// whose BRDF later work models analytically.
pub struct SphereHalfSpaceSpecimen<'a> {
    surface: Arc<dyn Bsdf + 'a>,
    max_events: u32,
    name: String,
}

impl<'a> SphereHalfSpaceSpecimen<'a> {
    /// Spheres made of `surface`; a photon is dropped after `max_events` collisions (the walk
    /// of a lossless medium is long: give thousands).
    pub fn new(surface: Arc<dyn Bsdf + 'a>, max_events: u32, name: impl Into<String>) -> Self {
        Self {
            surface,
            max_events,
            name: name.into(),
        }
    }
}

impl Sample for SphereHalfSpaceSpecimen<'_> {
    fn scatter(
        &self,
        to_source: Vec3,
        rng: &mut Pcg32,
        wl: &mut SampledWavelengths,
    ) -> Option<(Vec3, SampledSpectrum)> {
        let ctx = BsdfContext::importance();
        let mut d = -to_source;
        let mut z = 0.0f32;
        let mut throughput = SampledSpectrum::ONE;
        for _ in 0..self.max_events {
            let t = -(1.0 - rng.next_f32()).ln();
            z += d.z * t;
            if z > 0.0 {
                return Some((d, throughput));
            }
            // The sphere's normal at the hit point: cosine-weighted about −d.
            let n =
                Frame::from_normal(-d).to_world(crate::warp::square_to_cosine_hemisphere(rng.next_vec2()));
            let frame = Frame::from_normal(n.normalize());
            let wi = frame.to_local(-d);
            if wi.z <= 0.0 {
                continue; // grazing hit rounded below the horizon: no interaction
            }
            let s = self
                .surface
                .sample(&ctx, wi, rng.next_f32(), rng.next_vec2(), wl)?;
            if s.wo.z <= 0.0 {
                return None; // opaque spheres
            }
            throughput *= s.weight;
            d = frame.to_world(s.wo).normalize();
        }
        None
    }
    fn describe(&self) -> String {
        format!("half-space of sparse spheres of {}", self.name)
    }
}

/// Instrument settings.
#[derive(Clone, Debug, PartialEq)]
pub struct GonioSettings {
    /// Number of source polar angles θi, at the midpoints (k + ½)·90°/N.
    pub incident: usize,
    /// Number of detector polar angles θo, at the midpoints (k + ½)·90°/M.
    pub outgoing: usize,
    /// Number of detector azimuths φd = φo − φi over [0°, 180°], ends included.
    pub azimuths: usize,
    /// Half-angle of the detector's acceptance cone, degrees.
    pub aperture_deg: f32,
    /// Photons per source position.
    pub photons: u64,
    /// Relative detector noise σ (0 = none).
    pub noise: f32,
    /// Wavelengths measured, nm.
    pub wavelengths: Vec<f32>,
    /// Random seed.
    pub seed: u64,
}

impl Default for GonioSettings {
    fn default() -> Self {
        Self {
            incident: 9,
            outgoing: 9,
            azimuths: 19,
            aperture_deg: 3.0,
            photons: 200_000,
            noise: 0.0,
            wavelengths: vec![550.0],
            seed: 0,
        }
    }
}

impl GonioSettings {
    /// Checks the settings; the message names the offending value.
    pub fn validate(&self) -> Result<(), String> {
        if self.incident == 0 || self.outgoing == 0 || self.azimuths < 2 {
            return Err(format!(
                "need at least 1 incident and 1 outgoing angle and 2 azimuths (got {}, {}, {})",
                self.incident, self.outgoing, self.azimuths
            ));
        }
        if !(self.aperture_deg > 0.0 && self.aperture_deg < 45.0) {
            return Err(format!("aperture {}° must be in (0, 45)", self.aperture_deg));
        }
        if self.photons < 2 {
            return Err(format!("photons {} must be at least 2", self.photons));
        }
        if !(self.noise >= 0.0 && self.noise.is_finite()) {
            return Err(format!("noise {} must be finite and ≥ 0", self.noise));
        }
        if self.wavelengths.is_empty() || self.wavelengths.iter().any(|l| !(*l > 0.0 && l.is_finite())) {
            return Err(format!("wavelengths {:?} must be positive", self.wavelengths));
        }
        Ok(())
    }

    /// Source polar angles, degrees.
    pub fn theta_i_deg(&self) -> Vec<f32> {
        midpoints(self.incident)
    }
    /// Detector polar angles, degrees.
    pub fn theta_o_deg(&self) -> Vec<f32> {
        midpoints(self.outgoing)
    }
    /// Detector azimuths, degrees.
    pub fn phi_d_deg(&self) -> Vec<f32> {
        let n = self.azimuths;
        (0..n).map(|k| 180.0 * k as f32 / (n - 1) as f32).collect()
    }
}

fn midpoints(n: usize) -> Vec<f32> {
    (0..n).map(|k| (k as f32 + 0.5) * 90.0 / n as f32).collect()
}

/// ∫_cone max(cos θ, 0) dω for a cone of half-angle `alpha` around `axis` (midpoint rule).
pub fn projected_solid_angle(axis: Vec3, alpha: f32) -> f32 {
    let frame = Frame::from_normal(axis);
    const NB: usize = 48;
    const NP: usize = 96;
    let mut sum = 0.0f64;
    for b in 0..NB {
        let beta = (b as f32 + 0.5) / NB as f32 * alpha;
        let (sb, cb) = beta.sin_cos();
        for p in 0..NP {
            let psi = (p as f32 + 0.5) / NP as f32 * 2.0 * PI;
            let w = frame.to_world(Vec3::new(sb * psi.cos(), sb * psi.sin(), cb));
            sum += (w.z.max(0.0) * sb) as f64;
        }
    }
    (sum * (alpha as f64 / NB as f64) * (2.0 * std::f64::consts::PI / NP as f64)) as f32
}

/// The readings for one source angle: values and standard errors, indexed
/// `[(o * azimuths + p) * n_lambda + l]`.
#[derive(Clone, Debug, PartialEq)]
pub struct IncidentReadings {
    /// BRDF readings, 1/sr.
    pub values: Vec<f32>,
    /// Standard errors of the readings, 1/sr.
    pub stderr: Vec<f32>,
}

/// Measures at source angle index `i` (0-based, see [`GonioSettings::theta_i_deg`]). Independent
/// of the other angles, so a caller may run them in parallel.
pub fn measure_incident(specimen: &dyn Sample, settings: &GonioSettings, i: usize) -> IncidentReadings {
    let theta_i = settings.theta_i_deg()[i].to_radians();
    let to_source = Vec3::new(theta_i.sin(), 0.0, theta_i.cos());
    let theta_o: Vec<f32> = settings.theta_o_deg().iter().map(|t| t.to_radians()).collect();
    let phi_d: Vec<f32> = settings.phi_d_deg().iter().map(|t| t.to_radians()).collect();
    let (no, np, nl) = (theta_o.len(), phi_d.len(), settings.wavelengths.len());
    let alpha = settings.aperture_deg.to_radians();
    let cos_alpha = alpha.cos();
    let omega: Vec<f32> = theta_o
        .iter()
        .map(|&t| projected_solid_angle(Vec3::new(t.sin(), 0.0, t.cos()), alpha))
        .collect();
    let axes: Vec<[Vec3; 2]> = (0..no * np)
        .map(|k| {
            let (t, p) = (theta_o[k / np], phi_d[k % np]);
            let (st, ct) = t.sin_cos();
            [
                Vec3::new(st * p.cos(), st * p.sin(), ct),
                Vec3::new(st * p.cos(), -st * p.sin(), ct),
            ]
        })
        .collect();
    let self_mirror: Vec<bool> = phi_d.iter().map(|&p| p.sin().abs() < 1e-6).collect();
    let mut sum = vec![0.0f64; no * np * nl];
    let mut sum2 = vec![0.0f64; no * np * nl];
    let n_photons = settings.photons;
    let mut rng = Pcg32::new(settings.seed, 0x9e37_79b9 ^ i as u64);
    // Records one photon (direction `d`, power `thr[c]` at wavelength slot `c` of `lam_idx`).
    let mut record = |d: Vec3, thr: &[(usize, f32)]| {
        if d.z <= 0.0 {
            return;
        }
        let theta = d.z.clamp(-1.0, 1.0).acos();
        let phi = d.y.atan2(d.x).abs();
        let window = {
            let st = theta.sin();
            if st > alpha.sin() {
                (alpha.sin() / st).clamp(-1.0, 1.0).asin() + 1e-3
            } else {
                PI
            }
        };
        for o in 0..no {
            if (theta_o[o] - theta).abs() > alpha + 1e-4 {
                continue;
            }
            for p in 0..np {
                if (phi_d[p] - phi).abs() > window {
                    continue;
                }
                let [plus, minus] = axes[o * np + p];
                let hit_plus = d.dot(plus) >= cos_alpha;
                let frac = if self_mirror[p] {
                    hit_plus as u32 as f32
                } else {
                    0.5 * (hit_plus as u32 + (d.dot(minus) >= cos_alpha) as u32) as f32
                };
                if frac == 0.0 {
                    continue;
                }
                for &(l, t) in thr {
                    let x = (frac * t / omega[o]) as f64;
                    let k = (o * np + p) * nl + l;
                    sum[k] += x;
                    sum2[k] += x * x;
                }
            }
        }
    };
    for chunk_start in (0..nl).step_by(4) {
        let idx: Vec<usize> = (chunk_start..(chunk_start + 4).min(nl)).collect();
        let lam = |c: usize| settings.wavelengths[idx[c.min(idx.len() - 1)]];
        let wl0 = SampledWavelengths::from_parts([lam(0), lam(1), lam(2), lam(3)], [1.0; 4]);
        for _ in 0..n_photons {
            let mut wl = wl0;
            let Some((d, thr)) = specimen.scatter(to_source, &mut rng, &mut wl) else {
                continue;
            };
            if !wl.secondary_terminated() {
                let mut t = [(0usize, 0.0f32); 4];
                for (c, &l) in idx.iter().enumerate() {
                    t[c] = (l, thr[c]);
                }
                record(d, &t[..idx.len()]);
            } else {
                // A dispersive event kept only the hero: the other wavelengths get their own
                // photons, each traced alone.
                record(d, &[(idx[0], thr[0])]);
                for (c, &l) in idx.iter().enumerate().skip(1) {
                    let mut wlc = SampledWavelengths::fixed(lam(c));
                    if let Some((dc, tc)) = specimen.scatter(to_source, &mut rng, &mut wlc) {
                        record(dc, &[(l, tc[0])]);
                    }
                }
            }
        }
    }
    let n = n_photons as f64;
    let mut values = vec![0.0f32; no * np * nl];
    let mut stderr = vec![0.0f32; no * np * nl];
    for k in 0..values.len() {
        let mean = sum[k] / n;
        let var = ((sum2[k] / n - mean * mean) * n / (n - 1.0)).max(0.0);
        let mut v = mean as f32;
        let mut e = (var / n).sqrt() as f32;
        if settings.noise > 0.0 {
            let g = gaussian(&mut rng);
            let clean = v;
            v = (v * (1.0 + settings.noise * g)).max(0.0);
            e = (e * e + (settings.noise * clean).powi(2)).sqrt();
        }
        values[k] = v;
        stderr[k] = e;
    }
    IncidentReadings { values, stderr }
}

/// A standard normal variate (Box–Muller).
fn gaussian(rng: &mut Pcg32) -> f32 {
    let u1 = rng.next_f32().max(1e-12);
    let u2 = rng.next_f32();
    (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
}

/// Runs the whole measurement (all source angles, one after the other) and returns the table.
pub fn measure(specimen: &dyn Sample, settings: &GonioSettings) -> Result<TabulatedData, String> {
    settings.validate()?;
    let readings: Vec<IncidentReadings> = (0..settings.incident)
        .map(|i| measure_incident(specimen, settings, i))
        .collect();
    assemble(specimen, settings, readings)
}

/// Builds the table from per-angle readings (in source-angle order).
pub fn assemble(
    specimen: &dyn Sample,
    settings: &GonioSettings,
    readings: Vec<IncidentReadings>,
) -> Result<TabulatedData, String> {
    settings.validate()?;
    let mut values = Vec::new();
    let mut stderr = Vec::new();
    for r in readings {
        values.extend(r.values);
        stderr.extend(r.stderr);
    }
    let description = format!(
        "measured by gonio's virtual gonioreflectometer: {}; {} photons per source angle, aperture \
         half-angle {} deg, detector noise {}, seed {}",
        specimen.describe(),
        settings.photons,
        settings.aperture_deg,
        settings.noise,
        settings.seed
    );
    TabulatedData::new(
        settings.theta_i_deg(),
        settings.theta_o_deg(),
        settings.phi_d_deg(),
        settings.wavelengths.clone(),
        values,
        Some(stderr),
        description,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projected_solid_angle_of_a_small_cone() {
        // Fully above the horizon: π sin²α cos θ.
        let a = 5f32.to_radians();
        let w = Vec3::new(0.5f32.sin(), 0.0, 0.5f32.cos());
        let exact = PI * a.sin().powi(2) * 0.5f32.cos();
        assert!((projected_solid_angle(w, a) - exact).abs() / exact < 1e-3);
        // Straddling the horizon: only the part above counts, and it is small.
        let h = projected_solid_angle(Vec3::X, a);
        assert!(h > 0.0 && h < 0.01 * PI * a.sin().powi(2) + 1e-3);
    }

    #[test]
    fn invalid_settings_are_named() {
        let s = GonioSettings {
            aperture_deg: 0.0,
            ..Default::default()
        };
        assert!(s.validate().unwrap_err().contains("aperture"));
        let s = GonioSettings {
            wavelengths: vec![-1.0],
            ..Default::default()
        };
        assert!(s.validate().unwrap_err().contains("wavelengths"));
    }
}
