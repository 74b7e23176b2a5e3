//! Energy (white-furnace) checks: directional albedo, as in pbrt-v4's energy test
//! (`src/pbrt/bsdfs_test.cpp`).
//!
//! The directional albedo a(wi) = ∫ f(wi, ωo)·|cos θo| dωo (delta lobes included) is estimated
//! two independent ways:
//!
//! * **importance sampling**: the mean of `sample`'s weight (failed samples count 0), split into
//!   R (wo on wi's side) and T (the other side), with the sample standard error: this is the
//!   quantity a path tracer multiplies by, delta lobes included;
//! * **uniform sampling of `eval`**: the mean of f·|cos θo|/p over uniform directions on the
//!   sphere, p = 1/(4π), one jittered direction per cell of a k × k grid of the square the
//!   sphere is warped from. It sees smooth lobes only and does not trust `sample` or `pdf`.
//!   Its standard error is the independent samples' formula, an upper bound for stratified
//!   ones. Independent directions would hit a narrow lobe a Poisson number of times (Mitsuba's
//!   default `roughdielectric`, α = 0.1, at normal incidence refracts 90 % of its light into
//!   0.008 sr, which 3 300 directions meet about twice): with too few hits the estimate and its own standard
//!   error both come out low, and `gonio check` failed that model by 5–8 standard errors that
//!   were not there. Stratified, every lobe of solid angle Ω gets its N·Ω/4π hits.
//!
//! Rows:
//! * `energy`: in importance mode R + T ≤ 1 (+ k·σ, + 1e-6 for `f32` rounding) at every
//!   incidence angle, side and wavelength (pbrt-v4's energy test requires < 1.01 at 16k
//!   samples; we derive the slack from the standard error instead). In radiance mode a
//!   refraction into a denser medium legitimately exceeds 1 (F + (1 − F)η² from inside), so
//!   radiance-mode albedos are only reported.
//! * `albedo_estimators`: the smooth part of the importance estimate (delta samples excluded)
//!   equals the uniform estimate within k combined standard errors, in both modes. A weight
//!   inconsistent with eval/pdf, or a mixture whose smooth pdf omits a lobe (Mitsuba's
//!   blendbsdf bias, measured with Mitsuba 3.9.1), fails here.

use super::{Bound, CheckConfig, CheckResult, direction, sidak, z_quantile};
use crate::bsdf::{Bsdf, BsdfContext, TransportMode};
use crate::rng::ONE_MINUS_EPSILON;
use crate::rng::Pcg32;
use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use crate::warp::{square_to_uniform_sphere, square_to_uniform_sphere_pdf};
use glam::{Vec2, Vec3};

const N: usize = N_SPECTRUM_SAMPLES;

/// Running mean and standard error, per wavelength.
#[derive(Clone, Copy, Debug, Default)]
struct Moments {
    s1: [f64; N],
    s2: [f64; N],
}

impl Moments {
    fn add(&mut self, v: [f64; N]) {
        for ((s1, s2), x) in self.s1.iter_mut().zip(&mut self.s2).zip(v) {
            *s1 += x;
            *s2 += x * x;
        }
    }
    fn mean(&self, n: usize) -> [f64; N] {
        std::array::from_fn(|i| self.s1[i] / n as f64)
    }
    fn se(&self, n: usize) -> [f64; N] {
        std::array::from_fn(|i| {
            let m = self.s1[i] / n as f64;
            ((self.s2[i] / n as f64 - m * m).max(0.0) / n as f64).sqrt()
        })
    }
}

/// A directional-albedo estimate, per wavelength slot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Albedo {
    /// Reflected part R: scattering that leaves on wi's side.
    pub r: [f64; N],
    /// Standard error of `r`.
    pub r_se: [f64; N],
    /// Transmitted part T: the other side.
    pub t: [f64; N],
    /// Standard error of `t`.
    pub t_se: [f64; N],
    /// Standard error of R + T.
    pub total_se: [f64; N],
    /// The smooth (non-delta) part of R + T.
    pub smooth: [f64; N],
    /// Standard error of `smooth`.
    pub smooth_se: [f64; N],
    /// Number of estimator samples.
    pub samples: usize,
}

impl Albedo {
    /// R + T per wavelength slot.
    pub fn total(&self) -> [f64; N] {
        std::array::from_fn(|i| self.r[i] + self.t[i])
    }
}

/// Importance-sampling estimate of the albedo from `n` calls of `sample` with independent
/// uniforms. `wl` is copied for every call (a dispersive refraction may terminate its
/// secondaries; use [`SampledWavelengths::fixed`] for per-wavelength albedos).
pub fn albedo_sampled(
    bsdf: &dyn Bsdf,
    ctx: &BsdfContext,
    wi: Vec3,
    wl: &SampledWavelengths,
    n: usize,
    rng: &mut Pcg32,
) -> Albedo {
    albedo_sampled_by(
        bsdf,
        ctx,
        wi,
        n,
        rng,
        |_| *wl,
        |_, w| w.to_array().map(|x| x as f64),
    )
}

/// [`albedo_sampled`] with the wavelengths drawn per sample by `draw` and the sample weight turned
/// into the per-slot values by `value` (e.g. the spectral estimator (1/N)Σ w(λᵢ)/p(λᵢ) for an
/// albedo averaged over the visible range, as `gonio plot albedo` shows). `draw` runs before the
/// sample's own uniforms are taken from `rng`.
pub fn albedo_sampled_by(
    bsdf: &(impl Bsdf + ?Sized),
    ctx: &BsdfContext,
    wi: Vec3,
    n: usize,
    rng: &mut Pcg32,
    mut draw: impl FnMut(&mut Pcg32) -> SampledWavelengths,
    value: impl Fn(&SampledWavelengths, SampledSpectrum) -> [f64; N],
) -> Albedo {
    let (mut r, mut t, mut tot, mut sm) = (
        Moments::default(),
        Moments::default(),
        Moments::default(),
        Moments::default(),
    );
    for _ in 0..n {
        let mut wl2 = draw(rng);
        let u1 = rng.next_f32();
        let s = bsdf.sample(ctx, wi, u1, rng.next_vec2(), &mut wl2);
        let (w, refl, smooth) = match s {
            Some(s) => (value(&wl2, s.weight), s.wo.z * wi.z > 0.0, !s.flags.is_delta()),
            None => ([0.0; N], true, true),
        };
        let zero = [0.0; N];
        r.add(if refl { w } else { zero });
        t.add(if refl { zero } else { w });
        tot.add(w);
        sm.add(if smooth { w } else { zero });
    }
    Albedo {
        r: r.mean(n),
        r_se: r.se(n),
        t: t.mean(n),
        t_se: t.se(n),
        total_se: tot.se(n),
        smooth: sm.mean(n),
        smooth_se: sm.se(n),
        samples: n,
    }
}

/// Uniform-sphere estimate of the smooth albedo ∫ f·|cos θo| dωo from about `n` calls of
/// `eval`, stratified (module docs: k × k jittered cells, k = ⌊√n⌋; `samples` says how many);
/// delta lobes are invisible to it: `smooth` = R + T.
pub fn albedo_uniform(
    bsdf: &dyn Bsdf,
    ctx: &BsdfContext,
    wi: Vec3,
    wl: &SampledWavelengths,
    n: usize,
    rng: &mut Pcg32,
) -> Albedo {
    let inv_pdf = 1.0 / square_to_uniform_sphere_pdf() as f64;
    let k = (n as f64).sqrt().floor().max(1.0) as usize;
    let n = k * k;
    let (mut r, mut t, mut tot) = (Moments::default(), Moments::default(), Moments::default());
    for cell in 0..n {
        let jitter = rng.next_vec2();
        let u = (Vec2::new((cell % k) as f32, (cell / k) as f32) + jitter) / k as f32;
        let wo = square_to_uniform_sphere(u.min(Vec2::splat(ONE_MINUS_EPSILON)));
        let f = bsdf.eval(ctx, wi, wo, wl);
        let c = (wo.z as f64).abs() * inv_pdf;
        let v = f.to_array().map(|x| x as f64 * c);
        let zero = [0.0; N];
        let refl = wo.z * wi.z > 0.0;
        r.add(if refl { v } else { zero });
        t.add(if refl { zero } else { v });
        tot.add(v);
    }
    let total_se = tot.se(n);
    Albedo {
        r: r.mean(n),
        r_se: r.se(n),
        t: t.mean(n),
        t_se: t.se(n),
        total_se,
        smooth: tot.mean(n),
        smooth_se: total_se,
        samples: n,
    }
}

/// Hits a smooth lobe must get from the uniform estimator before its standard error is
/// trusted: its effective sample size (Σv)²/Σv², about the number of directions in the lobe.
const MIN_EFFECTIVE_SAMPLES: f64 = 64.0;

/// [`albedo_uniform`] with `n`, 4n, 16n or 64n directions: the first that resolves the smooth
/// albedo `imp` (the importance estimate) found, i.e. gives every wavelength slot whose sampled
/// smooth albedo is positive at least [`MIN_EFFECTIVE_SAMPLES`] effective samples. A lobe
/// narrower than 4π·64/N steradians gets too few of N uniform directions for a standard error
/// (Mitsuba's default `roughdielectric` refracts 90 % of its light into 0.008 sr at normal
/// incidence: about two hits in `--quick`'s 3 300), and a model that reflects only through delta lobes needs none.
fn albedo_uniform_resolved(
    bsdf: &dyn Bsdf,
    ctx: &BsdfContext,
    wi: Vec3,
    wl: &SampledWavelengths,
    n: usize,
    imp: &Albedo,
    rng: &mut Pcg32,
) -> Albedo {
    let mut m = n;
    loop {
        let uni = albedo_uniform(bsdf, ctx, wi, wl, m, rng);
        let resolved = (0..N).all(|c| {
            let (mean, se) = (uni.smooth[c], uni.smooth_se[c]);
            let ess = mean * mean / (se * se + mean * mean / uni.samples as f64);
            imp.smooth[c] <= 1e-6 || ess >= MIN_EFFECTIVE_SAMPLES
        });
        if resolved || m >= 64 * n {
            return uni;
        }
        m *= 4;
    }
}

/// The `energy` and `albedo_estimators` rows at level `alpha_row` each.
pub fn energy(bsdf: &dyn Bsdf, config: &CheckConfig, alpha_row: f64) -> Vec<CheckResult> {
    let mut rng = config.rng(0x000e_4e69);
    let n = config.energy_samples;
    let per_mode = config.energy_angles_deg.len() * 2 * config.energy_wavelengths.len();
    // One-sided bound (≤ 1) over the importance-mode queries; two-sided equality over both modes.
    let k1 = z_quantile(2.0 * sidak(alpha_row, per_mode));
    let k2 = z_quantile(sidak(alpha_row, 2 * per_mode));

    let mut pass1 = true;
    let mut worst1 = (f64::NEG_INFINITY, 0.0f64, 0.0f64, String::new()); // (excess, total, thr, where)
    let (mut max_r, mut max_t, mut max_rad) = ((0.0f64, String::new()), (0.0f64, String::new()), 0.0f64);
    let mut pass2 = true;
    let mut worst2 = (0.0f64, String::new());

    for mode in [TransportMode::Importance, TransportMode::Radiance] {
        let ctx = BsdfContext {
            mode,
            ..BsdfContext::radiance()
        };
        for &theta in &config.energy_angles_deg {
            for side in [1.0f32, -1.0] {
                let wi = direction(theta, 37.0, side);
                for &lambda in &config.energy_wavelengths {
                    let wl = SampledWavelengths::fixed(lambda);
                    let imp = albedo_sampled(bsdf, &ctx, wi, &wl, n, &mut rng);
                    let uni = albedo_uniform_resolved(bsdf, &ctx, wi, &wl, n, &imp, &mut rng);
                    let at = format!("θi={theta}° side={side:+} λ={lambda}nm {mode:?}");
                    for c in 0..N {
                        let total = imp.r[c] + imp.t[c];
                        if mode == TransportMode::Importance {
                            let thr = 1.0 + k1 * imp.total_se[c] + 1e-6;
                            pass1 &= total.is_finite() && total <= thr;
                            if total - thr > worst1.0 || total.is_nan() {
                                worst1 = (total - thr, total, thr, at.clone());
                            }
                            if imp.r[c] > max_r.0 {
                                max_r = (imp.r[c], at.clone());
                            }
                            if imp.t[c] > max_t.0 {
                                max_t = (imp.t[c], at.clone());
                            }
                        } else {
                            max_rad = max_rad.max(total);
                        }
                        let se = (imp.smooth_se[c].powi(2) + uni.smooth_se[c].powi(2)).sqrt();
                        // 1e-6: f32 rounding when both estimators are exact (zero variance).
                        let d = ((imp.smooth[c] - uni.smooth[c]).abs() - 1e-6).max(0.0);
                        let z = if d == 0.0 { 0.0 } else { d / se.max(1e-300) };
                        pass2 &= z.is_finite() && z <= k2;
                        if z > worst2.0 || z.is_nan() {
                            worst2 = (
                                if z.is_nan() { f64::INFINITY } else { z },
                                format!(
                                    "{at}: sampled {:.5}±{:.5} vs uniform {:.5}±{:.5}",
                                    imp.smooth[c], imp.smooth_se[c], uni.smooth[c], uni.smooth_se[c]
                                ),
                            );
                        }
                    }
                }
            }
        }
    }
    vec![
        CheckResult::with_verdict(
            "energy",
            worst1.1,
            Bound::AtMost,
            worst1.2,
            pass1,
            format!(
                "importance-mode albedo R+T, {n} samples per query; worst at {}; max R {:.5} ({}), max T {:.5} ({}); radiance-mode max {:.5}",
                worst1.3, max_r.0, max_r.1, max_t.0, max_t.1, max_rad
            ),
        ),
        CheckResult::with_verdict(
            "albedo_estimators",
            worst2.0,
            Bound::AtMost,
            k2,
            pass2,
            format!(
                "|sampled − uniform smooth albedo| in standard errors; worst {}",
                worst2.1
            ),
        ),
    ]
}
