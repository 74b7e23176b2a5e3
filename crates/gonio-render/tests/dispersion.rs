//! Dispersion, which Mitsuba cannot render: a thin beam through an SF11 prism leaves at the angle
//! Snell's law gives with the Sellmeier index, at each wavelength.
//!
//! The prism (apex 60°, an OBJ mesh) is loaded through the scene reader with
//! `<string name="int_ior" value="SF11"/>` in vacuum (`ext_ior` 1); the beam is traced through the scene's BVH and the
//! material's BSDF exactly as the path tracer does at each vertex (the refraction lobe picked with
//! a fixed lobe number). The expected exit direction comes from the textbook prism formula with
//! n(λ) from Schott's Sellmeier coefficients written out here, independent of the renderer's glass
//! table: θ₂ = asin(sin θ₁/n), θ₃ = A − θ₂, θ₄ = asin(n sin θ₃), deviation δ = θ₁ + θ₄ − A.

use glam::{Vec2, Vec3};
use gonio_core::{BsdfContext, SampledWavelengths};
use gonio_render::accel::Intersect;
use gonio_render::geometry::Ray;
use gonio_render::render::PreparedScene;
use std::f64::consts::PI;

/// Schott SF11 Sellmeier coefficients (B dimensionless, C in µm²).
const B: [f64; 3] = [1.73759695, 0.313747346, 1.89878101];
const C: [f64; 3] = [0.013188707, 0.0623068142, 155.23629];

fn n_sf11(lambda_nm: f64) -> f64 {
    let l2 = (lambda_nm / 1000.0).powi(2);
    (1.0 + (0..3).map(|j| B[j] * l2 / (l2 - C[j])).sum::<f64>()).sqrt()
}

/// An equilateral prism: cross-section (−1, 0), (1, 0), (0, √3) in the xy plane, z ∈ [−1, 1].
fn prism_obj() -> String {
    let h = 3f64.sqrt();
    let v = [
        [-1.0, 0.0, -1.0],
        [1.0, 0.0, -1.0],
        [0.0, h, -1.0],
        [-1.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, h, 1.0],
    ];
    let centroid = [0.0, h / 3.0, 0.0];
    // Quads split into triangles, each wound counter-clockwise seen from outside.
    let faces: [[usize; 3]; 8] = [
        [0, 1, 4],
        [0, 4, 3],
        [1, 2, 5],
        [1, 5, 4],
        [2, 0, 3],
        [2, 3, 5],
        [0, 2, 1],
        [3, 4, 5],
    ];
    let mut s = String::new();
    for p in v {
        s += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for f in faces {
        let (a, b, c) = (v[f[0]], v[f[1]], v[f[2]]);
        let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let out = [
            (a[0] + b[0] + c[0]) / 3.0 - centroid[0],
            (a[1] + b[1] + c[1]) / 3.0 - centroid[1],
            (a[2] + b[2] + c[2]) / 3.0 - centroid[2],
        ];
        let outward = n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0.0;
        let (i, j, k) = if outward {
            (f[0], f[1], f[2])
        } else {
            (f[0], f[2], f[1])
        };
        s += &format!("f {} {} {}\n", i + 1, j + 1, k + 1);
    }
    s
}

fn prism_scene() -> PreparedScene {
    let dir = std::env::temp_dir().join(format!("gonio-dispersion-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("prism.obj"), prism_obj()).unwrap();
    let xml = r#"<scene version="3.0.0">
        <sensor type="perspective">
            <float name="fov" value="40"/>
            <transform name="to_world"><lookat origin="0, 1, 10" target="0, 1, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
        </sensor>
        <shape type="obj">
            <string name="filename" value="prism.obj"/>
            <boolean name="face_normals" value="true"/>
            <bsdf type="dielectric">
                <string name="int_ior" value="SF11"/>
                <float name="ext_ior" value="1"/>
            </bsdf>
        </shape>
    </scene>"#;
    let scene = gonio_render::xml::load_scene_str(xml, &dir, &[]).expect("prism scene loads");
    let _ = std::fs::remove_dir_all(&dir);
    PreparedScene::new(scene).expect("prism scene prepares")
}

/// Traces a ray through the prism, refracting at each of the first two hits (the refraction lobe
/// chosen with lobe number 0.999); returns the direction after the second refraction.
fn trace_beam(prepared: &PreparedScene, lambda: f32, o: Vec3, d: Vec3) -> Vec3 {
    let mut wl = SampledWavelengths::fixed(lambda);
    let mut ray = Ray::new(o, d);
    let material = &prepared.scene.materials[prepared.scene.shapes[0].material];
    for bounce in 0..2 {
        let si = prepared
            .accel()
            .intersect(&ray)
            .unwrap_or_else(|| panic!("bounce {bounce}: the beam misses"));
        let wi = si.shading.to_local(-ray.d);
        let bs = material
            .with_bsdf(si.uv, |b| {
                b.sample(&BsdfContext::radiance(), wi, 0.999, Vec2::new(0.5, 0.5), &mut wl)
            })
            .unwrap_or_else(|| panic!("bounce {bounce}: no sample"));
        assert!(
            bs.flags.is_transmission(),
            "bounce {bounce}: expected a refraction, got {}",
            bs.flags
        );
        ray = si.spawn_ray(si.shading.to_world(bs.wo).normalize());
    }
    assert!(
        wl.secondary_terminated(),
        "a dispersive refraction keeps only the hero wavelength"
    );
    ray.d
}

#[test]
fn prism_exit_angles_follow_snell_and_sellmeier() {
    let prepared = prism_scene();
    let apex = PI / 3.0;
    let theta1 = 65f64.to_radians();
    // Left face: outward normal n = (−√3/2, ½, 0), tangent towards the apex t = (½, √3/2, 0).
    // The incident direction −cos θ₁·n + sin θ₁·t makes the angle θ₁ with the inward normal.
    let n_left = Vec3::new(-(3f32.sqrt()) / 2.0, 0.5, 0.0);
    let t_left = Vec3::new(0.5, 3f32.sqrt() / 2.0, 0.0);
    let d = (-(theta1.cos() as f32) * n_left + (theta1.sin() as f32) * t_left).normalize();
    let entry = Vec3::new(-0.5, 3f32.sqrt() / 2.0, 0.0);
    let o = entry - 5.0 * d;
    let phi_in = (d.y as f64).atan2(d.x as f64);

    let mut exits = Vec::new();
    for lambda in [450.0f64, 650.0] {
        let n = n_sf11(lambda);
        let theta2 = (theta1.sin() / n).asin();
        let theta3 = apex - theta2;
        let theta4 = (n * theta3.sin()).asin();
        let deviation = theta1 + theta4 - apex;
        // The prism bends the beam towards its base (−y): a clockwise turn by the deviation.
        let phi_expected = phi_in - deviation;
        let out = trace_beam(&prepared, lambda as f32, o, d);
        assert!(out.z.abs() < 1e-5, "the beam stays in the xy plane: {out}");
        let phi = (out.y as f64).atan2(out.x as f64);
        println!(
            "λ = {lambda} nm: n = {n:.5}, deviation {:.4}°, traced {:.4}°",
            deviation.to_degrees(),
            (phi_in - phi).to_degrees()
        );
        assert!(
            (phi - phi_expected).abs() < 2e-4,
            "λ = {lambda} nm: exit angle {:.5}° vs Snell/Sellmeier {:.5}°",
            phi.to_degrees(),
            phi_expected.to_degrees()
        );
        exits.push(phi);
    }
    // Blue is bent more than red: 70.90° against 65.48° of deviation, a 5.42° fan (a constant
    // index would give none).
    let spread = (exits[1] - exits[0]).to_degrees();
    assert!((spread - 5.4203).abs() < 0.02, "angular spread {spread}°");
}

#[test]
fn sf11_index_matches_catalogue() {
    // Schott catalogue values for SF11: n_d (587.56 nm) = 1.78472, Abbe number V_d = 25.68 with
    // F = 486.13 nm and C = 656.27 nm.
    assert!((n_sf11(587.56) - 1.78472).abs() < 2e-5);
    let abbe = (n_sf11(587.56) - 1.0) / (n_sf11(486.13) - n_sf11(656.27));
    assert!((abbe - 25.68).abs() < 0.01, "V_d = {abbe}");
}
