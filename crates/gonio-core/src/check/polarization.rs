//! `mueller_physical`: every polarized value of a BSDF maps physical light to physical light.
//!
//! A Stokes vector s is physical when s0 ≥ 0 and |(s1, s2, s3)| ≤ s0 (its degree of
//! polarization is at most 1). For random direction pairs, wavelengths and both transport
//! modes, the check applies [`Bsdf::eval_mueller`] and the weight of [`Bsdf::sample_mueller`] to
//! five fully or un-polarized probes (unpolarized; horizontal; +45°; right circular; an elliptical
//! state) and counts the outputs that are not physical (a relative tolerance of 10⁻⁴ of the
//! matrix's largest element for f32 round-off; the polarizing rough dielectric's worst excess
//! over random queries is 1.5·10⁻⁵). A depolarizing model passes trivially; a polarizing one
//! with a sign or frame error in its Fresnel matrix does not (a test below).

use super::{Bound, CheckConfig, CheckResult, random_wavelengths, uniform_sphere};
use crate::bsdf::{Bsdf, BsdfContext};
use crate::mueller::Mueller;
use crate::spectrum::N_SPECTRUM_SAMPLES;

/// Fully polarized Stokes states (1, cos2χ cos2ψ, cos2χ sin2ψ, sin2χ) and the unpolarized one.
fn probes() -> [[f32; 4]; 5] {
    let s = |psi: f32, chi: f32| {
        let (c2x, s2x) = ((2.0 * chi).cos(), (2.0 * chi).sin());
        [1.0, c2x * (2.0 * psi).cos(), c2x * (2.0 * psi).sin(), s2x]
    };
    [
        [1.0, 0.0, 0.0, 0.0],
        s(0.0, 0.0),
        s(std::f32::consts::FRAC_PI_4, 0.0),
        s(0.0, std::f32::consts::FRAC_PI_4),
        s(0.4, -0.3),
    ]
}

/// Number of (probe, wavelength) outputs of `m` that are not physical. The matrix is divided by
/// its largest element and the outputs are formed in f64: a BSDF value can be 10⁻²³, whose
/// squares underflow f32.
pub fn unphysical_outputs(m: &Mueller) -> usize {
    let mut bad = 0;
    for l in 0..N_SPECTRUM_SAMPLES {
        let scale = (0..16)
            .map(|k| m.get(k / 4, k % 4)[l].abs())
            .fold(0.0f32, f32::max);
        // A zero matrix passes on light unchanged in kind (nothing); NaN/Inf are `health`'s.
        if scale == 0.0 {
            continue;
        }
        for p in probes() {
            let out: [f64; 4] = std::array::from_fn(|r| {
                (0..4)
                    .map(|c| (m.get(r, c)[l] / scale) as f64 * p[c] as f64)
                    .sum()
            });
            let pol = (out[1] * out[1] + out[2] * out[2] + out[3] * out[3]).sqrt();
            if !(out[0] >= -1e-4 && pol <= out[0] + 1e-4) {
                bad += 1;
            }
        }
    }
    bad
}

/// The `mueller_physical` row: `config.pairs / 10` random queries per transport mode.
pub fn mueller_physical(bsdf: &dyn Bsdf, config: &CheckConfig) -> CheckResult {
    let mut rng = config.rng(0x0057_01e5);
    let n = (config.pairs / 10).max(1);
    let (mut bad, mut worst) = (0usize, String::new());
    for ctx in [BsdfContext::radiance(), BsdfContext::importance()] {
        for _ in 0..n {
            let (wi, wo) = (uniform_sphere(&mut rng), uniform_sphere(&mut rng));
            let mut wl = random_wavelengths(&mut rng);
            let e = unphysical_outputs(&bsdf.eval_mueller(&ctx, wi, wo, &wl));
            let (u1, u2) = (rng.next_f32(), rng.next_vec2());
            let s = bsdf
                .sample_mueller(&ctx, wi, u1, u2, &mut wl)
                .map_or(0, |s| unphysical_outputs(&s.weight));
            if e + s > 0 && worst.is_empty() {
                worst = format!("; first at wi {wi}, wo {wo}, {:?}", ctx.mode);
            }
            bad += e + s;
        }
    }
    CheckResult::compare(
        "mueller_physical",
        bad as f64,
        Bound::AtMost,
        0.0,
        format!(
            "unphysical Stokes outputs of eval_mueller and sample_mueller over {} queries × 5 probes × 4 wavelengths{worst}",
            2 * n
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mueller::{MuellerMatrix, StokesBasis};

    fn along_z(m: MuellerMatrix) -> Mueller {
        let b = StokesBasis::implicit(glam::Vec3::Z);
        Mueller::new(m, b, b)
    }

    #[test]
    fn a_matrix_that_polarizes_more_than_fully_is_caught() {
        // A linear polarizer is physical; the same matrix with its M10 doubled "polarizes" the
        // unpolarized probe beyond degree 1.
        let ok = MuellerMatrix::from_f32([
            [0.5, 0.5, 0.0, 0.0],
            [0.5, 0.5, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
        ]);
        assert_eq!(unphysical_outputs(&along_z(ok)), 0);
        let bad = MuellerMatrix::from_f32([
            [0.5, 0.5, 0.0, 0.0],
            [1.0, 0.5, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
        ]);
        assert!(unphysical_outputs(&along_z(bad)) > 0);
    }
}
