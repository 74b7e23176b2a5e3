//! Tests of `roughdiffuse` (Oren–Nayar): the Lambertian limit, an independent double-precision
//! evaluation of Oren and Nayar's formulas written with the angles themselves (no half-angle or
//! sine identities), reciprocity and the energy balance.

use super::*;
use crate::albedo::directional_albedo;
use crate::bsdf::TransportMode;
use crate::rng::Pcg32;
use std::f64::consts::PI;

fn dir(theta_deg: f64, phi_deg: f64) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(
        (t.sin() * p.cos()) as f32,
        (t.sin() * p.sin()) as f32,
        t.cos() as f32,
    )
}

/// Oren and Nayar 1994, Eqs. 30 (C1, C2, C3) and 31 (interreflections), with σ = α/√2, from the
/// polar angles and the azimuth difference directly.
fn reference(rho: f64, alpha_rms: f64, fast: bool, ti: f64, to: f64, dphi: f64) -> f64 {
    let sigma = alpha_rms / 2f64.sqrt();
    let s2 = sigma * sigma;
    let (a, b) = (ti.max(to), ti.min(to));
    let cphi = if ti.sin() > 1e-4 && to.sin() > 1e-4 {
        dphi.cos()
    } else {
        0.0
    };
    if fast {
        let aa = 1.0 - s2 / (2.0 * (s2 + 0.33));
        let bb = 0.45 * s2 / (s2 + 0.09);
        return rho / PI * (aa + bb * cphi.max(0.0) * a.sin() * b.tan());
    }
    let c1 = 1.0 - 0.5 * s2 / (s2 + 0.33);
    let c2 = if cphi > 0.0 {
        0.45 * s2 / (s2 + 0.09) * a.sin()
    } else {
        0.45 * s2 / (s2 + 0.09) * (a.sin() - (2.0 * b / PI).powi(3))
    };
    let c3 = 0.125 * s2 / (s2 + 0.09) * (4.0 * a * b / (PI * PI)).powi(2);
    let l1 = rho / PI * (c1 + cphi * c2 * b.tan() + (1.0 - cphi.abs()) * c3 * ((a + b) / 2.0).tan());
    let l2 = 0.17 * rho * rho / PI * s2 / (s2 + 0.13) * (1.0 - cphi * (2.0 * b / PI).powi(2));
    l1 + l2
}

fn model(rho: f32, alpha: f32, fast: bool) -> RoughDiffuse {
    let m = if fast {
        RoughDiffuseModel::OrenNayarFast
    } else {
        RoughDiffuseModel::OrenNayar
    };
    RoughDiffuse::new(Spectrum::Constant(rho), alpha, m)
}

fn f(m: &RoughDiffuse, wi: Vec3, wo: Vec3) -> f32 {
    m.eval(
        &BsdfContext::radiance(),
        wi,
        wo,
        &SampledWavelengths::fixed(550.0),
    )[0]
}

#[test]
fn both_forms_match_an_independent_evaluation() {
    // (θi, φi, θo, φo) in degrees: retro side, forward side, across, normal incidence, grazing.
    let points = [
        (30.0, 0.0, 60.0, 0.0),
        (60.0, 0.0, 60.0, 180.0),
        (45.0, 20.0, 70.0, 110.0),
        (0.0, 0.0, 50.0, 30.0),
        (80.0, 0.0, 80.0, 0.0),
        (85.0, 10.0, 20.0, 200.0),
        (10.0, 0.0, 75.0, 270.0),
    ];
    for fast in [false, true] {
        for (rho, alpha) in [(0.5, 0.2), (0.8, 0.5), (0.3, 1.0), (1.0, 2.0)] {
            let m = model(rho, alpha, fast);
            for &(ti, pi, to, po) in &points {
                let got = f(&m, dir(ti, pi), dir(to, po)) as f64;
                let want = reference(
                    rho as f64,
                    alpha as f64,
                    fast,
                    ti.to_radians(),
                    to.to_radians(),
                    (po - pi).to_radians(),
                );
                assert!(
                    (got - want).abs() <= 2e-5 * want.abs().max(1e-3),
                    "fast={fast} ρ={rho} α={alpha} ({ti},{pi})→({to},{po}): {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn the_forms_differ_as_the_paper_says() {
    // At normal incidence only C1 and the interreflections remain: f = ρ/π (C1 + 0.17ρσ²/(σ² + 0.13))
    // for the full model and ρA/π for the qualitative one (A = C1).
    let (rho, alpha) = (0.8f32, 0.5f32);
    let s2 = (alpha * alpha / 2.0) as f64;
    let c1 = 1.0 - 0.5 * s2 / (s2 + 0.33);
    let c4 = 0.17 * s2 / (s2 + 0.13);
    let wo = dir(40.0, 0.0);
    let full = f(&model(rho, alpha, false), Vec3::Z, wo) as f64;
    let fast = f(&model(rho, alpha, true), Vec3::Z, wo) as f64;
    let r = rho as f64;
    assert!((full - r / PI * (c1 + r * c4)).abs() < 1e-6, "{full}");
    assert!((fast - r / PI * c1).abs() < 1e-6, "{fast}");
    // Forward scattering (cos φ < 0): the qualitative form is flat at A, the full one falls below
    // it through −C2 tan β and the interreflections' −cos φ (2β/π)² sign.
    let (wi, wo) = (dir(60.0, 0.0), dir(60.0, 180.0));
    let full = f(&model(rho, alpha, false), wi, wo) as f64;
    let fast = f(&model(rho, alpha, true), wi, wo) as f64;
    assert!((fast - r / PI * c1).abs() < 1e-6);
    assert!(full != fast);
}

#[test]
fn zero_roughness_is_lambert_exactly() {
    let mut rng = Pcg32::new(7, 1);
    for fast in [false, true] {
        let m = model(0.7, 0.0, fast);
        for _ in 0..200 {
            let wi = square_to_cosine_hemisphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            let wo = square_to_cosine_hemisphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            if wi.z <= 0.0 || wo.z <= 0.0 {
                continue;
            }
            assert_eq!(f(&m, wi, wo), 0.7 * FRAC_1_PI, "fast={fast} {wi} {wo}");
        }
    }
}

#[test]
fn reciprocal() {
    let mut rng = Pcg32::new(11, 3);
    for fast in [false, true] {
        let m = model(0.6, 0.8, fast);
        for _ in 0..500 {
            let wi = square_to_cosine_hemisphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            let wo = square_to_cosine_hemisphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            if wi.z <= 0.0 || wo.z <= 0.0 {
                continue;
            }
            let (a, b) = (f(&m, wi, wo), f(&m, wo, wi));
            assert!((a - b).abs() <= 1e-5 * a.max(b), "fast={fast}: {a} vs {b}");
        }
    }
}

#[test]
fn energy_below_one_up_to_bright_albedos() {
    // Directional albedo by quadrature: < 1 for ρ ≤ 0.9 at every roughness and incidence, and
    // below ρ at normal incidence for the qualitative form (A ≤ 1 is all that remains there).
    let wl = SampledWavelengths::fixed(550.0);
    for fast in [false, true] {
        for alpha in [0.05, 0.2, 0.5, 1.0, 3.0] {
            let m = model(0.9, alpha, fast);
            for mu in [1.0f32, 0.7, 0.3, 0.1, 0.02] {
                let wi = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                let a = directional_albedo(&m, TransportMode::Radiance, wi, &wl, 64 * 128 * 2).r[0];
                assert!(a < 1.0, "fast={fast} α={alpha} μ={mu}: {a}");
                if fast && mu == 1.0 {
                    assert!(a <= 0.9 + 1e-4, "{a}");
                }
            }
        }
    }
    // Oren–Nayar is not energy-conserving: white facets at α = 0.5 reflect more than they receive
    // at grazing incidence (1.044 for the full model at cos θi = 0.01).
    let m = model(1.0, 0.5, false);
    let wi = Vec3::new((1.0f32 - 1e-4).sqrt(), 0.0, 0.01);
    let a = directional_albedo(&m, TransportMode::Radiance, wi, &wl, 64 * 128 * 2).r[0];
    assert!((a - 1.044).abs() < 0.003, "{a}");
}

#[test]
fn sample_weight_is_eval_over_pdf() {
    let m = model(0.8, 0.6, false);
    let wl = SampledWavelengths::fixed(550.0);
    let ctx = BsdfContext::radiance();
    let wi = dir(70.0, 30.0);
    let mut rng = Pcg32::new(3, 9);
    for _ in 0..100 {
        let mut wl2 = wl;
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let s = m.sample(&ctx, wi, 0.5, u, &mut wl2).unwrap();
        let want = m.eval(&ctx, wi, s.wo, &wl)[0] * s.wo.z / m.pdf(&ctx, wi, s.wo, &wl);
        assert!(
            (s.weight[0] - want).abs() <= 1e-5 * want,
            "{} vs {want}",
            s.weight[0]
        );
        assert_eq!(s.pdf, m.pdf(&ctx, wi, s.wo, &wl));
    }
    let mut wl3 = wl;
    assert!(m.sample(&ctx, -wi, 0.5, Vec2::splat(0.3), &mut wl3).is_none());
    assert_eq!(
        m.eval(&ctx, wi, -Vec3::Z, &wl),
        SampledSpectrum::ZERO,
        "one-sided"
    );
}

// ---- model="microfacet": Heitz et al. 2016 Lambertian microfacets ------------------------------

fn microfacet(rho: f32, alpha: f32, kind: MicrofacetKind) -> RoughDiffuse {
    RoughDiffuse::new(
        Spectrum::Constant(rho),
        alpha,
        RoughDiffuseModel::Microfacet(kind),
    )
}

/// Mean and standard error of the sample weights (a cut or failed walk counts as 0) over `n`
/// stratified-free uniform draws.
fn walk_albedo(m: &RoughDiffuse, wi: Vec3, n: usize, seed: u64) -> (f64, f64) {
    let ctx = BsdfContext::radiance();
    let wl = SampledWavelengths::fixed(550.0);
    let mut rng = Pcg32::new(seed, 5);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let mut wl2 = wl;
        let w = m
            .sample(&ctx, wi, rng.next_f32(), rng.next_vec2(), &mut wl2)
            .map_or(0.0, |s| s.weight[0] as f64);
        s += w;
        s2 += w * w;
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(0.0);
    (mean, (var / n as f64).sqrt())
}

#[test]
fn microfacet_white_furnace() {
    // ρ = 1: every walk that is not cut after 16 bounces returns weight 1 exactly.
    for kind in [MicrofacetKind::Beckmann, MicrofacetKind::Ggx] {
        for alpha in [0.2f32, 1.0] {
            for mu in [1.0f32, 0.5, 0.1] {
                let wi = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                let (a, _) = walk_albedo(&microfacet(1.0, alpha, kind), wi, 20_000, 1);
                assert!((0.997..=1.0).contains(&a), "{kind:?} α={alpha} μ={mu}: {a}");
            }
        }
    }
}

#[test]
fn microfacet_reference_albedos() {
    // Lambertian GGX microfacets at normal incidence, ρ = 0.8 (random-walk references):
    // α = 1: 0.6736 ± 0.0003, α = 0.5: 0.7487 ± 0.0002.
    for (alpha, want, want_se) in [(1.0f32, 0.6736, 0.0003), (0.5, 0.7487, 0.0002)] {
        let (a, se) = walk_albedo(&microfacet(0.8, alpha, MicrofacetKind::Ggx), Vec3::Z, 400_000, 2);
        let tol = 4.0 * (se * se + want_se * want_se).sqrt();
        eprintln!("GGX α={alpha} ρ=0.8 μ=1: walk albedo {a:.5} ± {se:.5} (reference {want})");
        assert!((a - want).abs() < tol, "α={alpha}: {a} ± {se} vs {want}");
    }
}

#[test]
fn microfacet_eval_integrates_to_the_walk_albedo() {
    // E[eval cos θo/(cos θo/π)] over cosine-distributed ωo is the albedo the walk samples.
    let m = microfacet(0.8, 0.7, MicrofacetKind::Beckmann);
    let wl = SampledWavelengths::fixed(550.0);
    let ctx = BsdfContext::radiance();
    let wi = dir(60.0, 0.0);
    let n = 100_000;
    let mut rng = Pcg32::new(9, 2);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let wo = square_to_cosine_hemisphere(rng.next_vec2());
        if wo.z <= 0.0 {
            continue;
        }
        let v = (m.eval(&ctx, wi, wo, &wl)[0] * std::f32::consts::PI) as f64;
        s += v;
        s2 += v * v;
    }
    let mean = s / n as f64;
    let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
    let (walk, walk_se) = walk_albedo(&m, wi, 100_000, 3);
    let tol = 4.0 * (se * se + walk_se * walk_se).sqrt();
    assert!(
        (mean - walk).abs() < tol,
        "eval {mean} ± {se}, walk {walk} ± {walk_se}"
    );
    assert!(!m.pdf_is_exact() && model(0.5, 0.2, false).pdf_is_exact());
}

#[test]
fn microfacet_smooth_limit_is_lambert_and_rough_retroreflects() {
    let wl = SampledWavelengths::fixed(550.0);
    // α → 0: a flat Lambertian surface, f = ρ/π (single scattering only, exact per estimate).
    let m = microfacet(0.6, 1e-4, MicrofacetKind::Beckmann);
    for (wi, wo) in [
        (dir(30.0, 0.0), dir(50.0, 120.0)),
        (dir(70.0, 10.0), dir(20.0, 200.0)),
    ] {
        let v = f(&m, wi, wo);
        assert!((v - 0.6 * FRAC_1_PI).abs() < 1e-3 * 0.6 * FRAC_1_PI, "{v}");
    }
    // Rough: back towards the light (φ = 0) brighter than forward (φ = 180°), like Oren–Nayar.
    // Averages of independent estimates (the microsurface with its own generator).
    let m = microfacet(0.8, 1.0, MicrofacetKind::Beckmann);
    let ms = m.microsurface(MicrofacetKind::Beckmann);
    let rho = m.reflectance.sample(&wl);
    let wi = dir(60.0, 0.0);
    let mean = |wo: Vec3, seed: u64| {
        let mut rng = Pcg32::new(seed, 1);
        let n = 20_000;
        (0..n)
            .map(|_| ms.eval_diffuse(wi, wo, rho, &mut rng)[0] as f64)
            .sum::<f64>()
            / n as f64
            / wo.z as f64
    };
    let (back, fwd) = (mean(dir(60.0, 0.0), 4), mean(dir(60.0, 180.0), 5));
    eprintln!("Beckmann α=1 ρ=0.8, θi = θo = 60°: f back {back:.4}, forward {fwd:.4}");
    assert!(back > 1.3 * fwd, "back {back} forward {fwd}");
}

#[test]
fn microfacet_reciprocal_in_expectation() {
    let wl = SampledWavelengths::fixed(550.0);
    let m = microfacet(0.7, 0.6, MicrofacetKind::Ggx);
    let ms = m.microsurface(MicrofacetKind::Ggx);
    let rho = m.reflectance.sample(&wl);
    let (a, b) = (dir(20.0, 0.0), dir(75.0, 140.0));
    let stats = |wi: Vec3, wo: Vec3, seed: u64| {
        let mut rng = Pcg32::new(seed, 7);
        let n = 40_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let v = (ms.eval_diffuse(wi, wo, rho, &mut rng)[0] / wo.z) as f64;
            s += v;
            s2 += v * v;
        }
        let mean = s / n as f64;
        (mean, ((s2 / n as f64 - mean * mean) / n as f64).sqrt())
    };
    let ((f_ab, se_ab), (f_ba, se_ba)) = (stats(a, b, 1), stats(b, a, 2));
    let tol = 4.0 * (se_ab * se_ab + se_ba * se_ba).sqrt();
    assert!((f_ab - f_ba).abs() < tol, "{f_ab} ± {se_ab} vs {f_ba} ± {se_ba}");
}

#[test]
fn oren_nayar_is_never_negative_on_very_rough_surfaces_seen_backwards() {
    // Found by proptest_health: at α = 3.58 (σ = 2.5 rad) the full model's direct bracket
    // C1 + cos φ C2 tan β is −0.11 for this backward, grazing pair; it is clamped at 0 and the
    // interreflection term alone remains.
    let m = model(0.05, 3.58, false);
    let wi = Vec3::new(-0.05376646, 0.93563145, 0.34885943);
    let wo = Vec3::new(0.3421514, -0.9396448, 0.00024414063).normalize();
    let value = f(&m, wi, wo);
    assert!(value >= 0.0 && value.is_finite(), "{value}");
    let mut rng = Pcg32::new(3, 4);
    for _ in 0..20_000 {
        let (a, b) = (rng.next_f32(), rng.next_f32());
        let (c, d) = (rng.next_f32(), rng.next_f32());
        let wi = crate::warp::square_to_cosine_hemisphere(glam::Vec2::new(a, b));
        let wo = crate::warp::square_to_cosine_hemisphere(glam::Vec2::new(c, d));
        for alpha in [1.0, 2.0, 4.0] {
            let v = f(&model(0.05, alpha, false), wi, wo);
            assert!(v >= 0.0, "α {alpha}, wi {wi}, wo {wo}: {v}");
        }
    }
}
