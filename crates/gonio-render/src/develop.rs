//! Developing a render into the image file its film asks for, as Mitsuba 3's `hdrfilm` does:
//! the `pixel_format` chooses the channels (`R G B`, `R G B A`, `Y`, `Y A`, `X Y Z`, `X Y Z A`),
//! the `component_format` an OpenEXR file's number type (half, float or unsigned integer), and the
//! `file_format` the format (OpenEXR, Radiance RGBE `.hdr`, portable float map `.pfm`). An EXR
//! file also records how it was made (`gonio` version, samples per pixel, seed, render time) as
//! text attributes of its header.
//!
//! The film accumulates linear sRGB; XYZ and luminance are its exact linear transforms
//! (IEC 61966-2-1 primaries, D65 white), so no information is lost on the way. Channels of other
//! layers (`albedo.R`, `S1.G`, ...) are kept after the main ones, unchanged.
//!
//! The PFM writer is ours: the format is a three-line text header and raw little-endian floats,
//! bottom row first, which no maintained image crate writes.

use crate::image::{ChannelImage, ImageError};
use crate::scene::{ComponentFormat, FileFormat, PixelFormat};
use glam::Vec3;
use gonio_core::color::xyz_from_linear_srgb;
use std::io::Cursor;
use std::path::Path;

/// Develops the film's channels (`R`, `G`, `B`, optionally `A`, then other layers) into the
/// channels of `format`.
pub fn develop(image: &ChannelImage, format: PixelFormat) -> ChannelImage {
    if format == PixelFormat::Bands {
        // A spectral film's channels are its bands, written as recorded.
        return image.clone();
    }
    let n = image.names.len();
    let find = |c: &str| image.names.iter().position(|name| name == c);
    let (r, g, b, a) = (find("R"), find("G"), find("B"), find("A"));
    let main: &[&str] = match format {
        PixelFormat::Rgb => &["R", "G", "B"],
        PixelFormat::Rgba => &["R", "G", "B", "A"],
        PixelFormat::Luminance => &["Y"],
        PixelFormat::LuminanceAlpha => &["Y", "A"],
        PixelFormat::Xyz => &["X", "Y", "Z"],
        PixelFormat::Xyza => &["X", "Y", "Z", "A"],
        PixelFormat::Bands => &[],
    };
    let others: Vec<usize> = (0..n)
        .filter(|&k| !["R", "G", "B", "A"].contains(&image.names[k].as_str()))
        .collect();
    let mut names: Vec<String> = main.iter().map(|s| s.to_string()).collect();
    names.extend(others.iter().map(|&k| image.names[k].clone()));
    let m = names.len();
    let pixels = image.width * image.height;
    let mut data = Vec::with_capacity(pixels * m);
    for i in 0..pixels {
        let px = &image.data[i * n..(i + 1) * n];
        let at = |k: Option<usize>| k.map_or(0.0, |k| px[k]);
        let rgb = Vec3::new(at(r), at(g), at(b));
        let xyz = xyz_from_linear_srgb(rgb);
        for c in main {
            data.push(match *c {
                "R" => rgb.x,
                "G" => rgb.y,
                "B" => rgb.z,
                "X" => xyz.x,
                "Y" => xyz.y,
                "Z" => xyz.z,
                // No alpha channel rendered: every ray counted (opaque).
                _ => a.map_or(1.0, |k| px[k]),
            });
        }
        data.extend(others.iter().map(|&k| px[k]));
    }
    ChannelImage {
        width: image.width,
        height: image.height,
        names,
        data,
    }
}

/// Writes a developed image in `file_format` (an EXR with `component` values and the header
/// `attributes`; RGBE takes `R`, `G`, `B`; PFM takes `Y` or `R`, `G`, `B`), atomically.
pub fn write_developed(
    image: &ChannelImage,
    path: &Path,
    file_format: FileFormat,
    component: ComponentFormat,
    attributes: &[(String, String)],
) -> Result<(), ImageError> {
    let encode_err = |message: String| ImageError::Encode {
        path: path.to_owned(),
        message,
    };
    let bytes = match file_format {
        FileFormat::OpenExr => encode_exr(image, component, attributes).map_err(encode_err)?,
        FileFormat::Rgbe => encode_rgbe(image).map_err(encode_err)?,
        FileFormat::Pfm => encode_pfm(image).map_err(encode_err)?,
    };
    crate::image::write_atomically(path, &bytes)
}

/// The planes `names` of `image`, or an error naming what is missing.
fn planes(image: &ChannelImage, names: &[&str]) -> Result<Vec<usize>, String> {
    names
        .iter()
        .map(|c| {
            image
                .names
                .iter()
                .position(|n| n == c)
                .ok_or_else(|| format!("the image has no {c} channel (its channels: {:?})", image.names))
        })
        .collect()
}

/// An OpenEXR file of `image`'s channels (one per name) with `component` values and the header
/// text `attributes` (also `ChannelImage::write_exr`'s encoder, float32 without attributes).
pub(crate) fn encode_exr(
    image: &ChannelImage,
    component: ComponentFormat,
    attributes: &[(String, String)],
) -> Result<Vec<u8>, String> {
    use exr::prelude::*;
    if image.width == 0 || image.height == 0 || image.names.is_empty() {
        return Err("an EXR image cannot be empty".into());
    }
    let n = image.names.len();
    let mut list = SmallVec::<[AnyChannel<FlatSamples>; 4]>::new();
    for (k, name) in image.names.iter().enumerate() {
        let name = Text::new_or_none(name.as_str()).ok_or_else(|| format!("bad channel name {name:?}"))?;
        let plane = image.data.iter().skip(k).step_by(n).copied();
        let samples = match component {
            ComponentFormat::Float16 => FlatSamples::F16(plane.map(f16::from_f32).collect()),
            ComponentFormat::Float32 => FlatSamples::F32(plane.collect()),
            ComponentFormat::Uint32 => FlatSamples::U32(
                plane
                    .map(|v| (v.clamp(0.0, 1.0) as f64 * u32::MAX as f64).round() as u32)
                    .collect(),
            ),
        };
        list.push(AnyChannel::new(name, samples));
    }
    let mut layer_attributes = LayerAttributes::default();
    for (key, value) in attributes {
        let (Some(k), Some(v)) = (Text::new_or_none(key.as_str()), Text::new_or_none(value.as_str())) else {
            return Err(format!("bad header attribute {key:?} = {value:?}"));
        };
        layer_attributes.other.insert(k, AttributeValue::Text(v));
    }
    let layer = Layer::new(
        (image.width, image.height),
        layer_attributes,
        exr::image::Encoding::FAST_LOSSLESS,
        AnyChannels::sort(list),
    );
    let mut cursor = Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut cursor)
        .map_err(|e| e.to_string())?;
    Ok(cursor.into_inner())
}

fn encode_rgbe(image: &ChannelImage) -> Result<Vec<u8>, String> {
    let idx = planes(image, &["R", "G", "B"])?;
    let n = image.names.len();
    let pixels: Vec<[f32; 3]> = (0..image.width * image.height)
        .map(|i| [0, 1, 2].map(|c| image.data[i * n + idx[c]]))
        .collect();
    Ok(crate::image::rgbe::encode(image.width, image.height, &pixels))
}

fn encode_pfm(image: &ChannelImage) -> Result<Vec<u8>, String> {
    // `PF` colour or `Pf` grey; a negative scale means little-endian; rows bottom to top.
    let (tag, idx) = match planes(image, &["R", "G", "B"]) {
        Ok(idx) => ("PF", idx),
        Err(_) => ("Pf", planes(image, &["Y"])?),
    };
    let n = image.names.len();
    let mut out = format!("{tag}\n{} {}\n-1.0\n", image.width, image.height).into_bytes();
    for y in (0..image.height).rev() {
        for x in 0..image.width {
            let i = y * image.width + x;
            for &k in &idx {
                out.extend_from_slice(&image.data[i * n + k].to_le_bytes());
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film() -> ChannelImage {
        // Two pixels: an orange one half covered, a grey one fully covered; one extra layer.
        ChannelImage {
            width: 2,
            height: 1,
            names: ["R", "G", "B", "A", "albedo.R"].map(String::from).to_vec(),
            data: vec![0.8, 0.4, 0.1, 0.5, 0.3, 0.2, 0.2, 0.2, 1.0, 0.7],
        }
    }

    #[test]
    fn luminance_and_xyz_are_the_srgb_transforms() {
        let f = film();
        let y = develop(&f, PixelFormat::LuminanceAlpha);
        assert_eq!(y.names, ["Y", "A", "albedo.R"]);
        let lum = 0.2126 * 0.8 + 0.7152 * 0.4 + 0.0722 * 0.1;
        assert!((y.data[0] - lum).abs() < 2e-4, "{}", y.data[0]);
        assert_eq!((y.data[1], y.data[2]), (0.5, 0.3));
        let xyz = develop(&f, PixelFormat::Xyz);
        assert_eq!(xyz.names, ["X", "Y", "Z", "albedo.R"]);
        // A grey pixel has D65's chromaticity: X/Y = 0.9505, Z/Y = 1.089.
        let g = &xyz.data[4..7];
        assert!(
            (g[0] / g[1] - 0.9505).abs() < 1e-3 && (g[2] / g[1] - 1.089).abs() < 1e-3,
            "{g:?}"
        );
        let rgb = develop(&f, PixelFormat::Rgb);
        assert_eq!(rgb.names, ["R", "G", "B", "albedo.R"]);
        assert_eq!(&rgb.data[..4], &[0.8, 0.4, 0.1, 0.3]);
    }

    #[test]
    fn a_film_without_alpha_develops_opaque() {
        let f = ChannelImage {
            width: 1,
            height: 1,
            names: ["R", "G", "B"].map(String::from).to_vec(),
            data: vec![1.0, 2.0, 3.0],
        };
        assert_eq!(develop(&f, PixelFormat::Rgba).data, [1.0, 2.0, 3.0, 1.0]);
    }

    #[test]
    fn pfm_is_bottom_row_first_little_endian() {
        let img = ChannelImage {
            width: 1,
            height: 2,
            names: vec!["Y".into()],
            data: vec![1.0, 2.0],
        };
        let bytes = encode_pfm(&img).unwrap();
        let header = b"Pf\n1 2\n-1.0\n";
        assert_eq!(&bytes[..header.len()], header);
        assert_eq!(
            &bytes[header.len()..],
            [2.0f32.to_le_bytes(), 1.0f32.to_le_bytes()].concat()
        );
    }
}
