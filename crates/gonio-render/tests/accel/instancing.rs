//! Instancing (`shapegroup` + `instance`): the two-level BVH against the same geometry placed flat.

use super::*;
use gonio_render::geometry::ShapeKind;
use gonio_render::geometry::instance::ShapeGroup;
use gonio_render::plugins::shape::instance::expand;

/// A group (group space) of a cube mesh with vertex normals and uvs, a rectangle and a disk.
fn group_shapes() -> Vec<ShapeDesc> {
    let mut cube = gonio_render::mesh::cube();
    cube.normals = gonio_render::mesh::vertex_normals(&cube);
    cube.uvs = cube.positions.iter().map(|p| glam::Vec2::new(p.x, p.y)).collect();
    let mut flipped = shape(
        Geometry::Rectangle,
        Affine3A::from_scale_rotation_translation(
            Vec3::new(1.5, 0.7, 1.0),
            Quat::from_rotation_x(0.4),
            Vec3::new(0.3, 0.0, 2.0),
        ),
    );
    flipped.flip_normals = true;
    flipped.material = 1;
    let mut disk = shape(
        Geometry::Disk,
        Affine3A::from_translation(Vec3::new(-2.0, 0.5, 0.0)),
    );
    disk.material = 2;
    vec![
        shape(
            Geometry::Mesh(Arc::new(cube)),
            Affine3A::from_scale(Vec3::splat(0.8)),
        ),
        flipped,
        disk,
    ]
}

fn placements(rng: &mut Rng) -> Vec<Affine3A> {
    (0..5)
        .map(|i| {
            let scale = if i == 0 {
                Vec3::ONE
            } else {
                Vec3::new(rng.range(0.4, 1.8), rng.range(0.4, 1.8), rng.range(0.4, 1.8))
            };
            let shear = Affine3A::from_cols_array(&[
                1.0,
                0.0,
                0.0,
                0.3 * (i % 2) as f32,
                1.0,
                0.0,
                0.0,
                0.0,
                1.0,
                0.0,
                0.0,
                0.0,
            ]);
            Affine3A::from_scale_rotation_translation(
                scale,
                Quat::from_scaled_axis(rng.v3(-2.0, 2.0)),
                rng.v3(-5.0, 5.0),
            ) * shear
        })
        .collect()
}

/// The instanced scene (expanded as the reader does) and the same shapes placed flat.
fn scenes(rng: &mut Rng) -> (Vec<ShapeDesc>, Vec<ShapeDesc>) {
    let members = group_shapes();
    let group = Arc::new(ShapeGroup::new("g".into(), members.clone()));
    let (mut instanced, mut flat) = (Vec::new(), Vec::new());
    for m in placements(rng) {
        let inst = ShapeDesc {
            geometry: Geometry::Instance {
                group: group.clone(),
                member: None,
            },
            ..shape(Geometry::Disk, m)
        };
        expand(inst, &mut instanced);
        for s in &members {
            flat.push(ShapeDesc {
                to_world: m * s.to_world,
                ..s.clone()
            });
        }
    }
    (instanced, flat)
}

fn world(descs: &[ShapeDesc]) -> Vec<WorldShape> {
    descs
        .iter()
        .enumerate()
        .map(|(i, s)| WorldShape::from_scene(s, &i.to_string()).unwrap())
        .collect()
}

#[test]
fn instances_agree_with_the_same_geometry_placed_flat() {
    let mut rng = Rng(77);
    let (instanced, flat) = scenes(&mut rng);
    assert_eq!(instanced.len(), flat.len());
    // Each member keeps its own material.
    for (a, b) in instanced.iter().zip(&flat) {
        assert_eq!(a.material, b.material);
    }
    let inst = Accel::new(world(&instanced));
    let flat = BruteForce::new(world(&flat));
    let mut dirs = axis_aligned_directions();
    for _ in 0..4000 {
        dirs.push(rng.dir());
    }
    let mut hits = 0;
    for (i, d) in dirs.iter().enumerate() {
        for k in 0..3 {
            let o = rng.v3(-7.0, 7.0);
            let mut ray = Ray::new(o, d.normalize());
            if k == 2 {
                ray.tmax = rng.range(0.5, 8.0);
            }
            let (a, b) = (inst.intersect(&ray), flat.intersect(&ray));
            assert_eq!(inst.occluded(&ray), flat.occluded(&ray), "ray {i}/{k}");
            match (a, b) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    hits += 1;
                    let tol = 2e-4 * a.t.max(1.0);
                    assert!((a.t - b.t).abs() <= tol, "ray {i}/{k}: t {} vs {}", a.t, b.t);
                    if a.shape == b.shape {
                        assert!((a.p - b.p).length() <= tol, "{:?} vs {:?}", a.p, b.p);
                        assert!((a.n - b.n).length() < 1e-3, "n {:?} vs {:?}", a.n, b.n);
                        assert!(
                            (a.shading.n - b.shading.n).length() < 1e-3,
                            "ns {:?} vs {:?}",
                            a.shading.n,
                            b.shading.n
                        );
                        assert!((a.uv - b.uv).length() < 1e-3, "uv {:?} vs {:?}", a.uv, b.uv);
                        assert_eq!(a.prim, b.prim);
                        let f = a.shading;
                        assert!((f.s.dot(f.t)).abs() < 1e-4 && (f.s.cross(f.t) - f.n).length() < 1e-3);
                    }
                }
                (a, b) => panic!("ray {i}/{k}: instanced {a:?} vs flat {b:?}"),
            }
        }
    }
    assert!(hits > 800, "only {hits} hits");
    // Any-hit queries see every hit inside an instance, as in the flat scene.
    let mut crossings = 0;
    for _ in 0..3000 {
        let ray = Ray::new(rng.v3(-7.0, 7.0), rng.dir());
        let count = |b: &dyn Intersect| {
            let mut ts = Vec::new();
            b.for_each_hit(&ray, &mut |si| {
                ts.push(si.t);
                false
            });
            ts.sort_by(f32::total_cmp);
            ts
        };
        let (a, b) = (count(&inst), count(&flat));
        assert_eq!(a.len(), b.len(), "{a:?} vs {b:?}");
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 2e-4 * x.max(1.0), "{a:?} vs {b:?}");
        }
        crossings += a.len();
    }
    assert!(crossings > 500, "{crossings}");
}

#[test]
fn instances_hold_one_copy_of_the_group() {
    let mut rng = Rng(5);
    let (instanced, _) = scenes(&mut rng);
    let shapes = world(&instanced);
    let inner: Vec<_> = shapes
        .iter()
        .map(|s| match &s.kind {
            ShapeKind::Instance(i) => i.inner.clone(),
            k => panic!("not an instance: {k:?}"),
        })
        .collect();
    // Five instances of three members: three BVHs, each shared by the five instances.
    for (i, a) in inner.iter().enumerate() {
        let same = inner.iter().filter(|b| Arc::ptr_eq(a, b)).count();
        assert_eq!(same, 5, "member {}", i % 3);
    }
    let distinct = inner
        .iter()
        .enumerate()
        .filter(|(i, a)| !inner[..*i].iter().any(|b| Arc::ptr_eq(a, b)))
        .count();
    assert_eq!(distinct, 3);
    // The cube's triangles are stored once, not once per instance.
    let ShapeKind::Mesh(m) = &inner[0].shapes()[0].kind else {
        panic!("the first member is the cube")
    };
    assert_eq!(Arc::strong_count(m), 1);
    assert_eq!(Arc::strong_count(&inner[0]), 1 + 5 + 5);
}

#[test]
fn instance_area_and_bounds_follow_the_transform() {
    let group = Arc::new(ShapeGroup::new(
        "g".into(),
        vec![shape(Geometry::Rectangle, Affine3A::IDENTITY)],
    ));
    let m = Affine3A::from_scale_rotation_translation(
        Vec3::splat(2.0),
        Quat::from_rotation_z(0.3),
        Vec3::new(1.0, 2.0, 3.0),
    );
    let mut out = Vec::new();
    expand(
        ShapeDesc {
            geometry: Geometry::Instance { group, member: None },
            ..shape(Geometry::Disk, m)
        },
        &mut out,
    );
    let w = WorldShape::from_scene(&out[0], "i").unwrap();
    // The rectangle [-1, 1]² scaled by 2: area 16.
    assert!((w.area() - 16.0).abs() < 1e-3, "{}", w.area());
    let flat = WorldShape::from_scene(&shape(Geometry::Rectangle, m), "f").unwrap();
    let (a, b) = (w.prim_bounds(0), flat.prim_bounds(0));
    assert!(
        (a.0 - b.0).length() < 1e-4 && (a.1 - b.1).length() < 1e-4,
        "{a:?} vs {b:?}"
    );
}
