//! Triangle meshes from files (`obj`, `ply`, Mitsuba's `serialized` in [`serialized`]) and
//! Mitsuba's `cube`.
//!
//! * OBJ: `tobj`, triangulated, one index per vertex (position/normal/uv merged); all objects of
//!   the file become one mesh. `flip_tex_coords` (Mitsuba default true for OBJ) maps v → 1 − v.
//! * PLY: our own reader for ASCII and binary (little/big endian) files. Why not a crate: the
//!   well-kept one (`ply-rs-bw`) stores each element in a string-keyed map unless one implements
//!   its access trait, which is slow for million-triangle meshes and about as long as this reader;
//!   here we read exactly the properties we use straight into the mesh arrays and report errors
//!   with the element and property involved. Vertex `x y z`, optional `nx ny nz` and
//!   `u v` / `s t` / `texture_u texture_v` / `texture_s texture_t`; faces as `vertex_indices` (or
//!   `vertex_index`) lists, fan-triangulated; other vertex and face properties become mesh
//!   attributes as Mitsuba names them ([`attributes`], [`load_ply_with_attributes`]); other
//!   elements are skipped.
//!
//! Every error names the file.

pub mod attributes;
pub mod serialized;

use crate::scene::TriangleMesh;
use attributes::{AttributeKind, MeshAttribute, MeshAttributes, attribute_value, group_properties};
use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};

/// A mesh file that could not be read.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The content is malformed or unsupported.
    #[error("{}: {message}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl MeshError {
    /// True when the file could not be read at all (missing, unreadable).
    pub fn is_io(&self) -> bool {
        matches!(self, MeshError::Io { .. })
    }
}

fn format_err(path: &Path, message: impl Into<String>) -> MeshError {
    MeshError::Format {
        path: path.to_owned(),
        message: message.into(),
    }
}

/// Mitsuba's `cube`: [−1, 1]³ as 12 triangles, 4 vertices per face with the face normal and uvs
/// (0, 1), (1, 1), (1, 0), (0, 0) (`src/shapes/cube.cpp`).
pub fn cube() -> TriangleMesh {
    const P: [[f32; 3]; 24] = [
        [1., -1., -1.],
        [1., -1., 1.],
        [-1., -1., 1.],
        [-1., -1., -1.],
        [1., 1., -1.],
        [-1., 1., -1.],
        [-1., 1., 1.],
        [1., 1., 1.],
        [1., -1., -1.],
        [1., 1., -1.],
        [1., 1., 1.],
        [1., -1., 1.],
        [1., -1., 1.],
        [1., 1., 1.],
        [-1., 1., 1.],
        [-1., -1., 1.],
        [-1., -1., 1.],
        [-1., 1., 1.],
        [-1., 1., -1.],
        [-1., -1., -1.],
        [1., 1., -1.],
        [1., -1., -1.],
        [-1., -1., -1.],
        [-1., 1., -1.],
    ];
    const N: [[f32; 3]; 6] = [
        [0., -1., 0.],
        [0., 1., 0.],
        [1., 0., 0.],
        [0., 0., 1.],
        [-1., 0., 0.],
        [0., 0., -1.],
    ];
    const UV: [[f32; 2]; 4] = [[0., 1.], [1., 1.], [1., 0.], [0., 0.]];
    let positions = P.iter().map(|p| Vec3::from_array(*p)).collect();
    let normals = (0..24).map(|i| Vec3::from_array(N[i / 4])).collect();
    let uvs = (0..24).map(|i| Vec2::from_array(UV[i % 4])).collect();
    let indices = (0..6u32)
        .flat_map(|f| [[4 * f, 4 * f + 1, 4 * f + 2], [4 * f + 3, 4 * f, 4 * f + 2]])
        .collect();
    TriangleMesh {
        positions,
        normals,
        uvs,
        indices,
    }
}

/// Per-vertex normals weighted by the angle each triangle makes at the vertex (Mitsuba's
/// `recompute_vertex_normals`, Thürmer & Wüthrich 1998), for meshes that come without normals.
/// A vertex whose triangles are all degenerate gets +z.
pub fn vertex_normals(m: &TriangleMesh) -> Vec<Vec3> {
    let mut n = vec![Vec3::ZERO; m.positions.len()];
    for t in &m.indices {
        let p = t.map(|i| m.positions[i as usize]);
        let face = (p[1] - p[0]).cross(p[2] - p[0]);
        if !(face.length_squared() > 0.0) {
            continue;
        }
        let face = face.normalize();
        for k in 0..3 {
            let a = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
            let b = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
            let angle = a.dot(b).clamp(-1.0, 1.0).acos();
            if angle.is_finite() {
                n[t[k] as usize] += face * angle;
            }
        }
    }
    n.into_iter()
        .map(|v| {
            if v.length_squared() > 0.0 {
                v.normalize()
            } else {
                Vec3::Z
            }
        })
        .collect()
}

/// Checks sizes, index ranges and finiteness.
fn validate(path: &Path, m: &TriangleMesh) -> Result<(), MeshError> {
    let n = m.positions.len();
    if m.indices.is_empty() {
        return Err(format_err(path, "the mesh has no triangles"));
    }
    if let Some((i, p)) = m.positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(format_err(
            path,
            format!("vertex {i} has a non-finite position {p}"),
        ));
    }
    if let Some((t, tri)) = m
        .indices
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&i| i as usize >= n))
    {
        return Err(format_err(
            path,
            format!(
                "triangle {t} refers to vertex {:?}, but there are only {n} vertices",
                tri
            ),
        ));
    }
    if !m.normals.is_empty() && m.normals.len() != n {
        return Err(format_err(
            path,
            format!("{} normals for {n} vertices", m.normals.len()),
        ));
    }
    if !m.uvs.is_empty() && m.uvs.len() != n {
        return Err(format_err(
            path,
            format!("{} texture coordinates for {n} vertices", m.uvs.len()),
        ));
    }
    Ok(())
}

/// Reads a Wavefront OBJ file (all objects merged, polygons triangulated).
pub fn load_obj(path: &Path, flip_tex_coords: bool) -> Result<TriangleMesh, MeshError> {
    if let Err(source) = std::fs::metadata(path) {
        return Err(MeshError::Io {
            path: path.to_owned(),
            source,
        });
    }
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _materials) =
        tobj::load_obj(path, &opts).map_err(|e| format_err(path, format!("invalid OBJ: {e}")))?;
    let mut out = TriangleMesh::default();
    let all_normals = models.iter().all(|m| !m.mesh.normals.is_empty());
    let all_uvs = models.iter().all(|m| !m.mesh.texcoords.is_empty());
    for m in &models {
        let mesh = &m.mesh;
        let base = out.positions.len() as u32;
        let nv = mesh.positions.len() / 3;
        out.positions.extend(
            mesh.positions
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2])),
        );
        if all_normals {
            if mesh.normals.len() != 3 * nv {
                return Err(format_err(
                    path,
                    format!("object \"{}\": normal count does not match", m.name),
                ));
            }
            out.normals
                .extend(mesh.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        }
        if all_uvs {
            if mesh.texcoords.len() != 2 * nv {
                return Err(format_err(
                    path,
                    format!("object \"{}\": texture coordinate count does not match", m.name),
                ));
            }
            out.uvs.extend(
                mesh.texcoords
                    .chunks_exact(2)
                    .map(|c| Vec2::new(c[0], if flip_tex_coords { 1.0 - c[1] } else { c[1] })),
            );
        }
        if mesh.indices.len() % 3 != 0 {
            return Err(format_err(
                path,
                format!("object \"{}\": index count is not a multiple of 3", m.name),
            ));
        }
        out.indices.extend(
            mesh.indices
                .chunks_exact(3)
                .map(|c| [base + c[0], base + c[1], base + c[2]]),
        );
    }
    validate(path, &out)?;
    Ok(out)
}

/// Scalar types of PLY properties.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PlyType {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl PlyType {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "char" | "int8" => PlyType::I8,
            "uchar" | "uint8" => PlyType::U8,
            "short" | "int16" => PlyType::I16,
            "ushort" | "uint16" => PlyType::U16,
            "int" | "int32" => PlyType::I32,
            "uint" | "uint32" => PlyType::U32,
            "float" | "float32" => PlyType::F32,
            "double" | "float64" => PlyType::F64,
            _ => return None,
        })
    }
    /// The divisor Mitsuba 3.9.1 normalizes an attribute of this type by (`None`: stored as is).
    fn attribute_max(self) -> Option<f64> {
        match self {
            PlyType::I8 => Some(i8::MAX as f64),
            PlyType::I16 => Some(i16::MAX as f64),
            PlyType::U16 => Some(u16::MAX as f64),
            PlyType::I32 => Some(i32::MAX as f64),
            PlyType::U32 => Some(u32::MAX as f64),
            PlyType::U8 | PlyType::F32 | PlyType::F64 => None,
        }
    }

    fn size(self) -> usize {
        match self {
            PlyType::I8 | PlyType::U8 => 1,
            PlyType::I16 | PlyType::U16 => 2,
            PlyType::I32 | PlyType::U32 | PlyType::F32 => 4,
            PlyType::F64 => 8,
        }
    }
}

#[derive(Debug)]
struct PlyProperty {
    name: String,
    /// `Some(count type)` for a list.
    list: Option<PlyType>,
    ty: PlyType,
}

#[derive(Debug)]
struct PlyElement {
    name: String,
    count: usize,
    props: Vec<PlyProperty>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PlyFormat {
    Ascii,
    LittleEndian,
    BigEndian,
}

/// The body of a PLY file, read value by value.
struct PlyBody<'a> {
    format: PlyFormat,
    bytes: &'a [u8],
    pos: usize,
}

impl PlyBody<'_> {
    fn next_token(&mut self) -> Option<&str> {
        let b = self.bytes;
        while self.pos < b.len() && b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < b.len() && !b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            None
        } else {
            std::str::from_utf8(&b[start..self.pos]).ok()
        }
    }

    /// Reads one value of type `ty` as f64 (exact for every PLY integer type).
    fn read(&mut self, ty: PlyType) -> Result<f64, String> {
        if self.format == PlyFormat::Ascii {
            let t = self.next_token().ok_or("unexpected end of file")?;
            return t.parse::<f64>().map_err(|_| format!("invalid number \"{t}\""));
        }
        let n = ty.size();
        let Some(raw) = self.bytes.get(self.pos..self.pos + n) else {
            return Err("unexpected end of file".into());
        };
        self.pos += n;
        let mut a = [0u8; 8];
        a[..n].copy_from_slice(raw);
        if self.format == PlyFormat::BigEndian {
            a[..n].reverse();
        }
        Ok(match ty {
            PlyType::I8 => a[0] as i8 as f64,
            PlyType::U8 => a[0] as f64,
            PlyType::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
            PlyType::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
            PlyType::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            PlyType::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            PlyType::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            PlyType::F64 => f64::from_le_bytes(a),
        })
    }
}

/// Splits the header (up to and including the `end_header` line) from the body.
fn ply_header(bytes: &[u8]) -> Option<(&str, &[u8])> {
    let key = b"end_header";
    let i = bytes.windows(key.len()).position(|w| w == key)?;
    let mut end = i + key.len();
    // The line ends with \n or \r\n.
    while end < bytes.len() && bytes[end] != b'\n' {
        end += 1;
    }
    let body_start = (end + 1).min(bytes.len());
    Some((std::str::from_utf8(&bytes[..i]).ok()?, &bytes[body_start..]))
}

/// Reads a PLY file, ASCII or binary.
pub fn load_ply(path: &Path, flip_tex_coords: bool) -> Result<TriangleMesh, MeshError> {
    load_ply_with_attributes(path, flip_tex_coords).map(|(m, _)| m)
}

/// Reads a PLY file with its extra vertex and face properties as Mitsuba's mesh attributes.
pub fn load_ply_with_attributes(
    path: &Path,
    flip_tex_coords: bool,
) -> Result<(TriangleMesh, MeshAttributes), MeshError> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_owned(),
        source,
    })?;
    parse_ply_with_attributes(&bytes, flip_tex_coords).map_err(|m| format_err(path, m))
}

#[cfg(test)]
fn parse_ply(bytes: &[u8], flip_tex_coords: bool) -> Result<TriangleMesh, String> {
    parse_ply_with_attributes(bytes, flip_tex_coords).map(|(m, _)| m)
}

/// The vertex properties that are the mesh's own, never attributes.
const VERTEX_RESERVED: &[&str] = &[
    "x",
    "y",
    "z",
    "nx",
    "ny",
    "nz",
    "u",
    "v",
    "s",
    "t",
    "texture_u",
    "texture_v",
    "texture_s",
    "texture_t",
];

/// The attributes `groups` of an element with properties `props`, with room for `count` elements.
fn new_attributes(
    groups: &[attributes::AttributeGroup],
    kind: AttributeKind,
    count: usize,
    cap: usize,
) -> Vec<MeshAttribute> {
    groups
        .iter()
        .map(|g| MeshAttribute {
            name: g.name.clone(),
            kind,
            dim: g.props.len(),
            data: Vec::with_capacity((count * g.props.len()).min(cap)),
        })
        .collect()
}

fn parse_ply_with_attributes(
    bytes: &[u8],
    flip_tex_coords: bool,
) -> Result<(TriangleMesh, MeshAttributes), String> {
    if !bytes.starts_with(b"ply") {
        return Err("not a PLY file (missing the \"ply\" magic line)".into());
    }
    let (header, body) = ply_header(bytes).ok_or("PLY header without \"end_header\"")?;
    let mut format = None;
    let mut elements: Vec<PlyElement> = Vec::new();
    for (lineno, line) in header.lines().enumerate().skip(1) {
        let mut t = line.split_whitespace();
        let Some(kw) = t.next() else { continue };
        let bad = || format!("header line {}: cannot parse \"{}\"", lineno + 1, line.trim());
        match kw {
            "format" => {
                format = Some(match t.next() {
                    Some("ascii") => PlyFormat::Ascii,
                    Some("binary_little_endian") => PlyFormat::LittleEndian,
                    Some("binary_big_endian") => PlyFormat::BigEndian,
                    _ => return Err(bad()),
                })
            }
            "comment" | "obj_info" => {}
            "element" => {
                let name = t.next().ok_or_else(bad)?.to_owned();
                let count = t.next().and_then(|c| c.parse().ok()).ok_or_else(bad)?;
                elements.push(PlyElement {
                    name,
                    count,
                    props: Vec::new(),
                });
            }
            "property" => {
                let el = elements.last_mut().ok_or_else(bad)?;
                let a = t.next().ok_or_else(bad)?;
                let prop = if a == "list" {
                    let ct = PlyType::parse(t.next().ok_or_else(bad)?).ok_or_else(bad)?;
                    let ty = PlyType::parse(t.next().ok_or_else(bad)?).ok_or_else(bad)?;
                    PlyProperty {
                        name: t.next().ok_or_else(bad)?.to_owned(),
                        list: Some(ct),
                        ty,
                    }
                } else {
                    let ty = PlyType::parse(a).ok_or_else(bad)?;
                    PlyProperty {
                        name: t.next().ok_or_else(bad)?.to_owned(),
                        list: None,
                        ty,
                    }
                };
                el.props.push(prop);
            }
            _ => return Err(bad()),
        }
    }
    let format = format.ok_or("PLY header without a \"format\" line")?;
    let mut body = PlyBody {
        format,
        bytes: body,
        pos: 0,
    };
    let mut mesh = TriangleMesh::default();
    let mut attrs = MeshAttributes::default();
    let mut n_vertices = None;
    for el in &elements {
        let find = |names: &[&str]| {
            el.props
                .iter()
                .position(|p| names.contains(&p.name.as_str()) && p.list.is_none())
        };
        match el.name.as_str() {
            "vertex" => {
                let xyz = [find(&["x"]), find(&["y"]), find(&["z"])];
                let [Some(ix), Some(iy), Some(iz)] = xyz else {
                    return Err("the vertex element lacks x, y or z".into());
                };
                let nrm = [find(&["nx"]), find(&["ny"]), find(&["nz"])];
                let has_n = nrm.iter().all(Option::is_some);
                let u = find(&["u", "s", "texture_u", "texture_s"]);
                let v = find(&["v", "t", "texture_v", "texture_t"]);
                let has_uv = u.is_some() && v.is_some();
                mesh.positions.reserve(el.count.min(body.bytes.len()));
                let prop_names: Vec<Option<&str>> = el
                    .props
                    .iter()
                    .map(|p| p.list.is_none().then_some(p.name.as_str()))
                    .collect();
                let groups = group_properties("vertex_", &prop_names, VERTEX_RESERVED);
                let mut va = new_attributes(&groups, AttributeKind::Vertex, el.count, body.bytes.len());
                let mut vals = vec![0f64; el.props.len()];
                for i in 0..el.count {
                    for (k, p) in el.props.iter().enumerate() {
                        if let Some(ct) = p.list {
                            let n = body.read(ct).map_err(|e| format!("vertex {i}: {e}"))? as usize;
                            for _ in 0..n {
                                body.read(p.ty).map_err(|e| format!("vertex {i}: {e}"))?;
                            }
                        } else {
                            vals[k] = body
                                .read(p.ty)
                                .map_err(|e| format!("vertex {i}, property {}: {e}", p.name))?;
                        }
                    }
                    mesh.positions
                        .push(Vec3::new(vals[ix] as f32, vals[iy] as f32, vals[iz] as f32));
                    if has_n {
                        let [a, b, c] = nrm.map(|j| vals[j.expect("checked")] as f32);
                        mesh.normals.push(Vec3::new(a, b, c));
                    }
                    if has_uv {
                        let (uu, vv) = (vals[u.expect("checked")] as f32, vals[v.expect("checked")] as f32);
                        mesh.uvs
                            .push(Vec2::new(uu, if flip_tex_coords { 1.0 - vv } else { vv }));
                    }
                    for (g, a) in groups.iter().zip(&mut va) {
                        a.data.extend(
                            g.props
                                .iter()
                                .map(|&k| attribute_value(vals[k], el.props[k].ty.attribute_max())),
                        );
                    }
                }
                attrs.list.extend(va);
                n_vertices = Some(el.count);
            }
            "face" => {
                let Some(fi) = el.props.iter().position(|p| {
                    (p.name == "vertex_indices" || p.name == "vertex_index") && p.list.is_some()
                }) else {
                    return Err("the face element lacks a vertex_indices list".into());
                };
                mesh.indices.reserve(el.count.min(body.bytes.len()));
                let prop_names: Vec<Option<&str>> = el
                    .props
                    .iter()
                    .map(|p| p.list.is_none().then_some(p.name.as_str()))
                    .collect();
                let groups = group_properties("face_", &prop_names, &[]);
                let mut fa = new_attributes(&groups, AttributeKind::Face, el.count, body.bytes.len());
                let mut vals = vec![0f64; el.props.len()];
                let mut poly: Vec<u32> = Vec::with_capacity(8);
                for f in 0..el.count {
                    let first = mesh.indices.len();
                    for (k, p) in el.props.iter().enumerate() {
                        if let Some(ct) = p.list {
                            let n = body.read(ct).map_err(|e| format!("face {f}: {e}"))?;
                            if !(n >= 0.0) || n.fract() != 0.0 {
                                return Err(format!("face {f}: invalid list length {n}"));
                            }
                            poly.clear();
                            for _ in 0..n as usize {
                                let x = body.read(p.ty).map_err(|e| format!("face {f}: {e}"))?;
                                if k == fi {
                                    if !(x >= 0.0 && x <= u32::MAX as f64) || x.fract() != 0.0 {
                                        return Err(format!("face {f}: invalid vertex index {x}"));
                                    }
                                    poly.push(x as u32);
                                }
                            }
                            if k == fi {
                                if poly.len() < 3 {
                                    return Err(format!(
                                        "face {f} has {} vertices (at least 3 needed)",
                                        poly.len()
                                    ));
                                }
                                for j in 1..poly.len() - 1 {
                                    mesh.indices.push([poly[0], poly[j], poly[j + 1]]);
                                }
                            }
                        } else {
                            vals[k] = body.read(p.ty).map_err(|e| format!("face {f}: {e}"))?;
                        }
                    }
                    // Each triangle of the face's fan gets the face's attributes.
                    for _ in first..mesh.indices.len() {
                        for (g, a) in groups.iter().zip(&mut fa) {
                            a.data.extend(
                                g.props
                                    .iter()
                                    .map(|&k| attribute_value(vals[k], el.props[k].ty.attribute_max())),
                            );
                        }
                    }
                }
                attrs.list.extend(fa);
            }
            _ => {
                for i in 0..el.count {
                    for p in &el.props {
                        let n = match p.list {
                            Some(ct) => body.read(ct).map_err(|e| format!("{} {i}: {e}", el.name))? as usize,
                            None => 1,
                        };
                        for _ in 0..n {
                            body.read(p.ty).map_err(|e| format!("{} {i}: {e}", el.name))?;
                        }
                    }
                }
            }
        }
    }
    if n_vertices.is_none() {
        return Err("no vertex element".into());
    }
    let dummy = Path::new("");
    validate(dummy, &mesh).map_err(|e| match e {
        MeshError::Format { message, .. } => message,
        MeshError::Io { source, .. } => source.to_string(),
    })?;
    Ok((mesh, attrs))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_faces_point_outwards_and_match_normals() {
        let m = cube();
        assert_eq!(m.positions.len(), 24);
        assert_eq!(m.indices.len(), 12);
        let mut area = 0.0;
        for t in &m.indices {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let g = (b - a).cross(c - a);
            area += 0.5 * g.length();
            let n = m.normals[t[0] as usize];
            assert!(
                (g.normalize() - n).length() < 1e-6,
                "winding disagrees with normal {n}"
            );
            // Outwards: the face centre lies along the normal.
            assert!(((a + b + c) / 3.0).dot(n) > 0.0);
            assert!(t.iter().all(|&i| m.normals[i as usize] == n));
        }
        assert!((area - 24.0).abs() < 1e-5);
        assert!(
            m.uvs
                .iter()
                .all(|uv| (0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y))
        );
    }

    #[test]
    fn ply_binary_big_endian_quad() {
        let mut b = b"ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
        for p in [[0f32, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]] {
            for c in p {
                b.extend_from_slice(&c.to_be_bytes());
            }
        }
        b.push(4);
        for i in [0i32, 1, 2, 3] {
            b.extend_from_slice(&i.to_be_bytes());
        }
        let m = parse_ply(&b, false).unwrap();
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.positions[2], Vec3::new(1.0, 1.0, 0.0));
        // Truncated body.
        let err = parse_ply(&b[..b.len() - 2], false).unwrap_err();
        assert!(err.contains("face 0") && err.contains("end of file"), "{err}");
    }

    #[test]
    fn ply_absurd_counts_fail_without_allocating() {
        let b = b"ply\nformat ascii 1.0\nelement vertex 1000000000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
        let err = parse_ply(b, false).unwrap_err();
        assert!(err.contains("vertex 1") && err.contains("end of file"), "{err}");
        let b = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1 0 0 0 1 0\n2 0 1\n";
        let err = parse_ply(b, false).unwrap_err();
        assert!(err.contains("face 0 has 2 vertices"), "{err}");
    }
}
