//! The `Accel` (obvhs BVH, or the flat list of small scenes) against the brute-force oracle on random mixed scenes.

use glam::{Affine3A, Quat, Vec3};
use gonio_core::hash::{GOLDEN_GAMMA, mix64, unit_f32};
use gonio_render::accel::{Accel, BruteForce, Intersect, embree};
use gonio_render::geometry::{Ray, SurfaceInteraction, WorldShape};
use gonio_render::scene::{Geometry, ShapeDesc, TriangleMesh};
use std::sync::Arc;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(GOLDEN_GAMMA);
        unit_f32(mix64(self.0))
    }
    fn range(&mut self, a: f32, b: f32) -> f32 {
        a + (b - a) * self.next()
    }
    fn v3(&mut self, a: f32, b: f32) -> Vec3 {
        Vec3::new(self.range(a, b), self.range(a, b), self.range(a, b))
    }
    fn dir(&mut self) -> Vec3 {
        let z = 1.0 - 2.0 * self.next();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * self.next();
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

fn random_scene(rng: &mut Rng) -> Vec<WorldShape> {
    let mut shapes = Vec::new();
    for _ in 0..6 {
        let c = rng.v3(-4.0, 4.0);
        shapes.push(shape(
            Geometry::Sphere {
                center: c,
                radius: rng.range(0.2, 1.0),
            },
            Affine3A::IDENTITY,
        ));
    }
    for _ in 0..4 {
        let q = Quat::from_scaled_axis(rng.v3(-2.0, 2.0));
        let m = Affine3A::from_scale_rotation_translation(
            Vec3::new(rng.range(0.3, 2.0), rng.range(0.3, 2.0), 1.0),
            q,
            rng.v3(-4.0, 4.0),
        );
        shapes.push(shape(Geometry::Rectangle, m));
        let m2 = Affine3A::from_scale_rotation_translation(
            Vec3::splat(rng.range(0.3, 1.5)),
            q.inverse(),
            rng.v3(-4.0, 4.0),
        );
        shapes.push(shape(Geometry::Disk, m2));
    }
    // A soup of 3000 random triangles and an axis-aligned quad (flat bounding box).
    let mut mesh = TriangleMesh::default();
    for i in 0..3000u32 {
        let c = rng.v3(-5.0, 5.0);
        for _ in 0..3 {
            mesh.positions.push(c + rng.v3(-0.4, 0.4));
        }
        mesh.indices.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    shapes.push(shape(Geometry::Mesh(Arc::new(mesh)), Affine3A::IDENTITY));
    let quad = TriangleMesh {
        positions: vec![
            Vec3::new(-6.0, -6.0, -5.5),
            Vec3::new(6.0, -6.0, -5.5),
            Vec3::new(6.0, 6.0, -5.5),
            Vec3::new(-6.0, 6.0, -5.5),
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Default::default()
    };
    shapes.push(shape(Geometry::Mesh(Arc::new(quad)), Affine3A::IDENTITY));
    world(&shapes)
}

/// The world-space shapes of `shapes`, each named by its index.
fn world(shapes: &[ShapeDesc]) -> Vec<WorldShape> {
    shapes
        .iter()
        .enumerate()
        .map(|(i, s)| WorldShape::from_scene(s, &i.to_string()).unwrap())
        .collect()
}

#[test]
fn accel_agrees_with_brute_force() {
    // With Embree (when the process has it) and with our own BVH for the triangles.
    for allow_embree in [true, false] {
        let accel = {
            let mut rng = Rng(1234);
            Accel::with_embree(random_scene(&mut rng), allow_embree)
        };
        assert_eq!(accel.uses_embree(), allow_embree && embree::available());
        accel_agrees_with_brute_force_on(&accel);
    }
}

/// `Accel::intersect_packet` (Embree's 16-ray packets for the triangles, the analytic shapes per
/// ray) answers every ray as `intersect` does: the same surface (but for a tie) at the same
/// distance, for full and partial packets, rays that end early, and rays with nothing to travel
/// (`tmax` 0).
#[test]
fn packet_queries_agree_with_single_ray_queries() {
    for allow_embree in [true, false] {
        let mut rng = Rng(1234);
        let accel = Accel::with_embree(random_scene(&mut rng), allow_embree);
        let rays: Vec<Ray> = (0..4099)
            .map(|i| {
                let mut ray = Ray::new(rng.v3(-7.0, 7.0), rng.dir());
                match i % 7 {
                    0 => ray.tmax = rng.range(0.5, 6.0),
                    1 if i % 2 == 0 => ray.tmax = 0.0,
                    _ => {}
                }
                ray
            })
            .collect();
        let mut out = vec![None; rays.len()];
        accel.intersect_packet(&rays, &mut out);
        // Two kernels may settle a tie (an edge two triangles share) differently.
        let mut count = HitCount::default();
        for (i, (ray, packet)) in rays.iter().zip(&out).enumerate() {
            count.add(same_closest_hit(i, ray, *packet, accel.intersect(ray), 1e-6));
        }
        assert!(
            count.hits > 1000,
            "the test scene should be hit often: {}",
            count.hits
        );
        assert!(count.ties < 5, "{}", count.ties);
    }
}

/// The lazy query of the volumetric path tracer (`intersect_lazy`, then `complete`) finds the
/// single-ray query's hit, with and without Embree, for rays of every length.
#[test]
fn lazy_queries_equal_single_ray_queries() {
    for allow_embree in [true, false] {
        let mut rng = Rng(4321);
        let accel = Accel::with_embree(random_scene(&mut rng), allow_embree);
        let mut hits = 0;
        for i in 0..2000 {
            let mut ray = Ray::new(rng.v3(-7.0, 7.0), rng.dir());
            if i % 3 == 0 {
                ray.tmax = rng.range(0.5, 6.0);
            }
            let lazy = accel.intersect_lazy(&ray);
            let eager = accel.intersect(&ray);
            assert_eq!(lazy.map(|h| h.t()), eager.map(|h| h.t), "ray {i}");
            assert_eq!(lazy.map(|h| accel.complete(&ray, h)), eager, "ray {i}");
            hits += eager.is_some() as u32;
        }
        assert!(hits > 500, "the test scene should be hit often: {hits}");
    }
}

/// `.ci/run` installs Embree: a CI run that fell back to our BVH would measure and test the
/// wrong path without saying so.
#[test]
fn embree_is_loaded_where_ci_installs_it() {
    if std::env::var_os("GONIO_REQUIRE_EMBREE").is_some() {
        assert!(
            embree::available(),
            "CI installs libembree3 (.ci/run), but it did not load"
        );
    }
    let mut rng = Rng(1234);
    let accel = Accel::new(random_scene(&mut rng));
    assert_eq!(accel.uses_embree(), embree::available());
}

fn accel_agrees_with_brute_force_on(accel: &Accel) {
    let mut rng = Rng(1234);
    let shapes = random_scene(&mut rng);
    let brute = BruteForce::new(shapes);
    assert_eq!(accel.prim_count(), 6 + 8 + 3000 + 2);
    let mut count = HitCount::default();
    for i in 0..20_000 {
        let o = rng.v3(-7.0, 7.0);
        let mut ray = Ray::new(o, rng.dir());
        if i % 3 == 0 {
            ray.tmax = rng.range(0.5, 6.0);
        }
        count.add(same_closest_hit(
            i,
            &ray,
            accel.intersect(&ray),
            brute.intersect(&ray),
            1e-5,
        ));
        assert_eq!(
            accel.occluded(&ray),
            brute.intersect(&ray).is_some(),
            "ray {i}: occluded"
        );
        if i % 10 == 0 {
            let mut ta = Vec::new();
            accel.for_each_hit(&ray, &mut |h| {
                ta.push((h.shape, h.prim));
                false
            });
            let mut tb = Vec::new();
            brute.for_each_hit(&ray, &mut |h| {
                tb.push((h.shape, h.prim));
                false
            });
            ta.sort();
            tb.sort();
            assert_eq!(ta, tb, "ray {i}: all hits");
        }
    }
    assert!(
        count.hits > 5000,
        "the test scene should be hit often: {}",
        count.hits
    );
    assert!(count.ties < 5, "{}", count.ties);
}

/// Hits and ties counted by [`same_closest_hit`].
#[derive(Default)]
struct HitCount {
    hits: usize,
    ties: usize,
}

impl HitCount {
    fn add(&mut self, (hit, tie): (bool, bool)) {
        self.hits += usize::from(hit);
        self.ties += usize::from(tie);
    }
}

/// Asserts that `a` (the query under test) and `b` (the one it must agree with) find the same
/// closest hit of ray `i`: both or neither, at the same distance (relative `t_tol`), on the same
/// primitive with the same point and normal, or on two primitives at the same distance (a tie,
/// within 10⁻⁶). Returns (a hit, a tie).
fn same_closest_hit(
    i: usize,
    ray: &Ray,
    a: Option<SurfaceInteraction>,
    b: Option<SurfaceInteraction>,
    t_tol: f32,
) -> (bool, bool) {
    match (a, b) {
        (None, None) => (false, false),
        (Some(a), Some(b)) => {
            assert!(
                (a.t - b.t).abs() <= t_tol * a.t.max(1.0),
                "ray {i}: t {} vs {}",
                a.t,
                b.t
            );
            if (a.shape, a.prim) != (b.shape, b.prim) {
                // Only acceptable when two primitives are hit at the same distance.
                assert!((a.t - b.t).abs() <= 1e-6 * a.t.max(1.0), "ray {i}: not a tie");
                (true, true)
            } else {
                assert!(
                    (a.p - b.p).length() < 1e-4 && (a.n - b.n).length() < 1e-5,
                    "ray {i}"
                );
                (true, false)
            }
        }
        (a, b) => panic!("ray {i} {ray:?}: {:?} vs {:?}", a.map(|h| h.t), b.map(|h| h.t)),
    }
}

#[test]
fn for_each_hit_stops_when_asked_and_passes_thin_sheets() {
    // Three parallel sheets along +z; a shadow ray that lets the first two through (like
    // thindielectric) and stops at the third.
    let sheets: Vec<WorldShape> = (0..3)
        .map(|k| {
            WorldShape::from_scene(
                &shape(
                    Geometry::Rectangle,
                    Affine3A::from_translation(Vec3::Z * (k as f32 + 1.0)),
                ),
                "s",
            )
            .unwrap()
        })
        .collect();
    let accel = Accel::new(sheets);
    let ray = Ray::new(Vec3::new(0.1, 0.2, 0.0), Vec3::Z);
    let mut transmittance = 1.0f32;
    let mut seen = 0;
    let stopped = accel.for_each_hit(&ray, &mut |h| {
        seen += 1;
        if h.shape == 2 {
            return true;
        }
        transmittance *= 0.5;
        false
    });
    assert!(stopped);
    // Hit order is unspecified; with the stop at shape 2 we see between 1 and 3 hits.
    assert!((1..=3).contains(&seen));
    let short = Ray { tmax: 2.5, ..ray };
    let mut t = 1.0f32;
    let stopped = accel.for_each_hit(&short, &mut |h| {
        assert!(h.shape < 2, "beyond tmax");
        t *= 0.5;
        false
    });
    assert!(!stopped && t == 0.25, "two sheets passed: {t}");
}

#[test]
fn empty_scene_hits_nothing() {
    let accel = Accel::new(Vec::new());
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    assert!(accel.intersect(&ray).is_none() && !accel.occluded(&ray));
    assert!(!accel.for_each_hit(&ray, &mut |_| true));
}

#[test]
fn shadow_rays_between_surfaces_see_neither_endpoint_surface() {
    // An empty box of five rectangles (open front) and a sphere in a corner touching nothing:
    // segments between random points on different faces must not be occluded by the faces they
    // start and end on, including near the shared edges where rays graze.
    use gonio_render::geometry::sampling::sample_area;
    use gonio_render::geometry::spawn_ray_between;
    use std::f32::consts::FRAC_PI_2;
    let faces = [
        Affine3A::from_translation(Vec3::new(0.0, -1.0, 0.0)) * Affine3A::from_rotation_x(-FRAC_PI_2),
        Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0)) * Affine3A::from_rotation_x(FRAC_PI_2),
        Affine3A::from_translation(Vec3::new(0.0, 0.0, -1.0)),
        Affine3A::from_translation(Vec3::new(-1.0, 0.0, 0.0)) * Affine3A::from_rotation_y(FRAC_PI_2),
        Affine3A::from_translation(Vec3::new(1.0, 0.0, 0.0)) * Affine3A::from_rotation_y(-FRAC_PI_2),
    ];
    let shapes: Vec<WorldShape> = faces
        .iter()
        .map(|&m| WorldShape::from_scene(&shape(Geometry::Rectangle, m), "face").unwrap())
        .collect();
    let accel = Accel::new(shapes.clone());
    let mut rng = Rng(77);
    let mut tested = 0;
    for _ in 0..50_000 {
        let i = (rng.next() * 5.0) as usize % 5;
        let j = (i + 1 + (rng.next() * 4.0) as usize % 4) % 5;
        // Squash samples towards the edges half of the time.
        let mut u = glam::Vec2::new(rng.next(), rng.next());
        if rng.next() < 0.5 {
            u = u.map(|v| {
                if v < 0.5 {
                    (2.0 * v).powi(6) * 0.5
                } else {
                    1.0 - (2.0 * (1.0 - v)).powi(6) * 0.5
                }
            });
        }
        let a = sample_area(&shapes[i], u);
        let b = sample_area(&shapes[j], glam::Vec2::new(rng.next(), rng.next()));
        // Both normals point into the box (rectangles face +z, rotated inwards).
        if (b.p - a.p).dot(a.n) <= 0.0 || (a.p - b.p).dot(b.n) <= 0.0 {
            continue;
        }
        let ray = spawn_ray_between(a.p, a.n, b.p, Some(b.n));
        assert!(
            !accel.occluded(&ray),
            "face {i} {:?} → face {j} {:?} occluded",
            a.p,
            b.p
        );
        tested += 1;
    }
    assert!(tested > 20_000, "{tested}");
}

/// Directions with exactly-zero components, of both signs: the six axes and the twelve diagonals
/// of the coordinate planes, and a few with tiny components. A negated axis direction such as `-(0, 0, -1)` carries `-0.0`
/// components, which is how a shadow ray towards a straight-down directional light is made.
fn axis_aligned_directions() -> Vec<Vec3> {
    let mut dirs = Vec::new();
    for axis in 0..3 {
        for s in [1.0f32, -1.0] {
            let mut d = Vec3::ZERO;
            d[axis] = s;
            dirs.push(d);
            dirs.push(-d); // -0.0 in the other two components
            let mut e = Vec3::splat(-0.0);
            e[axis] = s;
            dirs.push(e);
        }
    }
    let h = std::f32::consts::FRAC_1_SQRT_2;
    for zero in 0..3 {
        for (sa, sb) in [(1.0f32, 1.0f32), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
            for z in [0.0f32, -0.0] {
                let mut d = Vec3::ZERO;
                d[zero] = z;
                d[(zero + 1) % 3] = sa * h;
                d[(zero + 2) % 3] = sb * h;
                dirs.push(d);
            }
        }
    }
    // Tiny components, which a slab test must not round to a narrower slab.
    for tiny in [1e-9f32, -1e-9, 1e-30, -1e-30] {
        dirs.push(Vec3::new(tiny, -tiny, 1.0));
        dirs.push(Vec3::new(-1.0, tiny, tiny));
    }
    dirs
}

#[test]
fn axis_aligned_rays_agree_with_brute_force_for_every_query() {
    let mut rng = Rng(4321);
    let shapes = random_scene(&mut rng);
    let accel = Accel::new(shapes.clone());
    let brute = BruteForce::new(shapes);
    let dirs = axis_aligned_directions();
    let (mut hits, mut occluded) = (0, 0);
    for i in 0..6000 {
        let d = dirs[i % dirs.len()];
        let mut ray = Ray::new(rng.v3(-7.0, 7.0), d);
        if i % 3 == 0 {
            ray.tmax = rng.range(0.5, 6.0);
        }
        let a = accel.intersect(&ray).map(|h| (h.t, h.shape, h.prim));
        let b = brute.intersect(&ray).map(|h| (h.t, h.shape, h.prim));
        match (a, b) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                hits += 1;
                assert!(
                    (a.0 - b.0).abs() <= 1e-5 * a.0.max(1.0),
                    "ray {i} {ray:?}: {a:?} vs {b:?}"
                );
            }
            _ => panic!("closest hit, ray {i} {ray:?}: accel {a:?} vs brute {b:?}"),
        }
        let occ = accel.occluded(&ray);
        assert_eq!(occ, b.is_some(), "occlusion, ray {i} {ray:?}");
        occluded += occ as u32;
        let mut ta = Vec::new();
        accel.for_each_hit(&ray, &mut |h| {
            ta.push((h.shape, h.prim));
            false
        });
        let mut tb = Vec::new();
        brute.for_each_hit(&ray, &mut |h| {
            tb.push((h.shape, h.prim));
            false
        });
        ta.sort();
        tb.sort();
        assert_eq!(ta, tb, "any-hit, ray {i} {ray:?}");
    }
    assert!(
        hits > 1500 && occluded > 1500,
        "the scene should be hit often: {hits}"
    );
}

#[test]
fn straight_up_shadow_ray_is_blocked_by_a_sphere_above() {
    // The shadow ray towards a directional light with direction (0, 0, -1) is -(0, 0, -1),
    // whose x and y are -0.0; a unit sphere above the origin must block it.
    let sphere = shape(
        Geometry::Sphere {
            center: Vec3::new(0.0, 0.0, 3.0),
            radius: 1.0,
        },
        Affine3A::IDENTITY,
    );
    let ground = shape(
        Geometry::Rectangle,
        Affine3A::from_scale(Vec3::new(10.0, 10.0, 1.0)),
    );
    let shapes: Vec<WorldShape> = [sphere, ground]
        .iter()
        .map(|s| WorldShape::from_scene(s, "s").unwrap())
        .collect();
    let accel = Accel::new(shapes);
    for o in [Vec3::new(0.0, 0.0, 1e-4), Vec3::new(0.3, -0.2, 1e-4)] {
        let ray = Ray::new(o, -Vec3::new(0.0, 0.0, -1.0));
        assert!(ray.d.x.is_sign_negative() && ray.d.y.is_sign_negative());
        assert!(accel.occluded(&ray), "occlusion from {o}");
        assert_eq!(
            accel.intersect(&ray).map(|h| h.shape),
            Some(0),
            "closest hit from {o}"
        );
        assert!(
            accel.for_each_hit(&ray, &mut |h| h.shape == 0),
            "any-hit from {o}"
        );
    }
}

/// A scene of `n_tris + 8` primitives: 3 spheres, 2 rectangles, 2 disks, an axis-aligned
/// triangle (flat box) and `n_tris` random triangles — small enough for the flat list when
/// `n_tris <= 8`, the BVH above. `None`: the 7 analytic shapes alone, no mesh.
fn small_scene(rng: &mut Rng, n_tris: Option<u32>) -> Vec<WorldShape> {
    let mut shapes = Vec::new();
    for _ in 0..3 {
        let (c, r) = (rng.v3(-3.0, 3.0), rng.range(0.3, 1.2));
        shapes.push(shape(
            Geometry::Sphere { center: c, radius: r },
            Affine3A::IDENTITY,
        ));
    }
    for g in [
        Geometry::Rectangle,
        Geometry::Rectangle,
        Geometry::Disk,
        Geometry::Disk,
    ] {
        let q = Quat::from_scaled_axis(rng.v3(-2.0, 2.0));
        let m =
            Affine3A::from_scale_rotation_translation(Vec3::splat(rng.range(0.5, 2.0)), q, rng.v3(-3.0, 3.0));
        shapes.push(shape(g, m));
    }
    let Some(n_tris) = n_tris else {
        return world(&shapes);
    };
    let mut mesh = TriangleMesh {
        positions: vec![
            Vec3::new(-4.0, -4.0, -3.5),
            Vec3::new(4.0, -4.0, -3.5),
            Vec3::new(0.0, 4.0, -3.5),
        ],
        indices: vec![[0, 1, 2]],
        ..Default::default()
    };
    for i in 1..=n_tris {
        let c = rng.v3(-3.0, 3.0);
        for _ in 0..3 {
            mesh.positions.push(c + rng.v3(-1.0, 1.0));
        }
        mesh.indices.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    shapes.push(shape(Geometry::Mesh(Arc::new(mesh)), Affine3A::IDENTITY));
    world(&shapes)
}

/// Ray `i` of the small-scene tests: from a random point of the scenes' cube, in a random
/// direction (even `i`) or along one of `dirs` (odd), every third one short.
fn mixed_ray(rng: &mut Rng, dirs: &[Vec3], i: usize) -> Ray {
    let d = if i.is_multiple_of(2) {
        rng.dir()
    } else {
        dirs[(i / 2) % dirs.len()]
    };
    let mut ray = Ray::new(rng.v3(-3.5, 3.5), d);
    if i.is_multiple_of(3) {
        ray.tmax = rng.range(0.5, 6.0);
    }
    ray
}

#[test]
fn small_scenes_agree_with_brute_force_on_both_sides_of_the_flat_list_limit() {
    // 15 and 16 primitives take the flat list, 17 the BVH; random and axis-aligned rays,
    // every query, against the oracle. Analytic shapes alone (7) take the flat list without the
    // triangle test's ray set-up.
    let dirs = axis_aligned_directions();
    for (seed, n_tris) in [(11u64, Some(7u32)), (12, Some(8)), (13, Some(9)), (14, None)] {
        let mut rng = Rng(seed);
        let shapes = small_scene(&mut rng, n_tris);
        let accel = Accel::new(shapes.clone());
        let brute = BruteForce::new(shapes);
        assert_eq!(accel.prim_count(), n_tris.map_or(7, |n| n as usize + 8));
        let (mut hits, mut misses) = (0, 0);
        for i in 0..6000 {
            let ray = mixed_ray(&mut rng, &dirs, i);
            let a = accel.intersect(&ray).map(|h| (h.t, h.shape, h.prim));
            let b = brute.intersect(&ray).map(|h| (h.t, h.shape, h.prim));
            match (a, b) {
                (None, None) => misses += 1,
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert!(
                        (a.0 - b.0).abs() <= 1e-5 * a.0.max(1.0),
                        "{n_tris:?} triangles, ray {i} {ray:?}: {a:?} vs {b:?}"
                    );
                }
                _ => panic!("{n_tris:?} triangles, closest hit, ray {i} {ray:?}: accel {a:?} vs brute {b:?}"),
            }
            assert_eq!(
                accel.occluded(&ray),
                b.is_some(),
                "{n_tris:?} triangles, occlusion, ray {i} {ray:?}"
            );
            let mut ta = Vec::new();
            accel.for_each_hit(&ray, &mut |h| {
                ta.push((h.shape, h.prim));
                false
            });
            let mut tb = Vec::new();
            brute.for_each_hit(&ray, &mut |h| {
                tb.push((h.shape, h.prim));
                false
            });
            ta.sort();
            tb.sort();
            assert_eq!(ta, tb, "{n_tris:?} triangles, any-hit, ray {i} {ray:?}");
        }
        assert!(
            hits > 600 && misses > 600,
            "{n_tris:?} triangles: {hits} hits, {misses} misses"
        );
    }
}

/// A scene for the flat list's lanes: `spheres` spheres and `planes` rectangles and disks
/// (alternating), randomly placed, and one triangle.
fn lane_scene(rng: &mut Rng, spheres: usize, planes: usize) -> Vec<WorldShape> {
    let mut shapes: Vec<ShapeDesc> = (0..spheres)
        .map(|_| {
            let (c, r) = (rng.v3(-3.0, 3.0), rng.range(0.2, 0.9));
            shape(Geometry::Sphere { center: c, radius: r }, Affine3A::IDENTITY)
        })
        .collect();
    for i in 0..planes {
        let q = Quat::from_scaled_axis(rng.v3(-2.0, 2.0));
        let m = Affine3A::from_scale_rotation_translation(
            Vec3::new(rng.range(0.4, 1.5), rng.range(0.4, 1.5), 1.0),
            q,
            rng.v3(-3.0, 3.0),
        );
        let g = if i.is_multiple_of(2) {
            Geometry::Rectangle
        } else {
            Geometry::Disk
        };
        shapes.push(shape(g, m));
    }
    let mesh = TriangleMesh {
        positions: vec![rng.v3(-3.0, 3.0), rng.v3(-3.0, 3.0), rng.v3(-3.0, 3.0)],
        indices: vec![[0, 1, 2]],
        ..Default::default()
    };
    shapes.push(shape(Geometry::Mesh(Arc::new(mesh)), Affine3A::IDENTITY));
    world(&shapes)
}

/// A scene made from a seeded generator.
type SceneMaker = fn(&mut Rng) -> Vec<WorldShape>;

#[test]
fn flat_list_lanes_find_the_scalar_tests_hits_bit_for_bit() {
    // The flat list tests spheres, and rectangles and disks, four at a time in lanes with the
    // scalar tests' arithmetic: the same primitive must come out at the same distance, point
    // and surface coordinates, to the bit (the brute force runs the scalar tests), and a ray
    // must be occluded exactly when it hits. Scenes with one chunk of each kind, and with
    // several chunks (the distance found in one bounds the next), full and partial. Rays from
    // inside and outside the shapes, random and axis-aligned directions, short and unbounded;
    // also rays from points on the shapes (the next segment of a path).
    let dirs = axis_aligned_directions();
    let scenes: [(u64, SceneMaker); 5] = [
        (21, |r| small_scene(r, Some(8))),
        (22, |r| small_scene(r, Some(3))),
        (23, |r| small_scene(r, None)),
        (24, |r| lane_scene(r, 7, 6)),
        (25, |r| lane_scene(r, 9, 5)),
    ];
    for (seed, make) in scenes {
        let mut rng = Rng(seed);
        let shapes = make(&mut rng);
        let accel = Accel::new(shapes.clone());
        assert!(accel.prim_count() <= 16, "the flat list's size");
        let brute = BruteForce::new(shapes);
        let (mut same, mut ties) = (0, 0);
        for i in 0..8000 {
            let ray = mixed_ray(&mut rng, &dirs, i);
            let from_surface = brute.intersect(&ray).map(|h| h.spawn_ray(rng.dir()));
            for ray in std::iter::once(ray).chain(from_surface) {
                let (a, b) = (accel.intersect(&ray), brute.intersect(&ray));
                assert_eq!(a.is_some(), b.is_some(), "seed {seed}, ray {i} {ray:?}");
                assert_eq!(
                    accel.occluded(&ray),
                    b.is_some(),
                    "seed {seed}, ray {i}: occlusion"
                );
                let (Some(a), Some(b)) = (a, b) else { continue };
                if (a.shape, a.prim) != (b.shape, b.prim) {
                    // Two primitives at exactly the same distance: the lanes take the first
                    // tested, the brute force the first in scene order.
                    assert_eq!(a.t.to_bits(), b.t.to_bits(), "seed {seed}, ray {i}: not a tie");
                    ties += 1;
                    continue;
                }
                // uv: a rectangle's or disk's comes straight from the lane's object-space (x, y).
                let bits = |h: &SurfaceInteraction| {
                    (
                        h.t.to_bits(),
                        h.p.to_array().map(f32::to_bits),
                        h.uv.to_array().map(f32::to_bits),
                        h.bary.to_array().map(f32::to_bits),
                    )
                };
                assert_eq!(
                    bits(&a),
                    bits(&b),
                    "seed {seed}, ray {i} {ray:?}: shape {} primitive {}",
                    a.shape,
                    a.prim
                );
                same += 1;
            }
        }
        assert!(
            same > 1000 && ties < 10,
            "seed {seed}: {same} hits compared, {ties} ties"
        );
    }
}

mod instancing;
