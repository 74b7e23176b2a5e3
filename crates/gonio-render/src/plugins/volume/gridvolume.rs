//! `gridvolume`: a `.vol` grid placed by `to_world` (Mitsuba 3 `src/volumes/grid.cpp`; lookups
//! and parameter table in [`crate::texture::volume`]).

use crate::geometry::sdfgrid::read_vol;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::WrapMode;
use crate::texture::volume::{GridVolume, Volume, spectral_samples};
use crate::xml::{Builder, ErrorKind, Params, SceneError, err};
use std::sync::Arc;

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the `.vol` grid (1 or 3 channels; 6 for `sggx`), relative to the scene file (required)",
);
const FILTER_TYPE: ParamSpec = ParamSpec::new(
    "filter_type",
    ParamType::String,
    DefaultValue::Str("trilinear"),
    "`trilinear` or `nearest` lookups",
);
const WRAP_MODE: ParamSpec = ParamSpec::new(
    "wrap_mode",
    ParamType::String,
    DefaultValue::Str("clamp"),
    "outside [0, 1]³: `clamp`, `repeat` or `mirror`",
);
const RAW: ParamSpec = ParamSpec::new(
    "raw",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "no colour conversion of 3-channel data (such a grid is no spectrum)",
);
const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "places the grid's unit cube (identity when absent)",
);
const ACCEL: ParamSpec = ParamSpec::new(
    "accel",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "accepted and ignored",
);

/// The `gridvolume` plugin.
pub static PLUGIN: Plugin<Volume> = Plugin {
    name: "gridvolume",
    summary: "A `.vol` grid over the unit cube placed by `to_world`, trilinear or nearest lookups.",
    params: &[FILENAME, FILTER_TYPE, WRAP_MODE, RAW, TO_WORLD, ACCEL],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Volume, SceneError> {
    let Some((name, loc)) = p.string_opt(FILENAME.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "<volume type=\"gridvolume\"> needs a filename",
        ));
    };
    let trilinear = p.choice(
        FILTER_TYPE.name,
        FILTER_TYPE.default.str(),
        &["trilinear", "nearest"],
    )? == "trilinear";
    let wrap = match p.choice(
        WRAP_MODE.name,
        WRAP_MODE.default.str(),
        &["clamp", "repeat", "mirror"],
    )? {
        "repeat" => WrapMode::Repeat,
        "mirror" => WrapMode::Mirror,
        _ => WrapMode::Clamp,
    };
    let raw = p.bool(RAW.name, RAW.default.bool())?;
    let to_world = p.affine(TO_WORLD.name)?;
    p.bool(ACCEL.name, ACCEL.default.bool())?;
    if to_world.matrix3.determinant() == 0.0 || !to_world.is_finite() {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            "<volume type=\"gridvolume\"> has a singular or non-finite to_world",
        ));
    }
    let path = b.resolve_file(p, name);
    let bytes = std::fs::read(&path).map_err(|e| {
        err(
            loc,
            ErrorKind::Io,
            format!("cannot read grid volume \"{name}\" ({}): {e}", path.display()),
        )
    })?;
    let v = read_vol(&bytes)
        .map_err(|e| err(loc, ErrorKind::BadValue, format!("grid volume \"{name}\": {e}")))?;
    if ![1, 3, 6].contains(&v.channels) {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "grid volume \"{name}\" has {} channels; a volume holds 1 or 3 (6: the matrix of an sggx phase function)",
                v.channels
            ),
        ));
    }
    if v.channels == 3 && raw {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "grid volume \"{name}\": 3 channels with raw = true are not a spectrum (Mitsuba refuses to evaluate it as one)"
            ),
        ));
    }
    Ok(Volume::Grid(Arc::new(GridVolume {
        res: v.res,
        channels: v.channels,
        spectra: spectral_samples(&v.data, v.channels, raw),
        data: v.data,
        trilinear,
        wrap,
        raw,
        to_local: to_world.inverse(),
    })))
}
