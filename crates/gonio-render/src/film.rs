//! The film: filtered accumulation of colour samples into pixels (Mitsuba's `hdrfilm`).
//!
//! A sample at film position `p` (pixels; pixel `(i, j)` covers `[i, i+1) × [j, j+1)`, its centre
//! at `(i + ½, j + ½)`) adds `w·c` and `w` to every pixel whose centre lies within the filter
//! radius, with `w = f(pₓ − cₓ)·f(p_y − c_y)`; a pixel's value is `Σ w·c / Σ w` (the weighted mean,
//! as Mitsuba and pbrt compute it). Filters, as Mitsuba defines them:
//!
//! * `box` (radius r, default ½): `f(x) = 1` for `−r ≤ x < r` (half-open, so a sample on a pixel
//!   border belongs to exactly one pixel);
//! * `tent` (radius r, default 1): `f(x) = max(0, 1 − |x|/r)`;
//! * `gaussian` (σ, default ½, radius 4σ): `f(x) = max(0, exp(−x²/2σ²) − exp(−r²/2σ²))`;
//! * `mitchell` (B, C; default ⅓, ⅓) and `catmullrom` (B = 0, C = ½), radius 2 (Mitchell and
//!   Netravali 1988): with t = |x|, `f = ((12 − 9B − 6C)t³ + (−18 + 12B + 6C)t² + 6 − 2B)/6` for
//!   t < 1, `((−B − 6C)t³ + (6B + 30C)t² + (−12B − 48C)t + 8B + 24C)/6` for 1 ≤ t < 2, else 0;
//! * `lanczos` (a lobes, default 3, radius a): `f(x) = sinc(πx)·sinc(πx/a)` for |x| < a.
//!
//! The last two are negative in places, as in Mitsuba; a pixel is still `Σ w·c / Σ w`.
//!
//! Threads render into [`FilmTile`]s (a block of pixels plus the margin the filter reaches) and
//! the tiles are added into the [`Film`] with [`Film::merge`]. The film adds in `f64` and in the
//! order tiles are merged: merging in a fixed order (e.g. tile index) gives the same image
//! whatever the number of threads.
//!
//! # Channels
//!
//! The film accumulates named channels ([`Channels`]), each filtered like the others with the
//! same weights: today the integrators write `R`, `G`, `B` (linear sRGB; the caller converts
//! spectral samples first, with `gonio_core::color`: the filter is linear, so converting before
//! or after filtering gives the same pixel); an AOV, moment or Stokes integrator adds layers with
//! the EXR naming `layer.channel` (`albedo.R`, `m2.R`, `S1.G`), and [`Film::to_channels`]
//! writes them all to EXR under those names. With three channels a pixel is exactly what the
//! RGB film was: four sums (three channels and the weight).

use crate::image::{ChannelImage, RgbImage};
use crate::scene::FilterDesc;
use glam::{UVec2, Vec2, Vec4};
use gonio_core::math::{ceil, floor};
use gonio_core::sensor_response::SensorResponse;

/// A filter with its support radius precomputed.
#[derive(Clone, Copy, Debug)]
struct Kernel {
    filter: FilterDesc,
    radius: f32,
    gauss_alpha: f32,
    gauss_bias: f32,
}

impl Kernel {
    fn new(filter: FilterDesc) -> Self {
        let radius = filter.radius();
        let (gauss_alpha, gauss_bias) = match filter {
            FilterDesc::Gaussian { stddev } => {
                let a = -1.0 / (2.0 * stddev * stddev);
                (a, (a * radius * radius).exp())
            }
            _ => (0.0, 0.0),
        };
        Self {
            filter,
            radius,
            gauss_alpha,
            gauss_bias,
        }
    }

    #[inline]
    fn eval(&self, x: f32) -> f32 {
        match self.filter {
            FilterDesc::Box { radius } => {
                if -radius <= x && x < radius {
                    1.0
                } else {
                    0.0
                }
            }
            FilterDesc::Tent { radius } => (1.0 - x.abs() / radius).max(0.0),
            FilterDesc::Gaussian { .. } => ((self.gauss_alpha * x * x).exp() - self.gauss_bias).max(0.0),
            FilterDesc::Mitchell { b, c } => {
                let t = x.abs();
                if t < 1.0 {
                    ((12.0 - 9.0 * b - 6.0 * c) * t * t * t
                        + (-18.0 + 12.0 * b + 6.0 * c) * t * t
                        + (6.0 - 2.0 * b))
                        / 6.0
                } else if t < 2.0 {
                    ((-b - 6.0 * c) * t * t * t
                        + (6.0 * b + 30.0 * c) * t * t
                        + (-12.0 * b - 48.0 * c) * t
                        + (8.0 * b + 24.0 * c))
                        / 6.0
                } else {
                    0.0
                }
            }
            FilterDesc::Lanczos { lobes } => {
                let a = lobes as f32;
                if x.abs() >= a {
                    0.0
                } else {
                    sinc(std::f32::consts::PI * x) * sinc(std::f32::consts::PI * x / a)
                }
            }
        }
    }

    /// How many pixels beyond a block the filter reaches.
    fn margin(&self) -> u32 {
        (self.radius - 0.5).max(0.0).ceil() as u32
    }
}

/// sin(x)/x, 1 at 0.
#[inline]
fn sinc(x: f32) -> f32 {
    if x.abs() < 1e-4 {
        1.0 - x * x / 6.0
    } else {
        x.sin() / x
    }
}

/// The names of a film's channels, in the order samples give their values.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Channels {
    names: Vec<String>,
}

impl Channels {
    /// `R`, `G`, `B`: linear sRGB radiance.
    pub fn rgb() -> Self {
        Self::new(["R", "G", "B"])
    }

    /// What a film of this response records: `R`, `G`, `B`, or one channel per spectral band
    /// under the band's name.
    pub fn for_response(response: &SensorResponse) -> Self {
        match response {
            SensorResponse::Srgb | SensorResponse::Filtered(_) => Self::rgb(),
            SensorResponse::Bands(b) => Self::new(b.names().iter().cloned()),
        }
    }

    /// Channels with these names (EXR naming: `R`, or `layer.R` for a layer).
    pub fn new<S: Into<String>>(names: impl IntoIterator<Item = S>) -> Self {
        Self {
            names: names.into_iter().map(Into::into).collect(),
        }
    }

    /// Adds the channels of a layer: `layer.c` for each `c` of `channels` (`R`, `G`, `B` for a
    /// colour layer).
    pub fn with_layer(mut self, layer: &str, channels: &[&str]) -> Self {
        self.names.extend(channels.iter().map(|c| format!("{layer}.{c}")));
        self
    }

    /// Adds one channel called `name`.
    pub fn with_channel(mut self, name: &str) -> Self {
        self.names.push(name.to_string());
        self
    }

    /// Number of channels.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// True when there is no channel.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// The names.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Index of the channel called `name`.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
}

/// The whole image being accumulated.
#[derive(Clone, Debug)]
pub struct Film {
    width: u32,
    height: u32,
    kernel: Kernel,
    channels: Channels,
    /// Per pixel: weighted channel sums, then the weight sum (stride `channels.len() + 1`).
    pixels: Vec<f64>,
}

/// A rectangular part of the film that one thread accumulates into.
#[derive(Clone, Debug)]
pub struct FilmTile {
    /// Pixels the tile's samples are meant for: `[min, max)`.
    block_min: UVec2,
    block_max: UVec2,
    /// Pixels the tile stores (block plus filter margin, clipped to the film).
    min: UVec2,
    max: UVec2,
    kernel: Kernel,
    /// Per stored pixel: weighted channel sums, then the weight sum.
    data: Vec<f32>,
    /// Values per stored pixel (channels + 1).
    stride: usize,
    invalid: u64,
}

impl Film {
    /// An empty film with the channels `R`, `G`, `B`.
    pub fn new(width: u32, height: u32, filter: FilterDesc) -> Self {
        Self::with_channels(width, height, filter, Channels::rgb())
    }

    /// An empty film with these channels.
    pub fn with_channels(width: u32, height: u32, filter: FilterDesc, channels: Channels) -> Self {
        let stride = channels.len() + 1;
        Self {
            width,
            height,
            kernel: Kernel::new(filter),
            channels,
            pixels: vec![0.0; (width * height) as usize * stride],
        }
    }

    /// How many pixels beyond the image the filter reaches (Mitsuba's `border_size`,
    /// ⌈radius − ½⌉): the width of the band `hdrfilm`'s `sample_border` samples around it.
    pub fn border(&self) -> u32 {
        self.kernel.margin()
    }

    /// The channels.
    pub fn channels(&self) -> &Channels {
        &self.channels
    }

    /// Film size in pixels.
    pub fn size(&self) -> UVec2 {
        UVec2::new(self.width, self.height)
    }

    /// A tile for the samples of pixels `[min, max)` (clipped to the film).
    pub fn tile(&self, min: UVec2, max: UVec2) -> FilmTile {
        let size = self.size();
        let block_max = max.min(size);
        let block_min = min.min(block_max);
        let m = UVec2::splat(self.kernel.margin());
        let lo = block_min.saturating_sub(m);
        let hi = (block_max + m).min(size);
        let n = ((hi.x - lo.x) * (hi.y - lo.y)) as usize;
        let stride = self.channels.len() + 1;
        FilmTile {
            block_min,
            block_max,
            min: lo,
            max: hi,
            kernel: self.kernel,
            data: vec![0.0; n * stride],
            stride,
            invalid: 0,
        }
    }

    /// Splits the film into square blocks of `size` pixels, in row-major order: merge the tiles
    /// in this order for a thread-count-independent image.
    pub fn tiles(&self, size: u32) -> Vec<FilmTile> {
        let size = size.max(1);
        let mut out = Vec::new();
        for y in (0..self.height).step_by(size as usize) {
            for x in (0..self.width).step_by(size as usize) {
                out.push(self.tile(UVec2::new(x, y), UVec2::new(x + size, y + size)));
            }
        }
        out
    }

    /// Adds a tile's sums into the film.
    pub fn merge(&mut self, tile: &FilmTile) {
        let tw = tile.max.x - tile.min.x;
        let stride = tile.stride;
        debug_assert_eq!(stride, self.channels.len() + 1, "a tile of another film");
        for y in tile.min.y..tile.max.y {
            for x in tile.min.x..tile.max.x {
                let i = ((y - tile.min.y) * tw + (x - tile.min.x)) as usize * stride;
                let s = &tile.data[i..i + stride];
                let j = (y * self.width + x) as usize * stride;
                let d = &mut self.pixels[j..j + stride];
                for c in 0..stride {
                    d[c] += s[c] as f64;
                }
            }
        }
    }

    /// Every channel: per pixel the filter-weighted mean of its samples (zero where none landed).
    pub fn to_channels(&self) -> ChannelImage {
        let stride = self.channels.len() + 1;
        let n = self.channels.len();
        let mut data = Vec::with_capacity(self.pixels.len() / stride * n);
        for p in self.pixels.chunks_exact(stride) {
            let w = p[n];
            data.extend(p[..n].iter().map(|&v| if w > 0.0 { (v / w) as f32 } else { 0.0 }));
        }
        ChannelImage {
            width: self.width as usize,
            height: self.height as usize,
            names: self.channels.names().to_vec(),
            data,
        }
    }

    /// The image of the channels `R`, `G`, `B`: per pixel the filter-weighted mean of its
    /// samples (black where none landed, or where the film has no such channel).
    pub fn to_image(&self) -> RgbImage {
        self.to_channels().rgb()
    }

    /// The accumulated weight of a pixel (for tests and progress displays).
    pub fn weight(&self, x: u32, y: u32) -> f64 {
        let stride = self.channels.len() + 1;
        self.pixels[(y * self.width + x) as usize * stride + stride - 1]
    }
}

impl FilmTile {
    /// The pixels `[min, max)` whose samples this tile takes.
    pub fn block(&self) -> (UVec2, UVec2) {
        (self.block_min, self.block_max)
    }

    /// Samples with a non-finite component, dropped (Mitsuba warns about them too).
    pub fn invalid_samples(&self) -> u64 {
        self.invalid
    }

    /// Adds a sample of channel values `c` (one per channel of the film, e.g. `[r, g, b]`) at
    /// film position `p` (pixels). Samples outside the tile's block are accepted; only pixels the
    /// tile stores receive them.
    #[inline]
    pub fn add_sample(&mut self, p: Vec2, c: impl AsRef<[f32]>) {
        let c = c.as_ref();
        debug_assert_eq!(c.len() + 1, self.stride, "one value per channel");
        if !c.iter().all(|v| v.is_finite()) {
            self.invalid += 1;
            return;
        }
        if let FilterDesc::Box { radius } = self.kernel.filter
            && radius <= 0.5
        {
            self.add_box_sample(p, radius, c);
        } else {
            self.add_footprint_sample(p, c);
        }
    }

    /// [`Self::add_sample`] through the filter's footprint: every pixel of the tile whose
    /// centre is within the radius, weighted by [`Kernel::eval`] on both axes.
    #[inline]
    fn add_footprint_sample(&mut self, p: Vec2, c: &[f32]) {
        let r = self.kernel.radius;
        // Pixel centres x + ½ with |p − x − ½| ≤ r.
        let x0 = (ceil(p.x - 0.5 - r) as i64).max(self.min.x as i64);
        let x1 = (floor(p.x - 0.5 + r) as i64).min(self.max.x as i64 - 1);
        let y0 = (ceil(p.y - 0.5 - r) as i64).max(self.min.y as i64);
        let y1 = (floor(p.y - 0.5 + r) as i64).min(self.max.y as i64 - 1);
        if x0 > x1 || y0 > y1 {
            return;
        }
        let tw = (self.max.x - self.min.x) as usize;
        let stride = self.stride;
        let nx = (x1 - x0 + 1) as usize;
        let mut stack = [0.0f32; 16];
        let mut heap;
        let wx: &mut [f32] = if nx <= 16 {
            &mut stack[..nx]
        } else {
            heap = vec![0.0f32; nx];
            &mut heap
        };
        for (i, w) in wx.iter_mut().enumerate() {
            *w = self.kernel.eval(p.x - (x0 + i as i64) as f32 - 0.5);
        }
        // The row's pixels x0..=x1 as one slice (the bounds checked once per row).
        let (cx, cy) = (
            (x0 - self.min.x as i64) as usize,
            (y0 - self.min.y as i64) as usize,
        );
        for (j, y) in (y0..=y1).enumerate() {
            let wy = self.kernel.eval(p.y - y as f32 - 0.5);
            if wy == 0.0 {
                continue;
            }
            let at = ((cy + j) * tw + cx) * stride;
            let row = &mut self.data[at..at + nx * stride];
            if let (4, &[r, g, b]) = (stride, c) {
                // Three channels (the RGB film): one pixel's four sums side by side.
                let c = Vec4::new(r, g, b, 1.0);
                for (d, &wxi) in row.as_chunks_mut::<4>().0.iter_mut().zip(wx.iter()) {
                    let w = wxi * wy;
                    if w != 0.0 {
                        *d = (Vec4::from_array(*d) + Vec4::splat(w) * c).to_array();
                    }
                }
            } else {
                for (d, &wxi) in row.chunks_exact_mut(stride).zip(wx.iter()) {
                    let w = wxi * wy;
                    if w == 0.0 {
                        continue;
                    }
                    let (sums, weight) = d.split_at_mut(stride - 1);
                    for (dk, &ck) in sums.iter_mut().zip(c) {
                        *dk += w * ck;
                    }
                    weight[0] += w;
                }
            }
        }
    }

    /// [`Self::add_sample`] under a box of radius r ≤ ½: the one pixel `⌊p⌋` if
    /// `−r ≤ p − ⌊p⌋ − ½ < r` on both axes (the filter's own test), weight 1: what
    /// [`Self::add_footprint_sample`] adds, bit for bit (the unit test below), without its loops.
    #[inline]
    fn add_box_sample(&mut self, p: Vec2, r: f32, c: &[f32]) {
        let (x, y) = (floor(p.x) as i64, floor(p.y) as i64);
        let inside = |d: f32| -r <= d && d < r;
        if !(inside(p.x - x as f32 - 0.5) && inside(p.y - y as f32 - 0.5)) {
            return;
        }
        let (lo, hi) = (self.min.as_i64vec2(), self.max.as_i64vec2());
        if x < lo.x || x >= hi.x || y < lo.y || y >= hi.y {
            return;
        }
        let at = ((y - lo.y) as usize * (hi.x - lo.x) as usize + (x - lo.x) as usize) * self.stride;
        let (sums, weight) = self.data[at..at + self.stride].split_at_mut(self.stride - 1);
        for (dk, &ck) in sums.iter_mut().zip(c) {
            *dk += ck;
        }
        weight[0] += 1.0;
    }
}

/// An image that light paths splat into from any thread (light tracing, see
/// `integrator::caustics`), with sums that do not depend on the order of the splats.
///
/// A splat of colour `c` at film position `p` adds `h_q(p)·c / ∫h_q` to every pixel `q` the
/// filter reaches, where `h_q` is the reconstruction filter centred on `q` and `∫h_q` its
/// integral over the film: the estimate of the same filtered pixel mean the camera samples of
/// [`Film`] compute (they normalize by `Σ w`, whose expectation is that integral).
///
/// Sums are kept in 64-bit fixed point with atomic integer additions: integer addition is
/// associative, so the image is bit-identical whatever the thread count and the order in which
/// splats arrive, without per-thread copies of the image. The unit is 2⁻⁴⁰ (10⁻¹² absolute), so
/// a pixel channel holds sums up to 8·10⁶: callers splat values already divided by the number of
/// light paths, which makes the sums pixel values.
#[derive(Debug)]
pub struct SplatFilm {
    width: u32,
    height: u32,
    kernel: Kernel,
    /// Per column and per row: ∫ of the 1-D filter centred on the pixel over the film.
    norm_x: Vec<f32>,
    norm_y: Vec<f32>,
    /// Values per pixel.
    channels: usize,
    sums: Vec<std::sync::atomic::AtomicI64>,
    dropped: std::sync::atomic::AtomicU64,
}

/// Fixed-point scale of [`SplatFilm`] sums.
const SPLAT_SCALE: f64 = (1u64 << 40) as f64;

impl SplatFilm {
    /// An empty splat image of the film's size and filter, with three channels (`R`, `G`, `B`).
    pub fn new(width: u32, height: u32, filter: FilterDesc) -> Self {
        Self::with_channels(width, height, filter, 3)
    }

    /// An empty splat image with `channels` values per pixel (those of the film it adds to).
    pub fn with_channels(width: u32, height: u32, filter: FilterDesc, channels: usize) -> Self {
        let kernel = Kernel::new(filter);
        let norm = |n: u32| -> Vec<f32> {
            (0..n)
                .map(|i| {
                    let c = i as f64 + 0.5;
                    let (a, b) = (
                        (c - kernel.radius as f64).max(0.0),
                        (c + kernel.radius as f64).min(n as f64),
                    );
                    // Midpoint rule; exact for the box filter away from the film's edges.
                    const STEPS: usize = 1024;
                    let h = (b - a) / STEPS as f64;
                    let s: f64 = (0..STEPS)
                        .map(|k| kernel.eval((a + (k as f64 + 0.5) * h - c) as f32) as f64)
                        .sum();
                    (s * h) as f32
                })
                .collect()
        };
        Self {
            width,
            height,
            norm_x: norm(width),
            norm_y: norm(height),
            kernel,
            channels,
            sums: (0..channels * width as usize * height as usize)
                .map(|_| std::sync::atomic::AtomicI64::new(0))
                .collect(),
            dropped: std::sync::atomic::AtomicU64::new(0),
        }
    }

    /// Adds channel values `c` (e.g. a colour `[r, g, b]`) at film position `p` (pixels), spread
    /// by the filter.
    pub fn splat(&self, p: Vec2, c: impl AsRef<[f32]>) {
        use std::sync::atomic::Ordering::Relaxed;
        let c = c.as_ref();
        debug_assert_eq!(c.len(), self.channels, "one value per channel");
        let limit = (i64::MAX / 4) as f64 / SPLAT_SCALE;
        if !c.iter().all(|v| v.is_finite() && (*v as f64).abs() < limit) {
            self.dropped.fetch_add(1, Relaxed);
            return;
        }
        let r = self.kernel.radius;
        let x0 = (ceil(p.x - 0.5 - r) as i64).max(0);
        let x1 = (floor(p.x - 0.5 + r) as i64).min(self.width as i64 - 1);
        let y0 = (ceil(p.y - 0.5 - r) as i64).max(0);
        let y1 = (floor(p.y - 0.5 + r) as i64).min(self.height as i64 - 1);
        for y in y0..=y1 {
            let wy = self.kernel.eval(p.y - y as f32 - 0.5) / self.norm_y[y as usize];
            if !(wy > 0.0) {
                continue;
            }
            for x in x0..=x1 {
                let w = wy * self.kernel.eval(p.x - x as f32 - 0.5) / self.norm_x[x as usize];
                if !(w > 0.0) {
                    continue;
                }
                let i = self.channels * (y as usize * self.width as usize + x as usize);
                for (k, &v) in c.iter().enumerate() {
                    let q = (w as f64 * v as f64 * SPLAT_SCALE).round() as i64;
                    if q != 0 {
                        self.sums[i + k].fetch_add(q, Relaxed);
                    }
                }
            }
        }
    }

    /// Splats rejected as non-finite or absurdly large.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Adds `scale` × the splat sums to `image` (of the same size; a splat image of three
    /// channels).
    pub fn add_to(&self, image: &mut RgbImage, scale: f64) {
        debug_assert_eq!(self.channels, 3, "an RGB splat image");
        let data = image.data.as_flattened_mut();
        self.add_to_values(data, scale);
    }

    /// Adds `scale` × the splat sums to the channels of `image` (of the same size and channels).
    pub fn add_to_channels(&self, image: &mut ChannelImage, scale: f64) {
        debug_assert_eq!(self.channels, image.names.len(), "the film's channels");
        self.add_to_values(&mut image.data, scale);
    }

    fn add_to_values(&self, data: &mut [f32], scale: f64) {
        use std::sync::atomic::Ordering::Relaxed;
        for (v, s) in data.iter_mut().zip(&self.sums) {
            let s = s.load(Relaxed) as f64 / SPLAT_SCALE;
            *v = (*v as f64 + s * scale) as f32;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gonio_core::rng::Pcg32;

    /// The box's one-pixel path is an optimization of the footprint path: the same sums, bit
    /// for bit, for any position (on and off pixel borders, inside and outside the tile and
    /// the film), tile, radius up to ½ and channel count.
    #[test]
    fn box_one_pixel_path_adds_what_the_footprint_path_adds() {
        let mut rng = Pcg32::new(7, 0);
        for radius in [0.5f32, 0.4, 0.25, 0.01] {
            let mut received = 0;
            for channels in [Channels::rgb(), Channels::rgb().with_layer("depth", &["Z"])] {
                let film = Film::with_channels(9, 7, FilterDesc::Box { radius }, channels);
                for (lo, hi) in [((0, 0), (9, 7)), ((2, 3), (6, 5)), ((8, 6), (9, 7))] {
                    let (lo, hi) = (UVec2::new(lo.0, lo.1), UVec2::new(hi.0, hi.1));
                    let mut one = film.tile(lo, hi);
                    let mut footprint = film.tile(lo, hi);
                    for k in 0..4000 {
                        // Every fourth position on a pixel border or a quarter-pixel grid line.
                        let coord = |rng: &mut Pcg32, k: u32| {
                            let x = rng.next_f32() * 11.0 - 1.0;
                            if k.is_multiple_of(4) {
                                (x * 4.0).round() / 4.0
                            } else {
                                x
                            }
                        };
                        let p = Vec2::new(coord(&mut rng, k), coord(&mut rng, k / 2));
                        let c: Vec<f32> = (0..film.channels().len()).map(|_| rng.next_f32() * 3.0).collect();
                        one.add_box_sample(p, radius, &c);
                        footprint.add_footprint_sample(p, &c);
                    }
                    let bits = |t: &FilmTile| t.data.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&one), bits(&footprint), "radius {radius}, tile {lo}..{hi}");
                    received += one.data.iter().filter(|&&v| v > 0.0).count();
                }
            }
            assert!(received > 0, "radius {radius}: no tile received a sample");
        }
    }
}
