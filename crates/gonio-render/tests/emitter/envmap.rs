//! The `envmap` light: orientation (Mitsuba's), texel values and blending, and its sampling
//! densities, plain, MIS-compensated and times the cosine (product sampling), against their pdf
//! functions (χ² tests).

use super::{Rng, chi2_p_value, integrate_sphere};
use glam::{Affine3A, Vec2, Vec3};
use gonio_core::color::luminance;
use gonio_core::{SampledWavelengths, Spectrum};
use gonio_render::emitter::*;
use std::f32::consts::PI;

fn uplift_luminance(c: [f32; 3]) -> Spectrum {
    Spectrum::Constant(luminance(c))
}

/// A 32 × 16 test environment: a smooth gradient plus one very bright pixel.
pub(super) fn test_envmap(to_world: Affine3A) -> EnvMapLight {
    test_envmap_with_spike(to_world, 40.0)
}

/// [`test_envmap`] with the bright pixel's value `spike`.
fn test_envmap_with_spike(to_world: Affine3A, spike: f32) -> EnvMapLight {
    let (w, h) = (32, 16);
    let mut rgb = vec![[0.0f32; 3]; w * h];
    for j in 0..h {
        for i in 0..w {
            let v = 0.2 + 0.8 * (i as f32 / w as f32) * (1.0 - j as f32 / h as f32);
            rgb[j * w + i] = [v, 0.5 * v, 0.25 * v];
        }
    }
    rgb[5 * w + 20] = [spike; 3];
    EnvMapLight::new(w, h, rgb, 2.0, to_world, uplift_luminance).unwrap()
}

/// A reference point whose BSDF transmits (so product sampling never applies): the light's own
/// next-event density, compensated when `mis` (the BSDF is sampled too).
fn at(mis: bool) -> LightRef {
    LightRef {
        p: Vec3::ZERO,
        n: Vec3::Y,
        hemisphere: false,
        mis,
        resolved_density: 0.0,
        resampled: false,
    }
}

/// A surface with shading normal `n` whose BSDF only reflects and is sampled too: where product
/// sampling applies.
fn facing(n: Vec3) -> LightRef {
    LightRef {
        p: Vec3::ZERO,
        n: n.normalize(),
        hemisphere: true,
        mis: true,
        resolved_density: 0.0,
        resampled: false,
    }
}

#[test]
fn envmap_orientation_follows_mitsuba() {
    let e = test_envmap(Affine3A::IDENTITY);
    // Image centre column looks down −z; a quarter to the right is +x; the top row is +y.
    assert!((e.uv_to_dir(Vec2::new(0.5, 0.5)) - Vec3::Z).length() < 1e-5);
    assert!((e.uv_to_dir(Vec2::new(0.0, 0.5)) + Vec3::Z).length() < 1e-5);
    assert!((e.uv_to_dir(Vec2::new(0.25, 0.5)) - Vec3::X).length() < 1e-5);
    assert!((e.uv_to_dir(Vec2::new(0.3, 0.0)) - Vec3::Y).length() < 1e-5);
    let mut rng = Rng(7);
    for _ in 0..1000 {
        let uv = Vec2::new(rng.next_f32(), 0.01 + 0.98 * rng.next_f32());
        let back = e.dir_to_uv(e.uv_to_dir(uv));
        let du = (back.x - uv.x).abs().min(1.0 - (back.x - uv.x).abs());
        assert!(du < 1e-4 && (back.y - uv.y).abs() < 1e-4, "{uv} -> {back}");
    }
    // to_world rotates the map: with a 90° turn about +y the centre column looks down −x.
    let rot = test_envmap(Affine3A::from_rotation_y(PI / 2.0));
    assert!((rot.uv_to_dir(Vec2::new(0.5, 0.5)) - Vec3::X).length() < 1e-5);
    assert!((rot.dir_to_uv(Vec3::X) - Vec2::new(0.5, 0.5)).length() < 1e-4);
}

#[test]
fn envmap_radiance_is_scaled_pixel_value() {
    let e = test_envmap(Affine3A::IDENTITY);
    let wl = SampledWavelengths::sample_visible(0.3);
    // Centre of the bright pixel (column 20, row 5).
    let uv = Vec2::new(20.5 / 32.0, 5.5 / 16.0);
    let le = e.le(e.uv_to_dir(uv), &wl);
    for i in 0..4 {
        assert!((le[i] - 2.0 * 40.0).abs() < 1e-2, "{le:?}");
    }
}

#[test]
fn envmap_pdf_integrates_to_one_and_matches_samples() {
    let e = test_envmap(Affine3A::from_rotation_x(0.4));
    let integral = integrate_sphere(|d| e.pdf_dir(d, &at(false)), 400);
    assert!((integral - 1.0).abs() < 5e-3, "∫pdf = {integral}");
    let mut rng = Rng(11);
    for _ in 0..2000 {
        let (d, pdf) = e.sample_dir(rng.next_2d()).unwrap();
        assert!((d.length() - 1.0).abs() < 1e-4);
        let p2 = e.pdf_dir(d, &at(false));
        assert!((pdf - p2).abs() <= 2e-3 * pdf, "{pdf} vs {p2}");
    }
}

/// The escaped-ray lookup maps a direction to the image once for radiance and density: the
/// same figures as the two separate calls, bit for bit.
#[test]
fn envmap_le_pdf_is_le_and_pdf_dir_bit_for_bit() {
    let e = test_envmap(Affine3A::from_rotation_x(0.4)).with_mis_compensation();
    let mut rng = Rng(5);
    for _ in 0..500 {
        let wl = SampledWavelengths::sample_visible(rng.next_f32());
        let d = gonio_core::warp::square_to_uniform_sphere(rng.next_2d());
        for mis in [false, true] {
            let (le, pdf) = e.le_pdf(d, &wl, &at(mis));
            assert_eq!(
                (le.0, pdf),
                (e.le(d, &wl).0, e.pdf_dir(d, &at(mis))),
                "direction {d}, mis {mis}"
            );
        }
    }
}

/// MIS compensation (Karlík et al. 2019): next-event samples ∝ max(L − L̄, 0)·sin θ where the
/// caller samples the BSDF too (`mis`). On the test gradient (no spike, whose one texel would
/// hold most of the compensated density, beyond the χ² bins' quadrature) its density integrates
/// to one, matches its samples (χ²), is zero on texels dimmer than the mean and larger than the
/// plain one on the brightest; without `mis`, and for emission sampling, the plain density is
/// kept bit for bit.
#[test]
fn envmap_compensated_density_is_normalized_and_matches_its_samples() {
    let plain = test_envmap_with_spike(Affine3A::from_rotation_z(0.3), 0.0);
    let e = test_envmap_with_spike(Affine3A::from_rotation_z(0.3), 0.0).with_mis_compensation();
    let integral = integrate_sphere(|d| e.pdf_dir(d, &at(true)), 400);
    assert!((integral - 1.0).abs() < 5e-3, "∫pdf = {integral}");
    let wl = SampledWavelengths::sample_visible(0.3);
    let sample = |u: Vec2| e.sample_dir_le(u, &wl, &at(true)).map(|s| s.0);
    let p = chi2_p_value(sample, |d| e.pdf_dir(d, &at(true)), 5);
    assert!(p > 0.01, "χ² p-value {p}");
    // Negative control: the compensated samples against the plain density are rejected.
    let p_wrong = chi2_p_value(sample, |d| plain.pdf_dir(d, &at(false)), 5);
    assert!(
        p_wrong < 1e-6,
        "χ² failed to tell the densities apart: p = {p_wrong}"
    );
    // The gradient's mean luminance (≈ 0.24) lies between its dim corner (luminance ≈ 0.12 at
    // column 0, row 15) and its bright one (≈ 0.55 at column 31, row 0).
    let (w, h) = (32.0, 16.0);
    let texel = |i: f32, j: f32| e.uv_to_dir(Vec2::new((i + 0.5) / w, (j + 0.5) / h));
    assert!(e.pdf_dir(texel(31.0, 0.0), &at(true)) > plain.pdf_dir(texel(31.0, 0.0), &at(false)));
    for (i, j) in [(3.0, 2.0), (1.0, 14.0), (12.0, 12.0)] {
        assert_eq!(e.pdf_dir(texel(i, j), &at(true)), 0.0, "texel ({i}, {j})");
    }
    let mut rng = Rng(3);
    for _ in 0..200 {
        let u = rng.next_2d();
        let d = gonio_core::warp::square_to_uniform_sphere(rng.next_2d());
        assert_eq!(e.pdf_dir(d, &at(false)), plain.pdf_dir(d, &at(false)));
        assert_eq!(e.sample_dir(u), plain.sample_dir(u));
        assert_eq!(
            e.sample_dir_le(u, &wl, &at(false)).map(|s| s.0),
            plain.sample_dir(u).map(|s| s.0)
        );
    }
}

/// A map with no texel above its mean (a uniform one) keeps the plain density when compensated.
#[test]
fn envmap_compensation_of_a_uniform_map_is_the_plain_density() {
    let e = EnvMapLight::new(
        8,
        4,
        vec![[0.7; 3]; 32],
        1.0,
        Affine3A::IDENTITY,
        uplift_luminance,
    )
    .unwrap()
    .with_mis_compensation();
    let mut rng = Rng(9);
    for _ in 0..200 {
        let d = gonio_core::warp::square_to_uniform_sphere(rng.next_2d());
        assert_eq!(e.pdf_dir(d, &at(true)), e.pdf_dir(d, &at(false)));
        assert!(e.pdf_dir(d, &at(true)) > 0.0);
    }
}

#[test]
fn envmap_sampling_passes_chi2() {
    let e = test_envmap(Affine3A::from_rotation_z(0.3));
    let p = chi2_p_value(|u| e.sample_dir(u).map(|s| s.0), |d| e.pdf_dir(d, &at(false)), 5);
    assert!(p > 0.01, "χ² p-value {p}");
    // Negative control: the same samples against a density that forgets the 1/sin θ of the
    // lat-long map must be rejected.
    let wrong = |d: Vec3| {
        let uv = e.dir_to_uv(d);
        e.pdf_dir(d, &at(false)) * (PI * uv.y).sin() * 4.0 / PI
    };
    let p_wrong = chi2_p_value(|u| e.sample_dir(u).map(|s| s.0), wrong, 5);
    assert!(p_wrong < 1e-6, "χ² failed to reject a wrong pdf: p = {p_wrong}");
}

/// An environment texel is an area of the sphere: column i covers φ/2π ∈ [i, i + 1]/W and row j
/// covers θ/π ∈ [j, j + 1]/H, its value sits at the centre, and between centres the radiance is
/// the bilinear interpolation of the texels' spectra, so its colour is the bilinear
/// interpolation of the image's colours. `lookup="mitsuba"` reproduces Mitsuba 3.9.1
/// (`envmap.cpp`): row j at θ = π j/(H − 1) (the first and last rows at the poles), and each
/// texel's shape sᵢ = Lᵢ/fᵢ and scale fᵢ = 2 max(rgb) interpolated separately and multiplied, so
/// that midway between a bright red and a dim blue texel the blue shape gets half the weight
/// instead of its share of the radiance.
#[test]
fn envmap_blends_texels_as_radiance_unless_lookup_mitsuba() {
    use gonio_render::texture::uplift_emission_texel;
    let (w, h) = (4, 3);
    let red = [8.0, 0.5, 0.2];
    let blue = [0.05, 0.1, 0.6];
    let mut rgb = vec![[0.5f32; 3]; w * h];
    rgb[..w].fill([2.0; 3]);
    rgb[2 * w..].fill([0.1, 0.2, 0.3]);
    rgb[w] = red;
    rgb[w + 1] = blue;
    let scale = 1.5;
    let env = EnvMapLight::new(w, h, rgb, scale, Affine3A::IDENTITY, uplift_emission_texel).unwrap();
    let mitsuba = env.clone().with_mitsuba_lookup();
    for u in [0.1, 0.5, 0.9] {
        let wl = SampledWavelengths::sample_visible(u);
        let texel = |c: [f32; 3]| uplift_emission_texel(c).sample(&wl) * scale;
        let close = |a: gonio_core::SampledSpectrum, b: gonio_core::SampledSpectrum, what: &str| {
            for i in 0..4 {
                assert!((a[i] / b[i] - 1.0).abs() < 1e-4, "{what}: {a:?} vs {b:?}");
            }
        };
        let at = |e: &EnvMapLight, u: f32, v: f32| e.le(e.uv_to_dir(Vec2::new(u, v)), &wl);
        // Texel centres: (j + ½)/H here, j/(H − 1) in Mitsuba's layout (rows at the poles).
        close(at(&env, 2.5 / 4.0, 0.5 / 3.0), texel([2.0; 3]), "first row");
        close(at(&env, 2.5 / 4.0, 2.5 / 3.0), texel([0.1, 0.2, 0.3]), "last row");
        close(mitsuba.le(Vec3::Y, &wl), texel([2.0; 3]), "Mitsuba's north pole");
        close(
            mitsuba.le(-Vec3::Y, &wl),
            texel([0.1, 0.2, 0.3]),
            "Mitsuba's south pole",
        );
        close(
            at(&mitsuba, 2.5 / 4.0, 0.25),
            (texel([2.0; 3]) + texel([0.5; 3])) * 0.5,
            "Mitsuba between rows",
        );
        for e in [&env, &mitsuba] {
            close(at(e, 0.5 / 4.0, 0.5), texel(red), "red texel");
            close(at(e, 1.5 / 4.0, 0.5), texel(blue), "blue texel");
        }
        // Midway between the red and the blue texel.
        close(
            at(&env, 1.0 / 4.0, 0.5),
            (texel(red) + texel(blue)) * 0.5,
            "radiance blend",
        );
        let (f_red, f_blue) = (2.0 * 8.0, 2.0 * 0.6);
        let shapes = (texel(red) / f_red + texel(blue) / f_blue) * 0.5;
        close(
            at(&mitsuba, 1.0 / 4.0, 0.5),
            shapes * (0.5 * (f_red + f_blue)),
            "Mitsuba's blend",
        );
    }
    // The two blends differ: Mitsuba's is bluer midway.
    let wl = SampledWavelengths::sample_visible(0.2);
    let mid = env.uv_to_dir(Vec2::new(1.0 / 4.0, 0.5));
    let (a, b) = (env.le(mid, &wl), mitsuba.le(mid, &wl));
    assert!((0..4).any(|i| (a[i] / b[i] - 1.0).abs() > 0.05), "{a:?} vs {b:?}");
}

/// A `w × h` map: a smooth gradient, a bright 2 × 2 patch and a dim band; sizes that are not
/// multiples of the product tables' tiles exercise their partial tiles.
fn gradient_map(w: usize, h: usize, to_world: Affine3A) -> EnvMapLight {
    let mut rgb = vec![[0.0f32; 3]; w * h];
    for j in 0..h {
        for i in 0..w {
            let v = 0.1 + 0.9 * (i as f32 / w as f32) * (1.0 - j as f32 / h as f32);
            rgb[j * w + i] = if (h / 2..h / 2 + 2).contains(&j) {
                [0.02; 3]
            } else {
                [v, 0.6 * v, 0.3 * v]
            };
        }
    }
    for (i, j) in [
        (w / 3, h / 4),
        (w / 3 + 1, h / 4),
        (w / 3, h / 4 + 1),
        (w / 3 + 1, h / 4 + 1),
    ] {
        rgb[j * w + i] = [30.0, 25.0, 20.0];
    }
    EnvMapLight::new(w, h, rgb, 1.5, to_world, uplift_luminance).unwrap()
}

/// Product sampling (`product_sampling`, `emitter/envmap_product.rs`): at a reflecting surface
/// whose BSDF is sampled too, next-event directions follow the map's tile weights, compensated
/// by half the hemisphere's mean, × the clamped cosine at the centre of the normal's cell. For
/// normals up, tilted, sideways and down (the map turned by `to_world`), on a map of one texel
/// per tile and one of 3 × 3 texels with partial tiles, its density integrates to one and
/// matches its samples (χ²), is zero well below the surface's horizon (a cell reaches ≤ 7.6°
/// from its centre, a tile ≤ 8°), and each sample returns the map's radiance and the density
/// `pdf_dir` gives it.
/// Negative control: the samples against the light's own density (plain: positive wherever the
/// map is lit, so the χ² can judge every bin) are rejected.
/// Where it does not apply (a transmitting BSDF, or no BSDF samples) the light's own densities
/// are kept bit for bit.
#[test]
fn envmap_product_density_is_normalized_follows_the_cosine_and_matches_its_samples() {
    let rot = Affine3A::from_rotation_z(0.3);
    let wl = SampledWavelengths::sample_visible(0.3);
    let maps = [
        (test_envmap(rot), "32 × 16"),
        (gradient_map(150, 70, Affine3A::from_rotation_x(-0.5)), "150 × 70"),
    ];
    let normals = [
        Vec3::Y,
        Vec3::new(0.3, 0.9, 0.2),
        Vec3::X,
        Vec3::new(0.1, -1.0, 0.4),
        Vec3::new(-0.5, 0.1, -0.8),
    ];
    let mut rng = Rng(17);
    for (map, name) in maps {
        let own = map.clone().with_mis_compensation();
        let e = own.clone().with_product_sampling();
        for n in normals {
            let r = facing(n);
            let integral = integrate_sphere(|d| e.pdf_dir(d, &r), 400);
            assert!(
                (integral - 1.0).abs() < 5e-3,
                "{name}, n = {n}: ∫pdf = {integral}"
            );
            // A sample on a texel's edge may map back into its neighbour (f32 round trip through
            // the direction), which may be a tile of zero density: counted and left out of the
            // χ² (whose bins of zero density must stay empty), rare, never systematic.
            let edge = std::cell::Cell::new(0);
            let sample = |u: Vec2| {
                let d = e.sample_dir_le(u, &wl, &r)?.0;
                if e.pdf_dir(d, &r) == 0.0 {
                    edge.set(edge.get() + 1);
                    return None;
                }
                Some(d)
            };
            let p = chi2_p_value(sample, |d| e.pdf_dir(d, &r), 5);
            assert!(p > 0.01, "{name}, n = {n}: χ² p-value {p}");
            assert!(
                edge.get() <= 5,
                "{name}, n = {n}: {} of 400 000 samples where pdf_dir is 0",
                edge.get()
            );
            let mut elsewhere = 0;
            for _ in 0..2000 {
                let (d, pdf, le) = e.sample_dir_le(rng.next_2d(), &wl, &r).expect("a lit hemisphere");
                assert!(
                    d.dot(r.n) > -0.3,
                    "{name}, n = {n}: sampled {d} below the horizon"
                );
                let p2 = e.pdf_dir(d, &r);
                if (pdf - p2).abs() > 2e-3 * pdf {
                    elsewhere += 1;
                }
                let l2 = e.le(d, &wl);
                assert!(
                    (le[0] - l2[0]).abs() <= 1e-3 * l2[0].max(1e-3),
                    "{name}: {le:?} vs {l2:?}"
                );
                let below = gonio_core::warp::square_to_uniform_sphere(rng.next_2d());
                if below.dot(r.n) < -0.3 {
                    assert_eq!(e.pdf_dir(below, &r), 0.0, "{name}, n = {n}: {below}");
                }
            }
            assert!(
                elsewhere <= 10,
                "{name}, n = {n}: {elsewhere} of 2000 sample pdfs differ from pdf_dir"
            );
        }
        let r = facing(Vec3::X);
        let p_wrong = chi2_p_value(
            |u| e.sample_dir_le(u, &wl, &r).map(|s| s.0),
            |d| own.pdf_dir(d, &at(false)),
            5,
        );
        assert!(
            p_wrong < 1e-6,
            "{name}: χ² failed to tell the densities apart: p = {p_wrong}"
        );
        for _ in 0..200 {
            let u = rng.next_2d();
            let d = gonio_core::warp::square_to_uniform_sphere(rng.next_2d());
            let transmitting = LightRef {
                hemisphere: false,
                ..r
            };
            let no_bsdf_samples = LightRef { mis: false, ..r };
            for (mine, theirs) in [(transmitting, at(true)), (no_bsdf_samples, at(false))] {
                assert_eq!(e.pdf_dir(d, &mine), own.pdf_dir(d, &theirs));
                assert_eq!(
                    e.sample_dir_le(u, &wl, &mine).map(|s| s.0),
                    own.sample_dir_le(u, &wl, &theirs).map(|s| s.0)
                );
            }
        }
    }
}

/// `feature_density` is the map's largest luminance density per steradian: a uniform map's is
/// 1/4π (a constant light's too), and one bright texel raises it by its share of the light over
/// its solid angle. Lights are left to BSDF sampling only from a surface whose lobe resolves
/// them (`LightRef::resolved_density` at least their feature density), never from one without
/// such a lobe, and never the lights that are not at infinity.
#[test]
fn narrow_lobes_leave_only_smooth_lights_at_infinity_to_bsdf_sampling() {
    let uniform = EnvMapLight::new(
        32,
        16,
        vec![[0.7; 3]; 32 * 16],
        1.0,
        Affine3A::IDENTITY,
        uplift_luminance,
    )
    .unwrap();
    // Rows sample sin θ at their centres: the discrete ∫L dω differs from 4πL by < 0.2 %.
    let quarter_pi = 0.25 / PI;
    assert!(
        (uniform.feature_density() / quarter_pi - 1.0).abs() < 2e-3,
        "{}",
        uniform.feature_density()
    );
    let constant = Light::Constant(ConstantLight {
        radiance: Spectrum::Constant(1.0),
    });
    assert_eq!(constant.feature_density(), quarter_pi);
    // A sun: one texel of a 256 × 128 map (row 40, about 3·10⁻⁴ sr) at 10⁵ × the rest holds
    // most of the light.
    let (w, h, row) = (256usize, 128usize, 40usize);
    let mut rgb = vec![[0.01f32; 3]; w * h];
    rgb[row * w + 20] = [1000.0; 3];
    let sun = EnvMapLight::new(w, h, rgb, 1.0, Affine3A::IDENTITY, uplift_luminance).unwrap();
    let texel =
        (std::f32::consts::TAU / w as f32) * (PI / h as f32) * (PI * (row as f32 + 0.5) / h as f32).sin();
    let share = 1000.0 * texel / (1000.0 * texel + 0.01 * 4.0 * PI);
    assert!(
        (sun.feature_density() * texel / share - 1.0).abs() < 0.01,
        "{} against {}",
        sun.feature_density(),
        share / texel
    );
    let bounds = BoundingSphere {
        center: Vec3::ZERO,
        radius: 10.0,
    };
    let lights = Lights::new(
        vec![
            Light::EnvMap(uniform),
            Light::EnvMap(sun),
            constant,
            Light::Point(PointLight {
                position: Vec3::Y,
                intensity: Spectrum::Constant(1.0),
            }),
        ],
        0,
        10.0,
        bounds,
    );
    let from = |resolved_density: f32| LightRef {
        resolved_density,
        ..facing(Vec3::Y)
    };
    // Beckmann rough glass at α = 0.02 resolves densities up to 0.05/(4π α²) ≈ 9.9 per sr.
    let narrow = from(
        gonio_core::microfacet::MicrofacetDistribution::isotropic(
            gonio_core::microfacet::MicrofacetKind::Beckmann,
            0.02,
        )
        .resolved_light_density(),
    );
    assert!((narrow.resolved_density - 0.05 / (4.0 * PI * 4e-4)).abs() < 1e-3);
    let left: Vec<bool> = (0..4).map(|i| lights.left_to_bsdf(&narrow, i)).collect();
    assert_eq!(left, [true, false, true, false]);
    for i in 0..4 {
        assert!(
            !lights.left_to_bsdf(&from(0.0), i),
            "no narrow lobe: light {i} keeps its samples"
        );
        if left[i] {
            assert_eq!(
                lights.pmf_at(&narrow, i),
                0.0,
                "light {i} is never sampled from there"
            );
        } else {
            assert_eq!(lights.pmf_at(&narrow, i), lights.pmf_at(&from(0.0), i));
        }
    }
    // Just below and at the uniform map's density.
    let f = lights.lights()[0].feature_density();
    assert!(!lights.left_to_bsdf(&from(f * 0.999), 0));
    assert!(lights.left_to_bsdf(&from(f), 0));
    // A pick of a light left to BSDF sampling draws no sample; the others' are unchanged.
    let wl = SampledWavelengths::sample_visible(0.3);
    for k in 0..64 {
        let u_sel = (k as f32 + 0.5) / 64.0;
        let drawn = lights.sample_li_indexed(&[], &narrow, u_sel, Vec2::new(0.3, 0.6), &wl);
        let plain = lights.sample_li_indexed(&[], &from(0.0), u_sel, Vec2::new(0.3, 0.6), &wl);
        match (drawn, plain) {
            (Some((i, a)), Some((j, b))) => {
                assert_eq!(i, j);
                assert!(!left[i]);
                assert_eq!(a.pdf, b.pdf);
            }
            (None, Some((j, _))) => assert!(left[j], "light {j} lost its sample"),
            (Some((i, _)), None) => panic!("light {i} sampled only from the narrow lobe"),
            (None, None) => {}
        }
    }
}
