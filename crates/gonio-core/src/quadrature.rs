//! Gauss–Legendre quadrature, for deterministic integrals over θ (albedos, hemispherical
//! averages).

/// Nodes and weights of the `n`-point Gauss–Legendre rule on [a, b] (f64): Newton's method on
/// Pₙ from Tricomi's initial guesses, wᵢ = 2/((1 − zᵢ²) Pₙ'(zᵢ)²), mapped to [a, b]. Exact for
/// polynomials of degree ≤ 2n − 1.
pub fn gauss_legendre(n: usize, a: f64, b: f64) -> Vec<(f64, f64)> {
    let n = n.max(1);
    let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
    (0..n)
        .map(|i| {
            let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre(n, z);
                let dz = p / dp;
                z -= dz;
                if dz.abs() < 1e-16 {
                    break;
                }
            }
            let (_, dp) = legendre(n, z);
            (m + h * z, h * 2.0 / ((1.0 - z * z) * dp * dp))
        })
        .collect()
}

/// Pₙ(z) and Pₙ'(z) by the three-term recurrence.
fn legendre(n: usize, z: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, z);
    for j in 2..=n {
        let jf = j as f64;
        let p2 = ((2.0 * jf - 1.0) * z * p1 - (jf - 1.0) * p0) / jf;
        p0 = p1;
        p1 = p2;
    }
    if n == 1 {
        return (z, 1.0);
    }
    (p1, n as f64 * (z * p1 - p0) / (z * z - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_exactly_and_smooth_functions_to_machine_precision() {
        let rule = gauss_legendre(5, 0.0, 2.0);
        let poly: f64 = rule
            .iter()
            .map(|&(x, w)| w * (x.powi(9) - 3.0 * x.powi(4) + 1.0))
            .sum();
        let exact = 2f64.powi(10) / 10.0 - 3.0 * 2f64.powi(5) / 5.0 + 2.0;
        assert!((poly - exact).abs() < 1e-10, "{poly} vs {exact}");
        let cos: f64 = gauss_legendre(20, 0.0, std::f64::consts::FRAC_PI_2)
            .iter()
            .map(|&(x, w)| w * x.cos())
            .sum();
        assert!((cos - 1.0).abs() < 1e-14);
        assert_eq!(gauss_legendre(1, -1.0, 1.0), vec![(0.0, 2.0)]);
    }
}
