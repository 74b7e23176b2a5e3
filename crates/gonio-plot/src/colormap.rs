//! The viridis colour map (van der Walt & Smith, matplotlib's default): perceptually uniform,
//! monotone in lightness, readable in grey and by colour-blind viewers.

/// viridis at 17 evenly spaced points (from matplotlib's `_viridis_data`, every 16th entry).
const VIRIDIS: [[f32; 3]; 17] = [
    [0.267004, 0.004874, 0.329415],
    [0.282327, 0.094955, 0.417331],
    [0.278826, 0.175490, 0.483397],
    [0.258965, 0.251537, 0.524736],
    [0.229739, 0.322361, 0.545706],
    [0.199430, 0.387607, 0.554642],
    [0.172719, 0.448791, 0.557885],
    [0.149039, 0.508051, 0.557250],
    [0.127568, 0.566949, 0.550556],
    [0.120638, 0.625828, 0.533488],
    [0.157851, 0.683765, 0.501686],
    [0.246070, 0.738910, 0.452024],
    [0.369214, 0.788888, 0.382914],
    [0.515992, 0.831158, 0.294279],
    [0.678489, 0.863742, 0.189503],
    [0.845561, 0.887322, 0.099702],
    [0.993248, 0.906157, 0.143936],
];

/// viridis at `t` ∈ [0, 1] (clamped), as linear interpolation between the table points.
pub fn viridis(t: f32) -> [f32; 3] {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let x = t * (VIRIDIS.len() - 1) as f32;
    let k = (x as usize).min(VIRIDIS.len() - 2);
    let f = x - k as f32;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    [
        a[0] + f * (b[0] - a[0]),
        a[1] + f * (b[1] - a[1]),
        a[2] + f * (b[2] - a[2]),
    ]
}

/// viridis at `t` as 8-bit RGB.
pub fn colormap(t: f32) -> [u8; 3] {
    let c = viridis(t);
    [
        (c[0] * 255.0).round() as u8,
        (c[1] * 255.0).round() as u8,
        (c[2] * 255.0).round() as u8,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_lightness_increase() {
        assert_eq!(colormap(0.0), [68, 1, 84]);
        assert_eq!(colormap(1.0), [253, 231, 37]);
        let lum = gonio_core::color::luminance;
        for k in 0..100 {
            assert!(lum(viridis((k + 1) as f32 / 100.0)) > lum(viridis(k as f32 / 100.0)));
        }
    }
}
