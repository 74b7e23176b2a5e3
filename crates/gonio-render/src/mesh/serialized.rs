//! Mitsuba's `.serialized` mesh files (Mitsuba 3 `src/shapes/serialized.cpp`, whose plugin
//! documentation describes the format).
//!
//! A file is one or more meshes, each a little-endian header `u16 0x041C` (format) and `u16`
//! version (3 or 4) followed by a zlib stream holding:
//!
//! | field | type |
//! |---|---|
//! | flags | `u32`: `0x1` vertex normals, `0x2` texture coordinates, `0x8` vertex colours, `0x10` face normals, `0x1000` single, `0x2000` double precision |
//! | name | NUL-terminated UTF-8 (version 4 only) |
//! | vertex count, triangle count | `u64`, `u64` |
//! | positions, normals, uvs, colours | `f32` or `f64` arrays, the optional ones as the flags say |
//! | triangles | `u32` index triples (`u64` when there are more than 2³² vertices) |
//!
//! The file ends with the byte offset of every mesh (`u64` in version 4, `u32` in version 3)
//! and the mesh count (`u32`); `shape_index` picks a mesh through that table.
//!
//! As in Mitsuba 3.9.1: vertex colours are skipped, the file's face-normals flag is ignored (the
//! plugin's `face_normals` decides), and normals in the file are dropped when `face_normals` is
//! set. Every size is checked before anything is allocated: counts that the compressed data
//! cannot hold (deflate expands at most 1032:1) are errors, and data is read only as far as the
//! stream really goes, so a hostile or truncated file fails with a message naming the file.

use super::{MeshError, format_err, validate};
use crate::scene::TriangleMesh;
use glam::{Vec2, Vec3};
use std::io::Read;
use std::path::Path;

/// The format identifier that opens every mesh.
pub const SERIALIZED_MAGIC: u16 = 0x041C;

const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const DOUBLE_PRECISION: u32 = 0x2000;

/// The largest expansion factor of DEFLATE (a 258-byte match per ≈ 2 bits): no valid stream
/// decompresses to more than this many bytes per compressed byte.
const MAX_DEFLATE_RATIO: u64 = 1032;

/// Reads mesh number `shape_index` of the `.serialized` file at `path`. Without normals in the
/// file the mesh has none (the caller computes them unless `face_normals`).
pub fn load_serialized(path: &Path, shape_index: u32, face_normals: bool) -> Result<TriangleMesh, MeshError> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_owned(),
        source,
    })?;
    let mesh = parse_serialized(&bytes, shape_index, face_normals).map_err(|m| format_err(path, m))?;
    validate(path, &mesh)?;
    Ok(mesh)
}

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(
        b.get(at..at.checked_add(2)?)?.try_into().ok()?,
    ))
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(
        b.get(at..at.checked_add(4)?)?.try_into().ok()?,
    ))
}

fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(
        b.get(at..at.checked_add(8)?)?.try_into().ok()?,
    ))
}

/// The header at `at`: checks the magic and returns the version.
fn header(bytes: &[u8], at: usize) -> Result<u16, String> {
    let (Some(format), Some(version)) = (u16_at(bytes, at), u16_at(bytes, at + 2)) else {
        return Err(format!(
            "truncated: no mesh header at byte {at} (the file has {} bytes)",
            bytes.len()
        ));
    };
    if format != SERIALIZED_MAGIC {
        return Err(format!(
            "not a Mitsuba serialized mesh: format identifier 0x{format:04X} at byte {at} (expected 0x{SERIALIZED_MAGIC:04X})"
        ));
    }
    if version != 3 && version != 4 {
        return Err(format!(
            "unsupported serialized format version {version} (3 and 4 are)"
        ));
    }
    Ok(version)
}

/// The byte offset of mesh `index`, from the table at the end of the file.
fn mesh_offset(bytes: &[u8], version: u16, index: u32) -> Result<usize, String> {
    let n = bytes.len();
    let count = n
        .checked_sub(4)
        .and_then(|at| u32_at(bytes, at))
        .ok_or("truncated: no mesh table")?;
    if index >= count {
        return Err(format!(
            "shape_index {index} is out of range: the file holds {count} mesh{}",
            if count == 1 { "" } else { "es" }
        ));
    }
    let entry = if version == 4 { 8 } else { 4 };
    let table = (count as usize)
        .checked_mul(entry)
        .and_then(|t| n.checked_sub(4 + t))
        .ok_or_else(|| format!("truncated: a table of {count} mesh offsets does not fit in {n} bytes"))?;
    let at = table + index as usize * entry;
    let offset = if version == 4 {
        u64_at(bytes, at).unwrap_or(u64::MAX)
    } else {
        u64::from(u32_at(bytes, at).unwrap_or(u32::MAX))
    };
    if offset >= table as u64 {
        return Err(format!(
            "mesh {index} starts at byte {offset}, beyond the mesh data ({table} bytes)"
        ));
    }
    Ok(offset as usize)
}

/// A zlib stream read with errors that say what was being read.
struct Stream<'a> {
    z: flate2::bufread::ZlibDecoder<&'a [u8]>,
}

impl Stream<'_> {
    fn exact<const N: usize>(&mut self, what: &str) -> Result<[u8; N], String> {
        let mut b = [0u8; N];
        self.z.read_exact(&mut b).map_err(|e| stream_error(what, &e))?;
        Ok(b)
    }

    /// `len` bytes, read as far as the stream goes (never allocating for more than it holds).
    fn bytes(&mut self, len: u64, what: &str) -> Result<Vec<u8>, String> {
        let mut out = Vec::new();
        (&mut self.z)
            .take(len)
            .read_to_end(&mut out)
            .map_err(|e| stream_error(what, &e))?;
        if (out.len() as u64) < len {
            return Err(format!(
                "truncated: the compressed stream ends after {} of the {len} bytes of {what}",
                out.len()
            ));
        }
        Ok(out)
    }
}

fn stream_error(what: &str, e: &std::io::Error) -> String {
    if e.kind() == std::io::ErrorKind::UnexpectedEof {
        format!("truncated: the compressed stream ends inside {what}")
    } else {
        format!("corrupt compressed stream while reading {what}: {e}")
    }
}

/// Parses mesh `shape_index` of a file already in memory.
pub(crate) fn parse_serialized(
    bytes: &[u8],
    shape_index: u32,
    face_normals: bool,
) -> Result<TriangleMesh, String> {
    let version = header(bytes, 0)?;
    let start = if shape_index == 0 {
        0
    } else {
        let at = mesh_offset(bytes, version, shape_index)?;
        let v = header(bytes, at)?;
        if v != version {
            return Err(format!("mesh {shape_index} has version {v}, the file {version}"));
        }
        at
    };
    let compressed = &bytes[start + 4..];
    let mut s = Stream {
        z: flate2::bufread::ZlibDecoder::new(compressed),
    };
    let flags = u32::from_le_bytes(s.exact("the flags")?);
    if version == 4 {
        // The mesh's name, NUL-terminated; not used.
        let mut len = 0usize;
        while s.exact::<1>("the mesh name")?[0] != 0 {
            len += 1;
            if len > compressed.len().saturating_mul(MAX_DEFLATE_RATIO as usize) {
                return Err("corrupt: the mesh name does not end".into());
            }
        }
    }
    let vertices = u64::from_le_bytes(s.exact("the vertex count")?);
    let triangles = u64::from_le_bytes(s.exact("the triangle count")?);
    let scalar = if flags & DOUBLE_PRECISION != 0 { 8 } else { 4 };
    // Per-vertex scalars in the file: position, then the optional attributes.
    let mut per_vertex = 3u64;
    for (flag, n) in [(HAS_NORMALS, 3), (HAS_TEXCOORDS, 2), (HAS_COLORS, 3)] {
        if flags & flag != 0 {
            per_vertex += n;
        }
    }
    if vertices > u64::from(u32::MAX) {
        return Err(format!(
            "vertex count {vertices} exceeds 2³² − 1, the most a mesh can index"
        ));
    }
    let too_big = || {
        format!(
            "vertex count {vertices} and triangle count {triangles} need more data than {} compressed bytes can hold",
            compressed.len()
        )
    };
    let data = vertices
        .checked_mul(per_vertex * scalar)
        .and_then(|v| triangles.checked_mul(12).and_then(|t| t.checked_add(v)))
        .ok_or_else(too_big)?;
    if data > (compressed.len() as u64).saturating_mul(MAX_DEFLATE_RATIO) {
        return Err(too_big());
    }
    let mut read_floats = |dim: u64, what: &str| -> Result<Vec<f32>, String> {
        let raw = s.bytes(vertices * dim * scalar, what)?;
        Ok(if scalar == 8 {
            raw.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()) as f32)
                .collect()
        } else {
            raw.chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                .collect()
        })
    };
    let positions: Vec<Vec3> = read_floats(3, "the vertex positions")?
        .chunks_exact(3)
        .map(Vec3::from_slice)
        .collect();
    let mut normals = Vec::new();
    if flags & HAS_NORMALS != 0 {
        let v = read_floats(3, "the vertex normals")?;
        if !face_normals {
            normals = v.chunks_exact(3).map(Vec3::from_slice).collect();
        }
    }
    let mut uvs = Vec::new();
    if flags & HAS_TEXCOORDS != 0 {
        uvs = read_floats(2, "the texture coordinates")?
            .chunks_exact(2)
            .map(Vec2::from_slice)
            .collect();
    }
    if flags & HAS_COLORS != 0 {
        read_floats(3, "the vertex colours")?;
    }
    let raw = s.bytes(triangles * 12, "the triangles")?;
    let indices: Vec<[u32; 3]> = raw
        .chunks_exact(12)
        .map(|c| {
            let i = |k: usize| u32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap());
            [i(0), i(1), i(2)]
        })
        .collect();
    // Texture coordinates stay as stored (Mitsuba flips none); normals are transformed and
    // normalized with the world mesh.
    Ok(TriangleMesh {
        positions,
        normals,
        uvs,
        indices,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::Compression;
    use flate2::write::ZlibEncoder;
    use std::io::Write;

    /// One mesh of a test file.
    struct Mesh {
        positions: Vec<[f64; 3]>,
        normals: Option<Vec<[f64; 3]>>,
        uvs: Option<Vec<[f64; 2]>>,
        colors: Option<Vec<[f64; 3]>>,
        triangles: Vec<[u32; 3]>,
    }

    fn quad() -> Mesh {
        Mesh {
            positions: vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.5]],
            normals: Some(vec![[0., 0., 1.]; 4]),
            uvs: Some(vec![[0., 0.], [1., 0.], [1., 1.], [0., 1.]]),
            colors: Some(vec![[1., 0., 0.]; 4]),
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    fn triangle() -> Mesh {
        Mesh {
            positions: vec![[0., 0., 1.], [2., 0., 1.], [0., 3., 1.]],
            normals: None,
            uvs: None,
            colors: None,
            triangles: vec![[0, 1, 2]],
        }
    }

    /// The uncompressed payload of `m` (flags, name in version 4, counts, arrays).
    fn payload(m: &Mesh, version: u16, double: bool) -> Vec<u8> {
        let mut flags = if double { DOUBLE_PRECISION } else { 0x1000 };
        flags |= if m.normals.is_some() { HAS_NORMALS } else { 0 };
        flags |= if m.uvs.is_some() { HAS_TEXCOORDS } else { 0 };
        flags |= if m.colors.is_some() { HAS_COLORS } else { 0 };
        let mut b = flags.to_le_bytes().to_vec();
        if version == 4 {
            b.extend_from_slice(b"test mesh\0");
        }
        b.extend_from_slice(&(m.positions.len() as u64).to_le_bytes());
        b.extend_from_slice(&(m.triangles.len() as u64).to_le_bytes());
        let mut put = |v: f64| {
            if double {
                b.extend_from_slice(&v.to_le_bytes());
            } else {
                b.extend_from_slice(&(v as f32).to_le_bytes());
            }
        };
        m.positions.iter().flatten().for_each(|&v| put(v));
        m.normals.iter().flatten().flatten().for_each(|&v| put(v));
        m.uvs.iter().flatten().flatten().for_each(|&v| put(v));
        m.colors.iter().flatten().flatten().for_each(|&v| put(v));
        for t in &m.triangles {
            for i in t {
                b.extend_from_slice(&i.to_le_bytes());
            }
        }
        b
    }

    /// A file of `meshes` in `version`, with the offset table at the end.
    fn file(meshes: &[Mesh], version: u16, double: bool) -> Vec<u8> {
        let mut out = Vec::new();
        let mut offsets = Vec::new();
        for m in meshes {
            offsets.push(out.len() as u64);
            out.extend_from_slice(&SERIALIZED_MAGIC.to_le_bytes());
            out.extend_from_slice(&version.to_le_bytes());
            let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
            z.write_all(&payload(m, version, double)).unwrap();
            out.extend(z.finish().unwrap());
        }
        for o in offsets {
            if version == 4 {
                out.extend_from_slice(&o.to_le_bytes());
            } else {
                out.extend_from_slice(&(o as u32).to_le_bytes());
            }
        }
        out.extend_from_slice(&(meshes.len() as u32).to_le_bytes());
        out
    }

    fn same(m: &TriangleMesh, e: &Mesh) {
        let v3 = |a: &[f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        assert_eq!(m.positions, e.positions.iter().map(v3).collect::<Vec<_>>());
        assert_eq!(m.indices, e.triangles);
        let normals: Vec<Vec3> = e.normals.iter().flatten().map(v3).collect();
        assert_eq!(m.normals, normals);
        let uvs: Vec<Vec2> = e
            .uvs
            .iter()
            .flatten()
            .map(|a| Vec2::new(a[0] as f32, a[1] as f32))
            .collect();
        assert_eq!(m.uvs, uvs, "texture coordinates are kept as stored");
    }

    #[test]
    fn versions_precisions_and_shape_index_round_trip() {
        for version in [3, 4] {
            for double in [false, true] {
                let f = file(&[quad(), triangle(), quad()], version, double);
                same(&parse_serialized(&f, 0, false).unwrap(), &quad());
                same(&parse_serialized(&f, 1, false).unwrap(), &triangle());
                same(&parse_serialized(&f, 2, false).unwrap(), &quad());
            }
        }
    }

    #[test]
    fn face_normals_drop_the_files_normals() {
        let f = file(&[quad()], 4, false);
        let m = parse_serialized(&f, 0, true).unwrap();
        assert!(m.normals.is_empty() && m.uvs.len() == 4 && m.indices.len() == 2);
    }

    #[test]
    fn bad_headers_and_indices_are_errors_naming_the_value() {
        let mut f = file(&[quad()], 4, false);
        f[0] = 0x1D;
        let e = parse_serialized(&f, 0, false).unwrap_err();
        assert!(e.contains("0x041D") && e.contains("format identifier"), "{e}");
        let mut f = file(&[quad()], 4, false);
        f[2] = 5;
        let e = parse_serialized(&f, 0, false).unwrap_err();
        assert!(e.contains("version 5"), "{e}");
        let f = file(&[quad(), triangle()], 3, false);
        let e = parse_serialized(&f, 2, false).unwrap_err();
        assert!(e.contains("shape_index 2") && e.contains("2 meshes"), "{e}");
        let e = parse_serialized(&f, u32::MAX, false).unwrap_err();
        assert!(e.contains(&format!("shape_index {}", u32::MAX)), "{e}");
        // An offset table pointing past the data.
        let mut g = file(&[quad(), triangle()], 4, false);
        let n = g.len();
        g[n - 12..n - 4].copy_from_slice(&u64::MAX.to_le_bytes());
        let e = parse_serialized(&g, 1, false).unwrap_err();
        assert!(e.contains("mesh 1 starts at byte 18446744073709551615"), "{e}");
        assert!(
            parse_serialized(&[0x1C], 0, false)
                .unwrap_err()
                .contains("truncated")
        );
    }

    #[test]
    fn every_truncation_is_an_error_not_a_panic() {
        for version in [3, 4] {
            let f = file(&[quad(), triangle()], version, true);
            for len in 0..f.len() {
                for index in [0, 1] {
                    // A cut inside the table can still leave mesh 0 readable; never a panic.
                    if let Ok(m) = parse_serialized(&f[..len], index, false) {
                        assert_eq!(index, 0, "len {len}");
                        same(&m, &quad());
                    }
                }
            }
        }
    }

    #[test]
    fn hostile_counts_fail_before_allocating() {
        for (vertices, triangles) in [(u64::MAX, 1), (1 << 31, 1), (3, u64::MAX / 8), (3, 1 << 40)] {
            let mut p = 0x1000u32.to_le_bytes().to_vec();
            p.extend_from_slice(&vertices.to_le_bytes());
            p.extend_from_slice(&triangles.to_le_bytes());
            p.extend_from_slice(&[0u8; 64]);
            let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
            z.write_all(&p).unwrap();
            let mut f = SERIALIZED_MAGIC.to_le_bytes().to_vec();
            f.extend_from_slice(&3u16.to_le_bytes());
            f.extend(z.finish().unwrap());
            let e = parse_serialized(&f, 0, false).unwrap_err();
            assert!(e.contains(&vertices.to_string()), "{e}");
        }
    }

    #[test]
    fn out_of_range_vertex_indices_are_rejected_with_the_file() {
        let mut m = triangle();
        m.triangles = vec![[0, 1, 7]];
        let dir = std::env::temp_dir().join(format!("gonio-serialized-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.serialized");
        std::fs::write(&path, file(&[m], 4, false)).unwrap();
        let e = load_serialized(&path, 0, false).unwrap_err().to_string();
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(e.contains("bad.serialized") && e.contains("[0, 1, 7]"), "{e}");
    }
}
