//! Radiance RGBE (`.hdr`, `.pic`): Greg Ward's shared-exponent pixels, read and written.
//!
//! A file is a text header (`#?` and the writing program's name, `KEY=value` lines, an empty
//! line), a resolution line (`-Y height +X width`: rows top to bottom, or `+Y`: bottom to top)
//! and the scanlines: flat 4-byte pixels, "old" run-length pixels (`1 1 1 n` repeats the pixel
//! before), or "new" run-length scanlines (`2 2 hi lo`, then each of the four byte planes as
//! runs). A pixel (r, g, b, e) is (r, g, b) · 2^(e − 136), black when e = 0 (Ward's `rgbe.c`,
//! the convention of Mitsuba's and pbrt's readers: no half-unit offset on the mantissa).
//!
//! Our own code, not a crate's: `zune-hdr` 0.5 computes 2^k with a 32-bit shift and wraps for
//! |k| ≥ 32 (a pixel of exponent byte 64 reads as 1/256 of its mantissa instead of ~10⁻²⁰), and
//! `image` brings a colour-management crate whose compilation is most of the test build's
//! third-party time. The format fits in this file.

use super::MAX_PIXELS;

/// Decodes a Radiance RGBE image into linear RGB, rows top to bottom. Errors name what is wrong
/// (the caller adds the file).
pub fn decode(bytes: &[u8]) -> Result<(usize, usize, Vec<[f32; 3]>), String> {
    let (width, height, bottom_up, mut at) = header(bytes)?;
    // Grown row by row: a header promising more than the file holds fails at its first missing
    // scanline, not at an allocation.
    let mut out = Vec::new();
    let mut line = vec![[0u8; 4]; width];
    for row in 0..height {
        at = scanline(bytes, at, &mut line).map_err(|e| format!("scanline {row}: {e}"))?;
        out.extend(line.iter().map(|&p| rgbe_to_rgb(p)));
    }
    if bottom_up {
        out = out.chunks_exact(width).rev().flatten().copied().collect();
    }
    Ok((width, height, out))
}

/// Encodes linear RGB (rows top to bottom, non-negative) as a Radiance file with flat scanlines.
///
/// Flat scanlines are unambiguous: a pixel read as a run-length marker would start `2 2 b`
/// with b < 128, but the largest of a pixel's mantissas is at least 128.
pub fn encode(width: usize, height: usize, rgb: &[[f32; 3]]) -> Vec<u8> {
    assert_eq!(rgb.len(), width * height, "pixel count");
    let head = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n");
    let mut out = Vec::with_capacity(head.len() + 4 * rgb.len());
    out.extend_from_slice(head.as_bytes());
    for p in rgb {
        out.extend_from_slice(&rgb_to_rgbe(*p));
    }
    out
}

/// (r, g, b) · 2^(e − 136); exact (a product of an 8-bit integer and a power of two).
pub fn rgbe_to_rgb([r, g, b, e]: [u8; 4]) -> [f32; 3] {
    if e == 0 {
        return [0.0; 3];
    }
    let scale = 2f64.powi(i32::from(e) - 136);
    [r, g, b].map(|m| (f64::from(m) * scale) as f32)
}

/// Ward's encoding: the largest component v = m · 2^k with m in [0.5, 1) sets the exponent byte
/// k + 128 and every mantissa is ⌊c · 256 · m / v⌋. Values below 10⁻³² (and NaN) are black;
/// values above the format's range saturate.
pub fn rgb_to_rgbe(rgb: [f32; 3]) -> [u8; 4] {
    let rgb = rgb.map(|c| if c > 0.0 { c.min(f32::MAX) } else { 0.0 });
    let v = rgb[0].max(rgb[1]).max(rgb[2]);
    if !(v >= 1e-32) {
        return [0; 4];
    }
    let (m, k) = frexp(f64::from(v));
    if k > 127 {
        return [255, 255, 255, 255];
    }
    let scale = m * 256.0 / f64::from(v);
    let [r, g, b] = rgb.map(|c| (f64::from(c) * scale).min(255.0) as u8);
    [r, g, b, (k + 128) as u8]
}

/// v = m · 2^k with m in [0.5, 1), for positive finite normal v.
fn frexp(v: f64) -> (f64, i32) {
    let bits = v.to_bits();
    let k = ((bits >> 52) & 0x7ff) as i32 - 1022;
    let m = f64::from_bits((bits & !(0x7ff << 52)) | (1022 << 52));
    (m, k)
}

/// Reads the header and the resolution line: (width, height, rows bottom to top, offset of the
/// first scanline).
fn header(bytes: &[u8]) -> Result<(usize, usize, bool, usize), String> {
    let mut lines = Lines { bytes, at: 0 };
    let first = lines.next().ok_or("no header line")?;
    if !first.starts_with("#?") {
        return Err("not a Radiance file (no `#?` signature)".into());
    }
    loop {
        let line = lines.next().ok_or("the header does not end (no empty line)")?;
        if line.is_empty() {
            break;
        }
        if let Some(format) = line.strip_prefix("FORMAT=")
            && format.trim() != "32-bit_rle_rgbe"
        {
            return Err(format!("pixel format {format:?} (only 32-bit_rle_rgbe is read)"));
        }
    }
    let res = lines.next().ok_or("no resolution line")?;
    let words: Vec<&str> = res.split_whitespace().collect();
    let (bottom_up, h, w) = match words.as_slice() {
        ["-Y", h, "+X", w] => (false, h, w),
        ["+Y", h, "+X", w] => (true, h, w),
        _ => {
            return Err(format!(
                "resolution line {res:?} (read: `-Y height +X width` or `+Y height +X width`)"
            ));
        }
    };
    let dim = |s: &str| -> Result<usize, String> {
        match s.parse::<usize>() {
            Ok(n) if (1..=1 << 16).contains(&n) => Ok(n),
            _ => Err(format!("image size {s:?} in {res:?} (1 to 65536)")),
        }
    };
    let (width, height) = (dim(w)?, dim(h)?);
    if width * height > MAX_PIXELS {
        return Err(format!(
            "{width} × {height} pixels (at most {MAX_PIXELS} are read)"
        ));
    }
    Ok((width, height, bottom_up, lines.at))
}

struct Lines<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Lines<'a> {
    /// The next line without its `\n` (header lines are ASCII; at most 4 KB each).
    fn next(&mut self) -> Option<&'a str> {
        let rest = &self.bytes[self.at..];
        let end = rest.iter().take(4096).position(|&b| b == b'\n')?;
        self.at += end + 1;
        std::str::from_utf8(&rest[..end]).ok()
    }
}

/// Reads one scanline into `line` from `at`; returns the offset after it.
fn scanline(bytes: &[u8], mut at: usize, line: &mut [[u8; 4]]) -> Result<usize, String> {
    let width = line.len();
    let take4 = |at: usize| -> Result<[u8; 4], String> {
        bytes
            .get(at..at + 4)
            .map(|s| [s[0], s[1], s[2], s[3]])
            .ok_or_else(|| "the file ends inside it".to_string())
    };
    let first = take4(at)?;
    let new_rle = (8..=0x7fff).contains(&width) && first[0] == 2 && first[1] == 2 && first[2] < 128;
    if new_rle {
        let len = usize::from(first[2]) << 8 | usize::from(first[3]);
        if len != width {
            return Err(format!(
                "its run-length header says {len} pixels, the image {width}"
            ));
        }
        at += 4;
        for plane in 0..4 {
            let mut x = 0;
            while x < width {
                let &count = bytes.get(at).ok_or("the file ends inside it")?;
                at += 1;
                if count > 128 {
                    let n = usize::from(count - 128);
                    let &v = bytes.get(at).ok_or("the file ends inside it")?;
                    at += 1;
                    if x + n > width {
                        return Err("a run goes past its end".into());
                    }
                    line[x..x + n].iter_mut().for_each(|p| p[plane] = v);
                    x += n;
                } else {
                    let n = usize::from(count);
                    if n == 0 || x + n > width {
                        return Err("a literal run is empty or goes past its end".into());
                    }
                    let src = bytes.get(at..at + n).ok_or("the file ends inside it")?;
                    at += n;
                    line[x..x + n]
                        .iter_mut()
                        .zip(src)
                        .for_each(|(p, &v)| p[plane] = v);
                    x += n;
                }
            }
        }
        return Ok(at);
    }
    // Flat pixels, with the old run-length form: `1 1 1 n` repeats the pixel before n times,
    // consecutive such markers shifting n by 8 more bits each.
    let mut x = 0;
    let mut shift = 0u32;
    while x < width {
        let p = take4(at)?;
        at += 4;
        if p[0] == 1 && p[1] == 1 && p[2] == 1 {
            if x == 0 || shift > 16 {
                return Err("an old-style run has no pixel to repeat".into());
            }
            let n = usize::from(p[3]) << shift;
            if x + n > width {
                return Err("an old-style run goes past its end".into());
            }
            let prev = line[x - 1];
            line[x..x + n].fill(prev);
            x += n;
            shift += 8;
        } else {
            line[x] = p;
            x += 1;
            shift = 0;
        }
    }
    Ok(at)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixels_survive_a_round_trip_to_eight_bits_of_mantissa() {
        let px = [
            [0.0, 0.0, 0.0],
            [1.0, 0.5, 0.25],
            [3e4, 1e-3, 7.0],
            [1e-20, 0.0, 2e-20],
        ];
        let (w, h, back) = decode(&encode(2, 2, &px)).unwrap();
        assert_eq!((w, h), (2, 2));
        for (a, b) in px.iter().zip(&back) {
            let v = a[0].max(a[1]).max(a[2]);
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() <= v / 128.0, "{a:?} → {b:?}");
            }
        }
        assert_eq!(back[1], [1.0, 0.5, 0.25], "powers of two are exact");
    }

    #[test]
    fn exponents_far_from_128_are_not_wrapped() {
        // 128 · 2^(64 − 136) = 2^-65; a 32-bit shift would make it 0.5.
        assert_eq!(rgbe_to_rgb([128, 0, 0, 64]), [2f32.powi(-65), 0.0, 0.0]);
        assert_eq!(rgbe_to_rgb([128, 0, 0, 200]), [2f32.powi(71), 0.0, 0.0]);
    }

    #[test]
    fn new_run_length_scanlines_are_read() {
        let mut f = b"#?RGBE\n\n-Y 1 +X 8\n".to_vec();
        f.extend([2, 2, 0, 8]);
        f.extend([136, 128]); // r: 8 × 128
        f.extend([4, 0, 64, 128, 255, 132, 7]); // g: 0 64 128 255, then 4 × 7
        f.extend([136, 0]); // b
        f.extend([136, 129]); // e: 2^(129 − 136) = 1/128
        let (_, _, px) = decode(&f).unwrap();
        assert_eq!(px[0], [1.0, 0.0, 0.0]);
        assert_eq!(px[2], [1.0, 1.0, 0.0]);
        assert_eq!(px[7], [1.0, 7.0 / 128.0, 0.0]);
    }

    #[test]
    fn old_runs_repeat_the_pixel_before_and_bottom_up_files_are_flipped() {
        let mut f = b"#?RADIANCE\n\n+Y 2 +X 3\n".to_vec();
        f.extend([128, 0, 0, 129, 1, 1, 1, 2]); // bottom row: red, then 2 more
        f.extend([0, 128, 0, 129, 0, 0, 0, 0, 0, 0, 128, 129]); // top row
        let (w, h, px) = decode(&f).unwrap();
        assert_eq!((w, h), (3, 2));
        assert_eq!(px[0], [0.0, 1.0, 0.0]);
        assert_eq!(px[2], [0.0, 0.0, 1.0]);
        assert_eq!(px[3..], [[1.0, 0.0, 0.0]; 3]);
    }

    #[test]
    fn malformed_files_are_refused_with_the_reason() {
        let cases: [(&[u8], &str); 7] = [
            (b"P6\n", "signature"),
            (
                b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\0\0\0\0",
                "xyze",
            ),
            (b"#?RADIANCE\n\n-Y 2 +X 2\n", "ends inside"),
            (b"#?RADIANCE\n\n+X 1 -Y 1\n\0\0\0\0", "resolution line"),
            (b"#?RADIANCE\n\n-Y 1 +X 99999999999\n", "image size"),
            (b"#?RADIANCE\n\n-Y 65536 +X 65536\n", "at most"),
            (b"#?RADIANCE\n\n-Y 1 +X 1\n\x01\x01\x01\x05", "no pixel to repeat"),
        ];
        for (bytes, says) in cases {
            let e = decode(bytes).unwrap_err();
            assert!(e.contains(says), "{e:?} should say {says:?}");
        }
        let mut rle = b"#?RADIANCE\n\n-Y 1 +X 8\n".to_vec();
        rle.extend([2, 2, 0, 8, 200, 1]);
        assert!(decode(&rle).unwrap_err().contains("past its end"));
    }
}
