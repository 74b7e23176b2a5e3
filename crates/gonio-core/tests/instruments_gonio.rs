//! The virtual gonioreflectometer against known answers: a Lambertian specimen reads ρ/π within
//! the instrument's own error bars, detector noise is accounted for in them, a flat heightfield
//! of Lambertian facets is a Lambertian, a rough one back-scatters, and the `tabulated` BSDF
//! plays a measured table back.

use glam::Vec3;
use gonio_core::bsdf::{Bsdf, BsdfContext, TransportMode};
use gonio_core::bsdfs::tabulated::{Tabulated, TabulatedData};
use gonio_core::bsdfs::{Conductor, Diffuse};
use gonio_core::instruments::albedo::{Wavelengths, directional_albedo};
use gonio_core::instruments::gonioreflectometer::{
    BsdfSpecimen, GonioSettings, HeightfieldSpecimen, Sample, measure,
};
use gonio_core::instruments::spherical_direction;
use gonio_core::{SampledWavelengths, Spectrum};
use std::f32::consts::PI;
use std::sync::Arc;

fn small_settings(photons: u64) -> GonioSettings {
    GonioSettings {
        incident: 4,
        outgoing: 6,
        azimuths: 7,
        aperture_deg: 5.0,
        photons,
        noise: 0.0,
        wavelengths: vec![450.0, 550.0],
        seed: 7,
    }
}

/// z-scores of every entry against a constant expected value: (max |z|, mean z²).
fn z_scores(t: &TabulatedData, expect: f32) -> (f32, f32) {
    let err = t.stderr.as_ref().expect("a measured table has error bars");
    let z: Vec<f32> = t.values.iter().zip(err).map(|(v, e)| (v - expect) / e).collect();
    let max = z.iter().map(|z| z.abs()).fold(0.0, f32::max);
    let mean2 = z.iter().map(|z| z * z).sum::<f32>() / z.len() as f32;
    (max, mean2)
}

#[test]
fn lambertian_table_matches_rho_over_pi_within_its_noise() {
    let d = Diffuse::new(Spectrum::Constant(0.6));
    let table = measure(&BsdfSpecimen::new(&d, "diffuse 0.6"), &small_settings(200_000)).unwrap();
    let expect = 0.6 / PI;
    let (max_z, mean_z2) = z_scores(&table, expect);
    // 168 readings: |z| < 4.5 for all, and the error bars are honest (mean z² ≈ 1).
    assert!(max_z < 4.5, "max |z| = {max_z}");
    assert!((0.5..2.0).contains(&mean_z2), "mean z² = {mean_z2}");
    // And the noise is small: a few per cent.
    let err = table.stderr.as_ref().unwrap();
    assert!(err.iter().all(|e| *e < 0.08 * expect), "error bars too wide");
    // The grazing detector (θo = 82.5°) reads right only if it divides by the *projected*
    // solid angle: ρ/π, not ρ/π·cos θo.
    let o_last = table.theta_o_deg.len() - 1;
    let v = table.values[table.index(1, o_last, 3, 1)];
    assert!((v - expect).abs() < 0.1 * expect, "grazing reading {v}");
}

#[test]
fn detector_noise_is_in_the_error_bars() {
    let d = Diffuse::new(Spectrum::Constant(0.5));
    let s = GonioSettings {
        noise: 0.1,
        ..small_settings(100_000)
    };
    let table = measure(&BsdfSpecimen::new(&d, "diffuse 0.5"), &s).unwrap();
    let expect = 0.5 / PI;
    let spread = table
        .values
        .iter()
        .map(|v| (v - expect).abs())
        .fold(0.0, f32::max);
    assert!(
        spread > 0.1 * expect,
        "10 % noise must show: max deviation {spread}"
    );
    let (max_z, mean_z2) = z_scores(&table, expect);
    assert!(max_z < 4.5 && (0.5..2.0).contains(&mean_z2), "{max_z} {mean_z2}");
}

#[test]
fn a_mirror_reads_as_a_bump_of_height_f_over_projected_solid_angle() {
    // A perfect mirror sends every photon to the mirror direction: the detector there reads
    // 1/Ω⊥, every other detector 0. θi = θo = 22.5° at φd = 180° is a grid point.
    let m = Conductor::mirror();
    let s = GonioSettings {
        incident: 2,
        outgoing: 2,
        azimuths: 3,
        photons: 10_000,
        ..small_settings(0)
    };
    let table = measure(&BsdfSpecimen::new(&m, "mirror"), &s).unwrap();
    let omega = gonio_core::instruments::gonioreflectometer::projected_solid_angle(
        spherical_direction(22.5f32.to_radians(), PI),
        5f32.to_radians(),
    );
    let peak = table.values[table.index(0, 0, 2, 0)];
    assert!(
        (peak - 1.0 / omega).abs() < 1e-3 / omega,
        "peak {peak} vs {}",
        1.0 / omega
    );
    assert_eq!(table.values[table.index(0, 1, 2, 0)], 0.0);
    assert_eq!(table.values[table.index(0, 0, 0, 0)], 0.0);
}

#[test]
fn heightfields_of_lambertian_facets() {
    let facet: Arc<dyn Bsdf> = Arc::new(Diffuse::new(Spectrum::Constant(0.5)));
    let flat = HeightfieldSpecimen::new(4, vec![0.2; 16], facet.clone(), "diffuse 0.5").unwrap();
    let s = GonioSettings {
        wavelengths: vec![550.0],
        ..small_settings(100_000)
    };
    let table = measure(&flat, &s).unwrap();
    let (max_z, _) = z_scores(&table, 0.5 / PI);
    assert!(
        max_z < 4.5,
        "a flat heightfield is the facet itself: max |z| = {max_z}"
    );

    // A rough surface of white Lambertian facets loses nothing (every photon escapes in the
    // end), and it back-scatters: at grazing incidence the retro direction is brighter than the
    // forward one (Oren & Nayar's observation).
    let white: Arc<dyn Bsdf> = Arc::new(Diffuse::new(Spectrum::Constant(1.0)));
    let rough = HeightfieldSpecimen::random(8, 0.35, 3, white, "white diffuse").unwrap();
    let mut rng = gonio_core::rng::Pcg32::new(1, 1);
    let to_source = spherical_direction(60f32.to_radians(), 0.0);
    let mut escaped = 0.0;
    for _ in 0..20_000 {
        let mut wl = SampledWavelengths::fixed(550.0);
        if let Some((d, thr)) = rough.scatter(to_source, &mut rng, &mut wl) {
            assert!(d.z > 0.0);
            escaped += thr[0];
        }
    }
    assert!(
        escaped / 20_000.0 > 0.99,
        "white facets conserve energy: {}",
        escaped / 20_000.0
    );
    let s = GonioSettings {
        incident: 3,
        outgoing: 3,
        azimuths: 2,
        aperture_deg: 10.0,
        wavelengths: vec![550.0],
        ..small_settings(100_000)
    };
    let t = measure(&rough, &s).unwrap();
    let (retro, forward) = (t.values[t.index(2, 2, 0, 0)], t.values[t.index(2, 2, 1, 0)]);
    let err = t.stderr.as_ref().unwrap()[t.index(2, 2, 0, 0)];
    assert!(
        retro > forward + 4.0 * err,
        "retro {retro} vs forward {forward} ± {err}"
    );
}

#[test]
fn tabulated_playback_of_a_measured_lambertian() {
    let d = Diffuse::new(Spectrum::Constant(0.6));
    let table = measure(&BsdfSpecimen::new(&d, "diffuse 0.6"), &small_settings(200_000)).unwrap();
    let max_err = table.stderr.as_ref().unwrap().iter().copied().fold(0.0, f32::max);
    let t = Tabulated::new(table);
    let ctx = BsdfContext::radiance();
    let wl = SampledWavelengths::fixed(500.0);
    let mut rng = gonio_core::rng::Pcg32::new(9, 0);
    for _ in 0..1000 {
        let a = rng.next_vec2();
        let b = rng.next_vec2();
        let wi = spherical_direction(a.x * 1.55, a.y * std::f32::consts::TAU);
        let wo = spherical_direction(b.x * 1.55, b.y * std::f32::consts::TAU);
        let f = t.eval(&ctx, wi, wo, &wl)[0];
        assert!((f - 0.6 / PI).abs() < 3.0 * max_err, "f({wi}, {wo}) = {f}");
    }
    // Its directional albedo is ρ within the measurement noise (importance-sampled).
    let alb = directional_albedo(
        &t,
        &[10.0, 50.0, 80.0],
        20_000,
        TransportMode::Radiance,
        Wavelengths::Fixed(550.0),
        false,
        1,
    );
    for p in alb {
        assert!((p.r - 0.6).abs() < 0.03 + 4.0 * p.r_stderr, "{p:?}");
        assert_eq!(p.t, 0.0);
    }
    assert_eq!(t.eval(&ctx, Vec3::Z, -Vec3::Z, &wl)[0], 0.0);
}

#[test]
fn a_measured_table_passes_the_property_battery() {
    // The played-back table must be a well-behaved BSDF: χ² sampling test, weight = f·cos/pdf,
    // reciprocity (enforced), isotropy, energy, health — the same battery `gonio check` runs.
    let d = Diffuse::new(Spectrum::Constant(0.8));
    let s = GonioSettings {
        incident: 6,
        outgoing: 6,
        azimuths: 10,
        ..small_settings(100_000)
    };
    let t = Tabulated::new(measure(&BsdfSpecimen::new(&d, "diffuse 0.8"), &s).unwrap());
    let rows = gonio_core::check::battery(&t, &gonio_core::check::CheckConfig::quick());
    assert!(
        gonio_core::check::all_passed(&rows),
        "{}",
        gonio_core::check::failures(&rows)
    );
    assert!(rows.iter().any(|r| r.name == "chi2"));
}

#[test]
fn a_half_space_of_lambertian_spheres_has_the_published_plane_albedo() {
    // Plane albedo of d'Eon 2021's half-space of Lambert spheres (CGF 40(4), EGSR) with c = 0.5:
    // a(μ = 1) = 0.175734, a(μ = 0.5) = 0.200553 (deterministic solver of its transport problem).
    use gonio_core::instruments::gonioreflectometer::SphereHalfSpaceSpecimen;
    let c: Arc<dyn Bsdf> = Arc::new(Diffuse::new(Spectrum::Constant(0.5)));
    let spheres = SphereHalfSpaceSpecimen::new(c, 1000, "diffuse 0.5");
    for (mu, expect) in [(1.0f32, 0.175734f64), (0.5, 0.200553)] {
        let to_source = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        let mut rng = gonio_core::rng::Pcg32::new(11, 0);
        let n = 200_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let mut wl = SampledWavelengths::fixed(550.0);
            if let Some((d, thr)) = spheres.scatter(to_source, &mut rng, &mut wl) {
                assert!(d.z > 0.0);
                s += thr[0] as f64;
                s2 += (thr[0] as f64).powi(2);
            }
        }
        let mean = s / n as f64;
        let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!(
            (mean - expect).abs() < 4.0 * se,
            "μ = {mu}: {mean} ± {se} vs {expect}"
        );
    }
}

/// A Gaussian heightfield of perfect mirrors (Beckmann slope statistics, α = 0.2) read by the
/// instrument, against `roughconductor` (Beckmann α = 0.2, F = 1) read by the same instrument.
fn gaussian_mirrors_and_roughconductor(alpha: f32) -> (TabulatedData, TabulatedData) {
    use gonio_core::bsdfs::RoughConductor;
    use gonio_core::microfacet::{MicrofacetDistribution, MicrofacetKind};
    let facet: Arc<dyn Bsdf> = Arc::new(Conductor::mirror());
    let surface = HeightfieldSpecimen::gaussian(512, alpha, 1, facet, "mirror").unwrap();
    let model = RoughConductor::mirror(MicrofacetDistribution::isotropic(MicrofacetKind::Beckmann, alpha));
    let s = GonioSettings {
        incident: 3,
        outgoing: 6,
        azimuths: 7,
        aperture_deg: 5.0,
        photons: 200_000,
        noise: 0.0,
        wavelengths: vec![550.0],
        seed: 3,
    };
    (
        measure(&surface, &s).unwrap(),
        measure(&BsdfSpecimen::new(&model, "roughconductor"), &s).unwrap(),
    )
}

#[test]
fn gaussian_heightfield_of_mirrors_reads_as_roughconductor_at_low_roughness() {
    // Microfacet theory is a statistical model of exactly this surface: at α = 0.2 and
    // incidence up to 45°, where a photon meets one facet and leaves, every reading of the
    // surface agrees with the model's within its photon noise plus 6 % (one realization of the
    // surface holds ~16 000 independent patches, whose slope histogram fluctuates by a few %).
    let (surface, model) = gaussian_mirrors_and_roughconductor(0.2);
    let (es, em) = (surface.stderr.as_ref().unwrap(), model.stderr.as_ref().unwrap());
    let mut worst = 0.0f32;
    for i in 0..2 {
        for o in 0..6 {
            for p in 0..7 {
                let k = surface.index(i, o, p, 0);
                let (a, b) = (surface.values[k], model.values[k]);
                let tol = 4.0 * (es[k] * es[k] + em[k] * em[k]).sqrt() + 0.06 * a.max(b);
                worst = worst.max((a - b).abs() / tol.max(1e-9));
                assert!(
                    (a - b).abs() <= tol,
                    "θi #{i}, θo #{o}, φ #{p}: surface {a} vs roughconductor {b} (tolerance {tol})"
                );
            }
        }
    }
    assert!(worst > 0.0, "the comparison compared something");
    // Where they part: at θi = 75° the lit points of a real, correlated surface are its crests,
    // whose slopes are small, while Smith's model takes a facet's visibility as independent of
    // its slope. The surface's forward lobe is narrower: brighter at the grazing mirror
    // direction (θo = 82.5°, φd = 180°) than the model's by well over its noise.
    let k = surface.index(2, 5, 6, 0);
    let (a, b) = (surface.values[k], model.values[k]);
    assert!(
        a > b * 1.05 && a - b > 4.0 * (es[k] * es[k] + em[k] * em[k]).sqrt(),
        "grazing forward peak: surface {a} vs roughconductor {b}"
    );
}

#[test]
fn gaussian_heightfield_of_mirrors_keeps_the_energy_single_scattering_loses() {
    // A surface of perfect mirrors absorbs nothing: every photon leaves in the end. The
    // single-scattering model of the same surface (Beckmann α = 0.5) loses the photons its
    // masking term rejects (gonio plot microfacet-albedo); at θi = 75° that is 10 %.
    use gonio_core::instruments::microfacet_albedo::white_albedo;
    use gonio_core::microfacet::MicrofacetKind;
    let facet: Arc<dyn Bsdf> = Arc::new(Conductor::mirror());
    let surface = HeightfieldSpecimen::gaussian(256, 0.5, 2, facet, "mirror").unwrap();
    let mut rng = gonio_core::rng::Pcg32::new(5, 1);
    let to_source = spherical_direction(75f32.to_radians(), 0.0);
    let n = 20_000;
    let mut escaped = 0.0;
    for _ in 0..n {
        let mut wl = SampledWavelengths::fixed(550.0);
        if let Some((d, thr)) = surface.scatter(to_source, &mut rng, &mut wl) {
            assert!(d.z > 0.0);
            escaped += thr[0] as f64;
        }
    }
    let surface_albedo = escaped / n as f64;
    let model_albedo = white_albedo(MicrofacetKind::Beckmann, 0.5, 75.0);
    assert!(surface_albedo > 0.999, "mirrors lose nothing: {surface_albedo}");
    assert!(model_albedo < 0.95, "single scattering loses: {model_albedo}");
}

#[test]
fn gaussian_heightfield_of_mirrors_reads_as_multiple_scattering_roughconductor() {
    // The heightfield of mirrors at Beckmann α = 0.5 (one realization, as the α = 0.2
    // comparison), bin by bin against `roughconductor` with multiple scattering (Heitz et al.
    // 2016) and without, same instrument, same tolerance: 4 standard errors plus 6 % for the
    // realization. Measured (seed 3, 200 000 photons): worst |Δ|/tolerance at θi = 15°, 45°,
    // 75°: multiple 0.77, 0.79, 1.07; single 0.96, 2.00, 1.41. Sums of the 42 readings: surface
    // 13.34, 14.76, 17.60; multiple 13.10, 14.75, 18.22; single 12.34 (−7.5 %), 12.87 (−12.8 %),
    // 16.15 (−8.2 %). At 75° the surface's forward lobe is shaped by its crests (see the α = 0.2
    // test: Smith's uncorrelated masking), so there only the energy is compared.
    use gonio_core::bsdfs::RoughConductor;
    use gonio_core::microfacet::{MicrofacetDistribution, MicrofacetKind};
    let alpha = 0.5;
    let facet: Arc<dyn Bsdf> = Arc::new(Conductor::mirror());
    let surface = HeightfieldSpecimen::gaussian(512, alpha, 1, facet, "mirror").unwrap();
    let single = RoughConductor::mirror(MicrofacetDistribution::isotropic(MicrofacetKind::Beckmann, alpha));
    let mut multiple = single.clone();
    multiple.multiple_scattering = true;
    let s = GonioSettings {
        incident: 3,
        outgoing: 6,
        azimuths: 7,
        aperture_deg: 5.0,
        photons: 200_000,
        noise: 0.0,
        wavelengths: vec![550.0],
        seed: 3,
    };
    let t_surface = measure(&surface, &s).unwrap();
    let t_ms = measure(&BsdfSpecimen::new(&multiple, "ms"), &s).unwrap();
    let t_ss = measure(&BsdfSpecimen::new(&single, "ss"), &s).unwrap();
    let (es, em, e1) = (
        t_surface.stderr.as_ref().unwrap(),
        t_ms.stderr.as_ref().unwrap(),
        t_ss.stderr.as_ref().unwrap(),
    );
    for i in 0..3 {
        let (mut worst_ms, mut worst_ss) = (0.0f32, 0.0f32);
        let (mut sum_a, mut sum_ms, mut sum_ss) = (0.0f32, 0.0f32, 0.0f32);
        for o in 0..6 {
            for p in 0..7 {
                let k = t_surface.index(i, o, p, 0);
                let (a, b, c) = (t_surface.values[k], t_ms.values[k], t_ss.values[k]);
                let tol_ms = 4.0 * (es[k] * es[k] + em[k] * em[k]).sqrt() + 0.06 * a.max(b);
                let tol_ss = 4.0 * (es[k] * es[k] + e1[k] * e1[k]).sqrt() + 0.06 * a.max(c);
                worst_ms = worst_ms.max((a - b).abs() / tol_ms.max(1e-9));
                worst_ss = worst_ss.max((a - c).abs() / tol_ss.max(1e-9));
                sum_a += a;
                sum_ms += b;
                sum_ss += c;
            }
        }
        let at = format!(
            "θi = {}°: worst |Δ|/tol multiple {worst_ms:.2}, single {worst_ss:.2}; sums surface {sum_a:.3}, multiple {sum_ms:.3}, single {sum_ss:.3}",
            t_surface.theta_i_deg[i]
        );
        if i < 2 {
            assert!(worst_ms <= 1.0, "multiple scattering off the surface: {at}");
        }
        // Energy: multiple scattering is closer to the surface than single scattering, which
        // lies below it by more than 5 %.
        assert!((sum_ms - sum_a).abs() < (sum_ss - sum_a).abs(), "{at}");
        assert!(sum_ss < 0.95 * sum_a, "{at}");
        if i == 1 {
            assert!(worst_ss > 1.0, "single scattering should visibly miss: {at}");
        }
    }
}

/// A Gaussian heightfield of Lambertian facets (Beckmann slopes, α = 0.5, ρ = 0.8) read by the
/// instrument, against `roughdiffuse` with `model="microfacet"` (Heitz et al. 2016, Beckmann
/// α = 0.5: a random walk on the Smith microsurface of the same slope statistics) and against
/// Oren–Nayar (`roughdiffuse`'s default, σ = α/√2) read by the same instrument.
#[test]
fn gaussian_heightfield_of_lambertian_facets_reads_as_roughdiffuse_microfacet() {
    use gonio_core::bsdfs::roughdiffuse::{RoughDiffuse, RoughDiffuseModel};
    use gonio_core::microfacet::MicrofacetKind;
    let (alpha, rho) = (0.5f32, 0.8f32);
    let facet: Arc<dyn Bsdf> = Arc::new(Diffuse::new(Spectrum::Constant(rho)));
    let surface = HeightfieldSpecimen::gaussian(256, alpha, 4, facet, "diffuse 0.8").unwrap();
    let walk = RoughDiffuse::new(
        Spectrum::Constant(rho),
        alpha,
        RoughDiffuseModel::Microfacet(MicrofacetKind::Beckmann),
    );
    let oren_nayar = RoughDiffuse::new(Spectrum::Constant(rho), alpha, RoughDiffuseModel::OrenNayar);
    let s = GonioSettings {
        incident: 3,
        outgoing: 6,
        azimuths: 7,
        aperture_deg: 5.0,
        photons: 100_000,
        noise: 0.0,
        wavelengths: vec![550.0],
        seed: 11,
    };
    let surface = measure(&surface, &s).unwrap();
    let model = measure(&BsdfSpecimen::new(&walk, "roughdiffuse microfacet"), &s).unwrap();
    let on = measure(&BsdfSpecimen::new(&oren_nayar, "roughdiffuse orennayar"), &s).unwrap();
    let (es, em, eo) = (
        surface.stderr.as_ref().unwrap(),
        model.stderr.as_ref().unwrap(),
        on.stderr.as_ref().unwrap(),
    );
    let (mut worst_model, mut worst_on, mut z_on_max) = (0.0f32, 0.0f32, 0.0f32);
    for i in 0..3 {
        for o in 0..6 {
            for p in 0..7 {
                let k = surface.index(i, o, p, 0);
                let (a, b, c) = (surface.values[k], model.values[k], on.values[k]);
                worst_model = worst_model.max((a - b).abs() / a);
                worst_on = worst_on.max((a - c).abs() / a);
                z_on_max = z_on_max.max((a - c).abs() / (es[k] * es[k] + eo[k] * eo[k]).sqrt());
                if i < 2 {
                    // Photon noise plus 6 % for the one realization of the surface (as for
                    // the mirrors above).
                    let tol = 4.0 * (es[k] * es[k] + em[k] * em[k]).sqrt() + 0.06 * a.max(b);
                    assert!(
                        (a - b).abs() <= tol,
                        "θi #{i}, θo #{o}, φ #{p}: surface {a} vs microfacet model {b} (tolerance {tol})"
                    );
                }
            }
        }
    }
    eprintln!(
        "Lambertian-facet heightfield α = {alpha}, ρ = {rho}: largest relative deviation of the \
         microfacet walk {worst_model:.3}, of Oren–Nayar {worst_on:.3} (max {z_on_max:.1} σ)"
    );
    assert!(
        z_on_max > 4.0,
        "Oren–Nayar is a different surface: max {z_on_max} σ"
    );
}
