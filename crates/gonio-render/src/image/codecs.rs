//! The integer image formats through their crates: PNG (`png`), JPEG (`zune-jpeg`), BMP
//! (`zune-bmp`), each decoded to RGB in [0, 1] (stored value over the largest integer, grey
//! replicated, alpha dropped: Mitsuba's reading of an RGB texture), and PNG written.
//!
//! The sRGB curve is the caller's ([`super::Encoding`]). Every decoder refuses an image above
//! [`MAX_PIXELS`] before allocating for it.

use super::MAX_PIXELS;
use std::io::Cursor;
use zune_core::bytestream::ZCursor;
use zune_core::colorspace::ColorSpace;
use zune_core::options::DecoderOptions;

/// An image as (width, height, linear-or-encoded RGB pixels, rows top to bottom).
pub type Decoded = (usize, usize, Vec<[f32; 3]>);

/// Decodes a PNG of any colour type and depth (palettes and depths below 8 bits expanded,
/// 16-bit samples over 65535).
pub fn decode_png(bytes: &[u8]) -> Result<Decoded, String> {
    let limits = png::Limits { bytes: 1 << 31 };
    let mut decoder = png::Decoder::new_with_limits(Cursor::new(bytes), limits);
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(|e| e.to_string())?;
    let (width, height) = {
        let info = reader.info();
        (info.width as usize, info.height as usize)
    };
    check_size(width, height)?;
    let size = reader.output_buffer_size().ok_or("the image is too large")?;
    let mut buf = vec![0u8; size];
    let frame = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    let channels = frame.color_type.samples();
    let line = frame.line_size;
    let sample: fn(&[u8], usize) -> f32 = match frame.bit_depth {
        png::BitDepth::Eight => |b, i| f32::from(b[i]) / 255.0,
        png::BitDepth::Sixteen => |b, i| f32::from(u16::from_be_bytes([b[2 * i], b[2 * i + 1]])) / 65535.0,
        depth => return Err(format!("bit depth {depth:?} after expansion")),
    };
    let mut out = Vec::with_capacity(width * height);
    for row in buf.chunks_exact(line).take(height) {
        out.extend((0..width).map(|x| pixel(channels, |c| sample(row, x * channels + c))));
    }
    Ok((width, height, out))
}

/// Decodes a baseline or progressive JPEG (grey, YCbCr or CMYK) to 8-bit RGB.
pub fn decode_jpeg(bytes: &[u8]) -> Result<Decoded, String> {
    let options = options().jpeg_set_out_colorspace(ColorSpace::RGB);
    let mut decoder = zune_jpeg::JpegDecoder::new_with_options(ZCursor::new(bytes), options);
    decoder.decode_headers().map_err(|e| e.to_string())?;
    let (width, height) = decoder.dimensions().ok_or("no image size in the headers")?;
    check_size(width, height)?;
    let channels = decoder
        .output_colorspace()
        .ok_or("no colour space in the headers")?
        .num_components();
    if !jpeg_has_end(bytes) {
        return Err("truncated: the image data ends before the end-of-image marker (FF D9)".into());
    }
    let buf = decoder.decode().map_err(|e| e.to_string())?;
    Ok((width, height, bytes_to_rgb(&buf, width * height, channels)?))
}

/// Whether the end-of-image marker FF D9 follows the first start-of-scan marker FF DA (an EXIF
/// thumbnail's own FF D9 comes before it; inside the entropy-coded data FF is always followed
/// by 00 or a restart marker). Without it the file was cut short: the lenient decoder would
/// fill the missing part of the image and render it without a word (libjpeg warns "Premature
/// end of JPEG file" and does the same).
fn jpeg_has_end(bytes: &[u8]) -> bool {
    let marker = |m: u8| move |w: &[u8]| w == [0xFF, m];
    match bytes.windows(2).position(marker(0xDA)) {
        Some(sos) => bytes[sos..].windows(2).any(marker(0xD9)),
        None => true, // no scan at all: the decoder says so
    }
}

/// Decodes a BMP (1 to 32 bits per pixel, palettes, run-length and bit-field forms).
pub fn decode_bmp(bytes: &[u8]) -> Result<Decoded, String> {
    // zune-bmp's errors have only a `Debug` form (its message, with a newline).
    let bmp_err = |e: zune_bmp::BmpDecoderErrors| format!("{e:?}").trim_end().to_string();
    let mut decoder = zune_bmp::BmpDecoder::new_with_options(ZCursor::new(bytes), options());
    decoder.decode_headers().map_err(bmp_err)?;
    let (width, height) = decoder.dimensions().ok_or("no image size in the headers")?;
    check_size(width, height)?;
    let channels = decoder
        .colorspace()
        .ok_or("no colour space in the headers")?
        .num_components();
    let buf = decoder.decode().map_err(bmp_err)?;
    Ok((width, height, bytes_to_rgb(&buf, width * height, channels)?))
}

/// Encodes 8-bit RGB (row-major) as a PNG.
pub fn encode_png_rgb8(rgb8: &[u8], width: usize, height: usize) -> Result<Vec<u8>, String> {
    if rgb8.len() != width * height * 3 {
        return Err(format!("{} bytes for {width} × {height} RGB pixels", rgb8.len()));
    }
    let w = u32::try_from(width).map_err(|e| e.to_string())?;
    let h = u32::try_from(height).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(rgb8).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    Ok(out)
}

/// The zune decoders' options: sizes up to 65536 (their default stops at 16384; the pixel
/// count is checked separately), lenient about the small format deviations real files have.
fn options() -> DecoderOptions {
    DecoderOptions::default()
        .set_strict_mode(false)
        .set_max_width(1 << 16)
        .set_max_height(1 << 16)
}

fn check_size(width: usize, height: usize) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!("an empty image ({width} × {height})"));
    }
    if width.saturating_mul(height) > MAX_PIXELS {
        return Err(format!(
            "{width} × {height} pixels (at most {MAX_PIXELS} are read)"
        ));
    }
    Ok(())
}

/// 8-bit samples of `channels` per pixel (grey, grey + alpha, RGB, RGBA) as RGB in [0, 1].
fn bytes_to_rgb(buf: &[u8], pixels: usize, channels: usize) -> Result<Vec<[f32; 3]>, String> {
    if !(1..=4).contains(&channels) || buf.len() < pixels * channels {
        return Err(format!(
            "{} bytes for {pixels} pixels of {channels} channels",
            buf.len()
        ));
    }
    Ok(buf
        .chunks_exact(channels)
        .take(pixels)
        .map(|p| pixel(channels, |c| f32::from(p[c]) / 255.0))
        .collect())
}

/// One pixel of `channels` samples as RGB: grey (1 or 2 channels) replicated, alpha dropped.
#[inline]
fn pixel(channels: usize, sample: impl Fn(usize) -> f32) -> [f32; 3] {
    if channels < 3 {
        [sample(0); 3]
    } else {
        [sample(0), sample(1), sample(2)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PNG of `color` and `depth` holding `data`, through the `png` encoder.
    fn png_of(
        w: u32,
        h: u32,
        color: png::ColorType,
        depth: png::BitDepth,
        data: &[u8],
        palette: Option<&[u8]>,
    ) -> Vec<u8> {
        let mut out = Vec::new();
        let mut e = png::Encoder::new(&mut out, w, h);
        e.set_color(color);
        e.set_depth(depth);
        if let Some(p) = palette {
            e.set_palette(p.to_vec());
        }
        let mut w = e.write_header().unwrap();
        w.write_image_data(data).unwrap();
        w.finish().unwrap();
        out
    }

    #[test]
    fn png_colour_types_and_depths_decode_to_rgb() {
        use png::{BitDepth, ColorType};
        // 16-bit grey: big-endian samples over 65535, replicated.
        let (w, h, px) = decode_png(&png_of(
            2,
            1,
            ColorType::Grayscale,
            BitDepth::Sixteen,
            &[0xff, 0xff, 0x80, 0x00],
            None,
        ))
        .unwrap();
        assert_eq!((w, h), (2, 1));
        assert_eq!(px, vec![[1.0; 3], [32768.0 / 65535.0; 3]]);
        // Grey + alpha: the alpha is dropped.
        let (_, _, px) = decode_png(&png_of(
            1,
            1,
            ColorType::GrayscaleAlpha,
            BitDepth::Eight,
            &[51, 0],
            None,
        ))
        .unwrap();
        assert_eq!(px, vec![[0.2; 3]]);
        // A 2-bit palette, expanded.
        let palette = [255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30];
        let (_, _, px) = decode_png(&png_of(
            4,
            1,
            ColorType::Indexed,
            BitDepth::Two,
            &[0b00_01_10_11],
            Some(&palette),
        ))
        .unwrap();
        assert_eq!(
            px,
            vec![
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [10.0 / 255.0, 20.0 / 255.0, 30.0 / 255.0]
            ]
        );
        // 16-bit RGBA.
        let rgba = [0, 0, 0xff, 0xff, 0x40, 0x00, 0x12, 0x34];
        let (_, _, px) = decode_png(&png_of(1, 1, ColorType::Rgba, BitDepth::Sixteen, &rgba, None)).unwrap();
        assert_eq!(px, vec![[0.0, 1.0, 16384.0 / 65535.0]]);
    }

    #[test]
    fn broken_or_empty_integer_images_are_refused() {
        assert!(decode_png(b"\x89PNG\r\n\x1a\nrest").is_err());
        assert!(decode_jpeg(&[0xff, 0xd8, 0xff, 0xe0, 0, 2]).is_err());
        assert!(decode_bmp(b"BM\0\0").is_err());
        assert!(check_size(0, 5).unwrap_err().contains("empty"));
        assert!(check_size(1 << 15, 1 << 15).unwrap_err().contains("at most"));
    }

    /// regression: a JPEG cut short rendered with the missing part of its image filled in.
    #[test]
    fn a_truncated_jpeg_is_refused() {
        let whole: &[u8] =
            include_bytes!("../../../../testdata/mitsuba-corpus/common/textures/floor_tiles.jpg");
        assert!(decode_jpeg(whole).is_ok());
        for keep in [whole.len() - 2, whole.len() / 2, 2000] {
            let err = decode_jpeg(&whole[..keep]).unwrap_err();
            eprintln!("{keep} bytes: {err}");
            assert!(
                err.contains("truncated") || err.contains("end"),
                "{keep} bytes: {err}"
            );
        }
    }
}
