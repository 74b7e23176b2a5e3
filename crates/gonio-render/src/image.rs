//! Linear-RGB images and image files: reading EXR (`exr`), PNG (`png`), JPEG (`zune-jpeg`), BMP
//! (`zune-bmp`), the integer ones sRGB-decoded, and Radiance HDR ([`rgbe`]); writing float EXR
//! and 8-bit sRGB PNG, always atomically.
//!
//! Formats are recognized by their magic bytes, not by the file name, so a mislabelled file still
//! reads and a file that is none of them gives a clear [`ImageError`] naming it.
//!
//! Every write goes through [`crate::output::write_atomically`] (a temporary file in the
//! destination's folder, then renamed over the destination): a reader never sees a half-written
//! image, and a crash leaves the old file in place.

pub mod codecs;
pub mod rgbe;

use std::io::Cursor;
use std::path::{Path, PathBuf};

/// The largest image the integer and RGBE decoders read, in pixels (2²⁸: 16384 × 16384, 3 GiB
/// as f32 RGB); checked before allocating for it.
pub const MAX_PIXELS: usize = 1 << 28;

/// A linear RGB image in row-major order (row 0 at the top), one `[r, g, b]` per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `width * height` pixels, row-major, top row first.
    pub data: Vec<[f32; 3]>,
}

/// How 8-bit/16-bit integer images (PNG, JPEG) are turned into floats. Float formats (EXR, HDR)
/// are always taken as linear.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Apply the inverse sRGB transfer curve (what colour images need; Mitsuba's default).
    Srgb,
    /// Use the stored values divided by the maximum integer value, unchanged (Mitsuba's `raw`,
    /// for data such as roughness maps).
    Raw,
}

/// Image file errors; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The bytes are not an image format we read.
    #[error("{}: not a recognized image (expected OpenEXR, PNG, JPEG, BMP or Radiance HDR)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The format was recognized but the content is broken or unsupported.
    #[error("{}: cannot decode {format} image: {message}", path.display())]
    Decode {
        /// The file.
        path: PathBuf,
        /// "OpenEXR", "PNG", ...
        format: &'static str,
        /// What the decoder said.
        message: String,
    },
    /// Encoding failed, or the output name has an extension we do not write.
    #[error("{}: cannot write image: {message}", path.display())]
    Encode {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl RgbImage {
    /// A black image.
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            data: vec![[0.0; 3]; width * height],
        }
    }

    /// An image from a function of the pixel coordinates `(x, y)`.
    pub fn from_fn(width: usize, height: usize, mut f: impl FnMut(usize, usize) -> [f32; 3]) -> Self {
        let mut data = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                data.push(f(x, y));
            }
        }
        Self { width, height, data }
    }

    /// The pixel at column `x`, row `y` (panics when out of range, like slice indexing).
    #[inline]
    pub fn get(&self, x: usize, y: usize) -> [f32; 3] {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside {}x{}",
            self.width,
            self.height
        );
        self.data[y * self.width + x]
    }

    /// Sets the pixel at column `x`, row `y`.
    #[inline]
    pub fn set(&mut self, x: usize, y: usize, rgb: [f32; 3]) {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside {}x{}",
            self.width,
            self.height
        );
        self.data[y * self.width + x] = rgb;
    }

    /// Reads an image file as linear RGB; PNG and JPEG are sRGB-decoded ([`Encoding::Srgb`]).
    pub fn read(path: impl AsRef<Path>) -> Result<Self, ImageError> {
        Self::read_with(path, Encoding::Srgb)
    }

    /// Reads an image file, choosing how integer formats are decoded.
    pub fn read_with(path: impl AsRef<Path>, encoding: Encoding) -> Result<Self, ImageError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| ImageError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::decode(&bytes, path, encoding)
    }

    /// Decodes an image held in memory; `path` only names it in errors.
    pub fn decode(bytes: &[u8], path: &Path, encoding: Encoding) -> Result<Self, ImageError> {
        if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
            return decode_exr(bytes, path);
        }
        type Decoder = fn(&[u8]) -> Result<codecs::Decoded, String>;
        let (decoder, name, integer): (Decoder, _, _) = if bytes.starts_with(b"\x89PNG") {
            (codecs::decode_png, "PNG", true)
        } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
            (codecs::decode_jpeg, "JPEG", true)
        } else if bytes.starts_with(b"#?") {
            // "#?" and the writing program's name: "#?RADIANCE", "#?RGBE" (Mitsuba, pbrt, stb).
            (rgbe::decode, "Radiance HDR", false)
        } else if bytes.starts_with(b"BM") {
            (codecs::decode_bmp, "BMP", true)
        } else {
            return Err(ImageError::UnknownFormat {
                path: path.to_owned(),
            });
        };
        let (width, height, mut data) = decoder(bytes).map_err(|message| ImageError::Decode {
            path: path.to_owned(),
            format: name,
            message,
        })?;
        if integer && encoding == Encoding::Srgb {
            data.iter_mut().for_each(|c| *c = c.map(srgb_to_linear));
        }
        Ok(Self { width, height, data })
    }

    /// Writes a float-32 RGB OpenEXR file (linear values, unclamped), atomically.
    pub fn write_exr(&self, path: impl AsRef<Path>) -> Result<(), ImageError> {
        let path = path.as_ref();
        let bytes = self.encode_exr().map_err(|message| ImageError::Encode {
            path: path.to_owned(),
            message,
        })?;
        write_atomically(path, &bytes)
    }

    /// Writes an 8-bit sRGB PNG (values clamped to [0, 1], sRGB transfer curve), atomically.
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), ImageError> {
        let path = path.as_ref();
        let bytes = self.encode_png().map_err(|message| ImageError::Encode {
            path: path.to_owned(),
            message,
        })?;
        write_atomically(path, &bytes)
    }

    /// Writes EXR or PNG according to the extension (`.exr`, `.png`, case-insensitive).
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), ImageError> {
        let path = path.as_ref();
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("exr") => self.write_exr(path),
            Some("png") => self.write_png(path),
            _ => Err(ImageError::Encode {
                path: path.to_owned(),
                message: "unknown extension (use .exr or .png)".into(),
            }),
        }
    }

    /// The image as 8-bit sRGB bytes (RGB, row-major), clamped.
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.data
            .iter()
            .flat_map(|p| p.map(|v| (linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8))
            .collect()
    }

    fn encode_exr(&self) -> Result<Vec<u8>, String> {
        use exr::prelude::*;
        if self.width == 0 || self.height == 0 {
            return Err("an EXR image cannot be empty".into());
        }
        let w = self.width;
        let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
            let p = self.data[y * w + x];
            (p[0], p[1], p[2])
        });
        let image = Image::from_channels((self.width, self.height), channels);
        let mut cursor = Cursor::new(Vec::new());
        image
            .write()
            .to_buffered(&mut cursor)
            .map_err(|e| e.to_string())?;
        Ok(cursor.into_inner())
    }

    fn encode_png(&self) -> Result<Vec<u8>, String> {
        codecs::encode_png_rgb8(&self.to_srgb8(), self.width, self.height)
    }
}

fn decode_exr(bytes: &[u8], path: &Path) -> Result<RgbImage, ImageError> {
    use exr::prelude::*;
    let err = |message: String| ImageError::Decode {
        path: path.to_owned(),
        format: "OpenEXR",
        message,
    };
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| err(e.to_string()))?;
    let layer = image.layer_data;
    let (width, height) = (layer.size.0, layer.size.1);
    let list = &layer.channel_data.list;
    // Channel names may carry a layer prefix ("diffuse.R"); match on the last component.
    let find = |name: &str| {
        list.iter().find(|c| {
            let full = c.name.to_string();
            full.rsplit('.')
                .next()
                .is_some_and(|last| last.eq_ignore_ascii_case(name))
        })
    };
    let planes: [&FlatSamples; 3] = match (find("R"), find("G"), find("B"), find("Y")) {
        (Some(r), Some(g), Some(b), _) => [&r.sample_data, &g.sample_data, &b.sample_data],
        (_, _, _, Some(y)) => [&y.sample_data, &y.sample_data, &y.sample_data],
        _ => {
            let names: Vec<String> = list.iter().map(|c| c.name.to_string()).collect();
            return Err(err(format!("no R, G, B (or Y) channels; found {names:?}")));
        }
    };
    let n = width * height;
    if planes.iter().any(|p| p.len() != n) {
        return Err(err(
            "a channel has the wrong number of samples (subsampled channels are not supported)".into(),
        ));
    }
    let data = (0..n)
        .map(|i| {
            [
                planes[0].value_by_flat_index(i).to_f32(),
                planes[1].value_by_flat_index(i).to_f32(),
                planes[2].value_by_flat_index(i).to_f32(),
            ]
        })
        .collect();
    Ok(RgbImage { width, height, data })
}

/// An image of named float channels (a film's layers: `R`, `G`, `B`, `albedo.R`, `S1.G`, ...),
/// row-major, top row first, the channels of a pixel contiguous.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Channel names, as written to EXR.
    pub names: Vec<String>,
    /// `width * height * names.len()` values.
    pub data: Vec<f32>,
}

impl ChannelImage {
    /// Reads every channel of the first layer of an OpenEXR file, under its full name
    /// (`S1.R`, ...); other formats and subsampled channels are errors naming the file.
    pub fn read(path: impl AsRef<Path>) -> Result<Self, ImageError> {
        use exr::prelude::*;
        let path = path.as_ref();
        let err = |message: String| ImageError::Decode {
            path: path.to_owned(),
            format: "OpenEXR",
            message,
        };
        let bytes = std::fs::read(path).map_err(|source| ImageError::Io {
            path: path.to_owned(),
            source,
        })?;
        if !bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
            return Err(err(
                "not an OpenEXR file (named channels are read from EXR only)".into()
            ));
        }
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .from_buffered(Cursor::new(bytes))
            .map_err(|e| err(e.to_string()))?;
        let layer = image.layer_data;
        let (width, height) = (layer.size.0, layer.size.1);
        let list = &layer.channel_data.list;
        let n = width * height;
        if list.iter().any(|c| c.sample_data.len() != n) {
            return Err(err(
                "a channel has the wrong number of samples (subsampled channels are not supported)".into(),
            ));
        }
        let names: Vec<String> = list.iter().map(|c| c.name.to_string()).collect();
        let k = names.len();
        let mut data = vec![0.0f32; n * k];
        for (j, c) in list.iter().enumerate() {
            for i in 0..n {
                data[i * k + j] = c.sample_data.value_by_flat_index(i).to_f32();
            }
        }
        Ok(Self {
            width,
            height,
            names,
            data,
        })
    }

    /// The values of channel `name`, row-major; `None` when the image has no such channel.
    pub fn channel(&self, name: &str) -> Option<Vec<f32>> {
        let k = self.names.len();
        let j = self.names.iter().position(|n| n == name)?;
        Some(
            (0..self.width * self.height)
                .map(|i| self.data[i * k + j])
                .collect(),
        )
    }

    /// The channels `R`, `G`, `B` as an RGB image (zero for a missing channel).
    pub fn rgb(&self) -> RgbImage {
        let n = self.names.len();
        let find = |c: &str| self.names.iter().position(|name| name == c);
        let idx = [find("R"), find("G"), find("B")];
        let data = (0..self.width * self.height)
            .map(|i| idx.map(|k| k.map_or(0.0, |k| self.data[i * n + k])))
            .collect();
        RgbImage {
            width: self.width,
            height: self.height,
            data,
        }
    }

    /// Writes a float-32 OpenEXR file with one channel per name (linear values), atomically.
    pub fn write_exr(&self, path: impl AsRef<Path>) -> Result<(), ImageError> {
        let path = path.as_ref();
        let bytes = self.encode_exr().map_err(|message| ImageError::Encode {
            path: path.to_owned(),
            message,
        })?;
        write_atomically(path, &bytes)
    }

    fn encode_exr(&self) -> Result<Vec<u8>, String> {
        crate::develop::encode_exr(self, crate::scene::ComponentFormat::Float32, &[])
    }

    /// The three channels `layer.R`, `layer.G`, `layer.B` (`R`, `G`, `B` for the empty layer
    /// name) as an RGB image, or `None` when one is missing.
    pub fn layer_rgb(&self, layer: &str) -> Option<RgbImage> {
        let n = self.names.len();
        let name = |c: &str| {
            if layer.is_empty() {
                c.to_string()
            } else {
                format!("{layer}.{c}")
            }
        };
        let find = |c: &str| self.names.iter().position(|x| *x == name(c));
        let idx = [find("R")?, find("G")?, find("B")?];
        let data = (0..self.width * self.height)
            .map(|i| idx.map(|k| self.data[i * n + k]))
            .collect();
        Some(RgbImage {
            width: self.width,
            height: self.height,
            data,
        })
    }
}

/// Writes 8-bit RGB bytes (display colours, e.g. of a colour map; no transfer curve applied) as a
/// PNG, atomically.
pub fn write_png_rgb8(
    path: impl AsRef<Path>,
    width: usize,
    height: usize,
    rgb8: &[u8],
) -> Result<(), ImageError> {
    let path = path.as_ref();
    let bytes = codecs::encode_png_rgb8(rgb8, width, height).map_err(|message| ImageError::Encode {
        path: path.to_owned(),
        message,
    })?;
    write_atomically(path, &bytes)
}

/// Writes `bytes` through the one atomic writer ([`crate::output::write_atomically`]).
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), ImageError> {
    crate::output::write_atomically(path, bytes).map_err(|e| ImageError::Io {
        path: e.path,
        source: e.source,
    })
}

/// The inverse sRGB transfer curve (IEC 61966-2-1). H1's `gonio_core::color` has the same curve;
/// this private copy keeps image I/O independent of it.
#[inline]
fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB transfer curve (IEC 61966-2-1).
#[inline]
fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}
