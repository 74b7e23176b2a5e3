//! Textures: spatially varying spectra (`checkerboard`, `bitmap`) and constants, evaluated at a
//! surface's uv.
//!
//! * `checkerboard` (Mitsuba `src/textures/checkerboard.cpp`): after `to_uv`, `color0` where
//!   (u mod 1 > ½) == (v mod 1 > ½), `color1` otherwise; mean ½(color0 + color1).
//! * `bitmap` (Mitsuba `src/textures/bitmap.cpp`): texel (0, 0) is the top-left of the image at
//!   uv = (0, 0) (so row = v·height; OBJ files flip v at load, `flip_tex_coords`). Bilinear
//!   lookups sample at texel centres (uv·size − ½); wrap modes `repeat`, `mirror`, `clamp`.
//!   8-bit images are sRGB-decoded unless `raw`. RGB is uplifted to a spectrum with Jakob &
//!   Hanika's sigmoid polynomials in the role of the parameter (reflectance, emission): with
//!   `nearest` each texel is uplifted once at load; with `bilinear` the interpolated RGB is
//!   uplifted at the hit (Mitsuba interpolates the four texel spectra instead; the two agree at
//!   texel centres and differ by far less than the uplift's own error in between).

use glam::{Affine2, Vec2};
use gonio_core::Spectrum;
use gonio_core::color::luminance;
use gonio_core::hash::mix64;
use gonio_core::math::floor;
use gonio_core::rgb2spec::srgb_to_sigmoid;
use gonio_core::spectra::{RgbKind, RgbSpectrum};
use rayon::prelude::*;
use std::sync::Arc;

pub mod hit;
pub mod volume;

/// A reflectance or radiance that may vary over a surface.
#[derive(Clone, Debug)]
pub enum Texture {
    /// The same spectrum everywhere.
    Spectrum(Spectrum),
    /// Mitsuba `checkerboard`: `color0` where (u mod 1 > ½) == (v mod 1 > ½), else `color1`.
    Checkerboard {
        /// Default 0.4.
        color0: Box<Texture>,
        /// Default 0.2.
        color1: Box<Texture>,
        /// uv transform applied before the lookup.
        to_uv: Affine2,
        /// Mitsuba 3.9.1's float lookup (`eval_1`, `eval_1_grad`): `color0` and `color1`
        /// exchanged against the colour lookup (`float_cells="mitsuba"`, for comparisons).
        float_cells_swapped: bool,
    },
    /// Mitsuba `bitmap`.
    Bitmap(Arc<Bitmap>),
    /// Mitsuba `mesh_attribute`: a vertex or face attribute of the mesh hit ([`hit`]).
    MeshAttribute(Arc<hit::AttributeTexture>),
    /// Mitsuba `volume`: a grid evaluated at the hit's world position ([`volume`]).
    Volume(Arc<volume::GridVolume>),
}

/// Texel lookup for [`Bitmap`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterType {
    /// Bilinear interpolation (default).
    Bilinear,
    /// Nearest texel.
    Nearest,
}

/// What happens outside [0, 1]².
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrapMode {
    /// Tile (default).
    Repeat,
    /// Tile, mirroring every other copy.
    Mirror,
    /// Clamp to the edge texel.
    Clamp,
}

impl WrapMode {
    /// Maps an integer texel index into [0, n).
    #[inline]
    fn wrap(self, i: i64, n: i64) -> usize {
        let r = match self {
            WrapMode::Repeat => gonio_core::math::wrap_repeat(i, n),
            WrapMode::Clamp => i.clamp(0, n - 1),
            WrapMode::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m >= n { 2 * n - 1 - m } else { m }
            }
        };
        r as usize
    }
}

/// A decoded bitmap texture: linear RGB texels, row 0 at the top (v = 0).
#[derive(Clone, Debug)]
pub struct Bitmap {
    width: usize,
    height: usize,
    rgb: Vec<[f32; 3]>,
    /// Per-texel spectra (only for `nearest`).
    texels: Vec<Spectrum>,
    filter: FilterType,
    wrap: WrapMode,
    kind: RgbKind,
    to_uv: Affine2,
    mean: f32,
    max: f32,
}

impl Bitmap {
    /// A bitmap from linear RGB texels (row-major, top row first). `kind` is the role of the
    /// parameter (albedo for reflectances, illuminant for emission). Returns `None` if the size
    /// does not match the data or is zero.
    pub fn new(
        width: usize,
        height: usize,
        rgb: Vec<[f32; 3]>,
        filter: FilterType,
        wrap: WrapMode,
        kind: RgbKind,
        to_uv: Affine2,
    ) -> Option<Self> {
        if width == 0 || height == 0 || rgb.len() != width * height {
            return None;
        }
        let texels = match filter {
            FilterType::Nearest => rgb.iter().map(|&c| uplift(c, kind)).collect(),
            FilterType::Bilinear => Vec::new(),
        };
        let mean = texel_mean(&rgb, kind);
        let m = rgb.iter().fold(0f32, |m, c| m.max(c[0]).max(c[1]).max(c[2]));
        let max = uplift([m; 3], kind).max_value();
        Some(Self {
            width,
            height,
            rgb,
            texels,
            filter,
            wrap,
            kind,
            to_uv,
            mean,
            max,
        })
    }

    /// Width in texels.
    pub fn width(&self) -> usize {
        self.width
    }
    /// Height in texels.
    pub fn height(&self) -> usize {
        self.height
    }
    /// Interpolation.
    pub fn filter(&self) -> FilterType {
        self.filter
    }
    /// Wrapping.
    pub fn wrap(&self) -> WrapMode {
        self.wrap
    }
    /// The uv transform.
    pub fn to_uv(&self) -> Affine2 {
        self.to_uv
    }

    #[inline]
    fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        self.rgb[y * self.width + x]
    }

    /// Linear RGB at `uv` (after `to_uv`), filtered and wrapped.
    pub fn eval_rgb(&self, uv: Vec2) -> [f32; 3] {
        let uv = self.to_uv.transform_point2(uv);
        let (w, h) = (self.width as i64, self.height as i64);
        match self.filter {
            FilterType::Nearest => {
                let (x, y) = self.nearest(uv);
                self.texel(x, y)
            }
            FilterType::Bilinear => {
                let px = uv.x * self.width as f32 - 0.5;
                let py = uv.y * self.height as f32 - 0.5;
                if !(px.is_finite() && py.is_finite()) {
                    return [0.0; 3];
                }
                let (fx, fy) = (floor(px), floor(py));
                let (tx, ty) = (px - fx, py - fy);
                let (x0, y0) = (fx as i64, fy as i64);
                let xs = [self.wrap.wrap(x0, w), self.wrap.wrap(x0 + 1, w)];
                let ys = [self.wrap.wrap(y0, h), self.wrap.wrap(y0 + 1, h)];
                let (c00, c10) = (self.texel(xs[0], ys[0]), self.texel(xs[1], ys[0]));
                let (c01, c11) = (self.texel(xs[0], ys[1]), self.texel(xs[1], ys[1]));
                std::array::from_fn(|i| {
                    let top = c00[i] + tx * (c10[i] - c00[i]);
                    let bottom = c01[i] + tx * (c11[i] - c01[i]);
                    top + ty * (bottom - top)
                })
            }
        }
    }

    fn nearest(&self, uv: Vec2) -> (usize, usize) {
        let (w, h) = (self.width as i64, self.height as i64);
        let fx = floor(uv.x * self.width as f32);
        let fy = floor(uv.y * self.height as f32);
        let x = if fx.is_finite() { fx as i64 } else { 0 };
        let y = if fy.is_finite() { fy as i64 } else { 0 };
        (self.wrap.wrap(x, w), self.wrap.wrap(y, h))
    }

    /// The spectrum at `uv`.
    pub fn eval(&self, uv: Vec2) -> Spectrum {
        match self.filter {
            FilterType::Nearest => {
                let (x, y) = self.nearest(self.to_uv.transform_point2(uv));
                self.texels[y * self.width + x].clone()
            }
            FilterType::Bilinear => uplift(self.eval_rgb(uv), self.kind),
        }
    }

    /// The gradient (∂f/∂u, ∂f/∂v) of the scalar (luminance) lookup at `uv`, as Mitsuba's
    /// `bitmap` gives it (`eval_1_grad`): the partial derivatives of the bilinear interpolation
    /// in texels, scaled by the resolution and taken back through `to_uv` (its transposed
    /// linear part); zero for `nearest`, which is piecewise constant.
    pub fn eval_1_grad(&self, uv: Vec2) -> Vec2 {
        if self.filter == FilterType::Nearest {
            return Vec2::ZERO;
        }
        let st = self.to_uv.transform_point2(uv);
        let px = st.x * self.width as f32 - 0.5;
        let py = st.y * self.height as f32 - 0.5;
        if !(px.is_finite() && py.is_finite()) {
            return Vec2::ZERO;
        }
        let (fx, fy) = (floor(px), floor(py));
        let (tx, ty) = (px - fx, py - fy);
        let (w, h) = (self.width as i64, self.height as i64);
        let (x0, y0) = (fx as i64, fy as i64);
        let xs = [self.wrap.wrap(x0, w), self.wrap.wrap(x0 + 1, w)];
        let ys = [self.wrap.wrap(y0, h), self.wrap.wrap(y0 + 1, h)];
        let f = |x: usize, y: usize| luminance(self.texel(x, y));
        let (f00, f10) = (f(xs[0], ys[0]), f(xs[1], ys[0]));
        let (f01, f11) = (f(xs[0], ys[1]), f(xs[1], ys[1]));
        let df_x = (1.0 - ty) * (f10 - f00) + ty * (f11 - f01);
        let df_y = (1.0 - tx) * (f01 - f00) + tx * (f11 - f10);
        let m = self.to_uv.matrix2;
        let df_uv = Vec2::new(
            m.x_axis.x * df_x + m.x_axis.y * df_y,
            m.y_axis.x * df_x + m.y_axis.y * df_y,
        );
        df_uv * Vec2::new(self.width as f32, self.height as f32)
    }

    /// Mean over the image and the spectrum (Mitsuba's `mean()`: each texel's, averaged), for
    /// the plastics' sampling weight.
    pub fn mean(&self) -> f32 {
        self.mean
    }
}

/// Mitsuba's `mean()` of a bitmap: each texel's uplifted spectrum's mean, averaged (not the
/// spectrum of the mean colour: for two texels (0.2, 0.5, 0.8) and (0.9, 0.1, 0.05) that would be
/// 0.65 where Mitsuba has 0.50). Chunks of a fixed size in parallel, their sums added in order,
/// so the value does not depend on the thread count; within a chunk a small direct-mapped cache
/// skips the uplift of a colour met just before (photographs repeat colours).
fn texel_mean(rgb: &[[f32; 3]], kind: RgbKind) -> f32 {
    const CHUNK: usize = 1 << 16;
    const SLOT_BITS: u32 = 10;
    let partial: Vec<f64> = rgb
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut cache = [([u32::MAX; 3], 0.0f32); 1 << SLOT_BITS];
            let mut sum = 0.0f64;
            for c in chunk {
                let key = c.map(f32::to_bits);
                let h = mix64((((key[0] as u64) << 32) | key[1] as u64) ^ mix64(key[2] as u64));
                let slot = &mut cache[(h >> (64 - SLOT_BITS)) as usize];
                if slot.0 != key {
                    *slot = (key, uplift(*c, kind).mean());
                }
                sum += slot.1 as f64;
            }
            sum
        })
        .collect();
    (partial.iter().sum::<f64>() / rgb.len().max(1) as f64) as f32
}

/// RGB → spectrum in the given role, from the coefficient table without Newton polish: this
/// runs per texel at load (a bitmap's mean, its `nearest` texels) and per hit for bilinear
/// lookups, and the table is within ~2e-3 of the colour, far below 8-bit quantization (the
/// polish costs microseconds a colour: a 2048² normal map took 9 s to load with it). Reflectances
/// are the table's sigmoid of the clamped colour; unbounded values and emission are scaled as
/// Mitsuba's spectral variants store them, 2·max(rgb) times the sigmoid of rgb/(2·max), and
/// emission carries D65 of unit luminance ([`RgbKind::Illuminant`]).
pub fn uplift(rgb: [f32; 3], kind: RgbKind) -> Spectrum {
    match kind {
        RgbKind::Albedo => {
            let rgb = rgb.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) });
            Spectrum::Rgb(RgbSpectrum {
                sigmoid: srgb_to_sigmoid(rgb),
                scale: 1.0,
                kind,
            })
        }
        RgbKind::Unbounded | RgbKind::Illuminant => {
            let rgb = rgb.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
            let m = rgb[0].max(rgb[1]).max(rgb[2]);
            if m <= 0.0 {
                return Spectrum::Constant(0.0);
            }
            let scale = 2.0 * m;
            Spectrum::Rgb(RgbSpectrum {
                sigmoid: srgb_to_sigmoid(rgb.map(|v| v / scale)),
                scale,
                kind,
            })
        }
    }
}

/// An emission texel (an environment map's) from linear sRGB, as Mitsuba's spectral `envmap`
/// uplifts it: [`uplift`] as an illuminant. Negative or non-finite components count as 0.
pub fn uplift_emission_texel(rgb: [f32; 3]) -> Spectrum {
    uplift(rgb, RgbKind::Illuminant)
}

impl Texture {
    /// One colour everywhere, read raw where colours are read (a normal map's constant) and
    /// uplifted as an unbounded colour where a spectrum is needed: a 1 × 1 bitmap.
    pub(crate) fn raw_rgb(c: [f64; 3]) -> Self {
        let texel = Bitmap::new(
            1,
            1,
            vec![c.map(|v| v as f32)],
            FilterType::Nearest,
            WrapMode::Repeat,
            RgbKind::Unbounded,
            glam::Affine2::IDENTITY,
        )
        .expect("one texel");
        Texture::Bitmap(std::sync::Arc::new(texel))
    }

    /// A constant texture.
    pub fn constant(v: f32) -> Self {
        Texture::Spectrum(Spectrum::Constant(v))
    }

    /// The constant spectrum, if the texture does not vary over the surface.
    pub fn as_spectrum(&self) -> Option<&Spectrum> {
        match self {
            Texture::Spectrum(s) => Some(s),
            _ => None,
        }
    }

    /// True when the texture varies over the surface.
    pub fn is_textured(&self) -> bool {
        !matches!(self, Texture::Spectrum(_))
    }

    /// The spectrum at surface coordinates `uv`.
    pub fn eval(&self, uv: Vec2) -> Spectrum {
        match self {
            Texture::Spectrum(s) => s.clone(),
            Texture::Checkerboard {
                color0,
                color1,
                to_uv,
                ..
            } => {
                if checker_is_color0(*to_uv, uv) {
                    color0.eval(uv)
                } else {
                    color1.eval(uv)
                }
            }
            Texture::Bitmap(b) => b.eval(uv),
            Texture::MeshAttribute(a) => a.eval(),
            Texture::Volume(g) => match hit::hit_point() {
                None => Spectrum::Constant(0.0),
                Some(p) if g.channels == 1 => Spectrum::Constant(g.eval(p)[0]),
                Some(p) => uplift(g.eval(p), RgbKind::Unbounded),
            },
        }
    }

    /// A scalar at `uv` (Mitsuba `eval_1`: a blend weight): a constant spectrum's value (or mean),
    /// a bitmap's luminance.
    pub fn eval_1(&self, uv: Vec2) -> f32 {
        match self {
            Texture::Spectrum(s) => s.as_constant().unwrap_or_else(|| s.mean()),
            Texture::Checkerboard {
                color0,
                color1,
                to_uv,
                float_cells_swapped,
            } => {
                if checker_is_color0(*to_uv, uv) != *float_cells_swapped {
                    color0.eval_1(uv)
                } else {
                    color1.eval_1(uv)
                }
            }
            Texture::Bitmap(b) => luminance(b.eval_rgb(uv)),
            Texture::MeshAttribute(a) => a.eval_1(),
            Texture::Volume(g) => hit::hit_point().map_or(0.0, |p| {
                let v = g.eval(p);
                if g.channels == 1 { v[0] } else { luminance(v) }
            }),
        }
    }

    /// Three values at `uv` as Mitsuba's `eval_3` reads them (a normal map): a bitmap's linear
    /// (or `raw`) RGB, a constant's value three times; `None` for a spectrum that is no
    /// constant and for a checkerboard.
    pub fn eval_3(&self, uv: Vec2) -> Option<[f32; 3]> {
        match self {
            Texture::Spectrum(s) => s.as_constant().map(|v| [v; 3]),
            Texture::Bitmap(b) => Some(b.eval_rgb(uv)),
            Texture::Checkerboard { .. } => None,
            Texture::MeshAttribute(a) => Some(a.eval_3()),
            Texture::Volume(g) => Some(hit::hit_point().map_or([0.0; 3], |p| g.eval(p))),
        }
    }

    /// The uv gradient of [`Texture::eval_1`] (Mitsuba `eval_1_grad`, for `bumpmap`): zero for a
    /// constant and inside a checkerboard's cells, the bilinear derivative for a bitmap.
    pub fn eval_1_grad(&self, uv: Vec2) -> Vec2 {
        match self {
            Texture::Bitmap(b) => b.eval_1_grad(uv),
            Texture::Spectrum(_) | Texture::MeshAttribute(_) | Texture::Volume(_) => Vec2::ZERO,
            Texture::Checkerboard {
                color0,
                color1,
                to_uv,
                float_cells_swapped,
            } => {
                if checker_is_color0(*to_uv, uv) != *float_cells_swapped {
                    color0.eval_1_grad(uv)
                } else {
                    color1.eval_1_grad(uv)
                }
            }
        }
    }

    /// Mean over the surface and over 360–830 nm (Mitsuba `Texture::mean`, used by `plastic`).
    pub fn mean(&self) -> f32 {
        match self {
            Texture::Spectrum(s) => s.mean(),
            Texture::Checkerboard { color0, color1, .. } => 0.5 * (color0.mean() + color1.mean()),
            Texture::Bitmap(b) => b.mean(),
            // Mitsuba 3.9.1 has no mean for it (a `plastic` over one fails to load); the value
            // of a colour half-way ([0, 1] after its clamp) stands in. (An area light whose
            // radiance it is averages it over its mesh instead: `emitter::area::surface_mean`.)
            Texture::MeshAttribute(a) => 0.5 * a.scale,
            Texture::Volume(g) => {
                g.data.iter().map(|&v| v as f64).sum::<f64>() as f32 / g.data.len().max(1) as f32
            }
        }
    }

    /// An upper bound of the value (for light power estimates and checks).
    pub fn max_value(&self) -> f32 {
        match self {
            Texture::Spectrum(s) => s.max_value(),
            Texture::Checkerboard { color0, color1, .. } => color0.max_value().max(color1.max_value()),
            Texture::Bitmap(b) => b.max,
            // A colour attribute is clamped to [0, 1]; other attributes are not bounded.
            Texture::MeshAttribute(a) => {
                if a.name.contains("color") {
                    a.scale.abs()
                } else {
                    f32::INFINITY
                }
            }
            Texture::Volume(g) => g.max(),
        }
    }
}

#[inline]
fn checker_is_color0(to_uv: Affine2, uv: Vec2) -> bool {
    let p = to_uv.transform_point2(uv);
    let fx = p.x - floor(p.x);
    let fy = p.y - floor(p.y);
    (fx > 0.5) == (fy > 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression: bitmaps of unbounded values (a raw normal map, η or k) and of emission were
    /// uplifted texel by texel with the Newton polish, microseconds each: a 2048² normal map took
    /// 9 s to load. They now take the table as reflectances do, as Mitsuba stores them, and keep
    /// their colour to the table's accuracy.
    #[test]
    fn unbounded_and_emission_texels_take_the_table_and_keep_their_colour() {
        use gonio_core::color::spectrum_to_linear_srgb;
        for rgb in [
            [0.9, 0.4, 0.1],
            [3.0, 0.5, 0.25],
            [0.02, 0.05, 0.3],
            [0.5, 0.5, 0.5],
        ] {
            let scale = 2.0 * rgb.iter().fold(0.0f32, |m, &v| m.max(v));
            for (kind, polished) in [
                (RgbKind::Unbounded, Spectrum::rgb_unbounded(rgb)),
                (RgbKind::Illuminant, Spectrum::rgb_illuminant(rgb)),
            ] {
                let table = uplift(rgb, kind);
                assert_eq!(
                    table,
                    Spectrum::Rgb(RgbSpectrum {
                        sigmoid: srgb_to_sigmoid(rgb.map(|v| v / scale)),
                        scale,
                        kind,
                    })
                );
                let (a, b) = (
                    spectrum_to_linear_srgb(&table),
                    spectrum_to_linear_srgb(&polished),
                );
                assert!(
                    (a - b).abs().max_element() < 3e-3 * scale,
                    "{kind:?} {rgb:?}: {a} vs {b}"
                );
            }
        }
        assert_eq!(
            uplift([0.0, -1.0, f32::NAN], RgbKind::Unbounded),
            Spectrum::Constant(0.0)
        );
        assert_eq!(
            uplift_emission_texel([2.0, 1.0, 0.5]),
            uplift([2.0, 1.0, 0.5], RgbKind::Illuminant)
        );
    }

    #[test]
    fn the_gradient_of_a_ramp_is_its_slope_in_uv() {
        // Texel i holds i/4 along u: the bilinear lookup rises by 1/4 per texel, 1 per unit of u.
        let rgb: Vec<[f32; 3]> = (0..4).map(|i| [i as f32 / 4.0; 3]).collect();
        let ramp = |to_uv: Affine2, filter: FilterType| {
            Bitmap::new(4, 1, rgb.clone(), filter, WrapMode::Clamp, RgbKind::Albedo, to_uv).unwrap()
        };
        let b = ramp(Affine2::IDENTITY, FilterType::Bilinear);
        let g = b.eval_1_grad(Vec2::new(0.5, 0.5));
        assert!((g - Vec2::new(1.0, 0.0)).length() < 1e-5, "{g:?}");
        // to_uv scaling u by ½ halves the slope per unit of the surface's u (chain rule).
        let b = ramp(Affine2::from_scale(Vec2::new(0.5, 1.0)), FilterType::Bilinear);
        let g = b.eval_1_grad(Vec2::new(1.0, 0.5));
        assert!((g - Vec2::new(0.5, 0.0)).length() < 1e-5, "{g:?}");
        // Nearest lookups are piecewise constant; constants have no gradient.
        let b = ramp(Affine2::IDENTITY, FilterType::Nearest);
        assert_eq!(b.eval_1_grad(Vec2::new(0.5, 0.5)), Vec2::ZERO);
        assert_eq!(
            Texture::constant(0.3).eval_1_grad(Vec2::new(0.5, 0.5)),
            Vec2::ZERO
        );
        assert_eq!(Texture::constant(0.3).eval_3(Vec2::ZERO), Some([0.3; 3]));
    }

    #[test]
    fn wrap_modes() {
        assert_eq!(WrapMode::Repeat.wrap(-1, 4), 3);
        assert_eq!(WrapMode::Repeat.wrap(5, 4), 1);
        assert_eq!(WrapMode::Clamp.wrap(-3, 4), 0);
        assert_eq!(WrapMode::Clamp.wrap(9, 4), 3);
        assert_eq!(WrapMode::Mirror.wrap(4, 4), 3);
        assert_eq!(WrapMode::Mirror.wrap(5, 4), 2);
        assert_eq!(WrapMode::Mirror.wrap(-1, 4), 0);
        assert_eq!(WrapMode::Mirror.wrap(8, 4), 0);
    }

    #[test]
    fn checkerboard_pattern() {
        let t = Texture::Checkerboard {
            color0: Box::new(Texture::constant(0.4)),
            color1: Box::new(Texture::constant(0.2)),
            to_uv: Affine2::from_scale(Vec2::splat(2.0)),
            float_cells_swapped: false,
        };
        // uv (0.1, 0.1) → (0.2, 0.2): both halves ≤ ½ → equal masks → color0.
        assert_eq!(t.eval_1(Vec2::new(0.1, 0.1)), 0.4);
        // (0.3, 0.1) → (0.6, 0.2): masks differ → color1.
        assert_eq!(t.eval_1(Vec2::new(0.3, 0.1)), 0.2);
        assert_eq!(t.eval_1(Vec2::new(0.3, 0.3)), 0.4);
        assert!((t.mean() - 0.3).abs() < 1e-6);
    }

    /// Mitsuba 3.9.1's float lookup of a checkerboard exchanges the cells of its colour lookup
    /// (probed with `mitsuba==3.9.1`, `scalar_spectral`, color0 = 0.05, color1 = 0.8, no
    /// `to_uv`: `eval` / `eval_1` at uv (0.1, 0.1) 0.05 / 0.8, (0.6, 0.1) 0.8 / 0.05,
    /// (0.6, 0.6) 0.05 / 0.8, (0.1, 0.6) 0.8 / 0.05); `float_cells_swapped` reproduces it.
    #[test]
    fn mitsubas_float_lookup_swaps_the_cells() {
        let checker = |float_cells_swapped| Texture::Checkerboard {
            color0: Box::new(Texture::constant(0.05)),
            color1: Box::new(Texture::constant(0.8)),
            to_uv: Affine2::IDENTITY,
            float_cells_swapped,
        };
        let (ours, mitsuba) = (checker(false), checker(true));
        for (uv, eval, eval_1) in [
            ((0.1, 0.1), 0.05, 0.8),
            ((0.6, 0.1), 0.8, 0.05),
            ((0.6, 0.6), 0.05, 0.8),
            ((0.1, 0.6), 0.8, 0.05),
        ] {
            let uv = Vec2::new(uv.0, uv.1);
            assert_eq!(mitsuba.eval(uv).as_constant(), Some(eval));
            assert_eq!(mitsuba.eval_1(uv), eval_1);
            assert_eq!(ours.eval(uv).as_constant(), Some(eval));
            assert_eq!(ours.eval_1(uv), eval);
        }
        assert_eq!(mitsuba.mean(), ours.mean());
    }

    /// A bitmap's mean is Mitsuba 3.9.1's: its texels' means, averaged, not the mean of the
    /// spectrum of the mean colour (`testdata/mitsuba/reference/mitsuba-spot-values.json`,
    /// `bitmaps`; our RGB table differs from Mitsuba's by up to 2 % per wavelength).
    #[test]
    fn bitmap_mean_is_mitsubas_average_of_the_texel_means() {
        let data: serde_json::Value = serde_json::from_str(include_str!(
            "../../../testdata/mitsuba/reference/mitsuba-spot-values.json"
        ))
        .unwrap();
        let bitmaps = data["bitmaps"].as_array().unwrap();
        assert_eq!(bitmaps.len(), 2);
        for b in bitmaps {
            let rgb: Vec<[f32; 3]> = b["texels"]
                .as_array()
                .unwrap()
                .iter()
                .map(|t| {
                    let c: Vec<f32> = t
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|x| x.as_f64().unwrap() as f32)
                        .collect();
                    [c[0], c[1], c[2]]
                })
                .collect();
            let mitsuba = b["mean"].as_f64().unwrap() as f32;
            for filter in [FilterType::Nearest, FilterType::Bilinear] {
                let bm = Bitmap::new(
                    rgb.len(),
                    1,
                    rgb.clone(),
                    filter,
                    WrapMode::Repeat,
                    RgbKind::Albedo,
                    Affine2::IDENTITY,
                )
                .unwrap();
                assert!(
                    (bm.mean() / mitsuba - 1.0).abs() < 5e-3,
                    "{rgb:?}: {} vs Mitsuba's {mitsuba}",
                    bm.mean()
                );
            }
        }
    }

    #[test]
    fn bilinear_interpolates_between_texel_centres() {
        let rgb = vec![[0.0; 3], [1.0; 3]];
        let b = Bitmap::new(
            2,
            1,
            rgb,
            FilterType::Bilinear,
            WrapMode::Clamp,
            RgbKind::Albedo,
            Affine2::IDENTITY,
        )
        .unwrap();
        // Texel centres at u = 0.25 and 0.75.
        assert!((b.eval_rgb(Vec2::new(0.25, 0.5))[0] - 0.0).abs() < 1e-6);
        assert!((b.eval_rgb(Vec2::new(0.75, 0.5))[0] - 1.0).abs() < 1e-6);
        assert!((b.eval_rgb(Vec2::new(0.5, 0.5))[0] - 0.5).abs() < 1e-6);
        // Clamp beyond the edges.
        assert!((b.eval_rgb(Vec2::new(0.0, 0.5))[0] - 0.0).abs() < 1e-6);
        assert!((b.eval_rgb(Vec2::new(1.0, 0.5))[0] - 1.0).abs() < 1e-6);
        // Repeat wraps: u = 0 lies between the last and the first texel.
        let r = Bitmap::new(
            2,
            1,
            vec![[0.0; 3], [1.0; 3]],
            FilterType::Bilinear,
            WrapMode::Repeat,
            RgbKind::Albedo,
            Affine2::IDENTITY,
        )
        .unwrap();
        assert!((r.eval_rgb(Vec2::new(0.0, 0.5))[0] - 0.5).abs() < 1e-6);
    }

    #[test]
    fn nearest_picks_rows_from_the_top() {
        let rgb = vec![[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]; // 1 x 2: top red, bottom blue
        let b = Bitmap::new(
            1,
            2,
            rgb,
            FilterType::Nearest,
            WrapMode::Repeat,
            RgbKind::Albedo,
            Affine2::IDENTITY,
        )
        .unwrap();
        assert_eq!(b.eval_rgb(Vec2::new(0.5, 0.25)), [1.0, 0.0, 0.0]);
        assert_eq!(b.eval_rgb(Vec2::new(0.5, 0.75)), [0.0, 0.0, 1.0]);
        let top = b.eval(Vec2::new(0.5, 0.25));
        // Red reflectance: high at 650 nm, low at 450 nm.
        assert!(top.eval(650.0) > 0.5 && top.eval(450.0) < 0.2);
    }
}
