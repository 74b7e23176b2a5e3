//! Lights at infinity: `constant` (uniform environment) and `envmap` (lat-long image).
//!
//! # Mitsuba parameters
//!
//! * `constant`: `radiance` (spectrum, default 1; an RGB value is uplifted as an illuminant, i.e.
//!   × D65, by the scene reader).
//! * `envmap`: `filename` (lat-long EXR/HDR image, linear RGB), `scale` (default 1), `to_world`
//!   (default identity), `mis_compensation` (Mitsuba's default false; ours true: see Sampling);
//!   ours: `product_sampling` (default true: see Sampling).
//!
//! # Orientation (Mitsuba 3 `envmap.cpp`)
//!
//! A world direction d is taken to the emitter's frame, v = to_world⁻¹·d, and mapped to
//! u = atan2(v.x, −v.z)/(2π) (wrapped into [0, 1)), v = acos(v.y)/π: the image's top row is +y
//! (up), its centre column looks down −z. Inversely, (θ, φ) = (π v, 2π u) gives
//! v = (sin θ sin φ, cos θ, −sin θ cos φ).
//!
//! # Texels
//!
//! A texel is an area of the sphere: column i covers u ∈ [i, i + 1]/W (wrapping around), row j
//! covers v ∈ [j, j + 1]/H; its value sits at its centre and between centres the lookup is
//! bilinear in the texels' radiance spectra, Σ wᵢ Lᵢ(λ), so the colour between texels is the
//! bilinear interpolation of the image's colours.
//!
//! Mitsuba 3.9.1 (`envmap.cpp`, `eval_spectrum`) differs twice: its row j sits at v = j/(H − 1)
//! (the first row at the north pole, the last at the south pole: the image stretched by
//! H/(H − 1)), and it stores each texel as a shape sᵢ(λ) (the sigmoid of rgb/(2 max)) and a scale
//! fᵢ = 2 max(rgb), interpolated separately, (Σ wᵢ sᵢ)(Σ wᵢ fᵢ)·D65: between a bright and a dim
//! texel of different colours the dim one's colour gets the bright one's weight (under
//! `museum.exr` a diffuse plane's red comes out 1.2 % above the bilinear radiance's).
//! [`EnvMapLight::with_mitsuba_lookup`] (the plugin's `lookup="mitsuba"`) reproduces both.
//!
//! # Sampling
//!
//! `constant` samples a cosine-weighted hemisphere about the shading normal when only reflection
//! lobes can use the light (zero variance for an unoccluded Lambertian surface), the uniform
//! sphere otherwise. `envmap` samples pixels ∝ luminance·sin θ (a 2D piecewise-constant
//! distribution), so the solid-angle density is p(u, v)/(2π² sin θ).
//!
//! With MIS compensation (Karlík et al. 2019, "MIS compensation: optimizing sampling
//! techniques in multiple importance sampling"; Mitsuba's `mis_compensation`), next-event
//! estimation samples ∝ max(L − L̄, 0)·sin θ instead, L̄ = ∫L dω/4π the mean luminance over the
//! sphere: where the map is dimmer than its mean, BSDF sampling (which the power heuristic
//! weighs against the light) already does well, so the light's samples go where it outshines
//! the mean. Only callers that sample the BSDF too may use it ([`super::LightRef::mis`]);
//! emission sampling (the particle tracer) and NEE without BSDF samples keep the plain density,
//! whose support is the whole lit sphere. A map with no texel above its mean (a uniform one)
//! keeps the plain density everywhere.
//!
//! With product sampling (ours), next-event estimation at a surface that only reflects draws
//! directions ∝ that density × max(0, n·ω) for the cell of its shading normal
//! ([`super::envmap_product`]), under the same condition as compensation (the BSDF is sampled
//! too).
//!
//! For resampled next-event estimation at glossy surfaces (`integrator/resampled.rs`) the map
//! also has a coarse luminance table ([`EnvMapLight::resampling_luminance`], in
//! `infinite/resampling.rs`).

use super::LightRef;
use super::envmap_product::CosineProduct;
use glam::Vec4;
use glam::{Affine3A, Vec2, Vec3};
use gonio_core::color::luminance;
use gonio_core::math::floor;
use gonio_core::rgb2spec::RgbSigmoid;
use gonio_core::sampling::Distribution2D;
use gonio_core::spectra::RgbKind;
use gonio_core::warp;
use gonio_core::{Frame, SampledSpectrum, SampledWavelengths, Spectrum};
use rayon::prelude::*;
use std::f32::consts::{PI, TAU};

mod resampling;
pub use resampling::ResamplingLookup;

/// `constant`: the same radiance from every direction.
#[derive(Clone, Debug)]
pub struct ConstantLight {
    /// Radiance.
    pub radiance: Spectrum,
}

impl ConstantLight {
    /// Radiance arriving from any direction.
    pub fn le(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        self.radiance.sample(wl)
    }

    /// Direction towards the light and its solid-angle density.
    pub fn sample_dir(&self, r: &LightRef, u: Vec2) -> (Vec3, f32) {
        if r.hemisphere {
            let local = warp::square_to_cosine_hemisphere(u);
            let pdf = warp::square_to_cosine_hemisphere_pdf(local);
            (Frame::from_normal(r.n).to_world(local), pdf)
        } else {
            (
                warp::square_to_uniform_sphere(u),
                warp::square_to_uniform_sphere_pdf(),
            )
        }
    }

    /// Density of [`Self::sample_dir`] for `dir`.
    pub fn pdf_dir(&self, r: &LightRef, dir: Vec3) -> f32 {
        if r.hemisphere {
            (r.n.dot(dir)).max(0.0) * std::f32::consts::FRAC_1_PI
        } else {
            warp::square_to_uniform_sphere_pdf()
        }
    }

    /// Mean radiance over the sphere (a scalar for light selection).
    pub fn mean_radiance(&self) -> f32 {
        self.radiance.mean()
    }
}

/// An `envmap` emitter: linear RGB lat-long image, each texel uplifted once when the light is
/// built; a lookup interpolates the four nearest texels' spectra at the path's wavelengths (as
/// Mitsuba's spectral `envmap` does), never uplifting at render time.
#[derive(Clone)]
pub struct EnvMapLight {
    width: usize,
    height: usize,
    rgb: Vec<[f32; 3]>,
    /// `uplift` of each texel of `rgb`.
    spectra: Vec<Spectrum>,
    /// The same texels as sigmoid polynomials and scales, 16 bytes each, when every one is an
    /// RGB uplift of one kind (`kind`): the lookup then weights four sigmoids and applies the
    /// kind's common factor (D65 for an illuminant) once instead of per texel.
    sigmoids: Option<(Vec<(RgbSigmoid, f32)>, RgbKind)>,
    scale: f32,
    to_world: Affine3A,
    to_local: Affine3A,
    distribution: Distribution2D,
    /// The compensated density of next-event estimation (module docs), if built and if some
    /// texel outshines the mean.
    compensated: Option<Distribution2D>,
    /// Next-event sampling × the clamped cosine (module docs), if asked for.
    product: Option<CosineProduct>,
    mean_luminance: f32,
    /// The brightest texel's share of the plain density, per steradian (see
    /// [`EnvMapLight::feature_density`]).
    feature_density: f32,
    /// Mitsuba 3.9.1's row layout and separate interpolation of shapes and scales (module docs).
    mitsuba_lookup: bool,
    /// The coarse luminance table of [`EnvMapLight::resampling_luminance`], built once, by
    /// [`EnvMapLight::prepare_resampling`] or the first lookup (a pure function of the map:
    /// images do not depend on which thread built it).
    resampling_table: std::sync::OnceLock<Box<[f32]>>,
}

impl std::fmt::Debug for EnvMapLight {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EnvMapLight")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("scale", &self.scale)
            .finish()
    }
}

impl EnvMapLight {
    /// From a row-major linear RGB image (top row first), a scale, the emitter-to-world
    /// transform and the function that turns an RGB radiance into an emission spectrum (the
    /// illuminant uplift, × D65 in spectral mode). Returns `None` for an empty image or a
    /// singular transform.
    pub fn new(
        width: usize,
        height: usize,
        rgb: Vec<[f32; 3]>,
        scale: f32,
        to_world: Affine3A,
        uplift: fn([f32; 3]) -> Spectrum,
    ) -> Option<Self> {
        if width == 0 || height == 0 || rgb.len() != width * height || to_world.matrix3.determinant() == 0.0 {
            return None;
        }
        let rgb: Vec<[f32; 3]> = rgb
            .into_iter()
            .map(|c| c.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 }))
            .collect();
        let weights = texel_weights(&rgb, width, height, |l| l);
        let total: f64 = weights.iter().map(|&w| w as f64).sum();
        // ∫ L dω / 4π with dω = sin θ (2π/W)(π/H).
        let mean_luminance = (total * (TAU as f64 / width as f64) * (PI as f64 / height as f64)
            / (4.0 * PI as f64)) as f32
            * scale;
        let distribution = Distribution2D::new(&weights, width, height);
        // Solid-angle density L·sin θ/(Σ L sin θ · 2π²/(W·H) · sin θ) at the brightest texel.
        let max_luminance = rgb.iter().map(|&c| luminance(c)).fold(0.0f32, f32::max) as f64;
        let feature_density = if total > 0.0 {
            (max_luminance * (width * height) as f64 / (2.0 * (PI as f64).powi(2) * total)) as f32
        } else {
            0.0
        };
        // The compact (sigmoid, scale) form when every texel is an RGB uplift of one kind (the
        // spectra themselves are then not kept: 200 MB for a 4096 × 2048 map); else the spectra.
        let (spectra, sigmoids) = match compact_sigmoids(&rgb, uplift) {
            Some(compact) => (Vec::new(), Some(compact)),
            None => (rgb.iter().map(|&c| uplift(c)).collect(), None),
        };
        Some(Self {
            width,
            height,
            rgb,
            spectra,
            sigmoids,
            scale,
            to_world,
            to_local: to_world.inverse(),
            distribution,
            compensated: None,
            product: None,
            mean_luminance,
            feature_density,
            mitsuba_lookup: false,
            resampling_table: std::sync::OnceLock::new(),
        })
    }

    /// The same light whose next-event samples, where the caller also samples the BSDF, follow
    /// max(L − L̄, 0)·sin θ (MIS compensation, module docs).
    pub fn with_mis_compensation(mut self) -> Self {
        let (w, h) = (self.width, self.height);
        // L̄ without the scale (the weights are the image's own luminances).
        let mean = self.mean_luminance / self.scale;
        let weights = texel_weights(&self.rgb, w, h, |l| (l - mean).max(0.0));
        let any = weights.iter().any(|&x| x > 0.0);
        self.compensated = (any && mean.is_finite()).then(|| Distribution2D::new(&weights, w, h));
        if self.product.is_some() {
            self = self.with_product_sampling();
        }
        self
    }

    /// The same light whose next-event samples, where the caller also samples the BSDF and it
    /// only reflects, follow its next-event density × the clamped cosine at the shading normal
    /// (module docs, [`super::envmap_product`]).
    pub fn with_product_sampling(mut self) -> Self {
        let (w, h) = (self.width, self.height);
        let weights = texel_weights(&self.rgb, w, h, |l| l);
        // Compensated locally, by half each normal cell's own mean, where the light compensates.
        let compensation = if self.compensated.is_some() { 0.5 } else { 0.0 };
        self.product = CosineProduct::new(&weights, w, h, compensation, |uv| self.uv_to_dir(uv));
        self
    }

    /// The density that next-event estimation draws from: the compensated one when the caller
    /// also samples the BSDF (`mis`) and it exists.
    #[inline]
    fn nee_distribution(&self, mis: bool) -> &Distribution2D {
        match &self.compensated {
            Some(c) if mis => c,
            _ => &self.distribution,
        }
    }

    /// The product tables when next-event estimation from `r` uses them: the BSDF there is
    /// sampled too and only reflects.
    #[inline]
    fn nee_product(&self, r: &LightRef) -> Option<&CosineProduct> {
        self.product.as_ref().filter(|_| r.mis && r.hemisphere)
    }

    /// The same light with Mitsuba 3.9.1's lookup: rows at v = j/(H − 1), texel shapes and
    /// scales interpolated separately and multiplied (module docs).
    pub fn with_mitsuba_lookup(mut self) -> Self {
        self.mitsuba_lookup = true;
        self
    }

    /// World direction → image coordinates in [0, 1)².
    pub fn dir_to_uv(&self, dir: Vec3) -> Vec2 {
        self.dir_to_uv_sin(dir).0
    }

    /// [`Self::dir_to_uv`] and sin θ of the direction, taken from its components (near a pole
    /// acos(cos θ) rounds to 0 in single precision, sin(π v) with it, but the direction's own
    /// distance from the axis does not).
    fn dir_to_uv_sin(&self, dir: Vec3) -> (Vec2, f32) {
        let v = self.to_local.transform_vector3(dir).normalize_or_zero();
        let mut u = v.x.atan2(-v.z) / TAU;
        u -= floor(u);
        let t = v.y.clamp(-1.0, 1.0).acos() / PI;
        (Vec2::new(u.min(1.0 - f32::EPSILON), t), v.x.hypot(v.z))
    }

    /// Image coordinates → world direction (unit).
    pub fn uv_to_dir(&self, uv: Vec2) -> Vec3 {
        let (st, ct) = (PI * uv.y).sin_cos();
        let (sp, cp) = (TAU * uv.x).sin_cos();
        let local = Vec3::new(st * sp, ct, -st * cp);
        self.to_world.transform_vector3(local).normalize()
    }

    /// The four texels around `uv` (columns at (i + ½)/W, wrapping; rows at (j + ½)/H,
    /// clamping, or at j/(H − 1) in Mitsuba's layout) and their bilinear weights.
    fn bilinear(&self, uv: Vec2) -> [(usize, f32); 4] {
        let (w, h) = (self.width as isize, self.height as isize);
        let x = uv.x * w as f32 - 0.5;
        let (y, y0) = if self.mitsuba_lookup {
            let rows = (h - 1).max(1) as f32;
            let y = uv.y.clamp(0.0, 1.0) * rows;
            (y, floor(y).min(rows - 1.0).max(0.0))
        } else {
            let y = uv.y * h as f32 - 0.5;
            (y, floor(y))
        };
        let x0 = floor(x);
        let (fx, fy) = (x - x0, y - y0);
        // Columns wrap around (once, then its neighbour), rows clamp.
        let i0 = gonio_core::math::wrap_repeat(x0 as i64, w as i64) as usize;
        let i1 = if i0 + 1 == self.width { 0 } else { i0 + 1 };
        let y0 = y0 as isize;
        let row = |j: isize| j.clamp(0, h - 1) as usize * self.width;
        let (r0, r1) = (row(y0), row(y0 + 1));
        [
            (r0 + i0, (1.0 - fx) * (1.0 - fy)),
            (r0 + i1, fx * (1.0 - fy)),
            (r1 + i0, (1.0 - fx) * fy),
            (r1 + i1, fx * fy),
        ]
    }

    /// Bilinear RGB lookup between pixel centres, wrapping in u and clamping in v.
    pub fn lookup_rgb(&self, uv: Vec2) -> [f32; 3] {
        let mut out = [0.0f32; 3];
        for (i, w) in self.bilinear(uv) {
            for (o, c) in out.iter_mut().zip(self.rgb[i]) {
                *o += w * c;
            }
        }
        out
    }

    /// Radiance arriving from world direction `dir` (travelling towards the viewer along −dir):
    /// the bilinear interpolation of the uplifted texels, × `scale`.
    pub fn le(&self, dir: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.le_uv(self.dir_to_uv(dir), wl)
    }

    /// [`Self::le`] at image coordinates `uv` (a sampled direction's, without mapping it back).
    fn le_uv(&self, uv: Vec2, wl: &SampledWavelengths) -> SampledSpectrum {
        if self.mitsuba_lookup {
            return self.le_mitsuba(uv, wl);
        }
        if let Some((sigmoids, kind)) = &self.sigmoids {
            // Σ wᵢ fᵢ sᵢ(λ), then the factor all texels share.
            let (acc, _) = self.sigmoid_sums(sigmoids, *kind, uv, wl, |w, f| w * f);
            return SampledSpectrum(acc * self.scale);
        }
        let mut l = SampledSpectrum::ZERO;
        for (i, w) in self.bilinear(uv) {
            if w > 0.0 && self.rgb[i] != [0.0; 3] {
                l += self.spectra[i].sample(wl) * w;
            }
        }
        l * self.scale
    }

    /// The sums both lookups of a map of sigmoids take over the four texels around `uv`
    /// ([`Self::bilinear`]) whose scale fᵢ is positive: Σ weight(wᵢ, fᵢ)·sᵢ(λ) (× D65 for an
    /// emission map, a factor all texels share) and Σ wᵢ fᵢ.
    #[inline]
    fn sigmoid_sums(
        &self,
        sigmoids: &[(RgbSigmoid, f32)],
        kind: RgbKind,
        uv: Vec2,
        wl: &SampledWavelengths,
        weight: impl Fn(f32, f32) -> f32,
    ) -> (Vec4, f32) {
        let lambda = Vec4::from_array(wl.lambdas());
        let (mut acc, mut f) = (Vec4::ZERO, 0.0f32);
        for (i, w) in self.bilinear(uv) {
            let (sigmoid, fi) = sigmoids[i];
            if w > 0.0 && fi > 0.0 {
                acc += sigmoid.eval4(lambda) * weight(w, fi);
                f += fi * w;
            }
        }
        if kind == RgbKind::Illuminant {
            acc *= Vec4::from_array(wl.d65());
        }
        (acc, f)
    }

    /// Mitsuba 3.9.1's lookup: (Σ wᵢ sᵢ)(Σ wᵢ fᵢ)·scale, a texel's spectrum split into its
    /// scale fᵢ (2 max(rgb) for an RGB uplift, the value of a constant) and its shape sᵢ = Lᵢ/fᵢ
    /// (which keeps the D65 factor, common to all texels).
    fn le_mitsuba(&self, uv: Vec2, wl: &SampledWavelengths) -> SampledSpectrum {
        let mut shape = SampledSpectrum::ZERO;
        let mut f = 0.0f32;
        if let Some((sigmoids, kind)) = &self.sigmoids {
            // A texel's shape is its sigmoid (× D65, common to all texels), its scale f.
            let (acc, f) = self.sigmoid_sums(sigmoids, *kind, uv, wl, |w, _| w);
            return SampledSpectrum(acc) * (f * self.scale);
        }
        for (i, w) in self.bilinear(uv) {
            let (s, fi) = match &self.spectra[i] {
                Spectrum::Rgb(r) if r.scale > 0.0 => (self.spectra[i].sample(wl) / r.scale, r.scale),
                Spectrum::Rgb(_) => (SampledSpectrum::ZERO, 0.0),
                Spectrum::Constant(c) if *c > 0.0 => (SampledSpectrum::splat(1.0), *c),
                Spectrum::Constant(_) => (SampledSpectrum::ZERO, 0.0),
                other => (other.sample(wl), 1.0),
            };
            shape += s * w;
            f += fi * w;
        }
        shape * (f * self.scale)
    }

    /// Direction towards the light ∝ luminance·sin θ, and its solid-angle density (the plain
    /// density, whose support is every direction the map lights: emission sampling).
    pub fn sample_dir(&self, u: Vec2) -> Option<(Vec3, f32)> {
        self.sample_uv(u, &LightRef::EMISSION)
            .map(|(uv, pdf)| (self.uv_to_dir(uv), pdf))
    }

    /// A next-event direction from `r` with the radiance arriving from it, looked up at the
    /// sampled image coordinates: where `r` also samples the BSDF and weighs both by MIS
    /// (`r.mis`), the compensated density if the light has one, × the clamped cosine if the
    /// light does product sampling and the BSDF only reflects; else [`Self::sample_dir`]'s.
    pub fn sample_dir_le(
        &self,
        u: Vec2,
        wl: &SampledWavelengths,
        r: &LightRef,
    ) -> Option<(Vec3, f32, SampledSpectrum)> {
        self.sample_uv(u, r)
            .map(|(uv, pdf)| (self.uv_to_dir(uv), pdf, self.le_uv(uv, wl)))
    }

    /// Image coordinates from the next-event density for `r` and the solid-angle density of
    /// their direction.
    fn sample_uv(&self, u: Vec2, r: &LightRef) -> Option<(Vec2, f32)> {
        let (uv, pdf_uv) = match self.nee_product(r) {
            Some(p) => p.sample(r.n, u)?,
            None => self.nee_distribution(r.mis).sample(u),
        };
        let sin_theta = (PI * uv.y).sin();
        if pdf_uv <= 0.0 || sin_theta <= 0.0 {
            return None;
        }
        Some((uv, pdf_uv / (2.0 * PI * PI * sin_theta)))
    }

    /// Density with which [`Self::sample_dir_le`] (same `r`) draws world direction `dir`.
    pub fn pdf_dir(&self, dir: Vec3, r: &LightRef) -> f32 {
        let (uv, sin_theta) = self.dir_to_uv_sin(dir);
        self.pdf_uv(uv, sin_theta, r)
    }

    /// [`Self::le`] and [`Self::pdf_dir`] of one direction, mapped to the image once (a ray that
    /// escapes after a BSDF sample needs both).
    pub fn le_pdf(&self, dir: Vec3, wl: &SampledWavelengths, r: &LightRef) -> (SampledSpectrum, f32) {
        let (uv, sin_theta) = self.dir_to_uv_sin(dir);
        (self.le_uv(uv, wl), self.pdf_uv(uv, sin_theta, r))
    }

    /// Solid-angle density of the direction at image coordinates `uv`, whose sin θ is
    /// `sin_theta`.
    fn pdf_uv(&self, uv: Vec2, sin_theta: f32, r: &LightRef) -> f32 {
        if sin_theta <= 0.0 {
            return 0.0;
        }
        let pdf_uv = match self.nee_product(r) {
            Some(p) => p.pdf(r.n, uv),
            None => self.nee_distribution(r.mis).pdf(uv),
        };
        pdf_uv / (2.0 * PI * PI * sin_theta)
    }

    /// Mean luminance over the sphere, × scale (for light selection).
    pub fn mean_radiance(&self) -> f32 {
        self.mean_luminance
    }

    /// The largest solid-angle density of the map's luminance, L_max/∫L dω (1/sr): a feature
    /// of the map holding a fraction φ of its light spans at least φ/(this) steradians, so a
    /// BSDF lobe whose own peak density is several times this sees the map as smooth
    /// ([`super::Lights`]). 0 for a black map.
    pub fn feature_density(&self) -> f32 {
        self.feature_density
    }
}

/// Each texel's f(luminance)·sin θ (θ at the row's centre), row-major: the cell values of the
/// sampling distributions (plain: f(L) = L; compensated: max(L − L̄, 0)).
fn texel_weights(rgb: &[[f32; 3]], width: usize, height: usize, f: impl Fn(f32) -> f32) -> Vec<f32> {
    let mut weights = Vec::with_capacity(width * height);
    for j in 0..height {
        let sin_theta = (PI * (j as f32 + 0.5) / height as f32).sin();
        weights.extend(
            rgb[j * width..(j + 1) * width]
                .iter()
                .map(|&c| f(luminance(c)) * sin_theta),
        );
    }
    weights
}

/// The texels as (sigmoid, scale) pairs when all are RGB uplifts of one kind (a black texel, any
/// kind with scale 0, fits every kind); `None` otherwise (the lookup then samples each spectrum).
fn compact_sigmoids(
    rgb: &[[f32; 3]],
    uplift: fn([f32; 3]) -> Spectrum,
) -> Option<(Vec<(RgbSigmoid, f32)>, RgbKind)> {
    // The first texel with light decides the kind (a black one, of scale 0, fits every kind).
    let kind = match rgb.iter().map(|&c| uplift(c)).find(|s| !is_black_texel(s)) {
        Some(Spectrum::Rgb(r)) => r.kind,
        Some(_) => return None,
        None => RgbKind::Illuminant,
    };
    // Texel by texel, in parallel (the uplift is a table lookup per texel: a 4096 × 2048 map
    // has eight million), straight into one vector in the texels' order; a texel of another
    // form is marked by a NaN scale (an uplift's scale is finite).
    let black = (RgbSigmoid::constant(0.0), 0.0);
    let mut pairs = Vec::new();
    rgb.par_iter()
        .map(|&c| match uplift(c) {
            s if is_black_texel(&s) => black,
            Spectrum::Rgb(r) if r.kind == kind && r.scale.is_finite() => (r.sigmoid, r.scale),
            _ => (black.0, f32::NAN),
        })
        .collect_into_vec(&mut pairs);
    (!pairs.par_iter().any(|p| p.1.is_nan())).then_some((pairs, kind))
}

/// A texel without light: an RGB uplift of scale 0 or the constant 0.
fn is_black_texel(s: &Spectrum) -> bool {
    matches!(s, Spectrum::Rgb(r) if r.scale == 0.0) || matches!(s, Spectrum::Constant(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::uplift_emission_texel;

    /// Regression: a map whose texels are all RGB uplifts keeps only their (sigmoid, scale)
    /// pairs, black texels included (the uplift gives those the constant 0, which used to send
    /// the whole map to the per-texel spectra: 24 bytes a texel beside the pairs, 200 MB for a
    /// 4096 × 2048 map), and both lookups give what the texels' spectra give.
    #[test]
    fn a_map_with_black_texels_keeps_only_its_sigmoids_and_looks_up_the_same() {
        let (w, h) = (8, 4);
        let rgb: Vec<[f32; 3]> = (0..w * h)
            .map(|i| match i % 5 {
                0 => [0.0; 3],
                k => [0.3 * k as f32, 0.1 + 0.05 * k as f32, 2.0 / k as f32],
            })
            .collect();
        let texels: Vec<Spectrum> = rgb.iter().map(|&c| uplift_emission_texel(c)).collect();
        let env = EnvMapLight::new(w, h, rgb, 1.5, Affine3A::IDENTITY, uplift_emission_texel).unwrap();
        assert!(env.sigmoids.is_some() && env.spectra.is_empty());
        let mitsuba = env.clone().with_mitsuba_lookup();
        let wl = SampledWavelengths::sample_visible(0.3);
        for k in 0..97 {
            let uv = Vec2::new((k as f32 * 0.377).fract(), (k as f32 * 0.611).fract());
            // Σ wᵢ Lᵢ(λ) over the texels' own spectra.
            let mut expect = SampledSpectrum::ZERO;
            for (i, wi) in env.bilinear(uv) {
                expect += texels[i].sample(&wl) * wi;
            }
            let got = env.le_uv(uv, &wl);
            for j in 0..4 {
                assert!(
                    (got[j] - 1.5 * expect[j]).abs() <= 1e-5 * (1.0 + expect[j]),
                    "{uv}: {got:?} {expect:?}"
                );
            }
            // Mitsuba's (Σ wᵢ sᵢ)(Σ wᵢ fᵢ), the shapes sᵢ = Lᵢ/fᵢ of the non-black texels.
            let (mut shape, mut f) = (SampledSpectrum::ZERO, 0.0f32);
            for (i, wi) in mitsuba.bilinear(uv) {
                if let Spectrum::Rgb(r) = &texels[i] {
                    shape += texels[i].sample(&wl) / r.scale * wi;
                    f += r.scale * wi;
                }
            }
            let got = mitsuba.le_uv(uv, &wl);
            for j in 0..4 {
                let e = shape[j] * f * 1.5;
                assert!((got[j] - e).abs() <= 1e-5 * (1.0 + e), "{uv}: {got:?} vs {e}");
            }
        }
    }
}
