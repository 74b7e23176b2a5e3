//! `measured_polarized`: a measured isotropic polarimetric BRDF (pBRDF) played back, as Mitsuba
//! 3.9.1 does in `src/bsdfs/measured_polarized.cpp` for the KAIST dataset of Baek et al. 2020,
//! "Image-based acquisition and modeling of polarimetric reflectance", ACM TOG 39(4).
//!
//! The table holds a 4 × 4 Mueller matrix P(φd, θd, θh, λ) on a grid of the Rusinkiewicz (1998)
//! half/difference angles and of wavelength. With the light arriving along −ω̂o and leaving
//! along ω̂i (ω̂o = ωo, ω̂i = ωi in radiance mode, exchanged in importance mode, see
//! [`crate::bsdf::light_directions`]), both rotated about the normal so that ω̂i lies in the
//! x–z plane (the table is isotropic), and h = (ω̂i + ω̂o)/|ω̂i + ω̂o|:
//!
//! ```text
//!     θh = acos(h·n),  θd = acos(h·ω̂o),
//!     φd = atan2(b·p, t·p),  b = n×h/|n×h|,  t = b×h/|b×h|,  p = the projection of ω̂o ⟂ h,
//!     M(ωi, ωo) = R_out · P(φd, θd, θh, λ) · R_in,        f = M00
//! ```
//!
//! P maps Stokes vectors between the data's own frames, whose x axis is in both beams
//! s = −(ω̂i × ω̂o)/|ω̂i × ω̂o| (perpendicular to the plane of reflection; Baek et al. 2020,
//! Fig. 4; Mitsuba builds the two frames by cross products that reduce to this vector);
//! R_in and R_out rotate them to Mitsuba's implicit bases of −ω̂o and ω̂i.
//!
//! **Interpolation** (Mitsuba's `Marginal2D` without normalization): multilinear in the four
//! parameters, each weight clamped to [0, 1], so beyond an axis's ends the end values hold
//! (the dataset spans 450–650 nm; at 700 nm the 650 nm matrix is used). The dataset marks
//! configurations it could not measure by NaN (the whole matrix): when an interpolation touches
//! such a node (with any weight, zero included, as in Mitsuba) the whole matrix is 0 at every
//! wavelength. M00 is then clamped to ≥ 0 (the other elements are kept: the table's own noise
//! can make M unphysical). A node with only some elements NaN counts as unmeasured too; Mitsuba
//! zeroes the matrix only when the NaN is in M00, M01, M10 or M11 (the corners of its bilinear
//! lookup of M00) and otherwise returns NaN in that element: gonio never returns NaN.
//!
//! **Sampling** (Mitsuba's): with probability 0.1 a cosine-weighted direction, else the mirror
//! reflection of ωi about a GGX visible normal of roughness `alpha_sample`;
//! pdf = 0.1 μo/π + 0.9 D_ωi(h)/(4 ωo·h); weight f μo / pdf. `alpha_sample` only shapes the
//! noise, never the image. One-sided: nothing unless μi > 0 and μo > 0.
//!
//! Mitsuba 3 plugin `measured_polarized`:
//!
//! | parameter      | type   | default | meaning                                                  |
//! |----------------|--------|---------|----------------------------------------------------------|
//! | `filename`     | string | —       | the `.pbsdf` file (Mitsuba's tensor format; read by the scene loader) |
//! | `alpha_sample` | float  | 0.1     | GGX roughness of the sampling lobe (> 0)                 |
//! | `wavelength`   | float  | −1      | −1: spectral; else every wavelength looks up this one (nm) |

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, light_directions};
use crate::marginal2d::param_interval;
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
use crate::mueller::{Mueller, MuellerMatrix, StokesBasis};
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use crate::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::TAU;

/// Probability of the cosine-weighted lobe in [`MeasuredPolarized::sample`] (Mitsuba's
/// `COSINE_HEMISPHERE_PDF_WEIGHT`).
pub const COSINE_LOBE_PROBABILITY: f32 = 0.1;

/// Why a table was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum PbrdfError {
    /// An axis has no value.
    EmptyAxis(&'static str),
    /// An axis value is not finite or not larger than the one before it.
    BadAxis {
        /// `phi_d`, `theta_d`, `theta_h` or `wavelengths`.
        axis: &'static str,
        /// Index of the offending value.
        index: usize,
        /// The value.
        value: f32,
    },
    /// The matrix array's length is not the product of the axes' lengths times 16.
    Size {
        /// Elements expected.
        expected: usize,
        /// Elements given.
        got: usize,
    },
    /// A matrix element is ±∞ (NaN is allowed: it marks an unmeasured configuration).
    Infinite {
        /// Index into the matrix array.
        index: usize,
    },
}

impl std::fmt::Display for PbrdfError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::EmptyAxis(a) => write!(f, "axis `{a}` has no value"),
            Self::BadAxis { axis, index, value } => write!(
                f,
                "axis `{axis}`: value {value} at index {index} is not finite or not larger than the one before"
            ),
            Self::Size { expected, got } => write!(
                f,
                "the Mueller matrices hold {got} values, the axes call for {expected} (n_phi_d × n_theta_d × n_theta_h × n_wavelengths × 16)"
            ),
            Self::Infinite { index } => write!(f, "Mueller matrix value {index} is infinite"),
        }
    }
}

impl std::error::Error for PbrdfError {}

/// The measured table: axes (radians; wavelengths in nm) and the matrices
/// `m[((((p·n_θd + d)·n_θh + h)·n_λ + l)·4 + row)·4 + col]`.
#[derive(Clone, Debug, PartialEq)]
pub struct PbrdfTable {
    phi_d: Vec<f32>,
    theta_d: Vec<f32>,
    theta_h: Vec<f32>,
    wavelengths: Vec<f32>,
    m: Vec<f32>,
    /// Per node (φd, θd, θh, λ): some element of its matrix is NaN.
    nan_nodes: Vec<bool>,
}

impl PbrdfTable {
    /// Checks and wraps a table: every axis non-empty, finite and strictly increasing;
    /// `m.len()` = n_φd · n_θd · n_θh · n_λ · 16; no element infinite (NaN marks an unmeasured
    /// configuration).
    pub fn new(
        phi_d: Vec<f32>,
        theta_d: Vec<f32>,
        theta_h: Vec<f32>,
        wavelengths: Vec<f32>,
        m: Vec<f32>,
    ) -> Result<Self, PbrdfError> {
        for (axis, v) in [
            ("phi_d", &phi_d),
            ("theta_d", &theta_d),
            ("theta_h", &theta_h),
            ("wavelengths", &wavelengths),
        ] {
            if v.is_empty() {
                return Err(PbrdfError::EmptyAxis(axis));
            }
            for (index, &value) in v.iter().enumerate() {
                if !value.is_finite() || (index > 0 && value <= v[index - 1]) {
                    return Err(PbrdfError::BadAxis { axis, index, value });
                }
            }
        }
        let expected = [phi_d.len(), theta_d.len(), theta_h.len(), wavelengths.len(), 16]
            .iter()
            .try_fold(1usize, |a, &n| a.checked_mul(n))
            .unwrap_or(usize::MAX);
        if m.len() != expected {
            return Err(PbrdfError::Size {
                expected,
                got: m.len(),
            });
        }
        if let Some(index) = m.iter().position(|x| x.is_infinite()) {
            return Err(PbrdfError::Infinite { index });
        }
        let nan_nodes = m.chunks_exact(16).map(|n| n.iter().any(|x| x.is_nan())).collect();
        Ok(Self {
            phi_d,
            theta_d,
            theta_h,
            wavelengths,
            m,
            nan_nodes,
        })
    }

    /// Whether the stencil touches a node with a NaN element, at any weight.
    #[inline]
    fn touches_nan(&self, s: &Stencil) -> bool {
        s.lambda.iter().any(|lambda| {
            s.corners.iter().any(|&(base, _)| {
                lambda
                    .iter()
                    .any(|&(offset, _)| self.nan_nodes[(base + offset) / 16])
            })
        })
    }

    /// The wavelength axis (nm).
    pub fn wavelengths(&self) -> &[f32] {
        &self.wavelengths
    }

    /// The interpolation stencil at (φd, θd, θh) and the wavelengths `lambda`.
    fn stencil(&self, phi_d: f32, theta_d: f32, theta_h: f32, lambda: [f32; N_SPECTRUM_SAMPLES]) -> Stencil {
        let (p, d, h) = (
            axis_weight(&self.phi_d, phi_d),
            axis_weight(&self.theta_d, theta_d),
            axis_weight(&self.theta_h, theta_h),
        );
        let (n_d, n_h, n_l) = (self.theta_d.len(), self.theta_h.len(), self.wavelengths.len());
        let mut corners = [(0usize, 0.0f32); 8];
        for (c, corner) in corners.iter_mut().enumerate() {
            let (ip, wp) = p.corner(c & 1);
            let (id, wd) = d.corner((c >> 1) & 1);
            let (ih, wh) = h.corner((c >> 2) & 1);
            *corner = ((((ip * n_d) + id) * n_h + ih) * n_l * 16, wp * wd * wh);
        }
        let lambda = lambda.map(|l| {
            let w = axis_weight(&self.wavelengths, l);
            let ((i0, w0), (i1, w1)) = (w.corner(0), w.corner(1));
            [(i0 * 16, w0), (i1 * 16, w1)]
        });
        Stencil { corners, lambda }
    }

    /// Element (`row`, `col`) of the interpolated matrix at the stencil's wavelengths.
    #[inline]
    fn element(&self, s: &Stencil, row: usize, col: usize) -> SampledSpectrum {
        let e = row * 4 + col;
        let mut out = SampledSpectrum::ZERO;
        for (k, lambda) in s.lambda.iter().enumerate() {
            let mut v = 0.0;
            for &(base, w) in &s.corners {
                v += w
                    * (lambda[0].1 * self.m[base + lambda[0].0 + e]
                        + lambda[1].1 * self.m[base + lambda[1].0 + e]);
            }
            out[k] = v;
        }
        out
    }
}

/// Where a parameter falls on one axis: the lower node and the upper node's weight.
#[derive(Clone, Copy)]
struct AxisWeight {
    index: usize,
    last: usize,
    w1: f32,
}

impl AxisWeight {
    /// Node `0` (lower) or `1` (upper) and its weight; a one-node axis has only its node.
    #[inline]
    fn corner(self, upper: usize) -> (usize, f32) {
        if upper == 0 {
            (self.index, 1.0 - self.w1)
        } else {
            ((self.index + 1).min(self.last), self.w1)
        }
    }
}

/// Mitsuba's `Marginal2D` parameter lookup ([`param_interval`]), a one-node axis included.
#[inline]
fn axis_weight(axis: &[f32], x: f32) -> AxisWeight {
    let last = axis.len() - 1;
    if last == 0 {
        return AxisWeight {
            index: 0,
            last,
            w1: 0.0,
        };
    }
    let (index, w1) = param_interval(axis, x);
    AxisWeight { index, last, w1 }
}

/// The 8 spatial corners (offset into the matrices, weight) and, per wavelength, the two
/// wavelength nodes (offset, weight).
struct Stencil {
    corners: [(usize, f32); 8],
    lambda: [[(usize, f32); 2]; N_SPECTRUM_SAMPLES],
}

/// The azimuth of `v` in [0, 2π).
#[inline]
fn azimuth(v: Vec3) -> f32 {
    let p = v.y.atan2(v.x);
    if p < 0.0 { p + TAU } else { p }
}

/// `v` turned by `angle` about the z axis.
#[inline]
fn rotate_z(v: Vec3, angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    Vec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}

/// Rusinkiewicz's (φd, θh, θd) of the pair (`a`, `b`), with φd measured for `a` (Mitsuba calls
/// this with a = ω̂o, b = ω̂i). Where h is the normal (b undefined) or `a` is h (φd undefined),
/// the fallbacks give b = y and φd = 0; Mitsuba returns NaN there (a set of measure zero).
pub fn rusinkiewicz(a: Vec3, b: Vec3) -> (f32, f32, f32) {
    let h = (a + b).normalize_or_zero();
    let bn = Vec3::Z.cross(h).try_normalize().unwrap_or(Vec3::Y);
    let t = bn.cross(h).normalize_or_zero();
    let theta_d = a.dot(h).clamp(-1.0, 1.0).acos();
    let theta_h = h.z.clamp(-1.0, 1.0).acos();
    let phi_d = match (a - a.dot(h) * h).try_normalize() {
        Some(p) => bn.dot(p).clamp(-1.0, 1.0).atan2(t.dot(p).clamp(-1.0, 1.0)),
        None => 0.0,
    };
    (phi_d, theta_h, theta_d)
}

/// Mitsuba `measured_polarized`: a measured pBRDF table (see the module docs).
#[derive(Clone, Debug)]
pub struct MeasuredPolarized {
    table: PbrdfTable,
    sampling: MicrofacetDistribution,
    wavelength: Option<f32>,
}

impl MeasuredPolarized {
    /// The table with the GGX sampling roughness `alpha_sample` (> 0) and, when `wavelength` is
    /// given, every lookup at that wavelength (Mitsuba's `wavelength` ≠ −1).
    pub fn new(table: PbrdfTable, alpha_sample: f32, wavelength: Option<f32>) -> Self {
        Self {
            table,
            sampling: MicrofacetDistribution::new(MicrofacetKind::Ggx, alpha_sample, alpha_sample, true),
            wavelength,
        }
    }

    /// The table.
    pub fn table(&self) -> &PbrdfTable {
        &self.table
    }

    fn enabled(ctx: &BsdfContext) -> bool {
        ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION)
    }

    /// The stencil of the query and the light's directions (−ω̂o's, ω̂i's).
    fn lookup(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (Stencil, Vec3, Vec3) {
        let (light_in, light_out) = light_directions(ctx, wi, wo);
        let (wo_hat, wi_hat) = (-light_in, light_out);
        let phi = azimuth(wi_hat);
        let (phi_d, theta_h, theta_d) = rusinkiewicz(rotate_z(wo_hat, -phi), rotate_z(wi_hat, -phi));
        let lambda = match self.wavelength {
            Some(l) => [l; N_SPECTRUM_SAMPLES],
            None => wl.lambdas(),
        };
        (
            self.table.stencil(phi_d, theta_d, theta_h, lambda),
            light_in,
            light_out,
        )
    }

    /// f = M00 with the NaN and sign rules, or `None` for an unmeasured configuration (then
    /// every element is 0).
    fn intensity(&self, s: &Stencil) -> Option<SampledSpectrum> {
        if self.table.touches_nan(s) {
            return None;
        }
        Some(self.table.element(s, 0, 0).map(|v| v.max(0.0)))
    }

    fn mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        let (s, light_in, light_out) = self.lookup(ctx, wi, wo, wl);
        let Some(m00) = self.intensity(&s) else {
            return Mueller::depolarizer(SampledSpectrum::ZERO);
        };
        let mut m = MuellerMatrix::ZERO;
        for (r, row) in m.0.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = if r + c == 0 {
                    m00
                } else {
                    self.table.element(&s, r, c)
                };
            }
        }
        // The data's frames: x perpendicular to the plane of reflection in both beams. Where
        // ω̂i ∥ ω̂o (retro-reflection, or the degenerate in-out pair) the plane is undefined:
        // Mitsuba's cross products give NaN there; gonio takes the implicit bases.
        let x = light_out.cross(-light_in).try_normalize().map(|n| -n);
        let (input, output) = match x {
            Some(x) => (StokesBasis::new(light_in, x), StokesBasis::new(light_out, x)),
            None => (StokesBasis::implicit(light_in), StokesBasis::implicit(light_out)),
        };
        Mueller::new(m, input, output)
            .in_bases(StokesBasis::implicit(light_in), StokesBasis::implicit(light_out))
    }

    /// The direction `sample` and `sample_mueller` draw and its pdf, `None` where nothing is
    /// drawn (below the surface, lobes disabled, a zero or non-finite density).
    fn sampled(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &SampledWavelengths,
    ) -> Option<(Vec3, f32)> {
        if !Self::enabled(ctx) || wi.z <= 0.0 {
            return None;
        }
        let wo = self.sample_direction(wi, u1, u2)?;
        let pdf = self.pdf(ctx, wi, wo, wl);
        (pdf > 0.0 && pdf.is_finite()).then_some((wo, pdf))
    }

    /// The direction drawn, before evaluation.
    fn sample_direction(&self, wi: Vec3, u1: f32, u2: Vec2) -> Option<Vec3> {
        let wo = if u1 < COSINE_LOBE_PROBABILITY {
            square_to_cosine_hemisphere(u2)
        } else {
            let (m, pdf_m) = self.sampling.sample(wi, u2);
            if pdf_m <= 0.0 {
                return None;
            }
            2.0 * wi.dot(m) * m - wi
        };
        (wo.z > 0.0).then_some(wo)
    }
}

impl Bsdf for MeasuredPolarized {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::GLOSSY_REFLECTION
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if !Self::enabled(ctx) || wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let (s, _, _) = self.lookup(ctx, wi, wo, wl);
        self.intensity(&s).unwrap_or(SampledSpectrum::ZERO)
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> f32 {
        if !Self::enabled(ctx) || wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let h = (wi + wo).normalize();
        let glossy = self.sampling.pdf(wi, h) / (4.0 * wo.dot(h));
        COSINE_LOBE_PROBABILITY * square_to_cosine_hemisphere_pdf(wo)
            + (1.0 - COSINE_LOBE_PROBABILITY) * glossy
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let (wo, pdf) = self.sampled(ctx, wi, u1, u2, wl)?;
        Some(BsdfSample {
            wo,
            weight: self.eval(ctx, wi, wo, wl) * (wo.z / pdf),
            pdf,
            flags: BsdfFlags::GLOSSY_REFLECTION,
            eta: 1.0,
        })
    }

    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        if !Self::enabled(ctx) || wi.z <= 0.0 || wo.z <= 0.0 {
            return Mueller::depolarizer(SampledSpectrum::ZERO);
        }
        self.mueller(ctx, wi, wo, wl)
    }

    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        let (wo, pdf) = self.sampled(ctx, wi, u1, u2, wl)?;
        Some(BsdfSample {
            wo,
            weight: self.mueller(ctx, wi, wo, wl) * (wo.z / pdf),
            pdf,
            flags: BsdfFlags::GLOSSY_REFLECTION,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table whose matrices are known functions of the node indices.
    fn table(f: impl Fn(usize, usize, usize, usize, usize, usize) -> f32) -> PbrdfTable {
        let phi_d: Vec<f32> = (0..5)
            .map(|i| -std::f32::consts::PI + i as f32 * std::f32::consts::FRAC_PI_2)
            .collect();
        let theta: Vec<f32> = (0..4).map(|i| i as f32 * std::f32::consts::FRAC_PI_6).collect();
        let wl = vec![450.0, 550.0, 650.0];
        let mut m = Vec::new();
        for p in 0..5 {
            for d in 0..4 {
                for h in 0..4 {
                    for l in 0..3 {
                        for r in 0..4 {
                            for c in 0..4 {
                                m.push(f(p, d, h, l, r, c));
                            }
                        }
                    }
                }
            }
        }
        PbrdfTable::new(phi_d, theta.clone(), theta, wl, m).unwrap()
    }

    #[test]
    fn interpolation_is_multilinear_and_clamped_at_the_ends() {
        // Linear in every index: multilinear interpolation reproduces it exactly between nodes.
        let t = table(|p, d, h, l, r, c| {
            p as f32 + 10.0 * d as f32 + 100.0 * h as f32 + 1000.0 * l as f32 + (r * 4 + c) as f32 * 0.01
        });
        let pi = std::f32::consts::PI;
        let s = t.stencil(
            -pi + 0.25 * pi,
            0.75 * std::f32::consts::FRAC_PI_6,
            2.5 * std::f32::consts::FRAC_PI_6,
            [500.0, 420.0, 700.0, 600.0],
        );
        let e = t.element(&s, 2, 3);
        // φd, θd, θh at 0.5, 0.75 and 2.5 nodes; λ at 0.5, clamped to 0, clamped to 2, 1.5.
        let spatial = 0.5 + 7.5 + 250.0 + 0.11;
        for (k, lambda_part) in [500.0, 0.0, 2000.0, 1500.0].into_iter().enumerate() {
            let want = spatial + lambda_part;
            assert!((e[k] - want).abs() < 2e-3, "λ{k}: {} vs {want}", e[k]);
        }
    }

    #[test]
    fn a_nan_neighbour_zeroes_the_whole_matrix_even_at_zero_weight() {
        let t = table(|p, d, h, _, r, c| {
            if (p, d, h) == (2, 1, 1) {
                f32::NAN
            } else {
                0.1 + 0.01 * (r + c) as f32
            }
        });
        let b = MeasuredPolarized::new(t, 0.1, None);
        // On the node (φd = 0, θd = θh = 0): the lookup's intervals end at φd's node 2 and start
        // at θ's node 0, so the corners (weights 1 × 0 × 0) include the NaN node (2, 1, 1).
        let s = b.table.stencil(0.0, 0.0, 0.0, [550.0; 4]);
        assert!(b.intensity(&s).is_none());
        // On θd = θh = node 2 the intervals are [1, 2] (Mitsuba's strict `<`): NaN again.
        let node = |i: f32| i * std::f32::consts::FRAC_PI_6;
        let s = b.table.stencil(0.0, node(2.0), node(2.0), [550.0; 4]);
        assert!(b.intensity(&s).is_none());
        // On node 3 they are [2, 3]: no NaN corner.
        let s = b.table.stencil(0.0, node(3.0), node(3.0), [550.0; 4]);
        assert!(b.intensity(&s).is_some());
    }

    #[test]
    fn a_nan_in_any_element_zeroes_the_matrix() {
        let t = table(|p, d, h, _, r, c| {
            if (p, d, h, r, c) == (2, 1, 1, 2, 3) {
                f32::NAN
            } else {
                0.1 + 0.01 * (r + c) as f32
            }
        });
        let b = MeasuredPolarized::new(t, 0.1, None);
        let node = |i: f32| i * std::f32::consts::FRAC_PI_6;
        assert!(
            b.intensity(&b.table.stencil(0.1, node(1.5), node(1.5), [550.0; 4]))
                .is_none()
        );
        let m = b
            .intensity(&b.table.stencil(0.1, node(2.5), node(2.5), [550.0; 4]))
            .unwrap();
        assert!((m[0] - 0.1).abs() < 1e-6);
    }

    #[test]
    fn rusinkiewicz_angles_of_a_known_pair() {
        // In the x–z plane, symmetric about the normal: h = z, θd = the polar angle.
        let th = 0.6f32;
        let a = Vec3::new(th.sin(), 0.0, th.cos());
        let b = Vec3::new(-th.sin(), 0.0, th.cos());
        let (_, theta_h, theta_d) = rusinkiewicz(a, b);
        assert!(theta_h.abs() < 1e-6 && (theta_d - th).abs() < 1e-6);
        // Tilted half vector: θh its polar angle.
        let h = Vec3::new(0.3f32.sin(), 0.0, 0.3f32.cos());
        let a = (h * 0.9 + Vec3::Y * 0.4358899).normalize();
        let b = 2.0 * a.dot(h) * h - a;
        let (phi_d, theta_h, theta_d) = rusinkiewicz(a, b);
        assert!((theta_h - 0.3).abs() < 1e-5, "{theta_h}");
        assert!((theta_d - a.dot(h).acos()).abs() < 1e-5);
        assert!(
            (phi_d.abs() - std::f32::consts::FRAC_PI_2).abs() < 1e-4,
            "{phi_d}"
        );
    }

    #[test]
    fn bad_tables_are_refused_with_the_reason() {
        let ok = || (vec![0.0], vec![0.0, 1.0], vec![0.0], vec![500.0]);
        let (p, d, h, l) = ok();
        assert_eq!(
            PbrdfTable::new(p, d, h, l, vec![0.0; 31]).unwrap_err(),
            PbrdfError::Size {
                expected: 32,
                got: 31
            }
        );
        let (p, _, h, l) = ok();
        assert!(matches!(
            PbrdfTable::new(p, vec![0.0, 0.0], h, l, vec![0.0; 32]),
            Err(PbrdfError::BadAxis {
                axis: "theta_d",
                index: 1,
                ..
            })
        ));
        let (p, d, h, l) = ok();
        let mut m = vec![0.0; 32];
        m[5] = f32::INFINITY;
        assert_eq!(
            PbrdfTable::new(p, d, h, l, m).unwrap_err(),
            PbrdfError::Infinite { index: 5 }
        );
        let (_, d, h, l) = ok();
        assert_eq!(
            PbrdfTable::new(vec![], d, h, l, vec![]).unwrap_err(),
            PbrdfError::EmptyAxis("phi_d")
        );
    }
}
