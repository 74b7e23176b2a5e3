//! Figures for the lecture's generalizations of the ideal diffuse BRDF (Oren–Nayar, Heitz et
//! al. 2016 Lambertian microfacets, d'Eon 2021 Lambertian spheres) and for multiple scattering
//! on microfacets. The numbers are computed by the caller (`gonio plot retroreflection`,
//! `saturation`, `multiple-scattering`); these functions only lay them out.

use super::{Figure, LegendPosition, LinePlot, Panel, Series, VLine};

/// One named curve of (x, y) points.
pub type Curve = (String, Vec<(f64, f64)>);

/// In-plane BRDFs f (no cosine) against the signed view angle, one panel per incident angle
/// (`panels`: θi in degrees and its curves). The light is at −θi (marked); positive angles are
/// the mirror side, negative ones the side the light comes from (retro-reflection at −θi).
pub fn retroreflection_figure(panels: &[(f32, Vec<Curve>)], note: &str) -> Figure {
    let mut out = vec![];
    for (theta_i, curves) in panels {
        let mut p = LinePlot::new(
            format!("In-plane BRDF, light at θi = {theta_i}°"),
            "view angle θo  [deg]  (< 0: towards the light, > 0: mirror side)",
            "f  [1/sr]  (no cosine)",
        );
        p.x_range = Some((-90.0, 90.0));
        p.note = note.to_string();
        p.legend = LegendPosition::UpperRight;
        p.vlines.push(VLine {
            x: -*theta_i as f64,
            label: "light".into(),
        });
        for (k, (name, pts)) in curves.iter().enumerate() {
            p.series.push(Series::new(name.clone(), pts.clone()).color(k));
        }
        out.push(Panel::Line(p));
    }
    Figure {
        title: String::new(),
        panels: out,
        columns: 2,
        panel_size: (620, 520),
    }
}

/// Reflectance spectra of several materials sharing one `reflectance` spectrum (the first curve
/// is usually that spectrum itself, i.e. `diffuse`), to show how multiple scattering saturates
/// colour; the caller may name each curve's sRGB colour in its label.
pub fn saturation_figure(curves: &[Curve], note: &str) -> Figure {
    let mut p = LinePlot::new(
        "Colour saturation at the same reflectance k_d",
        "wavelength λ  [nm]",
        "directional albedo  [–]",
    );
    p.note = note.to_string();
    p.legend = LegendPosition::UpperLeft;
    p.y_range = Some((0.0, 1.0));
    for (k, (name, pts)) in curves.iter().enumerate() {
        p.series.push(Series::new(name.clone(), pts.clone()).color(k));
    }
    Figure::single(Panel::Line(p), (820, 560))
}

/// Directional albedo against roughness, single scattering (solid) against multiple scattering
/// (dashed), one panel per material (`panels`: title and curves; a curve whose name contains
/// "multiple" is dashed).
pub fn scattering_order_figure(panels: &[(String, Vec<Curve>)], note: &str) -> Figure {
    let mut out = vec![];
    for (title, curves) in panels {
        let mut p = LinePlot::new(title.clone(), "roughness α  [–]", "directional albedo  [–]");
        p.note = note.to_string();
        p.legend = LegendPosition::LowerLeft;
        p.y_range = Some((0.0, 1.05));
        let mut colours: Vec<String> = vec![];
        for (name, pts) in curves {
            let key = name.replace("multiple", "").replace("single", "");
            if !colours.contains(&key) {
                colours.push(key.clone());
            }
            let k = colours.iter().position(|c| *c == key).unwrap_or(0);
            let s = Series::new(name.clone(), pts.clone()).color(k);
            p.series
                .push(if name.contains("multiple") { s.dashed() } else { s });
        }
        out.push(Panel::Line(p));
    }
    Figure {
        title: String::new(),
        panels: out,
        columns: 2,
        panel_size: (620, 520),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(name: &str, f: impl Fn(f64) -> f64) -> Curve {
        (
            name.to_string(),
            (0..=36)
                .map(|k| -90.0 + 5.0 * k as f64)
                .map(|x| (x, f(x)))
                .collect(),
        )
    }

    #[test]
    fn figures_render_with_their_labels() {
        let f = retroreflection_figure(
            &[
                (
                    60.0,
                    vec![
                        curve("diffuse", |_| 0.25),
                        curve("lambertsphere", |x| 0.2 - x / 900.0),
                    ],
                ),
                (80.0, vec![curve("diffuse", |_| 0.25)]),
            ],
            "k_d = 0.8, α = 1; λ = 550 nm",
        );
        assert_eq!(f.panels.len(), 2);
        let svg = f.to_svg().unwrap();
        for label in ["light at θi = 80°", "lambertsphere", "f  [1/sr]  (no cosine)"] {
            assert!(svg.contains(label), "{label}");
        }
        let s = saturation_figure(&[curve("diffuse", |_| 0.5)], "θi = 0");
        assert!(s.to_svg().unwrap().contains("Colour saturation"));
        let m = scattering_order_figure(
            &[(
                "conductor".into(),
                vec![curve("ggx single", |_| 0.5), curve("ggx multiple", |_| 1.0)],
            )],
            "",
        );
        let Panel::Line(p) = &m.panels[0] else {
            panic!("line plot")
        };
        assert!(!p.series[0].dashed && p.series[1].dashed);
        assert_eq!(
            p.series[0].color, p.series[1].color,
            "same colour per distribution"
        );
        m.to_png().unwrap();
    }
}
