//! Indices of refraction, constant or dispersive, and the rule that ties dispersion to
//! hero-wavelength termination.
//!
//! A refraction direction needs one scalar η. For a dispersive [`Ior`] the only way to get that
//! scalar is [`Ior::hero_eta`] / [`relative_hero_eta`], which take `&mut SampledWavelengths` and
//! terminate the secondary wavelengths: the path continues with the hero alone (pbrt-v4's
//! `TerminateSecondary`). Amplitudes that do not change a direction (Fresnel reflectance of a
//! reflection) may use all four wavelengths through [`Ior::sample`].

use crate::spectra::Spectrum;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// An index of refraction: a number, or a function of wavelength (Sellmeier, Cauchy, table).
#[derive(Clone, Debug, PartialEq)]
pub enum Ior {
    /// The same index at every wavelength.
    Constant(f32),
    /// A wavelength-dependent index (disperses light).
    Dispersive(Spectrum),
}

impl Ior {
    /// Wraps a spectrum, collapsing a constant one to [`Ior::Constant`].
    pub fn from_spectrum(s: Spectrum) -> Self {
        match s.as_constant() {
            Some(v) => Ior::Constant(v),
            None => Ior::Dispersive(s),
        }
    }

    /// True when the index depends on wavelength.
    pub fn is_dispersive(&self) -> bool {
        matches!(self, Ior::Dispersive(_))
    }

    /// Index at one wavelength. A table that returns 0 outside its range gives 1 (pbrt's
    /// guard: a zero index would divide by zero).
    pub fn eval(&self, lambda: f32) -> f32 {
        match self {
            Ior::Constant(v) => *v,
            Ior::Dispersive(s) => {
                let v = s.eval(lambda);
                if v > 0.0 { v } else { 1.0 }
            }
        }
    }

    /// Index at each of the four wavelengths (for amplitudes only, never for a direction).
    pub fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Ior::Constant(v) => SampledSpectrum::splat(*v),
            Ior::Dispersive(_) => SampledSpectrum::from_fn(|i| self.eval(wl.lambda(i))),
        }
    }

    /// The scalar index that a refraction uses: the value at the hero wavelength. If the index is
    /// dispersive the secondary wavelengths are terminated here.
    pub fn hero_eta(&self, wl: &mut SampledWavelengths) -> f32 {
        match self {
            Ior::Constant(v) => *v,
            Ior::Dispersive(_) => {
                wl.terminate_secondary();
                self.eval(wl.hero())
            }
        }
    }

    /// Value at 589.3 nm (sodium D line), for reports.
    pub fn nominal(&self) -> f32 {
        self.eval(589.3)
    }
}

impl From<f32> for Ior {
    fn from(v: f32) -> Self {
        Ior::Constant(v)
    }
}

/// An index of refraction as a BSDF model holds it: an [`Ior`] (any wavelengths) or a
/// [`SampledIor`] (already evaluated at one path's wavelengths, for the per-hit BSDF value).
/// Either way the only scalar η for a refraction comes from [`IorValue::hero_eta`].
pub trait IorValue: Clone + std::fmt::Debug + Send + Sync {
    /// True when the index depends on wavelength.
    fn is_dispersive(&self) -> bool;
    /// Index at each of the four wavelengths (for amplitudes only, never for a direction).
    fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum;
    /// The scalar index a refraction uses: the hero's; terminates the secondaries if dispersive.
    fn hero_eta(&self, wl: &mut SampledWavelengths) -> f32;
}

impl IorValue for Ior {
    fn is_dispersive(&self) -> bool {
        Ior::is_dispersive(self)
    }
    fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        Ior::sample(self, wl)
    }
    fn hero_eta(&self, wl: &mut SampledWavelengths) -> f32 {
        Ior::hero_eta(self, wl)
    }
}

/// An [`Ior`] evaluated at a path's four wavelengths ([`Ior::at`]): `Copy`, for the BSDF value a
/// material becomes at a hit. Valid only for those wavelengths (a terminated secondary keeps its
/// λ, so termination does not invalidate it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledIor {
    /// The index at each wavelength.
    pub eta: SampledSpectrum,
    /// Whether the index depends on wavelength (refraction then terminates the secondaries).
    pub dispersive: bool,
}

impl Ior {
    /// This index at the four wavelengths of `wl`.
    pub fn at(&self, wl: &SampledWavelengths) -> SampledIor {
        SampledIor {
            eta: self.sample(wl),
            dispersive: self.is_dispersive(),
        }
    }
}

impl IorValue for SampledIor {
    fn is_dispersive(&self) -> bool {
        self.dispersive
    }
    fn sample(&self, _wl: &SampledWavelengths) -> SampledSpectrum {
        self.eta
    }
    fn hero_eta(&self, wl: &mut SampledWavelengths) -> f32 {
        if self.dispersive {
            wl.terminate_secondary();
        }
        self.eta[0]
    }
}

/// Relative index η = n_int/n_ext that a refraction uses; terminates the secondary wavelengths if
/// either side is dispersive.
pub fn relative_hero_eta<I: IorValue>(int_ior: &I, ext_ior: &I, wl: &mut SampledWavelengths) -> f32 {
    let n_int = int_ior.hero_eta(wl);
    let n_ext = ext_ior.hero_eta(wl);
    n_int / n_ext
}

/// Relative index n_int/n_ext per wavelength, for amplitudes only.
pub fn relative_eta<I: IorValue>(int_ior: &I, ext_ior: &I, wl: &SampledWavelengths) -> SampledSpectrum {
    int_ior.sample(wl) / ext_ior.sample(wl)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectra::{Extrapolation, PiecewiseLinear};
    use std::sync::Arc;

    #[test]
    fn dispersive_hero_eta_terminates_and_constant_does_not() {
        let table = PiecewiseLinear::new(vec![400.0, 700.0], vec![1.53, 1.51], Extrapolation::Clamp).unwrap();
        let glass = Ior::from_spectrum(Spectrum::PiecewiseLinear(Arc::new(table)));
        let air = Ior::Constant(1.0);
        let mut wl = SampledWavelengths::sample_visible(0.3);
        let _ = relative_hero_eta(&Ior::Constant(1.5), &air, &mut wl);
        assert!(!wl.secondary_terminated());
        let eta = relative_hero_eta(&glass, &air, &mut wl);
        assert!(wl.secondary_terminated());
        assert!((eta - glass.eval(wl.hero())).abs() < 1e-7);
    }

    #[test]
    fn zero_table_value_becomes_one() {
        let table = PiecewiseLinear::new(vec![400.0, 500.0], vec![1.5, 1.6], Extrapolation::Zero).unwrap();
        let ior = Ior::from_spectrum(Spectrum::PiecewiseLinear(Arc::new(table)));
        assert_eq!(ior.eval(800.0), 1.0);
    }
}
