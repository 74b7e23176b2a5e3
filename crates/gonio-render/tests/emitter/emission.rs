//! Emission sampling (`Light::sample_ray`): the mean weight of sampled rays is the emitted power
//! at the sampled wavelengths, checked against closed forms and numerical integrals within
//! 4 standard errors (plus 10⁻⁴ relative for f32 rounding where every weight is the same).

use super::Rng;
use glam::{Affine2, Affine3A, Vec2, Vec3};
use gonio_core::{SampledSpectrum, SampledWavelengths, Spectrum};
use gonio_render::emitter::*;
use gonio_render::geometry::WorldShape;
use gonio_render::scene::{Geometry, ShapeDesc};
use gonio_render::texture::Texture;
use std::f32::consts::PI;

const N: usize = 40_000;

fn wl() -> SampledWavelengths {
    SampledWavelengths::sample_visible(0.37)
}

fn bounds() -> BoundingSphere {
    BoundingSphere {
        center: Vec3::new(0.5, -1.0, 2.0),
        radius: 3.0,
    }
}

fn checker(a: f32, b: f32) -> Texture {
    Texture::Checkerboard {
        color0: Box::new(Texture::Spectrum(Spectrum::Constant(a))),
        color1: Box::new(Texture::Spectrum(Spectrum::Constant(b))),
        to_uv: Affine2::from_scale(Vec2::splat(3.0)),
        float_cells_swapped: false,
    }
}

/// Mean weight of `N` rays and its standard error, per wavelength of `wl`; also checks every
/// ray.
fn estimate(
    light: &Light,
    shapes: &[WorldShape],
    seed: u64,
    wl: &SampledWavelengths,
) -> ([f64; 4], [f64; 4]) {
    let b = bounds();
    let mut rng = Rng(seed);
    let (mut s, mut s2) = ([0.0f64; 4], [0.0f64; 4]);
    for _ in 0..N {
        let (u_pos, u_dir) = (rng.next_2d(), rng.next_2d());
        if let Some(e) = light.sample_ray(shapes, &b, u_pos, u_dir, wl) {
            assert!((e.ray.d.length() - 1.0).abs() < 1e-4, "unit direction");
            if light.is_infinite() || matches!(light, Light::Directional(_)) {
                // Rays enter through the bounding sphere's disk, from outside it, inwards.
                let to_c = b.center - e.ray.o;
                assert!(to_c.length() <= b.radius * 1.4143 && to_c.dot(e.ray.d) > 0.0);
            }
            for k in 0..4 {
                let w = e.weight[k] as f64;
                s[k] += w;
                s2[k] += w * w;
            }
        }
    }
    let n = N as f64;
    let mean = s.map(|x| x / n);
    let se = std::array::from_fn(|k| ((s2[k] / n - mean[k] * mean[k]).max(0.0) / n).sqrt());
    (mean, se)
}

fn check(name: &str, light: &Light, shapes: &[WorldShape], exact: SampledSpectrum) {
    check_at(name, light, shapes, exact, &wl());
}

/// [`check`] at the wavelengths `wl`.
fn check_at(
    name: &str,
    light: &Light,
    shapes: &[WorldShape],
    exact: SampledSpectrum,
    wl: &SampledWavelengths,
) {
    let (mean, se) = estimate(light, shapes, 11, wl);
    for k in 0..4 {
        let e = exact[k] as f64;
        let tol = 4.0 * se[k] + 1e-4 * e.abs();
        println!("{name} λ{k}: {:.5} vs {e:.5} (se {:.2e})", mean[k], se[k]);
        assert!(e > 0.0, "{name}: the exact power is positive");
        assert!(
            (mean[k] - e).abs() <= tol,
            "{name} λ{k}: {} vs {e} (se {})",
            mean[k],
            se[k]
        );
    }
}

/// ∫ f(ω) dω over the sphere (midpoint rule in cos θ and φ).
fn integrate_sphere(f: impl Fn(Vec3) -> SampledSpectrum, n: usize) -> SampledSpectrum {
    let mut s = SampledSpectrum::ZERO;
    for a in 0..n {
        let z = -1.0 + 2.0 * (a as f32 + 0.5) / n as f32;
        let r = (1.0 - z * z).max(0.0).sqrt();
        for b in 0..2 * n {
            let phi = 2.0 * PI * (b as f32 + 0.5) / (2 * n) as f32;
            s += f(Vec3::new(r * phi.cos(), r * phi.sin(), z));
        }
    }
    s * ((2.0 / n as f32) * (2.0 * PI / (2 * n) as f32))
}

fn rectangle() -> WorldShape {
    let desc = ShapeDesc {
        geometry: Geometry::Rectangle,
        to_world: Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0))
            * Affine3A::from_rotation_x(0.4)
            * Affine3A::from_scale(Vec3::new(2.0, 1.5, 1.0)),
        flip_normals: false,
        face_normals: false,
        outside_only: false,
        media: Default::default(),
        material: 0,
        emitter: None,
        id: None,
    };
    WorldShape::from_scene(&desc, "light").unwrap()
}

fn area_light(radiance: Texture, shape: &WorldShape) -> Light {
    Light::Area(AreaLight {
        shape: 0,
        mean_radiance: radiance.mean(),
        radiance,
        area: shape.area(),
        center: Vec3::ZERO,
        radius: 3.0,
        hit: None,
    })
}

#[test]
fn area_power_is_pi_area_radiance() {
    let shapes = [rectangle()];
    let l = Spectrum::Constant(2.5);
    let light = area_light(Texture::Spectrum(l.clone()), &shapes[0]);
    check("area", &light, &shapes, l.sample(&wl()) * (PI * 12.0));
    assert!((shapes[0].area() - 12.0).abs() < 1e-4);
}

#[test]
fn textured_area_power_is_pi_times_the_radiance_integral() {
    let shapes = [rectangle()];
    let tex = checker(3.0, 0.5);
    // π ∫ L dA = π·A·∫∫ L(u, v) du dv (the rectangle's uv is affine), by a midpoint rule.
    let m = 240;
    let mut integral = SampledSpectrum::ZERO;
    for i in 0..m {
        for j in 0..m {
            let uv = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
            integral += tex.eval(uv).sample(&wl());
        }
    }
    let exact = integral * (PI * shapes[0].area() / (m * m) as f32);
    check("textured area", &area_light(tex, &shapes[0]), &shapes, exact);
}

#[test]
fn point_power_is_four_pi_intensity() {
    let i = Spectrum::Constant(3.0);
    let light = Light::Point(PointLight {
        position: Vec3::new(1.0, 2.0, 3.0),
        intensity: i.clone(),
    });
    check("point", &light, &[], i.sample(&wl()) * (4.0 * PI));
}

#[test]
fn spot_power_is_the_falloff_integral() {
    let to_world = Affine3A::from_rotation_y(0.7) * Affine3A::from_translation(Vec3::Y);
    let spot = SpotLight::new(to_world, Spectrum::Constant(5.0), 30.0, 15.0);
    // Closed form of ∫ falloff dω: 2π(1 − cos β) + 2π((γ − β)cos β + sin β − sin γ)/(γ − β).
    let (b, g) = (15f32.to_radians(), 30f32.to_radians());
    let solid = 2.0 * PI * (1.0 - b.cos()) + 2.0 * PI * ((g - b) * b.cos() + b.sin() - g.sin()) / (g - b);
    check(
        "spot",
        &Light::Spot(spot),
        &[],
        SampledSpectrum::splat(5.0 * solid),
    );
}

#[test]
fn textured_spot_power_is_the_numerical_integral() {
    let to_world = Affine3A::from_rotation_x(-0.5);
    let spot =
        SpotLight::new(to_world, Spectrum::Constant(2.0), 25.0, 10.0).with_texture(Some(checker(1.0, 0.2)));
    let exact = integrate_sphere(|d| spot.intensity_towards(d, &wl()), 1200);
    check("textured spot", &Light::Spot(spot), &[], exact);
}

#[test]
fn projector_power_is_the_irradiance_integral() {
    // Untextured: π·scale·D65·E·A_img, A_img = 4 tan²(φ/2)/a on the plane z = 1.
    let to_world = Affine3A::from_rotation_z(0.3) * Affine3A::from_translation(Vec3::new(0.0, 0.0, -2.0));
    let (fov, aspect, scale) = (40.0f32, 1.5f32, 2.0f32);
    let flat = ProjectorLight::new(
        to_world,
        Texture::Spectrum(Spectrum::Constant(0.8)),
        scale,
        fov,
        aspect,
    );
    let t = (fov.to_radians() * 0.5).tan();
    let d65 = Spectrum::d65().sample(&wl());
    let exact = d65 * (PI * scale * 0.8 * 4.0 * t * t / aspect);
    check("projector", &Light::Projector(flat), &[], exact);

    // Textured: ∫ I dω = ∫ Lᵢ(p)·|p|²·dA/|p|³ over the plane z = 1 in front of the pinhole
    // (Lᵢ the delta light's arriving radiance at p, I = Lᵢ·d²), by a midpoint rule.
    let tex = ProjectorLight::new(Affine3A::IDENTITY, checker(1.0, 0.1), scale, fov, aspect);
    let m = 300;
    let (hx, hy) = (t, t / aspect);
    let mut integral = SampledSpectrum::ZERO;
    for i in 0..m {
        for j in 0..m {
            let x = -hx + 2.0 * hx * (i as f32 + 0.5) / m as f32;
            let y = -hy + 2.0 * hy * (j as f32 + 0.5) / m as f32;
            let p = Vec3::new(x, y, 1.0);
            integral += tex.li_at(p, &wl()) / p.length();
        }
    }
    let exact = integral * (4.0 * hx * hy / (m * m) as f32);
    check("textured projector", &Light::Projector(tex), &[], exact);
}

#[test]
fn directional_power_is_the_flux_through_the_bounding_disk() {
    let e = Spectrum::Constant(1.7);
    let light = Light::Directional(DirectionalLight {
        direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
        irradiance: e.clone(),
    });
    let r = bounds().radius;
    check("directional", &light, &[], e.sample(&wl()) * (PI * r * r));
}

#[test]
fn infinite_power_is_the_flux_through_the_bounding_disk() {
    let r = bounds().radius;
    let l = Spectrum::Constant(0.6);
    let c = Light::Constant(ConstantLight { radiance: l.clone() });
    check("constant", &c, &[], l.sample(&wl()) * (4.0 * PI * PI * r * r));

    let env = super::envmap::test_envmap(Affine3A::from_rotation_y(0.8));
    let exact = integrate_sphere(|d| env.le(d, &wl()), 1000) * (PI * r * r);
    check("envmap", &Light::EnvMap(env), &[], exact);
}

/// `sunsky` (the limb-darkened sun and the sky of 11:00 in Tokyo): the flux through the
/// bounding disk, π r² ∫ L dω, at wavelengths the model covers (it is black beyond 720 nm).
#[test]
fn sunsky_power_is_the_flux_through_the_bounding_disk() {
    let light = crate::sunsky::light_of(
        "<float name=\"hour\" value=\"11\"/><boolean name=\"complex_sun\" value=\"true\"/>\
         <float name=\"sun_aperture\" value=\"2\"/>",
    );
    let Light::SunSky(s) = &light else {
        panic!("not a sunsky light")
    };
    let wl = SampledWavelengths::from_parts([410.0, 480.0, 560.0, 650.0], [1.0; 4]);
    let r = bounds().radius;
    let i = crate::sunsky::sphere_integral(s, |d| light.le_infinite(d, &wl).to_array());
    let exact = SampledSpectrum::new(i.map(|v| v as f32)) * (PI * r * r);
    check_at("sunsky", &light, &[], exact, &wl);
}
