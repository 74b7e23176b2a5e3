//! Tests of `principled` (a separate file to keep the model's under 800 lines).

use super::*;
use crate::albedo::directional_albedo;
use crate::bsdf::TransportMode;

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    Vec3::new(st * cp, st * sp, ct)
}

fn everything() -> Principled {
    let mut p = Principled::new(Spectrum::Constant(0.7));
    p.roughness = 0.4;
    p.anisotropic = 0.5;
    p.metallic = 0.2;
    p.spec_trans = 0.5;
    p.spec_tint = 0.3;
    p.sheen = 0.6;
    p.sheen_tint = 0.5;
    p.flatness = 0.3;
    p.clearcoat = 0.8;
    p.clearcoat_gloss = 0.6;
    p
}

#[test]
fn sampling_weight_is_eval_over_pdf_from_both_sides() {
    let ctx = BsdfContext::radiance();
    let m = everything();
    let (mut n_t, mut n_r) = (0, 0);
    for wi in [
        dir(0.0, 0.0),
        dir(40.0, 30.0),
        dir(80.0, 200.0),
        -dir(30.0, 60.0),
        -dir(70.0, 10.0),
    ] {
        for j in 0..64 {
            let mut wl = SampledWavelengths::fixed(550.0);
            let u1 = (j as f32 + 0.5) / 64.0;
            let u2 = Vec2::new(
                ((j * 37) % 64) as f32 / 64.0 + 0.004,
                ((j * 11) % 64) as f32 / 64.0 + 0.007,
            );
            let Some(s) = m.sample(&ctx, wi, u1, u2, &mut wl) else {
                continue;
            };
            let (f, pdf) = m.eval_pdf(&ctx, wi, s.wo, &wl);
            assert!((pdf / s.pdf - 1.0).abs() < 1e-4, "pdf {pdf} vs {}", s.pdf);
            let w = f[0] * s.wo.z.abs() / pdf;
            assert!(
                (w - s.weight[0]).abs() <= 1e-4 * w.max(1e-3),
                "{w} vs {}",
                s.weight[0]
            );
            if s.flags.is_transmission() {
                n_t += 1;
                assert!(wi.z * s.wo.z < 0.0);
                let expect = if wi.z > 0.0 { m.eta } else { 1.0 / m.eta };
                assert!((s.eta - expect).abs() < 1e-6);
            } else {
                n_r += 1;
            }
        }
    }
    assert!(n_t > 20 && n_r > 100, "{n_t} transmissions, {n_r} reflections");
}

#[test]
fn zero_roughness_is_finite_and_not_black() {
    // r = 0 clamps α to 10⁻³: samples are finite, the specular peak is sharp but finite, and the
    // sampled weights carry energy (F and the diffuse), never NaN.
    let ctx = BsdfContext::radiance();
    let mut m = everything();
    m.roughness = 0.0;
    m.anisotropic = 0.0;
    for wi in [dir(0.0, 0.0), dir(45.0, 10.0), dir(89.0, 10.0), -dir(45.0, 10.0)] {
        let mut sum = 0.0;
        for j in 0..256 {
            let mut wl = SampledWavelengths::fixed(550.0);
            let u = Vec2::new((j as f32 + 0.5) / 256.0, ((j * 97) % 256) as f32 / 256.0 + 0.001);
            if let Some(s) = m.sample(&ctx, wi, ((j * 13) % 256) as f32 / 256.0, u, &mut wl) {
                assert!(s.weight.is_finite() && s.pdf.is_finite() && s.pdf > 0.0, "{s}");
                sum += s.weight[0];
            }
        }
        assert!(sum > 0.0, "θi = {}: black", wi.z.acos().to_degrees());
        let wl = SampledWavelengths::fixed(550.0);
        let (f, pdf) = m.eval_pdf(&ctx, wi, reflect_about(wi, Vec3::Z), &wl);
        assert!(f.is_finite() && pdf.is_finite() && f[0] > 0.0, "{f} {pdf}");
    }
}

#[test]
fn anisotropy_stretches_along_the_tangent() {
    let mut m = Principled::new(Spectrum::Constant(0.0));
    m.roughness = 0.4;
    m.anisotropic = 0.9;
    let ctx = BsdfContext::radiance();
    let wl = SampledWavelengths::fixed(550.0);
    let along_x = m.eval(&ctx, Vec3::Z, dir(20.0, 0.0), &wl)[0];
    let along_y = m.eval(&ctx, Vec3::Z, dir(20.0, 90.0), &wl)[0];
    assert!(along_x > 3.0 * along_y, "{along_x} vs {along_y}");
    assert!(m.flags().contains(BsdfFlags::ANISOTROPIC));
}

#[test]
fn pure_metal_is_schlick_ggx() {
    // metallic = 1: f = F_schlick(c) D G / (4 cos θi cos θo), no other lobe.
    let mut m = Principled::new(Spectrum::Constant(0.8));
    m.metallic = 1.0;
    m.roughness = 0.5;
    let ctx = BsdfContext::radiance();
    let wl = SampledWavelengths::fixed(550.0);
    let (wi, wo) = (dir(30.0, 0.0), dir(50.0, 170.0));
    let h = (wi + wo).normalize();
    let d = MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, 0.25);
    let fs = 0.8 + 0.2 * (1.0 - wi.dot(h)).powi(5);
    let expect = fs * d.d(h) * d.g(wi, wo, h) / (4.0 * wi.z * wo.z);
    let f = m.eval(&ctx, wi, wo, &wl)[0];
    assert!((f / expect - 1.0).abs() < 1e-5, "{f} vs {expect}");
}

#[test]
fn lambertian_limit() {
    // roughness 0, metallic 0, specular → 0 (η → 1): the diffuse lobe at normal incidence and
    // exitance is c/π (F_L = F_V = 0, no retro-reflection at r = 0).
    let mut m = Principled::new(Spectrum::Constant(0.6));
    m.roughness = 0.0;
    m.eta = 1.0;
    let wl = SampledWavelengths::fixed(550.0);
    let f = m.eval(&BsdfContext::radiance(), Vec3::Z, dir(60.0, 0.0), &wl)[0];
    let expect = 0.6 * FRAC_1_PI * (1.0 - 0.5 * 0.5f32.powi(5));
    assert!((f - expect).abs() < 1e-6, "{f} vs {expect}");
}

/// The energy figures of Mitsuba's model, measured by quadrature of eval (4·10⁶ directions):
/// a white dielectric (c = 1) at roughness 1 reflects more than it receives at grazing
/// incidence (the retro-reflection of Burley's diffuse gains energy); a half transmissive, half
/// diffuse one gains a little outside (its diffuse lobe is not weighted by 1 − F), while light
/// inside it keeps only w_bsdf of what single scattering would return.
#[test]
fn energy_gain_and_loss_of_mitsubas_principled() {
    let wl = SampledWavelengths::fixed(550.0);
    let mut white = Principled::new(Spectrum::Constant(1.0));
    white.roughness = 1.0;
    let grazing = directional_albedo(&white, TransportMode::Importance, dir(80.0, 0.0), &wl, 4_000_000);
    let total = grazing.r[0] + grazing.t[0];
    eprintln!("principled c=1 r=1 θi=80°: albedo {total:.4}");
    assert!(
        total > 1.05,
        "Burley's retro-reflection gains energy at grazing incidence: {total}"
    );

    let mut glass = Principled::new(Spectrum::Constant(1.0));
    glass.spec_trans = 0.5;
    glass.roughness = 0.3;
    let inside = directional_albedo(&glass, TransportMode::Importance, -dir(20.0, 0.0), &wl, 4_000_000);
    let outside = directional_albedo(&glass, TransportMode::Importance, dir(20.0, 0.0), &wl, 4_000_000);
    let (a_in, a_out) = (inside.r[0] + inside.t[0], outside.r[0] + outside.t[0]);
    eprintln!("principled spec_trans=0.5 r=0.3: albedo inside {a_in:.4}, outside {a_out:.4}");
    // Inside, reflection and transmission are both scaled by w_bsdf = 0.5.
    assert!(a_in < 0.5 + 1e-3 && a_in > 0.45, "inside: {a_in}");
    assert!(a_out > 1.0 && a_out < 1.05, "outside: {a_out}");
}

/// Mitsuba's tint divides the base colour by its spectral luminance over the path's four
/// wavelengths. With all four at one wavelength (as the battery queries) the tint is 1/ȳ(λ):
/// at 400 nm a spec_tint of 0.4 makes the surface reflect tens of times more than
/// it receives (37× at θi = 30°), while at 555 nm (ȳ ≈ 1) it stays below 1. Over four wavelengths spread
/// across the spectrum, as a renderer samples them, ȳ averages to a moderate value.
#[test]
fn tinted_principled_at_one_wavelength() {
    let mut m = Principled::new(Spectrum::Constant(0.5));
    m.spec_tint = 0.4;
    let wi = dir(30.0, 0.0);
    let at = |lambda: f32| {
        let wl = SampledWavelengths::fixed(lambda);
        let a = directional_albedo(&m, TransportMode::Importance, wi, &wl, 1_000_000);
        a.r[0] + a.t[0]
    };
    let (blue, green) = (at(400.0), at(555.0));
    let spread = SampledWavelengths::from_parts([420.0, 520.0, 620.0, 720.0], [1.0; 4]);
    let a = directional_albedo(&m, TransportMode::Importance, wi, &spread, 1_000_000);
    eprintln!(
        "principled spec_tint 0.4, c = 0.5, θi = 30°: albedo {blue:.1} at 400 nm, {green:.4} at 555 nm, {:.4}..{:.4} over 420/520/620/720 nm",
        a.r.min_component(),
        a.r.max_component()
    );
    assert!(blue > 10.0, "{blue}");
    assert!(green < 1.0, "{green}");
    assert!(a.r.max_component() < 1.0, "{}", a.r);
}
