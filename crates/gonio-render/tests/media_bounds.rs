//! Where a heterogeneous medium is: inside the world-axis-aligned bounds of its extinction
//! volume's unit cube under `to_world` (Mitsuba 3.9.1's `Volume::bbox`), for a number the unit
//! cube, for a turned grid with clamped lookups in the corners of its bounds; a constant there
//! is the homogeneous medium of the box, its free flights drawn exactly.

use crate::media::{meter, meter_mean};
use std::path::PathBuf;

/// A `volpath` scene of a radiance meter at (x, y, 5) looking down −z under a unit sky, with
/// `body` (the media and shapes).
fn meter_scene((x, y): (f32, f32), body: &str) -> String {
    format!(
        r#"<scene version="3.0.0"><integrator type="volpath"/>
        <sensor type="radiancemeter">
            <point name="origin" x="{x}" y="{y}" z="5"/><vector name="direction" x="0" y="0" z="-1"/>
            <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/><rfilter type="box"/></film>
        </sensor>
        <emitter type="constant"><float name="radiance" value="1"/></emitter>
        {body}
        </scene>"#
    )
}

/// A heterogeneous medium given a number is that extinction inside the unit cube and empty
/// outside (Mitsuba 3.9.1: the medium is where its `sigma_t` volume's box is; probed on a cube
/// [−2, 2]³ holding it, seen along −z: 0.31 through the unit cube, 1 elsewhere), a
/// `constvolume` the same inside the axis-aligned bounds of its `to_world`'s unit cube (probed
/// with a 45° turn about z: Mitsuba's transmittance is the same inside and outside the turned
/// cube within its bounds), and a grid too.
#[test]
fn a_heterogeneous_constant_extinction_fills_its_volumes_box() {
    let scene = |sigma_t: &str, at: (f32, f32)| {
        meter_scene(
            at,
            &format!(
                r#"<medium type="heterogeneous" id="m">{sigma_t}<float name="albedo" value="0"/></medium>
                <shape type="cube"><transform name="to_world"><scale value="2"/></transform>
                    <bsdf type="null"/><ref name="interior" id="m"/></shape>"#
            ),
        )
    };
    let number = r#"<float name="sigma_t" value="1"/>"#;
    let placed = r#"<volume name="sigma_t" type="constvolume"><float name="value" value="0.5"/>
        <transform name="to_world"><scale value="4"/><translate x="-2" y="-2" z="-2"/></transform></volume>"#;
    let turned = r#"<volume name="sigma_t" type="constvolume"><float name="value" value="1"/>
        <transform name="to_world"><rotate z="1" angle="45"/></transform></volume>"#;
    // Through the unit cube: T = exp(−1); beside it, inside the cube: 1; the placed volume
    // fills the cube: exp(−0.5 · 4); the turned cube's bounds, outside the turned cube: exp(−1).
    // A turned grid (`testdata/sggx/density.vol`: 4 everywhere) fills the same bounds, read
    // with clamped lookups outside the turned cube (Mitsuba 3.9.1, probed at 256 spp: 0.025 at
    // (0.5, 0.2), 0.99 at (0.8, 0.2), against exp(−4) = 0.018 and 1).
    let grid_file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/sggx/density.vol");
    let turned_grid = format!(
        r#"<volume name="sigma_t" type="gridvolume"><string name="filename" value="{}"/>
        <transform name="to_world"><rotate z="1" angle="45"/></transform></volume>"#,
        grid_file.display()
    );
    // Tolerances: the sky's spectral estimate (3e-3) where the transmittance is exact (a
    // constant), four standard errors of ratio tracking's 0/1 estimate through the grid
    // (σ = σ̄), √((1 − T)/(T·N)) relative.
    let n = 1 << 16;
    let tracked = |t: f64| 4.0 * ((1.0 - t) / (t * n as f64)).sqrt();
    let e4 = (-4.0f64).exp();
    let cases = [
        (number, (0.5, 0.5), (-1.0f64).exp(), 3e-3),
        (number, (-1.0, -1.0), 1.0, 3e-3),
        (placed, (-1.0, -1.0), (-2.0f64).exp(), 3e-3),
        (turned, (0.5, 0.2), (-1.0f64).exp(), 3e-3),
        (turned, (0.8, 0.2), 1.0, 3e-3),
        (turned_grid.as_str(), (0.5, 0.2), e4, tracked(e4)),
        (turned_grid.as_str(), (0.0, 0.5), e4, tracked(e4)),
        (turned_grid.as_str(), (0.8, 0.2), 1.0, 3e-3),
    ];
    for (sigma_t, at, t, tol) in cases {
        let v = meter(&scene(sigma_t, at), n, 1);
        for c in 0..3 {
            assert!(
                (v[c] as f64 / t - 1.0).abs() < tol,
                "{sigma_t} at {at:?}: {v:?} against {t}"
            );
        }
    }
}

/// A scattering heterogeneous medium given a (chromatic) constant in a large cube is the
/// homogeneous medium of its box, the unit cube: its free flights are drawn exactly inside the
/// box (the meter's ray enters the large cube at t = 3, the box at 4, leaves it at 5, then sees
/// the lamp below through it), so the two meters agree within four standard errors of their
/// difference, and both differ from the meter without a medium by far more.
#[test]
fn a_constant_heterogeneous_medium_scatters_as_the_homogeneous_one_of_its_box() {
    let scene = |medium: &str, scale: f32, shift: f32| {
        meter_scene(
            (0.5, 0.5),
            &format!(
                r#"<shape type="rectangle"><transform name="to_world"><scale value="0.3"/><translate x="0.5" y="0.5" z="-3"/></transform>
                    <emitter type="area"><rgb name="radiance" value="4, 3, 2"/></emitter></shape>
                {medium}
                <shape type="cube"><transform name="to_world"><scale value="{scale}"/><translate x="{shift}" y="{shift}" z="{shift}"/></transform>
                    <bsdf type="null"/><ref name="interior" id="m"/></shape>"#
            ),
        )
    };
    let parts = r#"<rgb name="sigma_t" value="0.5, 1, 2"/><float name="albedo" value="0.8"/><phase type="hg"><float name="g" value="0.3"/></phase>"#;
    let boxed = scene(
        &format!(r#"<medium type="heterogeneous" id="m">{parts}</medium>"#),
        2.0,
        0.0,
    );
    let plain = scene(
        &format!(r#"<medium type="homogeneous" id="m">{parts}</medium>"#),
        0.5,
        0.5,
    );
    let empty = scene(
        r#"<medium type="homogeneous" id="m"><float name="sigma_t" value="0"/></medium>"#,
        0.5,
        0.5,
    );
    let (a, se_a) = meter_mean(&boxed, 1 << 12, 8);
    let (b, se_b) = meter_mean(&plain, 1 << 12, 8);
    let (e, _) = meter_mean(&empty, 1 << 10, 2);
    for c in 0..3 {
        let se = (se_a[c].powi(2) + se_b[c].powi(2)).sqrt();
        assert!(
            (a[c] - b[c]).abs() < 4.0 * se,
            "channel {c}: {a:?} ± {se_a:?} against {b:?} ± {se_b:?}"
        );
        assert!(
            (a[c] - e[c]).abs() > 50.0 * se,
            "channel {c}: the medium changes {e:?} to {a:?} only"
        );
    }
}
