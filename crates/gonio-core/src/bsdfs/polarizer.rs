//! `polarizer`, `retarder`, `circular`: ideal thin optical filters that light crosses without
//! changing direction (ωo = −ωi), changing only its polarization.
//!
//! Mueller matrices (Collett, *Polarized Light*, ch. 5 eq. 13; Goldstein, *Polarized Light* 3rd
//! ed., eq. 6.43; Chipman et al., *Polarized Light and Optical Systems*, table 6.2), for a beam
//! along `forward` (the direction light travels), θ the filter's angle:
//!
//! ```text
//!     polarizer  t · ½[1 1 0 0; 1 1 0 0; 0…; 0…]                 in the basis whose x-axis is the
//!                                                                tilted transmission axis
//!     retarder   t · R(θ)ᵀ [1 0 0 0; 0 1 0 0; 0 0 cos δ' sin δ'; 0 0 −sin δ' cos δ'] R(θ),
//!                δ' = δ |cos θi|                                 in the basis of x = (1, 0, 0)
//!     circular   t · ½[1 0 0 ±1; 0…; 0…; ±1 0 0 1]               (every basis: rotation invariant)
//! ```
//!
//! As Mitsuba 3 (`src/bsdfs/polarizer.cpp`, `retarder.cpp`, `circular.cpp`): the polarizer's
//! transmission axis is forward × normalize(a − (a·forward) forward) with the absorbing axis
//! a = (sin θ, cos θ, 0), which handles oblique incidence (Korger et al. 2013, "The polarization
//! properties of a tilted polarizer"); the retarder's phase falls
//! off with |cos θi| and its reference axis is the local x-axis, the angle to the implicit Stokes
//! basis measured as Mitsuba's `rotate_mueller_basis_collinear` measures it. In an unpolarized
//! render they are what Mitsuba's unpolarized variants make of them: the polarizer transmits
//! t/2 (unpolarized light through an ideal polarizer), the retarder t, the
//! circular polarizer t/2. Flags: straight-through delta transmission (`DELTA | TRANSMISSION |
//! NULL`, Mitsuba's `Null`), two-sided; [`Bsdf::null_transmission`] passes shadow rays.
//!
//! | plugin      | parameter       | type           | default |
//! |-------------|-----------------|----------------|---------|
//! | `polarizer` | `theta`         | float, degrees | 0       |
//! |             | `transmittance` | spectrum       | 1       |
//! |             | `polarizing`    | boolean        | true (false: an absorber of t/2) |
//! | `retarder`  | `theta`         | float, degrees | 0 (mirrored from the back side) |
//! |             | `delta`         | float, degrees | 90 (a quarter-wave plate) |
//! |             | `transmittance` | spectrum       | 1       |
//! | `circular`  | `transmittance` | spectrum       | 1       |
//! |             | `left_handed`   | boolean        | false   |
//!
//! (Mitsuba also accepts textures for `theta` and `delta`; here they are constants.)

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, light_directions};
use crate::fresnel_polarized::normalized;
use crate::mueller::{Mueller, MuellerMatrix, StokesBasis};
use crate::spectra::{SpectralValue, Spectrum};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// Straight-through transmission.
const PASS: BsdfFlags = BsdfFlags(BsdfFlags::DELTA_TRANSMISSION.0 | BsdfFlags::NULL.0);

/// A straight-through filter: its unpolarized transmittance and its Mueller matrix for a beam.
trait Filter {
    /// What an unpolarized render sees.
    fn unpolarized(&self, wl: &SampledWavelengths) -> SampledSpectrum;
    /// The Mueller matrix for light travelling along `forward` (unit), crossing at incidence
    /// cosine `cos_theta`.
    fn mueller(&self, forward: Vec3, cos_theta: f32, wl: &SampledWavelengths) -> Mueller;
}

fn filter_sample<F: Filter>(
    f: &F,
    ctx: &BsdfContext,
    wi: Vec3,
    wl: &SampledWavelengths,
) -> Option<BsdfSample> {
    if !ctx.is_enabled(BsdfFlags::DELTA_TRANSMISSION) || wi.z == 0.0 {
        return None;
    }
    let weight = f.unpolarized(wl);
    (!weight.is_black()).then_some(BsdfSample {
        wo: -wi,
        weight,
        pdf: 1.0,
        flags: PASS,
        eta: 1.0,
    })
}

/// The filter's matrix with M00 set to the unpolarized weight `w` exactly.
fn with_intensity(m: Mueller, w: SampledSpectrum) -> Mueller {
    let shape = normalized(m.matrix());
    match m.frames() {
        Some((i, o)) => Mueller::new(shape.scaled(w), i, o),
        None => Mueller::frame_free(shape.scaled(w)),
    }
}

/// Mitsuba's `rotate_mueller_basis_collinear(M, forward, current, stokes_basis(forward))` for a
/// reference axis `current` that need not be perpendicular to `forward`: the angle is that
/// between the two vectors as given (`unit_angle`), signed by forward · (current × target).
fn collinear_to_implicit(m: &MuellerMatrix, forward: Vec3, current: Vec3) -> Mueller {
    let target = StokesBasis::implicit(forward);
    let c = current.normalize();
    let x = c.cross(target.x());
    let mut theta = x.length().atan2(c.dot(target.x()));
    if forward.dot(x) < 0.0 {
        theta = -theta;
    }
    let r = MuellerMatrix::rotator(theta);
    Mueller::new(r * *m * r.transpose(), target, target)
}

macro_rules! filter_bsdf {
    ($t:ident) => {
        impl<S: SpectralValue> Bsdf for $t<S> {
            fn flags(&self) -> BsdfFlags {
                PASS
            }
            fn eval(&self, _: &BsdfContext, _: Vec3, _: Vec3, _: &SampledWavelengths) -> SampledSpectrum {
                SampledSpectrum::ZERO
            }
            fn pdf(&self, _: &BsdfContext, _: Vec3, _: Vec3, _: &SampledWavelengths) -> f32 {
                0.0
            }
            fn sample(
                &self,
                ctx: &BsdfContext,
                wi: Vec3,
                _u1: f32,
                _u2: Vec2,
                wl: &mut SampledWavelengths,
            ) -> Option<BsdfSample> {
                filter_sample(self, ctx, wi, wl)
            }
            fn null_transmission(&self, _wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
                Some(self.unpolarized(wl))
            }
            fn sample_mueller(
                &self,
                ctx: &BsdfContext,
                wi: Vec3,
                _u1: f32,
                _u2: Vec2,
                wl: &mut SampledWavelengths,
            ) -> Option<BsdfSample<Mueller>> {
                let s = filter_sample(self, ctx, wi, wl)?;
                let (light_in, _) = light_directions(ctx, wi, s.wo);
                Some(s.with_weight(with_intensity(self.mueller(light_in, wi.z, wl), s.weight)))
            }
            /// Light crossing along `wi` (towards the shadow ray's origin).
            fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
                Some(with_intensity(
                    self.mueller(wi, wi.z, wl),
                    self.unpolarized(wl),
                ))
            }
        }
    };
}

/// `polarizer`: an ideal linear polarizer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polarizer<S = Spectrum> {
    /// Angle of the transmission axis, degrees (0: the tilted local y-axis's perpendicular).
    pub theta: f32,
    /// Transmittance t of the transmitted component.
    pub transmittance: S,
    /// false: an absorber of t/2, polarizing nothing.
    pub polarizing: bool,
}

impl Default for Polarizer {
    fn default() -> Self {
        Self {
            theta: 0.0,
            transmittance: Spectrum::Constant(1.0),
            polarizing: true,
        }
    }
}

impl Polarizer {
    /// This model at the four wavelengths of a path.
    pub fn at(&self, wl: &SampledWavelengths) -> Polarizer<SampledSpectrum> {
        Polarizer {
            theta: self.theta,
            transmittance: self.transmittance.sample(wl),
            polarizing: self.polarizing,
        }
    }
}

impl<S: SpectralValue> Filter for Polarizer<S> {
    fn unpolarized(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        self.transmittance.sample(wl) * 0.5
    }
    fn mueller(&self, forward: Vec3, _cos_theta: f32, wl: &SampledWavelengths) -> Mueller {
        let t = self.transmittance.sample(wl);
        if !self.polarizing {
            return Mueller::absorber(t * 0.5);
        }
        // The absorbing axis (sin θ, cos θ, 0), projected perpendicular to the beam; the
        // transmission axis is forward × that.
        let (s, c) = self.theta.to_radians().sin_cos();
        let a = Vec3::new(s, c, 0.0);
        let a = (a - a.dot(forward) * forward).try_normalize().unwrap_or(Vec3::X);
        let axis = StokesBasis::new(forward, forward.cross(a).normalize());
        let lp = MuellerMatrix::from_f32([[0.5, 0.5, 0.0, 0.0], [0.5, 0.5, 0.0, 0.0], [0.0; 4], [0.0; 4]]);
        let target = StokesBasis::implicit(forward);
        Mueller::new(lp.scaled(t), axis, axis).in_bases(target, target)
    }
}

filter_bsdf!(Polarizer);

/// `retarder`: an ideal linear retarder (wave plate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Retarder<S = Spectrum> {
    /// Angle of the fast axis, degrees (mirrored when crossed from the back side).
    pub theta: f32,
    /// Phase difference between the fast and slow axes at normal incidence, degrees.
    pub delta: f32,
    /// Transmittance t.
    pub transmittance: S,
}

impl Default for Retarder {
    fn default() -> Self {
        Self::new(0.0, 90.0)
    }
}

impl Retarder {
    /// A clear retarder of fast axis `theta` and phase `delta`, degrees.
    pub fn new(theta: f32, delta: f32) -> Self {
        Self {
            theta,
            delta,
            transmittance: Spectrum::Constant(1.0),
        }
    }
    /// This model at the four wavelengths of a path.
    pub fn at(&self, wl: &SampledWavelengths) -> Retarder<SampledSpectrum> {
        Retarder {
            theta: self.theta,
            delta: self.delta,
            transmittance: self.transmittance.sample(wl),
        }
    }
}

impl<S: SpectralValue> Filter for Retarder<S> {
    fn unpolarized(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        self.transmittance.sample(wl)
    }
    fn mueller(&self, forward: Vec3, cos_theta: f32, wl: &SampledWavelengths) -> Mueller {
        let delta = self.delta.to_radians() * cos_theta.abs();
        let (s, c) = delta.sin_cos();
        let lr = MuellerMatrix::from_f32([
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, c, s],
            [0.0, 0.0, -s, c],
        ]);
        let theta = if cos_theta >= 0.0 { self.theta } else { -self.theta };
        let m = lr
            .rotated_element(theta.to_radians())
            .scaled(self.transmittance.sample(wl));
        collinear_to_implicit(&m, forward, Vec3::X)
    }
}

filter_bsdf!(Retarder);

/// `circular`: an ideal right (or left) circular polarizer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircularPolarizer<S = Spectrum> {
    /// Transmittance t.
    pub transmittance: S,
    /// Left instead of right circular polarization.
    pub left_handed: bool,
}

impl Default for CircularPolarizer {
    fn default() -> Self {
        Self {
            transmittance: Spectrum::Constant(1.0),
            left_handed: false,
        }
    }
}

impl CircularPolarizer {
    /// This model at the four wavelengths of a path.
    pub fn at(&self, wl: &SampledWavelengths) -> CircularPolarizer<SampledSpectrum> {
        CircularPolarizer {
            transmittance: self.transmittance.sample(wl),
            left_handed: self.left_handed,
        }
    }
}

impl<S: SpectralValue> Filter for CircularPolarizer<S> {
    fn unpolarized(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        self.transmittance.sample(wl) * 0.5
    }
    fn mueller(&self, _forward: Vec3, _cos_theta: f32, wl: &SampledWavelengths) -> Mueller {
        Mueller::circular_polarizer(!self.left_handed) * self.transmittance.sample(wl)
    }
}

filter_bsdf!(CircularPolarizer);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mueller::Stokes;

    #[test]
    fn unpolarized_values_are_mitsubas() {
        let wl = SampledWavelengths::fixed(550.0);
        let ctx = BsdfContext::radiance();
        let wi = Vec3::new(0.3, 0.2, 0.9).normalize();
        let p = Polarizer {
            transmittance: Spectrum::Constant(0.8),
            ..Polarizer::default()
        };
        let s = p
            .sample(&ctx, wi, 0.5, Vec2::splat(0.5), &mut wl.clone())
            .unwrap();
        assert_eq!(
            (s.wo, s.weight[0], s.pdf, s.flags, s.eta),
            (-wi, 0.4, 1.0, PASS, 1.0)
        );
        assert_eq!(Retarder::default().null_transmission(wi, &wl).unwrap()[0], 1.0);
        assert_eq!(
            CircularPolarizer::default().null_transmission(wi, &wl).unwrap()[0],
            0.5
        );
        // Masked by the context: no sample.
        let refl = BsdfContext::radiance().with_lobes(BsdfFlags::DELTA_REFLECTION);
        assert!(
            p.sample(&refl, wi, 0.5, Vec2::splat(0.5), &mut wl.clone())
                .is_none()
        );
    }

    #[test]
    fn malus_through_two_polarizer_plugins_at_normal_incidence() {
        let wl = SampledWavelengths::fixed(550.0);
        let ctx = BsdfContext::radiance();
        let wi = Vec3::Z;
        let first = Polarizer::default();
        for deg in [0.0f32, 30.0, 60.0, 90.0] {
            let second = Polarizer {
                theta: deg,
                ..Polarizer::default()
            };
            let a = first
                .sample_mueller(&ctx, wi, 0.5, Vec2::ZERO, &mut wl.clone())
                .unwrap()
                .weight;
            let b = second
                .sample_mueller(&ctx, wi, 0.5, Vec2::ZERO, &mut wl.clone())
                .unwrap()
                .weight;
            let out = (b * a)
                .apply(&Stokes::unpolarized(SampledSpectrum::ONE))
                .components()[0][0];
            let want = 0.5 * deg.to_radians().cos().powi(2);
            assert!((out - want).abs() < 1e-6, "{deg}°: {out} vs {want}");
        }
    }
}
