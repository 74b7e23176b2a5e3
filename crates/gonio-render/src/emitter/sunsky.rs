//! `sunsky`: the Hosek–Wilkie sky and sun at infinity (the model is
//! [`gonio_core::sunsky`]; Mitsuba 3.9.1 `src/emitters/sunsky.cpp`).
//!
//! # Mitsuba parameters
//!
//! `turbidity` (1–10, default 3), `albedo` (ground albedo, a spectrum in [0, 1], default 0.3),
//! the sun's place in the sky either from `latitude`, `longitude`, `timezone`, `year`, `month`,
//! `day`, `hour`, `minute`, `second` (defaults: Tokyo, 2010-07-10 15:00) or from
//! `sun_direction` (not both), `sun_scale` and `sky_scale` (default 1), `sun_aperture` (the disk's
//! full angle in degrees, default 0.5358), `complex_sun` (default false) and `to_world` (the sky's
//! local +z is its zenith). The plugin's tables are Mitsuba's own, embedded
//! (`data/sunsky/`, with their licence).
//!
//! # Sampling (ours)
//!
//! Mitsuba samples the sky through a mixture fitted to the model; gonio tabulates it instead: the
//! sky's luminance on a grid of [`SKY_PHI`] azimuths × [`SKY_COS`] values of cos θ over the upper
//! hemisphere (equal solid angles, so the density is the cell's probability × cells/2π), each
//! cell the largest of its centre's and corners' values so that no lit cell is left out. The sun
//! is sampled uniformly in its cone. The two are mixed in proportion to their luminous
//! irradiance (∫Y dω; the sun's taken as its centre's radiance over the whole disk, a little
//! more than a limb-darkened or horizon-cut disk has), so a clear noon sky draws most
//! next-event samples from the sun.
//!
//! `to_world` may scale or shear: directions are mapped by its linear part and normalized (as in
//! Mitsuba), and densities carry the Jacobian |det M| / |M ω|³ of that map.

use crate::tensor_file::TensorFile;
use glam::{Affine3A, Mat3A, Vec2, Vec3, Vec3A};
use gonio_core::color::cie_y;
use gonio_core::sampling::Distribution2D;
use gonio_core::sunsky::{CHANNELS, LAMBDA_FIRST, LAMBDA_STEP, SkyTables, SunSky, SunSkyParams};
use gonio_core::{Frame, SampledSpectrum, SampledWavelengths};
use std::f32::consts::{PI, TAU};
use std::sync::LazyLock;

/// Mitsuba 3.9.1's Hosek–Wilkie tables, spectral fields in `f32` (`data/sunsky/make_data.py`).
static DATA: &[u8] = include_bytes!("../../data/sunsky/sunsky_spectral.bin");

/// The tables read from [`DATA`] once.
struct OwnedTables {
    sky_params: Vec<f32>,
    sky_radiance: Vec<f32>,
    sun_irradiance: Vec<f32>,
    sun_radiance: Vec<f32>,
    sun_limb_darkening: Vec<f32>,
}

static TABLES: LazyLock<Result<OwnedTables, String>> = LazyLock::new(|| {
    let file = TensorFile::parse(DATA).map_err(|e| e.to_string())?;
    let get = |name: &str| file.require(name).map(|f| f.to_f32());
    let t = OwnedTables {
        sky_params: get("sky_params_spec")?,
        sky_radiance: get("sky_rad_spec")?,
        sun_irradiance: get("sun_irradiance")?,
        sun_radiance: get("sun_rad_spec")?,
        sun_limb_darkening: get("sun_ld_spec")?,
    };
    if !t.view().sizes_ok() {
        return Err("the embedded sky tables have the wrong sizes".into());
    }
    Ok(t)
});

impl OwnedTables {
    fn view(&self) -> SkyTables<'_> {
        SkyTables {
            sky_params: &self.sky_params,
            sky_radiance: &self.sky_radiance,
            sun_irradiance: &self.sun_irradiance,
            sun_radiance: &self.sun_radiance,
            sun_limb_darkening: &self.sun_limb_darkening,
        }
    }
}

/// The sky and sun of `params` from the embedded tables.
pub fn model(params: &SunSkyParams) -> Result<SunSky, String> {
    let tables = TABLES.as_ref().map_err(|e| format!("sunsky tables: {e}"))?;
    Ok(SunSky::new(&tables.view(), params))
}

/// Azimuth cells of the sky's sampling table.
pub const SKY_PHI: usize = 256;
/// cos θ cells of the sky's sampling table.
pub const SKY_COS: usize = 128;

/// A `sunsky` emitter.
#[derive(Clone, Debug)]
pub struct SunSkyLight {
    model: SunSky,
    to_world: Mat3A,
    to_local: Mat3A,
    abs_det: f32,
    sky: Distribution2D,
    /// Probability of sampling the sky rather than the sun (0 when the sky is black).
    sky_weight: f32,
    /// Sky and sun are both black (the sun below the horizon, or both scales 0): the light
    /// samples nothing.
    dark: bool,
    /// The sun's frame (local) and its cone's 1 − cos α.
    sun_frame: Frame,
    one_minus_cos_alpha: f32,
    /// Mean radiance over the sphere and 360–830 nm (for light selection).
    mean: f32,
    /// The sky's mean radiance over the upper hemisphere and the sun's irradiance on a surface
    /// facing it (means over 360–830 nm), for [`Self::local_importance`].
    sky_hemisphere_mean: f32,
    sun_irradiance: f32,
    /// Sine of the sun disk's half-angle.
    sin_alpha: f32,
    /// Unit world directions towards the sun and the zenith.
    sun_world: Vec3,
    zenith_world: Vec3,
    /// max L / ∫L dω in luminance (see [`super::Light::feature_density`]).
    feature_density: f32,
}

/// Luminance-like weight of the model's channel values: Σ ȳ(λₖ) Lₖ.
fn luminance(ch: &[f32; CHANNELS]) -> f32 {
    ch.iter()
        .enumerate()
        .map(|(k, &l)| cie_y(LAMBDA_FIRST + LAMBDA_STEP * k as f32) * l)
        .sum()
}

/// The mean over 360–830 nm (1 nm steps) of channel values interpolated linearly in λ, 0 beyond
/// the model's 320–720 nm.
fn visible_mean(ch: &[f32; CHANNELS]) -> f32 {
    let mut acc = 0.0f64;
    for l in 360..=830 {
        let x = (l as f32 - LAMBDA_FIRST) / LAMBDA_STEP;
        if x <= (CHANNELS - 1) as f32 {
            let i = (x as usize).min(CHANNELS - 2);
            let t = x - i as f32;
            acc += ((1.0 - t) * ch[i] + t * ch[i + 1]) as f64;
        }
    }
    (acc / 471.0) as f32
}

impl SunSkyLight {
    /// The light of `model` placed by `to_world` (whose linear part must be invertible).
    pub fn new(model: SunSky, to_world: Affine3A) -> Option<Self> {
        let m = to_world.matrix3;
        let det = m.determinant();
        if !(det.abs() > 0.0) || !det.is_finite() {
            return None;
        }
        // The sky's table: the largest luminance at a cell's centre and corners.
        let dir = |i: f32, j: f32| {
            let phi = TAU * i / SKY_PHI as f32;
            let cos = (j / SKY_COS as f32).min(1.0);
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
        };
        let corner_y: Vec<f32> = (0..=SKY_COS)
            .flat_map(|j| (0..=SKY_PHI).map(move |i| (i, j)))
            .map(|(i, j)| luminance(&model.sky_channels(dir(i as f32, j as f32))))
            .collect();
        let mut cells = vec![0.0f32; SKY_PHI * SKY_COS];
        let mut sky_channels = [0.0f64; CHANNELS];
        let cell_solid = TAU / (SKY_PHI * SKY_COS) as f32;
        for j in 0..SKY_COS {
            for i in 0..SKY_PHI {
                let centre = model.sky_channels(dir(i as f32 + 0.5, j as f32 + 0.5));
                for (acc, c) in sky_channels.iter_mut().zip(centre) {
                    *acc += (c * cell_solid) as f64;
                }
                let c = |di: usize, dj: usize| corner_y[(j + dj) * (SKY_PHI + 1) + i + di];
                cells[j * SKY_PHI + i] = luminance(&centre)
                    .max(c(0, 0))
                    .max(c(1, 0))
                    .max(c(0, 1))
                    .max(c(1, 1));
            }
        }
        let sky_channels = sky_channels.map(|v| v as f32);
        let sky = Distribution2D::new(&cells, SKY_PHI, SKY_COS);
        let sun_radiance = model.sun_channels();
        let one_minus_cos_alpha = model.one_minus_cos_aperture();
        let sun_solid = TAU * one_minus_cos_alpha;
        let sun_channels = sun_radiance.map(|l| l * sun_solid);
        let (sky_y, sun_y) = (luminance(&sky_channels), luminance(&sun_channels));
        let total_y = sky_y + sun_y;
        let sky_weight = if total_y > 0.0 { sky_y / total_y } else { 0.0 };
        let max_sky_y = cells.iter().copied().fold(0.0f32, f32::max);
        let max_y = max_sky_y.max(if sun_y > 0.0 {
            luminance(&sun_radiance)
        } else {
            0.0
        });
        let all: [f32; CHANNELS] = std::array::from_fn(|k| sky_channels[k] + sun_channels[k]);
        let sun_world = Vec3::from(m * Vec3A::from(model.sun_dir())).normalize_or_zero();
        Some(Self {
            sun_frame: Frame::from_normal(model.sun_dir()),
            model,
            to_world: m,
            to_local: m.inverse(),
            abs_det: det.abs(),
            sky,
            sky_weight,
            dark: sky_weight <= 0.0 && sun_radiance.iter().all(|&v| v <= 0.0),
            one_minus_cos_alpha,
            mean: visible_mean(&all) / (4.0 * PI),
            sky_hemisphere_mean: visible_mean(&sky_channels) / TAU,
            sun_irradiance: visible_mean(&sun_channels),
            sin_alpha: (one_minus_cos_alpha * (2.0 - one_minus_cos_alpha))
                .max(0.0)
                .sqrt(),
            sun_world,
            zenith_world: Vec3::from(m * Vec3A::Z).normalize_or_zero(),
            feature_density: if total_y > 0.0 { max_y / total_y } else { 0.0 },
        })
    }

    /// Unit world direction towards the sun's centre.
    pub fn sun_direction(&self) -> Vec3 {
        self.sun_world
    }

    /// Unit world direction of the sky's zenith (the local +z).
    pub fn zenith(&self) -> Vec3 {
        self.zenith_world
    }

    /// The model (local frame).
    pub fn model(&self) -> &SunSky {
        &self.model
    }

    /// The unit direction in the sky's local frame (+z the zenith) of the world direction
    /// `dir` (zero for a zero or NaN one).
    #[inline]
    pub fn local_direction(&self, dir: Vec3) -> Vec3 {
        Vec3::from(self.to_local * Vec3A::from(dir)).normalize_or_zero()
    }

    /// [`Self::local_direction`] of `dir` and |M ω|³/|det M|: the factor taking a local
    /// solid-angle density to the world's.
    #[inline]
    fn local(&self, dir: Vec3) -> (Vec3, f32) {
        let l = self.local_direction(dir);
        let len = Vec3::from(self.to_world * Vec3A::from(l)).length();
        (l, len * len * len / self.abs_det)
    }

    /// Radiance arriving from the world direction `dir` (pointing away from the scene).
    pub fn le(&self, dir: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.model.radiance(self.local_direction(dir), wl)
    }

    /// Local solid-angle density of [`Self::sample_local`] at the unit local direction `l`,
    /// the sun's share counted when `in_sun`.
    fn pdf_local(&self, l: Vec3, in_sun: bool) -> f32 {
        let mut pdf = 0.0;
        if self.sky_weight > 0.0 && l.z >= 0.0 {
            let phi = l.y.atan2(l.x);
            let u = Vec2::new((if phi < 0.0 { phi + TAU } else { phi }) / TAU, l.z);
            pdf += self.sky_weight * self.sky.pdf(u) / TAU;
        }
        if self.sky_weight < 1.0 && in_sun {
            pdf += (1.0 - self.sky_weight) / (TAU * self.one_minus_cos_alpha);
        }
        pdf
    }

    /// A unit local direction, the sky's table or the sun's cone by `u.x` against the sky's
    /// weight (rescaled), and whether it was drawn from the sun.
    fn sample_local(&self, u: Vec2) -> Option<(Vec3, bool)> {
        if self.dark {
            return None;
        }
        if u.x < self.sky_weight {
            let (uv, pdf) = self.sky.sample(Vec2::new(u.x / self.sky_weight, u.y));
            if !(pdf > 0.0) {
                return None;
            }
            let phi = TAU * uv.x;
            let cos = uv.y;
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            Some((Vec3::new(sin * phi.cos(), sin * phi.sin(), cos), false))
        } else {
            let v = ((u.x - self.sky_weight) / (1.0 - self.sky_weight)).min(1.0 - f32::EPSILON / 2.0);
            // Uniform in the cone (pbrt's `SampleUniformCone`) from 1 − cos θ, which keeps the
            // sun's angles: sin θ = √((1 − cos θ)(1 + cos θ)).
            let one_minus = v * self.one_minus_cos_alpha;
            let sin = (one_minus * (2.0 - one_minus)).max(0.0).sqrt();
            let (sp, cp) = (TAU * u.y).sin_cos();
            let local = Vec3::new(sin * cp, sin * sp, 1.0 - one_minus);
            Some((self.sun_frame.to_world(local).normalize(), true))
        }
    }

    /// A world direction towards the light (away from the scene), its solid-angle density and
    /// the radiance arriving from it. A direction drawn from the sun's cone counts as in the
    /// disk whatever rounding does to it on the way to the world and back (as Mitsuba carries
    /// its `hit_sun`); one drawn from the sky is in it if the disk's test says so.
    pub fn sample_dir_le(&self, u: Vec2, wl: &SampledWavelengths) -> Option<(Vec3, f32, SampledSpectrum)> {
        let (l, from_sun) = self.sample_local(u)?;
        let d = Vec3::from(self.to_world * Vec3A::from(l)).normalize_or_zero();
        let (l, jacobian) = self.local(d);
        let in_sun = from_sun || self.model.hits_sun(l);
        let pdf = self.pdf_local(l, in_sun) * jacobian;
        (pdf > 0.0 && pdf.is_finite()).then(|| (d, pdf, self.model.eval(l, wl, in_sun)))
    }

    /// Density of [`Self::sample_dir_le`] for the world direction `dir`.
    pub fn pdf_dir(&self, dir: Vec3) -> f32 {
        let (l, jacobian) = self.local(dir);
        self.pdf_local(l, self.model.hits_sun(l)) * jacobian
    }

    /// [`Self::le`] and [`Self::pdf_dir`] together.
    pub fn le_pdf(&self, dir: Vec3, wl: &SampledWavelengths) -> (SampledSpectrum, f32) {
        let (l, jacobian) = self.local(dir);
        let in_sun = self.model.hits_sun(l);
        (
            self.model.eval(l, wl, in_sun),
            self.pdf_local(l, in_sun) * jacobian,
        )
    }

    /// Mean radiance over the sphere and 360–830 nm.
    pub fn mean_radiance(&self) -> f32 {
        self.mean
    }

    /// An estimate of the irradiance at a surface (light selection's, see
    /// [`super::Light::local_importance`]): the sun's irradiance × `cos_to_sun` (the caller's
    /// cosine towards the disk, widened by its angular radius, [`Self::sin_alpha`]) plus
    /// π × the sky's mean radiance over its hemisphere × `sky_view`, the share of the sky the
    /// surface sees ((1 + cos β)/2 for a normal at β from the zenith: exact for a uniform sky; 1
    /// for a surface that lets light through). Light selection's `π × mean` would give a
    /// quarter of the sun to a surface facing it and as much to one turned away.
    pub fn local_importance(&self, cos_to_sun: f32, sky_view: f32) -> f32 {
        PI * self.sky_hemisphere_mean * sky_view + self.sun_irradiance * cos_to_sun
    }

    /// Sine of the sun disk's half-angle.
    pub fn sin_alpha(&self) -> f32 {
        self.sin_alpha
    }

    /// max L/∫L dω in luminance: the sun's disk, or the sky's brightest cell.
    pub fn feature_density(&self) -> f32 {
        self.feature_density
    }
}
