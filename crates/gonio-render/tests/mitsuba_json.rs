//! Reading the Mitsuba 3.9.1 reference values (`testdata/mitsuba/reference/mitsuba-*-values.json`,
//! each made by the script its test file names): the small accessors every
//! `mitsuba_*_values` test shares.

use glam::{Vec2, Vec3};
use gonio_core::BsdfContext;
use gonio_core::mueller::{Mueller, StokesBasis};
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

/// The transport mode of a row (`"mode": "importance"`, else radiance).
pub fn context(q: &Value) -> BsdfContext {
    if q["mode"] == "importance" {
        BsdfContext::importance()
    } else {
        BsdfContext::radiance()
    }
}

/// A 4 × 4 Mueller matrix written as rows, `M[r][c]`.
pub fn mueller_matrix(v: &Value) -> [[f64; 4]; 4] {
    let mut m = [[0.0; 4]; 4];
    for (r, row) in v.as_array().unwrap().iter().enumerate() {
        for (c, x) in row.as_array().unwrap().iter().enumerate() {
            m[r][c] = x.as_f64().unwrap();
        }
    }
    m
}

/// Largest |Δ| over the elements (first wavelength) relative to the largest |element| of
/// `want`; `shape` divides both by their M00 first.
pub fn mueller_rel_diff(got: &Mueller, want: &[[f64; 4]; 4], shape: bool) -> f64 {
    let g00 = got.get(0, 0)[0] as f64;
    let scale_g = if shape && g00 != 0.0 { 1.0 / g00 } else { 1.0 };
    let scale_w = if shape && want[0][0] != 0.0 {
        1.0 / want[0][0]
    } else {
        1.0
    };
    let big = want
        .iter()
        .flatten()
        .fold(0.0f64, |a, x| a.max((x * scale_w).abs()));
    let mut d = 0.0f64;
    for (r, row) in want.iter().enumerate() {
        for (c, w) in row.iter().enumerate() {
            d = d.max((got.get(r, c)[0] as f64 * scale_g - w * scale_w).abs());
        }
    }
    if big > 0.0 { d / big } else { d }
}

/// Fails unless a framed `m` maps Mitsuba's implicit basis of `light_in` to that of `light_out`
/// (a frame-free matrix passes).
pub fn assert_implicit_bases(m: &Mueller, light_in: Vec3, light_out: Vec3, what: &str) {
    if let Some((i, o)) = m.frames() {
        assert!(
            i.same_as(&StokesBasis::implicit(light_in)) && o.same_as(&StokesBasis::implicit(light_out)),
            "{what}: bases {i:?} → {o:?} are not the implicit bases of {light_in} → {light_out}"
        );
    }
}
