//! The energy a single-scattering microfacet surface loses: the directional albedo of a *white*
//! rough conductor (mirror facets, F ≡ 1) against its roughness α.
//!
//! A photon from wi meets a visible facet m (density D_wi(m), Heitz & d'Eon 2014), is mirrored
//! to wo = 2(wi·m)m − wi and leaves if the microsurface does not mask it, with probability
//! G1(wo, m) under Smith's uncorrelated-heights assumption. The single-scattering albedo is
//!
//! ```text
//!   E(wi) = ∫ f(wi, wo) cos θo dωo = E_{m∼D_wi}[ G1(wo(m), m) ]
//! ```
//!
//! computed by deterministic quadrature over the visible-normal sampler
//! ([`MicrofacetDistribution::vndf_expectation`]). The photons that G1 rejects are not absorbed
//! by a real surface of mirrors: they hit another facet and leave after more bounces. A
//! single-scattering model drops them, so a white surface grows darker as it grows rougher —
//! the loss that Heitz et al. 2016 ("Multiple-Scattering Microfacet BSDFs with the Smith Model")
//! recovers with a random walk, and Kulla & Conty 2017 with a compensation lobe.

use crate::instruments::spherical_direction;
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};

/// Gauss–Legendre nodes per axis of the VNDF quadrature. The integrand G1(wo(m), m) is smooth
/// but for its cut where wo drops below the horizon, so the rule converges slowly (error ~1/N):
/// 256 × 256 nodes put it below 10⁻⁴ (the tests bound it by the change from N/2 to N nodes).
const NODES: usize = 256;

/// The single-scattering directional albedo E(θ) of a white (F ≡ 1) isotropic rough conductor
/// with distribution `kind` and roughness `alpha`, lit from polar angle `theta_deg` (< 90°).
pub fn white_albedo(kind: MicrofacetKind, alpha: f32, theta_deg: f32) -> f64 {
    white_albedo_with(kind, alpha, theta_deg, NODES)
}

fn white_albedo_with(kind: MicrofacetKind, alpha: f32, theta_deg: f32, nodes: usize) -> f64 {
    let distr = MicrofacetDistribution::isotropic(kind, alpha);
    let wi = spherical_direction(theta_deg.to_radians(), 0.0);
    distr.vndf_expectation(wi, nodes, |m| {
        let wo = 2.0 * wi.dot(m) * m - wi;
        if wo.z <= 0.0 { 0.0 } else { distr.g1(wo, m) as f64 }
    })
}

/// One curve of [`albedo_vs_roughness`]: E(α) for one distribution at one incident angle.
#[derive(Clone, Debug, PartialEq)]
pub struct RoughnessCurve {
    /// The normal distribution.
    pub kind: MicrofacetKind,
    /// Incident polar angle, degrees.
    pub theta_deg: f32,
    /// (α, E) pairs, α ascending.
    pub points: Vec<(f32, f64)>,
}

/// E(α) of a white rough conductor for every distribution in `kinds` and angle in `thetas_deg`,
/// at the roughness values `alphas`.
pub fn albedo_vs_roughness(
    kinds: &[MicrofacetKind],
    thetas_deg: &[f32],
    alphas: &[f32],
) -> Vec<RoughnessCurve> {
    let mut curves = Vec::with_capacity(kinds.len() * thetas_deg.len());
    for &kind in kinds {
        for &theta_deg in thetas_deg {
            let points = alphas
                .iter()
                .map(|&a| (a, white_albedo(kind, a, theta_deg)))
                .collect();
            curves.push(RoughnessCurve {
                kind,
                theta_deg,
                points,
            });
        }
    }
    curves
}

/// `n` roughness values spread evenly over [`lo`, `hi`].
pub fn alpha_grid(lo: f32, hi: f32, n: usize) -> Vec<f32> {
    let n = n.max(2);
    (0..n)
        .map(|k| lo + (hi - lo) * k as f32 / (n - 1) as f32)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::TransportMode;
    use crate::bsdfs::RoughConductor;
    use crate::instruments::albedo::{Wavelengths, directional_albedo};

    #[test]
    fn quadrature_agrees_with_the_sampled_albedo_of_a_white_roughconductor() {
        // Two independent routes to the same number: quadrature over the VNDF here, Monte Carlo
        // through RoughConductor::sample (whose weight is F·G1(wo)) in the albedo instrument.
        for kind in [MicrofacetKind::Beckmann, MicrofacetKind::Ggx] {
            for alpha in [0.3f32, 1.0] {
                let bsdf = RoughConductor::mirror(MicrofacetDistribution::isotropic(kind, alpha));
                let thetas = [0.0f32, 45.0, 80.0];
                let mc = directional_albedo(
                    &bsdf,
                    &thetas,
                    200_000,
                    TransportMode::Radiance,
                    Wavelengths::Fixed(550.0),
                    false,
                    3,
                );
                for p in mc {
                    let q = white_albedo(kind, alpha, p.theta_deg);
                    // The quadrature's own error, bounded by its change from N/2 to N nodes.
                    let q_err = (q - white_albedo_with(kind, alpha, p.theta_deg, NODES / 2)).abs();
                    assert!(
                        q_err < 1e-4,
                        "{kind:?} α={alpha} θ={}: quadrature error {q_err}",
                        p.theta_deg
                    );
                    assert!(
                        (q - p.r).abs() < 4.0 * p.r_stderr + q_err,
                        "{kind:?} α={alpha} θ={}: quadrature {q:.6}, Monte Carlo {:.6} ± {:.6}",
                        p.theta_deg,
                        p.r,
                        p.r_stderr
                    );
                }
            }
        }
    }

    #[test]
    fn a_white_microsurface_darkens_as_it_roughens() {
        // The lecture's point: a smooth white mirror keeps all its energy, single scattering
        // loses more and more of it as α grows (at normal incidence, where no grazing masking
        // confounds it), and GGX's long tails lose more than Beckmann at the same α.
        let alphas = alpha_grid(0.05, 1.0, 20);
        for kind in [MicrofacetKind::Beckmann, MicrofacetKind::Ggx] {
            let e: Vec<f64> = alphas.iter().map(|&a| white_albedo(kind, a, 0.0)).collect();
            // GGX's long tails already send 0.3 % of normal-incidence light into the surface at
            // α = 0.05 (facets steeper than 45°: a fraction 1/(1 + 1/α²) ≈ α² of them).
            assert!(e[0] > 0.995, "{kind:?}: α = 0.05 keeps its energy ({})", e[0]);
            assert!(
                e.windows(2).all(|w| w[1] < w[0] + 1e-6),
                "{kind:?}: E(α) decreases: {e:?}"
            );
            assert!(
                e[e.len() - 1] < 0.9,
                "{kind:?} α = 1 loses over 10 %: {}",
                e[e.len() - 1]
            );
        }
        for &a in &[0.5f32, 1.0] {
            assert!(
                white_albedo(MicrofacetKind::Ggx, a, 0.0) < white_albedo(MicrofacetKind::Beckmann, a, 0.0),
                "GGX loses more at α = {a}"
            );
        }
    }
}
