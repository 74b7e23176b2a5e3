//! Shapes: intersections, normals, uv against analytic answers; self-intersection; sampling pdfs.

use glam::{Affine3A, Quat, Vec2, Vec3};
use gonio_core::hash::{GOLDEN_GAMMA, mix64, unit_f32};
use gonio_render::accel::{BruteForce, Intersect};
use gonio_render::geometry::sampling::{pdf_solid_angle, sample_area, sample_solid_angle};
use gonio_render::geometry::{Ray, SurfaceInteraction, WorldShape};
use gonio_render::scene::{Geometry, ShapeDesc, TriangleMesh};
use std::f32::consts::PI;
use std::sync::Arc;

/// A tiny fixed-seed generator for the tests: a Weyl sequence hashed by the core's mixer.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(GOLDEN_GAMMA);
        unit_f32(mix64(self.0))
    }
    fn v2(&mut self) -> Vec2 {
        Vec2::new(self.next(), self.next())
    }
    fn dir(&mut self) -> Vec3 {
        let z = 1.0 - 2.0 * self.next();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * self.next();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

fn shape(geometry: Geometry, to_world: Affine3A) -> ShapeDesc {
    ShapeDesc {
        geometry,
        to_world,
        flip_normals: false,
        face_normals: false,
        outside_only: false,
        media: Default::default(),
        material: 0,
        emitter: None,
        id: None,
    }
}

fn world(s: &ShapeDesc) -> WorldShape {
    WorldShape::from_scene(s, "test").unwrap()
}

fn hit(s: &WorldShape, ray: Ray) -> Option<SurfaceInteraction> {
    BruteForce::new(vec![s.clone()]).intersect(&ray)
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).length() <= tol
}

#[test]
fn sphere_hits_normals_and_uv() {
    // Object sphere centre (0,0,0) r = 1, placed by to_world: scale 2, translate (1, 2, 3).
    let s = shape(
        Geometry::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        Affine3A::from_translation(Vec3::new(1.0, 2.0, 3.0)) * Affine3A::from_scale(Vec3::splat(2.0)),
    );
    let w = world(&s);
    assert!((w.area() - 16.0 * PI).abs() < 1e-3);
    let h = hit(&w, Ray::new(Vec3::new(1.0, 2.0, -10.0), Vec3::Z)).unwrap();
    assert!((h.t - 11.0).abs() < 1e-5, "t = {}", h.t);
    assert!(close(h.p, Vec3::new(1.0, 2.0, 1.0), 1e-5) && close(h.n, -Vec3::Z, 1e-6));
    assert!(
        (h.uv - Vec2::new(0.0, 1.0)).length() < 1e-5,
        "south pole: v = θ/π = 1, {:?}",
        h.uv
    );
    // From +x: hits (3, 2, 3), θ = π/2, φ = 0.
    let h = hit(&w, Ray::new(Vec3::new(10.0, 2.0, 3.0), -Vec3::X)).unwrap();
    assert!((h.t - 7.0).abs() < 1e-5 && close(h.n, Vec3::X, 1e-6));
    assert!((h.uv - Vec2::new(0.0, 0.5)).length() < 1e-5, "{:?}", h.uv);
    // From +y: φ = π/2 → u = 0.25; shading frame tangent along ∂p/∂u = (−1, 0, 0) direction.
    let h = hit(&w, Ray::new(Vec3::new(1.0, 10.0, 3.0), -Vec3::Y)).unwrap();
    assert!((h.uv - Vec2::new(0.25, 0.5)).length() < 1e-5, "{:?}", h.uv);
    assert!(close(h.shading.s, -Vec3::X, 1e-5) && close(h.shading.n, Vec3::Y, 1e-6));
    // From inside: the far side, one radius away.
    let h = hit(&w, Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::Z)).unwrap();
    assert!((h.t - 2.0).abs() < 1e-5 && close(h.n, Vec3::Z, 1e-6));
    // Misses: tangent-plus-epsilon, behind, and beyond tmax.
    assert!(hit(&w, Ray::new(Vec3::new(3.001, 2.0, -10.0), Vec3::Z)).is_none());
    assert!(hit(&w, Ray::new(Vec3::new(1.0, 2.0, 10.0), Vec3::Z)).is_none());
    assert!(
        hit(
            &w,
            Ray {
                o: Vec3::new(1.0, 2.0, -10.0),
                d: Vec3::Z,
                tmax: 10.9
            }
        )
        .is_none()
    );
    // flip_normals: the normal points inwards.
    let mut f = s.clone();
    f.flip_normals = true;
    let h = hit(&world(&f), Ray::new(Vec3::new(1.0, 2.0, -10.0), Vec3::Z)).unwrap();
    assert!(close(h.n, Vec3::Z, 1e-6) && close(h.shading.n, Vec3::Z, 1e-6));
    // Object-space centre and radius compose with to_world.
    let c = shape(
        Geometry::Sphere {
            center: Vec3::new(0.0, 0.0, 1.0),
            radius: 0.5,
        },
        Affine3A::from_scale(Vec3::splat(2.0)),
    );
    let h = hit(&world(&c), Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z)).unwrap();
    assert!((h.t - 6.0).abs() < 1e-5, "centre (0,0,2), radius 1: {}", h.t);
}

#[test]
fn sphere_with_nonuniform_scale_is_an_error() {
    let s = shape(
        Geometry::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        Affine3A::from_scale(Vec3::new(1.0, 2.0, 1.0)),
    );
    let e = WorldShape::from_scene(&s, "ellipsoid").unwrap_err();
    assert!(e.to_string().contains("ellipsoid"), "{e}");
}

#[test]
fn rectangle_hits_uv_and_normal_convention() {
    let m =
        Affine3A::from_translation(Vec3::new(0.0, 0.0, 1.0)) * Affine3A::from_scale(Vec3::new(2.0, 3.0, 1.0));
    let w = world(&shape(Geometry::Rectangle, m));
    assert!((w.area() - 24.0).abs() < 1e-5);
    let h = hit(&w, Ray::new(Vec3::new(1.0, 1.5, 5.0), -Vec3::Z)).unwrap();
    assert!((h.t - 4.0).abs() < 1e-6 && close(h.p, Vec3::new(1.0, 1.5, 1.0), 1e-6));
    assert!((h.uv - Vec2::new(0.75, 0.75)).length() < 1e-6, "{:?}", h.uv);
    assert!(close(h.n, Vec3::Z, 1e-6), "normal +z regardless of the ray side");
    // From below as well (two-sided intersection), and misses just outside.
    assert!(hit(&w, Ray::new(Vec3::new(-1.9, -2.9, -5.0), Vec3::Z)).is_some());
    assert!(hit(&w, Ray::new(Vec3::new(2.01, 0.0, 5.0), -Vec3::Z)).is_none());
    assert!(
        hit(&w, Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::X)).is_none(),
        "parallel ray"
    );
    // A mirror (scale x by −1) keeps Mitsuba's normal: inverse transpose of +z is still +z.
    let mirror = world(&shape(
        Geometry::Rectangle,
        Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
    ));
    let h = hit(&mirror, Ray::new(Vec3::new(0.5, 0.0, 1.0), -Vec3::Z)).unwrap();
    assert!(close(h.n, Vec3::Z, 1e-6), "{:?}", h.n);
    assert!(
        (h.uv.x - 0.25).abs() < 1e-6,
        "world x = 0.5 is object x = −0.5: {:?}",
        h.uv
    );
    // Rotated 90° about x: the normal becomes −y.
    let r = world(&shape(Geometry::Rectangle, Affine3A::from_rotation_x(PI / 2.0)));
    let h = hit(&r, Ray::new(Vec3::new(0.2, -3.0, 0.3), Vec3::Y)).unwrap();
    assert!(close(h.n, -Vec3::Y, 1e-6), "{:?}", h.n);
}

#[test]
fn disk_hits_and_uv() {
    let w = world(&shape(Geometry::Disk, Affine3A::from_scale(Vec3::splat(2.0))));
    assert!((w.area() - 4.0 * PI).abs() < 1e-4);
    let h = hit(&w, Ray::new(Vec3::new(0.0, 1.0, 3.0), -Vec3::Z)).unwrap();
    // Object point (0, 0.5): uv = (r, φ/2π) = (0.5, 0.25).
    assert!((h.uv - Vec2::new(0.5, 0.25)).length() < 1e-6, "{:?}", h.uv);
    assert!(close(h.n, Vec3::Z, 1e-6));
    assert!(
        hit(&w, Ray::new(Vec3::new(1.5, 1.5, 3.0), -Vec3::Z)).is_none(),
        "inside the square, outside the disk"
    );
    let h = hit(&w, Ray::new(Vec3::new(0.0, -1.0, 3.0), -Vec3::Z)).unwrap();
    assert!((h.uv.y - 0.75).abs() < 1e-6, "φ = −π/2 wraps to 0.75: {:?}", h.uv);
}

/// Mitsuba's conventions for ∂p/∂u and ∂p/∂v where they are not the derivatives of p(u, v)
/// (Mitsuba 3 `src/shapes/tests/test_disk.py` `test05`, `test_sphere.py` `test09`): the disk's are
/// the unit radial and tangential directions, (1, 0, 0) and (0, 1, 0) at its centre; the
/// sphere's ∂p/∂v at a pole is π (1, 0, 0). Bump maps and the `dp_dv` AOV follow them.
#[test]
fn disk_and_sphere_partials_follow_mitsuba_at_singular_points() {
    let disk = world(&shape(Geometry::Disk, Affine3A::IDENTITY));
    let h = hit(&disk, Ray::new(Vec3::new(0.1, -0.2, 1.0), -Vec3::Z)).unwrap();
    let (c, s) = (0.1 / 0.05f32.sqrt(), -0.2 / 0.05f32.sqrt());
    assert!(close(h.dpdu, Vec3::new(c, s, 0.0), 1e-5), "{:?}", h.dpdu);
    assert!(close(h.dpdv, Vec3::new(-s, c, 0.0), 1e-5), "{:?}", h.dpdv);
    let centre = hit(&disk, Ray::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z)).unwrap();
    assert_eq!((centre.dpdu, centre.dpdv), (Vec3::X, Vec3::Y));
    let sphere = world(&shape(
        Geometry::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        Affine3A::IDENTITY,
    ));
    let pole = hit(&sphere, Ray::new(Vec3::new(0.0, 0.0, -3.0), Vec3::Z)).unwrap();
    assert!(close(pole.p, -Vec3::Z, 1e-6));
    assert!(close(pole.dpdv, Vec3::new(PI, 0.0, 0.0), 1e-5), "{:?}", pole.dpdv);
}

/// Mitsuba's regression scene `various_shapes` scales a disk by (1.5, 2.5, 1): an ellipse of
/// semi-axes 1.5 and 2.5 (area 3.75π), hit inside and missed outside its boundary, with uv
/// (r, φ/2π) of the unit disk it came from; the scale along z leaves it unchanged.
#[test]
fn disk_under_a_non_uniform_scale_is_an_ellipse() {
    let m = Affine3A::from_scale_rotation_translation(Vec3::new(1.5, 2.5, 3.0), Quat::IDENTITY, Vec3::ZERO);
    let w = world(&shape(Geometry::Disk, m));
    assert!((w.area() - 3.75 * PI).abs() < 1e-4, "area {}", w.area());
    let h = hit(&w, Ray::new(Vec3::new(0.0, 2.4, 3.0), -Vec3::Z)).expect("inside along y");
    assert!((h.uv - Vec2::new(0.96, 0.25)).length() < 1e-5, "{:?}", h.uv);
    assert!(close(h.n, Vec3::Z, 1e-6));
    assert!(
        hit(&w, Ray::new(Vec3::new(1.45, 0.0, 3.0), -Vec3::Z)).is_some(),
        "inside along x"
    );
    assert!(
        hit(&w, Ray::new(Vec3::new(1.55, 0.0, 3.0), -Vec3::Z)).is_none(),
        "outside along x"
    );
    assert!(
        hit(&w, Ray::new(Vec3::new(1.2, 1.6, 3.0), -Vec3::Z)).is_none(),
        "inside the circle of radius 2.5, outside the ellipse"
    );
    // The same disk scaled (1.5, 2.5, 1): identical.
    let flat = world(&shape(
        Geometry::Disk,
        Affine3A::from_scale(Vec3::new(1.5, 2.5, 1.0)),
    ));
    assert_eq!(flat.area(), w.area());
    // Area sampling stays uniform: its pdf 1/area matches the hits (`check_sampling`).
    let tilted = world(&shape(
        Geometry::Disk,
        Affine3A::from_rotation_translation(Quat::from_rotation_y(0.7), Vec3::new(0.0, 0.5, 2.0)) * m,
    ));
    check_sampling(&tilted, Vec3::ZERO, false, "ellipse");
}

fn quad_mesh(normals: bool, uvs: bool) -> TriangleMesh {
    TriangleMesh {
        positions: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        normals: if normals {
            vec![
                Vec3::Z,
                Vec3::new(1.0, 0.0, 1.0).normalize(),
                Vec3::new(1.0, 0.0, 1.0).normalize(),
                Vec3::Z,
            ]
        } else {
            vec![]
        },
        uvs: if uvs {
            vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 1.0),
            ]
        } else {
            vec![]
        },
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}

#[test]
fn mesh_barycentrics_uv_shading_normals_and_flags() {
    let s = shape(
        Geometry::Mesh(Arc::new(quad_mesh(true, true))),
        Affine3A::from_translation(Vec3::new(0.0, 0.0, 2.0)),
    );
    let w = world(&s);
    assert!((w.area() - 1.0).abs() < 1e-6);
    let h = hit(&w, Ray::new(Vec3::new(0.75, 0.25, 5.0), -Vec3::Z)).unwrap();
    assert_eq!(h.prim, 0);
    assert!((h.t - 3.0).abs() < 1e-6);
    assert!((h.uv - Vec2::new(0.75, 0.25)).length() < 1e-6, "{:?}", h.uv);
    assert!(close(h.n, Vec3::Z, 1e-6));
    // Shading normal: b0 = 0.25 (n = z), b1 = 0.5, b2 = 0.25 (both (1,0,1)/√2) → normalize.
    let k = 0.75 / 2f32.sqrt();
    let want = Vec3::new(k, 0.0, 0.25 + k).normalize();
    assert!(close(h.shading.n, want, 1e-5), "{:?} vs {want:?}", h.shading.n);
    assert!(close(h.dpdu, Vec3::X, 1e-5) && close(h.shading.s, (Vec3::X - want * want.x).normalize(), 1e-5));
    // face_normals: shading normal = geometric normal.
    let mut f = s.clone();
    f.face_normals = true;
    let h = hit(&world(&f), Ray::new(Vec3::new(0.75, 0.25, 5.0), -Vec3::Z)).unwrap();
    assert!(close(h.shading.n, Vec3::Z, 1e-6));
    // flip_normals negates both.
    f.face_normals = false;
    f.flip_normals = true;
    let h = hit(&world(&f), Ray::new(Vec3::new(0.75, 0.25, 5.0), -Vec3::Z)).unwrap();
    assert!(close(h.n, -Vec3::Z, 1e-6) && close(h.shading.n, -want, 1e-5));
    // Without uvs, Mitsuba's uv = (b1, b2).
    let w = world(&shape(
        Geometry::Mesh(Arc::new(quad_mesh(false, false))),
        Affine3A::IDENTITY,
    ));
    let h = hit(&w, Ray::new(Vec3::new(0.25, 0.75, 1.0), -Vec3::Z)).unwrap();
    assert_eq!(h.prim, 1);
    // Triangle (0, 2, 3): p = b0·(0,0) + b1·(1,1) + b2·(0,1) = (b1, b1 + b2) → b1 = 0.25, b2 = 0.5.
    assert!((h.uv - Vec2::new(0.25, 0.5)).length() < 1e-6, "{:?}", h.uv);
}

#[test]
fn mesh_with_bad_indices_is_an_error() {
    let mut m = quad_mesh(false, false);
    m.indices.push([0, 1, 9]);
    let e = WorldShape::from_scene(
        &shape(Geometry::Mesh(Arc::new(m.clone())), Affine3A::IDENTITY),
        "broken.obj",
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("broken.obj") && e.to_string().contains("triangle 2"),
        "{e}"
    );
    m.indices.pop();
    m.positions[1].x = f32::NAN;
    let e = WorldShape::from_scene(&shape(Geometry::Mesh(Arc::new(m)), Affine3A::IDENTITY), "nan.ply")
        .unwrap_err();
    assert!(
        e.to_string().contains("nan.ply") && e.to_string().contains("vertex 1"),
        "{e}"
    );
    let s = shape(
        Geometry::Sphere {
            center: Vec3::ZERO,
            radius: 0.0,
        },
        Affine3A::IDENTITY,
    );
    assert!(WorldShape::from_scene(&s, "zero").is_err());
    let r = shape(
        Geometry::Rectangle,
        Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0)),
    );
    assert!(
        WorldShape::from_scene(&r, "flat")
            .unwrap_err()
            .to_string()
            .contains("flat")
    );
}

#[test]
fn shared_edges_are_watertight() {
    // Rays aimed exactly at the diagonal shared by the two triangles, and at the shared vertex:
    // the watertight test must report a hit for every one.
    let w = world(&shape(
        Geometry::Mesh(Arc::new(quad_mesh(false, false))),
        Affine3A::IDENTITY,
    ));
    let b = BruteForce::new(vec![w]);
    let mut rng = Rng(7);
    for i in 0..20_000 {
        let s = (i as f32 + 0.5) / 20_000.0;
        let target = Vec3::new(s, s, 0.0);
        let o = target + rng.dir() * 3.0 + Vec3::Z * 4.0;
        let ray = Ray::new(o, (target - o).normalize());
        assert!(
            b.intersect(&ray).is_some(),
            "ray {i} through the shared edge at {target:?} leaked"
        );
    }
}

#[test]
fn spawned_rays_do_not_self_intersect() {
    // A sphere far from the origin (large coordinates are where fixed epsilons fail).
    let big = shape(
        Geometry::Sphere {
            center: Vec3::new(1000.0, -2000.0, 500.0),
            radius: 3.0,
        },
        Affine3A::IDENTITY,
    );
    let rect = shape(
        Geometry::Rectangle,
        Affine3A::from_rotation_translation(Quat::from_rotation_y(0.3), Vec3::new(-400.0, 10.0, 7.0))
            * Affine3A::from_scale(Vec3::splat(50.0)),
    );
    let mesh = shape(
        Geometry::Mesh(Arc::new(quad_mesh(true, false))),
        Affine3A::from_translation(Vec3::new(123.0, 456.0, 789.0)),
    );
    let mut rng = Rng(11);
    let small = shape(
        Geometry::Sphere {
            center: Vec3::new(0.5, -1.0, 2.0),
            radius: 3.0,
        },
        Affine3A::IDENTITY,
    );
    for s in [big, small, rect, mesh] {
        let w = world(&s);
        let b = BruteForce::new(vec![w.clone()]);
        for _ in 0..5_000 {
            let p = sample_area(&w, rng.v2());
            let si = SurfaceInteraction {
                p: p.p,
                t: 0.0,
                n: p.n,
                shading: gonio_core::Frame::from_normal(p.ns),
                uv: p.uv,
                dpdu: Vec3::ZERO,
                dpdv: Vec3::ZERO,
                shape: 0,
                prim: 0,
                bary: glam::Vec2::ZERO,
            };
            let mut d = rng.dir();
            if d.dot(p.n) < 0.0 {
                d = -d;
            }
            // Leaving on the normal side: a convex or planar shape is never hit again.
            let r = si.spawn_ray(d);
            assert!(b.intersect(&r).is_none(), "self-hit at {:?} dir {d:?}", p.p);
            // Entering (refraction into a sphere): the hit is across the chord, not at the start.
            if matches!(s.geometry, Geometry::Sphere { .. }) {
                let r = si.spawn_ray(-d);
                let h = b.intersect(&r).expect("the inside of the sphere is hit");
                // The origin sits up to 256 ULPs (of the largest coordinate) inside the surface,
                // which moves the start of the chord by that much over the cosine.
                let cos = d.dot(p.n).abs();
                let chord = 2.0 * 3.0 * cos;
                let ulp = f32::EPSILON * p.p.abs().max_element();
                if cos > 0.05 {
                    let tol = 2.0 * 256.0 * ulp * 3f32.sqrt() / cos + 1e-4;
                    assert!(
                        (h.t - chord).abs() < tol,
                        "t = {} vs chord {chord} (tol {tol})",
                        h.t
                    );
                }
            }
        }
    }
}

/// Checks that `sample_solid_angle` draws points with the density `pdf_solid_angle` reports:
/// (1) ∫ pdf dω over the visible set = 1 (uniform directions, stratified), (2) for test functions
/// g, the importance estimate E[g/pdf] equals the uniform-direction estimate of ∫ g dω,
/// (3) each sample's pdf equals `pdf_solid_angle` at the point, which is visible from `r`.
fn check_sampling(w: &WorldShape, r: Vec3, first_hit_only: bool, label: &str) {
    let b = BruteForce::new(vec![w.clone()]);
    let mut rng = Rng(42);
    let gs: [fn(Vec3) -> f64; 3] = [
        |_| 1.0,
        |d| (d.x * d.x) as f64,
        |d| (d.y.max(0.0) + 0.1 * d.z) as f64,
    ];
    // (1) and the uniform estimates.
    let n_dir = 400_000;
    let mut pdf_sum = 0.0f64;
    let mut pdf_sq = 0.0f64;
    let mut g_uni = [0.0f64; 3];
    let mut g_uni_sq = [0.0f64; 3];
    for _ in 0..n_dir {
        let d = rng.dir();
        let ray = Ray::new(r, d);
        let mut acc = 0.0f64;
        if first_hit_only {
            if let Some(h) = b.intersect(&ray) {
                acc += pdf_solid_angle(w, r, &h) as f64;
            }
        } else {
            b.for_each_hit(&ray, &mut |h| {
                acc += pdf_solid_angle(w, r, h) as f64;
                false
            });
        }
        let x = acc * 4.0 * std::f64::consts::PI;
        pdf_sum += x;
        pdf_sq += x * x;
        // Points hit along d: the first only (cone sampling sees the front), or all of them
        // (area sampling draws hidden points too).
        let mut hits = 0usize;
        b.for_each_hit(&ray, &mut |_| {
            hits += 1;
            first_hit_only
        });
        if hits > 0 {
            for (k, g) in gs.iter().enumerate() {
                let v = g(d) * 4.0 * std::f64::consts::PI * hits as f64;
                g_uni[k] += v;
                g_uni_sq[k] += v * v;
            }
        }
    }
    let n = n_dir as f64;
    let mean = pdf_sum / n;
    let se = ((pdf_sq / n - mean * mean) / n).sqrt();
    assert!(
        (mean - 1.0).abs() < 4.0 * se + 2e-3,
        "{label}: ∫pdf = {mean} ± {se}"
    );
    // (2) and (3).
    let n_s = 200_000;
    let mut g_imp = [0.0f64; 3];
    let mut g_imp_sq = [0.0f64; 3];
    for i in 0..n_s {
        let Some(s) = sample_solid_angle(w, r, rng.v2()) else {
            continue;
        };
        let d = (s.p - r).normalize();
        if i % 16 == 0 {
            let h = b
                .intersect(&Ray::new(r, d))
                .unwrap_or_else(|| panic!("{label}: sample {:?} not hit from r", s.p));
            if first_hit_only || matches!(w.kind, gonio_render::geometry::ShapeKind::Rectangle { .. }) {
                assert!(
                    (h.p - s.p).length() < 1e-3 * (1.0 + (s.p - r).length()),
                    "{label}: sample hidden: {:?} vs {:?}",
                    h.p,
                    s.p
                );
                // The sample's normal and uv are those of the surface there (u may wrap at a seam).
                assert!(
                    (h.n - s.n).length() < 1e-4,
                    "{label}: normal {:?} vs {:?}",
                    s.n,
                    h.n
                );
                let du = (h.uv.x - s.uv.x).abs();
                assert!(
                    !(1e-3..=0.999).contains(&du) && (h.uv.y - s.uv.y).abs() < 1e-3,
                    "{label}: uv {:?} vs {:?}",
                    s.uv,
                    h.uv
                );
            }
            let mut hs = h;
            hs.p = s.p;
            hs.n = s.n;
            let q = pdf_solid_angle(w, r, &hs);
            assert!(
                (q - s.pdf).abs() <= 1e-3 * s.pdf,
                "{label}: sampled pdf {} vs pdf_solid_angle {q}",
                s.pdf
            );
        }
        for (k, g) in gs.iter().enumerate() {
            let v = g(d) / s.pdf as f64;
            g_imp[k] += v;
            g_imp_sq[k] += v * v;
        }
    }
    for k in 0..3 {
        let (m1, m2) = (g_uni[k] / n, g_imp[k] / n_s as f64);
        let v1 = (g_uni_sq[k] / n - m1 * m1) / n;
        let v2 = (g_imp_sq[k] / n_s as f64 - m2 * m2) / n_s as f64;
        let se = (v1 + v2).sqrt();
        assert!(
            (m1 - m2).abs() < 4.5 * se + 1e-6,
            "{label} g{k}: uniform {m1} vs importance {m2} (se {se})"
        );
    }
}

#[test]
fn sphere_cone_sampling_matches_its_pdf() {
    let w = world(&shape(
        Geometry::Sphere {
            center: Vec3::new(0.3, 0.2, 3.0),
            radius: 1.2,
        },
        Affine3A::IDENTITY,
    ));
    check_sampling(&w, Vec3::ZERO, true, "sphere near");
    // Far: the small-cone Taylor branch (sin²θmax < 6.9e-4).
    let far = world(&shape(
        Geometry::Sphere {
            center: Vec3::new(0.0, 30.0, 0.0),
            radius: 0.7,
        },
        Affine3A::IDENTITY,
    ));
    check_sampling(&far, Vec3::ZERO, true, "sphere far");
    // Inside: area sampling, every point visible.
    check_sampling(&w, Vec3::new(0.5, 0.0, 3.2), true, "sphere inside");
}

#[test]
fn spherical_rectangle_sampling_matches_its_pdf() {
    let m = Affine3A::from_rotation_translation(
        Quat::from_rotation_x(0.4) * Quat::from_rotation_z(0.3),
        Vec3::new(0.2, 0.1, 1.5),
    ) * Affine3A::from_scale(Vec3::new(1.0, 0.6, 1.0));
    let w = world(&shape(Geometry::Rectangle, m));
    check_sampling(&w, Vec3::ZERO, false, "rectangle front");
    check_sampling(&w, Vec3::new(0.3, 0.5, 3.0), false, "rectangle back side");
    // Mirrored (x scaled by −1) and flipped: uv and normal must still match the surface.
    let mut mirrored = shape(
        Geometry::Rectangle,
        m * Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
    );
    mirrored.flip_normals = true;
    check_sampling(
        &world(&mirrored),
        Vec3::new(-0.2, 0.1, 0.0),
        false,
        "rectangle mirrored, flipped",
    );
    // A sheared rectangle (parallelogram) falls back to area sampling.
    let shear = Affine3A::from_cols_array(&[1.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0]);
    check_sampling(
        &world(&shape(Geometry::Rectangle, shear)),
        Vec3::new(0.1, 0.0, 0.0),
        false,
        "parallelogram",
    );
}

#[test]
fn spherical_rectangle_is_uniform_in_solid_angle() {
    // The pdf is 1/Ω: Ω from the sampler must equal the solid angle from a fine quadrature.
    let w = world(&shape(
        Geometry::Rectangle,
        Affine3A::from_translation(Vec3::new(0.4, -0.2, 1.0)),
    ));
    let s = sample_solid_angle(&w, Vec3::ZERO, Vec2::new(0.3, 0.6)).unwrap();
    let omega = 1.0 / s.pdf as f64;
    let n = 2000;
    let mut quad = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let x = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64 + 0.4;
            let y = -1.0 + 2.0 * (j as f64 + 0.5) / n as f64 - 0.2;
            let d2 = x * x + y * y + 1.0;
            quad += (4.0 / (n * n) as f64) / (d2 * d2.sqrt());
        }
    }
    assert!(
        (omega - quad).abs() < 1e-4 * quad,
        "Ω sampler {omega} vs quadrature {quad}"
    );
}

#[test]
fn disk_and_mesh_area_sampling_match_their_pdf() {
    let d = world(&shape(
        Geometry::Disk,
        Affine3A::from_rotation_translation(Quat::from_rotation_y(0.7), Vec3::new(0.0, 0.5, 2.0)),
    ));
    check_sampling(&d, Vec3::ZERO, false, "disk");
    // A cube-like closed mesh: area sampling covers front and back faces (all hits counted).
    let mut m = quad_mesh(false, false);
    m.positions.extend([
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(3.0, 0.0, 1.0),
        Vec3::new(0.0, 1.0, 1.0),
    ]);
    m.indices.push([4, 5, 6]); // a second, larger triangle above: area weighting matters
    let w = world(&shape(
        Geometry::Mesh(Arc::new(m)),
        Affine3A::from_translation(Vec3::new(-0.5, -0.5, 1.0)),
    ));
    assert!((w.area() - 2.5).abs() < 1e-5);
    check_sampling(&w, Vec3::ZERO, false, "mesh");
}

#[test]
fn area_sampling_is_uniform_over_the_mesh() {
    // Triangle choice by area: the fraction of samples on each of two triangles of areas 1/2 and
    // 3/2 must be 1/4 and 3/4 (binomial 4σ).
    let mut m = quad_mesh(false, false);
    m.indices = vec![[0, 1, 2]];
    m.positions.extend([
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(3.0, 0.0, 1.0),
        Vec3::new(0.0, 1.0, 1.0),
    ]);
    m.indices.push([4, 5, 6]);
    let w = world(&shape(Geometry::Mesh(Arc::new(m)), Affine3A::IDENTITY));
    let mut rng = Rng(5);
    let n = 100_000;
    let mut upper = 0;
    let mut xs = 0.0f64;
    for _ in 0..n {
        let s = sample_area(&w, rng.v2());
        assert!((s.pdf - 0.5).abs() < 1e-6);
        if s.p.z > 0.5 {
            upper += 1;
            xs += s.p.x as f64;
        }
    }
    let f = upper as f64 / n as f64;
    let sd = (0.75 * 0.25 / n as f64).sqrt();
    assert!((f - 0.75).abs() < 4.0 * sd, "fraction {f}");
    // Uniform on the upper triangle (0,0)-(3,0)-(0,1): mean x = 1.
    let mx = xs / upper as f64;
    assert!((mx - 1.0).abs() < 0.02, "mean x {mx}");
}
