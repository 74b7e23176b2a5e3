//! Mesh attributes: the extra vertex and face properties of a PLY file, as Mitsuba 3 groups and
//! names them (`src/shapes/ply.cpp`, `find_other_fields`), for the `mesh_attribute` texture.
//!
//! Naming (checked against Mitsuba 3.9.1 `scalar_rgb`/`scalar_spectral` by loading small PLY
//! files and reading `Mesh::attribute_buffer`):
//!
//! * `r g b [a]` or `red green blue [alpha]` become `vertex_color` / `face_color` (3 or 4
//!   values);
//! * other properties are grouped by consecutive runs `{prefix}_{postfix}` whose postfixes follow
//!   one of the sequences `x y z w`, `r g b a`, `0 1 2 3`, `1 2 3 4` from its start; a run of 1 or
//!   3 properties becomes `vertex_{prefix}` / `face_{prefix}` (`…_{prefix}_color` for `r g b`),
//!   other lengths, properties without `_`, postfixes longer than one letter, runs that do not
//!   start a sequence and prefixes seen before are ignored (Mitsuba warns);
//! * positions, normals, texture coordinates and the face index list are never attributes.
//!
//! Values as Mitsuba 3.9.1 stores them: floats (`float`, `double`) as they are; `uchar` as its
//! integer value (not scaled, as measured: Mitsuba warns that colours are expected in [0, 1]);
//! the other integer types divided by their largest value and decoded from sRGB to linear
//! (`Struct`'s normalized + gamma conversion). A polygon face fan-triangulated into n triangles
//! gives its face attributes to each of them.
//!
//! Memory: every attribute is kept as `f32` (4 bytes per value, as Mitsuba keeps them) while the
//! scene is read; a shape keeps only the attributes its textures name ([`MeshAttributes::pick`]).

/// Where an attribute lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AttributeKind {
    /// One value set per vertex, interpolated with the hit's barycentric coordinates.
    Vertex,
    /// One value set per triangle.
    Face,
}

/// One named attribute: `dim` values per vertex or per triangle.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshAttribute {
    /// Mitsuba's name (`vertex_color`, `face_weight`, …).
    pub name: String,
    /// Per vertex or per face.
    pub kind: AttributeKind,
    /// Values per element (1, 3 or 4).
    pub dim: usize,
    /// `dim` values per vertex (or per triangle), element after element.
    pub data: Vec<f32>,
}

/// The attributes of one mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshAttributes {
    /// In file order, vertex attributes first.
    pub list: Vec<MeshAttribute>,
}

impl MeshAttributes {
    /// The attribute called `name`.
    pub fn get(&self, name: &str) -> Option<&MeshAttribute> {
        self.list.iter().find(|a| a.name == name)
    }

    /// The names, for error messages.
    pub fn names(&self) -> Vec<&str> {
        self.list.iter().map(|a| a.name.as_str()).collect()
    }

    /// Only the attributes called `names` (each at most once), what a shape keeps.
    pub fn pick(&self, names: &[&str]) -> MeshAttributes {
        MeshAttributes {
            list: self
                .list
                .iter()
                .filter(|a| names.contains(&a.name.as_str()))
                .cloned()
                .collect(),
        }
    }
}

/// A group of properties (indices into an element's property list) forming one attribute.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct AttributeGroup {
    pub name: String,
    pub props: Vec<usize>,
}

const POSTFIXES: [[char; 4]; 4] = [
    ['x', 'y', 'z', 'w'],
    ['r', 'g', 'b', 'a'],
    ['0', '1', '2', '3'],
    ['1', '2', '3', '4'],
];

/// The attributes Mitsuba forms from the scalar properties `names` of an element (`None` for
/// list properties), `prefix` being `"vertex_"` or `"face_"` and `reserved` the properties the
/// mesh itself uses.
pub(crate) fn group_properties(
    prefix: &str,
    names: &[Option<&str>],
    reserved: &[&str],
) -> Vec<AttributeGroup> {
    let find = |n: &str| names.iter().position(|x| *x == Some(n));
    let mut groups = Vec::new();
    // Colours without a prefix.
    let rgb = ["r", "g", "b", "a"];
    let long = ["red", "green", "blue", "alpha"];
    let colour = if [0, 1, 2].iter().all(|&i| find(rgb[i]).is_some()) {
        Some(rgb)
    } else if [0, 1, 2].iter().all(|&i| find(long[i]).is_some()) {
        Some(long)
    } else {
        None
    };
    let mut taken: Vec<usize> = Vec::new();
    if let Some(c) = colour {
        let mut props: Vec<usize> = c[..3].iter().filter_map(|n| find(n)).collect();
        if let Some(a) = find(c[3]) {
            props.push(a);
        }
        taken.extend(&props);
        groups.push(AttributeGroup {
            name: format!("{prefix}color"),
            props,
        });
    }
    let is_reserved = |i: usize, n: &str| reserved.contains(&n) || rgb.contains(&n) || taken.contains(&i);

    // Runs of {prefix}_{postfix}.
    struct Run {
        prefix: String,
        category: usize,
        props: Vec<usize>,
    }
    let mut seen: Vec<String> = Vec::new();
    let mut run: Option<Run> = None;
    let flush = |run: &mut Option<Run>, groups: &mut Vec<AttributeGroup>, seen: &mut Vec<String>| {
        if let Some(r) = run.take()
            && (r.props.len() == 1 || r.props.len() == 3)
        {
            let colour = if r.category == 1 { "_color" } else { "" };
            groups.push(AttributeGroup {
                name: format!("{prefix}{}{colour}", r.prefix),
                props: r.props,
            });
            seen.push(r.prefix);
        }
    };
    let mut i = 0;
    while i < names.len() {
        let Some(name) = names[i] else {
            i += 1;
            continue;
        };
        if is_reserved(i, name) {
            i += 1;
            continue;
        }
        let Some(pos) = name.rfind('_') else {
            flush(&mut run, &mut groups, &mut seen);
            i += 1;
            continue;
        };
        let (pre, post) = (&name[..pos], &name[pos + 1..]);
        let mut chars = post.chars();
        let (Some(c), None) = (chars.next(), chars.next()) else {
            flush(&mut run, &mut groups, &mut seen);
            i += 1;
            continue;
        };
        if run.as_ref().is_some_and(|r| r.prefix != pre) {
            flush(&mut run, &mut groups, &mut seen);
        }
        match &mut run {
            None => {
                if seen.iter().any(|s| s == pre) {
                    // A prefix seen before: its properties are ignored.
                    while i < names.len() && names[i].is_some_and(|n| n.starts_with(pre)) {
                        i += 1;
                    }
                    continue;
                }
                if let Some(category) = (0..4).find(|&k| POSTFIXES[k][0] == c) {
                    run = Some(Run {
                        prefix: pre.to_owned(),
                        category,
                        props: vec![i],
                    });
                }
            }
            Some(r) => {
                let level = r.props.len();
                if level < 4 && POSTFIXES[r.category][level] == c {
                    r.props.push(i);
                } else {
                    // A broken sequence: the attribute is ignored, with the rest of its prefix.
                    run = None;
                    while i < names.len() && names[i].is_some_and(|n| n.starts_with(pre)) {
                        i += 1;
                    }
                    continue;
                }
            }
        }
        i += 1;
    }
    flush(&mut run, &mut groups, &mut seen);
    groups
}

/// The sRGB transfer function's inverse, odd-symmetric (Mitsuba's gamma conversion of
/// normalized integers).
fn srgb_to_linear(x: f64) -> f64 {
    let a = x.abs();
    let l = if a <= 0.04045 {
        a / 12.92
    } else {
        ((a + 0.055) / 1.055).powf(2.4)
    };
    l.copysign(x)
}

/// An attribute value read from a property of integer or float type as Mitsuba 3.9.1 stores it
/// (see the module documentation). `max` is the type's largest value for integers other than
/// `uchar`, `None` otherwise.
pub(crate) fn attribute_value(v: f64, max: Option<f64>) -> f32 {
    match max {
        Some(m) => srgb_to_linear(v / m) as f32,
        None => v as f32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(prefix: &str, props: &[&str]) -> Vec<(String, Vec<usize>)> {
        let n: Vec<Option<&str>> = props.iter().map(|p| Some(*p)).collect();
        group_properties(prefix, &n, &["x", "y", "z", "nx", "ny", "nz", "u", "v"])
            .into_iter()
            .map(|g| (g.name, g.props))
            .collect()
    }

    /// The groups Mitsuba 3.9.1 forms from the same property lists (its `has_attribute` on a
    /// one-triangle PLY of each list).
    #[test]
    fn properties_group_as_in_mitsuba() {
        let g = |n: &str, p: &[usize]| (n.to_string(), p.to_vec());
        assert_eq!(
            names("vertex_", &["x", "y", "z", "r", "g", "b"]),
            vec![g("vertex_color", &[3, 4, 5])]
        );
        assert_eq!(
            names("vertex_", &["x", "y", "z", "red", "green", "blue", "alpha"]),
            vec![g("vertex_color", &[3, 4, 5, 6])]
        );
        assert_eq!(
            names("face_", &["foo_0", "foo_1", "foo_2"]),
            vec![g("face_foo", &[0, 1, 2])]
        );
        assert_eq!(
            names("vertex_", &["x", "y", "z", "foo_r", "foo_g", "foo_b"]),
            vec![g("vertex_foo_color", &[3, 4, 5])]
        );
        assert_eq!(
            names("face_", &["foo_1", "foo_2", "foo_3"]),
            vec![g("face_foo", &[0, 1, 2])]
        );
        assert_eq!(names("face_", &["q_1"]), vec![g("face_q", &[0])]);
        // Two or four values, no postfix, a sequence not started at its beginning or broken:
        // nothing (Mitsuba warns).
        assert!(names("vertex_", &["foo_x", "foo_y"]).is_empty());
        assert!(names("vertex_", &["foo_x", "foo_y", "foo_z", "foo_w"]).is_empty());
        assert!(names("vertex_", &["foo"]).is_empty());
        assert!(names("vertex_", &["foo_y"]).is_empty());
        assert!(names("vertex_", &["foo_x", "foo_z"]).is_empty());
        assert!(names("vertex_", &["foo_xx"]).is_empty());
        assert_eq!(
            names("vertex_", &["foo_x", "bar_x"]),
            vec![g("vertex_foo", &[0]), g("vertex_bar", &[1])]
        );
        // A prefix seen before is ignored.
        assert_eq!(
            names("vertex_", &["foo_x", "bar_x", "foo_y"]),
            vec![g("vertex_foo", &[0]), g("vertex_bar", &[1])]
        );
        // Normals and texture coordinates are the mesh's own.
        assert_eq!(
            names("vertex_", &["x", "y", "z", "nx", "ny", "nz", "u", "v", "foo_x"]),
            vec![g("vertex_foo", &[8])]
        );
    }

    /// Values Mitsuba 3.9.1 stores for integer properties (`attribute_buffer` of `w_x`).
    #[test]
    fn integer_values_as_mitsuba_stores_them() {
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * b.abs().max(1e-30);
        // uchar: the integer itself.
        assert_eq!(attribute_value(128.0, None), 128.0);
        // char -5, 100 / 127; short ±1000 / 32767; ushort 1000 / 65535; int 1000 / (2³¹ − 1).
        assert!(close(attribute_value(-5.0, Some(127.0)), -0.003_047_219_7));
        assert!(close(attribute_value(100.0, Some(127.0)), 0.582_693_5));
        assert!(close(attribute_value(-1000.0, Some(32767.0)), -0.002_362_113_7));
        assert!(close(attribute_value(1000.0, Some(65535.0)), 0.001_181_038_8));
        assert!(close(attribute_value(1000.0, Some(2147483647.0)), 3.604_189_7e-8));
        assert!(close(attribute_value(65535.0, Some(65535.0)), 1.0));
    }

    /// A quad face with colours per vertex (`uchar`, kept as integers as Mitsuba does) and a
    /// weight per face (`ushort`, normalized and sRGB-decoded): the fan's two triangles share it.
    #[test]
    fn ply_attributes_are_read_per_vertex_and_per_triangle() {
        let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
            property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
            element face 1\nproperty list uchar int vertex_indices\nproperty ushort weight_1\n\
            end_header\n0 0 0 1 2 3\n1 0 0 4 5 6\n1 1 0 7 8 9\n0 1 0 10 11 12\n4 0 1 2 3 1000\n";
        let (mesh, attrs) = crate::mesh::parse_ply_with_attributes(text.as_bytes(), false).unwrap();
        assert_eq!(mesh.indices.len(), 2);
        assert_eq!(attrs.names(), vec!["vertex_color", "face_weight"]);
        let c = attrs.get("vertex_color").unwrap();
        assert_eq!((c.kind, c.dim), (AttributeKind::Vertex, 3));
        assert_eq!(c.data, (1..=12).map(|i| i as f32).collect::<Vec<_>>());
        let w = attrs.get("face_weight").unwrap();
        assert_eq!((w.kind, w.dim), (AttributeKind::Face, 1));
        assert_eq!(w.data.len(), 2);
        assert!(
            w.data.iter().all(|&v| (v - 0.001_181_038_8).abs() < 1e-9),
            "{:?}",
            w.data
        );
        // A shape keeps only what its textures name.
        assert_eq!(attrs.pick(&["face_weight"]).names(), vec!["face_weight"]);
    }
}
