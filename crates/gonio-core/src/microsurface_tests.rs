//! Tests of the Smith microsurface walks against the closed forms and reference numbers of
//! Heitz et al. 2016 (GGX, uniform heights).

use super::*;
use crate::microfacet::MicrofacetKind::{self, Beckmann, Ggx};
use glam::Vec2;

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    Vec3::new(st * cp, st * sp, ct)
}

fn surface(kind: MicrofacetKind, au: f32, av: f32) -> Microsurface {
    Microsurface::new(MicrofacetDistribution::new(kind, au, av, true))
}

fn white(_c: f32) -> SampledSpectrum {
    SampledSpectrum::splat(1.0)
}

/// (albedo, fraction leaving after one bounce, mean order, fraction cut) of `n` walks.
fn walk_stats(n: u32, mut walk: impl FnMut(&mut Pcg32) -> Option<WalkSample>) -> (f64, f64, f64, f64) {
    let mut rng = Pcg32::new(7, 11);
    let (mut sum, mut one, mut orders, mut cut) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..n {
        match walk(&mut rng) {
            Some(s) => {
                sum += s.weight[0] as f64;
                orders += s.order as f64;
                if s.order == 1 {
                    one += s.weight[0] as f64;
                }
            }
            None => cut += 1.0,
        }
    }
    let n = n as f64;
    (sum / n, one / n, orders / (n - cut), cut / n)
}

#[test]
fn projected_area_is_the_integral_of_the_visible_facets_on_both_sides() {
    // σ(ω) = ∫ max(0, ω·m) D(m) dm by quadrature over the upper hemisphere of normals, for ω
    // above and below the horizon (below: |cos θ| Λ(−ω)).
    for (kind, au, av) in [(Ggx, 0.5, 0.5), (Beckmann, 0.3, 0.8), (Ggx, 1.0, 0.4)] {
        let s = surface(kind, au, av);
        for w in [
            dir(30.0, 20.0),
            dir(75.0, 200.0),
            dir(120.0, 40.0),
            dir(160.0, 300.0),
            dir(95.0, 10.0),
        ] {
            let (nt, np) = (800, 400);
            let mut sum = 0.0f64;
            for i in 0..nt {
                let t = (i as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
                for j in 0..np {
                    let p = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
                    let m = Vec3::new(
                        (t.sin() * p.cos()) as f32,
                        (t.sin() * p.sin()) as f32,
                        t.cos() as f32,
                    );
                    let dw = t.sin()
                        * (std::f64::consts::FRAC_PI_2 / nt as f64)
                        * (std::f64::consts::TAU / np as f64);
                    sum += (w.dot(m).max(0.0) * s.distribution.d(m)) as f64 * dw;
                }
            }
            let sigma = s.projected_area(w) as f64;
            assert!(
                (sum / sigma - 1.0).abs() < 5e-3,
                "{kind:?} {w}: quadrature {sum} vs σ {sigma}"
            );
        }
    }
}

#[test]
fn visible_normals_below_the_horizon_follow_the_vndf() {
    // Mean of m (a vector moment) under the rejection sampler against quadrature of m D_ω(m).
    for (kind, au, av) in [(Ggx, 0.6, 0.6), (Beckmann, 0.4, 0.9)] {
        let s = surface(kind, au, av);
        let w = dir(110.0, 30.0);
        let mut rng = Pcg32::new(3, 5);
        let n = 200_000;
        let mut mean = glam::DVec3::ZERO;
        for _ in 0..n {
            let m = s.sample_vndf(w, &mut rng);
            assert!(w.dot(m) > 0.0 && m.z > 0.0);
            mean += m.as_dvec3();
        }
        mean /= n as f64;
        let (nt, np) = (600, 300);
        let mut quad = glam::DVec3::ZERO;
        for i in 0..nt {
            let t = (i as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
            for j in 0..np {
                let p = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
                let m = Vec3::new(
                    (t.sin() * p.cos()) as f32,
                    (t.sin() * p.sin()) as f32,
                    t.cos() as f32,
                );
                let dw =
                    t.sin() * (std::f64::consts::FRAC_PI_2 / nt as f64) * (std::f64::consts::TAU / np as f64);
                quad += m.as_dvec3() * (s.vndf(w, m) as f64 * dw);
            }
        }
        // Each component of m is bounded by 1: standard error ≤ 1/√n ≈ 2.2e-3.
        assert!(
            (mean - quad).abs().max_element() < 7e-3,
            "{kind:?}: {mean} vs {quad}"
        );
    }
}

#[test]
fn reference_numbers_of_the_ggx_conductor_walk() {
    // Heitz et al. 2016 (the notes' table): single-scattering albedo = fraction of walks leaving
    // after one bounce: α = 1, μ = 1: 1 − ln 2; α = 0.5, μ = 1: 0.68785; α = 1, μ = 0.5: 0.4507;
    // mean bounce counts 2.30 (α = 1) and 1.41 (α = 0.5); white albedo 1.
    let n = 200_000;
    for (alpha, mu, single, mean_order) in [
        (1.0f32, 1.0f32, 1.0 - std::f64::consts::LN_2, Some(2.30)),
        (0.5, 1.0, 0.68785, Some(1.41)),
        (1.0, 0.5, 0.4507, None),
        (0.5, 0.5, 0.6983, None),
        (0.1, 1.0, 0.98830, None),
    ] {
        let s = surface(Ggx, alpha, alpha);
        let wi = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        let (albedo, one, order, cut) = walk_stats(n, |rng| s.sample_conductor(wi, white, rng));
        let se = (single * (1.0 - single) / n as f64).sqrt();
        assert!(
            (one - single).abs() < 4.0 * se + 1e-3,
            "α={alpha} μ={mu}: one bounce {one} vs {single}"
        );
        assert!(
            (albedo + cut - 1.0).abs() < 1e-9,
            "every walk not cut has weight 1"
        );
        assert!(
            cut < 1e-3,
            "α={alpha} μ={mu}: {cut} of the walks cut at {MAX_ORDER}"
        );
        if let Some(m) = mean_order {
            assert!((order - m).abs() < 0.01, "α={alpha}: mean order {order} vs {m}");
        }
    }
}

#[test]
fn reference_numbers_of_the_diffuse_walk() {
    // Lambertian microfacets at μ = 1 (the notes' table): ρ = 0.8, α = 1: 0.6736 ± 0.0003, single
    // bounce 0.4652; ρ = 0.8, α = 0.5: 0.7487 ± 0.0002, single 0.6242.
    let n = 200_000;
    for (alpha, total, single) in [(1.0f32, 0.6736, 0.4652), (0.5, 0.7487, 0.6242)] {
        let s = surface(Ggx, alpha, alpha);
        let rho = SampledSpectrum::splat(0.8);
        let (albedo, one, _, _) = walk_stats(n, |rng| s.sample_diffuse(Vec3::Z, rho, rng));
        // Weights ≤ 0.8: standard error ≤ 0.4/√n ≈ 9e-4.
        assert!(
            (albedo - total).abs() < 3.5e-3,
            "α={alpha}: albedo {albedo} vs {total}"
        );
        assert!(
            (one - single).abs() < 3.5e-3,
            "α={alpha}: one bounce {one} vs {single}"
        );
    }
}

/// ∫ eval dωo over the sphere (f·|cos θo| per unit solid angle) by uniform-sphere Monte Carlo,
/// with its standard error.
fn integrate_eval(n: u32, mut eval: impl FnMut(Vec3, &mut Pcg32) -> f64) -> (f64, f64) {
    let mut rng = Pcg32::new(17, 19);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let wo = crate::warp::square_to_uniform_sphere(rng.next_vec2());
        let v = eval(wo, &mut rng) * 4.0 * std::f64::consts::PI;
        s += v;
        s2 += v * v;
    }
    let n = n as f64;
    let mean = s / n;
    (mean, ((s2 / n - mean * mean) / n).sqrt())
}

#[test]
fn white_conductor_eval_integrates_to_one() {
    for (kind, au, av, theta) in [
        (Ggx, 1.0, 1.0, 0.0),
        (Ggx, 0.5, 0.5, 70.0),
        (Beckmann, 0.8, 0.3, 45.0),
    ] {
        let s = surface(kind, au, av);
        let wi = dir(theta, 30.0);
        let (mean, se) = integrate_eval(200_000, |wo, rng| s.eval_conductor(wi, wo, white, rng)[0] as f64);
        assert!(
            (mean - 1.0).abs() < 4.0 * se + 2e-3,
            "{kind:?} α=({au},{av}) θ={theta}: {mean} ± {se}"
        );
    }
}

#[test]
fn dielectric_walk_conserves_energy_and_eval_integrates_to_one() {
    // Importance transport: R + T = 1 for the walk (weights 1) and for ∫ eval over the sphere.
    for (kind, alpha, eta, theta) in [
        (Ggx, 0.6, 1.5, 30.0),
        (Beckmann, 0.3, 1.5, 75.0),
        (Ggx, 0.8, 1.0 / 1.5, 40.0),
    ] {
        let s = surface(kind, alpha, alpha);
        let wi = dir(theta, 0.0);
        let (albedo, _, _, cut) = walk_stats(100_000, |rng| {
            s.sample_dielectric(wi, SampledSpectrum::splat(eta), rng)
        });
        assert!(
            cut < 2e-3 && (albedo + cut - 1.0).abs() < 1e-9,
            "{kind:?}: cut {cut}"
        );
        let (mean, se) = integrate_eval(200_000, |wo, rng| s.eval_dielectric(wi, wo, eta, rng) as f64);
        assert!(
            (mean - 1.0).abs() < 4.0 * se + 3e-3,
            "{kind:?} α={alpha} η={eta} θ={theta}: {mean} ± {se}"
        );
    }
}

#[test]
fn white_diffuse_eval_integrates_to_one() {
    let s = surface(Ggx, 0.7, 0.7);
    let wi = dir(60.0, 0.0);
    let one = SampledSpectrum::splat(1.0);
    let (mean, se) = integrate_eval(200_000, |wo, rng| s.eval_diffuse(wi, wo, one, rng)[0] as f64);
    assert!((mean - 1.0).abs() < 4.0 * se + 2e-3, "{mean} ± {se}");
}

#[test]
fn stochastic_eval_is_reciprocal_in_expectation() {
    // f(a, b) = f(b, a): the means of eval(a, b)/cos θb and eval(b, a)/cos θa over many seeds.
    let s = surface(Ggx, 0.8, 0.8);
    let (a, b) = (dir(70.0, 0.0), dir(30.0, 150.0));
    let n = 200_000;
    let mut rng = Pcg32::new(1, 2);
    let (mut fab, mut fba, mut v) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..n {
        let x = (s.eval_conductor(a, b, white, &mut rng)[0] / b.z) as f64;
        let y = (s.eval_conductor(b, a, white, &mut rng)[0] / a.z) as f64;
        fab += x;
        fba += y;
        v += (x - y) * (x - y);
    }
    let (fab, fba) = (fab / n as f64, fba / n as f64);
    let se = (v / n as f64 / n as f64).sqrt();
    assert!((fab - fba).abs() < 4.0 * se, "{fab} vs {fba} (se {se})");
}

#[test]
fn eval_and_sample_rngs_are_pure_functions_of_their_arguments() {
    let wl = SampledWavelengths::fixed(550.0);
    let (a, b) = (dir(10.0, 0.0), dir(40.0, 90.0));
    assert_eq!(eval_rng(a, b, &wl), eval_rng(a, b, &wl));
    assert_ne!(eval_rng(a, b, &wl), eval_rng(b, a, &wl));
    let u = Vec2::new(0.3, 0.7);
    assert_eq!(sample_rng(a, 0.5, u), sample_rng(a, 0.5, u));
    assert_ne!(sample_rng(a, 0.5, u), sample_rng(a, 0.5, Vec2::new(0.3, 0.70001)));
}

#[test]
fn zz_debug_cell() {
    let s = surface(Ggx, 0.6, 0.6);
    let wi = Vec3::new(0.5, 0.3, 0.8).normalize();
    let (z0, z1, p0, p1) = (-0.25f32, 0.0f32, 180f32.to_radians(), 225f32.to_radians());
    let inside = |w: Vec3| {
        let p = w.y.atan2(w.x).rem_euclid(std::f32::consts::TAU);
        w.z >= z0 && w.z < z1 && p >= p0 && p < p1
    };
    let mut rng = Pcg32::new(3, 3);
    let n = 2_000_000;
    let mut a = 0.0f64;
    let mut hits = 0;
    let mut by_order = [0u32; 17];
    let mut by_cross = [0u32; 8];
    for _ in 0..n {
        if let Some(w) = s.sample_dielectric(wi, SampledSpectrum::splat(1.5), &mut rng)
            && inside(w.wo)
        {
            a += w.weight[0] as f64;
            hits += 1;
            by_order[w.order as usize] += 1;
            by_cross[(w.crossings as usize).min(7)] += 1;
        }
    }
    let m = 200_000;
    let area = ((z1 - z0) * (p1 - p0)) as f64;
    let mut b = 0.0f64;
    let mut bu = 0.0f64;
    for _ in 0..m {
        let z = z0 + (z1 - z0) * rng.next_f32();
        let p = p0 + (p1 - p0) * rng.next_f32();
        let r = (1.0 - z * z).sqrt();
        let wo = Vec3::new(r * p.cos(), r * p.sin(), z);
        b += s.eval_dielectric(wi, wo, 1.5, &mut rng) as f64;
        bu += uni(&s, wi, wo, 1.5, &mut rng) as f64;
    }
    eprintln!(
        "sampled {} ({hits} hits, orders {:?}, crossings {:?}) eval {} uni {}",
        a / n as f64,
        by_order,
        by_cross,
        b / m as f64 * area,
        bu / m as f64 * area
    );
}

fn uni(s: &Microsurface, wi: Vec3, wo: Vec3, eta: f32, rng: &mut Pcg32) -> f32 {
    let mut sum = s.dielectric_single(wi, wo, eta);
    let (mut w, mut c1, mut eta_l) = (-wi, 1.0f32, eta);
    let mut outside = true;
    for order in 1..=MAX_ORDER {
        match s.sample_height(w, c1, rng.next_f32()) {
            None => break,
            Some(c) => c1 = c,
        }
        let wv = -w;
        if order >= 2 {
            let wo_l = if outside { wo } else { -wo };
            let sh = if wo_l.z > 0.0 {
                s.g1_height(wo_l, c1)
            } else {
                s.g1_height(-wo_l, 1.0 - c1)
            };
            let t = s.dielectric_phase(wv, wo_l, eta_l) * sh;
            if t.is_finite() {
                sum += t;
            }
        }
        let m = s.sample_vndf(wv, rng);
        let c = wv.dot(m).max(0.0);
        let f = fresnel_dielectric(c, eta_l).reflectance;
        let r = if rng.next_f32() < f {
            None
        } else {
            refract_about(wv, m, eta_l)
        };
        match r {
            None => w = (2.0 * c * m - wv).normalize(),
            Some((wt, _)) => {
                w = -wt.normalize();
                c1 = 1.0 - c1;
                eta_l = 1.0 / eta_l;
                outside = !outside;
            }
        }
    }
    sum
}
