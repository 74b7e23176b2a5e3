//! The `serialized` shape: the same mesh as a PLY file, Mitsuba's material-preview meshes, and
//! errors that name the file, the line and the value.

use flate2::Compression;
use flate2::write::ZlibEncoder;
use gonio_render::scene::{Geometry, Scene, TriangleMesh};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mitsuba-corpus")
}

fn meshes(scene: &Scene) -> Vec<Arc<TriangleMesh>> {
    scene
        .shapes
        .iter()
        .map(|s| match &s.geometry {
            Geometry::Mesh(m) => m.clone(),
            g => panic!("not a mesh: {g:?}"),
        })
        .collect()
}

fn shapes_xml(shapes: &str) -> String {
    format!(r#"<scene version="3.0.0"><path value="common"/>{shapes}</scene>"#)
}

/// A tetrahedron with per-vertex normals and uvs, as Mitsuba serialized (version 4, single
/// precision) and as an ASCII PLY file.
fn write_tetrahedron(dir: &Path) {
    let p = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let n = [
        [-0.57735f32, -0.57735, -0.57735],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let uv = [[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.5]];
    let t = [[0u32, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let mut b = (0x1000u32 | 0x1 | 0x2).to_le_bytes().to_vec();
    b.extend_from_slice(b"tetra\0");
    b.extend_from_slice(&4u64.to_le_bytes());
    b.extend_from_slice(&4u64.to_le_bytes());
    for v in p
        .iter()
        .flatten()
        .chain(n.iter().flatten())
        .chain(uv.iter().flatten())
    {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for i in t.iter().flatten() {
        b.extend_from_slice(&i.to_le_bytes());
    }
    let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
    z.write_all(&b).unwrap();
    let mut f = 0x041Cu16.to_le_bytes().to_vec();
    f.extend_from_slice(&4u16.to_le_bytes());
    f.extend(z.finish().unwrap());
    f.extend_from_slice(&0u64.to_le_bytes());
    f.extend_from_slice(&1u32.to_le_bytes());
    std::fs::write(dir.join("tetra.serialized"), f).unwrap();
    let mut ply = String::from(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n\
         element face 4\nproperty list uchar int vertex_indices\nend_header\n",
    );
    for k in 0..4 {
        let [x, y, z] = p[k];
        let [a, b, c] = n[k];
        let [u, v] = uv[k];
        ply += &format!("{x} {y} {z} {a} {b} {c} {u} {v}\n");
    }
    for [i, j, k] in t {
        ply += &format!("3 {i} {j} {k}\n");
    }
    std::fs::write(dir.join("tetra.ply"), ply).unwrap();
}

#[test]
fn serialized_mesh_equals_the_same_mesh_as_ply() {
    let dir = std::env::temp_dir().join(format!("gonio-serialized-ply-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    write_tetrahedron(&dir);
    let xml = r#"<scene version="3.0.0">
        <shape type="serialized"><string name="filename" value="tetra.serialized"/>
            <transform name="to_world"><scale value="2"/><translate x="1"/></transform></shape>
        <shape type="ply"><string name="filename" value="tetra.ply"/>
            <transform name="to_world"><scale value="2"/><translate x="1"/></transform></shape>
    </scene>"#;
    let scene = gonio_render::xml::load_scene_str(xml, &dir, &[]);
    std::fs::remove_dir_all(&dir).unwrap();
    let scene = scene.unwrap();
    let m = meshes(&scene);
    assert_eq!(m[0].positions, m[1].positions);
    assert_eq!(m[0].normals, m[1].normals);
    assert_eq!(m[0].uvs, m[1].uvs);
    assert_eq!(m[0].indices, m[1].indices);
    assert_eq!(scene.shapes[0].to_world, scene.shapes[1].to_world);
}

#[test]
fn matpreview_meshes_load_by_shape_index() {
    // Vertex and triangle counts of the three meshes of Mitsuba's matpreview.serialized (format
    // version 3), read with Python's zlib and struct.
    let xml = shapes_xml(
        r#"<shape type="serialized"><string name="filename" value="meshes/matpreview.serialized"/></shape>
        <shape type="serialized"><string name="filename" value="meshes/matpreview.serialized"/>
            <integer name="shape_index" value="1"/></shape>
        <shape type="serialized"><string name="filename" value="meshes/matpreview.serialized"/>
            <integer name="shape_index" value="2"/><boolean name="face_normals" value="true"/></shape>"#,
    );
    let scene = gonio_render::xml::load_scene_str(&xml, corpus(), &[]).unwrap();
    let m = meshes(&scene);
    let counts: Vec<(usize, usize)> = m.iter().map(|m| (m.positions.len(), m.indices.len())).collect();
    assert_eq!(counts, vec![(289, 512), (2078, 3936), (29439, 57152)]);
    assert!(
        m[0].normals.len() == 289 && m[0].uvs.len() == 289,
        "the file has normals and uvs"
    );
    assert!(m[2].normals.is_empty() && scene.shapes[2].face_normals);
}

#[test]
fn bad_serialized_files_name_file_line_and_value() {
    let err = |shape: &str| {
        gonio_render::xml::load_scene_str(&shapes_xml(shape), corpus(), &[])
            .unwrap_err()
            .to_string()
    };
    let e = err(
        r#"<shape type="serialized"><string name="filename" value="meshes/matpreview.serialized"/>
        <integer name="shape_index" value="3"/></shape>"#,
    );
    assert!(
        e.contains("matpreview.serialized") && e.contains("shape_index 3") && e.contains(":1:"),
        "{e}"
    );
    let e = err(
        r#"<shape type="serialized"><string name="filename" value="meshes/matpreview.serialized"/>
        <integer name="shape_index" value="-1"/></shape>"#,
    );
    assert!(e.contains("shape_index -1") && e.contains(":2:"), "{e}");
    let e = err(r#"<shape type="serialized"><string name="filename" value="textures/museum.exr"/></shape>"#);
    assert!(e.contains("museum.exr") && e.contains("format identifier"), "{e}");
    let e = err(r#"<shape type="serialized"><string name="filename" value="missing.serialized"/></shape>"#);
    assert!(e.contains("missing.serialized"), "{e}");
}
