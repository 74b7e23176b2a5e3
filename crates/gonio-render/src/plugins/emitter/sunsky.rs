//! `sunsky`: the Hosek–Wilkie sky and sun (Mitsuba 3.9.1 `src/emitters/sunsky.cpp`; the model
//! is [`gonio_core::sunsky`], the light [`crate::emitter::SunSkyLight`]).

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::EmitterDesc;
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use glam::{Vec3, Vec3A};
use gonio_core::spectra::RgbKind;
use gonio_core::sunsky::{
    CHANNELS, DateTime, LAMBDA_FIRST, LAMBDA_STEP, Location, SunSkyParams, sph_to_dir, sun_coordinates,
};

const TURBIDITY: ParamSpec = ParamSpec::new(
    "turbidity",
    ParamType::Float,
    DefaultValue::Float(3.0),
    "atmospheric turbidity, in [1, 10] (3: a clear sky in a temperate climate)",
);
const ALBEDO: ParamSpec = ParamSpec::new(
    "albedo",
    ParamType::Spectrum,
    DefaultValue::Float(0.3),
    "ground albedo, in [0, 1] at each of the model's wavelengths (320–720 nm)",
);
const LATITUDE: ParamSpec = ParamSpec::new(
    "latitude",
    ParamType::Float,
    DefaultValue::Float(35.6894),
    "the observer's latitude, degrees north (default: Tokyo)",
);
const LONGITUDE: ParamSpec = ParamSpec::new(
    "longitude",
    ParamType::Float,
    DefaultValue::Float(139.6917),
    "the observer's longitude, degrees east",
);
const TIMEZONE: ParamSpec = ParamSpec::new(
    "timezone",
    ParamType::Float,
    DefaultValue::Float(9.0),
    "hours ahead of UTC",
);
const YEAR: ParamSpec = ParamSpec::new("year", ParamType::Integer, DefaultValue::Int(2010), "year");
const MONTH: ParamSpec = ParamSpec::new("month", ParamType::Integer, DefaultValue::Int(7), "month, 1–12");
const DAY: ParamSpec = ParamSpec::new(
    "day",
    ParamType::Integer,
    DefaultValue::Int(10),
    "day of the month (any integer: the date runs on, as in Mitsuba)",
);
const HOUR: ParamSpec = ParamSpec::new("hour", ParamType::Float, DefaultValue::Float(15.0), "local hour");
const MINUTE: ParamSpec = ParamSpec::new("minute", ParamType::Float, DefaultValue::Float(0.0), "minute");
const SECOND: ParamSpec = ParamSpec::new("second", ParamType::Float, DefaultValue::Float(0.0), "second");
const SUN_DIRECTION: ParamSpec = ParamSpec::new(
    "sun_direction",
    ParamType::Point,
    DefaultValue::None,
    "world direction towards the sun, instead of the place, date and time (not with them)",
);
const SUN_SCALE: ParamSpec = ParamSpec::new(
    "sun_scale",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "factor on the sun's radiance (0 turns the sun off)",
);
const SKY_SCALE: ParamSpec = ParamSpec::new(
    "sky_scale",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "factor on the sky's radiance (0 turns the sky off)",
);
const SUN_APERTURE: ParamSpec = ParamSpec::new(
    "sun_aperture",
    ParamType::Float,
    DefaultValue::Float(0.5358),
    "the sun disk's full angle in degrees, in [1e-6, 180); the sun's irradiance is kept (Mitsuba's documentation says 0.5338, its code uses 0.5358)",
);
const COMPLEX_SUN: ParamSpec = ParamSpec::new(
    "complex_sun",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "the sun's radiance with limb darkening (Hosek and Wilkie 2013) instead of a uniform disk",
);
const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "sky to world: the sky's local +z is the zenith",
);

/// The parameters that place the sun by date, time and place.
const TIME_AND_PLACE: [&ParamSpec; 9] = [
    &LATITUDE, &LONGITUDE, &TIMEZONE, &YEAR, &MONTH, &DAY, &HOUR, &MINUTE, &SECOND,
];

/// The `sunsky` plugin.
pub static PLUGIN: Plugin<EmitterDesc> = Plugin {
    name: "sunsky",
    summary: "Hosek–Wilkie sky and sun (spectral, W m⁻² sr⁻¹ nm⁻¹; the scene in metres).",
    params: &[
        TURBIDITY,
        ALBEDO,
        LATITUDE,
        LONGITUDE,
        TIMEZONE,
        YEAR,
        MONTH,
        DAY,
        HOUR,
        MINUTE,
        SECOND,
        SUN_DIRECTION,
        SUN_SCALE,
        SKY_SCALE,
        SUN_APERTURE,
        COMPLEX_SUN,
        TO_WORLD,
        super::MEDIUM,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<EmitterDesc, SceneError> {
    let turbidity = p.float_checked(
        TURBIDITY.name,
        TURBIDITY.default.float(),
        |v| (1.0..=10.0).contains(&v),
        "must be in [1, 10]",
    )? as f32;
    let non_negative = |v: f64| v >= 0.0;
    let sun_scale = p.float_checked(SUN_SCALE.name, 1.0, non_negative, "must be non-negative")? as f32;
    let sky_scale = p.float_checked(SKY_SCALE.name, 1.0, non_negative, "must be non-negative")? as f32;
    // Above 1e-6°, so that 1 − cos of the half-angle (≈ 10⁻¹⁶) is a normal float and the sun's
    // radiance E/(2π(1 − cos α)) finite.
    let aperture = p.float_checked(
        SUN_APERTURE.name,
        SUN_APERTURE.default.float(),
        |v| (1e-6..180.0).contains(&v),
        "must be in [1e-6, 180) degrees",
    )? as f32;
    let complex_sun = p.bool(COMPLEX_SUN.name, false)?;
    let to_world = p.affine(TO_WORLD.name)?;
    let obj = p.obj;
    let albedo_loc = obj
        .props
        .iter()
        .find(|q| q.name == ALBEDO.name)
        .map_or(&obj.loc, |q| &q.value_loc);
    let albedo_spectrum = b.spectrum(p, &ALBEDO, RgbKind::Albedo)?;
    let albedo: [f32; CHANNELS] =
        std::array::from_fn(|k| albedo_spectrum.eval(LAMBDA_FIRST + LAMBDA_STEP * k as f32));
    if let Some(a) = albedo.iter().find(|a| !(0.0..=1.0).contains(*a)) {
        return Err(err(
            albedo_loc,
            ErrorKind::BadValue,
            format!("invalid albedo {a} in <emitter type=\"sunsky\"> (must be in [0, 1] at 320–720 nm)"),
        ));
    }
    let singular = || {
        err(
            &obj.loc,
            ErrorKind::BadValue,
            "singular (or overflowing) to_world in <emitter type=\"sunsky\">",
        )
    };
    let det = to_world.matrix3.determinant();
    if !(det.abs() > 0.0) || !det.is_finite() {
        return Err(singular());
    }
    let to_local = to_world.matrix3.inverse();

    let sun_dir_local = if let Some((d, loc)) = p.point_opt(SUN_DIRECTION.name)? {
        if let Some(other) = TIME_AND_PLACE.iter().find(|s| p.has(s.name)) {
            return Err(err(
                loc,
                ErrorKind::Grammar,
                format!(
                    "give either sun_direction or the place and time ({} …) of <emitter type=\"sunsky\">, not both",
                    other.name
                ),
            ));
        }
        let d = d.as_vec3();
        if !d.is_finite() || !(d.length_squared() > 0.0) {
            return Err(err(
                loc,
                ErrorKind::BadValue,
                format!("invalid sun_direction {d} (must be finite and non-zero)"),
            ));
        }
        Vec3::from(to_local * Vec3A::from(d.normalize())).normalize()
    } else {
        let f = |p: &mut Params<'d>, s: &ParamSpec| -> Result<f32, SceneError> {
            Ok(p.float_checked(s.name, s.default.float(), |_| true, "must be finite")? as f32)
        };
        let latitude = p.float_checked(
            LATITUDE.name,
            LATITUDE.default.float(),
            |v| (-90.0..=90.0).contains(&v),
            "must be in [-90, 90]",
        )? as f32;
        let location = Location {
            latitude,
            longitude: f(p, &LONGITUDE)?,
            timezone: f(p, &TIMEZONE)?,
        };
        let time = DateTime {
            year: p.int_in(YEAR.name, 2010, -100_000, 100_000)? as i32,
            month: p.int_in(MONTH.name, 7, 1, 12)? as i32,
            // Any day: the Julian date is linear in it (day 200 of January is in July), as in
            // Mitsuba.
            day: p.int_in(DAY.name, 10, -1_000_000, 1_000_000)? as i32,
            hour: f(p, &HOUR)?,
            minute: f(p, &MINUTE)?,
            second: f(p, &SECOND)?,
        };
        let (theta, phi) = sun_coordinates(&time, &location);
        if !theta.is_finite() || !phi.is_finite() {
            return Err(err(
                &obj.loc,
                ErrorKind::BadValue,
                format!(
                    "the sun's position at {}-{}-{} {}:{}:{} (timezone {}) is not a number: the date and time are out of range",
                    time.year, time.month, time.day, time.hour, time.minute, time.second, location.timezone
                ),
            ));
        }
        // Mitsuba places the sun in the world by to_world and reads it back through the inverse.
        let world = Vec3::from(to_world.matrix3 * Vec3A::from(sph_to_dir(theta, phi)));
        Vec3::from(to_local * Vec3A::from(world)).normalize()
    };
    if !sun_dir_local.is_finite() {
        return Err(singular());
    }
    Ok(EmitterDesc::SunSky {
        params: SunSkyParams {
            turbidity,
            albedo,
            sun_dir: sun_dir_local,
            sun_half_aperture: (0.5 * aperture).to_radians(),
            sun_scale,
            sky_scale,
            complex_sun,
        },
        to_world,
    })
}
