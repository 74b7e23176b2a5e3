//! OBJ and PLY fixtures and the cube.

use glam::{Vec2, Vec3};
use gonio_render::mesh::{cube, load_obj, load_ply, vertex_normals};
use gonio_render::scene::TriangleMesh;
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn area_vector(m: &TriangleMesh) -> (f32, Vec3) {
    let mut area = 0.0;
    let mut sum = Vec3::ZERO;
    for t in &m.indices {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        let n = 0.5 * (b - a).cross(c - a);
        area += n.length();
        sum += n;
    }
    (area, sum)
}

#[test]
fn obj_quad_is_triangulated_with_uvs_and_normals() {
    let m = load_obj(&data("quad.obj"), false).unwrap();
    assert_eq!(m.positions.len(), 4);
    assert_eq!(m.indices.len(), 2);
    assert_eq!(m.normals, vec![Vec3::Z; 4]);
    let (area, n) = area_vector(&m);
    assert!((area - 1.0).abs() < 1e-6);
    assert!(
        (n - 0.5 * Vec3::Z * 2.0).length() < 1e-6,
        "counter-clockwise winding kept: {n}"
    );
    for (p, uv) in m.positions.iter().zip(&m.uvs) {
        assert_eq!(
            *uv,
            Vec2::new(p.x, p.y),
            "uv follows the position in this fixture"
        );
    }
    let flipped = load_obj(&data("quad.obj"), true).unwrap();
    for (p, uv) in flipped.positions.iter().zip(&flipped.uvs) {
        assert_eq!(*uv, Vec2::new(p.x, 1.0 - p.y));
    }
}

#[test]
fn obj_objects_merge() {
    let m = load_obj(&data("two_tris.obj"), true).unwrap();
    assert_eq!(m.positions.len(), 6);
    assert_eq!(m.indices.len(), 2);
    assert!(m.normals.is_empty() && m.uvs.is_empty());
    // The second triangle refers to the second object's vertices (z = 1).
    assert!(m.indices[1].iter().all(|&i| m.positions[i as usize].z == 1.0));
}

#[test]
fn obj_errors_name_the_file() {
    let e = load_obj(&data("broken.obj"), true).unwrap_err();
    assert!(!e.is_io());
    assert!(e.to_string().contains("broken.obj"), "{e}");
    let e = load_obj(&data("absent.obj"), true).unwrap_err();
    assert!(e.is_io() && e.to_string().contains("absent.obj"), "{e}");
}

#[test]
fn ply_ascii_quad() {
    let m = load_ply(&data("quad_ascii.ply"), false).unwrap();
    assert_eq!(
        m.positions,
        vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]
    );
    assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(m.normals, vec![Vec3::Z; 4]);
    assert_eq!(m.uvs[2], Vec2::new(1.0, 1.0));
    assert_eq!(m.uvs[1], Vec2::new(1.0, 0.0));
}

#[test]
fn ply_binary_little_endian_tetrahedron_is_closed() {
    let m = load_ply(&data("tetra_le.ply"), false).unwrap();
    assert_eq!(m.positions.len(), 4);
    assert_eq!(m.indices.len(), 4);
    assert!(m.normals.is_empty() && m.uvs.is_empty());
    let (area, sum) = area_vector(&m);
    // Three right triangles of area ½ and one equilateral of side √2.
    assert!((area - (1.5 + 3f32.sqrt() / 2.0)).abs() < 1e-5, "{area}");
    assert!(sum.length() < 1e-6, "a closed surface: {sum}");
    // Outward orientation: the signed volume is positive.
    let vol: f32 = m
        .indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    assert!((vol - 1.0 / 6.0).abs() < 1e-6, "{vol}");
}

#[test]
fn ply_errors_name_the_file_and_the_problem() {
    let e = load_ply(&data("truncated.ply"), false).unwrap_err();
    let s = e.to_string();
    assert!(
        s.contains("truncated.ply") && s.contains("face 3") && s.contains("end of file"),
        "{s}"
    );
    let e = load_ply(&data("bad_index.ply"), false).unwrap_err();
    let s = e.to_string();
    assert!(
        s.contains("bad_index.ply") && s.contains("vertex [0, 1, 5]"),
        "{s}"
    );
    let e = load_ply(&data("quad.obj"), false).unwrap_err();
    assert!(e.to_string().contains("not a PLY file"), "{e}");
}

#[test]
fn cube_is_closed_and_outward() {
    let m = cube();
    let (area, sum) = area_vector(&m);
    assert!((area - 24.0).abs() < 1e-5);
    assert!(sum.length() < 1e-5);
    assert!(m.positions.iter().all(|p| p.abs() == Vec3::ONE));
}

#[test]
fn vertex_normals_are_angle_weighted() {
    // A roof: two triangles meeting at 90° along the x axis.
    let m = TriangleMesh {
        positions: vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(0.0, -1.0, 1.0),
        ],
        normals: vec![],
        uvs: vec![],
        indices: vec![[0, 1, 2], [1, 0, 3]],
    };
    let n = vertex_normals(&m);
    let (f0, f1) = (
        Vec3::new(0.0, -1.0, 1.0).normalize(),
        Vec3::new(0.0, 1.0, 1.0).normalize(),
    );
    // Vertex 2 belongs to the first triangle only.
    assert!((n[2] - f0).length() < 1e-6, "{}", n[2]);
    assert!((n[3] - f1).length() < 1e-6, "{}", n[3]);
    // Vertex 0: angles 90° in both triangles → the bisector +z.
    assert!((n[0] - Vec3::Z).length() < 1e-6, "{}", n[0]);
    // The cube's own normals are per face; recomputing them on its 24-vertex layout gives the same.
    let c = cube();
    assert_eq!(vertex_normals(&c), c.normals);
}

#[test]
fn ply_large_binary_grid_round_trips() {
    // A 400 × 400 quad grid (320 000 triangles) with uvs, written big-endian with float
    // positions, read back exactly.
    let n = 401usize;
    let mut b = format!(
        "ply\nformat binary_big_endian 1.0\ncomment grid\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float u\nproperty float v\nelement face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        n * n,
        (n - 1) * (n - 1)
    )
    .into_bytes();
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f32 / 400.0, j as f32 / 400.0);
            for v in [x, y, (x * y).sin(), x, y] {
                b.extend_from_slice(&v.to_be_bytes());
            }
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            b.push(4);
            for v in [a, a + 1, a + 1 + n as u32, a + n as u32] {
                b.extend_from_slice(&v.to_be_bytes());
            }
        }
    }
    let path = std::env::temp_dir().join(format!("gonio-grid-{}.ply", std::process::id()));
    std::fs::write(&path, &b).unwrap();
    let t = std::time::Instant::now();
    let m = load_ply(&path, false);
    let dt = t.elapsed();
    std::fs::remove_file(&path).ok();
    let m = m.unwrap();
    println!(
        "{} triangles in {:.1} ms",
        m.indices.len(),
        dt.as_secs_f64() * 1e3
    );
    assert_eq!(m.positions.len(), n * n);
    assert_eq!(m.indices.len(), 2 * (n - 1) * (n - 1));
    let k = 123 * n + 77;
    let (x, y) = (77.0f32 / 400.0, 123.0f32 / 400.0);
    assert_eq!(m.positions[k], Vec3::new(x, y, (x * y).sin()));
    assert_eq!(m.uvs[k], Vec2::new(x, y));
    // The surface area of z = sin(xy) over the unit square, by the midpoint rule.
    let k = 1000;
    let mut exact = 0.0f64;
    for j in 0..k {
        for i in 0..k {
            let (x, y) = ((i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64);
            let c = (x * y).cos();
            exact += (1.0 + (y * c).powi(2) + (x * c).powi(2)).sqrt();
        }
    }
    exact /= (k * k) as f64;
    let (area, _) = area_vector(&m);
    assert!((area as f64 - exact).abs() < 1e-3, "{area} vs {exact}");
}

#[test]
fn a_mesh_named_in_an_included_fragment_resolves_against_the_scene_folder() {
    // Mitsuba's scenes/cbox: cbox-rgb.xml includes fragments/shapes.xml, which names
    // "meshes/cbox_floor.obj", a file beside cbox-rgb.xml, not beside the fragment. Mitsuba's
    // resolver keeps the scene's folder while it reads the include; so does gonio's (after the
    // fragment's own folder and the <path> folders).
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("fragments")).unwrap();
    std::fs::create_dir_all(dir.path().join("meshes")).unwrap();
    std::fs::copy(data("quad.obj"), dir.path().join("meshes/quad.obj")).unwrap();
    std::fs::write(
        dir.path().join("fragments/shapes.xml"),
        r#"<scene version="3.0.0"><shape type="obj"><string name="filename" value="meshes/quad.obj"/></shape></scene>"#,
    )
    .unwrap();
    std::fs::write(
        dir.path().join("scene.xml"),
        r#"<scene version="3.0.0"><include filename="fragments/shapes.xml"/></scene>"#,
    )
    .unwrap();
    let scene = gonio_render::xml::load_scene_file(dir.path().join("scene.xml"), &[]).expect("loads");
    assert_eq!(scene.shapes.len(), 1);
    // A name found beside the fragment still wins (the fragment's folder comes first).
    std::fs::create_dir_all(dir.path().join("fragments/meshes")).unwrap();
    std::fs::write(dir.path().join("fragments/meshes/quad.obj"), "garbage\n").unwrap();
    let e = gonio_render::xml::load_scene_file(dir.path().join("scene.xml"), &[])
        .expect_err("the fragment's copy");
    assert!(e.to_string().contains("fragments/meshes/quad.obj"), "{e}");
}
