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

/// Relative index η = n_int/n_ext that a refraction uses; terminates the secondary wavelengths if
/// either side is dispersive.
pub fn relative_hero_eta(int_ior: &Ior, ext_ior: &Ior, wl: &mut SampledWavelengths) -> f32 {
    let n_int = int_ior.hero_eta(wl);
    let n_ext = ext_ior.hero_eta(wl);
    n_int / n_ext
}

/// Relative index n_int/n_ext per wavelength, for amplitudes only.
pub fn relative_eta(int_ior: &Ior, ext_ior: &Ior, wl: &SampledWavelengths) -> SampledSpectrum {
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
