//! Lobes in the plane of incidence, as a polar plot: the surface is the horizontal line, the
//! normal points up, radius = the BSDF value; several BSDFs overlaid, delta lobes as arrows.

use super::{PlotError, draw_err, draw_lines, fitting_size, font, line_height, series_color, wrap_text};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One lobe: (signed angle from the normal in degrees, radius) points.
#[derive(Clone, Debug, PartialEq)]
pub struct PolarCurve {
    /// Legend entry.
    pub label: String,
    /// (α in degrees, r ≥ 0); α > 0 towards the right, |α| > 90 below the surface.
    pub points: Vec<(f32, f32)>,
    /// Colour index.
    pub color: usize,
}

/// A delta lobe, drawn as an arrow from the origin to the rim.
#[derive(Clone, Debug, PartialEq)]
pub struct PolarArrow {
    /// Direction, degrees (as for curve points).
    pub angle_deg: f32,
    /// Text at its tip (e.g. "δ F = 0.04").
    pub label: String,
    /// Colour index.
    pub color: usize,
}

/// A polar-plot panel.
#[derive(Clone, Debug, PartialEq)]
pub struct PolarPlot {
    /// Panel title.
    pub title: String,
    /// The lobes.
    pub curves: Vec<PolarCurve>,
    /// Delta lobes.
    pub arrows: Vec<PolarArrow>,
    /// Where the light comes from, degrees (drawn as an incoming arrow).
    pub light_deg: f32,
    /// What the radius is, with units.
    pub r_label: String,
    /// Draw the lower half (transmission) too.
    pub full_circle: bool,
}

fn nice_step(max: f32) -> f32 {
    let raw = max / 4.0;
    let mag = 10f32.powf(raw.log10().floor());
    let n = raw / mag;
    let s = if n < 1.5 {
        1.0
    } else if n < 3.5 {
        2.0
    } else if n < 7.5 {
        5.0
    } else {
        10.0
    };
    s * mag
}

impl PolarPlot {
    /// Draws the plot into `area`.
    pub fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let (w, h) = area.dim_in_pixel();
        let top = Pos::new(HPos::Center, VPos::Top);
        area.draw(&Text::new(
            self.title.clone(),
            (w as i32 / 2, 8),
            font(fitting_size(&self.title, 18, w.saturating_sub(20))).pos(top),
        ))
        .map_err(draw_err)?;
        let rmax = self
            .curves
            .iter()
            .flat_map(|c| c.points.iter().map(|p| p.1))
            .filter(|r| r.is_finite())
            .fold(0.0f32, f32::max);
        let rmax = if rmax > 0.0 { rmax } else { 1.0 };
        let step = nice_step(rmax);
        let rings = (rmax / step).ceil().max(1.0) as usize;
        let big_r = step * rings as f32;
        let ylo = if self.full_circle {
            -big_r * 1.12
        } else {
            -big_r * 0.12
        };
        let plot_h = h as i32 - 70;
        let aspect = (2.24 * big_r) / (big_r * 1.12 - ylo);
        let mut pw = (w as i32 - 40).min((plot_h as f32 * aspect) as i32);
        let ph = (pw as f32 / aspect) as i32;
        pw = pw.max(50);
        let sub = area
            .clone()
            .shrink(((w as i32 - pw) / 2, 36), (pw as u32, ph.max(50) as u32));
        let mut chart = ChartBuilder::on(&sub)
            .build_cartesian_2d(-big_r * 1.12..big_r * 1.12, ylo..big_r * 1.12)
            .map_err(draw_err)?;
        let grey = RGBColor(200, 200, 200);
        let (a0, a1) = if self.full_circle {
            (-180.0f32, 180.0f32)
        } else {
            (-90.0, 90.0)
        };
        let arc = |r: f32| -> Vec<(f32, f32)> {
            (0..=180)
                .map(|k| {
                    let a = (a0 + (a1 - a0) * k as f32 / 180.0).to_radians();
                    (r * a.sin(), r * a.cos())
                })
                .collect()
        };
        for k in 1..=rings {
            let r = step * k as f32;
            chart
                .draw_series(std::iter::once(PathElement::new(arc(r), grey.stroke_width(1))))
                .map_err(draw_err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    trim(r),
                    (r * 0.02, r),
                    font(11).color(&RGBColor(110, 110, 110)),
                )))
                .map_err(draw_err)?;
        }
        let mut spoke = a0 as i32;
        while spoke <= a1 as i32 {
            let a = (spoke as f32).to_radians();
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(0.0, 0.0), (big_r * a.sin(), big_r * a.cos())],
                    grey.stroke_width(1),
                )))
                .map_err(draw_err)?;
            if spoke.abs() != 180 || spoke == 180 {
                chart
                    .draw_series(std::iter::once(Text::new(
                        format!("{spoke}°"),
                        (big_r * 1.07 * a.sin(), big_r * 1.07 * a.cos()),
                        font(11)
                            .color(&RGBColor(110, 110, 110))
                            .pos(Pos::new(HPos::Center, VPos::Center)),
                    )))
                    .map_err(draw_err)?;
            }
            spoke += 30;
        }
        // The surface.
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(-big_r * 1.1, 0.0), (big_r * 1.1, 0.0)],
                BLACK.stroke_width(2),
            )))
            .map_err(draw_err)?;
        // The light, coming in.
        let la = self.light_deg.to_radians();
        let tail = (big_r * la.sin(), big_r * la.cos());
        chart
            .draw_series(DashedLineSeries::new(
                vec![tail, (0.0, 0.0)],
                6,
                4,
                RGBColor(230, 159, 0).stroke_width(2),
            ))
            .map_err(draw_err)?;
        let head = |tip: (f32, f32), from: (f32, f32)| -> Vec<(f32, f32)> {
            let d = ((tip.0 - from.0), (tip.1 - from.1));
            let len = (d.0 * d.0 + d.1 * d.1).sqrt().max(1e-9);
            let (ux, uy) = (d.0 / len, d.1 / len);
            let s = big_r * 0.05;
            vec![
                (tip.0 - s * ux + 0.5 * s * uy, tip.1 - s * uy - 0.5 * s * ux),
                tip,
                (tip.0 - s * ux - 0.5 * s * uy, tip.1 - s * uy + 0.5 * s * ux),
            ]
        };
        chart
            .draw_series(std::iter::once(PathElement::new(
                head((0.0, 0.0), tail),
                RGBColor(230, 159, 0).stroke_width(2),
            )))
            .map_err(draw_err)?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("light, θi = {}°", trim(-self.light_deg)),
                (tail.0, tail.1 + big_r * 0.04),
                font(13)
                    .color(&RGBColor(200, 120, 0))
                    .pos(Pos::new(HPos::Center, VPos::Bottom)),
            )))
            .map_err(draw_err)?;
        for c in &self.curves {
            let col = series_color(c.color);
            let pts: Vec<(f32, f32)> = c
                .points
                .iter()
                .filter(|p| p.1.is_finite())
                .map(|&(a, r)| {
                    let a = a.to_radians();
                    (r * a.sin(), r * a.cos())
                })
                .collect();
            chart
                .draw_series(LineSeries::new(pts, col.stroke_width(2)))
                .map_err(draw_err)?
                .label(c.label.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2)));
        }
        for a in &self.arrows {
            let col = series_color(a.color);
            let ang = a.angle_deg.to_radians();
            let tip = (big_r * ang.sin(), big_r * ang.cos());
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(0.0, 0.0), tip],
                    col.stroke_width(3),
                )))
                .map_err(draw_err)?;
            chart
                .draw_series(std::iter::once(PathElement::new(
                    head(tip, (0.0, 0.0)),
                    col.stroke_width(3),
                )))
                .map_err(draw_err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    a.label.clone(),
                    (tip.0 * 0.75, tip.1 * 0.75),
                    font(13).color(&col).pos(Pos::new(HPos::Left, VPos::Bottom)),
                )))
                .map_err(draw_err)?;
        }
        if self.curves.iter().any(|c| !c.label.is_empty()) {
            chart
                .configure_series_labels()
                .label_font(font(13))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(180, 180, 180))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(draw_err)?;
        }
        let caption = format!("radius: {}; surface horizontal, normal up", self.r_label);
        let lines = wrap_text(&caption, 12, w.saturating_sub(24));
        let y = h as i32 - 8 - lines.len() as i32 * line_height(12);
        draw_lines(area, &lines, (w as i32 / 2, y), 12, RGBColor(80, 80, 80))?;
        Ok(())
    }
}

/// A number without trailing zeros.
fn trim(x: f32) -> String {
    let s = format!("{x:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}
