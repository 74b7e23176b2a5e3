//! The `<spectrum type="…">` objects against Mitsuba 3.9.1 (`scalar_spectral`, each texture's
//! `eval` at single wavelengths, measured 2026-12-06 with `mi.load_dict`), and their refusals.

use gonio_core::Spectrum;
use gonio_render::xml::{SceneError, load_scene_str};
use std::path::PathBuf;

/// Where Mitsuba was evaluated (nm): outside, at and inside the 360–830 nm range.
const LAMBDAS: [f32; 9] = [350.0, 359.9, 360.0, 400.0, 456.0, 550.0, 700.0, 830.0, 840.0];

/// The radiance of an area emitter given as `spectrum` (a `<spectrum name="radiance" …>`).
fn radiance(spectrum: &str) -> Result<Spectrum, SceneError> {
    let text = format!(
        "<scene version=\"3.0.0\"><shape type=\"sphere\"><emitter type=\"area\">{spectrum}</emitter></shape></scene>"
    );
    let s = load_scene_str(&text, PathBuf::from("."), &[])?;
    Ok(s.shapes[0]
        .emitter
        .as_ref()
        .unwrap()
        .radiance
        .as_spectrum()
        .unwrap()
        .clone())
}

fn assert_values(what: &str, s: &Spectrum, expected: &[f32], rel: f32) {
    for (&l, &e) in LAMBDAS.iter().zip(expected) {
        let v = s.eval(l);
        assert!(
            (v - e).abs() <= rel * e.abs() + 1e-6,
            "{what} at {l} nm: {v}, Mitsuba {e}"
        );
    }
}

/// Regression: `blackbody` was pbrt's shape normalized to a peak of 1, so a Mitsuba scene's
/// black-body light rendered about 12 800 times too dark at 5000 K. Mitsuba's is a radiance in
/// W·m⁻²·sr⁻¹·nm⁻¹, 0 outside `wavelength_min`–`wavelength_max`.
#[test]
fn blackbody_is_mitsubas_radiance_per_nanometre() {
    let bb = |params: &str| {
        radiance(&format!(
            "<spectrum name=\"radiance\" type=\"blackbody\"><float name=\"temperature\" value=\"5000\"/>{params}</spectrum>"
        ))
        .unwrap()
    };
    // At 360 and 830 nm (not in the measured set): Planck's law, ends included.
    let planck = |l: f64| (1e-9 * gonio_core::spectra::planck(l, 5000.0)) as f32;
    let (at_360, at_830) = (planck(360.0), planck(830.0));
    let mitsuba = [
        0.0, 0.0, at_360, 8743.565, 10997.899, 12712.999, 11811.964, at_830, 0.0,
    ];
    assert_values("blackbody 5000 K", &bb(""), &mitsuba, 1e-4);
    let band = [0.0, 0.0, 0.0, 8743.565, 10997.899, 12712.999, 11811.964, 0.0, 0.0];
    assert_values(
        "blackbody 400–700 nm",
        &bb("<float name=\"wavelength_min\" value=\"400\"/><float name=\"wavelength_max\" value=\"700\"/>"),
        &band,
        1e-4,
    );
    // Mitsuba 3.9.1 at 3000 K, the range's ends included.
    let cold = radiance(
        "<spectrum name=\"radiance\" type=\"blackbody\"><float name=\"temperature\" value=\"3000\"/></spectrum>",
    )
    .unwrap();
    for (l, e) in [
        (359.9, 0.0),
        (360.0, 32.265572),
        (456.0, 163.48425),
        (830.0, 938.49707),
        (830.1, 0.0),
    ] {
        assert!(
            (cold.eval(l) - e).abs() <= 1e-4 * e,
            "3000 K at {l} nm: {}, Mitsuba {e}",
            cold.eval(l)
        );
    }
    // `scale` (ours) multiplies.
    let twice = bb("<float name=\"scale\" value=\"2\"/>");
    assert!((twice.eval(550.0) - 2.0 * 12712.999).abs() < 0.05);
}

/// `d65` with `color` is Mitsuba's RGB emitter: D65 times the colour's uplift, with scale
/// 2·max(rgb) (so also above 1). Compared as ratios to each one's own D65, whose normalizations
/// differ by 0.1 % (each matches its own CIE tables: white renders as (1, 1, 1) in both).
#[test]
fn d65_color_tints_the_illuminant_as_mitsuba() {
    let white = radiance("<spectrum name=\"radiance\" type=\"d65\"/>").unwrap();
    assert_eq!(white, Spectrum::d65());
    for (rgb, mitsuba) in [
        ("0.5, 0.2, 0.1", [0.097142, 0.115871, 0.216239, 0.35899, 0.801062]),
        (
            "2.5, 0.2, 0.1",
            [0.163213, 0.146292, 0.308498, 1.110155, 4.868635],
        ),
    ] {
        let tinted = radiance(&format!(
            "<spectrum name=\"radiance\" type=\"d65\"><rgb name=\"color\" value=\"{rgb}\"/></spectrum>"
        ))
        .unwrap();
        // Two fits of the same uplift (our coefficient table against Mitsuba's): within 0.2 % of
        // the spectrum's peak.
        let peak = mitsuba.iter().copied().fold(0.0f32, f32::max);
        for (l, e) in [400.0, 456.0, 550.0, 600.0, 700.0].into_iter().zip(mitsuba) {
            let ratio = tinted.eval(l) / white.eval(l);
            assert!(
                (ratio - e).abs() < 2e-3 * peak,
                "d65 × ({rgb}) at {l} nm: {ratio}, Mitsuba {e}"
            );
        }
    }
    let scaled = radiance(
        "<spectrum name=\"radiance\" type=\"d65\"><rgb name=\"color\" value=\"0.5, 0.2, 0.1\"/><float name=\"scale\" value=\"4\"/></spectrum>",
    )
    .unwrap();
    let once = radiance(
        "<spectrum name=\"radiance\" type=\"d65\"><rgb name=\"color\" value=\"0.5, 0.2, 0.1\"/></spectrum>",
    )
    .unwrap();
    assert!((scaled.eval(600.0) - 4.0 * once.eval(600.0)).abs() < 1e-5);
}

/// `regular`, `irregular` and `srgb`, which Mitsuba's own tests and scenes write out in full.
#[test]
fn regular_irregular_and_srgb_match_mitsuba() {
    let regular = radiance(
        "<spectrum name=\"radiance\" type=\"regular\"><float name=\"wavelength_min\" value=\"400\"/><float name=\"wavelength_max\" value=\"700\"/><string name=\"values\" value=\"0.1, 0.2, 0.4\"/></spectrum>",
    )
    .unwrap();
    assert_values(
        "regular",
        &regular,
        &[0.0, 0.0, 0.0, 0.1, 0.137333, 0.2, 0.4, 0.0, 0.0],
        1e-5,
    );
    let irregular = radiance(
        "<spectrum name=\"radiance\" type=\"irregular\"><string name=\"wavelengths\" value=\"400, 500, 700\"/><string name=\"values\" value=\"0.1, 0.2, 0.4\"/></spectrum>",
    )
    .unwrap();
    assert_values(
        "irregular",
        &irregular,
        &[0.0, 0.0, 0.0, 0.1, 0.156, 0.25, 0.4, 0.0, 0.0],
        1e-5,
    );
    let srgb = radiance(
        "<spectrum name=\"radiance\" type=\"srgb\"><rgb name=\"color\" value=\"0.5, 0.2, 0.1\"/></spectrum>",
    )
    .unwrap();
    let mitsuba = [
        0.091932, 0.09227, 0.092275, 0.097142, 0.115871, 0.216239, 0.801062, 0.967355, 0.970838,
    ];
    // Two fits of the same uplift (our coefficient table against Mitsuba's).
    assert_values("srgb", &srgb, &mitsuba, 5e-3);
    assert_eq!(srgb, Spectrum::rgb_albedo([0.5, 0.2, 0.1]));
    // `unbounded`: components above 1 accepted, fitted as the clamped colour (Mitsuba 3.9.1 gives
    // the bounded fit of (1, 0.2, 0.1): 0.308132, 0.112816, 0.214045, 0.990411 at 400, 456,
    // 550, 700 nm).
    let unbounded = radiance(
        "<spectrum name=\"radiance\" type=\"srgb\"><rgb name=\"color\" value=\"2.5, 0.2, 0.1\"/><boolean name=\"unbounded\" value=\"true\"/></spectrum>",
    )
    .unwrap();
    for (l, e) in [
        (400.0, 0.308132),
        (456.0, 0.112816),
        (550.0, 0.214045),
        (700.0, 0.990411),
    ] {
        assert!(
            (unbounded.eval(l) - e).abs() < 5e-3,
            "srgb unbounded at {l} nm: {}, Mitsuba {e}",
            unbounded.eval(l)
        );
    }
}

#[test]
fn spectrum_objects_refuse_bad_values_by_name() {
    for (xml, quoted) in [
        (
            "type=\"blackbody\"><float name=\"temperature\" value=\"5000\"/><float name=\"wavelength_min\" value=\"700\"/><float name=\"wavelength_max\" value=\"400\"/>",
            "400",
        ),
        (
            "type=\"blackbody\"><float name=\"temperature\" value=\"5000\"/><float name=\"wavelength_min\" value=\"nan\"/>",
            "NaN",
        ),
        ("type=\"d65\"><rgb name=\"color\" value=\"1, -1, 0\"/>", "-1"),
        (
            "type=\"d65\"><rgb name=\"color\" value=\"1e39, 0, 0\"/>",
            "invalid color",
        ),
        (
            "type=\"d65\"><rgb name=\"color\" value=\"1e30, 0, 0\"/><float name=\"scale\" value=\"1e30\"/>",
            "beyond single precision",
        ),
        (
            "type=\"srgb\"><rgb name=\"color\" value=\"1.5, 0.2, 0.1\"/>",
            "1.5",
        ),
        ("type=\"srgb\">", "needs a color"),
        (
            "type=\"regular\"><float name=\"wavelength_min\" value=\"400\"/><float name=\"wavelength_max\" value=\"700\"/><string name=\"values\" value=\"0.5\"/>",
            "at least 2",
        ),
        (
            "type=\"regular\"><float name=\"wavelength_min\" value=\"400\"/><string name=\"values\" value=\"0.5, 1\"/>",
            "wavelength_max",
        ),
        (
            "type=\"regular\"><float name=\"wavelength_min\" value=\"400\"/><float name=\"wavelength_max\" value=\"700\"/><string name=\"values\" value=\"0.5, x\"/>",
            "\"x\"",
        ),
        (
            "type=\"irregular\"><string name=\"wavelengths\" value=\"400, 500\"/><string name=\"values\" value=\"1, 2, 3\"/>",
            "2 wavelengths and 3 values",
        ),
        (
            "type=\"irregular\"><string name=\"wavelengths\" value=\"500, 400\"/><string name=\"values\" value=\"1, 2\"/>",
            "increasing",
        ),
        (
            "type=\"irregular\"><string name=\"wavelengths\" value=\"400, 500\"/><string name=\"values\" value=\"1, -2\"/>",
            "-2",
        ),
        (
            "type=\"regular\"><float name=\"wavelength_min\" value=\"400\"/><float name=\"wavelength_max\" value=\"700\"/><string name=\"values\" value=\"1, 1e39\"/>",
            "invalid value 1000000000000000000000000000000000000000",
        ),
    ] {
        let e = radiance(&format!("<spectrum name=\"radiance\" {xml}</spectrum>"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(quoted) && e.contains(":1:"), "{xml}: {e}");
    }
}

/// `rawconstant` (a texture): a number as written, never × D65 even as an emitter's radiance
/// (Mitsuba 3.9.1's `RawConstantTexture`); negative or non-finite values refused by value.
#[test]
fn rawconstant_is_its_value_as_written() {
    let texture = |value: &str| {
        radiance(&format!(
            "<texture name=\"radiance\" type=\"rawconstant\">{value}</texture>"
        ))
    };
    assert_eq!(
        texture("<float name=\"value\" value=\"2.5\"/>").unwrap(),
        Spectrum::Constant(2.5)
    );
    for bad in [
        "<float name=\"value\" value=\"-1\"/>",
        "<float name=\"value\" value=\"inf\"/>",
    ] {
        let e = texture(bad).unwrap_err().to_string();
        assert!(e.contains("invalid value") && e.contains(":1:"), "{bad}: {e}");
    }
    let e = texture("").unwrap_err().to_string();
    assert!(e.contains("needs a value"), "{e}");
}
