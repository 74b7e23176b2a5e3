//! `hair`: a fibre seen up close, Chiang et al.'s near-field hair model.
//!
//! Chiang, Bitterli, Tappan, Burley, "A Practical and Controllable Hair and Fur Model for
//! Production Path Tracing" (EGSR 2016), on d'Eon et al.'s longitudinal lobes ("An
//! Energy-Conserving Hair Reflectance Model", EGSR 2011) and Marschner et al.'s decomposition
//! (2003); the form of pbrt-v3 §9.9 and Mitsuba 3's `src/bsdfs/hair.cpp`.
//!
//! Light meeting a fibre (a dielectric cylinder of relative index η) at offset h ∈ [−1, 1] across
//! its width either reflects (p = 0, R), crosses it (p = 1, TT), reflects once inside (p = 2, TRT)
//! or more (p ≥ 3, summed). Each path p leaves in a cone about the fibre and scatters as
//!
//! ```text
//!     S(ωi, ωo) = Σ_{p<3} M_p(θi′, θo) A_p(θi, h) N_p(Δφ)  +  M_3(θi, θo) A_3(θi, h) / 2π
//!     M_p = exp(−sin θi sin θo / v_p) I₀(cos θi cos θo / v_p) / (2 v_p sinh(1/v_p))   (d'Eon)
//!     A_0 = F,  A_1 = (1 − F)² T,  A_p = A_{p−1} T F,  A_3 = A_2 F T / (1 − T F)
//!     T = exp(−σa · 2 cos γt / cos θt)   (the chord through the fibre, radius 1)
//!     N_p(Δφ) = trimmed logistic(Δφ − Φ_p; s) on [−π, π],  Φ_p = 2p γt − 2γi + pπ
//! ```
//!
//! with θ the angle between a direction and the fibre's normal plane, φ the angle about the fibre,
//! γi = asin h the incidence angle in the normal plane, γt its refraction at η′ =
//! √(η² − sin²θi)/cos θi, F the dielectric Fresnel reflectance at cos θi cos γi, and θi′ the
//! incidence tilted by the cuticle's scales (−2α for R, +α for TT, +4α for TRT). The roughnesses
//! map to the lobe variances v_0 = (0.726 βm + 0.812 βm² + 3.7 βm²⁰)², v_1 = v_0/4,
//! v_2 = v_3 = 4 v_0, and the logistic scale s = √(π/8)(0.265 βn + 1.194 βn² + 5.372 βn²²).
//!
//! **Frame** (Mitsuba's): the fibre runs along local **y** (sin θ = w.y), the normal is **z**, φ =
//! atan2(w.z, w.x), and h = sin γi with γi = ±acos(wi.z/|wi.xz|), positive when wi.x < 0 (on
//! Mitsuba's curves, whose shading frame's first tangent runs around the fibre). S is a
//! scattering function per unit projected solid angle about the fibre; f = S/|cos θo| with θo
//! measured from the normal z, so that the renderer's f·|cos θo| is S (Mitsuba's `eval` returns S).
//! The model has no sides: a path may leave on either side of the normal (TT mostly behind).
//!
//! **Sampling**: the lobe p by the luminance of A_p (Mitsuba's), θo exactly by d'Eon's inversion,
//! Δφ by the trimmed logistic (uniform for p = 3); the density is the mixture's, exact. (Mitsuba
//! draws the p = 3 lobe's θo about the normal plane instead of about −θi, while its pdf is the
//! mixture's; the estimator here uses the exact draw.)
//!
//! **Not reciprocal**: the scale tilt, h read from ωi and A_p from θi make S(ωi, ωo) ≠ S(ωo, ωi)
//! (Chiang et al. §4). Importance transport (light paths) uses the adjoint, f_imp(a, b) =
//! f_rad(b, a); Mitsuba evaluates the radiance form in both modes.
//!
//! Mitsuba 3 plugin `hair`:
//!
//! | parameter                 | type              | default |
//! |---------------------------|-------------------|---------|
//! | `eumelanin`               | float             | 1.3     |
//! | `pheomelanin`             | float             | 0.2     |
//! | `sigma_a`                 | spectrum/texture  | (instead of the pigments) |
//! | `scale`                   | float             | 1 (multiplies `sigma_a`) |
//! | `int_ior`, `ext_ior`      | float or name     | amber (1.55), air |
//! | `longitudinal_roughness`  | float in [0, 1]   | 0.3 (βm) |
//! | `azimuthal_roughness`     | float in [0, 1]   | 0.3 (βn) |
//! | `scale_tilt`              | float, degrees    | 2 (α)   |
//!
//! The pigments' absorption (per unit fibre radius, d'Eon et al. 2011) is given as linear sRGB,
//! eumelanin (0.419, 0.697, 1.37) and pheomelanin (0.187, 0.4, 1.05); in spectral rendering
//! Mitsuba uplifts those colours as reflectances (clamped to [0, 1]), and so does this model.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, TransportMode};
use crate::bsdfs::principled_common::tint_luminances;
use crate::fresnel::fresnel_dielectric;
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI, TAU};

/// Number of explicit lobes (R, TT, TRT); the rest is summed into one.
pub const P_MAX: usize = 3;

/// Eumelanin's absorption per unit radius as linear sRGB (d'Eon et al. 2011).
pub const EUMELANIN_SIGMA_A: [f32; 3] = [0.419, 0.697, 1.37];
/// Pheomelanin's absorption per unit radius as linear sRGB (d'Eon et al. 2011).
pub const PHEOMELANIN_SIGMA_A: [f32; 3] = [0.187, 0.4, 1.05];

/// The fibre's roughness and cuticle tilt turned into the lobes' constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairLobes {
    /// Longitudinal variances v_0..v_3.
    v: [f32; P_MAX + 1],
    /// Logistic scale s of the azimuthal lobes.
    s: f32,
    /// sin 2ᵏα, k = 0, 1, 2.
    sin_2k_alpha: [f32; 3],
    /// cos 2ᵏα, k = 0, 1, 2.
    cos_2k_alpha: [f32; 3],
    /// What the lobes' densities share at every query, made once: d'Eon's normalization
    /// 2 sinh(1/v_p), the e^(−2/v_p) of his inversion, and the (untrimmed) logistic's cdf at −π
    /// and its mass on [−π, π], which trimming divides by. (Per query they were most of a
    /// query's exponentials; `sinh` alone, through the platform's `expm1f`, was 15 % of the
    /// hair battery's time.)
    two_sinh_kappa: [f32; P_MAX + 1],
    exp_m2_over_v: [f32; P_MAX + 1],
    logistic_lo: f32,
    logistic_mass: f32,
}

impl HairLobes {
    /// Lobes of longitudinal roughness βm, azimuthal roughness βn (both in [0, 1]) and scale
    /// tilt α in degrees.
    pub fn new(beta_m: f32, beta_n: f32, alpha_deg: f32) -> Self {
        let v0 = (0.726 * beta_m + 0.812 * beta_m * beta_m + 3.7 * beta_m.powi(20)).powi(2);
        let s = (PI / 8.0).sqrt() * (0.265 * beta_n + 1.194 * beta_n * beta_n + 5.372 * beta_n.powi(22));
        let mut sin_2k_alpha = [0.0; 3];
        let mut cos_2k_alpha = [0.0; 3];
        sin_2k_alpha[0] = alpha_deg.to_radians().sin();
        cos_2k_alpha[0] = (1.0 - sin_2k_alpha[0] * sin_2k_alpha[0]).max(0.0).sqrt();
        for k in 1..3 {
            sin_2k_alpha[k] = 2.0 * cos_2k_alpha[k - 1] * sin_2k_alpha[k - 1];
            cos_2k_alpha[k] = cos_2k_alpha[k - 1].powi(2) - sin_2k_alpha[k - 1].powi(2);
        }
        let v = [v0, 0.25 * v0, 4.0 * v0, 4.0 * v0];
        let (logistic_lo, logistic_mass) = logistic_on_pi(s);
        Self {
            v,
            s,
            sin_2k_alpha,
            cos_2k_alpha,
            two_sinh_kappa: v.map(|v| 2.0 * (1.0 / v).sinh()),
            exp_m2_over_v: v.map(|v| (-2.0 / v).exp()),
            logistic_lo,
            logistic_mass,
        }
    }

    /// The longitudinal variances v_0..v_3.
    pub fn v(&self) -> [f32; P_MAX + 1] {
        self.v
    }

    /// The azimuthal lobes' logistic scale s.
    pub fn s(&self) -> f32 {
        self.s
    }

    /// (sin θi′, |cos θi′|) of lobe p: the incidence tilted by the scales (−2α for R, +α for TT,
    /// +4α for TRT, none for the rest).
    #[inline]
    fn tilted(&self, sin_theta: f32, cos_theta: f32, p: usize) -> (f32, f32) {
        let (s, c) = match p {
            0 => (
                sin_theta * self.cos_2k_alpha[1] - cos_theta * self.sin_2k_alpha[1],
                cos_theta * self.cos_2k_alpha[1] + sin_theta * self.sin_2k_alpha[1],
            ),
            1 => (
                sin_theta * self.cos_2k_alpha[0] + cos_theta * self.sin_2k_alpha[0],
                cos_theta * self.cos_2k_alpha[0] - sin_theta * self.sin_2k_alpha[0],
            ),
            2 => (
                sin_theta * self.cos_2k_alpha[2] + cos_theta * self.sin_2k_alpha[2],
                cos_theta * self.cos_2k_alpha[2] - sin_theta * self.sin_2k_alpha[2],
            ),
            _ => (sin_theta, cos_theta),
        };
        (s, c.abs())
    }
}

/// I₀(x), the modified Bessel function of the first kind, by its series to the x²⁰ term (pbrt's
/// and Mitsuba's: used where x ≤ 1/v ≤ 10).
#[inline]
pub fn bessel_i0(x: f32) -> f32 {
    let x2 = x * x;
    let (mut sum, mut term, mut denom) = (1.0f32, x2, 4.0f32);
    for i in 1..=10 {
        sum += term / denom;
        term *= x2;
        let next = (i + 1) as f32;
        denom *= 4.0 * next * next;
    }
    sum
}

/// ln I₀(x): the series' logarithm up to 12, the asymptotic form beyond.
#[inline]
pub fn log_bessel_i0(x: f32) -> f32 {
    if x > 12.0 {
        x + 0.5 * ((1.0 / (TAU * x)).ln() + 1.0 / (8.0 * x))
    } else {
        bessel_i0(x).ln()
    }
}

/// d'Eon's longitudinal lobe M_p per unit solid angle (its density in θ over 2π):
/// exp(−sin θi sin θo/v) I₀(cos θi cos θo/v) / (2v sinh(1/v)) / 2π, in log form for v ≤ 0.1.
#[inline]
pub fn longitudinal(sin_i: f32, cos_i: f32, sin_o: f32, cos_o: f32, v: f32) -> f32 {
    longitudinal_with(sin_i, cos_i, sin_o, cos_o, v, || 2.0 * (1.0 / v).sinh())
}

/// [`longitudinal`] with its normalization 2 sinh(1/v) (needed where 1/v ≤ 10) from `two_sinh_kappa`.
#[inline]
fn longitudinal_with(
    sin_i: f32,
    cos_i: f32,
    sin_o: f32,
    cos_o: f32,
    v: f32,
    two_sinh_kappa: impl FnOnce() -> f32,
) -> f32 {
    let kappa = 1.0 / v;
    let a = cos_i * cos_o * kappa;
    let b = sin_i * sin_o * kappa;
    let m = if kappa > 10.0 {
        (log_bessel_i0(a) - b - kappa + std::f32::consts::LN_2 + (0.5 * kappa).ln()).exp()
    } else {
        (-b).exp() * bessel_i0(a) * kappa / two_sinh_kappa()
    };
    m * (0.5 * FRAC_1_PI)
}

/// The logistic density of scale s at x.
#[inline]
fn logistic(x: f32, s: f32) -> f32 {
    let e = (-x.abs() / s).exp();
    e / (s * (1.0 + e) * (1.0 + e))
}

/// The logistic distribution's cdf.
#[inline]
fn logistic_cdf(x: f32, s: f32) -> f32 {
    1.0 / (1.0 + (-x / s).exp())
}

/// The logistic of scale s restricted to [−π, π] and renormalized.
#[inline]
pub fn trimmed_logistic(x: f32, s: f32) -> f32 {
    logistic(x, s) / logistic_on_pi(s).1
}

/// The logistic's cdf at −π and its mass on [−π, π] (what trimming to [−π, π] subtracts and
/// divides by).
#[inline]
fn logistic_on_pi(s: f32) -> (f32, f32) {
    let lo = logistic_cdf(-PI, s);
    (lo, logistic_cdf(PI, s) - lo)
}

/// Inverse cdf of [`trimmed_logistic`].
#[inline]
pub fn sample_trimmed_logistic(u: f32, s: f32) -> f32 {
    let (lo, mass) = logistic_on_pi(s);
    sample_trimmed_logistic_with(u, s, lo, mass)
}

/// [`sample_trimmed_logistic`] given the cdf at −π, `lo`, and the mass on [−π, π], `k`.
#[inline]
fn sample_trimmed_logistic_with(u: f32, s: f32, lo: f32, k: f32) -> f32 {
    (-s * (1.0 / (u * k + lo) - 1.0).ln()).clamp(-PI, PI)
}

/// An angle wrapped into [−π, π].
#[inline]
fn wrap_pi(phi: f32) -> f32 {
    let mut x = phi % TAU;
    if x < -PI {
        x += TAU;
    } else if x > PI {
        x -= TAU;
    }
    x
}

/// The azimuthal lobe N_p(Δφ): the trimmed logistic about the perfect deflection
/// Φ_p = 2p γt − 2γi + pπ.
#[inline]
pub fn azimuthal(delta_phi: f32, p: usize, s: f32, gamma_i: f32, gamma_t: f32) -> f32 {
    azimuthal_with(delta_phi, p, s, logistic_on_pi(s).1, gamma_i, gamma_t)
}

/// [`azimuthal`] given the logistic's mass on [−π, π], `mass`.
#[inline]
fn azimuthal_with(delta_phi: f32, p: usize, s: f32, mass: f32, gamma_i: f32, gamma_t: f32) -> f32 {
    let perfect = 2.0 * p as f32 * gamma_t - 2.0 * gamma_i + p as f32 * PI;
    logistic(wrap_pi(delta_phi - perfect), s) / mass
}

/// Everything the lobes need from the incident direction.
#[derive(Clone, Copy, Debug)]
struct Incidence {
    sin_theta: f32,
    cos_theta: f32,
    phi: f32,
    gamma_i: f32,
    gamma_t: f32,
    h: f32,
    /// The chord through the fibre over its radius, 2 cos γt / cos θt.
    chord: f32,
}

/// A fibre's absorption per unit radius, at any wavelength: given, or made of the two melanins.
#[derive(Clone, Debug, PartialEq)]
pub enum HairAbsorption {
    /// σa(λ), `scale` already applied.
    Sigma(Spectrum),
    /// c_eu σ_eu(λ) + c_pheo σ_pheo(λ): the pigments' concentrations and their uplifted spectra.
    Pigments {
        /// Eumelanin concentration.
        eumelanin: f32,
        /// Pheomelanin concentration.
        pheomelanin: f32,
        /// [`EUMELANIN_SIGMA_A`] as a spectrum.
        eu: Spectrum,
        /// [`PHEOMELANIN_SIGMA_A`] as a spectrum.
        pheo: Spectrum,
    },
}

impl HairAbsorption {
    /// The pigments' absorption at the given concentrations.
    pub fn pigments(eumelanin: f32, pheomelanin: f32) -> Self {
        HairAbsorption::Pigments {
            eumelanin,
            pheomelanin,
            eu: Spectrum::rgb_albedo(EUMELANIN_SIGMA_A),
            pheo: Spectrum::rgb_albedo(PHEOMELANIN_SIGMA_A),
        }
    }
}

impl SpectralValue for HairAbsorption {
    fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            HairAbsorption::Sigma(s) => s.sample(wl),
            HairAbsorption::Pigments {
                eumelanin,
                pheomelanin,
                eu,
                pheo,
            } => eu.sample(wl) * *eumelanin + pheo.sample(wl) * *pheomelanin,
        }
    }
}

/// The hair model; `sigma_a` is the absorption per unit fibre radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hair<S = HairAbsorption> {
    /// σa(λ) per unit radius.
    pub sigma_a: S,
    /// η = n_int/n_ext.
    pub eta: f32,
    /// Lobe constants.
    pub lobes: HairLobes,
}

impl Default for Hair {
    /// Mitsuba's default: brown hair (eumelanin 1.3, pheomelanin 0.2), amber in air, βm = βn =
    /// 0.3, α = 2°.
    fn default() -> Self {
        Hair {
            sigma_a: HairAbsorption::pigments(1.3, 0.2),
            eta: 1.55 / 1.000_277,
            lobes: HairLobes::new(0.3, 0.3, 2.0),
        }
    }
}

impl<S: SpectralValue> Hair<S> {
    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> Hair<SampledSpectrum> {
        Hair {
            sigma_a: self.sigma_a.sample(wl),
            eta: self.eta,
            lobes: self.lobes,
        }
    }

    /// σa(λ) per unit radius.
    #[inline]
    pub fn absorption(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        self.sigma_a.sample(wl)
    }

    #[inline]
    fn incidence(&self, wi: Vec3) -> Incidence {
        let sin_theta = wi.y.clamp(-1.0, 1.0);
        let cos_theta = (1.0 - sin_theta * sin_theta).max(0.0).sqrt();
        let proj = (wi.x * wi.x + wi.z * wi.z).sqrt();
        let (gamma_i, h) = if proj > 0.0 {
            let g = (wi.z / proj).clamp(-1.0, 1.0).acos();
            (if wi.x < 0.0 { g } else { -g }, -wi.x / proj)
        } else {
            (0.0, 0.0)
        };
        // Refraction in the longitudinal plane and, at the modified index, in the normal plane.
        let sin_theta_t = sin_theta / self.eta;
        let cos_theta_t = (1.0 - sin_theta_t * sin_theta_t).max(0.0).sqrt();
        let eta_p = (self.eta * self.eta - sin_theta * sin_theta).max(0.0).sqrt() / cos_theta;
        let sin_gamma_t = (h / eta_p).clamp(-1.0, 1.0);
        let cos_gamma_t = (1.0 - sin_gamma_t * sin_gamma_t).max(0.0).sqrt();
        Incidence {
            sin_theta,
            cos_theta,
            phi: wi.z.atan2(wi.x),
            gamma_i,
            gamma_t: sin_gamma_t.asin(),
            h,
            chord: 2.0 * cos_gamma_t / cos_theta_t,
        }
    }

    /// A_0..A_3 at incidence `inc`.
    #[inline]
    fn attenuation(&self, inc: &Incidence, wl: &SampledWavelengths) -> [SampledSpectrum; P_MAX + 1] {
        let t = (-(self.absorption(wl) * inc.chord)).exp();
        let cos_gamma_i = (1.0 - inc.h * inc.h).max(0.0).sqrt();
        let f = fresnel_dielectric(inc.cos_theta * cos_gamma_i, self.eta).reflectance;
        let a0 = SampledSpectrum::splat(f);
        let a1 = t * ((1.0 - f) * (1.0 - f));
        let a2 = a1 * t * f;
        let tf = t * f;
        let a3 = a2 * tf / (SampledSpectrum::ONE - tf);
        [a0, a1, a2, a3]
    }

    /// The lobes' selection probabilities: A_p's luminance over their sum (Mitsuba's).
    #[inline]
    fn lobe_pmf(a: &[SampledSpectrum; P_MAX + 1], wl: &SampledWavelengths) -> [f32; P_MAX + 1] {
        let lum = tint_luminances(*a, wl);
        let sum: f32 = lum.iter().sum();
        if sum > 0.0 && sum.is_finite() {
            lum.map(|l| l / sum)
        } else {
            [0.0; P_MAX + 1]
        }
    }

    /// Σ_p M_p N_p w_p over the lobes, w_p = 2π·weight_p for p < 3 and weight_3 for the rest: S
    /// with the weights A_p, the pdf with their selection probabilities.
    #[inline]
    fn lobe_sum<W: Copy + std::ops::Mul<f32, Output = W> + std::ops::Add<Output = W>>(
        &self,
        inc: &Incidence,
        wo: Vec3,
        weights: &[W; P_MAX + 1],
        zero: W,
    ) -> W {
        let sin_o = wo.y.clamp(-1.0, 1.0);
        let cos_o = (1.0 - sin_o * sin_o).max(0.0).sqrt();
        let delta_phi = wo.z.atan2(wo.x) - inc.phi;
        let l = &self.lobes;
        let mut sum = zero;
        for (p, w) in weights.iter().enumerate().take(P_MAX) {
            let (sin_ip, cos_ip) = l.tilted(inc.sin_theta, inc.cos_theta, p);
            let m = longitudinal_with(sin_ip, cos_ip, sin_o, cos_o, l.v[p], || l.two_sinh_kappa[p]);
            let n = azimuthal_with(delta_phi, p, l.s, l.logistic_mass, inc.gamma_i, inc.gamma_t);
            sum = sum + *w * (m * TAU * n);
        }
        let (sin_i, cos_i) = (inc.sin_theta, inc.cos_theta);
        let m = longitudinal_with(sin_i, cos_i, sin_o, cos_o, l.v[P_MAX], || l.two_sinh_kappa[P_MAX]);
        sum + weights[P_MAX] * m
    }

    /// The incidence of `wi` and its attenuations A_0..A_3: what S and the pdf from `wi` share.
    #[inline]
    fn incidence_and_attenuation(
        &self,
        wi: Vec3,
        wl: &SampledWavelengths,
    ) -> (Incidence, [SampledSpectrum; P_MAX + 1]) {
        let inc = self.incidence(wi);
        let a = self.attenuation(&inc, wl);
        (inc, a)
    }

    /// S at `wo` given the incidence and its attenuations (0 where not finite).
    #[inline]
    fn scattering_at(&self, inc: &Incidence, a: &[SampledSpectrum; P_MAX + 1], wo: Vec3) -> SampledSpectrum {
        let s = self.lobe_sum(inc, wo, a, SampledSpectrum::ZERO);
        if s.is_finite() { s } else { SampledSpectrum::ZERO }
    }

    /// The sampling density at `wo` given the incidence and its lobe probabilities (0 where not
    /// finite).
    #[inline]
    fn density_at(&self, inc: &Incidence, pmf: &[f32; P_MAX + 1], wo: Vec3) -> f32 {
        let pdf = self.lobe_sum(inc, wo, pmf, 0.0);
        if pdf.is_finite() { pdf } else { 0.0 }
    }

    /// S(ωi → ωo): the scattering function per unit solid angle, including the projection (what
    /// Mitsuba's `eval` returns), with ωi towards the viewer and ωo towards the light.
    pub fn scattering(&self, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let (inc, a) = self.incidence_and_attenuation(wi, wl);
        self.scattering_at(&inc, &a, wo)
    }

    /// S in the transport direction of `ctx` and the cosine f carries it over: radiance
    /// S(wi → wo) from the incidence of `wi` already at hand, |cos θo|; importance the adjoint
    /// S(wo → wi), |cos θi|.
    #[inline]
    fn transported(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
        inc: &Incidence,
        a: &[SampledSpectrum; P_MAX + 1],
    ) -> (SampledSpectrum, f32) {
        match ctx.mode {
            TransportMode::Radiance => (self.scattering_at(inc, a, wo), wo.z.abs()),
            TransportMode::Importance => (self.scattering(wo, wi, wl), wi.z.abs()),
        }
    }

    /// f in the transport direction of `ctx` (radiance S(wi → wo)/|cos θo|, importance its
    /// adjoint S(wo → wi)/|cos θi|) and the density of [`Bsdf::sample`] from `wi` at `wo`: the
    /// radiance value and the density share one incidence.
    #[inline]
    fn f_and_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        let (inc, a) = self.incidence_and_attenuation(wi, wl);
        let pdf = self.density_at(&inc, &Self::lobe_pmf(&a, wl), wo);
        let (s, cos) = self.transported(ctx, wi, wo, wl, &inc, &a);
        (if cos > 0.0 { s / cos } else { SampledSpectrum::ZERO }, pdf)
    }
}

/// Flags of the glossy fibre: both sides of the normal, not symmetric, anisotropic about it.
const HAIR_FLAGS: BsdfFlags = BsdfFlags::GLOSSY_REFLECTION
    .union(BsdfFlags::GLOSSY_TRANSMISSION)
    .union(BsdfFlags::NON_SYMMETRIC)
    .union(BsdfFlags::ANISOTROPIC);

impl<S: SpectralValue> Bsdf for Hair<S> {
    fn flags(&self) -> BsdfFlags {
        HAIR_FLAGS
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if !ctx.is_enabled(BsdfFlags::GLOSSY) {
            return SampledSpectrum::ZERO;
        }
        let (s, cos) = match ctx.mode {
            TransportMode::Radiance => (self.scattering(wi, wo, wl), wo.z.abs()),
            TransportMode::Importance => (self.scattering(wo, wi, wl), wi.z.abs()),
        };
        if cos > 0.0 { s / cos } else { SampledSpectrum::ZERO }
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        if !ctx.is_enabled(BsdfFlags::GLOSSY) {
            return 0.0;
        }
        let (inc, a) = self.incidence_and_attenuation(wi, wl);
        self.density_at(&inc, &Self::lobe_pmf(&a, wl), wo)
    }

    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        if !ctx.is_enabled(BsdfFlags::GLOSSY) {
            return (SampledSpectrum::ZERO, 0.0);
        }
        self.f_and_pdf(ctx, wi, wo, wl)
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !ctx.is_enabled(BsdfFlags::GLOSSY) {
            return None;
        }
        let (inc, a) = self.incidence_and_attenuation(wi, wl);
        let pmf = Self::lobe_pmf(&a, wl);
        // The lobe, and u1 rescaled within its interval for the azimuth.
        let mut p = 0;
        let mut u = u1;
        while p < P_MAX && u >= pmf[p] {
            u -= pmf[p];
            p += 1;
        }
        if pmf[p] <= 0.0 {
            return None;
        }
        let u_phi = (u / pmf[p]).clamp(0.0, 1.0);
        // θo about −θi′ (d'Eon et al. 2011, §4.2).
        let (sin_ip, cos_ip) = self.lobes.tilted(inc.sin_theta, inc.cos_theta, p);
        let l = &self.lobes;
        let v = l.v[p];
        let u0 = u2.x.max(1e-7);
        let cos_theta = (1.0 + v * (u0 + (1.0 - u0) * self.lobes.exp_m2_over_v[p]).ln()).clamp(-1.0, 1.0);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let cos_phi = (TAU * u2.y).cos();
        let sin_o = (-cos_theta * sin_ip + sin_theta * cos_phi * cos_ip).clamp(-1.0, 1.0);
        let cos_o = (1.0 - sin_o * sin_o).max(0.0).sqrt();
        let delta_phi = if p < P_MAX {
            2.0 * p as f32 * inc.gamma_t - 2.0 * inc.gamma_i
                + p as f32 * PI
                + sample_trimmed_logistic_with(u_phi, l.s, l.logistic_lo, l.logistic_mass)
        } else {
            TAU * u_phi
        };
        let (sin_phi_o, cos_phi_o) = (inc.phi + delta_phi).sin_cos();
        let wo = Vec3::new(cos_o * cos_phi_o, sin_o, cos_o * sin_phi_o).normalize();
        let pdf = self.density_at(&inc, &pmf, wo);
        if !(pdf > 0.0) {
            return None;
        }
        // f·|cos θo|/pdf: S/pdf in radiance transport, the adjoint's value in importance.
        // (|cos θo| over the transport's cosine is 1 in radiance mode; in importance mode it grows
        // without bound as wi grazes the normal plane, where a weight that overflows is dropped.)
        let (s, cos) = self.transported(ctx, wi, wo, wl, &inc, &a);
        let weight = (s / pdf) * (wo.z.abs() / cos);
        let weight = if weight.is_finite() {
            weight
        } else {
            SampledSpectrum::ZERO
        };
        Some(BsdfSample {
            wo,
            weight,
            pdf,
            flags: if wo.z * wi.z >= 0.0 {
                BsdfFlags::GLOSSY_REFLECTION
            } else {
                BsdfFlags::GLOSSY_TRANSMISSION
            },
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bessel_i0_matches_tabulated_values() {
        // Abramowitz & Stegun, table 9.8: I₀(1) = 1.266065878, I₀(5) = 27.23987182,
        // I₀(10) = 2815.716628 (the series to x²⁰ is 0.3 % short there; pbrt's and Mitsuba's).
        assert!((bessel_i0(1.0) - 1.266_065_9).abs() < 1e-6);
        assert!((bessel_i0(5.0) / 27.239_872 - 1.0).abs() < 1e-5);
        assert!((bessel_i0(10.0) / 2815.7166 - 1.0).abs() < 5e-3);
        // ln I₀: the series up to 12 (0.6 % short there: I₀(12) = 18948.925), the asymptotic
        // form beyond, whose last term pbrt and Mitsuba write as 1/(16x) where the expansion has
        // 1/(8x): 3e-3 low at 20 (I₀(20) = 4.355828e7).
        assert!((log_bessel_i0(12.0) - 18_948.925f32.ln()).abs() < 7e-3);
        assert!((log_bessel_i0(20.0) - 4.355_828e7f32.ln()).abs() < 4e-3);
    }

    #[test]
    fn longitudinal_lobe_is_normalized_over_the_sphere() {
        // ∫ M_p dω = 1 for every incidence and variance (d'Eon's normalization), by the midpoint
        // rule in θ (the lobe does not depend on φ).
        for &v in &[0.01f32, 0.05, 0.2, 0.8] {
            for &theta_i in &[-1.2f32, -0.3, 0.0, 0.7, 1.4] {
                let (si, ci) = theta_i.sin_cos();
                let n = 20_000;
                let mut sum = 0.0f64;
                for k in 0..n {
                    let th = -std::f32::consts::FRAC_PI_2 + PI * (k as f32 + 0.5) / n as f32;
                    let (so, co) = th.sin_cos();
                    sum += (longitudinal(si, ci, so, co, v) * co * TAU) as f64 * (PI as f64 / n as f64);
                }
                assert!((sum - 1.0).abs() < 4e-3, "v {v} θi {theta_i}: ∫M dω = {sum}");
            }
        }
    }

    #[test]
    fn trimmed_logistic_sampling_inverts_its_cdf() {
        for &s in &[0.05f32, 0.3, 1.2] {
            // The sampled x's density is the trimmed logistic: check the cdf at the sample.
            for &u in &[0.01f32, 0.25, 0.5, 0.8, 0.99] {
                let x = sample_trimmed_logistic(u, s);
                let lo = logistic_cdf(-PI, s);
                let cdf = (logistic_cdf(x, s) - lo) / (logistic_cdf(PI, s) - lo);
                assert!((cdf - u).abs() < 1e-4, "s {s} u {u}: cdf {cdf}");
            }
        }
    }

    #[test]
    fn lossless_fibre_scatters_all_light() {
        // σa = 0: every path leaves the fibre, so ∫ S dω = 1 for every incidence (within the
        // model's approximations: the tilted lobes and the truncated I₀). Uniform sphere
        // sampling, fixed seed.
        let hair = Hair {
            sigma_a: Spectrum::Constant(0.0),
            eta: 1.55,
            lobes: HairLobes::new(0.3, 0.3, 2.0),
        };
        let wl = SampledWavelengths::fixed(550.0);
        let mut rng = crate::rng::Pcg32::new(7, 1);
        for &wi in &[
            Vec3::new(0.3, 0.2, 0.93),
            Vec3::new(-0.7, -0.5, 0.5),
            Vec3::new(0.0, 0.9, 0.43),
        ] {
            let wi = wi.normalize();
            let n = 400_000;
            let mut sum = 0.0f64;
            for _ in 0..n {
                let wo = crate::warp::square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                sum += hair.scattering(wi, wo, &wl)[0] as f64 * 4.0 * std::f64::consts::PI;
            }
            let albedo = sum / n as f64;
            assert!((albedo - 1.0).abs() < 0.02, "wi {wi}: albedo {albedo}");
        }
    }
}
