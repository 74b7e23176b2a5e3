//! The Hosek–Wilkie sky and sun: spectral radiance of a clear sky and of the solar disk.
//!
//! # Formula
//!
//! Sky (Hosek and Wilkie 2012, "An analytic model for full spectral sky-dome radiance", eq. 9),
//! for a view direction at angle θ from the zenith and γ from the sun, at each of the model's
//! eleven wavelengths λₖ = 320, 360, …, 720 nm:
//!
//! ```text
//! L_sky(θ, γ) = (1 + A e^{B/(cos θ + 0.01)}) (C + D e^{Eγ} + F cos²γ + G χ(H, γ) + I √cos θ) · L_M
//! χ(H, γ)    = (1 + cos²γ) / (1 + H² − 2H cos γ)^{3/2}
//! ```
//!
//! The nine coefficients (stored A B C D E F G I H) and the mean radiance L_M are tabulated at
//! ten turbidities T = 1 … 10, two ground albedos (0 and 1) and six control points of a quintic
//! Bézier curve over x = (2η/π)^{1/3} (η the sun's elevation): a sky is the curve at x of the
//! tables interpolated linearly in T and in the albedo. Between the λₖ the radiance is linear in
//! λ; outside 320–720 nm it is 0.
//!
//! Sun (Hosek and Wilkie 2013, "Adding a solar-radiance function to the Hosek–Wilkie skylight
//! model"): a disk of half-angle α (0.2679°) about the sun's direction. By default its radiance is
//! uniform over the disk, the tabulated irradiance E_sun(T, η, λₖ) over the disk's solid angle
//! 2π(1 − cos α₀), α₀ = 0.2679°; a larger or smaller disk (`sun_aperture`) keeps the irradiance.
//! (1 − cos α is computed as 2 sin²(α/2): Mitsuba's `f32` 1 − cos α is off by up to an ulp of
//! the cosine, 0.55 % of the default disk's (0.22 % measured); gonio's sun is the exact
//! E/(2π(1 − cos α)).)
//! With `complex_sun` it is the 2013 paper's radiance: a cubic in the view direction's elevation
//! on each of 45 segments (breaks at (i/45)³·π/2) times the limb darkening Σⱼ cⱼ(λ) cos ψʲ,
//! cos ψ = √(1 − sin²γ / sin²α).
//!
//! Sun position (`latitude`, `longitude`, `timezone`, date and time): Blanco-Muriel et al. 2001,
//! "Computing the solar vector" (Solar Energy 70(5)), with its parallax correction.
//!
//! # Conventions (Mitsuba 3.9.1 `sunsky`)
//!
//! The sky's local frame has +z at the zenith; a direction at azimuth φ is
//! (sin θ cos φ, sin θ sin φ, cos θ). Radiance is in W m⁻² sr⁻¹ nm⁻¹ (the scene in metres).
//! Whatever the view direction, the sky is black when the sun is below the horizon, as in
//! Mitsuba. Arithmetic is `f32` throughout, as in Mitsuba's scalar variants, so that the sun's
//! position agrees with Mitsuba's to its rounding (its Julian date is a `float`, so the ecliptic
//! quantities move in steps of a quarter of a day).
//!
//! | parameter | meaning | Mitsuba default |
//! |---|---|---|
//! | turbidity T | haze, 1 (clear) … 10 | 3 |
//! | albedo | ground albedo per wavelength, in [0, 1] | 0.3 |
//! | sun direction | from the date, time and place, or given | Tokyo, 2010-07-10 15:00 |
//! | `sun_aperture` | the disk's full angle (degrees) | 0.5358 |
//! | `sun_scale`, `sky_scale` | factors on each part | 1, 1 |
//! | `complex_sun` | the 2013 radiance with limb darkening | false |

use crate::spectrum::{N_SPECTRUM_SAMPLES, SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, PI, TAU};

/// The model's wavelengths: λₖ = [`LAMBDA_FIRST`] + k·[`LAMBDA_STEP`], k < [`CHANNELS`].
pub const CHANNELS: usize = 11;
/// The first of the model's wavelengths (nm).
pub const LAMBDA_FIRST: f32 = 320.0;
/// The step between the model's wavelengths (nm).
pub const LAMBDA_STEP: f32 = 40.0;
/// Turbidities tabulated: 1, 2, …, 10.
pub const TURBIDITIES: usize = 10;
/// Ground albedos tabulated: 0 and 1.
pub const ALBEDOS: usize = 2;
/// Control points of the sky's Bézier curve in the sun's elevation.
pub const SKY_CONTROL_POINTS: usize = 6;
/// Coefficients of the sky's formula (A … I).
pub const SKY_PARAMS: usize = 9;
/// Sun elevations of the irradiance table: 2°, 5°, …, 89°.
pub const SUN_ELEVATIONS: usize = 30;
/// Segments of the complex sun's piecewise cubic.
pub const SUN_SEGMENTS: usize = 45;
/// Coefficients of each segment's cubic.
pub const SUN_CONTROL_POINTS: usize = 4;
/// Coefficients of the limb darkening polynomial.
pub const SUN_LD_PARAMS: usize = 6;
/// The disk's half-angle (radians) its tabulated irradiance belongs to (0.5358° across, as
/// Mitsuba's constant and its default `sun_aperture`; its documentation says 0.5338°, its code
/// and renders use 0.5358°).
pub const SUN_HALF_APERTURE: f32 = (std::f64::consts::PI * (0.5 * 0.5358) / 180.0) as f32;

/// The model's tables, as Mitsuba ships them (its `sunsky_datasets.bin` and
/// `sampling_data.bin`, spectral fields), row-major, rounded to `f32` as Mitsuba loads them.
#[derive(Clone, Copy, Debug)]
pub struct SkyTables<'a> {
    /// `sky_params_spec`: (turbidity, albedo, control point, channel, coefficient).
    pub sky_params: &'a [f32],
    /// `sky_rad_spec`: (turbidity, albedo, control point, channel).
    pub sky_radiance: &'a [f32],
    /// `sun_irradiance`: (turbidity, elevation (2° + 3°·i), channel).
    pub sun_irradiance: &'a [f32],
    /// `sun_rad_spec`: (turbidity, segment, channel, power of x).
    pub sun_radiance: &'a [f32],
    /// `sun_ld_spec`: (channel, power of cos ψ).
    pub sun_limb_darkening: &'a [f32],
}

impl SkyTables<'_> {
    /// Whether every table has the model's size.
    pub fn sizes_ok(&self) -> bool {
        self.sky_params.len() == TURBIDITIES * ALBEDOS * SKY_CONTROL_POINTS * CHANNELS * SKY_PARAMS
            && self.sky_radiance.len() == TURBIDITIES * ALBEDOS * SKY_CONTROL_POINTS * CHANNELS
            && self.sun_irradiance.len() == TURBIDITIES * SUN_ELEVATIONS * CHANNELS
            && self.sun_radiance.len() == TURBIDITIES * SUN_SEGMENTS * CHANNELS * SUN_CONTROL_POINTS
            && self.sun_limb_darkening.len() == CHANNELS * SUN_LD_PARAMS
    }
}

/// A place on Earth: degrees north and east, hours ahead of UTC.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Location {
    /// Degrees north.
    pub latitude: f32,
    /// Degrees east.
    pub longitude: f32,
    /// Hours ahead of UTC.
    pub timezone: f32,
}

/// A local date and time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DateTime {
    /// Year.
    pub year: i32,
    /// Month, 1–12.
    pub month: i32,
    /// Day of the month.
    pub day: i32,
    /// Hour (may carry a fraction).
    pub hour: f32,
    /// Minute.
    pub minute: f32,
    /// Second.
    pub second: f32,
}

/// The unit vector at polar angle `theta` from +z and azimuth `phi` from +x.
#[inline]
pub fn sph_to_dir(theta: f32, phi: f32) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(st * cp, st * sp, ct)
}

/// The angle between unit vectors, accurate near 0 and π (2 asin of half the chord).
#[inline]
pub fn unit_angle(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) >= 0.0 {
        2.0 * (0.5 * (a - b).length()).min(1.0).asin()
    } else {
        PI - 2.0 * (0.5 * (a + b).length()).min(1.0).asin()
    }
}

/// The sun's (zenith angle, azimuth) in radians seen from `location` at `t`, the azimuth in
/// the frame of [`sph_to_dir`] (Blanco-Muriel et al. 2001, in `f32` as Mitsuba computes it).
pub fn sun_coordinates(t: &DateTime, location: &Location) -> (f32, f32) {
    // Universal time in decimal hours, and the days since JD 2451545.0 (noon, 1 January 2000).
    let dec_hours = t.hour - location.timezone + (t.minute + t.second / 60.0) / 60.0;
    let aux1 = (t.month - 14) / 12;
    let aux2 = (1461 * (t.year + 4800 + aux1)) / 4 + (367 * (t.month - 2 - 12 * aux1)) / 12
        - (3 * ((t.year + 4900 + aux1) / 100)) / 4
        + t.day
        - 32075;
    let julian_date = aux2 as f32 - 0.5 + dec_hours / 24.0;
    let n = julian_date - 2451545.0;

    // Ecliptic coordinates.
    let omega = 2.1429 - 0.001_039_459_4 * n;
    let mean_longitude = 4.895_063 + 0.017_202_791_698 * n;
    let anomaly = 6.240_06 + 0.017_201_969_9 * n;
    let ecliptic_longitude =
        mean_longitude + 0.033_416_07 * anomaly.sin() + 0.000_348_94 * (2.0 * anomaly).sin()
            - 0.000_113_4
            - 0.000_020_3 * omega.sin();
    let obliquity = 0.409_092_8 - 6.2140e-9 * n + 0.000_039_6 * omega.cos();

    // Celestial coordinates.
    let sin_lon = ecliptic_longitude.sin();
    let mut right_ascension = (obliquity.cos() * sin_lon).atan2(ecliptic_longitude.cos());
    if right_ascension < 0.0 {
        right_ascension += TAU;
    }
    let declination = (obliquity.sin() * sin_lon).asin();

    // Local coordinates.
    let gmst = 6.697_424_3 + 0.065_709_83 * n + dec_hours;
    let lmst = (gmst * 15.0 + location.longitude).to_radians();
    let lat = location.latitude.to_radians();
    let (sin_lat, cos_lat) = lat.sin_cos();
    let hour_angle = lmst - right_ascension;
    let cos_ha = hour_angle.cos();
    let mut zenith = (cos_lat * cos_ha * declination.cos() + declination.sin() * sin_lat).acos();
    let mut azimuth = (-hour_angle.sin()).atan2(declination.tan() * cos_lat - sin_lat * cos_ha);
    if azimuth < 0.0 {
        azimuth += TAU;
    }
    // Parallax.
    zenith += (6371.01f64 / 149_597_890.0) as f32 * zenith.sin();
    (zenith, azimuth - PI)
}

/// Linear interpolation of `n`-element blocks `table[i]`, `table[i + 1]` at a fractional
/// index `x` clamped to the table (`count` blocks).
fn take_interp(table: &[f32], count: usize, x: f32, out: &mut [f32]) {
    let n = out.len();
    let x = x.clamp(0.0, (count - 1) as f32);
    let i = (x as usize).min(count - 2);
    let f = x - i as f32;
    for (k, o) in out.iter_mut().enumerate() {
        let a = table[i * n + k];
        let b = table[(i + 1) * n + k];
        *o = (1.0 - f) * a + f * b;
    }
}

/// The sky's tables interpolated in turbidity, then in albedo per channel, then along the
/// Bézier curve at the sun's elevation `eta`: `per_channel` values for each channel.
fn sky_table<const P: usize>(
    table: &[f32],
    turbidity: f32,
    albedo: &[f32; CHANNELS],
    eta: f32,
) -> [[f32; P]; CHANNELS] {
    let block = ALBEDOS * SKY_CONTROL_POINTS * CHANNELS * P;
    let mut by_albedo = vec![0.0f32; block];
    take_interp(table, TURBIDITIES, turbidity - 1.0, &mut by_albedo);
    let half = block / ALBEDOS;
    // Bézier weights over the control points (Mitsuba clamps x below 1).
    let x = (2.0 * FRAC_1_PI * eta).cbrt().min(1.0 - f32::EPSILON / 2.0);
    const BINOMIAL: [f32; SKY_CONTROL_POINTS] = [1.0, 5.0, 10.0, 10.0, 5.0, 1.0];
    let mut out = [[0.0f32; P]; CHANNELS];
    let mut x_pow = 1.0f32;
    let mut x_pow_inv = (1.0 - x).powi(SKY_CONTROL_POINTS as i32 - 1);
    let inv_scale = 1.0 / (1.0 - x);
    for (c, &binomial) in BINOMIAL.iter().enumerate() {
        let w = binomial * x_pow * x_pow_inv;
        for (ch, row) in out.iter_mut().enumerate() {
            let a = albedo[ch];
            for (p, v) in row.iter_mut().enumerate() {
                let k = (c * CHANNELS + ch) * P + p;
                let lo = by_albedo[k];
                let hi = by_albedo[half + k];
                *v += w * ((1.0 - a) * lo + a * hi);
            }
        }
        x_pow *= x;
        x_pow_inv *= inv_scale;
    }
    out
}

/// A view direction's angles, shared by the channels: θ from the zenith, γ from the sun.
struct ViewAngles {
    cos_theta: f32,
    sqrt_cos_theta: f32,
    gamma: f32,
    cos_gamma: f32,
    cos2_gamma: f32,
}

impl ViewAngles {
    #[inline]
    fn new(sun: Vec3, local: Vec3) -> Self {
        let gamma = unit_angle(sun, local);
        let cos_gamma = gamma.cos();
        Self {
            cos_theta: local.z,
            sqrt_cos_theta: local.z.max(0.0).sqrt(),
            gamma,
            cos_gamma,
            cos2_gamma: cos_gamma * cos_gamma,
        }
    }
}

/// The 2013 sun at a turbidity.
#[derive(Clone, Debug)]
struct ComplexSun {
    /// (segment, channel, power of x).
    cubic: [[[f32; SUN_CONTROL_POINTS]; CHANNELS]; SUN_SEGMENTS],
    /// Limb darkening: (channel, power of cos ψ).
    limb: [[f32; SUN_LD_PARAMS]; CHANNELS],
}

/// The sun's radiance model.
#[derive(Clone, Debug)]
enum SunModel {
    /// Uniform over the disk, per channel.
    Uniform([f32; CHANNELS]),
    /// The 2013 piecewise cubic at the turbidity and the limb darkening coefficients.
    Complex(Box<ComplexSun>),
}

/// The parameters of a sky and sun (see the module's table).
#[derive(Clone, Copy, Debug)]
pub struct SunSkyParams {
    /// Turbidity, in [1, 10].
    pub turbidity: f32,
    /// Ground albedo at the model's wavelengths, each in [0, 1].
    pub albedo: [f32; CHANNELS],
    /// Unit direction towards the sun's centre, in the sky's local frame (+z up).
    pub sun_dir: Vec3,
    /// Half-angle of the sun's disk (radians), in (0, π/2).
    pub sun_half_aperture: f32,
    /// Factor on the sun's radiance.
    pub sun_scale: f32,
    /// Factor on the sky's radiance.
    pub sky_scale: f32,
    /// The 2013 sun radiance with limb darkening instead of a uniform disk.
    pub complex_sun: bool,
}

/// A sky and sun ready to evaluate: the tables reduced to the parameters.
#[derive(Clone, Debug)]
pub struct SunSky {
    params: [[f32; SKY_PARAMS]; CHANNELS],
    radiance: [f32; CHANNELS],
    sun: SunModel,
    sun_dir: Vec3,
    /// 1 − cos α of the disk's half-angle α, computed as 2 sin²(α/2): at the sun's 10⁻⁵ an
    /// `f32` cosine is good to only 0.5 % of it.
    one_minus_cos_aperture: f32,
    sin_sun_aperture: f32,
    /// (1 − cos α₀)/(1 − cos α): the disk's irradiance kept across apertures.
    area_ratio: f32,
    sun_scale: f32,
    sky_scale: f32,
    /// The sun is above the horizon (otherwise everything is black, as in Mitsuba).
    sun_up: bool,
}

impl SunSky {
    /// The sky and sun of `p` from the model's `tables` (which must pass
    /// [`SkyTables::sizes_ok`]).
    pub fn new(tables: &SkyTables<'_>, p: &SunSkyParams) -> Self {
        let sun_dir = p.sun_dir.normalize_or_zero();
        let sun_theta = sun_dir.z.clamp(-1.0, 1.0).acos();
        let eta = FRAC_PI_2 - sun_theta;
        let params = sky_table::<SKY_PARAMS>(tables.sky_params, p.turbidity, &p.albedo, eta);
        let radiance = sky_table::<1>(tables.sky_radiance, p.turbidity, &p.albedo, eta).map(|r| r[0]);
        let sun = if p.complex_sun {
            let mut flat = vec![0.0f32; SUN_SEGMENTS * CHANNELS * SUN_CONTROL_POINTS];
            take_interp(tables.sun_radiance, TURBIDITIES, p.turbidity - 1.0, &mut flat);
            let mut cubic = Box::new([[[0.0f32; SUN_CONTROL_POINTS]; CHANNELS]; SUN_SEGMENTS]);
            for (s, seg) in cubic.iter_mut().enumerate() {
                for (c, ch) in seg.iter_mut().enumerate() {
                    for (k, v) in ch.iter_mut().enumerate() {
                        *v = flat[(s * CHANNELS + c) * SUN_CONTROL_POINTS + k];
                    }
                }
            }
            let mut limb = [[0.0f32; SUN_LD_PARAMS]; CHANNELS];
            for (c, row) in limb.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = tables.sun_limb_darkening[c * SUN_LD_PARAMS + j];
                }
            }
            SunModel::Complex(Box::new(ComplexSun { cubic: *cubic, limb }))
        } else {
            SunModel::Uniform(
                sun_irradiance(tables, p.turbidity, eta).map(|e| e / disk_solid_angle(SUN_HALF_APERTURE)),
            )
        };
        let one_minus = one_minus_cos(p.sun_half_aperture);
        Self {
            params,
            radiance,
            sun,
            sun_dir,
            one_minus_cos_aperture: one_minus,
            sin_sun_aperture: p.sun_half_aperture.sin(),
            area_ratio: (one_minus_cos(SUN_HALF_APERTURE) as f64 / one_minus as f64) as f32,
            sun_scale: p.sun_scale,
            sky_scale: p.sky_scale,
            sun_up: sun_dir.z >= 0.0,
        }
    }

    /// Unit direction towards the sun's centre (local frame).
    pub fn sun_dir(&self) -> Vec3 {
        self.sun_dir
    }

    /// 1 − cos α of the sun disk's half-angle α (accurate; see [`one_minus_cos`]).
    pub fn one_minus_cos_aperture(&self) -> f32 {
        self.one_minus_cos_aperture
    }

    /// Whether `local` (unit, local frame) falls in the sun's disk: 1 − cos γ ≤ 1 − cos α, with
    /// 1 − cos γ = |s − ω|²/2 (accurate at the disk's 10⁻⁵ scale, where a cosine's rounding
    /// is 0.5 % of the disk).
    #[inline]
    pub fn hits_sun(&self, local: Vec3) -> bool {
        0.5 * (self.sun_dir - local).length_squared() <= self.one_minus_cos_aperture
    }

    /// The sky's formula in channel `c` for the view's angles `v` (unscaled).
    #[inline]
    fn sky_channel(&self, c: usize, v: &ViewAngles) -> f32 {
        let p = &self.params[c];
        let c1 = 1.0 + p[0] * (p[1] / (v.cos_theta + 0.01)).exp();
        let h = 1.0 + p[8] * p[8] - 2.0 * p[8] * v.cos_gamma;
        let chi = (1.0 + v.cos2_gamma) / (h * h.sqrt());
        let c2 =
            p[2] + p[3] * (p[4] * v.gamma).exp() + p[5] * v.cos2_gamma + p[6] * chi + p[7] * v.sqrt_cos_theta;
        c1 * c2 * self.radiance[c]
    }

    /// The sun's radiance in channel `c` (disk membership decided by the caller).
    #[inline]
    fn sun_channel(&self, c: usize, cos_theta: f32) -> f32 {
        match &self.sun {
            SunModel::Uniform(l) => l[c],
            SunModel::Complex(sun) => {
                let cubic = &sun.cubic;
                let elevation = FRAC_PI_2 - cos_theta.clamp(-1.0, 1.0).acos();
                let pos = (((2.0 * elevation * FRAC_1_PI).cbrt() * SUN_SEGMENTS as f32).max(0.0) as usize)
                    .min(SUN_SEGMENTS - 1);
                let brk = FRAC_PI_2 * (pos as f32 / SUN_SEGMENTS as f32).powi(3);
                let x = elevation - brk;
                let k = &cubic[pos][c];
                k[0] + x * (k[1] + x * (k[2] + x * k[3]))
            }
        }
    }

    /// Limb darkening at the interpolated channel (1 for the uniform disk).
    #[inline]
    fn limb_darkening(&self, lo: usize, hi: usize, t: f32, gamma: f32) -> f32 {
        match &self.sun {
            SunModel::Uniform(_) => 1.0,
            SunModel::Complex(sun) => {
                let limb = &sun.limb;
                let s = gamma.sin() / self.sin_sun_aperture;
                let cos_psi = (1.0 - s * s).max(0.0).sqrt();
                let mut acc = 0.0;
                let mut pow = 1.0;
                for j in 0..SUN_LD_PARAMS {
                    acc += pow * ((1.0 - t) * limb[lo][j] + t * limb[hi][j]);
                    pow *= cos_psi;
                }
                acc
            }
        }
    }

    /// Radiance arriving from the unit direction `local` (local frame) at the wavelengths `wl`:
    /// sky plus sun, each scaled.
    pub fn radiance(&self, local: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.eval(local, wl, self.hits_sun(local))
    }

    /// [`Self::radiance`] with the disk's membership given (`in_sun`).
    #[inline]
    pub fn eval(&self, local: Vec3, wl: &SampledWavelengths, in_sun: bool) -> SampledSpectrum {
        self.eval_parts(local, wl, in_sun, self.sky_scale, self.sun_scale)
    }

    fn eval_parts(
        &self,
        local: Vec3,
        wl: &SampledWavelengths,
        in_sun: bool,
        sky: f32,
        sun: f32,
    ) -> SampledSpectrum {
        let cos_theta = local.z;
        // A zero direction (a NaN one normalized) lights nothing.
        if !(cos_theta >= 0.0) || !self.sun_up || !(local.length_squared() > 0.5) {
            return SampledSpectrum::ZERO;
        }
        let view = ViewAngles::new(self.sun_dir, local);
        let gamma = view.gamma;
        let mut out = [0.0f32; N_SPECTRUM_SAMPLES];
        for (i, o) in out.iter_mut().enumerate() {
            let x = (wl.lambda(i) - LAMBDA_FIRST) / LAMBDA_STEP;
            if !(0.0..=(CHANNELS - 1) as f32).contains(&x) {
                continue;
            }
            let lo = (x as usize).min(CHANNELS - 2);
            let hi = lo + 1;
            let t = x - lo as f32;
            let mut v = 0.0;
            if sky > 0.0 {
                let a = self.sky_channel(lo, &view);
                let b = self.sky_channel(hi, &view);
                v += sky * ((1.0 - t) * a + t * b);
            }
            if in_sun && sun > 0.0 {
                let a = self.sun_channel(lo, cos_theta);
                let b = self.sun_channel(hi, cos_theta);
                v += sun * ((1.0 - t) * a + t * b) * self.limb_darkening(lo, hi, t, gamma) * self.area_ratio;
            }
            *o = v;
        }
        SampledSpectrum::new(out)
    }

    /// The sky's radiance (scaled) in each model channel towards `local`: what a luminance
    /// table for sampling is made of.
    pub fn sky_channels(&self, local: Vec3) -> [f32; CHANNELS] {
        if !(local.z >= 0.0) || !self.sun_up {
            return [0.0; CHANNELS];
        }
        let v = ViewAngles::new(self.sun_dir, local);
        std::array::from_fn(|c| self.sky_scale * self.sky_channel(c, &v))
    }

    /// The sun disk's mean radiance (scaled) in each model channel, for sampling weights: the
    /// uniform disk's value, or the complex sun's at the disk's centre.
    pub fn sun_channels(&self) -> [f32; CHANNELS] {
        if !self.sun_up {
            return [0.0; CHANNELS];
        }
        let gamma = 0.0;
        std::array::from_fn(|c| {
            self.sun_scale
                * self.sun_channel(c, self.sun_dir.z)
                * self.limb_darkening(c, c, 0.0, gamma)
                * self.area_ratio
        })
    }
}

/// 1 − cos `alpha` as 2 sin²(`alpha`/2), in `f64`: accurate for the small angles where
/// 1 − cos in `f32` loses most of its digits (the sun's half-angle: 10⁻⁵, an ulp of the cosine
/// 0.5 % of it).
#[inline]
pub fn one_minus_cos(alpha: f32) -> f32 {
    let s = (0.5 * alpha as f64).sin();
    (2.0 * s * s) as f32
}

/// Solid angle of a cone of half-angle `alpha`: 2π(1 − cos α).
#[inline]
pub fn disk_solid_angle(alpha: f32) -> f32 {
    TAU * one_minus_cos(alpha)
}

/// The sun's irradiance per channel at turbidity `turbidity` and elevation `eta` (radians):
/// the table interpolated linearly in both (elevations 2° + 3°·i, clamped to the table).
fn sun_irradiance(tables: &SkyTables<'_>, turbidity: f32, eta: f32) -> [f32; CHANNELS] {
    let mut by_t = vec![0.0f32; SUN_ELEVATIONS * CHANNELS];
    take_interp(tables.sun_irradiance, TURBIDITIES, turbidity - 1.0, &mut by_t);
    let x = ((eta.to_degrees() - 2.0) / 3.0).clamp(0.0, SUN_ELEVATIONS as f32 - (1.0 - f32::EPSILON / 2.0));
    let mut out = [0.0f32; CHANNELS];
    take_interp(&by_t, SUN_ELEVATIONS, x, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_angle_matches_acos_away_from_the_ends() {
        let a = Vec3::new(0.3, -0.4, 0.866).normalize();
        let b = Vec3::new(-0.5, 0.1, 0.2).normalize();
        assert!((unit_angle(a, b) - a.dot(b).acos()).abs() < 1e-6);
        assert!((unit_angle(a, -a) - PI).abs() < 1e-6);
        assert_eq!(unit_angle(a, a), 0.0);
    }

    #[test]
    fn one_minus_cos_keeps_its_digits_at_the_suns_size() {
        for deg in [0.01f32, 0.2679, 1.0, 10.0, 60.0] {
            let a = deg.to_radians();
            let exact = 1.0 - (a as f64).cos();
            let rel = (one_minus_cos(a) as f64 - exact).abs() / exact;
            assert!(rel < 2e-7, "{deg}°: relative error {rel:e}");
        }
    }

    #[test]
    fn solar_noon_at_the_equinox_is_overhead_at_the_equator() {
        // 2010-03-20 12:00 UTC on the Greenwich meridian at the equator: the sun within the
        // equation of time (≈ 7.5 min, ≈ 2°) and the declination (≈ 0.1°) of the zenith.
        let t = DateTime {
            year: 2010,
            month: 3,
            day: 20,
            hour: 12.0,
            minute: 0.0,
            second: 0.0,
        };
        let loc = Location {
            latitude: 0.0,
            longitude: 0.0,
            timezone: 0.0,
        };
        let (zenith, _) = sun_coordinates(&t, &loc);
        assert!(zenith.to_degrees() < 2.5, "zenith {}°", zenith.to_degrees());
    }
}
