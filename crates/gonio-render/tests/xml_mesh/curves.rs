//! `linearcurve`, `bsplinecurve`: hits against Mitsuba 3.9.1 and errors.

use glam::{Affine3A, Vec2, Vec3};
use gonio_render::accel::{BruteForce, Intersect};
use gonio_render::geometry::curve::{CurveKind, parse_curves, tessellate};
use gonio_render::geometry::{Ray, WorldShape};
use gonio_render::scene::{Geometry, ShapeDesc};
use std::sync::Arc;

fn curve(text: &str, kind: CurveKind) -> BruteForce {
    let curves = parse_curves(text, kind, &Affine3A::IDENTITY).unwrap();
    let desc = ShapeDesc {
        geometry: Geometry::Mesh(Arc::new(tessellate(&curves, kind))),
        to_world: Affine3A::IDENTITY,
        flip_normals: false,
        face_normals: false,
        outside_only: false,
        media: Default::default(),
        material: 0,
        emitter: None,
        id: None,
    };
    BruteForce::new(vec![WorldShape::from_scene(&desc, "curve").unwrap()])
}

/// (origin, direction, expected (t, uv, n) or a miss): Mitsuba 3.9.1 `scalar_spectral`'s
/// `ray_intersect` on the same files, printed by `testdata/mitsuba-corpus/probe_curves.py`.
type Case = ([f32; 3], [f32; 3], Option<(f32, [f32; 2], [f32; 3])>);

fn check(b: &BruteForce, cases: &[Case]) {
    for (o, d, expected) in cases {
        let ray = Ray::new(Vec3::from(*o), Vec3::from(*d));
        let si = b.intersect(&ray);
        match (si, expected) {
            (None, None) => {}
            (Some(si), Some((t, uv, n))) => {
                // The tessellation's chord error is r(1 − cos(π/64)) ≈ 1.2e-4 for r = 0.1.
                assert!((si.t - t).abs() < 3e-4, "{o:?}: t {} vs {t}", si.t);
                let du = (si.uv.x - uv[0]).abs();
                assert!(du.min(1.0 - du) < 0.02, "{o:?}: u {} vs {}", si.uv.x, uv[0]);
                assert!(
                    (si.uv.y - uv[1]).abs() < 2e-3,
                    "{o:?}: v {} vs {}",
                    si.uv.y,
                    uv[1]
                );
                assert!(
                    si.shading.n.dot(Vec3::from(*n)) > 0.999,
                    "{o:?}: n {} vs {n:?}",
                    si.shading.n
                );
                assert!(si.n.dot(Vec3::from(*n)) > 0.99, "{o:?}: n {} vs {n:?}", si.n);
            }
            (a, b) => panic!("{o:?}: gonio {:?} vs Mitsuba {b:?}", a.map(|s| (s.t, s.uv))),
        }
    }
}

const STRAIGHT: &str = "0 0 0 0.1\n1 0 0 0.1\n2 0 0 0.1\n3 0 0 0.1\n4 0 0 0.1\n";

#[test]
fn linear_curve_matches_mitsuba() {
    check(
        &curve(STRAIGHT, CurveKind::Linear),
        &[
            (
                [1.5, 0., 5.],
                [0., 0., -1.],
                Some((4.9, [0.25, 0.375], [0., 0., 1.])),
            ),
            (
                [1.5, 5., 0.],
                [0., -1., 0.],
                Some((4.9, [0.0, 0.375], [0., 1., 0.])),
            ),
            (
                [1.5, 0., -5.],
                [0., 0., 1.],
                Some((4.9, [0.75, 0.375], [0., 0., -1.])),
            ),
            (
                [0.5, 0., 5.],
                [0., 0., -1.],
                Some((4.9, [0.25, 0.125], [0., 0., 1.])),
            ),
            (
                [2.5, 0., 5.],
                [0., 0., -1.],
                Some((4.9, [0.25, 0.625], [0., 0., 1.])),
            ),
            // The spherical end caps.
            (
                [-0.05, 0., 5.],
                [0., 0., -1.],
                Some((4.913397, [0.25, 0.0], [-0.5, 0., 0.866026])),
            ),
            (
                [4.05, 0., 5.],
                [0., 0., -1.],
                Some((4.913398, [0.25, 1.0], [0.5, 0., 0.866024])),
            ),
        ],
    );
    // A radius growing from 0.1 to 0.2 and back: a cone tangent to the joint spheres.
    check(
        &curve("0 0 0 0.1\n1 0 0 0.2\n2 0 0 0.1\n", CurveKind::Linear),
        &[
            (
                [0.25, 0., 5.],
                [0., 0., -1.],
                Some((4.87437, [0.25, 0.131313], [-0.1, 0., 0.994987])),
            ),
            (
                [0.75, 0., 5.],
                [0., 0., -1.],
                Some((4.824118, [0.25, 0.383838], [-0.1, 0., 0.994987])),
            ),
            (
                [1.0, 0., 5.],
                [0., 0., -1.],
                Some((4.8, [0.25, 0.5], [0., 0., 1.])),
            ),
            (
                [1.5, 0., 5.],
                [0., 0., -1.],
                Some((4.849244, [0.25, 0.742424], [0.1, 0., 0.994987])),
            ),
        ],
    );
}

#[test]
fn bspline_curve_matches_mitsuba() {
    check(
        &curve(STRAIGHT, CurveKind::BSpline),
        &[
            (
                [1.5, 0., 5.],
                [0., 0., -1.],
                Some((4.9, [0.25, 0.25], [0., 0., 1.])),
            ),
            (
                [1.5, 5., 0.],
                [0., -1., 0.],
                Some((4.9, [0.0, 0.25], [0., 1., 0.])),
            ),
            (
                [1.5, 0., -5.],
                [0., 0., 1.],
                Some((4.9, [0.75, 0.25], [0., 0., -1.])),
            ),
            (
                [2.5, 0., 5.],
                [0., 0., -1.],
                Some((4.9, [0.25, 0.75], [0., 0., 1.])),
            ),
            (
                [1.05, 0., 5.],
                [0., 0., -1.],
                Some((4.9, [0.25, 0.025], [0., 0., 1.])),
            ),
            // Open ends: the curve runs from x = 1 to x = 3, without caps.
            ([0.95, 0., 5.], [0., 0., -1.], None),
            ([3.05, 0., 5.], [0., 0., -1.], None),
            ([-5., 0., 0.], [1., 0., 0.], None),
        ],
    );
}

#[test]
fn curve_points_lie_on_the_tube_and_face_outwards() {
    let text = "-1 0 0 0.1\n-0.3 0 0.5 0.1\n0.3 0 -0.5 0.1\n1 0 0 0.1\n";
    for kind in [CurveKind::Linear, CurveKind::BSpline] {
        let curves = parse_curves(text, kind, &Affine3A::IDENTITY).unwrap();
        let m = tessellate(&curves, kind);
        assert!(!m.indices.is_empty());
        for t in &m.indices {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let f = (b - a).cross(c - a);
            let n = t.iter().map(|&i| m.normals[i as usize]).sum::<Vec3>();
            assert!(f.dot(n) > 0.0, "{kind:?}: a triangle faces inwards");
        }
        assert!(
            m.uvs
                .iter()
                .all(|uv| uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all())
        );
    }
}

#[test]
fn curve_files_with_errors_are_refused_with_their_line() {
    let err = |t: &str, k| parse_curves(t, k, &Affine3A::IDENTITY).unwrap_err();
    assert!(err("0 0 0 0.1\n", CurveKind::Linear).contains("needs at least 2"));
    assert!(err("0 0 0 1\n1 0 0 1\n2 0 0 1\n", CurveKind::BSpline).contains("needs at least 4"));
    assert!(err("0 0 0 0.1\n1 0 zero 0.1\n", CurveKind::Linear).contains("line 2"));
    assert!(err("0 0 0\n", CurveKind::Linear).contains("3 numbers"));
    assert!(err("0 0 0 -1\n1 0 0 1\n", CurveKind::Linear).contains("radius"));
    assert!(err("1e39 0 0 1\n1 0 0 1\n", CurveKind::Linear).contains("line 1"));
    assert!(err("\n\n", CurveKind::Linear).contains("empty"));
    // Two curves separated by an empty line: two separate tubes.
    let two = parse_curves(
        "0 0 0 1\n1 0 0 1\n\n0 1 0 1\n1 1 0 1\n",
        CurveKind::Linear,
        &Affine3A::IDENTITY,
    )
    .unwrap();
    assert_eq!(two.len(), 2);
}

/// Two straight B-spline fibres of radius 0.1 along x, one at z = 0 and one at z = −0.5, as the
/// scene reader places curves (`outside_only`), in the brute-force oracle and in the accelerated
/// structure (Embree's triangles when the library is there).
fn two_fibres() -> (BruteForce, gonio_render::accel::Accel) {
    let text = "-2 0 0 0.1\n-1 0 0 0.1\n0 0 0 0.1\n1 0 0 0.1\n2 0 0 0.1\n\n\
                -2 0 -0.5 0.1\n-1 0 -0.5 0.1\n0 0 -0.5 0.1\n1 0 -0.5 0.1\n2 0 -0.5 0.1\n";
    let curves = parse_curves(text, CurveKind::BSpline, &Affine3A::IDENTITY).unwrap();
    let desc = ShapeDesc {
        geometry: Geometry::Mesh(Arc::new(tessellate(&curves, CurveKind::BSpline))),
        to_world: Affine3A::IDENTITY,
        flip_normals: false,
        face_normals: false,
        outside_only: true,
        media: Default::default(),
        material: 0,
        emitter: None,
        id: None,
    };
    let shapes = vec![WorldShape::from_scene(&desc, "curve").unwrap()];
    (
        BruteForce::new(shapes.clone()),
        gonio_render::accel::Accel::new(shapes),
    )
}

#[test]
fn curves_are_hit_only_from_outside_as_in_mitsuba() {
    // Mitsuba 3.9.1 (`scalar_rgb` and `llvm_ad_rgb`, both curve shapes): a ray from inside a
    // fibre misses it (`ray_intersect` invalid, `ray_test` false); a ray that entered one passes
    // out through it and meets the next fibre's front, here at (0.3, 0.02, −0.40202) with
    // n = (0, 0.2, 0.9798).
    let (brute, accel) = two_fibres();
    let structures: [&dyn Intersect; 2] = [&brute, &accel];
    for s in structures {
        // From the centre line of the second fibre, outwards and away from the first: nothing.
        for d in [
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.0, 0.6, -0.8),
            Vec3::new(0.6, 0.0, -0.8),
        ] {
            let ray = Ray::new(Vec3::new(0.3, 0.0, -0.5), d);
            assert!(s.intersect(&ray).is_none(), "from inside along {d}");
            assert!(!s.occluded(&ray), "from inside along {d}: occluded");
        }
        // From outside: the first fibre's front.
        let ray = Ray::new(Vec3::new(0.3, 0.02, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let entry = s.intersect(&ray).expect("the first fibre");
        assert!((entry.p.z - 0.0979795).abs() < 3e-4, "entry {}", entry.p);
        // On inwards from the entry point: out through the first fibre to the second's front.
        let next = s.intersect(&entry.spawn_ray(ray.d)).expect("the second fibre");
        assert!(
            (next.p - Vec3::new(0.3, 0.02, -0.40202)).length() < 3e-4,
            "next {}",
            next.p
        );
        assert!(
            next.n.dot(Vec3::new(0.0, 0.2, 0.9797959)) > 0.999,
            "next n {}",
            next.n
        );
        // The distance counts from the spawned ray's origin, through the skipped inside.
        let spawned = entry.spawn_ray(ray.d);
        assert!((spawned.o + spawned.d * next.t - next.p).length() < 1e-4);
        // Any-hit queries skip the insides too: the ray from inside the first fibre is blocked
        // by the second only.
        let mut hits = 0;
        s.for_each_hit(&spawned, &mut |h| {
            assert!(h.n.dot(spawned.d) < 0.0, "an inside reported at {}", h.p);
            hits += 1;
            false
        });
        assert_eq!(hits, 1);
        assert!(s.occluded(&spawned));
    }
}

#[test]
fn curve_shading_frame_runs_along_the_fibre_as_in_mitsuba() {
    // Mitsuba 3.9.1 `bsplinecurve`, the same ray: sh_frame.s = normalize(dp_du) (around the
    // fibre) = (0, −0.9797959, 0.2), sh_frame.t = +tangent = (1, 0, 0) (towards increasing curve
    // parameter), n = (0, 0.2, 0.9797959): the `hair` model's y axis is the fibre.
    let (brute, _) = two_fibres();
    let ray = Ray::new(Vec3::new(0.3, 0.02, 5.0), Vec3::new(0.0, 0.0, -1.0));
    let si = brute.intersect(&ray).unwrap();
    assert!(
        si.shading.n.dot(Vec3::new(0.0, 0.2, 0.9797959)) > 0.9999,
        "n {}",
        si.shading.n
    );
    assert!(
        si.shading.s.dot(Vec3::new(0.0, -0.9797959, 0.2)) > 0.999,
        "s {}",
        si.shading.s
    );
    assert!(si.shading.t.dot(Vec3::X) > 0.999, "t {}", si.shading.t);
}
