//! `thindielectric`: a zero-thickness dielectric sheet (window pane, soap film without
//! interference), with all internal reflections summed.
//!
//! Lecture, slide "Fresnel Equations" and the Stokes relations: a parallel slab reflects R at
//! each interface and transmits T = 1 − R; light bouncing inside adds a geometric series,
//!
//! ```text
//!     R' = R + T² R (1 + R² + R⁴ + …) = R + T² R/(1 − R²) = 2R/(1 + R)
//!     T' = T²/(1 − R²) = (1 − R)/(1 + R) = 1 − R'
//! ```
//!
//! with R = F(|cos θi|, η) (the same from both sides; no TIR inside a parallel slab). The
//! transmitted ray leaves undeviated, ωo = −ωi, in the medium it came from: no η² factor, η = 1,
//! flags `DELTA | TRANSMISSION | NULL`. Sampling picks reflection with probability R'.
//! [`Bsdf::null_transmission`] returns T' so that shadow rays can pass the sheet.
//!
//! **Dispersion** needs no termination: no direction depends on λ. With a dispersive index the
//! lobe is chosen with the hero's R'₀ and every wavelength keeps the weight R'(λᵢ)/R'₀ (or
//! T'(λᵢ)/T'₀), which is unbiased per wavelength. (pbrt terminates here; that is conservative.)
//!
//! Mitsuba 3 plugin `thindielectric` (`src/bsdfs/thindielectric.cpp`), two-sided:
//!
//! | parameter                | type        | default                |
//! |--------------------------|-------------|------------------------|
//! | `int_ior`                | float, name | `bk7` 1.5046           |
//! | `ext_ior`                | float, name | `air` 1.000277         |
//! | `specular_reflectance`   | spectrum    | 1 (tint; not physical) |
//! | `specular_transmittance` | spectrum    | 1 (tint; not physical) |

use crate::bsdf::{
    Bsdf, BsdfContext, BsdfFlags, BsdfSample, LobeSplit, choose_delta_lobe, light_directions, reflect,
};
use crate::fresnel::{fresnel_dielectric, thin_slab_reflectance, thin_slab_transmittance};
use crate::fresnel_polarized::{fresnel_amplitudes, interface_mueller, normalized};
use crate::ior::{Ior, IorValue, SampledIor, relative_eta};
use crate::mueller::{Mueller, MuellerMatrix};
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};
use num_complex::Complex32;

/// A thin dielectric sheet: Stokes-summed delta reflection and straight-through transmission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectric<S = Spectrum, I = Ior> {
    /// Index of the sheet.
    pub int_ior: I,
    /// Index of the surrounding medium.
    pub ext_ior: I,
    /// Tint of the reflection (default 1).
    pub specular_reflectance: S,
    /// Tint of the transmission, applied once (default 1).
    pub specular_transmittance: S,
}

impl Default for ThinDielectric {
    /// Mitsuba's defaults: bk7 (1.5046) in air (1.000277).
    fn default() -> Self {
        Self::new(Ior::Constant(1.5046), Ior::Constant(1.000277))
    }
}

/// The lobe flags of the straight-through transmission.
const TRANSMISSION: BsdfFlags = BsdfFlags(BsdfFlags::DELTA_TRANSMISSION.0 | BsdfFlags::NULL.0);

impl ThinDielectric {
    /// The lobe flags of the straight-through transmission.
    pub const TRANSMISSION_FLAGS: BsdfFlags = TRANSMISSION;

    /// An untinted sheet of index `int_ior` in a medium of index `ext_ior`.
    pub fn new(int_ior: Ior, ext_ior: Ior) -> Self {
        Self {
            int_ior,
            ext_ior,
            specular_reflectance: Spectrum::Constant(1.0),
            specular_transmittance: Spectrum::Constant(1.0),
        }
    }

    /// This model at the four wavelengths of a path (the per-hit `Copy` value).
    pub fn at(&self, wl: &SampledWavelengths) -> ThinDielectric<SampledSpectrum, SampledIor> {
        ThinDielectric {
            int_ior: self.int_ior.at(wl),
            ext_ior: self.ext_ior.at(wl),
            specular_reflectance: self.specular_reflectance.sample(wl),
            specular_transmittance: self.specular_transmittance.sample(wl),
        }
    }
}

impl<S: SpectralValue, I: IorValue> ThinDielectric<S, I> {
    /// Untinted (R', T') per wavelength at |cos θi| = `cos_theta`.
    pub fn reflectance_transmittance(
        &self,
        cos_theta: f32,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, SampledSpectrum) {
        let c = cos_theta.abs();
        let eta = relative_eta(&self.int_ior, &self.ext_ior, wl);
        let r = SampledSpectrum::from_fn(|i| fresnel_dielectric(c, eta[i]).reflectance);
        (r.map(thin_slab_reflectance), r.map(thin_slab_transmittance))
    }

    /// Both lobes at once, for splitting: each as `sample` makes it with that lobe alone
    /// (weight R′·tint or T′·tint), with the probability R′₀ or 1 − R′₀ that `sample` takes it
    /// (the hero's), which also serves as its `pdf`. The lobes of `ctx` are replaced by each
    /// lobe alone. No direction depends on λ, so a dispersive index splits too; `None` for
    /// grazing ωi.
    pub fn sample_split(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wl: &mut SampledWavelengths,
    ) -> Option<LobeSplit> {
        if wi.z == 0.0 {
            return None;
        }
        let r_hero = self.reflectance_transmittance(wi.z, wl).0[0];
        Some(LobeSplit::of_delta_lobes(r_hero, TRANSMISSION, wl, |lobe, wl| {
            self.sample(&ctx.with_lobes(lobe), wi, 0.5, Vec2::ZERO, wl)
        }))
    }
}

impl<S: SpectralValue, I: IorValue> Bsdf for ThinDielectric<S, I> {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::DELTA_REFLECTION | TRANSMISSION
    }

    fn eval(&self, _ctx: &BsdfContext, _wi: Vec3, _wo: Vec3, _wl: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::ZERO
    }

    fn pdf(&self, _ctx: &BsdfContext, _wi: Vec3, _wo: Vec3, _wl: &SampledWavelengths) -> f32 {
        0.0
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        _u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let (r, t) = self.reflectance_transmittance(wi.z, wl);
        let (reflect_chosen, pdf) = choose_delta_lobe(ctx, u1, r[0])?;
        let (wo, lobe, tint, throughput) = if reflect_chosen {
            (
                reflect(wi),
                BsdfFlags::DELTA_REFLECTION,
                &self.specular_reflectance,
                r,
            )
        } else {
            (-wi, TRANSMISSION, &self.specular_transmittance, t)
        };
        let weight = throughput / pdf * tint.sample(wl);
        (pdf > 0.0 && !weight.is_black()).then_some(BsdfSample {
            wo,
            weight,
            pdf,
            flags: lobe,
            eta: 1.0,
        })
    }

    fn null_transmission(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        let (_, t) = self.reflectance_transmittance(wi.z, wl);
        Some(t * self.specular_transmittance.sample(wl))
    }

    /// `sample` with the polarization of the Stokes series summed per polarization
    /// ([`ThinDielectric::slab_mueller`]).
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        let s = self.sample(ctx, wi, u1, u2, wl)?;
        let m = self.slab_mueller(wi.z, s.flags.is_reflection(), wl);
        let (light_in, light_out) = light_directions(ctx, wi, s.wo);
        Some(s.with_weight(interface_mueller(
            m.scaled(s.weight),
            Vec3::Z,
            light_in,
            light_out,
        )))
    }

    fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        let t = self.null_transmission(wi, wl)?;
        Some(interface_mueller(
            self.slab_mueller(wi.z, false, wl).scaled(t),
            Vec3::Z,
            wi,
            wi,
        ))
    }
}

impl<S: SpectralValue, I: IorValue> ThinDielectric<S, I> {
    /// The polarization of the sheet's reflection (or transmission) with M00 = 1, in the s/p
    /// frames: the Stokes series summed separately for s and p light, R'_x = 2R_x/(1 + R_x),
    /// T'_x = (1 − R_x)/(1 + R_x), and for the s–p cross term (the amplitude products
    /// ρ = Re(a_p a_s*) and τ = √(T_s T_p), the same from both sides, r' = −r inside) the series
    /// ρ + τ²ρ/(1 − ρ²) for reflection and τ²/(1 − ρ²) for transmission. The reflections add
    /// incoherently (no thin-film interference). The unpolarized value stays the model's own
    /// 2R/(1 + R) of the averaged R (Mitsuba's), so only the shape M/M00 comes from the sums.
    pub fn slab_mueller(&self, cos_theta: f32, reflection: bool, wl: &SampledWavelengths) -> MuellerMatrix {
        let c = cos_theta.abs();
        let eta = relative_eta(&self.int_ior, &self.ext_ior, wl);
        let mut el = [[0.0f32; 4]; 4];
        for (i, e) in el.iter_mut().enumerate() {
            let (a_s, a_p) = fresnel_amplitudes(c, Complex32::new(eta[i], 0.0));
            let (rs, rp) = (a_s.norm_sqr(), a_p.norm_sqr());
            let rho = (a_p * a_s.conj()).re;
            let tau2 = (1.0 - rs) * (1.0 - rp);
            let (xs, xp, cross) = if reflection {
                (
                    2.0 * rs / (1.0 + rs),
                    2.0 * rp / (1.0 + rp),
                    rho + tau2 * rho / (1.0 - rho * rho),
                )
            } else {
                (
                    (1.0 - rs) / (1.0 + rs),
                    (1.0 - rp) / (1.0 + rp),
                    tau2 / (1.0 - rho * rho),
                )
            };
            // At grazing incidence ρ² → 1 and τ² → 0: the limit is total reflection, ρ = ±1.
            let cross = if cross.is_finite() { cross } else { rho };
            *e = [0.5 * (xs + xp), 0.5 * (xs - xp), cross, 0.0];
        }
        let col = |j: usize| SampledSpectrum::from_fn(|i| el[i][j]);
        normalized(&MuellerMatrix::interface(col(0), col(1), col(2), col(3)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::TransportMode;
    use crate::spectra::{Extrapolation, PiecewiseLinear};
    use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN};
    use std::sync::Arc;

    fn dir(theta_deg: f32) -> Vec3 {
        let t = theta_deg.to_radians();
        Vec3::new(t.sin(), 0.0, t.cos())
    }

    fn close(a: f32, b: f32, tol: f32) -> bool {
        (a - b).abs() <= tol
    }

    /// Lobe splitting: the lobe `sample` takes with `u1` is one of the two (same direction,
    /// flags and pdf, weight times the probability of taking it), the probabilities are R′₀ and
    /// 1 − R′₀, and the weights R′ and T′ whole at every wavelength, dispersive index included.
    #[test]
    fn split_lobes_are_the_coin_outcomes_of_sample_weighted_whole() {
        let ctx = BsdfContext::radiance();
        let table = PiecewiseLinear::new(
            vec![LAMBDA_MIN, LAMBDA_MAX],
            vec![1.53, 1.50],
            Extrapolation::Clamp,
        );
        let bk7 = Ior::Dispersive(Spectrum::PiecewiseLinear(Arc::new(table.unwrap())));
        for d in [
            ThinDielectric::default(),
            ThinDielectric::new(bk7, Ior::Constant(1.0)),
        ] {
            for wi in [dir(0.0), dir(40.0), dir(85.0), -dir(20.0), -dir(70.0)] {
                let mut wl = SampledWavelengths::from_parts([450.0, 520.0, 590.0, 660.0], [1.0; 4]);
                let split = d.sample_split(&ctx, wi, &mut wl).unwrap();
                assert!(!wl.secondary_terminated());
                let (rp, tp) = d.reflectance_transmittance(wi.z, &wl);
                assert!(close(split.reflectance, rp[0], 1e-7));
                let (r, c_r) = split.reflection.unwrap();
                let (t, c_t) = split.refraction.unwrap();
                assert!(close(c_r + c_t, 1.0, 1e-6) && r.pdf == c_r && t.pdf == c_t);
                for i in 0..4 {
                    assert!(close(r.weight[i], rp[i], 1e-6) && close(t.weight[i], tp[i], 1e-6));
                }
                for u1 in [0.001f32, 0.05, 0.1, 0.5, 0.9, 0.999] {
                    let p = d.sample(&ctx, wi, u1, Vec2::splat(0.5), &mut wl).unwrap();
                    let (lobe, c) = if u1 < split.reflectance {
                        (r, c_r)
                    } else {
                        (t, c_t)
                    };
                    assert!((p.wo - lobe.wo).length() < 1e-6 && p.flags == lobe.flags && p.pdf == lobe.pdf);
                    for i in 0..4 {
                        assert!(
                            close(lobe.weight[i] / c, p.weight[i], 1e-5),
                            "{lobe:?} / {c} vs {p:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn stokes_table_and_sampling_values() {
        // Stokes' sums R′ = 2R/(1 + R) at the defaults of Mitsuba's src/bsdfs/thindielectric.cpp
        // (η = 1.504183).
        let d = ThinDielectric::default();
        let wl = SampledWavelengths::fixed(550.0);
        for (deg, rp, tp) in [
            (0.0f32, 0.077914f32, 0.922086f32),
            (45.0, 0.096734, 0.903266),
            (60.0, 0.164935, 0.835065),
            (80.0, 0.559496, 0.440504),
        ] {
            for wi in [dir(deg), -dir(deg)] {
                let (r, t) = d.reflectance_transmittance(wi.z, &wl);
                assert!(
                    close(r[0], rp, 2e-6) && close(t[0], tp, 2e-6),
                    "θ {deg}: {} {}",
                    r[0],
                    t[0]
                );
                assert!(close(d.null_transmission(wi, &wl).unwrap()[0], tp, 2e-6));
            }
        }
        let ctx = BsdfContext::radiance();
        let mut wl = SampledWavelengths::fixed(550.0);
        let s = d.sample(&ctx, Vec3::Z, 0.01, Vec2::ZERO, &mut wl).unwrap();
        assert!(s.flags == BsdfFlags::DELTA_REFLECTION && close(s.pdf, 0.077914, 2e-6) && s.weight[0] == 1.0);
        let s = d.sample(&ctx, Vec3::Z, 0.99, Vec2::ZERO, &mut wl).unwrap();
        assert_eq!(
            (s.wo, s.flags, s.weight[0], s.eta),
            (-Vec3::Z, ThinDielectric::TRANSMISSION_FLAGS, 1.0, 1.0)
        );
        assert!(close(s.pdf, 0.922086, 2e-6));
        let wi = dir(60.0);
        let s = d.sample(&ctx, wi, 0.01, Vec2::ZERO, &mut wl).unwrap();
        assert!(close(s.pdf, 0.164935, 2e-6) && s.wo == reflect(wi));
        let s = d.sample(&ctx, wi, 0.99, Vec2::ZERO, &mut wl).unwrap();
        assert!(close(s.pdf, 0.835065, 2e-6) && s.wo == -wi, "undeviated");
        assert!((s.wo - Vec3::new(-0.866025, 0.0, -0.5)).length() < 1e-5);
    }

    #[test]
    fn energy_is_one_in_both_modes_and_from_both_sides() {
        let d = ThinDielectric::default();
        for mode in [TransportMode::Radiance, TransportMode::Importance] {
            let ctx = BsdfContext {
                mode,
                lobes: BsdfFlags::ALL,
            };
            for deg in [0.0f32, 30.0, 45.0, 60.0, 80.0, 89.5] {
                for wi in [dir(deg), -dir(deg)] {
                    let mut total = 0.0;
                    for u1 in [0.0, 1.0 - f32::EPSILON] {
                        let mut wl = SampledWavelengths::fixed(600.0);
                        let s = d.sample(&ctx, wi, u1, Vec2::ZERO, &mut wl).unwrap();
                        total += s.pdf * s.weight[0];
                    }
                    assert!(close(total, 1.0, 1e-6), "θ {deg}: {total}");
                }
            }
        }
    }

    #[test]
    fn single_lobe_contexts_weigh_by_r_and_t() {
        let d = ThinDielectric::default();
        let wi = dir(45.0);
        let mut wl = SampledWavelengths::fixed(550.0);
        let r_only = BsdfContext::radiance().with_lobes(BsdfFlags::DELTA_REFLECTION);
        let t_only = BsdfContext::radiance().with_lobes(BsdfFlags::DELTA_TRANSMISSION);
        for u1 in [0.0, 0.5, 0.99] {
            let s = d.sample(&r_only, wi, u1, Vec2::ZERO, &mut wl).unwrap();
            assert!(s.pdf == 1.0 && close(s.weight[0], 0.096734, 2e-6) && s.flags.is_reflection());
            let s = d.sample(&t_only, wi, u1, Vec2::ZERO, &mut wl).unwrap();
            assert!(s.pdf == 1.0 && close(s.weight[0], 0.903266, 2e-6) && s.flags.is_transmission());
        }
    }

    #[test]
    fn transmittance_tint_applies_once() {
        let d = ThinDielectric {
            specular_transmittance: Spectrum::Constant(0.5),
            ..ThinDielectric::default()
        };
        let wl = SampledWavelengths::fixed(550.0);
        assert!(close(
            d.null_transmission(Vec3::Z, &wl).unwrap()[0],
            0.5 * 0.922086,
            2e-6
        ));
        let mut wl = SampledWavelengths::fixed(550.0);
        let s = d
            .sample(&BsdfContext::radiance(), Vec3::Z, 0.99, Vec2::ZERO, &mut wl)
            .unwrap();
        assert!(close(s.weight[0], 0.5, 1e-7));
    }

    #[test]
    fn reflection_frequency_is_stokes_reflectance() {
        let d = ThinDielectric::default();
        let ctx = BsdfContext::radiance();
        let n = 100_000;
        for deg in [0.0f32, 60.0, 80.0] {
            let wi = dir(deg);
            let mut hits = 0;
            // A golden-ratio sequence: deterministic and equidistributed.
            for j in 0..n {
                let u1 = (0.5 + j as f64 * 0.618_033_988_749_894_9).fract() as f32;
                let mut wl = SampledWavelengths::fixed(550.0);
                hits += d
                    .sample(&ctx, wi, u1, Vec2::ZERO, &mut wl)
                    .unwrap()
                    .flags
                    .is_reflection() as usize;
            }
            let rp = d
                .reflectance_transmittance(wi.z, &SampledWavelengths::fixed(550.0))
                .0[0];
            assert!((hits as f32 / n as f32 - rp).abs() < 1e-3, "θ {deg}");
        }
    }

    #[test]
    fn dispersive_sheet_keeps_all_wavelengths() {
        let table = PiecewiseLinear::new(vec![400.0, 700.0], vec![1.53, 1.51], Extrapolation::Clamp).unwrap();
        let d = ThinDielectric::new(
            Ior::from_spectrum(Spectrum::PiecewiseLinear(Arc::new(table))),
            Ior::Constant(1.0),
        );
        let ctx = BsdfContext::radiance();
        let wi = dir(75.0);
        let lambdas = [LAMBDA_MIN + 50.0, 500.0, 600.0, LAMBDA_MAX - 100.0];
        let (r, t) = d.reflectance_transmittance(wi.z, &SampledWavelengths::from_parts(lambdas, [1.0; 4]));
        assert!(r[0] != r[3], "R' depends on λ");
        let n = 50_000;
        let (mut mr, mut mt) = ([0.0f64; 4], [0.0f64; 4]);
        for j in 0..n {
            let u1 = (j as f32 + 0.5) / n as f32;
            let mut wl = SampledWavelengths::from_parts(lambdas, [1.0; 4]);
            let s = d.sample(&ctx, wi, u1, Vec2::ZERO, &mut wl).unwrap();
            assert!(!wl.secondary_terminated());
            let acc = if s.flags.is_reflection() { &mut mr } else { &mut mt };
            for i in 0..4 {
                acc[i] += s.weight[i] as f64 / n as f64;
            }
        }
        for i in 0..4 {
            assert!(
                (mr[i] - r[i] as f64).abs() < 5e-5 && (mt[i] - t[i] as f64).abs() < 5e-5,
                "λ {}",
                lambdas[i]
            );
        }
    }
}
