//! Reading the Mitsuba 3.9.1 reference values (`testdata/mitsuba/reference/mitsuba-*-values.json`,
//! each made by the script its test file names): the small accessors every
//! `mitsuba_*_values` test shares.

use glam::{Vec2, Vec3};
use serde_json::Value;

/// The JSON text of a reference file (`include_str!` of it).
pub fn parse(text: &str) -> Value {
    serde_json::from_str(text).expect("reference JSON parses")
}

/// A JSON array of numbers as `f32`s.
pub fn floats(v: &Value) -> Vec<f32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect()
}

/// A direction or point written `[x, y, z]`.
pub fn vec3(v: &Value) -> Vec3 {
    let a = floats(v);
    Vec3::new(a[0], a[1], a[2])
}

/// A uv written `[u, v]`.
pub fn vec2(v: &Value) -> Vec2 {
    let a = floats(v);
    Vec2::new(a[0], a[1])
}

/// The number under `key` (a missing key fails the test by name).
pub fn num(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("missing {key}"))
}

/// The uv at which gonio's checkerboard gives what Mitsuba 3.9.1's `eval_1` (the float a
/// roughness texture reads) gives at `uv`: Mitsuba's `eval_1` answers with the other cell than
/// its `eval`, so a configuration whose roughness is a checkerboard is queried half a period
/// over in u. `swapped` says whether the configuration's roughness is such a texture.
pub fn mitsuba_eval_1_uv(swapped: bool, uv: Vec2) -> Vec2 {
    if swapped { uv + Vec2::new(0.5, 0.0) } else { uv }
}
