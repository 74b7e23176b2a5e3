//! Image comparison: the error metrics of `gonio compare` and of the reference-scene tests.
//!
//! With `a` the test image and `b` the reference, over pixels p and channels c (N = 3·pixels):
//!
//! * **relMSE** = (1/N) Σ (a − b)² / (b² + ε), ε = [`RELMSE_EPS`] = 10⁻² (the ε keeps black
//!   reference pixels from dominating; pbrt and Mitsuba use the same form with ε = 10⁻²);
//! * **RMSE** = √((1/N) Σ (a − b)²); **MAE** = (1/N) Σ |a − b|;
//! * **block relMSE** ([`block_relmse`]): the relMSE of `block × block` block means. Averaging
//!   first removes most of the Monte Carlo noise and keeps bias, so two unbiased renders of the
//!   same scene agree closely while a systematic difference (a wrong BSDF, a mirrored camera)
//!   stands out. Partial blocks at the right and bottom edges are averaged over the pixels they
//!   have.
//! * **worst block**: the `block × block` block with the largest relMSE of its block mean.
//!
//! Non-finite pixel values (in either image) are excluded from the sums and counted.

use crate::image::RgbImage;

/// ε in the relMSE denominator.
pub const RELMSE_EPS: f64 = 1e-2;

/// The images cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// Different sizes.
    #[error("image sizes differ: {0}x{1} vs {2}x{3}")]
    SizeMismatch(usize, usize, usize, usize),
    /// An empty image.
    #[error("empty image")]
    Empty,
}

/// Where the images differ most.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorstBlock {
    /// Left column of the block.
    pub x: usize,
    /// Top row of the block.
    pub y: usize,
    /// Block size (pixels per side; edge blocks may be smaller).
    pub size: usize,
    /// relMSE of the block's mean colour.
    pub relmse: f64,
}

/// All metrics of a comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Metrics {
    /// Width and height.
    pub size: (usize, usize),
    /// Relative mean squared error (see the module documentation).
    pub relmse: f64,
    /// Root mean squared error.
    pub rmse: f64,
    /// Mean absolute error.
    pub mae: f64,
    /// relMSE of block means.
    pub block_relmse: f64,
    /// Per-channel means of `a`.
    pub mean_a: [f64; 3],
    /// Per-channel means of `b`.
    pub mean_b: [f64; 3],
    /// The worst block.
    pub worst: WorstBlock,
    /// Pixels with a non-finite value in either image (excluded from the other figures).
    pub non_finite: usize,
}

fn check(a: &RgbImage, b: &RgbImage) -> Result<(), CompareError> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(CompareError::SizeMismatch(a.width, a.height, b.width, b.height));
    }
    if a.width == 0 || a.height == 0 {
        return Err(CompareError::Empty);
    }
    Ok(())
}

#[inline]
fn finite(p: &[f32; 3]) -> bool {
    p.iter().all(|v| v.is_finite())
}

#[inline]
fn rel(a: f64, b: f64) -> f64 {
    (a - b) * (a - b) / (b * b + RELMSE_EPS)
}

/// Per-pixel relMSE over pixels and channels (non-finite pixels skipped).
pub fn relmse(a: &RgbImage, b: &RgbImage) -> Result<f64, CompareError> {
    check(a, b)?;
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (pa, pb) in a.data.iter().zip(&b.data) {
        if finite(pa) && finite(pb) {
            sum += (0..3).map(|c| rel(pa[c] as f64, pb[c] as f64)).sum::<f64>();
            n += 3;
        }
    }
    Ok(if n > 0 { sum / n as f64 } else { 0.0 })
}

/// Block means of an image: `(blocks_x, blocks_y, means)`; non-finite pixels of either image
/// (`mask`) are skipped.
fn block_means(img: &RgbImage, other: &RgbImage, block: usize) -> (usize, usize, Vec<Option<[f64; 3]>>) {
    let bx = img.width.div_ceil(block);
    let by = img.height.div_ceil(block);
    let mut sums = vec![([0.0f64; 3], 0usize); bx * by];
    for y in 0..img.height {
        for x in 0..img.width {
            let i = y * img.width + x;
            let (p, q) = (&img.data[i], &other.data[i]);
            if finite(p) && finite(q) {
                let s = &mut sums[(y / block) * bx + x / block];
                for (acc, &v) in s.0.iter_mut().zip(p) {
                    *acc += v as f64;
                }
                s.1 += 1;
            }
        }
    }
    let means = sums
        .into_iter()
        .map(|(s, n)| (n > 0).then(|| s.map(|v| v / n as f64)))
        .collect();
    (bx, by, means)
}

/// relMSE of `block × block` block means (module documentation); `block` = 1 is [`relmse`].
pub fn block_relmse(a: &RgbImage, b: &RgbImage, block: usize) -> Result<f64, CompareError> {
    Ok(block_stats(a, b, block)?.0)
}

/// (block relMSE, worst block).
fn block_stats(a: &RgbImage, b: &RgbImage, block: usize) -> Result<(f64, WorstBlock), CompareError> {
    check(a, b)?;
    let block = block.max(1);
    let (bx, _, ma) = block_means(a, b, block);
    let (_, _, mb) = block_means(b, a, block);
    let mut worst = WorstBlock {
        x: 0,
        y: 0,
        size: block,
        relmse: -1.0,
    };
    let (mut sum, mut n) = (0.0, 0usize);
    for (i, (pa, pb)) in ma.iter().zip(&mb).enumerate() {
        if let (Some(pa), Some(pb)) = (pa, pb) {
            let e: f64 = (0..3).map(|c| rel(pa[c], pb[c])).sum::<f64>() / 3.0;
            sum += e;
            n += 1;
            if e > worst.relmse {
                worst = WorstBlock {
                    x: (i % bx) * block,
                    y: (i / bx) * block,
                    size: block,
                    relmse: e,
                };
            }
        }
    }
    worst.relmse = worst.relmse.max(0.0);
    Ok((if n > 0 { sum / n as f64 } else { 0.0 }, worst))
}

/// Every metric at once; `block` is the block size for the block relMSE and the worst block.
pub fn compare(a: &RgbImage, b: &RgbImage, block: usize) -> Result<Metrics, CompareError> {
    check(a, b)?;
    let (mut se, mut ae, mut n, mut non_finite) = (0.0f64, 0.0f64, 0usize, 0usize);
    let (mut mean_a, mut mean_b) = ([0.0f64; 3], [0.0f64; 3]);
    for (pa, pb) in a.data.iter().zip(&b.data) {
        if !(finite(pa) && finite(pb)) {
            non_finite += 1;
            continue;
        }
        for c in 0..3 {
            let d = pa[c] as f64 - pb[c] as f64;
            se += d * d;
            ae += d.abs();
            mean_a[c] += pa[c] as f64;
            mean_b[c] += pb[c] as f64;
        }
        n += 1;
    }
    let pixels = n.max(1) as f64;
    let (block_relmse, worst) = block_stats(a, b, block)?;
    Ok(Metrics {
        size: (a.width, a.height),
        relmse: relmse(a, b)?,
        rmse: (se / (3.0 * pixels)).sqrt(),
        mae: ae / (3.0 * pixels),
        block_relmse,
        mean_a: mean_a.map(|v| v / pixels),
        mean_b: mean_b.map(|v| v / pixels),
        worst,
        non_finite,
    })
}

/// A false-colour picture of the per-pixel relative difference
/// `e = mean_c |a − b| / (mean_c |b| + 0.1)`, on a logarithmic scale from 10⁻³ (black) through
/// blue, magenta and orange to ≥ 1 (white); non-finite pixels are bright green. Returned as linear
/// RGB, ready for [`RgbImage::write_png`].
pub fn diff_image(a: &RgbImage, b: &RgbImage) -> Result<RgbImage, CompareError> {
    check(a, b)?;
    Ok(RgbImage::from_fn(a.width, a.height, |x, y| {
        let (pa, pb) = (a.get(x, y), b.get(x, y));
        if !(finite(&pa) && finite(&pb)) {
            return [0.0, 1.0, 0.0];
        }
        let d: f32 = (0..3).map(|c| (pa[c] - pb[c]).abs()).sum::<f32>() / 3.0;
        let m: f32 = pb.iter().map(|v| v.abs()).sum::<f32>() / 3.0;
        let e = d / (m + 0.1);
        let t = if e <= 0.0 {
            0.0
        } else {
            ((e.log10() + 3.0) / 3.0).clamp(0.0, 1.0)
        };
        colormap(t)
    }))
}

/// A perceptually ordered map of [0, 1] (black → blue → magenta → orange → white), in linear
/// RGB (the stops are sRGB-encoded values, decoded here so the PNG shows them as designed).
fn colormap(t: f32) -> [f32; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [0.16, 0.11, 0.55],
        [0.73, 0.21, 0.47],
        [0.98, 0.60, 0.13],
        [1.0, 1.0, 1.0],
    ];
    let s = t * (STOPS.len() - 1) as f32;
    let i = (s.floor() as usize).min(STOPS.len() - 2);
    let f = s - i as f32;
    let lerp = |c: usize| STOPS[i][c] + f * (STOPS[i + 1][c] - STOPS[i][c]);
    let dec = |v: f32| {
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    [dec(lerp(0)), dec(lerp(1)), dec(lerp(2))]
}
