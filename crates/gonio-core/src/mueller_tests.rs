//! Physics of the Mueller types and the Fresnel matrices (issue 12 §4): Malus's law, crossed
//! polarizers, Brewster's angle, the quarter-wave plate, the retardance of total internal
//! reflection against its closed form, reciprocity, the frame checks, and the unpolarized values
//! of the Fresnel matrices against `crate::fresnel`.

use super::*;
use crate::bsdf::{Bsdf, BsdfContext};
use crate::bsdfs::RoughConductor;
use crate::fresnel::{fresnel_conductor_exterior, fresnel_dielectric};
use crate::fresnel_polarized::{
    conductor_reflection, dielectric_reflection, dielectric_transmission, fresnel_amplitudes,
    interface_mueller, reflection_retardance,
};
use crate::microfacet::{MicrofacetDistribution, MicrofacetKind};
use crate::spectra::Spectrum;
use crate::spectrum::SampledWavelengths;
use num_complex::Complex32;

fn beam() -> StokesBasis {
    StokesBasis::new(Vec3::Z, Vec3::X)
}

/// The basis of a beam along +z whose x-axis is turned by `theta` about z.
fn turned(theta: f32) -> StokesBasis {
    StokesBasis::new(Vec3::Z, Vec3::new(theta.cos(), theta.sin(), 0.0))
}

fn close(a: f32, b: f32, tol: f32) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn malus_law_through_two_polarizers() {
    let one = SampledSpectrum::ONE;
    let light = Stokes::unpolarized(one);
    let first = Mueller::linear_polarizer(one, beam());
    for deg in [0.0f32, 10.0, 30.0, 45.0, 60.0, 89.0, 90.0, 135.0] {
        let theta = deg.to_radians();
        // The second polarizer is stated in its own (turned) basis: multiplying it with the first
        // needs a change of basis; the product is then in the first's basis.
        let second = Mueller::linear_polarizer(one, turned(theta)).in_bases(beam(), beam());
        let out = (second * first).apply(&light);
        let want = 0.5 * theta.cos().powi(2);
        assert!(
            close(out.components()[0][0], want, 1e-6),
            "{deg}°: {:?} vs {want}",
            out.components()
        );
        assert!(out.is_physical(1e-6));
    }
}

#[test]
fn crossed_polarizers_block() {
    let one = SampledSpectrum::ONE;
    let p = Mueller::linear_polarizer(one, beam());
    let crossed =
        Mueller::linear_polarizer(one, turned(std::f32::consts::FRAC_PI_2)).in_bases(beam(), beam());
    let out = (crossed * p).apply(&Stokes::unpolarized(one));
    for c in out.components() {
        assert!(c.0.abs().max_element() < 1e-7, "{:?}", out.components());
    }
}

#[test]
fn a_product_with_mismatched_frames_is_an_error() {
    let one = SampledSpectrum::ONE;
    let a = Mueller::linear_polarizer(one, beam());
    let b = Mueller::linear_polarizer(one, turned(0.4));
    let e = a.try_mul(&b).unwrap_err();
    assert!(e.to_string().contains("rotate first"), "{e}");
    assert!(a.try_add(&b).is_err());
    assert!(a.try_apply(&Stokes::new([one; 4], turned(0.4))).is_err());
    // Frame-free elements combine with anything, and the rotation fixes the mismatch.
    assert!(a.try_mul(&Mueller::depolarizer(one)).is_ok());
    assert!(a.try_mul(&b.in_bases(beam(), beam())).is_ok());
}

/// Light that leaves an element unpolarized has no basis to match: a framed product ending in a
/// depolarizer (a diffuse vertex after a thin sheet, in light order) composes with an element
/// stated in any basis, and so does one that reads intensity only; a polarizing junction still
/// has to match.
#[test]
fn bases_need_not_meet_where_the_light_is_unpolarized() {
    let one = SampledSpectrum::ONE;
    let sheet = Mueller::linear_polarizer(one, turned(0.4));
    let diffuse_after_sheet = Mueller::depolarizer(one * 0.3) * sheet;
    let next = Mueller::linear_polarizer(one, beam());
    let product = next
        .try_mul(&diffuse_after_sheet)
        .expect("the junction carries unpolarized light");
    // Intensity: 0.3 · ½ (the sheet) · ½ (the second polarizer on unpolarized light).
    let out = product.apply(&Stokes::unpolarized(one));
    assert!(
        close(out.components()[0][0], 0.075, 1e-7),
        "{:?}",
        out.components()
    );
    let reads_intensity = Mueller::depolarizer(one) * Mueller::linear_polarizer(one, beam());
    assert!(
        reads_intensity.try_mul(&sheet).is_err(),
        "the polarizer reads the polarization"
    );
    let detector =
        Mueller::depolarizer(one * 2.0) * Mueller::linear_polarizer(one, beam()).in_bases(beam(), beam());
    assert!(detector.try_apply(&Stokes::new([one; 4], turned(0.4))).is_err());
    assert!(
        next.try_mul(&sheet).is_err(),
        "a polarizing junction still has to match"
    );
}

#[test]
#[cfg(debug_assertions)]
#[should_panic(expected = "Stokes frames differ")]
fn the_operator_checks_frames_in_debug_builds() {
    let one = SampledSpectrum::ONE;
    let _ = Mueller::linear_polarizer(one, beam()) * Mueller::linear_polarizer(one, turned(0.4));
}

#[test]
fn rotation_examples_of_mitsuba() {
    // mueller.h: horizontal light [1,1,0,0] in basis x = (1,0,0) reads as +45° light [1,0,1,0]
    // in the basis x = (0.707, −0.707, 0); the rotator of +45° turns [1,1,0,0] into [1,0,−1,0].
    let one = SampledSpectrum::ONE;
    let z = SampledSpectrum::ZERO;
    let h = Stokes::new([one, one, z, z], beam());
    let target = StokesBasis::new(Vec3::Z, Vec3::new(1.0, -1.0, 0.0).normalize());
    let s = h.in_basis(target).components();
    assert!(close(s[1][0], 0.0, 1e-6) && close(s[2][0], 1.0, 1e-6), "{s:?}");
    let r = Mueller::rotator(std::f32::consts::FRAC_PI_4, beam())
        .apply(&h)
        .components();
    assert!(close(r[1][0], 0.0, 1e-6) && close(r[2][0], -1.0, 1e-6), "{r:?}");
}

#[test]
fn quarter_wave_plate_at_45_degrees_makes_linear_light_circular() {
    let one = SampledSpectrum::ONE;
    let z = SampledSpectrum::ZERO;
    let horizontal = Stokes::new([one, one, z, z], beam());
    let qwp = Mueller::linear_retarder(std::f32::consts::FRAC_PI_2, turned(std::f32::consts::FRAC_PI_4))
        .in_bases(beam(), beam());
    let out = qwp.apply(&horizontal).components();
    assert!(close(out[0][0], 1.0, 1e-6), "{out:?}");
    assert!(close(out[3][0].abs(), 1.0, 1e-6), "circular: {out:?}");
    assert!(out[1][0].abs() < 1e-6 && out[2][0].abs() < 1e-6, "{out:?}");
    // A circular polarizer passes half of unpolarized light, fully circular.
    let c = Mueller::circular_polarizer(true)
        .apply(&Stokes::unpolarized(one))
        .components();
    assert!(close(c[0][0], 0.5, 1e-7) && close(c[3][0], 0.5, 1e-7));
}

#[test]
fn brewster_reflection_is_fully_s_polarized() {
    for eta in [1.33f32, 1.5, 2.4] {
        let cos_b = eta.atan().cos();
        let m = dielectric_reflection(cos_b, SampledSpectrum::splat(eta));
        let out = Mueller::new(m, beam(), beam()).apply(&Stokes::unpolarized(SampledSpectrum::ONE));
        let dop = out.degree_of_polarization()[0];
        assert!(close(dop, 1.0, 1e-4), "η {eta}: degree of polarization {dop}");
        // Along the s-axis (the x-axis of the s/p frame): S1 = +S0.
        let s = out.components();
        assert!(close(s[1][0] / s[0][0], 1.0, 1e-4), "{s:?}");
        // Elsewhere partially polarized.
        let m2 = dielectric_reflection(0.8, SampledSpectrum::splat(eta));
        let d2 = Mueller::new(m2, beam(), beam()).apply(&Stokes::unpolarized(SampledSpectrum::ONE));
        assert!(d2.degree_of_polarization()[0] < 0.9);
    }
}

#[test]
fn tir_retardance_matches_the_closed_form() {
    // From inside a medium of index n (cos θi < 0 with η = n): beyond the critical angle
    // |δ| = 2 atan(cos θ √(sin²θ − 1/n²) / sin²θ) (Born & Wolf §1.5.4).
    for n in [1.33f32, 1.5, 2.0] {
        let critical = (1.0 / n).asin();
        for k in 1..10 {
            let theta = critical + (std::f32::consts::FRAC_PI_2 - critical) * k as f32 / 10.0;
            let (s, c) = theta.sin_cos();
            let want = 2.0 * (c * (s * s - 1.0 / (n * n)).sqrt() / (s * s)).atan();
            let got = reflection_retardance(-c, Complex32::new(n, 0.0));
            assert!(
                close(got.abs(), want, 2e-5),
                "n {n} θ {}°: {got} vs {want}",
                theta.to_degrees()
            );
            // Total reflection: both amplitudes of modulus 1.
            let (a_s, a_p) = fresnel_amplitudes(-c, Complex32::new(n, 0.0));
            assert!(close(a_s.norm(), 1.0, 1e-5) && close(a_p.norm(), 1.0, 1e-5));
            // The Mueller matrix carries it: a pure retarder (M00 = 1, M22 = cos δ).
            let m = dielectric_reflection(-c, SampledSpectrum::splat(n));
            assert!(close(m.get(0, 0)[0], 1.0, 0.0) && close(m.get(2, 2)[0], want.cos(), 2e-5));
        }
    }
}

#[test]
fn fresnel_matrices_keep_the_unpolarized_values_exactly() {
    let eta = SampledSpectrum::new([1.2, 1.5, 0.7, 2.4]);
    let k = SampledSpectrum::new([3.9, 0.0, 1.0, 6.8]);
    let ext = SampledSpectrum::new([1.0, 1.33, 1.0, 1.2]);
    for i in 0..=40 {
        let c = -1.0 + i as f32 / 20.0;
        let r = dielectric_reflection(c, eta).get(0, 0);
        let t = dielectric_transmission(c, eta).get(0, 0);
        for l in 0..4 {
            let f = fresnel_dielectric(c, eta[l]).reflectance;
            assert_eq!(r[l], f, "cos {c} η {}", eta[l]);
            assert_eq!(t[l], if f >= 1.0 { 0.0 } else { 1.0 - f });
        }
        let cc = c.abs();
        assert_eq!(
            conductor_reflection(cc, eta, k, ext).get(0, 0),
            fresnel_conductor_exterior(cc, eta, k, ext)
        );
        // And the complex amplitudes agree with the real-arithmetic values: (|a_s|² + |a_p|²)/2 = F.
        for l in 0..4 {
            let (a_s, a_p) = fresnel_amplitudes(cc, Complex32::new(eta[l] / ext[l], k[l] / ext[l]));
            let f = 0.5 * (a_s.norm_sqr() + a_p.norm_sqr());
            let want = fresnel_conductor_exterior(cc, eta, k, ext)[l];
            assert!(
                close(f, want, 2e-5 * want.max(1e-3)),
                "conductor cos {cc}: {f} vs {want}"
            );
            let (a_s, a_p) = fresnel_amplitudes(c, Complex32::new(eta[l], 0.0));
            let f = 0.5 * (a_s.norm_sqr() + a_p.norm_sqr());
            let want = fresnel_dielectric(c, eta[l]).reflectance;
            assert!(close(f, want, 2e-5), "dielectric cos {c}: {f} vs {want}");
        }
    }
}

#[test]
fn fresnel_matrices_are_physical_and_passive() {
    let eta = SampledSpectrum::new([1.2, 1.5, 0.7, 2.4]);
    let k = SampledSpectrum::new([3.9, 0.0, 1.0, 6.8]);
    let one = SampledSpectrum::ONE;
    let z = SampledSpectrum::ZERO;
    let probes = [
        [one, z, z, z],
        [one, one, z, z],
        [one, z, -one, z],
        [one, z, z, one],
        [one, one * 0.6, one * 0.0, one * -0.8],
    ];
    for i in 0..=20 {
        let c = -1.0 + i as f32 / 10.0;
        for m in [
            dielectric_reflection(c, eta),
            dielectric_transmission(c, eta),
            conductor_reflection(c.abs(), eta, k, one),
        ] {
            for p in probes {
                let out = Mueller::new(m, beam(), beam()).apply(&Stokes::new(p, beam()));
                assert!(out.is_physical(1e-5), "cos {c}: {:?}", out.components());
                let s0 = out.components()[0];
                assert!((0..4).all(|l| s0[l] <= 1.0 + 1e-6), "passive: {s0:?}");
            }
        }
    }
}

/// Reciprocity of a BSDF's Mueller matrix: exchanging the roles of the two directions gives
/// Q Mᵀ Q with Q = diag(1, 1, −1, 1), when each reversed beam's basis keeps the x-axis of the
/// forward beam's basis (so its y-axis flips, which flips s2 but not s3, both being seen by
/// observers facing opposite ways). Checked on a rough conductor and the Fresnel mirror.
#[test]
fn mueller_reciprocity_relation() {
    let q = |m: &MuellerMatrix| {
        let mut r = m.transpose();
        for i in 0..4 {
            for j in 0..4 {
                if (i == 2) != (j == 2) {
                    r.0[i][j] = -r.0[i][j];
                }
            }
        }
        r
    };
    let d = MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.3, 0.3, true);
    let gold = RoughConductor::new(Spectrum::Constant(0.2), Spectrum::Constant(3.9), d);
    let wl = SampledWavelengths::fixed(550.0);
    let ctx = BsdfContext::radiance();
    let dirs = [
        Vec3::new(0.3, 0.2, 0.93).normalize(),
        Vec3::new(-0.5, 0.4, 0.5).normalize(),
        Vec3::new(0.7, -0.1, 0.2).normalize(),
    ];
    let mut checked = 0;
    for a in dirs {
        for b in dirs {
            if a == b {
                continue;
            }
            let m1 = gold.eval_mueller(&ctx, a, b, &wl); // light −b → a
            let m2 = gold.eval_mueller(&ctx, b, a, &wl); // light −a → b
            let (i1, o1) = m1.frames().unwrap();
            // The reversed beams with the same x-axes: −a (reverse of o1), b (reverse of i1).
            let m2 = m2.in_bases(StokesBasis::new(-a, o1.x()), StokesBasis::new(b, i1.x()));
            let want = q(m1.matrix());
            let diff = m2.matrix().max_abs_diff(&want);
            assert!(
                diff < 1e-5 * m1.get(0, 0)[0].max(1.0),
                "a {a} b {b}: {diff}\n{m2:?}\n{want:?}"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 6);
    // The ideal mirror (a delta lobe): the Fresnel matrix between the two s/p frames.
    let wi = dirs[1];
    let eta = SampledSpectrum::splat(0.2);
    let k = SampledSpectrum::splat(3.9);
    let m = conductor_reflection(wi.z, eta, k, SampledSpectrum::ONE);
    let fwd = interface_mueller(m, Vec3::Z, -crate::bsdf::reflect(wi), wi);
    let back = interface_mueller(m, Vec3::Z, -wi, crate::bsdf::reflect(wi));
    let (i1, o1) = fwd.frames().unwrap();
    let back = back.in_bases(
        StokesBasis::new(-wi, o1.x()),
        StokesBasis::new(crate::bsdf::reflect(wi), i1.x()),
    );
    assert!(back.matrix().max_abs_diff(&q(fwd.matrix())) < 1e-5);
}

/// `roughdielectric` polarizes like the smooth `dielectric` at the specular configurations (the
/// microfacet normal is then the macro-normal): the shapes M/M00 agree, for reflection and
/// refraction, from both sides (Mitsuba 3.9.1's `roughdielectric` does not polarize, so this is
/// its check).
#[test]
fn roughdielectric_shape_is_the_smooth_dielectrics_at_the_specular_directions() {
    use crate::bsdfs::{Dielectric, RoughDielectric};
    use crate::ior::Ior;
    use glam::Vec2;
    let smooth = Dielectric::new(Ior::Constant(1.5), Ior::Constant(1.0));
    let d = MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.05, 0.05, true);
    let rough = RoughDielectric::new(Ior::Constant(1.5), Ior::Constant(1.0), d);
    let wl = SampledWavelengths::fixed(550.0);
    let shape = |m: &Mueller| crate::fresnel_polarized::normalized(m.matrix());
    let mut checked = 0;
    for ctx in [BsdfContext::radiance(), BsdfContext::importance()] {
        for wi in [
            Vec3::new(0.5, 0.2, 0.84).normalize(),
            Vec3::new(-0.3, 0.6, -0.74).normalize(),
            Vec3::new(0.1, -0.2, -0.97).normalize(),
        ] {
            for u1 in [0.01f32, 0.99] {
                let Some(s) = smooth.sample_mueller(&ctx, wi, u1, Vec2::splat(0.5), &mut wl.clone()) else {
                    continue;
                };
                let r = rough.eval_mueller(&ctx, wi, s.wo, &wl);
                assert!(r.get(0, 0)[0] > 0.0);
                let (a, b) = (shape(&s.weight), shape(&r));
                assert!(a.max_abs_diff(&b) < 2e-3, "wi {wi} wo {}: {a:?} vs {b:?}", s.wo);
                assert_eq!(
                    s.weight.frames().map(|f| f.1.forward()),
                    r.frames().map(|f| f.1.forward())
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 10, "{checked}");
}
