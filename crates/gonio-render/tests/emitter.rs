//! Emitters: sampling densities against their pdf functions (χ² tests; the environment map's in
//! `emitter/envmap.rs`), radiance values, power values, light selection and the MIS heuristic.

use glam::{Affine3A, Vec2, Vec3};
use gonio_core::{SampledWavelengths, Spectrum};
use gonio_render::emitter::*;
use gonio_render::integrator::mis_power;
use std::f32::consts::PI;

/// A small deterministic generator (SplitMix64) so these tests depend on nothing else.
struct Rng(u64);
impl Rng {
    fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32
    }
    fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_f32(), self.next_f32())
    }
}

/// ∫ over the sphere of a direction density, by a midpoint rule on (cos θ, φ) (dω = d cos θ dφ).
fn integrate_sphere(pdf: impl Fn(Vec3) -> f32, n: usize) -> f64 {
    let mut s = 0.0f64;
    for a in 0..n {
        let z = -1.0 + 2.0 * (a as f32 + 0.5) / n as f32;
        let r = (1.0 - z * z).max(0.0).sqrt();
        for b in 0..2 * n {
            let phi = 2.0 * PI * (b as f32 + 0.5) / (2 * n) as f32;
            s += pdf(Vec3::new(r * phi.cos(), r * phi.sin(), z)) as f64;
        }
    }
    s * (2.0 / n as f64) * (2.0 * std::f64::consts::PI / (2 * n) as f64)
}

/// Pearson χ² of sampled directions binned in (φ, cos θ) against the pdf integrated per bin,
/// pooling bins with fewer than 5 expected samples; p-value from the χ² survival function.
fn chi2_p_value(sample: impl Fn(Vec2) -> Option<Vec3>, pdf: impl Fn(Vec3) -> f32, seed: u64) -> f64 {
    let (nphi, nz, n) = (48usize, 24usize, 400_000usize);
    let mut obs = vec![0.0f64; nphi * nz];
    let mut rng = Rng(seed);
    let bin = |d: Vec3| {
        let mut phi = d.y.atan2(d.x) / (2.0 * PI);
        phi -= phi.floor();
        let i = ((phi * nphi as f32) as usize).min(nphi - 1);
        let j = (((d.z + 1.0) * 0.5 * nz as f32) as usize).min(nz - 1);
        j * nphi + i
    };
    for _ in 0..n {
        if let Some(d) = sample(rng.next_2d()) {
            obs[bin(d)] += 1.0;
        }
    }
    // Expected counts: 16 × 16 midpoint rule inside each bin (texel edges cross the bins: a
    // coarser rule misjudges the compensated density's steps, which are steeper than the plain),
    // 128 × 128 where that finds nothing but samples landed (a sliver of a lit texel in a bin
    // of an otherwise zero density: the product density's edges).
    let bin_integral = |i: usize, j: usize, sub: usize| {
        let mut acc = 0.0f64;
        for b in 0..sub {
            let z = -1.0 + 2.0 * (j as f32 + (b as f32 + 0.5) / sub as f32) / nz as f32;
            let r = (1.0 - z * z).max(0.0).sqrt();
            for a in 0..sub {
                let phi = 2.0 * PI * (i as f32 + (a as f32 + 0.5) / sub as f32) / nphi as f32;
                acc += pdf(Vec3::new(r * phi.cos(), r * phi.sin(), z)) as f64;
            }
        }
        let area = (2.0 / nz as f64) * (2.0 * std::f64::consts::PI / nphi as f64);
        acc / (sub * sub) as f64 * area * n as f64
    };
    let mut exp = vec![0.0f64; nphi * nz];
    for j in 0..nz {
        for i in 0..nphi {
            let k = j * nphi + i;
            exp[k] = bin_integral(i, j, 16);
            if exp[k] == 0.0 && obs[k] > 0.0 {
                exp[k] = bin_integral(i, j, 128);
            }
        }
    }
    let mut cells: Vec<(f64, f64)> = exp.iter().copied().zip(obs.iter().copied()).collect();
    cells.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    // Bins where even the fine rule finds no density hold at most a sliver of a lit texel
    // thinner than 1/128 of a bin: a few samples may land there, counted in the bin of least
    // expectation (whose χ² they raise); more than 1 in 10⁴ is a density that misses its samples.
    let stray: f64 = cells.iter().filter(|c| c.0 == 0.0).map(|c| c.1).sum();
    assert!(stray <= 1e-4 * n as f64, "{stray} samples where the pdf is zero");
    if let Some(least) = cells.iter_mut().find(|c| c.0 > 0.0) {
        least.1 += stray;
    }
    let (mut chi2, mut dof, mut pool_e, mut pool_o) = (0.0f64, 0i64, 0.0f64, 0.0f64);
    for (e, o) in cells {
        if e == 0.0 {
            continue;
        }
        if e < 5.0 || pool_e > 0.0 && pool_e < 5.0 {
            pool_e += e;
            pool_o += o;
            if pool_e >= 5.0 {
                chi2 += (pool_o - pool_e).powi(2) / pool_e;
                dof += 1;
                pool_e = 0.0;
                pool_o = 0.0;
            }
            continue;
        }
        chi2 += (o - e).powi(2) / e;
        dof += 1;
    }
    dof -= 1;
    assert!(dof > 0);
    // Core's survival function: `puruspe::gammq` returns NaN for a ≥ 100 and x < a − 1, which
    // is exactly a good fit with many bins (the test would then fail on a correct sampler).
    gonio_core::check::chi2::chi2_sf(dof as f64, chi2)
}

#[test]
fn constant_light_sampling_matches_pdf() {
    let c = ConstantLight {
        radiance: Spectrum::Constant(0.7),
    };
    let n = Vec3::new(0.3, -0.5, 0.8).normalize();
    for hemisphere in [false, true] {
        let r = LightRef {
            p: Vec3::ZERO,
            n,
            hemisphere,
            mis: false,
            resolved_density: 0.0,
            resampled: false,
        };
        let integral = integrate_sphere(|d| c.pdf_dir(&r, d), 300);
        assert!(
            (integral - 1.0).abs() < 2e-3,
            "hemisphere {hemisphere}: ∫pdf = {integral}"
        );
        let p = chi2_p_value(|u| Some(c.sample_dir(&r, u).0), |d| c.pdf_dir(&r, d), 9);
        assert!(p > 0.01, "hemisphere {hemisphere}: χ² p-value {p}");
        let mut rng = Rng(3);
        for _ in 0..500 {
            let (d, pdf) = c.sample_dir(&r, rng.next_2d());
            assert!((pdf - c.pdf_dir(&r, d)).abs() < 1e-4 * pdf.max(1.0));
            if hemisphere {
                assert!(d.dot(n) >= -1e-6);
            }
        }
    }
    let wl = SampledWavelengths::sample_visible(0.5);
    let light = Light::Constant(c);
    let r = LightRef {
        p: Vec3::ONE,
        n: Vec3::Y,
        hemisphere: true,
        mis: false,
        resolved_density: 0.0,
        resampled: false,
    };
    let s = light.sample_li_nonarea(&r, Vec2::new(0.2, 0.7), &wl).unwrap();
    assert_eq!(s.li[0], 0.7);
    assert!(s.dist.is_infinite() && !s.delta);
    assert!((s.pdf - light.pdf_li_infinite(&r, s.wi)).abs() < 1e-5);
}

#[test]
fn point_light_irradiance_and_power() {
    let light = Light::Point(PointLight {
        position: Vec3::new(0.0, 3.0, 4.0),
        intensity: Spectrum::Constant(10.0),
    });
    let wl = SampledWavelengths::sample_visible(0.1);
    let r = LightRef {
        p: Vec3::ZERO,
        n: Vec3::Y,
        hemisphere: true,
        mis: false,
        resolved_density: 0.0,
        resampled: false,
    };
    let s = light.sample_li_nonarea(&r, Vec2::ZERO, &wl).unwrap();
    assert!((s.dist - 5.0).abs() < 1e-5);
    assert!((s.wi - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6);
    assert!((s.li[2] - 10.0 / 25.0).abs() < 1e-6);
    assert!(s.delta && s.pdf == 1.0);
    let bounds = BoundingSphere {
        center: Vec3::ZERO,
        radius: 5.0,
    };
    assert!((light.power(0.0, &bounds) - 40.0 * PI).abs() < 1e-3);
}

#[test]
fn directional_light_irradiance_and_power() {
    let light = Light::Directional(DirectionalLight {
        direction: Vec3::new(0.0, -1.0, 0.0),
        irradiance: Spectrum::Constant(2.0),
    });
    let wl = SampledWavelengths::sample_visible(0.1);
    let r = LightRef {
        p: Vec3::ZERO,
        n: Vec3::Y,
        hemisphere: true,
        mis: false,
        resolved_density: 0.0,
        resampled: false,
    };
    let s = light.sample_li_nonarea(&r, Vec2::ZERO, &wl).unwrap();
    assert_eq!(s.wi, Vec3::Y);
    assert_eq!(s.li[0], 2.0);
    assert!(s.dist.is_infinite() && s.delta);
    let bounds = BoundingSphere {
        center: Vec3::ZERO,
        radius: 3.0,
    };
    assert!((light.power(0.0, &bounds) - 2.0 * PI * 9.0).abs() < 1e-3);
}

#[test]
fn spot_light_falloff_and_power() {
    // Pointing down −y from (0, 2, 0): local +z maps to world −y.
    let to_world = Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)) * Affine3A::from_rotation_x(PI / 2.0);
    let spot = SpotLight::new(to_world, Spectrum::Constant(5.0), 20.0, 10.0);
    let at = |deg: f32| {
        let t = deg.to_radians();
        spot.falloff(Vec3::new(t.sin(), -t.cos(), 0.0))
    };
    assert_eq!(at(0.0), 1.0);
    assert_eq!(at(9.9), 1.0);
    assert!((at(15.0) - 0.5).abs() < 1e-3, "{}", at(15.0));
    assert!((at(17.5) - 0.25).abs() < 1e-3);
    assert_eq!(at(20.5), 0.0);
    assert_eq!(spot.falloff(Vec3::Y), 0.0);
    // Power = I ∫ falloff dω, checked by quadrature over the sphere.
    let numeric = 5.0 * integrate_sphere(|d| spot.falloff(d), 1200);
    assert!(
        (spot.power() as f64 - numeric).abs() < 2e-3 * numeric,
        "{} vs {numeric}",
        spot.power()
    );
    // Irradiance from below the light, 2 units away on the axis: I/d².
    let wl = SampledWavelengths::sample_visible(0.6);
    let light = Light::Spot(spot);
    let r = LightRef {
        p: Vec3::ZERO,
        n: Vec3::Y,
        hemisphere: true,
        mis: false,
        resolved_density: 0.0,
        resampled: false,
    };
    let s = light.sample_li_nonarea(&r, Vec2::ZERO, &wl).unwrap();
    assert!((s.li[1] - 5.0 / 4.0).abs() < 1e-5 && (s.wi - Vec3::Y).length() < 1e-6);
    // Outside the cone there is nothing to sample.
    let off = LightRef {
        p: Vec3::new(3.0, 0.0, 0.0),
        n: Vec3::Y,
        hemisphere: true,
        mis: false,
        resolved_density: 0.0,
        resampled: false,
    };
    assert!(light.sample_li_nonarea(&off, Vec2::ZERO, &wl).is_none());
}

#[test]
fn selection_is_proportional_to_power() {
    let bounds = BoundingSphere {
        center: Vec3::ZERO,
        radius: 10.0,
    };
    let lights = vec![
        Light::Point(PointLight {
            position: Vec3::ZERO,
            intensity: Spectrum::Constant(1.0),
        }),
        Light::Point(PointLight {
            position: Vec3::X,
            intensity: Spectrum::Constant(3.0),
        }),
        Light::Point(PointLight {
            position: Vec3::Y,
            intensity: Spectrum::Constant(0.0),
        }),
        Light::Constant(ConstantLight {
            radiance: Spectrum::Constant(1.0),
        }),
    ];
    // Scene area 8/π: the constant light's power estimate is π·1·(½·8/π) = 4 = 4π/π.
    let area = 8.0 / PI;
    let set = Lights::new(lights, 0, area, bounds);
    let powers = [4.0 * PI, 12.0 * PI, 0.0, 4.0];
    let total: f32 = powers.iter().sum();
    for (i, p) in powers.iter().enumerate() {
        assert!(
            (set.pmf(i) - p / total).abs() < 1e-5,
            "light {i}: {} vs {}",
            set.pmf(i),
            p / total
        );
    }
    let mut counts = [0usize; 4];
    let n = 100_000;
    for k in 0..n {
        let (i, p) = set.select((k as f32 + 0.5) / n as f32).unwrap();
        assert_eq!(p, set.pmf(i));
        counts[i] += 1;
    }
    assert_eq!(counts[2], 0, "a light without power is never chosen");
    assert_eq!(set.infinite(), &[3]);
    // No lights: nothing to select.
    assert!(Lights::new(vec![], 0, 1.0, bounds).select(0.5).is_none());
}

#[test]
fn power_heuristic_values() {
    assert_eq!(mis_power(1.0, 0.0, 2.0), 1.0);
    assert_eq!(mis_power(0.0, 1.0, 2.0), 0.0);
    assert!((mis_power(1.0, 1.0, 2.0) - 0.5).abs() < 1e-7);
    assert!((mis_power(3.0, 1.0, 2.0) - 0.9).abs() < 1e-6);
    assert!((mis_power(2.0, 5.0, 2.0) + mis_power(5.0, 2.0, 2.0) - 1.0).abs() < 1e-6);
}

/// The power heuristic with any exponent β: aᵝ/(aᵝ + bᵝ), the two weights of a pair summing to
/// one (so next-event estimation and BSDF sampling stay unbiased together), the balance
/// heuristic at β = 1, and the limits where one density vanishes or
/// overflows.
#[test]
fn power_heuristic_with_any_exponent() {
    let densities = [0.0, 1e-30, 1e-6, 0.3, 1.0, 2.5, 7e3, 1e30, f32::INFINITY];
    for beta in [1.0, 1.25, 1.5, 2.0, 3.0, 16.0] {
        for a in densities {
            for b in densities {
                let (wa, wb) = (mis_power(a, b, beta), mis_power(b, a, beta));
                assert!((0.0..=1.0).contains(&wa), "β {beta}, ({a}, {b}): {wa}");
                if a.is_finite() && b.is_finite() && a + b > 0.0 {
                    assert!((wa + wb - 1.0).abs() < 1e-5, "β {beta}, ({a}, {b}): {wa} + {wb}");
                }
            }
        }
        assert_eq!(mis_power(1.0, 0.0, beta), 1.0);
        assert_eq!(mis_power(0.0, 1.0, beta), 0.0);
        assert!((mis_power(1.0, 1.0, beta) - 0.5).abs() < 1e-7);
    }
    assert!((mis_power(3.0, 1.0, 1.0) - 0.75).abs() < 1e-7);
    assert!((mis_power(3.0, 1.0, 1.25) - 3f32.powf(1.25) / (3f32.powf(1.25) + 1.0)).abs() < 1e-6);
}

#[test]
fn selection_by_position_is_a_consistent_distribution() {
    let bounds = BoundingSphere {
        center: Vec3::ZERO,
        radius: 10.0,
    };
    let lights = vec![
        Light::Point(PointLight {
            position: Vec3::new(0.0, 1.0, 0.0),
            intensity: Spectrum::Constant(1.0),
        }),
        Light::Point(PointLight {
            position: Vec3::new(5.0, 1.0, 0.0),
            intensity: Spectrum::Constant(1.0),
        }),
        Light::Directional(DirectionalLight {
            direction: Vec3::NEG_Y,
            irradiance: Spectrum::Constant(0.5),
        }),
        Light::Constant(ConstantLight {
            radiance: Spectrum::Constant(0.2),
        }),
    ];
    let set = Lights::new(lights, 0, 100.0, bounds);
    for (p, n) in [
        (Vec3::ZERO, Vec3::Y),
        (Vec3::new(5.0, 0.0, 0.0), Vec3::Y),
        (Vec3::ZERO, Vec3::NEG_Y),
    ] {
        let r = LightRef {
            p,
            n,
            hemisphere: true,
            mis: false,
            resolved_density: 0.0,
            resampled: false,
        };
        let pmf: Vec<f32> = (0..4).map(|i| set.pmf_at(&r, i)).collect();
        assert!((pmf.iter().sum::<f32>() - 1.0).abs() < 1e-5, "{pmf:?}");
        // Every light with power keeps at least the 10 % defensive share of its global probability.
        for (i, &q) in pmf.iter().enumerate() {
            assert!(q >= 0.1 * set.pmf(i) - 1e-6);
        }
        let n_draws = 20_000;
        let mut counts = [0usize; 4];
        for k in 0..n_draws {
            let (i, q) = set.select_at(&r, (k as f32 + 0.5) / n_draws as f32).unwrap();
            assert!((q - pmf[i]).abs() < 1e-6);
            counts[i] += 1;
        }
        for i in 0..4 {
            assert!(
                (counts[i] as f32 / n_draws as f32 - pmf[i]).abs() < 1e-3,
                "light {i}: {counts:?} vs {pmf:?}"
            );
        }
    }
    // The nearer light dominates at its foot; facing down, the lights above get only the
    // defensive share.
    let below_first = LightRef {
        p: Vec3::ZERO,
        n: Vec3::Y,
        hemisphere: true,
        mis: false,
        resolved_density: 0.0,
        resampled: false,
    };
    assert!(set.pmf_at(&below_first, 0) > 5.0 * set.pmf_at(&below_first, 1));
    let facing_down = LightRef {
        p: Vec3::ZERO,
        n: Vec3::NEG_Y,
        hemisphere: true,
        mis: false,
        resolved_density: 0.0,
        resampled: false,
    };
    assert!((set.pmf_at(&facing_down, 0) - 0.1 * set.pmf(0)).abs() < 1e-6);
}

/// Light sampling behind `Lights`: for every light kind in a scene, a light sample from a
/// reference point, followed as a ray, finds the light with the density `pdf_li_hit` (area) or
/// `le_escaped` (infinite) reports, selection included — the agreement MIS relies on —
/// for a sphere, a rectangle sampled by spherical rectangle (near) and by area (far).
#[test]
fn light_samples_and_their_densities_agree_for_every_light_kind() {
    use gonio_render::accel::Intersect;
    use gonio_render::geometry::Ray;
    use gonio_render::render::PreparedScene;
    let xml = r#"<scene version="3.0.0">
        <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
        <shape type="sphere"><point name="center" value="0, 3, 0"/><float name="radius" value="0.5"/>
            <emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="2"/><rotate x="1" angle="90"/><translate y="2" x="3"/></transform>
            <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="0.2"/><rotate x="1" angle="90"/><translate y="9" x="-4" z="6"/></transform>
            <emitter type="area"><rgb name="radiance" value="40"/></emitter></shape>
        <emitter type="constant"><rgb name="radiance" value="0.3"/></emitter>
        <emitter type="point"><point name="position" value="1, 4, 1"/><rgb name="intensity" value="3"/></emitter>
    </scene>"#;
    let scene = gonio_render::xml::load_scene_str(xml, ".", &[]).expect("scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let (lights, accel) = (prepared.lights(), prepared.accel());
    let shapes = accel.shapes();
    let wl = SampledWavelengths::sample_visible(0.4);
    let mut rng = Rng(17);
    let mut seen = [0usize; 5];
    for k in 0..4000 {
        let r = LightRef {
            p: Vec3::new(0.5 * (k % 7) as f32 - 1.5, 0.0, 0.3 * (k % 5) as f32 - 0.6),
            n: Vec3::Y,
            hemisphere: true,
            mis: false,
            resolved_density: 0.0,
            resampled: false,
        };
        let Some((_, ls)) = lights.sample_li_indexed(shapes, &r, rng.next_f32(), rng.next_2d(), &wl) else {
            continue;
        };
        assert!(ls.pdf > 0.0 && ls.pdf.is_finite());
        if ls.delta {
            seen[4] += 1;
            continue;
        }
        let ray = Ray::new(r.p, ls.wi);
        let hit = accel.intersect(&ray);
        if ls.dist.is_finite() {
            // An area light: the ray finds the sampled point (unless another light is in front).
            let hit = hit.expect("the ray finds the sampled point");
            if (hit.t / ls.dist - 1.0).abs() > 1e-3 {
                continue;
            }
            let li = lights.shape_light(hit.shape as usize).expect("an emitter");
            seen[li] += 1;
            let pdf = lights.pdf_li_hit(shapes, &r, li, &hit);
            assert!(
                (pdf / ls.pdf - 1.0).abs() < 2e-3,
                "light {li}: sampled {} vs {pdf}",
                ls.pdf
            );
        } else if hit.is_none() {
            seen[3] += 1;
            let i = lights.infinite()[0] as usize;
            let (le, pdf) = lights.le_escaped(Some(&r), i, ls.wi, &wl);
            assert_eq!(le.0, ls.li.0, "the radiance the sample carries");
            assert!(
                (pdf / ls.pdf - 1.0).abs() < 1e-4,
                "environment: sampled {} vs {pdf}",
                ls.pdf
            );
        }
    }
    assert!(seen.iter().all(|&n| n > 20), "every light sampled: {seen:?}");
}

/// Mitsuba's `spot` `texture`: looked up at uv = ½ + ½·(x, y)/(z·tan γ) of the local direction,
/// so the texture's square spans the cutoff's tangent plane.
#[test]
fn spot_light_projects_its_texture_over_the_cone() {
    use gonio_render::texture::Texture;
    // A checkerboard (no to_uv) is 0.25 for u < ½ and 1 for u > ½ along v = ½.
    let texture = Texture::Checkerboard {
        color0: Box::new(Texture::constant(0.25)),
        color1: Box::new(Texture::constant(1.0)),
        to_uv: glam::Affine2::IDENTITY,
        float_cells_swapped: false,
    };
    let spot =
        SpotLight::new(Affine3A::IDENTITY, Spectrum::Constant(2.0), 30.0, 30.0).with_texture(Some(texture));
    let tan = 30f32.to_radians().tan();
    // The cutoff's edge along ±x maps to u = 1 and u = 0, the axis to the centre.
    let uv = spot.texture_uv(Vec3::new(tan, 0.0, 1.0));
    assert!((uv - Vec2::new(1.0, 0.5)).length() < 1e-6, "{uv:?}");
    let uv = spot.texture_uv(Vec3::new(-0.5 * tan, 0.25 * tan, 1.0));
    assert!((uv - Vec2::new(0.25, 0.625)).length() < 1e-6, "{uv:?}");
    let wl = SampledWavelengths::sample_visible(0.3);
    let i = |d: Vec3| spot.intensity_towards(d.normalize(), &wl)[0];
    assert!((i(Vec3::new(-0.3, 0.0, 1.0)) - 0.5).abs() < 1e-6);
    assert!((i(Vec3::new(0.3, 0.0, 1.0)) - 2.0).abs() < 1e-6);
    // Outside the cone: nothing, whatever the texture.
    assert_eq!(i(Vec3::new(1.0, 0.0, 1.0)), 0.0);
}

/// Mitsuba's `projector`: a constant texture projected on a plane facing it gives a constant
/// irradiance π·scale·E·D65/z² (the closed form its normalization is built for), the image's
/// edges are the field of view's, and nothing lands outside it or behind the light.
#[test]
fn projector_irradiance_on_a_facing_plane_is_constant() {
    use gonio_render::texture::Texture;
    let (scale, e, fov) = (3.0f32, 0.4f32, 40.0f32);
    let light = ProjectorLight::new(Affine3A::IDENTITY, Texture::constant(e), scale, fov, 2.0);
    let wl = SampledWavelengths::sample_visible(0.45);
    let d65 = Spectrum::d65().sample(&wl)[0];
    let t = (fov.to_radians() / 2.0).tan();
    let z = 2.0;
    let expected = PI * scale * e * d65 / (z * z);
    for (x, y) in [
        (0.0, 0.0),
        (0.9 * t * z, 0.0),
        (-0.5 * t * z, 0.2 * t * z),
        (0.3, -0.4 * t * z),
    ] {
        let p = Vec3::new(x, y, z);
        let cos = p.z / p.length();
        let irradiance = light.li_at(p, &wl)[0] * cos;
        assert!(
            (irradiance - expected).abs() < 1e-4 * expected,
            "{irradiance} vs {expected} at {p:?}"
        );
    }
    // The horizontal edges of the image are at ±tan(φ/2)·z (u = 0 and 1, mirrored as in
    // Mitsuba's camera); with aspect 2 the vertical ones at ±tan(φ/2)·z/2.
    let uv = light.texture_uv(Vec3::new(-t * z, 0.0, z)).unwrap();
    assert!((uv - Vec2::new(1.0, 0.5)).length() < 1e-5, "{uv:?}");
    let uv = light.texture_uv(Vec3::new(0.0, 0.5 * t * z, z)).unwrap();
    assert!((uv - Vec2::new(0.5, 0.0)).length() < 1e-5, "{uv:?}");
    assert!(light.texture_uv(Vec3::new(0.0, 0.6 * t * z, z)).is_none());
    assert_eq!(light.li_at(Vec3::new(1.1 * t * z, 0.0, z), &wl)[0], 0.0);
    assert_eq!(light.li_at(Vec3::new(0.0, 0.0, -1.0), &wl)[0], 0.0);
}

/// `Lights::select_at_remapped` picks the light whose share of [0, 1) (the running sum of
/// `pmf_at`) holds the number, with its probability, and hands on what is left of the number: the numbers that pick a light, remapped, spread evenly
/// over [0, 1), and each light is picked by a share of them equal to its probability. Checked
/// with the position-aware choice (three point lights) and the global one (nine).
#[test]
fn select_at_remapped_hands_on_an_even_number() {
    let bounds = BoundingSphere {
        center: Vec3::ZERO,
        radius: 10.0,
    };
    let point = |i: usize| {
        Light::Point(PointLight {
            position: Vec3::new(i as f32 - 1.0, 2.0, 0.5 * i as f32),
            intensity: Spectrum::Constant(1.0 + 3.0 * i as f32),
        })
    };
    let r = LightRef {
        p: Vec3::new(0.3, 0.0, -0.2),
        n: Vec3::Y,
        hemisphere: true,
        mis: true,
        resolved_density: 0.0,
        resampled: false,
    };
    for count in [3, 9] {
        let lights = Lights::new((0..count).map(point).collect(), 0, 10.0, bounds);
        let k = 1 << 14;
        let mut remapped: Vec<Vec<f32>> = vec![Vec::new(); count];
        // The light each number should pick: the first whose running sum of `pmf_at` exceeds it.
        let pmf: Vec<f32> = (0..count).map(|i| lights.pmf_at(&r, i)).collect();
        let expected = |u: f32| {
            let mut acc = 0.0f32;
            pmf.iter().position(|&p| {
                acc += p;
                u < acc
            })
        };
        for j in 0..k {
            let u = (j as f32 + 0.5) / k as f32;
            let (i, p, ur) = lights.select_at_remapped(&r, u).expect("a light");
            assert_eq!(Some(i), expected(u), "{count} lights, u = {u}");
            assert_eq!(p, pmf[i]);
            assert!((0.0..1.0).contains(&ur), "{ur}");
            remapped[i].push(ur);
        }
        for (i, us) in remapped.iter_mut().enumerate() {
            let p = lights.pmf_at(&r, i) as f64;
            let n = us.len();
            assert!(
                (n as f64 / k as f64 - p).abs() <= 2.0 / k as f64,
                "light {i}: {n} of {k}, p {p}"
            );
            // Sorted, the j-th is (j + ½)/n up to one step of the grid it came from.
            us.sort_by(f32::total_cmp);
            for (j, &ur) in us.iter().enumerate() {
                let even = (j as f64 + 0.5) / n as f64;
                assert!(
                    (ur as f64 - even).abs() <= 1.5 / n as f64,
                    "light {i}: {j}-th {ur}, {even}"
                );
            }
        }
    }
}

/// `Light::sample_ray` (in its own file: this one is long).
mod emission;

/// The environment map: orientation, texels, its densities (plain and MIS-compensated).
mod envmap;

/// A projector's texel projects its own colour: a texture object of grey 0.5 (a checkerboard of
/// two equal colours) projects 0.5·D65, exactly what `<rgb name="irradiance" value="0.5"/>` given
/// in place projects, since D65 is the white of sRGB (Lᵢ = π·scale·E·D65/(z² cos θ)).
/// `whitepoint="mitsuba"` reproduces Mitsuba 3.9.1, whose `texture_d65` leaves a texture object
/// without D65: the same texture then projects the equal-energy spectrum π·scale·0.5/(z² cos θ),
/// reddish against the sRGB white, while a colour given in place keeps its D65.
#[test]
fn projector_texture_projects_its_own_colour_unless_whitepoint_mitsuba() {
    use gonio_render::render::PreparedScene;
    let light = |irradiance: &str, whitepoint: &str| {
        let xml = format!(
            r#"<scene version="3.0.0">
            <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
            <emitter type="projector"><float name="fov" value="40"/><float name="scale" value="3"/>{whitepoint}{irradiance}</emitter>
        </scene>"#
        );
        let scene = gonio_render::xml::load_scene_str(&xml, ".", &[]).expect("scene loads");
        let prepared = PreparedScene::new(scene).expect("scene prepares");
        match &prepared.lights().lights()[0] {
            Light::Projector(p) => p.clone(),
            other => panic!("not a projector: {other:?}"),
        }
    };
    let grey_texture = r#"<texture type="checkerboard" name="irradiance"><rgb name="color0" value="0.5"/><rgb name="color1" value="0.5"/></texture>"#;
    let grey_in_place = r#"<rgb name="irradiance" value="0.5"/>"#;
    let mitsuba = r#"<string name="whitepoint" value="mitsuba"/>"#;
    let p = Vec3::new(0.3, -0.2, 2.0);
    let geometry = PI * 3.0 / (p.z * p.z * (p.z / p.length()));
    for u in [0.05, 0.3, 0.55, 0.8, 0.97] {
        let wl = SampledWavelengths::sample_visible(u);
        let d65 = Spectrum::d65().sample(&wl);
        for (irradiance, whitepoint, expected) in [
            (grey_texture, "", d65 * (0.5 * geometry)),
            (grey_in_place, "", d65 * (0.5 * geometry)),
            (
                grey_texture,
                mitsuba,
                gonio_core::SampledSpectrum::splat(0.5 * geometry),
            ),
            (grey_in_place, mitsuba, d65 * (0.5 * geometry)),
        ] {
            let li = light(irradiance, whitepoint).li_at(p, &wl);
            for i in 0..4 {
                assert!(
                    (li[i] / expected[i] - 1.0).abs() < 1e-4,
                    "{irradiance} {whitepoint}: {li:?} vs {expected:?}"
                );
            }
        }
    }
    // A misspelt choice is an error naming the value.
    let xml = format!(
        r#"<scene version="3.0.0"><emitter type="projector"><string name="whitepoint" value="d56"/>{grey_texture}</emitter></scene>"#
    );
    let e = gonio_render::xml::load_scene_str(&xml, ".", &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("d56") && e.contains(":1:"), "{e}");
}

/// An `area` emitter's texture emits its own colours (× D65, as a colour given in place: a white
/// texel renders sRGB (1, 1, 1)). With `whitepoint="mitsuba"` (or `--mitsuba-estimators`) it
/// reproduces Mitsuba 3.9.1, whose `texture_d65` leaves a texture object without D65: white
/// texels then emit the equal-energy spectrum. Mitsuba's image mean for this scene, from
/// `scalar_spectral` at 1024 spp (2026-12-02, `mi.render(mi.load_file(..), spp=1024)`):
/// (0.34908, 0.33494, 0.40986); gonio's own at 256 spp is within 0.3 % of it, the tolerance is
/// 1 % (the emitter's wavelength noise at 64 spp is about 0.3 % in the mean).
#[test]
fn area_texture_emits_its_own_colour_unless_whitepoint_mitsuba() {
    use crate::integrator::{mean, render_xml};
    let scene = |whitepoint: &str| {
        format!(
            r#"<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0,0,4" target="0,0,0" up="0,1,0"/></transform>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/><rfilter type="box"/></film>
    </sensor>
    <shape type="rectangle">
        <emitter type="area">{whitepoint}
            <texture type="checkerboard" name="radiance">
                <rgb name="color0" value="1, 1, 1"/>
                <rgb name="color1" value="0.2, 0.5, 0.9"/>
            </texture>
        </emitter>
    </shape>
</scene>"#
        )
    };
    // Ours: a white texel is white.
    let ours = render_xml(&scene(""), 64, 1);
    let white = ours.get(14, 16);
    for c in white {
        assert!((c - 1.0).abs() < 0.01, "white texel renders {white:?}");
    }
    // Mitsuba's way: its image mean.
    let mitsuba = mean(&render_xml(
        &scene(r#"<string name="whitepoint" value="mitsuba"/>"#),
        64,
        1,
    ));
    let reference = [0.34908, 0.33494, 0.40986];
    for k in 0..3 {
        assert!(
            (mitsuba[k] / reference[k] - 1.0).abs() < 0.01,
            "whitepoint=mitsuba: mean {mitsuba:?} vs Mitsuba's {reference:?}"
        );
    }
    // The two differ by far more than that: the point of the switch.
    let ours_mean = mean(&ours);
    assert!((ours_mean[0] / reference[0] - 1.0).abs() > 0.1, "{ours_mean:?}");
}
