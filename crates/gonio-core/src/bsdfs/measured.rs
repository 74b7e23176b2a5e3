//! `measured`: a BRDF measured by RGL's gonio-photometer and stored in the adaptive
//! parameterization of Dupuy and Jakob 2018, "An adaptive parameterization for efficient material
//! acquisition and rendering", ACM TOG 37(6) (the RGL material database's spectral `.bsdf` files;
//! as Mitsuba 3.9.1 plays them back in `src/bsdfs/measured.cpp`).
//!
//! The measurement is indexed not by ωo but by the point s ∈ [0, 1]² of the sample space from
//! which the visible-normal distribution of the material's own microfacet model warps to the
//! half vector h of (ωi, ωo). With (θ, φ) ↦ u = (√(2θ/π), (φ + π)/2π) the map of a direction to
//! the unit square, θi, φi the incidence and u_h that of h (its azimuth relative to φi for an
//! isotropic material, so the table's φi axis has one node):
//!
//! ```text
//!     s = V⁻¹(u_h | φi, θi)                 V the `vndf` warp (Marginal2D, continuous)
//!     f(ωi, ωo) cos θo = S(s | φi, θi, λ) · [D(u_h) / (4 σ(u_i))]   the bracket when `jacobian`
//! ```
//!
//! with S the `spectra` table, D the `ndf` and σ the projected area (`sigma`), all bilinear on
//! their grids and linear in φi, θi and λ ([`crate::marginal2d::Marginal2D`], Mitsuba's
//! interpolation). Anisotropic tables cover a quarter or a half turn of φi (`reduction` 4 or 2 =
//! 2π / the span, rounded); queries are mirrored into it by sign flips of x and y, as in
//! Mitsuba, into x ≤ 0, y ≤ 0 (reduction 4: φi ∈ [−π, −π/2]) or y ≤ 0 (any other reduction ≥ 2:
//! a half turn), and clamped to the axis's ends beyond it (a table over another quarter turn is
//! read at its end nodes, in Mitsuba too). A span of a full turn mirrors nothing.
//!
//! **Sampling** (Mitsuba's): s from the `luminance` warp, u_h = V(s), h from u_h, ωo its mirror
//! reflection of ωi; pdf = p_L(s) p_V(u_h) / J with J = max(2π² u_θ sin θh, 10⁻⁶) · 4 ωi·h (the
//! Jacobians of u ↦ h and h ↦ ωo); weight f cos θo / pdf. The warps are bijective and `invert`
//! gives the same densities, so the density of the sampled point equals `pdf(ωo)`; `sample`
//! reports `pdf(ωo)` and `eval(ωo)` themselves (in f32 they differ from the sampled point's by
//! up to 2·10⁻⁴, and by 0.5 % next to the mirror direction).
//!
//! Both transport modes evaluate the same table, as in Mitsuba: a measured table is reciprocal
//! only up to its measurement and interpolation errors (the battery's `reciprocity` and
//! `adjoint` rows see that). At normal incidence the density has an integrable 1/θ spike at the
//! mirror direction (the visible-normal table is 0 on its first column and linear next to it).
//!
//! One-sided: nothing unless μi > 0 and μo > 0. Spectral files only (Mitsuba too refuses an RGB
//! file in a spectral variant).
//!
//! Mitsuba 3 plugin `measured`:
//!
//! | parameter  | type   | default | meaning                                              |
//! |------------|--------|---------|------------------------------------------------------|
//! | `filename` | string | —       | the spectral `.bsdf` file (read by the scene loader) |

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::marginal2d::{Marginal2D, Marginal2DError};
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI, TAU};

/// A table of values over [0, 1]² per slice: (w, h) and the values.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Corners along x (the fastest index) and y.
    pub size: [usize; 2],
    /// The values, slices in parameter order, each row-major.
    pub values: Vec<f32>,
}

/// An RGL file's tables, as read (Mitsuba's field names).
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredData {
    /// The material's description.
    pub description: String,
    /// Whether the spectra are to be multiplied by D/(4σ) (`jacobian`).
    pub jacobian: bool,
    /// Incidence polar angles (radians, increasing).
    pub theta_i: Vec<f32>,
    /// Incidence azimuths (radians, increasing); two nodes or fewer mark an isotropic table.
    pub phi_i: Vec<f32>,
    /// Wavelengths of the spectra (nm, increasing).
    pub wavelengths: Vec<f32>,
    /// `ndf`: D over u_h (one slice).
    pub ndf: Grid,
    /// `sigma`: σ over u_i (one slice).
    pub sigma: Grid,
    /// `vndf`: one slice per (φi, θi).
    pub vndf: Grid,
    /// `luminance`: one slice per (φi, θi).
    pub luminance: Grid,
    /// `spectra`: one slice per (φi, θi, λ).
    pub spectra: Grid,
}

/// Why a file's tables were refused.
#[derive(Clone, Debug, PartialEq)]
pub enum MeasuredError {
    /// A table is malformed.
    Table {
        /// `ndf`, `sigma`, `vndf`, `luminance` or `spectra`.
        table: &'static str,
        /// What is wrong.
        error: Marginal2DError,
    },
    /// With `jacobian`, a projected area σ ≤ 0 (the spectra are divided by it).
    Sigma {
        /// Index into `sigma`.
        index: usize,
        /// The value.
        value: f32,
    },
}

impl std::fmt::Display for MeasuredError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Table { table, error } => write!(f, "table `{table}`: {error}"),
            Self::Sigma { index, value } => write!(
                f,
                "table `sigma`: value {value} at index {index}; with `jacobian` the spectra are divided by σ, which must be > 0"
            ),
        }
    }
}

impl std::error::Error for MeasuredError {}

/// Mitsuba `measured`: an RGL measured BRDF (see the module docs).
#[derive(Clone, Debug)]
pub struct Measured {
    description: String,
    jacobian: bool,
    isotropic: bool,
    reduction: i32,
    ndf: Marginal2D,
    sigma: Marginal2D,
    vndf: Marginal2D,
    luminance: Marginal2D,
    spectra: Marginal2D,
}

impl Measured {
    /// The BRDF of `data`'s tables (checked: sizes, finite non-negative values, increasing axes).
    pub fn new(data: MeasuredData) -> Result<Self, MeasuredError> {
        let err = |table| move |error| MeasuredError::Table { table, error };
        if data.jacobian
            && let Some(index) = data.sigma.values.iter().position(|v| !(*v > 0.0))
        {
            return Err(MeasuredError::Sigma {
                index,
                value: data.sigma.values[index],
            });
        }
        let incidence = vec![data.phi_i.clone(), data.theta_i.clone()];
        let isotropic = data.phi_i.len() <= 2;
        let reduction = if isotropic {
            0
        } else {
            (TAU / (data.phi_i[data.phi_i.len() - 1] - data.phi_i[0])).round() as i32
        };
        Ok(Self {
            description: data.description,
            jacobian: data.jacobian,
            isotropic,
            reduction,
            ndf: Marginal2D::new(data.ndf.size, vec![], &data.ndf.values, false, false)
                .map_err(err("ndf"))?,
            sigma: Marginal2D::new(data.sigma.size, vec![], &data.sigma.values, false, false)
                .map_err(err("sigma"))?,
            vndf: Marginal2D::new(data.vndf.size, incidence.clone(), &data.vndf.values, true, true)
                .map_err(err("vndf"))?,
            luminance: Marginal2D::new(data.luminance.size, incidence, &data.luminance.values, true, true)
                .map_err(err("luminance"))?,
            spectra: Marginal2D::new(
                data.spectra.size,
                vec![data.phi_i, data.theta_i, data.wavelengths],
                &data.spectra.values,
                false,
                false,
            )
            .map_err(err("spectra"))?,
        })
    }

    /// The material's description (from the file).
    pub fn description(&self) -> &str {
        &self.description
    }

    fn enabled(ctx: &BsdfContext) -> bool {
        ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION)
    }

    /// The sign flips that mirror `wi` into the table's azimuth range (none when isotropic).
    fn flips(&self, wi: Vec3) -> Option<(f32, f32)> {
        (self.reduction >= 2).then(|| {
            let sy = wi.y;
            let sx = if self.reduction == 4 { wi.x } else { sy };
            (sx, sy)
        })
    }

    /// The query in the table's frame: mirrored, with its incidence parameters and u_h.
    fn query(&self, wi: Vec3, wo: Vec3) -> (Vec3, [f32; 2], Vec2, Vec2) {
        let (wi, wo) = match self.flips(wi) {
            Some((sx, sy)) => (flip(wi, sx, sy), flip(wo, sx, sy)),
            None => (wi, wo),
        };
        let m = (wo + wi).normalize();
        let (theta_i, phi_i) = (elevation(wi), atan2(wi.y, wi.x));
        let (theta_m, phi_m) = (elevation(m), atan2(m.y, m.x));
        let u_wi = Vec2::new(theta2u(theta_i), phi2u(phi_i));
        let mut u_m = Vec2::new(
            theta2u(theta_m),
            phi2u(if self.isotropic { phi_m - phi_i } else { phi_m }),
        );
        u_m.y -= u_m.y.floor();
        (m, [phi_i, theta_i], u_wi, u_m)
    }

    /// f cos θo at the sample-space point `s` (Mitsuba's `spec`).
    fn spectrum(
        &self,
        s: Vec2,
        incidence: [f32; 2],
        u_wi: Vec2,
        u_m: Vec2,
        wl: &SampledWavelengths,
    ) -> SampledSpectrum {
        let mut spec = SampledSpectrum::ZERO;
        for k in 0..N_SPECTRUM_SAMPLES {
            spec[k] = self.spectra.eval(s, &[incidence[0], incidence[1], wl.lambda(k)]);
        }
        if self.jacobian {
            spec *= self.ndf.eval(u_m, &[]) / (4.0 * self.sigma.eval(u_wi, &[]));
        }
        spec
    }
}

/// `v` with x and y mirrored by Dr.Jit's `mulsign_neg` (x negated unless `sx` has its sign bit,
/// y likewise by `sy`).
#[inline]
fn flip(v: Vec3, sx: f32, sy: f32) -> Vec3 {
    Vec3::new(mulsign_neg(v.x, sx), mulsign_neg(v.y, sy), v.z)
}

/// a · −sign(b), by sign bits (−0 counts as negative): Dr.Jit's `mulsign_neg`.
#[inline]
fn mulsign_neg(a: f32, b: f32) -> f32 {
    f32::from_bits(a.to_bits() ^ (!b.to_bits() & 0x8000_0000))
}

/// atan2 as Dr.Jit computes it, blind to the sign of zero: atan2(±0, x < 0) = π and
/// atan2(±0, ±0) = 0 (a mirrored query has y = −0 and must read φi = π as Mitsuba does).
#[inline]
fn atan2(y: f32, x: f32) -> f32 {
    (y + 0.0).atan2(x + 0.0)
}

/// The polar angle of a unit vector, accurate near the pole: 2 asin(|d − z|/2).
#[inline]
fn elevation(d: Vec3) -> f32 {
    let dist = (d.x * d.x + d.y * d.y + (d.z - 1.0) * (d.z - 1.0)).sqrt();
    2.0 * (0.5 * dist).clamp(-1.0, 1.0).asin()
}

#[inline]
fn theta2u(theta: f32) -> f32 {
    (theta * (2.0 / PI)).sqrt()
}

#[inline]
fn phi2u(phi: f32) -> f32 {
    (phi + PI) * (0.5 / PI)
}

#[inline]
fn u2theta(u: f32) -> f32 {
    u * u * FRAC_PI_2
}

#[inline]
fn u2phi(u: f32) -> f32 {
    (2.0 * u - 1.0) * PI
}

/// The Jacobian of u_h ↦ ωo: max(2π² u_θ sin θh, 10⁻⁶) · 4 ωi·h.
#[inline]
fn jacobian(u_theta: f32, sin_theta_m: f32, wi_dot_m: f32) -> f32 {
    (2.0 * PI * PI * u_theta * sin_theta_m).max(1e-6) * 4.0 * wi_dot_m
}

impl Bsdf for Measured {
    fn flags(&self) -> BsdfFlags {
        if self.isotropic {
            BsdfFlags::GLOSSY_REFLECTION
        } else {
            BsdfFlags::GLOSSY_REFLECTION | BsdfFlags::ANISOTROPIC
        }
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if !Self::enabled(ctx) || wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.value_pdf(wi, wo, Some(wl)).0 * (1.0 / wo.z)
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> f32 {
        if !Self::enabled(ctx) || wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        self.value_pdf(wi, wo, None).1
    }

    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        if !Self::enabled(ctx) || wi.z <= 0.0 || wo.z <= 0.0 {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let (v, pdf) = self.value_pdf(wi, wo, Some(wl));
        (v * (1.0 / wo.z), pdf)
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        _u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !Self::enabled(ctx) || wi.z <= 0.0 {
            return None;
        }
        let wo = self.sample_direction(wi, u2)?;
        let (value, pdf) = self.value_pdf(wi, wo, Some(wl));
        if !(pdf > 0.0) {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: value * (1.0 / pdf),
            pdf,
            flags: BsdfFlags::GLOSSY_REFLECTION,
            eta: 1.0,
        })
    }
}

impl Measured {
    /// (f cos θo, pdf) at (ωi, ωo), both above the surface: Mitsuba's `eval` and `pdf` sharing
    /// the query and the inverse warp (`wl` `None`: the pdf alone).
    fn value_pdf(&self, wi: Vec3, wo: Vec3, wl: Option<&SampledWavelengths>) -> (SampledSpectrum, f32) {
        let (m, incidence, u_wi, u_m) = self.query(wi, wo);
        let Some((s, vndf_pdf)) = self.vndf.invert(u_m, &incidence) else {
            return (SampledSpectrum::ZERO, 0.0);
        };
        let value = wl.map_or(SampledSpectrum::ZERO, |wl| {
            self.spectrum(s, incidence, u_wi, u_m, wl)
        });
        // Finite tables can still overflow f32 in D/(4σ) · S: 0 rather than ∞ or NaN.
        let value = if value.is_finite() {
            value
        } else {
            SampledSpectrum::ZERO
        };
        let lum = self.luminance.eval(s, &incidence);
        let wi_mirrored = match self.flips(wi) {
            Some((sx, sy)) => flip(wi, sx, sy),
            None => wi,
        };
        // Mitsuba's `sin_theta`: √(x² + y²), not √(1 − z²), whose cancellation near the normal
        // is 10⁻³ off there.
        let sin_theta_m = (m.x * m.x + m.y * m.y).sqrt();
        let pdf = vndf_pdf * lum / jacobian(u_m.x, sin_theta_m, wi_mirrored.dot(m));
        (value, if pdf.is_finite() { pdf.max(0.0) } else { 0.0 })
    }

    /// The direction Mitsuba's `sample` draws (luminance warp, then the visible-normal warp,
    /// then the mirror reflection), `None` below the surface or where its density is not
    /// positive. Its value and pdf are then those of [`Bsdf::eval_pdf`] at it: Mitsuba reports
    /// the density and value of the sampled point instead, the same in exact arithmetic, but in
    /// f32 up to 2·10⁻⁴ and, next to the mirror direction (h at the normal, where the
    /// visible-normal table's first column vanishes), 0.5 % apart; MIS and the battery want the
    /// pdf and eval themselves.
    fn sample_direction(&self, wi_query: Vec3, u2: Vec2) -> Option<Vec3> {
        let flips = self.flips(wi_query);
        let wi = match flips {
            Some((sx, sy)) => flip(wi_query, sx, sy),
            None => wi_query,
        };
        let (theta_i, phi_i) = (elevation(wi), atan2(wi.y, wi.x));
        let incidence = [phi_i, theta_i];
        // Mitsuba draws from (u2.y, u2.x).
        let (s, lum_pdf) = self.luminance.sample(Vec2::new(u2.y, u2.x), &incidence)?;
        let (u_m, vndf_pdf) = self.vndf.sample(s, &incidence)?;
        let mut phi_m = u2phi(u_m.y);
        let theta_m = u2theta(u_m.x);
        if self.isotropic {
            phi_m += phi_i;
        }
        let (sin_phi, cos_phi) = phi_m.sin_cos();
        let (sin_theta, cos_theta) = theta_m.sin_cos();
        let m = Vec3::new(cos_phi * sin_theta, sin_phi * sin_theta, cos_theta);
        let pdf = vndf_pdf * lum_pdf / jacobian(u_m.x, sin_theta, wi.dot(m));
        let mut wo = 2.0 * m.dot(wi) * m - wi;
        if let Some((sx, sy)) = flips {
            wo = flip(wo, sx, sy);
        }
        (wo.z > 0.0 && pdf > 0.0 && pdf.is_finite()).then_some(wo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tiny isotropic table: 2 × 2 grids, two incidences, two wavelengths.
    fn data() -> MeasuredData {
        let grid = |n: usize| Grid {
            size: [2, 2],
            values: vec![1.0; 4 * n],
        };
        MeasuredData {
            description: "test".into(),
            jacobian: true,
            theta_i: vec![0.0, 1.0],
            phi_i: vec![0.0],
            wavelengths: vec![400.0, 700.0],
            ndf: grid(1),
            sigma: grid(1),
            vndf: grid(2),
            luminance: grid(2),
            spectra: grid(4),
        }
    }

    #[test]
    fn tables_that_would_divide_by_zero_or_overflow_are_refused() {
        assert!(Measured::new(data()).is_ok());
        let mut d = data();
        d.sigma.values[2] = 0.0;
        assert_eq!(
            Measured::new(d).unwrap_err(),
            MeasuredError::Sigma { index: 2, value: 0.0 }
        );
        let mut d = data();
        d.jacobian = false;
        d.sigma.values[2] = 0.0;
        assert!(Measured::new(d).is_ok(), "σ is not used without `jacobian`");
        let mut d = data();
        d.luminance.values = vec![1e-40; 8];
        assert!(matches!(
            Measured::new(d),
            Err(MeasuredError::Table {
                table: "luminance",
                ..
            })
        ));
    }

    #[test]
    fn an_overflowing_value_is_zero_not_infinite() {
        let mut d = data();
        d.spectra.values = vec![3e38; 16];
        d.ndf.values = vec![10.0; 4];
        d.sigma.values = vec![1e-3; 4];
        let m = Measured::new(d).unwrap();
        let wl = SampledWavelengths::fixed(500.0);
        let ctx = BsdfContext::radiance();
        let (wi, wo) = (
            Vec3::new(0.3, 0.1, 0.9).normalize(),
            Vec3::new(-0.2, 0.0, 0.9).normalize(),
        );
        let (f, pdf) = m.eval_pdf(&ctx, wi, wo, &wl);
        assert!(f.is_finite() && pdf.is_finite(), "{f:?} {pdf}");
    }

    #[test]
    fn mulsign_neg_follows_the_sign_bit() {
        assert_eq!(mulsign_neg(2.0, 3.0), -2.0);
        assert_eq!(mulsign_neg(2.0, -3.0), 2.0);
        assert_eq!(mulsign_neg(2.0, 0.0), -2.0);
        assert_eq!(mulsign_neg(2.0, -0.0), 2.0);
        assert_eq!(mulsign_neg(-2.0, 1.0), 2.0);
    }

    #[test]
    fn the_unit_square_maps_invert_each_other() {
        for k in 0..20 {
            let (theta, phi) = (k as f32 * 0.07, -3.0 + k as f32 * 0.3);
            assert!((u2theta(theta2u(theta)) - theta).abs() < 1e-6);
            assert!((u2phi(phi2u(phi)) - phi).abs() < 1e-5);
            let d = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
            assert!((elevation(d) - theta).abs() < 1e-5, "{theta}");
        }
    }
}
