//! Image files: round trips, sRGB decoding, HDR, error paths, atomic writes.

use gonio_render::image::{Encoding, ImageError, RgbImage, codecs, rgbe};
use std::path::Path;

/// A temporary folder, removed when the handle drops.
fn tmpdir() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
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
    let d = tmpdir();
    let d = d.path();
    let img = gradient(7, 5);
    let p = d.join("a.exr");
    img.write_exr(&p).unwrap();
    let back = RgbImage::read(&p).unwrap();
    assert_eq!(
        back, img,
        "float EXR must round-trip bit-exactly, including negatives and > 1"
    );
    // No temporary file left behind.
    let names: Vec<_> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
}

#[test]
fn png_round_trip_within_quantization_and_clamped() {
    let d = tmpdir();
    let d = d.path();
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
    let d = tmpdir();
    let d = d.path();
    let p = d.join("grey.png");
    let png = codecs::encode_png_rgb8(&[128, 10, 255].repeat(4), 2, 2).unwrap();
    std::fs::write(&p, png).unwrap();
    let lin = RgbImage::read(&p).unwrap().get(1, 1);
    // 128/255 = 0.50196 -> ((0.50196 + 0.055) / 1.055)^2.4 = 0.21586; 10/255 -> 0.0392/12.92 = 0.003035.
    assert!((lin[0] - 0.215_86).abs() < 1e-4, "{lin:?}");
    assert!((lin[1] - 0.003_035).abs() < 1e-5, "{lin:?}");
    assert!((lin[2] - 1.0).abs() < 1e-6);
    let raw = RgbImage::read_with(&p, Encoding::Raw).unwrap().get(0, 0);
    assert!((raw[0] - 128.0 / 255.0).abs() < 1e-6, "{raw:?}");
}

/// Pixels of Mitsuba's own textures as Mitsuba 3.9.1's `Bitmap` reads them (8-bit values,
/// `np.array(mi.Bitmap(file))`): PNG and BMP decode to the same integers; JPEG decoders may differ
/// by their IDCT's rounding (zune-jpeg against Mitsuba's libjpeg on the corpus's five JPEGs:
/// 74–99 % of the samples equal, at most 0.06 % more than 2 levels apart), so those points
/// allow 3 levels.
#[test]
fn mitsuba_textures_read_as_mitsuba_reads_them() {
    let tex = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mitsuba-corpus/common/textures");
    #[allow(clippy::type_complexity)]
    let cases: [(&str, u8, &[((usize, usize), [u8; 3])]); 4] = [
        // (file, levels allowed, ((x, y), RGB)); grey files replicate their value.
        (
            "flower.bmp",
            0,
            &[
                ((0, 0), [146, 168, 98]),
                ((50, 33), [252, 226, 184]),
                ((99, 66), [95, 88, 78]),
            ],
        ),
        (
            "leaf_mask.png",
            0,
            &[((0, 0), [0; 3]), ((120, 120), [255; 3]), ((200, 17), [0; 3])],
        ),
        (
            "floor_tiles.jpg",
            3,
            &[
                ((0, 0), [27, 35, 38]),
                ((100, 37), [4, 5, 7]),
                ((255, 255), [29, 33, 36]),
            ],
        ),
        ("noise_01.jpg", 3, &[((0, 0), [0; 3]), ((13, 200), [21; 3])]),
    ];
    for (file, levels, points) in cases {
        let img = RgbImage::read_with(tex.join(file), Encoding::Raw).unwrap();
        for &((x, y), want) in points {
            let got = img.get(x, y);
            for c in 0..3 {
                let d = (got[c] * 255.0 - f32::from(want[c])).abs();
                assert!(
                    d <= f32::from(levels) + 1e-3,
                    "{file} ({x}, {y}): {got:?} vs {want:?}/255"
                );
            }
        }
    }
    // Radiance RGBE: exact (Mitsuba's float values).
    let env = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/mitsuba-corpus/docs/scenes/principled_blend_creation/envmap.hdr");
    let img = RgbImage::read(env).unwrap();
    assert_eq!((img.width, img.height), (256, 128));
    assert_eq!(img.get(0, 0), [0.3359375, 0.26171875, 0.115234375]);
    assert_eq!(img.get(100, 60), [0.5859375, 0.671875, 0.765625]);
    assert_eq!(img.get(255, 127), [0.0; 3]);
}

#[test]
fn hdr_round_trips_within_rgbe_precision_and_is_linear() {
    let d = tmpdir();
    let ph = d.path().join("a.hdr");
    let px: Vec<[f32; 3]> = (0..6).map(|i| [i as f32 * 3.0, 0.5, 100.0]).collect();
    std::fs::write(&ph, rgbe::encode(3, 2, &px)).unwrap();
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
    let d = tmpdir();
    let d = d.path();
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
    let d = tmpdir();
    let d = d.path();
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
    let names: Vec<_> = std::fs::read_dir(d)
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
    // it); some readers (the `image` crate) accept only the latter.
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
