//! The viridis colour map (van der Walt & Smith, matplotlib's default): perceptually uniform,
//! monotone in lightness, readable in grey and by colour-blind viewers; a diverging map for signed
//! quantities (Moreland 2009, "Diverging color maps for scientific visualization": its cool–warm
//! end points) and a cyclic one for angles (the hue circle).

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

/// The cool–warm end points (Moreland 2009) and its grey midpoint, display RGB.
const COOL: [f32; 3] = [0.230, 0.299, 0.754];
const MID: [f32; 3] = [0.865, 0.865, 0.865];
const WARM: [f32; 3] = [0.706, 0.016, 0.150];

fn lerp3(a: [f32; 3], b: [f32; 3], f: f32) -> [f32; 3] {
    [
        a[0] + f * (b[0] - a[0]),
        a[1] + f * (b[1] - a[1]),
        a[2] + f * (b[2] - a[2]),
    ]
}

/// A diverging map of `v` ∈ [−1, 1] (clamped; NaN is the midpoint): blue for −1, grey for 0,
/// red for +1, linear in display RGB on each side.
pub fn diverging(v: f32) -> [f32; 3] {
    let v = if v.is_finite() { v.clamp(-1.0, 1.0) } else { 0.0 };
    if v < 0.0 {
        lerp3(MID, COOL, -v)
    } else {
        lerp3(MID, WARM, v)
    }
}

/// A cyclic map of `t` (taken modulo 1): the hue circle at full saturation and value, red at 0,
/// through yellow, green, cyan, blue and magenta back to red.
pub fn cyclic(t: f32) -> [f32; 3] {
    let t = if t.is_finite() { t.rem_euclid(1.0) } else { 0.0 };
    let h = t * 6.0;
    let k = (h as usize).min(5);
    let f = h - k as f32;
    match k {
        0 => [1.0, f, 0.0],
        1 => [1.0 - f, 1.0, 0.0],
        2 => [0.0, 1.0, f],
        3 => [0.0, 1.0 - f, 1.0],
        4 => [f, 0.0, 1.0],
        _ => [1.0, 0.0, 1.0 - f],
    }
}

/// A display colour as 8-bit RGB.
pub fn to_rgb8(c: [f32; 3]) -> [u8; 3] {
    c.map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8)
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

    #[test]
    fn diverging_and_cyclic_maps() {
        assert_eq!(to_rgb8(diverging(-1.0)), [59, 76, 192]);
        assert_eq!(to_rgb8(diverging(0.0)), [221, 221, 221]);
        assert_eq!(to_rgb8(diverging(1.0)), [180, 4, 38]);
        assert_eq!(to_rgb8(cyclic(0.0)), to_rgb8(cyclic(1.0)));
        assert_eq!(to_rgb8(cyclic(0.5)), [0, 255, 255]);
        assert_eq!(to_rgb8(cyclic(0.25)), [128, 255, 0]);
    }
}
