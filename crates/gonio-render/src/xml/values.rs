//! Property value syntax: numbers, lists, points, spectra (`λ:v` pairs and `.spd` files) and the
//! look-at transform.

use super::error::{ErrorKind, Location, SceneError};
use glam::{DMat4, DVec3, DVec4};
use std::path::Path;

/// A `<spectrum>` property value: one number, or (λ nm, value) pairs.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum SpecValue {
    /// The same value at every wavelength.
    Uniform(f64),
    /// Linear interpolation between samples, 0 outside (Mitsuba `irregular`).
    Pairs(Vec<(f64, f64)>),
}

fn bad(loc: &Location, msg: String) -> SceneError {
    SceneError::new(loc.clone(), ErrorKind::BadValue, msg)
}

/// A strict integer.
pub(crate) fn parse_int(s: &str, loc: &Location) -> Result<i64, SceneError> {
    s.trim()
        .parse::<i64>()
        .map_err(|_| bad(loc, format!("invalid integer \"{s}\"")))
}

/// A floating-point number.
pub(crate) fn parse_float(s: &str, loc: &Location) -> Result<f64, SceneError> {
    s.trim()
        .parse::<f64>()
        .map_err(|_| bad(loc, format!("invalid number \"{s}\"")))
}

/// Numbers separated by whitespace and/or commas.
pub(crate) fn parse_list(s: &str, loc: &Location) -> Result<Vec<f64>, SceneError> {
    s.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<f64>()
                .map_err(|_| bad(loc, format!("invalid number \"{t}\" in \"{s}\"")))
        })
        .collect()
}

/// Three numbers, or one replicated.
pub(crate) fn parse_vec3(s: &str, loc: &Location) -> Result<DVec3, SceneError> {
    let n = parse_list(s, loc)?;
    match n.as_slice() {
        [x] => Ok(DVec3::splat(*x)),
        [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
        _ => Err(bad(
            loc,
            format!("expected 1 or 3 numbers, found {} in \"{s}\"", n.len()),
        )),
    }
}

/// `"0.5"` (uniform) or `"400:0.56, 500:0.18, …"` (λ in nm : value, strictly increasing λ).
pub(crate) fn parse_spectrum_value(s: &str, loc: &Location) -> Result<SpecValue, SceneError> {
    if !s.contains(':') {
        let n = parse_list(s, loc)?;
        return match n.as_slice() {
            [v] => Ok(SpecValue::Uniform(*v)),
            _ => Err(bad(
                loc,
                format!("a spectrum needs one number or λ:value pairs, found \"{s}\""),
            )),
        };
    }
    let mut pairs = Vec::new();
    for tok in s
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
    {
        let Some((l, v)) = tok.split_once(':') else {
            return Err(bad(loc, format!("invalid λ:value pair \"{tok}\" in \"{s}\"")));
        };
        let l: f64 = l
            .trim()
            .parse()
            .map_err(|_| bad(loc, format!("invalid wavelength \"{l}\" in \"{s}\"")))?;
        let v: f64 = v
            .trim()
            .parse()
            .map_err(|_| bad(loc, format!("invalid value \"{v}\" in \"{s}\"")))?;
        pairs.push((l, v));
    }
    check_pairs(&pairs, loc, s)?;
    Ok(SpecValue::Pairs(pairs))
}

fn check_pairs(pairs: &[(f64, f64)], loc: &Location, what: &str) -> Result<(), SceneError> {
    if pairs.is_empty() {
        return Err(bad(loc, format!("empty spectrum \"{what}\"")));
    }
    if let Some(w) = pairs.windows(2).find(|w| w[1].0 <= w[0].0) {
        return Err(bad(
            loc,
            format!(
                "wavelengths must increase strictly: {} nm follows {} nm in \"{what}\"",
                w[1].0, w[0].0
            ),
        ));
    }
    if let Some(p) = pairs.iter().find(|p| !p.0.is_finite() || !p.1.is_finite()) {
        return Err(bad(
            loc,
            format!("non-finite sample {}:{} in \"{what}\"", p.0, p.1),
        ));
    }
    Ok(())
}

/// Reads a `.spd` file: one "λ value" pair per line (nm), `#` comments.
pub(crate) fn read_spd(path: &Path, written: &str, loc: &Location) -> Result<SpecValue, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        SceneError::new(
            loc.clone(),
            ErrorKind::Io,
            format!(
                "cannot read spectrum file \"{written}\" ({}): {e}",
                path.display()
            ),
        )
    })?;
    let mut pairs = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let n: Vec<f64> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .map(|t| t.parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| {
                bad(
                    loc,
                    format!("spectrum file \"{written}\" line {}: invalid \"{line}\"", i + 1),
                )
            })?;
        if n.len() != 2 {
            return Err(bad(
                loc,
                format!(
                    "spectrum file \"{written}\" line {}: expected \"λ value\", found \"{line}\"",
                    i + 1
                ),
            ));
        }
        pairs.push((n[0], n[1]));
    }
    check_pairs(&pairs, loc, written)?;
    Ok(SpecValue::Pairs(pairs))
}

/// Mitsuba's `coordinate_system(n)`: an orthonormal basis (s, t) around a unit vector
/// (Duff et al. 2017).
pub(crate) fn coordinate_system(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(n.x * n.x * a * sign + 1.0, sign * b, -sign * n.x),
        DVec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// Mitsuba's look-at: dir = normalize(target − origin), left = normalize(up × dir),
/// new_up = dir × left; columns [left, new_up, dir, origin] (camera +x = left, +z = forward).
pub(crate) fn look_at(origin: DVec3, target: DVec3, up: Option<DVec3>) -> Result<DMat4, String> {
    let d = target - origin;
    if d.length_squared() == 0.0 || !d.is_finite() {
        return Err(format!(
            "<lookat> target ({}, {}, {}) equals the origin",
            target.x, target.y, target.z
        ));
    }
    let dir = d.normalize();
    let up = match up {
        Some(u) if u.length_squared() > 0.0 => u,
        _ => coordinate_system(dir).0,
    };
    let left = up.cross(dir);
    if left.length_squared() < 1e-20 {
        return Err(format!(
            "<lookat> up ({}, {}, {}) is parallel to the viewing direction",
            up.x, up.y, up.z
        ));
    }
    let left = left.normalize();
    let new_up = dir.cross(left);
    Ok(DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        DVec4::new(origin.x, origin.y, origin.z, 1.0),
    ))
}
