//! Accel build time and ray throughput on a 1.3M-triangle mesh (an icosphere subdivided 8 times)
//! plus analytic shapes. `cargo bench -p gonio-render --bench accel`.
//!
//! * `build`: BVH construction for the mesh (single thread; obvhs without its `parallel` feature).
//! * `closest_coherent`: camera-like rays from outside, in scanline order (one 512×512 image).
//! * `closest_incoherent`: from random points inside the sphere in random directions, random
//!   order (what secondary bounces look like).
//! * `occluded_incoherent`: the same rays as shadow rays (any hit ends the query).
//! * `closest_coherent_packets`, `closest_incoherent_packets`: the same rays 16 at a time
//!   (`Accel::intersect_packet`: Embree's packet query for the triangles). `ICO=n` in the
//!   environment subdivides the icosphere `n` times instead of 8.
//!
//! Throughput is printed by divan as items (rays) per second, single thread.

use glam::{Affine3A, Vec3};
use gonio_core::hash::{GOLDEN_GAMMA, mix64, unit_f32};
use gonio_render::accel::{Accel, Intersect};
use gonio_render::geometry::{Ray, WorldShape};
use gonio_render::scene::{Geometry, ShapeDesc, TriangleMesh};
use std::collections::HashMap;
use std::sync::{Arc, OnceLock};

fn main() {
    divan::main();
}

/// An icosphere of radius 1 with `levels` subdivisions (20·4^levels triangles).
fn icosphere(levels: u32) -> TriangleMesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut indices: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut cache: HashMap<(u32, u32), u32> = HashMap::with_capacity(indices.len() * 2);
        let mut mid = |a: u32, b: u32, positions: &mut Vec<Vec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *cache.entry(key).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) * 0.5).normalize());
                positions.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(indices.len() * 4);
        for [a, b, c] in indices {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        indices = next;
    }
    TriangleMesh {
        positions,
        indices,
        ..Default::default()
    }
}

fn shapes() -> &'static Vec<WorldShape> {
    static S: OnceLock<Vec<WorldShape>> = OnceLock::new();
    S.get_or_init(|| {
        let mesh = icosphere(
            std::env::var("ICO")
                .ok()
                .and_then(|v| v.parse().ok())
                .unwrap_or(8),
        );
        let mk = |geometry, to_world| ShapeDesc {
            geometry,
            to_world,
            flip_normals: false,
            face_normals: false,
            outside_only: false,
            media: Default::default(),
            material: 0,
            emitter: None,
            id: None,
        };
        let list = [
            mk(Geometry::Mesh(Arc::new(mesh)), Affine3A::IDENTITY),
            mk(
                Geometry::Sphere {
                    center: Vec3::new(0.3, 0.1, 0.2),
                    radius: 0.2,
                },
                Affine3A::IDENTITY,
            ),
            mk(
                Geometry::Rectangle,
                Affine3A::from_translation(Vec3::new(0.0, -0.5, 0.0))
                    * Affine3A::from_scale(Vec3::splat(0.3)),
            ),
        ];
        list.iter()
            .map(|s| WorldShape::from_scene(s, "bench").unwrap())
            .collect()
    })
}

fn accel() -> &'static Accel {
    static A: OnceLock<Accel> = OnceLock::new();
    A.get_or_init(|| {
        let a = Accel::new(shapes().clone());
        eprintln!(
            "accel: {} primitives, built in {:?}",
            a.prim_count(),
            a.build_time()
        );
        a
    })
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(GOLDEN_GAMMA);
        unit_f32(mix64(self.0))
    }
    fn dir(&mut self) -> Vec3 {
        let z = 1.0 - 2.0 * self.next();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * self.next();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

const N_RAYS: usize = 262_144;

fn coherent_rays() -> &'static Vec<Ray> {
    static R: OnceLock<Vec<Ray>> = OnceLock::new();
    R.get_or_init(|| {
        let o = Vec3::new(0.0, 0.0, 3.0);
        (0..N_RAYS)
            .map(|i| {
                let (x, y) = ((i % 512) as f32 / 512.0, (i / 512) as f32 / 512.0);
                let d = Vec3::new((x - 0.5) * 0.8, (0.5 - y) * 0.8, -1.0).normalize();
                Ray::new(o, d)
            })
            .collect()
    })
}

fn incoherent_rays() -> &'static Vec<Ray> {
    static R: OnceLock<Vec<Ray>> = OnceLock::new();
    R.get_or_init(|| {
        let mut rng = Rng(3);
        (0..N_RAYS)
            .map(|_| Ray::new(rng.dir() * 0.9 * rng.next().cbrt(), rng.dir()))
            .collect()
    })
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn build(bencher: divan::Bencher) {
    let s = shapes();
    bencher
        .counter(divan::counter::ItemsCount::new(accel().prim_count()))
        .bench(|| Accel::new(s.clone()));
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn closest_coherent(bencher: divan::Bencher) {
    let (a, rays) = (accel(), coherent_rays());
    bencher
        .counter(divan::counter::ItemsCount::new(rays.len()))
        .bench(|| rays.iter().filter(|r| a.intersect(r).is_some()).count());
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn closest_incoherent(bencher: divan::Bencher) {
    let (a, rays) = (accel(), incoherent_rays());
    bencher
        .counter(divan::counter::ItemsCount::new(rays.len()))
        .bench(|| rays.iter().filter(|r| a.intersect(r).is_some()).count());
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn closest_coherent_packets(bencher: divan::Bencher) {
    packets(bencher, coherent_rays());
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn closest_incoherent_packets(bencher: divan::Bencher) {
    packets(bencher, incoherent_rays());
}

/// `rays` 16 at a time through `Accel::intersect_packet`.
fn packets(bencher: divan::Bencher, rays: &[Ray]) {
    let a = accel();
    let mut out = vec![None; 16];
    bencher
        .counter(divan::counter::ItemsCount::new(rays.len()))
        .bench_local(|| {
            rays.chunks(16)
                .map(|r| {
                    a.intersect_packet(r, &mut out[..r.len()]);
                    out.iter().filter(|h| h.is_some()).count()
                })
                .sum::<usize>()
        });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn occluded_incoherent(bencher: divan::Bencher) {
    let (a, rays) = (accel(), incoherent_rays());
    bencher
        .counter(divan::counter::ItemsCount::new(rays.len()))
        .bench(|| rays.iter().filter(|r| a.occluded(r)).count());
}

/// A Cornell box like `cornell-spheres.xml`: 6 rectangles (walls and light) and 2 spheres.
fn cornell() -> &'static Vec<WorldShape> {
    static S: OnceLock<Vec<WorldShape>> = OnceLock::new();
    S.get_or_init(|| {
        use std::f32::consts::FRAC_PI_2;
        let mk = |geometry, to_world| ShapeDesc {
            geometry,
            to_world,
            flip_normals: false,
            face_normals: false,
            outside_only: false,
            media: Default::default(),
            material: 0,
            emitter: None,
            id: None,
        };
        let list = [
            mk(
                Geometry::Rectangle,
                Affine3A::from_translation(Vec3::new(0.0, -1.0, 0.0)) * Affine3A::from_rotation_x(-FRAC_PI_2),
            ),
            mk(
                Geometry::Rectangle,
                Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0)) * Affine3A::from_rotation_x(FRAC_PI_2),
            ),
            mk(
                Geometry::Rectangle,
                Affine3A::from_translation(Vec3::new(0.0, 0.0, -1.0)),
            ),
            mk(
                Geometry::Rectangle,
                Affine3A::from_translation(Vec3::new(-1.0, 0.0, 0.0)) * Affine3A::from_rotation_y(FRAC_PI_2),
            ),
            mk(
                Geometry::Rectangle,
                Affine3A::from_translation(Vec3::new(1.0, 0.0, 0.0)) * Affine3A::from_rotation_y(-FRAC_PI_2),
            ),
            mk(
                Geometry::Rectangle,
                Affine3A::from_translation(Vec3::new(0.0, 0.99, 0.0))
                    * Affine3A::from_rotation_x(FRAC_PI_2)
                    * Affine3A::from_scale(Vec3::splat(0.25)),
            ),
            mk(
                Geometry::Sphere {
                    center: Vec3::new(-0.4, -0.6, -0.3),
                    radius: 0.4,
                },
                Affine3A::IDENTITY,
            ),
            mk(
                Geometry::Sphere {
                    center: Vec3::new(0.45, -0.6, 0.3),
                    radius: 0.4,
                },
                Affine3A::IDENTITY,
            ),
        ];
        list.iter()
            .map(|s| WorldShape::from_scene(s, "cornell").unwrap())
            .collect()
    })
}

fn cornell_rays() -> &'static Vec<Ray> {
    static R: OnceLock<Vec<Ray>> = OnceLock::new();
    R.get_or_init(|| {
        let mut rng = Rng(9);
        (0..N_RAYS / 4)
            .map(|_| {
                Ray::new(
                    (Vec3::new(rng.next(), rng.next(), rng.next()) * 1.8 - 0.9) * 0.95,
                    rng.dir(),
                )
            })
            .collect()
    })
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn cornell_closest_accel(bencher: divan::Bencher) {
    let a = Accel::new(cornell().clone());
    let rays = cornell_rays();
    bencher
        .counter(divan::counter::ItemsCount::new(rays.len()))
        .bench(|| rays.iter().filter(|r| a.intersect(r).is_some()).count());
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn cornell_closest_brute_force(bencher: divan::Bencher) {
    let a = gonio_render::accel::BruteForce::new(cornell().clone());
    let rays = cornell_rays();
    bencher
        .counter(divan::counter::ItemsCount::new(rays.len()))
        .bench(|| rays.iter().filter(|r| a.intersect(r).is_some()).count());
}

/// Baseline: obvhs on its own (its triangle type and Möller–Trumbore test, hit distance only,
/// no hit record), same mesh, same BVH settings: the cost of our wrapper is the difference.
fn native() -> &'static (obvhs::cwbvh::CwBvh, Vec<obvhs::triangle::Triangle>) {
    static N: OnceLock<(obvhs::cwbvh::CwBvh, Vec<obvhs::triangle::Triangle>)> = OnceLock::new();
    N.get_or_init(|| {
        let gonio_render::geometry::ShapeKind::Mesh(m) = &shapes()[0].kind else {
            unreachable!()
        };
        let tris: Vec<obvhs::triangle::Triangle> = (0..m.indices.len())
            .map(|i| {
                let [a, b, c] = m.tri(i);
                obvhs::triangle::Triangle {
                    v0: a.into(),
                    v1: b.into(),
                    v2: c.into(),
                }
            })
            .collect();
        let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(
            &tris,
            obvhs::BvhBuildParams::medium_build(),
            &mut std::time::Duration::default(),
        );
        let ordered = bvh.primitive_indices.iter().map(|&i| tris[i as usize]).collect();
        (bvh, ordered)
    })
}

fn native_closest(rays: &[Ray]) -> usize {
    let (bvh, tris) = native();
    rays.iter()
        .filter(|r| {
            let ray = obvhs::ray::Ray::new(r.o.into(), r.d.into(), 0.0, r.tmax);
            let mut hit = obvhs::ray::RayHit::none();
            bvh.ray_traverse(ray, &mut hit, |ray, id| tris[id].intersect(ray))
        })
        .count()
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn native_obvhs_closest_coherent(bencher: divan::Bencher) {
    native();
    let rays = coherent_rays();
    bencher
        .counter(divan::counter::ItemsCount::new(rays.len()))
        .bench(|| native_closest(rays));
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn native_obvhs_closest_incoherent(bencher: divan::Bencher) {
    native();
    let rays = incoherent_rays();
    bencher
        .counter(divan::counter::ItemsCount::new(rays.len()))
        .bench(|| native_closest(rays));
}
