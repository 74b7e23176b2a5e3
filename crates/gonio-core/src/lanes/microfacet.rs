//! Microfacet distributions on lanes: [`crate::microfacet::MicrofacetDistribution`]'s D, G1,
//! pdf and sampling, formula for formula, with a roughness per lane (textured α).

use super::math::{acos, erf, erf_inv, exp, ln, powf, sin_cos};
use super::{F32s, Isa, Mask, Portable, Vec3s};
use crate::microfacet::{MAX_ALPHA, MIN_ALPHA, MicrofacetDistribution, MicrofacetKind};
use glam::Vec3;
use std::f32::consts::PI;

/// 1/√π.
const INV_SQRT_PI: f32 = 0.564_189_6;

/// A microfacet distribution with a roughness per lane (the kind and the sampling strategy are
/// the same in every lane).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MicrofacetLanes<const N: usize, X: Isa = Portable> {
    /// Beckmann or GGX.
    pub kind: MicrofacetKind,
    /// α along the tangent, per lane, in [[`MIN_ALPHA`], [`MAX_ALPHA`]].
    pub alpha_u: F32s<N, X>,
    /// α along the bitangent, per lane.
    pub alpha_v: F32s<N, X>,
    /// Sample visible normals (Mitsuba's default) or all normals.
    pub sample_visible: bool,
}

impl MicrofacetDistribution {
    /// This distribution in every lane.
    #[inline(always)]
    pub fn lanes<const N: usize, X: Isa>(&self) -> MicrofacetLanes<N, X> {
        MicrofacetLanes {
            kind: self.kind,
            alpha_u: F32s::splat(self.alpha_u),
            alpha_v: F32s::splat(self.alpha_v),
            sample_visible: self.sample_visible,
        }
    }
}

impl<const N: usize, X: Isa> MicrofacetLanes<N, X> {
    /// A distribution with per-lane roughness, clamped as [`MicrofacetDistribution::new`] does
    /// (NaN becomes [`MIN_ALPHA`]).
    #[inline(always)]
    pub fn new(kind: MicrofacetKind, alpha_u: F32s<N, X>, alpha_v: F32s<N, X>, sample_visible: bool) -> Self {
        Self {
            kind,
            alpha_u: alpha_u.max(MIN_ALPHA).min(MAX_ALPHA),
            alpha_v: alpha_v.max(MIN_ALPHA).min(MAX_ALPHA),
            sample_visible,
        }
    }

    /// Lane `k` as a scalar distribution.
    pub fn lane(&self, k: usize) -> MicrofacetDistribution {
        MicrofacetDistribution {
            kind: self.kind,
            alpha_u: self.alpha_u.lane(k),
            alpha_v: self.alpha_v.lane(k),
            sample_visible: self.sample_visible,
        }
    }

    /// D(m) per lane; 0 below the surface and where D cos θm < 10⁻²⁰.
    #[inline(always)]
    pub fn d(&self, m: Vec3s<N, X>) -> F32s<N, X> {
        let cos_theta = m.z;
        let cos_theta_2 = cos_theta * cos_theta;
        let alpha_uv = self.alpha_u * self.alpha_v;
        let (xu, yv) = (m.x / self.alpha_u, m.y / self.alpha_v);
        let result = match self.kind {
            MicrofacetKind::Beckmann => {
                exp(-(xu * xu + yv * yv) / cos_theta_2) / (PI * alpha_uv * cos_theta_2 * cos_theta_2)
            }
            MicrofacetKind::Ggx => {
                let t = xu * xu + yv * yv + cos_theta_2;
                (PI * alpha_uv * t * t).recip()
            }
        };
        let ok = cos_theta.gt(0.0) & (result * cos_theta).gt(1e-20) & result.is_finite();
        ok.and_then(result)
    }

    /// Smith's G1(v, m) per lane, as [`MicrofacetDistribution::g1`] (Mitsuba's).
    #[inline(always)]
    pub fn g1(&self, v: Vec3s<N, X>, m: Vec3s<N, X>) -> F32s<N, X> {
        let facing = (v.dot(m) * v.z).gt(0.0);
        let (ax, ay) = (self.alpha_u * v.x, self.alpha_v * v.y);
        let xy = ax * ax + ay * ay;
        let tau2 = xy / (v.z * v.z);
        let g = match self.kind {
            MicrofacetKind::Beckmann => {
                let a = tau2.sqrt().recip();
                let a2 = a * a;
                let r = (3.535 * a + 2.181 * a2) / (1.0 + 2.276 * a + 2.577 * a2);
                a.ge(1.6).select(F32s::ONE, r)
            }
            MicrofacetKind::Ggx => 2.0 / (1.0 + (1.0 + tau2).sqrt()),
        };
        facing.and_then(xy.eq(0.0).select(F32s::ONE, g))
    }

    /// G1(wi, m) G1(wo, m).
    #[inline(always)]
    pub fn g(&self, wi: Vec3s<N, X>, wo: Vec3s<N, X>, m: Vec3s<N, X>) -> F32s<N, X> {
        self.g1(wi, m) * self.g1(wo, m)
    }

    /// The density of [`Self::sample`] at `m` per lane ([`MicrofacetDistribution::pdf`]).
    #[inline(always)]
    pub fn pdf(&self, wi: Vec3s<N, X>, m: Vec3s<N, X>) -> F32s<N, X> {
        let d = self.d(m);
        let g1_wi = if self.sample_visible {
            self.g1(wi, m)
        } else {
            F32s::ZERO
        };
        self.pdf_from(wi, m, d, g1_wi)
    }

    /// [`Self::pdf`] from D(m) and G1(wi, m) already computed (the latter only read for
    /// visible normals): what an eval that needs both anyway pays instead of a second D.
    #[inline(always)]
    pub fn pdf_from(&self, wi: Vec3s<N, X>, m: Vec3s<N, X>, d: F32s<N, X>, g1_wi: F32s<N, X>) -> F32s<N, X> {
        let p = if self.sample_visible {
            wi.z.gt(0.0).and_then(d * g1_wi * wi.dot(m).abs() / wi.z)
        } else {
            d * m.z
        };
        d.ne(0.0).and_then(p)
    }

    /// A normal per lane and its pdf (0 marks a failed sample), as
    /// [`MicrofacetDistribution::sample`].
    #[inline(always)]
    pub fn sample(&self, wi: Vec3s<N, X>, u: [F32s<N, X>; 2]) -> (Vec3s<N, X>, F32s<N, X>) {
        let (m, ok) = if self.sample_visible {
            let ok = wi.z.gt(0.0);
            (
                ok.select3(self.sample_visible_normal(wi, u), Vec3s::splat(Vec3::Z)),
                ok,
            )
        } else {
            (self.sample_all_normals(u), Mask::ALL)
        };
        let pdf = self.pdf(wi, m);
        (m, (ok & pdf.is_finite()).and_then(pdf))
    }

    /// A normal per lane drawn from all normals, density D(m) cos θm, as
    /// [`MicrofacetDistribution::sample_all_normals`] (Walter et al. 2007) with the lanes'
    /// logarithm and sine.
    #[inline(always)]
    pub fn sample_all_normals(&self, u: [F32s<N, X>; 2]) -> Vec3s<N, X> {
        let (s, c) = sin_cos(2.0 * PI * u[1]);
        let aniso = self.alpha_u.ne(self.alpha_v);
        let (sin_phi, cos_phi, alpha_2) = if aniso.any() {
            // tan φ = (α_v/α_u) tan(2π ξ₂), the quadrant of 2π ξ₂ kept.
            let tmp = self.alpha_v / self.alpha_u * (s / c);
            let cos_a = (tmp * tmp + 1.0)
                .sqrt()
                .recip()
                .copysign((u[1] - 0.5).abs() - 0.25);
            let sin_a = cos_a * tmp;
            let (x, y) = (cos_a / self.alpha_u, sin_a / self.alpha_v);
            let alpha_2_a = (x * x + y * y).recip();
            (
                aniso.select(sin_a, s),
                aniso.select(cos_a, c),
                aniso.select(alpha_2_a, self.alpha_u * self.alpha_u),
            )
        } else {
            (s, c, self.alpha_u * self.alpha_u)
        };
        let u1 = u[0].clamp(0.0, 1.0);
        let tan_theta_2 = match self.kind {
            MicrofacetKind::Beckmann => -alpha_2 * ln(F32s::ONE - u1),
            MicrofacetKind::Ggx => alpha_2 * u1 / (1.0 - u1),
        };
        let cos_theta = (1.0 + tan_theta_2).sqrt().recip();
        // sin θ = tan θ · cos θ, without the cancellation of √(1 − cos²θ) near the pole (the
        // scalar sampler's); 1 where tan θ overflows.
        let sin_theta = tan_theta_2
            .is_finite()
            .select(tan_theta_2.safe_sqrt() * cos_theta, F32s::ONE);
        Vec3s::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)
    }

    /// Visible normals for wi.z > 0 (Heitz & d'Eon 2014; GGX: Heitz 2018).
    #[inline(always)]
    fn sample_visible_normal(&self, wi: Vec3s<N, X>, u: [F32s<N, X>; 2]) -> Vec3s<N, X> {
        let (au, av) = (self.alpha_u, self.alpha_v);
        let wh = Vec3s::new(au * wi.x, av * wi.y, wi.z).normalize();
        match self.kind {
            MicrofacetKind::Ggx => {
                let lensq = wh.x * wh.x + wh.y * wh.y;
                let rcp = lensq.sqrt().recip();
                let has = lensq.gt(0.0);
                let t1 = Vec3s::new(
                    has.select(-wh.y * rcp, F32s::ONE),
                    has.and_then(wh.x * rcp),
                    F32s::ZERO,
                );
                let t2 = wh.cross(t1);
                let r = u[0].max(0.0).sqrt();
                let (s, c) = sin_cos(2.0 * PI * u[1]);
                let p1 = r * c;
                let h = 0.5 * (1.0 + wh.z);
                let p2 = (1.0 - h) * (F32s::ONE - p1 * p1).safe_sqrt() + h * r * s;
                let nz = (F32s::ONE - p1 * p1 - p2 * p2).safe_sqrt();
                let nh = t1 * p1 + t2 * p2 + wh * nz;
                Vec3s::new(au * nh.x, av * nh.y, nh.z.max(0.0)).normalize_or(Vec3::Z)
            }
            MicrofacetKind::Beckmann => {
                let sin_theta = (wh.x * wh.x + wh.y * wh.y).sqrt();
                let has = sin_theta.gt(0.0);
                let rcp = sin_theta.recip();
                let sin_phi = has.and_then(wh.y * rcp);
                let cos_phi = has.select(wh.x * rcp, F32s::ONE);
                let sx = beckmann_visible_slope_x_11(wh.z, sin_theta, u[0]);
                let sy = erf_inv(2.0 * u[1].clamp(1e-6, 1.0 - 1e-6) - 1.0);
                let slope_x = (cos_phi * sx - sin_phi * sy) * au;
                let slope_y = (sin_phi * sx + cos_phi * sy) * av;
                Vec3s::new(-slope_x, -slope_y, F32s::ONE).normalize()
            }
        }
    }
}

/// The x slope of Beckmann's visible normals for roughness 1 per lane: the safeguarded
/// Newton–bisection of the scalar `beckmann_visible_slope_x_11` in the erf domain, iterated
/// until every lane has converged (at most 24 steps); a converged lane keeps its value.
#[inline(always)]
fn beckmann_visible_slope_x_11<const N: usize, X: Isa>(
    cos_theta: F32s<N, X>,
    sin_theta: F32s<N, X>,
    u1: F32s<N, X>,
) -> F32s<N, X> {
    let u1 = u1.clamp(1e-6, 1.0 - 1e-6);
    let degenerate = !(cos_theta.is_finite() & sin_theta.is_finite());
    let normal_incidence = sin_theta.lt(1e-7);
    let cos_theta = cos_theta.max(1e-12);
    let tan_theta = sin_theta / cos_theta;
    let cot_theta = cos_theta / sin_theta;
    let mut a = F32s::splat(-1.0);
    let mut c = erf(cot_theta);
    let k = INV_SQRT_PI * tan_theta;
    let normalization = (1.0 + c + k * exp(-(cot_theta * cot_theta))).recip();
    let theta = acos(cos_theta.min(1.0));
    let fit = 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta));
    let mut b = c - (1.0 + c) * powf(F32s::ONE - u1, fit);
    let tolerance = (1e-3 * u1.min(F32s::ONE - u1)).clamp(1e-7, 1e-6);
    // Lanes that need no iteration are done from the start.
    let mut done = degenerate | normal_incidence;
    for _ in 0..24 {
        if done.all() {
            break;
        }
        let active = !done;
        b = (active & !(b.gt(a) & b.lt(c))).select(0.5 * (a + c), b);
        let inv_erf = erf_inv(b);
        let value = normalization * (1.0 + b + k * exp(-(inv_erf * inv_erf))) - u1;
        let derivative = normalization * (1.0 - inv_erf * tan_theta);
        let step = active & !value.abs().lt(tolerance);
        c = (step & value.gt(0.0)).select(b, c);
        a = (step & !value.gt(0.0)).select(b, a);
        b = step.select(b - value / derivative, b);
        done = done | !step;
    }
    let slope = erf_inv(b.clamp(-1.0 + 6e-8, 1.0 - 6e-8));
    let slope = normal_incidence.select(erf_inv(2.0 * u1 - 1.0), slope);
    degenerate.select(F32s::ZERO, slope)
}
