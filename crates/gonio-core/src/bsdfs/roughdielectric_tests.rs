//! Unit tests of `roughdielectric` (the model file's `tests` module).

use super::*;
use crate::albedo::directional_albedo;
use crate::bsdfs::Dielectric;
use crate::microfacet::MicrofacetKind::{Beckmann, Ggx};
use crate::microfacet::{rough_reflectance, rough_transmittance};
use crate::spectra::{Extrapolation, PiecewiseLinear};
use std::sync::Arc;

fn dir(theta_deg: f32, phi_deg: f32, side: f32) -> Vec3 {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    Vec3::new(st * cp, st * sp, side * ct)
}

fn glass(distribution: MicrofacetDistribution) -> RoughDielectric {
    RoughDielectric::new(Ior::Constant(1.5), Ior::Constant(1.0), distribution)
}

/// The importance-mode albedo split (R, T) from the visible-normal quadratures of
/// [`crate::microfacet`], for wi on either side of an interface of relative index `eta`.
fn vndf_albedo(d: &MicrofacetDistribution, wi: Vec3, eta: f32) -> (f32, f32) {
    let (up, eta) = if wi.z > 0.0 { (wi, eta) } else { (-wi, 1.0 / eta) };
    (rough_reflectance(d, up, eta), rough_transmittance(d, up, eta))
}

#[test]
fn importance_albedo_is_the_vndf_average_and_at_most_one() {
    // Two independent integrations of the same physics: quadrature of eval over directions,
    // and E_{m∼D_wi}[F G1(ωo, m)], E[(1 − F) G1(ωt, m)] over the visible-normal sampler. For
    // Beckmann, eval's G1(ωi) is Mitsuba's rational approximation (< 0.35 %) where the
    // sampler is exact, hence the relative term of the tolerance.
    let wl = SampledWavelengths::fixed(550.0);
    for kind in [Beckmann, Ggx] {
        for alpha in [0.3f32, 1.0] {
            let d = MicrofacetDistribution::isotropic(kind, alpha);
            let m = glass(d);
            for (theta, side) in [
                (0.0f32, 1.0f32),
                (45.0, 1.0),
                (80.0, 1.0),
                (30.0, -1.0),
                (60.0, -1.0),
            ] {
                let wi = dir(theta, 20.0, side);
                let quad = directional_albedo(&m, TransportMode::Importance, wi, &wl, 1_000_000);
                let (r, t) = vndf_albedo(&d, wi, 1.5);
                let tol = |x: f32| 1e-3 + if kind == Beckmann { 3.5e-3 * x } else { 0.0 };
                let at = format!("{kind:?} α={alpha} θ={theta} side={side}");
                assert!((quad.r[0] - r).abs() < tol(r), "{at}: R {} vs {r}", quad.r[0]);
                assert!((quad.t[0] - t).abs() < tol(t), "{at}: T {} vs {t}", quad.t[0]);
                assert!(r + t <= 1.0 + 1e-4, "{at}: R + T = {}", r + t);
            }
        }
    }
}

#[test]
fn single_scattering_loses_energy_as_roughness_grows() {
    // Mitsuba's default glass (bk7/air, Beckmann), importance mode, from outside: R + T ≤ 1,
    // lower the rougher and the more grazing. In radiance mode a transmission carries 1/η²,
    // so at small α the albedo is the smooth interface's F + (1 − F)/η².
    let eta = 1.5046f32 / 1.000277;
    for theta in [0.0f32, 45.0, 80.0] {
        let wi = dir(theta, 0.0, 1.0);
        let mut previous = 1.0 + 1e-4;
        for alpha in [0.01f32, 0.1, 0.5, 1.0] {
            let d = MicrofacetDistribution::isotropic(Beckmann, alpha);
            let (r, t) = vndf_albedo(&d, wi, eta);
            assert!(r + t <= previous, "θ={theta} α={alpha}: {}", r + t);
            previous = r + t;
        }
        assert!(previous < 0.97, "θ={theta}: α = 1 loses energy ({previous})");
    }
    let d = MicrofacetDistribution::isotropic(Beckmann, 0.1);
    let (r, t) = vndf_albedo(&d, Vec3::Z, eta);
    let f = fresnel_dielectric(1.0, eta).reflectance;
    let (rough, smooth) = (r + t / (eta * eta), f + (1.0 - f) / (eta * eta));
    assert!((rough - smooth).abs() < 1e-3, "{rough} vs {smooth}");
}

#[test]
fn sampling_weight_is_eval_over_pdf_for_both_samplers_sides_and_modes() {
    for kind in [Beckmann, Ggx] {
        for visible in [true, false] {
            let m = glass(MicrofacetDistribution::new(kind, 0.2, 0.5, visible));
            for ctx in [BsdfContext::radiance(), BsdfContext::importance()] {
                for wi in [
                    dir(0.0, 0.0, 1.0),
                    dir(50.0, 20.0, 1.0),
                    dir(85.0, 200.0, 1.0),
                    dir(30.0, 70.0, -1.0),
                    dir(60.0, 10.0, -1.0),
                ] {
                    let mut seen = [false; 2];
                    for j in 0..32 {
                        let u = Vec2::new((j as f32 + 0.3) / 32.0, ((j * 7) % 32) as f32 / 32.0 + 0.01);
                        let mut wl = SampledWavelengths::fixed(600.0);
                        let Some(s) = m.sample(&ctx, wi, (j as f32 + 0.5) / 32.0, u, &mut wl) else {
                            continue;
                        };
                        let refl = s.wo.z * wi.z > 0.0;
                        assert_eq!(refl, s.flags.is_reflection());
                        seen[refl as usize] = true;
                        let (f, pdf) = (m.eval(&ctx, wi, s.wo, &wl)[0], m.pdf(&ctx, wi, s.wo, &wl));
                        assert!((pdf / s.pdf - 1.0).abs() < 1e-5, "pdf {pdf} vs {}", s.pdf);
                        let w = f * s.wo.z.abs() / pdf;
                        assert!(
                            (w - s.weight[0]).abs() < 1e-5 * w.max(1e-3),
                            "{w} vs {}",
                            s.weight[0]
                        );
                        // Mitsuba's weight: G1(ωo, m) (× 1/η² for a radiance refraction);
                        // Beckmann's rational G1 peaks at 1.00003 (a = 1.6).
                        if visible && refl {
                            assert!(s.weight[0] <= 1.0 + 4e-5, "{kind:?} wi={wi} {s}");
                        }
                    }
                    assert!(seen[0] || wi.z < 0.0, "{kind:?} wi={wi}: no transmission sampled");
                }
            }
        }
    }
}

#[test]
fn radiance_and_importance_differ_by_eta_squared_on_transmission() {
    let m = glass(MicrofacetDistribution::isotropic(Ggx, 0.3));
    let wl = SampledWavelengths::fixed(550.0);
    let (rad, imp) = (BsdfContext::radiance(), BsdfContext::importance());
    let (a, b) = (dir(30.0, 10.0, 1.0), dir(25.0, 170.0, -1.0));
    let (fr, fi) = (m.eval(&rad, a, b, &wl)[0], m.eval(&imp, a, b, &wl)[0]);
    assert!(fr > 0.0 && (fi / fr - 2.25).abs() < 1e-5, "{fi} / {fr}");
    // Veach's law: f_rad(a, b)/η_a² = f_rad(b, a)/η_b²; importance is the transpose.
    let back = m.eval(&rad, b, a, &wl)[0];
    assert!((fr * 2.25 / back - 1.0).abs() < 1e-5, "{fr} {back}");
    assert!((m.eval(&imp, b, a, &wl)[0] / fr - 1.0).abs() < 1e-5);
    // Reflection is symmetric and mode-independent.
    let c = dir(40.0, 200.0, 1.0);
    let (x, y) = (m.eval(&rad, a, c, &wl)[0], m.eval(&imp, c, a, &wl)[0]);
    assert!(x > 0.0 && (x / y - 1.0).abs() < 1e-5);
}

#[test]
fn zero_roughness_behaves_like_the_smooth_dielectric() {
    // α = 0 (clamped to 1e-4) and 1e-4: the same lobe choice, directions near the smooth
    // interface's (the median within 1e-3 rad; GGX's long tail, amplified by refraction near
    // the critical angle, reaches ~1e-2 at the grid's edge), the same weights (1, and 1/η² for a radiance refraction, η²
    // from inside), never NaN, never black; total internal reflection beyond 41.8° inside.
    let smooth = Dielectric::new(Ior::Constant(1.5), Ior::Constant(1.0));
    let ctx = BsdfContext::radiance();
    for kind in [Beckmann, Ggx] {
        for visible in [true, false] {
            for alpha in [0.0f32, 1e-4] {
                let rough = glass(MicrofacetDistribution::new(kind, alpha, alpha, visible));
                for (theta, side) in [
                    (0.0f32, 1.0f32),
                    (30.0, 1.0),
                    (75.0, 1.0),
                    (89.0, 1.0),
                    (20.0, -1.0),
                    (40.0, -1.0),
                    (60.0, -1.0),
                ] {
                    let wi = dir(theta, 40.0, side);
                    for u1 in [0.001f32, 0.5, 0.999] {
                        let mut wl = SampledWavelengths::fixed(550.0);
                        let s0 = smooth.sample(&ctx, wi, u1, Vec2::ZERO, &mut wl).unwrap();
                        // Visible normals: each weight is the smooth one (G1 → 1). All normals:
                        // Walter's widened sampling α makes each weight D/D_sampled (mean 1);
                        // their midpoint-rule mean over a 64 × 64 grid of u is the smooth weight.
                        let (n, mut sum, mut far) = (64usize, 0.0f64, 0usize);
                        for k in 0..n * n {
                            let u = Vec2::new(
                                ((k % n) as f32 + 0.5) / n as f32,
                                ((k / n) as f32 + 0.5) / n as f32,
                            );
                            let at = format!(
                                "{kind:?} α={alpha} visible={visible} θ={theta} side={side} u1={u1} u={u}"
                            );
                            let s = rough.sample(&ctx, wi, u1, u, &mut wl).expect(&at);
                            assert_eq!(s.flags.is_reflection(), s0.flags.is_reflection(), "{at}");
                            assert!(s.wo.distance(s0.wo) < 5e-2, "{at}: {} vs {}", s.wo, s0.wo);
                            far += usize::from(s.wo.distance(s0.wo) > 1e-3);
                            assert!(s.weight.is_finite() && s.pdf.is_finite() && s.pdf > 0.0, "{at}");
                            assert!((s.eta - s0.eta).abs() < 1e-6, "{at}");
                            let ratio = s.weight[0] / s0.weight[0];
                            if visible {
                                assert!(
                                    (ratio - 1.0).abs() < 1e-3,
                                    "{at}: {} vs {}",
                                    s.weight[0],
                                    s0.weight[0]
                                );
                            }
                            sum += ratio as f64;
                        }
                        let mean = sum / (n * n) as f64;
                        assert!(
                            far * 2 < n * n,
                            "{kind:?} α={alpha} θ={theta}: {far} directions beyond 1e-3 rad"
                        );
                        assert!(
                            (mean - 1.0).abs() < 1e-2,
                            "{kind:?} α={alpha} visible={visible} θ={theta}: mean weight ratio {mean}"
                        );
                    }
                }
            }
        }
    }
}

fn dispersive(distribution: MicrofacetDistribution) -> RoughDielectric {
    let table = PiecewiseLinear::new(vec![400.0, 700.0], vec![1.53, 1.51], Extrapolation::Clamp).unwrap();
    RoughDielectric::new(
        Ior::from_spectrum(Spectrum::PiecewiseLinear(Arc::new(table))),
        Ior::Constant(1.0),
        distribution,
    )
}

#[test]
fn a_rough_prism_disperses_and_refraction_terminates_the_secondaries() {
    let d = MicrofacetDistribution::isotropic(Ggx, 0.05);
    let prism = dispersive(d);
    let lambdas = [420.0f32, 500.0, 580.0, 660.0];
    let wl = SampledWavelengths::from_parts(lambdas, [1.0; 4]);
    let ctx = BsdfContext::radiance();
    let (wi, wo) = (dir(60.0, 0.0, 1.0), dir(33.0, 180.0, -1.0));
    // eval: each wavelength is the constant-index model at its own index; pdf is the hero's.
    let f = prism.eval(&ctx, wi, wo, &wl);
    for (i, &l) in lambdas.iter().enumerate() {
        let fixed = glass(d);
        let at_l = RoughDielectric {
            int_ior: Ior::Constant(prism.int_ior.eval(l)),
            ..fixed
        };
        let expect = at_l.eval(&ctx, wi, wo, &wl)[0];
        assert!(
            expect > 0.0 && (f[i] / expect - 1.0).abs() < 1e-6,
            "λ {l}: {} vs {expect}",
            f[i]
        );
        if i == 0 {
            assert_eq!(prism.pdf(&ctx, wi, wo, &wl), at_l.pdf(&ctx, wi, wo, &wl));
        }
    }
    assert!(f[0] != f[3], "the lobes of blue and red differ");
    // A reflection keeps every wavelength, a refraction keeps the hero only.
    let mut w = wl;
    let s = prism.sample(&ctx, wi, 0.0, Vec2::new(0.3, 0.6), &mut w).unwrap();
    assert!(s.flags.is_reflection() && !w.secondary_terminated());
    assert!(s.weight[0] != s.weight[3], "F(λ) differs per wavelength");
    let s = prism.sample(&ctx, wi, 0.99, Vec2::new(0.3, 0.6), &mut w).unwrap();
    assert!(s.flags.is_transmission() && w.secondary_terminated());
    // The same facet refracts blue more than red.
    let refracted = |l: f32| {
        let mut w = SampledWavelengths::from_parts([l, 500.0, 600.0, 650.0], [1.0; 4]);
        prism
            .sample(&ctx, wi, 0.99, Vec2::new(0.3, 0.6), &mut w)
            .unwrap()
            .wo
    };
    assert!(
        refracted(400.0).x.abs() < refracted(700.0).x.abs(),
        "blue bends more"
    );
}

#[test]
fn anisotropy_follows_the_tangent() {
    // α_u (along x) small, α_v (along y) large: leaving the refraction direction along y costs
    // less than along x, in reflection and in transmission.
    let m = glass(MicrofacetDistribution::new(Ggx, 0.05, 0.3, true));
    assert!(m.flags().contains(BsdfFlags::ANISOTROPIC));
    assert!(
        !glass(MicrofacetDistribution::isotropic(Ggx, 0.3))
            .flags()
            .contains(BsdfFlags::ANISOTROPIC)
    );
    let ctx = BsdfContext::radiance();
    let wl = SampledWavelengths::fixed(550.0);
    for side in [1.0f32, -1.0] {
        let along_x = m.eval(&ctx, Vec3::Z, dir(10.0, 0.0, side), &wl)[0];
        let along_y = m.eval(&ctx, Vec3::Z, dir(10.0, 90.0, side), &wl)[0];
        assert!(along_y > 10.0 * along_x, "side {side}: {along_y} vs {along_x}");
    }
}

#[test]
fn lobes_masked_by_the_context() {
    let m = RoughDielectric::default();
    let wl = SampledWavelengths::fixed(550.0);
    let (a, r, t) = (dir(30.0, 0.0, 1.0), dir(30.0, 180.0, 1.0), dir(19.4, 180.0, -1.0));
    let refl_only = BsdfContext::radiance().with_lobes(BsdfFlags::GLOSSY_REFLECTION);
    let trans_only = BsdfContext::radiance().with_lobes(BsdfFlags::GLOSSY_TRANSMISSION);
    assert!(m.eval(&refl_only, a, r, &wl)[0] > 0.0 && m.eval(&refl_only, a, t, &wl)[0] == 0.0);
    assert!(m.eval(&trans_only, a, t, &wl)[0] > 0.0 && m.pdf(&trans_only, a, r, &wl) == 0.0);
    // One lobe enabled: it is sampled with probability 1 (the pdf has no F or 1 − F).
    let both = BsdfContext::radiance();
    let f = fresnel_dielectric(a.dot((a + r).normalize()), 1.5046 / 1.000277).reflectance;
    let ratio = m.pdf(&refl_only, a, r, &wl) / m.pdf(&both, a, r, &wl);
    assert!((ratio * f - 1.0).abs() < 1e-5, "{ratio} vs 1/{f}");
    let mut wl2 = wl;
    for u1 in [0.0f32, 0.5, 0.999] {
        let s = m
            .sample(&trans_only, a, u1, Vec2::new(0.4, 0.4), &mut wl2)
            .unwrap();
        assert!(s.flags.is_transmission());
    }
    assert!(
        m.sample(
            &both.with_lobes(BsdfFlags::DELTA_REFLECTION),
            a,
            0.5,
            Vec2::splat(0.5),
            &mut wl2
        )
        .is_none()
    );
}

/// Lobe splitting (`sample_split`): the lobe `sample` takes with the same numbers is one of the
/// two (direction, pdf, and weight times the probability of taking it), both are the same
/// facet's, each weighted f·|cos|/p_lobe with the full model's pdf, and their probabilities are
/// F and 1 − F.
#[test]
fn split_lobes_are_the_facet_of_sample_weighted_as_each_lobe_alone() {
    for kind in [Beckmann, Ggx] {
        for visible in [true, false] {
            let m = glass(MicrofacetDistribution::new(kind, 0.1, 0.3, visible));
            let ctx = BsdfContext::radiance();
            for wi in [
                dir(0.0, 0.0, 1.0),
                dir(50.0, 20.0, 1.0),
                dir(80.0, 200.0, 1.0),
                dir(20.0, 70.0, -1.0),
                dir(60.0, 10.0, -1.0),
            ] {
                let mut both = 0;
                for j in 0..64 {
                    let u1 = (j as f32 + 0.5) / 64.0;
                    let u2 = Vec2::new(
                        ((j * 17) % 64) as f32 / 64.0 + 0.005,
                        ((j * 29) % 64) as f32 / 64.0 + 0.01,
                    );
                    let mut wl = SampledWavelengths::fixed(600.0);
                    let plain = m.sample(&ctx, wi, u1, u2, &mut wl);
                    let split = m.sample_split(&ctx, wi, u2, &mut wl).unwrap();
                    let taken = if u1 < split.reflectance {
                        split.reflection
                    } else {
                        split.refraction
                    };
                    match (plain, taken) {
                        (None, None) => {}
                        (Some(p), Some((t, c))) => {
                            assert!((p.wo - t.wo).length() < 1e-6 && p.flags == t.flags);
                            assert!((p.pdf / t.pdf - 1.0).abs() < 1e-4, "{} vs {}", p.pdf, t.pdf);
                            let w = t.weight[0] / c;
                            assert!((w / p.weight[0] - 1.0).abs() < 1e-4, "{w} vs {}", p.weight[0]);
                        }
                        (p, t) => panic!("{kind:?} wi={wi} u1={u1}: sample {p:?}, split {t:?}"),
                    }
                    for (lobe, reflect) in [(split.reflection, true), (split.refraction, false)] {
                        let Some((o, c)) = lobe else { continue };
                        assert_eq!(o.flags.is_reflection(), reflect);
                        let (f, pdf) = (m.eval(&ctx, wi, o.wo, &wl)[0], m.pdf(&ctx, wi, o.wo, &wl));
                        assert!((pdf / o.pdf - 1.0).abs() < 1e-4, "pdf {pdf} vs {}", o.pdf);
                        let w = f * o.wo.z.abs() / (pdf / c);
                        assert!((w / o.weight[0] - 1.0).abs() < 1e-3, "{w} vs {}", o.weight[0]);
                    }
                    if let (Some((r, c_r)), Some((t, c_t))) = (split.reflection, split.refraction) {
                        both += 1;
                        assert!((c_r + c_t - 1.0).abs() < 1e-6);
                        // The same facet: the half vectors of the two directions agree.
                        let eta = if wi.z > 0.0 { 1.5 } else { 1.0 / 1.5 };
                        let hr = (wi + r.wo).normalize();
                        let ht = (wi + eta * t.wo).normalize();
                        let (hr, ht) = (hr * hr.z.signum(), ht * ht.z.signum());
                        assert!((hr - ht).length() < 1e-3, "{hr} vs {ht}");
                    }
                }
                if wi.z > 0.0 {
                    assert!(both > 32, "{kind:?} wi={wi}: both lobes {both} times of 64");
                }
            }
        }
    }
    // Multiple scattering has no one facet; a dispersive index is not split.
    let mut ms = glass(MicrofacetDistribution::isotropic(Ggx, 0.3));
    ms.multiple_scattering = true;
    let mut wl = SampledWavelengths::fixed(600.0);
    assert!(
        ms.sample_split(
            &BsdfContext::radiance(),
            dir(30.0, 0.0, 1.0),
            Vec2::splat(0.5),
            &mut wl
        )
        .is_none()
    );
    let prism = dispersive(MicrofacetDistribution::isotropic(Ggx, 0.3));
    let mut wl = SampledWavelengths::from_parts([450.0, 520.0, 590.0, 660.0], [1.0; 4]);
    assert!(
        prism
            .sample_split(
                &BsdfContext::radiance(),
                dir(30.0, 0.0, 1.0),
                Vec2::splat(0.5),
                &mut wl
            )
            .is_none()
    );
}
