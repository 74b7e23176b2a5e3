//! Image files: round trips, sRGB decoding, HDR, error paths, atomic writes.

use gonio_render::image::{Encoding, ImageError, RgbImage};
use std::path::PathBuf;

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gonio-image-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn gradient(w: usize, h: usize) -> RgbImage {
    RgbImage::from_fn(w, h, |x, y| {
        [
            x as f32 * 0.37 + 0.01,
            y as f32 * 1.5,
            (x * y) as f32 * 1e-3 - 0.25,
        ]
    })
}

#[test]
fn exr_round_trip_is_exact_for_f32() {
    let d = tmpdir("exr");
    let img = gradient(7, 5);
    let p = d.join("a.exr");
    img.write_exr(&p).unwrap();
    let back = RgbImage::read(&p).unwrap();
    assert_eq!(
        back, img,
        "float EXR must round-trip bit-exactly, including negatives and > 1"
    );
    // No temporary file left behind.
    let names: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
}

#[test]
fn png_round_trip_within_quantization_and_clamped() {
    let d = tmpdir("png");
    let img = RgbImage::from_fn(16, 3, |x, y| {
        [x as f32 / 15.0, 0.5, if y == 0 { 2.0 } else { -1.0 }]
    });
    let p = d.join("a.png");
    img.write_png(&p).unwrap();
    let back = RgbImage::read(&p).unwrap();
    assert_eq!((back.width, back.height), (16, 3));
    for (a, b) in img.data.iter().zip(&back.data) {
        for c in 0..2 {
            // 8-bit sRGB quantization: the step near 1 is ~1/255 * 2.4 in linear.
            assert!((a[c] - b[c]).abs() < 0.01, "{a:?} vs {b:?}");
        }
        let expect = if a[2] > 1.0 { 1.0 } else { 0.0 };
        assert_eq!(b[2], expect, "clamped");
    }
}

#[test]
fn srgb_decoding_matches_the_standard_curve_and_raw_skips_it() {
    let d = tmpdir("srgb");
    let p = d.join("grey.png");
    let buf = image::RgbImage::from_pixel(2, 2, image::Rgb([128u8, 10, 255]));
    buf.save(&p).unwrap();
    let lin = RgbImage::read(&p).unwrap().get(1, 1);
    // 128/255 = 0.50196 -> ((0.50196 + 0.055) / 1.055)^2.4 = 0.21586; 10/255 -> 0.0392/12.92 = 0.003035.
    assert!((lin[0] - 0.215_86).abs() < 1e-4, "{lin:?}");
    assert!((lin[1] - 0.003_035).abs() < 1e-5, "{lin:?}");
    assert!((lin[2] - 1.0).abs() < 1e-6);
    let raw = RgbImage::read_with(&p, Encoding::Raw).unwrap().get(0, 0);
    assert!((raw[0] - 128.0 / 255.0).abs() < 1e-6, "{raw:?}");
}

#[test]
fn jpeg_and_hdr_are_read() {
    let d = tmpdir("jpghdr");
    let pj = d.join("a.jpg");
    image::RgbImage::from_pixel(8, 8, image::Rgb([255u8, 255, 255]))
        .save(&pj)
        .unwrap();
    let j = RgbImage::read(&pj).unwrap();
    assert_eq!((j.width, j.height), (8, 8));
    assert!(
        j.data.iter().all(|p| p.iter().all(|&v| v > 0.97)),
        "white JPEG reads as ~1"
    );

    let ph = d.join("a.hdr");
    let px: Vec<image::Rgb<f32>> = (0..6).map(|i| image::Rgb([i as f32 * 3.0, 0.5, 100.0])).collect();
    let f = std::fs::File::create(&ph).unwrap();
    image::codecs::hdr::HdrEncoder::new(f).encode(&px, 3, 2).unwrap();
    let h = RgbImage::read(&ph).unwrap();
    assert_eq!((h.width, h.height), (3, 2));
    // RGBE keeps ~8 bits of mantissa; HDR values are linear (no sRGB curve).
    for (i, p) in h.data.iter().enumerate() {
        let want = [i as f32 * 3.0, 0.5, 100.0];
        for c in 0..3 {
            assert!(
                (p[c] - want[c]).abs() <= 0.01 * want[c].max(0.01) + 1e-6,
                "{p:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn bad_input_gives_errors_naming_the_file() {
    let d = tmpdir("bad");
    let missing = d.join("missing.exr");
    let e = RgbImage::read(&missing).unwrap_err();
    assert!(matches!(e, ImageError::Io { .. }));
    assert!(e.to_string().contains("missing.exr"), "{e}");

    let junk = d.join("junk.png");
    std::fs::write(&junk, b"this is not an image").unwrap();
    let e = RgbImage::read(&junk).unwrap_err();
    assert!(
        matches!(e, ImageError::UnknownFormat { .. }) && e.to_string().contains("junk.png"),
        "{e}"
    );

    // A truncated EXR and a truncated PNG: recognized by magic, broken content.
    let good = d.join("good.exr");
    gradient(32, 32).write_exr(&good).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let trunc = d.join("trunc.exr");
    std::fs::write(&trunc, &bytes[..bytes.len() / 2]).unwrap();
    let e = RgbImage::read(&trunc).unwrap_err();
    assert!(
        matches!(
            e,
            ImageError::Decode {
                format: "OpenEXR",
                ..
            }
        ) && e.to_string().contains("trunc.exr"),
        "{e}"
    );

    let goodp = d.join("good.png");
    gradient(32, 32).write_png(&goodp).unwrap();
    let bytes = std::fs::read(&goodp).unwrap();
    let truncp = d.join("trunc.png");
    std::fs::write(&truncp, &bytes[..bytes.len() / 2]).unwrap();
    let e = RgbImage::read(&truncp).unwrap_err();
    assert!(matches!(e, ImageError::Decode { format: "PNG", .. }), "{e}");
}

#[test]
fn failed_write_leaves_the_old_file_and_no_temporary() {
    let d = tmpdir("atomic");
    let p = d.join("keep.exr");
    gradient(4, 4).write_exr(&p).unwrap();
    let before = std::fs::read(&p).unwrap();
    // An empty image cannot be encoded: the write must fail without touching the file.
    assert!(RgbImage::new(0, 0).write_exr(&p).is_err());
    assert_eq!(std::fs::read(&p).unwrap(), before);
    // Unknown extension.
    let e = gradient(2, 2).write(d.join("x.tiff")).unwrap_err();
    assert!(e.to_string().contains("x.tiff"), "{e}");
    // Writing into a folder that does not exist is an I/O error naming the file.
    let e = gradient(2, 2).write_png(d.join("no/such/dir/y.png")).unwrap_err();
    assert!(
        matches!(e, ImageError::Io { .. }) && e.to_string().contains("y.png"),
        "{e}"
    );
    let names: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
    // write() dispatches on the extension.
    let q = d.join("Z.PNG");
    gradient(2, 2).write(&q).unwrap();
    assert!(std::fs::read(&q).unwrap().starts_with(b"\x89PNG"));
}

#[test]
fn radiance_hdr_with_an_rgbe_signature_reads() {
    // "#?RGBE" is as valid a Radiance signature as "#?RADIANCE" (Mitsuba, pbrt and stb write
    // it); the `image` crate accepts only the latter, so the reader renames it.
    let mut bytes = b"#?RGBE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n".to_vec();
    bytes.extend_from_slice(&[128, 64, 32, 129, 0, 0, 0, 0]); // a lit RGBE pixel, then a black one
    let img = gonio_render::image::RgbImage::decode(
        &bytes,
        std::path::Path::new("rgbe.hdr"),
        gonio_render::image::Encoding::Srgb,
    )
    .expect("an #?RGBE file decodes");
    assert_eq!((img.width, img.height), (2, 1));
    let radiance = [b"#?RADIANCE\n".as_slice(), &bytes[7..]].concat();
    let same = gonio_render::image::RgbImage::decode(
        &radiance,
        std::path::Path::new("radiance.hdr"),
        gonio_render::image::Encoding::Srgb,
    )
    .unwrap();
    assert_eq!(img.data, same.data, "the signature changes nothing else");
    assert!(img.data[0][0] > 0.0 && img.data[1] == [0.0; 3]);
}
