//! Mitsuba's tensor file (`TensorFile`, `src/core/tensor.cpp`): named n-dimensional arrays in one
//! little-endian file, the container of the `measured_polarized` pBRDF tables (`.pbsdf`) and of
//! RGL's measured BSDFs (`.bsdf`).
//!
//! ```text
//! "tensor_file\0"            12 bytes
//! version                    u8 major (1), u8 minor (0)
//! field count                u32
//! per field:                 u16 name length, the name (UTF-8), u16 ndim, u8 dtype,
//!                            u64 byte offset of the data, ndim × u64 shape
//! the data                   each field's elements row-major at its offset
//! ```
//!
//! dtype is Mitsuba's `Struct::Type` code: 1 uint8, 2 int8, 3 uint16, 4 int16, 5 uint32,
//! 6 int32, 7 uint64, 8 int64, 9 float16, 10 float32, 11 float64. Written here because no crate
//! reads this format; about a hundred lines with every size and offset checked against the file,
//! so that a truncated or hostile file gives an error, never a panic or a huge allocation.

use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

/// An element type of a field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    /// `int8`.
    I8,
    /// `uint8`.
    U8,
    /// `int16`.
    I16,
    /// `uint16`.
    U16,
    /// `int32`.
    I32,
    /// `uint32`.
    U32,
    /// `int64`.
    I64,
    /// `uint64`.
    U64,
    /// `float16`.
    F16,
    /// `float32`.
    F32,
    /// `float64`.
    F64,
}

impl Dtype {
    /// The type of Mitsuba's code, `None` for an unknown one.
    pub fn from_code(code: u8) -> Option<Self> {
        use Dtype::*;
        Some(match code {
            1 => U8,
            2 => I8,
            3 => U16,
            4 => I16,
            5 => U32,
            6 => I32,
            7 => U64,
            8 => I64,
            9 => F16,
            10 => F32,
            11 => F64,
            _ => return None,
        })
    }

    /// Bytes per element.
    pub fn size(self) -> usize {
        use Dtype::*;
        match self {
            I8 | U8 => 1,
            I16 | U16 | F16 => 2,
            I32 | U32 | F32 => 4,
            I64 | U64 | F64 => 8,
        }
    }

    /// The name Mitsuba prints.
    pub fn name(self) -> &'static str {
        use Dtype::*;
        match self {
            I8 => "int8",
            U8 => "uint8",
            I16 => "int16",
            U16 => "uint16",
            I32 => "int32",
            U32 => "uint32",
            I64 => "int64",
            U64 => "uint64",
            F16 => "float16",
            F32 => "float32",
            F64 => "float64",
        }
    }
}

/// One named array: its type, shape and place in the file's bytes (shared by all fields, so
/// fields that alias the same bytes cost nothing: a file of many fields over one range is not
/// a way to make the reader allocate more than the file).
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The element type.
    pub dtype: Dtype,
    /// The extent of each dimension, slowest first.
    pub shape: Vec<usize>,
    file: Arc<[u8]>,
    range: Range<usize>,
}

impl Field {
    /// The number of elements.
    pub fn len(&self) -> usize {
        self.range.len() / self.dtype.size()
    }

    /// True when the field holds no element.
    pub fn is_empty(&self) -> bool {
        self.range.is_empty()
    }

    /// The raw little-endian bytes of the elements.
    pub fn as_bytes(&self) -> &[u8] {
        &self.file[self.range.clone()]
    }

    /// The elements as `f32` (floats rounded, integers converted), in file order.
    pub fn to_f32(&self) -> Vec<f32> {
        let n = self.dtype.size();
        self.as_bytes()
            .chunks_exact(n)
            .map(|b| match self.dtype {
                Dtype::I8 => b[0] as i8 as f32,
                Dtype::U8 => b[0] as f32,
                Dtype::I16 => i16::from_le_bytes([b[0], b[1]]) as f32,
                Dtype::U16 => u16::from_le_bytes([b[0], b[1]]) as f32,
                Dtype::F16 => half::f16::from_le_bytes([b[0], b[1]]).to_f32(),
                Dtype::I32 => i32::from_le_bytes(b.try_into().unwrap()) as f32,
                Dtype::U32 => u32::from_le_bytes(b.try_into().unwrap()) as f32,
                Dtype::F32 => f32::from_le_bytes(b.try_into().unwrap()),
                Dtype::I64 => i64::from_le_bytes(b.try_into().unwrap()) as f32,
                Dtype::U64 => u64::from_le_bytes(b.try_into().unwrap()) as f32,
                Dtype::F64 => f64::from_le_bytes(b.try_into().unwrap()) as f32,
            })
            .collect()
    }
}

/// A file's fields by name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TensorFile {
    fields: HashMap<String, Field>,
}

/// What is wrong with a tensor file (the caller adds the file's name).
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{0}")]
pub struct TensorError(pub String);

/// A little-endian cursor that reports where the file ended.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], TensorError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(TensorError(format!(
                "truncated: the file ends at byte {} in the {what}",
                self.bytes.len()
            )));
        };
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u8(&mut self, what: &str) -> Result<u8, TensorError> {
        Ok(self.take(1, what)?[0])
    }
    fn u16(&mut self, what: &str) -> Result<u16, TensorError> {
        Ok(u16::from_le_bytes(self.take(2, what)?.try_into().unwrap()))
    }
    fn u32(&mut self, what: &str) -> Result<u32, TensorError> {
        Ok(u32::from_le_bytes(self.take(4, what)?.try_into().unwrap()))
    }
    fn u64(&mut self, what: &str) -> Result<u64, TensorError> {
        Ok(u64::from_le_bytes(self.take(8, what)?.try_into().unwrap()))
    }
}

impl TensorFile {
    /// Reads and parses `path`.
    pub fn read(path: &Path) -> Result<Self, TensorError> {
        let bytes = std::fs::read(path).map_err(|e| TensorError(e.to_string()))?;
        Self::parse(&bytes)
    }

    /// Parses a whole file's bytes.
    pub fn parse(bytes: &[u8]) -> Result<Self, TensorError> {
        let file: Arc<[u8]> = Arc::from(bytes);
        let mut c = Cursor { bytes, at: 0 };
        if c.take(12, "header").ok() != Some(b"tensor_file\0".as_slice()) {
            return Err(TensorError(
                "not a tensor file (it does not start with \"tensor_file\")".into(),
            ));
        }
        let (major, minor) = (c.u8("version")?, c.u8("version")?);
        if (major, minor) != (1, 0) {
            return Err(TensorError(format!(
                "tensor file version {major}.{minor}, only 1.0 is known"
            )));
        }
        let count = c.u32("field count")?;
        let mut fields = HashMap::new();
        for i in 0..count {
            let what = format!("header of field {i}");
            let name_len = c.u16(&what)? as usize;
            let name = std::str::from_utf8(c.take(name_len, &what)?)
                .map_err(|_| TensorError(format!("field {i}: its name is not UTF-8")))?
                .to_string();
            let ndim = c.u16(&what)? as usize;
            let code = c.u8(&what)?;
            let offset = c.u64(&what)?;
            let mut shape = Vec::with_capacity(ndim.min(64));
            for _ in 0..ndim {
                shape.push(c.u64(&what)?);
            }
            let dtype = Dtype::from_code(code)
                .ok_or_else(|| TensorError(format!("field \"{name}\": unknown element type code {code}")))?;
            let size = shape
                .iter()
                .try_fold(dtype.size() as u64, |a, &n| a.checked_mul(n))
                .filter(|&s| offset.checked_add(s).is_some_and(|end| end <= bytes.len() as u64));
            let Some(size) = size else {
                return Err(TensorError(format!(
                    "field \"{name}\": {shape:?} {} values at byte {offset} do not fit in the file ({} bytes)",
                    dtype.name(),
                    bytes.len()
                )));
            };
            let field = Field {
                dtype,
                shape: shape.iter().map(|&n| n as usize).collect(),
                file: file.clone(),
                range: offset as usize..(offset + size) as usize,
            };
            if fields.insert(name.clone(), field).is_some() {
                return Err(TensorError(format!("field \"{name}\" appears twice")));
            }
        }
        Ok(Self { fields })
    }

    /// The field called `name`.
    pub fn field(&self, name: &str) -> Option<&Field> {
        self.fields.get(name)
    }

    /// The field called `name`, or an error that lists the file's fields.
    pub fn require(&self, name: &str) -> Result<&Field, String> {
        self.field(name)
            .ok_or_else(|| format!("no field \"{name}\" (this file has {})", self.names().join(", ")))
    }

    /// The fields' names, sorted.
    pub fn names(&self) -> Vec<&str> {
        let mut v: Vec<&str> = self.fields.keys().map(String::as_str).collect();
        v.sort_unstable();
        v
    }
}

/// Writes `fields` (name, dtype, shape, little-endian bytes) as a tensor file's bytes, each
/// field's data 8-byte aligned: the inverse of [`TensorFile::parse`], for tests and tools.
pub fn write_tensor_file(fields: &[(&str, Dtype, &[usize], &[u8])]) -> Vec<u8> {
    let header_len: usize = 12
        + 2
        + 4
        + fields
            .iter()
            .map(|(name, _, shape, _)| 2 + name.len() + 2 + 1 + 8 + 8 * shape.len())
            .sum::<usize>();
    let mut offsets = Vec::with_capacity(fields.len());
    let mut at = header_len.next_multiple_of(8);
    for (_, _, _, data) in fields {
        offsets.push(at);
        at = (at + data.len()).next_multiple_of(8);
    }
    let mut out = Vec::with_capacity(at);
    out.extend_from_slice(b"tensor_file\0");
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(fields.len() as u32).to_le_bytes());
    for ((name, dtype, shape, _), offset) in fields.iter().zip(&offsets) {
        out.extend_from_slice(&(name.len() as u16).to_le_bytes());
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(&(shape.len() as u16).to_le_bytes());
        out.push(code_of(*dtype));
        out.extend_from_slice(&(*offset as u64).to_le_bytes());
        for &n in shape.iter() {
            out.extend_from_slice(&(n as u64).to_le_bytes());
        }
    }
    for ((_, _, _, data), &offset) in fields.iter().zip(&offsets) {
        out.resize(offset, 0);
        out.extend_from_slice(data);
    }
    out.resize(at, 0);
    out
}

fn code_of(d: Dtype) -> u8 {
    (1..=11).find(|&c| Dtype::from_code(c) == Some(d)).unwrap()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Vec<u8> {
        let a: Vec<u8> = [1.5f32, -2.0, 3.25]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let w: Vec<u8> = [450u16, 550].iter().flat_map(|x| x.to_le_bytes()).collect();
        write_tensor_file(&[("a", Dtype::F32, &[1, 3], &a), ("wvls", Dtype::U16, &[2], &w)])
    }

    #[test]
    fn a_written_file_reads_back() {
        let t = TensorFile::parse(&sample()).unwrap();
        assert_eq!(t.names(), ["a", "wvls"]);
        let a = t.field("a").unwrap();
        assert_eq!(
            (a.dtype, a.shape.as_slice(), a.to_f32()),
            (Dtype::F32, [1, 3].as_slice(), vec![1.5, -2.0, 3.25])
        );
        assert_eq!(t.field("wvls").unwrap().to_f32(), vec![450.0, 550.0]);
    }

    #[test]
    fn every_truncation_is_an_error_not_a_panic() {
        let bytes = sample();
        for n in 0..bytes.len() - 4 {
            // The last field ends 4 bytes before the padded end.
            assert!(TensorFile::parse(&bytes[..n]).is_err(), "{n} bytes parsed");
        }
    }

    #[test]
    fn fields_aliasing_one_range_share_its_bytes() {
        // 2000 fields over the same 4096 bytes: 8 MB if each were copied, one file's worth here.
        let data = vec![7u8; 4096];
        let names: Vec<String> = (0..2000).map(|i| format!("f{i}")).collect();
        let fields: Vec<(&str, Dtype, &[usize], &[u8])> = names
            .iter()
            .map(|n| (n.as_str(), Dtype::U8, [4096usize].as_slice(), &data[..0]))
            .collect();
        let mut bytes = write_tensor_file(&fields);
        // Point every field at the same range at the end of the file.
        let at = bytes.len();
        bytes.extend_from_slice(&data);
        let mut c = 12 + 2 + 4;
        for n in &names {
            c += 2 + n.len() + 2 + 1;
            bytes[c..c + 8].copy_from_slice(&(at as u64).to_le_bytes());
            c += 8 + 8;
        }
        let t = TensorFile::parse(&bytes).unwrap();
        let (a, b) = (t.field("f0").unwrap(), t.field("f1999").unwrap());
        assert_eq!((a.len(), b.as_bytes()), (4096, data.as_slice()));
        assert!(std::ptr::eq(a.as_bytes(), b.as_bytes()));
    }

    #[test]
    fn hostile_shapes_and_types_are_refused() {
        let mut bytes = sample();
        // The first field's shape: 1 × 3 → 2⁶⁴⁻¹ × 3 (the product overflows).
        let shape_at = 12 + 2 + 4 + 2 + 1 + 2 + 1 + 8;
        bytes[shape_at..shape_at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        let e = TensorFile::parse(&bytes).unwrap_err();
        assert!(e.0.contains("do not fit"), "{e}");
        let mut bytes = sample();
        bytes[12 + 2 + 4 + 2 + 1 + 2] = 42;
        assert!(
            TensorFile::parse(&bytes)
                .unwrap_err()
                .0
                .contains("unknown element type code 42")
        );
        let mut bytes = sample();
        bytes[0] = b'x';
        assert!(
            TensorFile::parse(&bytes)
                .unwrap_err()
                .0
                .contains("not a tensor file")
        );
        let mut bytes = sample();
        bytes[13] = 1;
        assert!(TensorFile::parse(&bytes).unwrap_err().0.contains("version 1.1"));
        let a = 1.0f32.to_le_bytes();
        let twice = write_tensor_file(&[("a", Dtype::F32, &[1], &a), ("a", Dtype::F32, &[1], &a)]);
        assert!(
            TensorFile::parse(&twice)
                .unwrap_err()
                .0
                .contains("\"a\" appears twice")
        );
    }
}
