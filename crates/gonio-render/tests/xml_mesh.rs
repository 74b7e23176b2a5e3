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

// ---------------------------------------------------------------------------------------------
// `sdfgrid`: intersections against closed forms and a dense march; `.vol` errors.

mod sdfgrid {
    use glam::Vec3;
    use gonio_core::hash::{GOLDEN_GAMMA, mix64, unit_f32};
    use gonio_render::geometry::sdfgrid::{SdfGrid, SdfNormals, VolGrid, read_vol};

    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_add(GOLDEN_GAMMA);
            unit_f32(mix64(self.0))
        }
        fn v3(&mut self, a: f32, b: f32) -> Vec3 {
            Vec3::new(self.next(), self.next(), self.next()) * (b - a) + Vec3::splat(a)
        }
        fn dir(&mut self) -> Vec3 {
            let z = 1.0 - 2.0 * self.next();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = std::f32::consts::TAU * self.next();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        }
    }

    fn grid(n: [usize; 3], f: impl Fn(Vec3) -> f32, normals: SdfNormals) -> SdfGrid {
        let mut data = Vec::new();
        for z in 0..n[2] {
            for y in 0..n[1] {
                for x in 0..n[0] {
                    let p = Vec3::new(
                        x as f32 / (n[0] - 1) as f32,
                        y as f32 / (n[1] - 1) as f32,
                        z as f32 / (n[2] - 1) as f32,
                    );
                    data.push(f(p));
                }
            }
        }
        let vol = VolGrid {
            res: n,
            channels: 1,
            bounds: (Vec3::ZERO, Vec3::ONE),
            data,
        };
        SdfGrid::new(vol, normals).unwrap()
    }

    fn axis_dirs() -> Vec<Vec3> {
        let mut v = Vec::new();
        for a in 0..3 {
            for s in [1.0f32, -1.0] {
                let mut d = Vec3::splat(0.0);
                d[a] = s;
                v.push(d);
                let mut e = Vec3::splat(-0.0);
                e[a] = s;
                v.push(e);
            }
        }
        v
    }

    /// A plane's distance is linear, so the trilinear interpolant is the plane exactly: every
    /// hit is the analytic one, normals (both kinds) are the plane's.
    #[test]
    fn plane_grid_hits_the_plane_exactly() {
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let d0 = n.dot(Vec3::splat(0.5)) + 0.03;
        for normals in [SdfNormals::Analytic, SdfNormals::Smooth] {
            let g = grid([9, 7, 12], |p| n.dot(p) - d0, normals);
            let mut rng = Rng(3);
            let mut dirs = axis_dirs();
            for _ in 0..3000 {
                dirs.push(rng.dir());
            }
            let mut hits = 0;
            for d in dirs {
                for _ in 0..3 {
                    let o = rng.v3(-0.5, 1.5);
                    let t_plane = (d0 - n.dot(o)) / n.dot(d);
                    let p = o + d * t_plane;
                    let expected = t_plane > 0.0 && p.cmpge(Vec3::ZERO).all() && p.cmple(Vec3::ONE).all();
                    let margin = p.min_element().min((Vec3::ONE - p).min_element()).abs();
                    let got = g.intersect(o, d, f32::INFINITY);
                    if margin < 1e-3 || t_plane.abs() < 1e-3 || !t_plane.is_finite() {
                        continue; // grazing the cube's faces or starting on the plane
                    }
                    match got {
                        Some((t, voxel)) => {
                            assert!(expected, "hit at {t} where the plane is missed (o {o}, d {d})");
                            assert!(
                                (t - t_plane).abs() < 1e-4 * t_plane.max(1.0),
                                "t {t} vs {t_plane}"
                            );
                            let q = o + d * t;
                            assert!(g.gradient(voxel, q).normalize().dot(n) > 0.9999);
                            // Mitsuba's smooth normals blend in clamped (flat) differences
                            // within a voxel of the grid's upper faces: checked inside.
                            if q.min_element() > 0.25 && q.max_element() < 0.75 {
                                assert!(g.smooth_normal(q).normalize().dot(n) > 0.9999);
                            }
                            hits += 1;
                        }
                        None => assert!(!expected, "missed the plane at t {t_plane} (o {o}, d {d})"),
                    }
                }
            }
            assert!(hits > 500, "{hits}");
        }
    }

    /// A sphere's distance sampled on 33³ points: the first hit agrees with a dense march of the
    /// same interpolant, and lies on the sphere within the interpolation error.
    #[test]
    fn sphere_grid_hits_agree_with_a_dense_march() {
        let c = Vec3::new(0.5, 0.48, 0.52);
        let r = 0.3;
        let g = grid([33, 33, 33], |p| (p - c).length() - r, SdfNormals::Smooth);
        let mut rng = Rng(11);
        let mut dirs = axis_dirs();
        for _ in 0..600 {
            dirs.push(rng.dir());
        }
        let mut hits = 0;
        for d in dirs {
            let o = c - d * 1.2 + rng.v3(-0.25, 0.25);
            let got = g.intersect(o, d, f32::INFINITY);
            // March the same interpolant in steps of 2e-4 from where the ray enters [0, 1]³.
            let (mut t, mut prev) = (0.0f32, None::<f32>);
            let mut marched = None;
            while t < 3.0 {
                let p = o + d * t;
                if p.cmpge(Vec3::ZERO).all() && p.cmple(Vec3::ONE).all() {
                    let f = g.value(p);
                    if let Some(fp) = prev
                        && fp > 0.0
                        && f <= 0.0
                    {
                        marched = Some(t);
                        break;
                    }
                    prev = Some(f);
                }
                t += 2e-4;
            }
            match (got, marched) {
                (Some((t, voxel)), Some(m)) => {
                    hits += 1;
                    assert!((t - m).abs() < 3e-4, "t {t} vs march {m}");
                    let p = o + d * t;
                    assert!(
                        ((p - c).length() - r).abs() < 2e-3,
                        "off the sphere by {}",
                        (p - c).length() - r
                    );
                    let n = g.gradient(voxel, p).normalize();
                    assert!(n.dot((p - c).normalize()) > 0.99, "{n}");
                    assert!(g.smooth_normal(p).normalize().dot((p - c).normalize()) > 0.99);
                }
                (None, None) => {}
                (a, b) => panic!("dir {d}: intersect {a:?} vs march {b:?}"),
            }
        }
        assert!(hits > 300, "{hits}");
    }

    fn vol(header: [i32; 5], bounds: [f32; 6], data: &[f32]) -> Vec<u8> {
        let mut b = b"VOL\x03".to_vec();
        for v in header {
            b.extend(v.to_le_bytes());
        }
        for v in bounds {
            b.extend(v.to_le_bytes());
        }
        for v in data {
            b.extend(v.to_le_bytes());
        }
        b
    }

    #[test]
    fn vol_files_are_read_and_bad_ones_refused_with_a_reason() {
        let data: Vec<f32> = (0..8).map(|i| if i == 0 { -1.0 } else { 1.0 }).collect();
        let ok = vol([1, 2, 2, 2, 1], [0., 0., 0., 1., 1., 1.], &data);
        let v = read_vol(&ok).unwrap();
        assert_eq!((v.res, v.channels, v.data.len()), ([2, 2, 2], 1, 8));
        assert!(SdfGrid::new(v, SdfNormals::Smooth).is_ok());
        let msg = |b: &[u8]| read_vol(b).unwrap_err();
        assert!(msg(&ok[..40]).contains("header"));
        assert!(msg(&ok[..ok.len() - 4]).contains("bytes"));
        let mut magic = ok.clone();
        magic[0] = b'X';
        assert!(msg(&magic).contains("VOL"));
        let mut version = ok.clone();
        version[3] = 2;
        assert!(msg(&version).contains("version 2"));
        assert!(msg(&vol([2, 2, 2, 2, 1], [0.; 6], &data)).contains("encoding 2"));
        assert!(msg(&vol([1, 1 << 30, 1 << 30, 4, 1], [0.; 6], &data)).contains("needs more data"));
        assert!(msg(&vol([1, -2, 2, 2, 1], [0.; 6], &data)).contains("resolution"));
        let three = read_vol(&vol([1, 2, 2, 2, 3], [0.; 6], &[0.0; 24])).unwrap();
        assert!(
            SdfGrid::new(three, SdfNormals::Smooth)
                .unwrap_err()
                .contains("3 channels")
        );
        let flat = read_vol(&vol([1, 1, 2, 2, 1], [0.; 6], &[1.0; 4])).unwrap();
        assert!(
            SdfGrid::new(flat, SdfNormals::Smooth)
                .unwrap_err()
                .contains("at least 2")
        );
        let empty = read_vol(&vol([1, 2, 2, 2, 1], [0.; 6], &[1.0; 8])).unwrap();
        assert!(
            SdfGrid::new(empty, SdfNormals::Smooth)
                .unwrap_err()
                .contains("no voxel")
        );
        let nan = read_vol(&vol([1, 2, 2, 2, 1], [0.; 6], &[f32::NAN; 8])).unwrap();
        assert!(
            SdfGrid::new(nan, SdfNormals::Smooth)
                .unwrap_err()
                .contains("not a finite")
        );
    }
}

// ---------------------------------------------------------------------------------------------
// `linearcurve`, `bsplinecurve`: hits against Mitsuba 3.9.1 and errors.

mod curves;

// ---------------------------------------------------------------------------------------------
// `mesh_attribute`: the errors of a texture that finds no attribute.

#[test]
fn mesh_attribute_errors_name_the_file_the_line_and_the_attribute() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tri.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nproperty float r\nproperty float g\nproperty float b\nelement face 1\n\
         property list uchar int vertex_indices\nend_header\n0 0 0 1 0 0\n1 0 0 0 1 0\n\
         0 1 0 0 0 1\n3 0 1 2\n",
    )
    .unwrap();
    let scene = |shape: &str, name: &str| {
        format!(
            "<scene version=\"3.0.0\">\n<bsdf type=\"diffuse\" id=\"m\">\n\
             <texture type=\"mesh_attribute\" name=\"reflectance\">\n\
             <string name=\"name\" value=\"{name}\"/>\n</texture>\n</bsdf>\n{shape}\n</scene>\n"
        )
    };
    let ply = r#"<shape type="ply"><string name="filename" value="tri.ply"/><ref id="m"/></shape>"#;
    let load = |text: String| {
        let path = dir.path().join("scene.xml");
        std::fs::write(&path, text).unwrap();
        gonio_render::xml::load_scene_file(&path, &[])
    };
    // The attribute exists: the shape's material is bound to the mesh.
    let s = load(scene(ply, "vertex_color")).expect("loads");
    assert_eq!(s.shapes.len(), 1);
    // Not on the mesh: the texture's line, the name and what the mesh has.
    let e = load(scene(ply, "face_color"))
        .expect_err("no face colours")
        .to_string();
    assert!(
        e.contains("scene.xml:4") && e.contains("\"face_color\"") && e.contains("vertex_color"),
        "{e}"
    );
    // On a shape that is no mesh.
    let e = load(scene(
        r#"<shape type="sphere"><ref id="m"/></shape>"#,
        "vertex_color",
    ))
    .expect_err("a sphere")
    .to_string();
    assert!(e.contains("scene.xml:4") && e.contains("not a mesh"), "{e}");
    // A name Mitsuba refuses.
    let e = load(scene(ply, "color")).expect_err("no prefix").to_string();
    assert!(e.contains("scene.xml:4") && e.contains("\"vertex_\""), "{e}");
}

// ---------------------------------------------------------------------------------------------
// `volume` textures over a `gridvolume`: the value a surface sees, and the errors.

#[test]
fn a_volume_texture_is_its_grid_at_the_hit_and_bad_grids_are_refused() {
    use gonio_core::{Bsdf, BsdfContext, SampledWavelengths};
    use gonio_render::material::ShadingPoint;
    // A 2 × 1 × 1 grid (values 0.2, 0.6 along x), `channels` channels.
    let vol = |channels: i32| {
        let mut b = b"VOL\x03".to_vec();
        for v in [1, 2, 1, 1, channels] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        for v in [0f32, 0., 0., 1., 1., 1.] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        for x in [0.2f32, 0.6] {
            for _ in 0..channels {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        b
    };
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("g1.vol"), vol(1)).unwrap();
    std::fs::write(dir.path().join("g2.vol"), vol(2)).unwrap();
    let scene = |file: &str| {
        format!(
            "<scene version=\"3.0.0\">\n<shape type=\"rectangle\">\n<bsdf type=\"diffuse\">\n\
             <texture type=\"volume\" name=\"reflectance\">\n<volume type=\"gridvolume\" name=\"volume\">\n\
             <string name=\"filename\" value=\"{file}\"/>\n\
             <transform name=\"to_world\"><scale value=\"4\"/><translate x=\"-2\" y=\"-2\" z=\"-2\"/></transform>\n\
             </volume>\n</texture>\n</bsdf>\n</shape>\n</scene>\n"
        )
    };
    let load = |text: String| {
        let path = dir.path().join("scene.xml");
        std::fs::write(&path, text).unwrap();
        gonio_render::xml::load_scene_file(&path, &[])
    };
    let s = load(scene("g1.vol")).expect("loads");
    let m = &s.materials[s.shapes[0].material];
    // The grid spans [−2, 2]³; sample centres at x = −1 (0.2) and x = 1 (0.6); half-way between
    // them (x = 0) the trilinear value is 0.4; beyond the centres it is clamped.
    // The diffuse reflectance at (x, 0.3, 0): π·f at normal incidence and exitance.
    let wl = SampledWavelengths::sample_visible(0.5);
    let reflectance_at = |m: &gonio_render::material::Material, x: f32| {
        let at = ShadingPoint {
            p: Vec3::new(x, 0.3, 0.0),
            ..ShadingPoint::flat(Vec2::ZERO)
        };
        let f = m
            .bsdf_at_point(&at, &wl)
            .eval(&BsdfContext::radiance(), Vec3::Z, Vec3::Z, &wl);
        f[0] * std::f32::consts::PI
    };
    for (x, want) in [(0.0f32, 0.4f32), (-0.5, 0.3), (1.5, 0.6), (-1.8, 0.2)] {
        let got = reflectance_at(m, x);
        assert!((got - want).abs() < 1e-5, "x = {x}: {got} vs {want}");
    }
    // Two channels: refused, naming the file, line and value.
    let e = load(scene("g2.vol")).expect_err("2 channels").to_string();
    assert!(
        e.contains("scene.xml:6") && e.contains("g2.vol") && e.contains("2 channels"),
        "{e}"
    );
    // A missing file.
    let e = load(scene("none.vol")).expect_err("no file").to_string();
    assert!(e.contains("scene.xml:6") && e.contains("none.vol"), "{e}");
    // A `constvolume`: the same value at every point.
    let s = load(
        "<scene version=\"3.0.0\"><shape type=\"rectangle\"><bsdf type=\"diffuse\">\
         <texture type=\"volume\" name=\"reflectance\"><volume type=\"constvolume\" name=\"volume\">\
         <float name=\"value\" value=\"0.35\"/></volume></texture></bsdf></shape></scene>"
            .to_string(),
    )
    .expect("constvolume loads");
    let m = &s.materials[s.shapes[0].material];
    for x in [-3.0f32, 0.0, 7.0] {
        let got = reflectance_at(m, x);
        assert!((got - 0.35).abs() < 1e-6, "x = {x}: {got}");
    }
}

// ---------------------------------------------------------------------------------------------
// `mesh_attribute` in instances and as an area emitter's radiance: renders against renders,
// constants and errors.

mod attributes;
