//! Curves against an x axis: Fresnel curves, reflectance against wavelength, albedo curves
//! with error bars.

use super::{PlotError, draw_err, draw_lines, fitting_size, font, series_color, wrap_text};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// An axis range (low, high).
type Range = (f64, f64);

/// One curve.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend entry.
    pub label: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// ± error bar at each point (same length as `points`), drawn as vertical bars.
    pub error: Option<Vec<f64>>,
    /// Draw dashed.
    pub dashed: bool,
    /// Colour index ([`series_color`]); `None` = the series' position.
    pub color: Option<usize>,
}

impl Series {
    /// A solid curve.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            error: None,
            dashed: false,
            color: None,
        }
    }
    /// The same curve, dashed.
    pub fn dashed(mut self) -> Self {
        self.dashed = true;
        self
    }
    /// The same curve in colour `k`.
    pub fn color(mut self, k: usize) -> Self {
        self.color = Some(k);
        self
    }
    /// The same curve with error bars.
    pub fn with_error(mut self, err: Vec<f64>) -> Self {
        self.error = Some(err);
        self
    }
}

/// A labelled vertical line (Brewster's angle, the critical angle, ...).
#[derive(Clone, Debug, PartialEq)]
pub struct VLine {
    /// Position on the x axis.
    pub x: f64,
    /// Text next to it.
    pub label: String,
}

/// A cartesian plot of curves.
#[derive(Clone, Debug, PartialEq)]
pub struct LinePlot {
    /// Panel title.
    pub title: String,
    /// x-axis label, with units.
    pub x_label: String,
    /// y-axis label, with units.
    pub y_label: String,
    /// x range; `None` = the data's.
    pub x_range: Option<(f64, f64)>,
    /// y range; `None` = the data's, from 0 when the data are non-negative.
    pub y_range: Option<(f64, f64)>,
    /// The curves.
    pub series: Vec<Series>,
    /// Vertical markers.
    pub vlines: Vec<VLine>,
    /// A line of small print under the title (how the data were made).
    pub note: String,
    /// Where the legend goes.
    pub legend: LegendPosition,
}

/// Corner of the plot that holds the legend.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LegendPosition {
    /// Top left (default).
    #[default]
    UpperLeft,
    /// Top right.
    UpperRight,
    /// Bottom left.
    LowerLeft,
    /// Bottom right.
    LowerRight,
}

impl LinePlot {
    /// An empty plot with a title and axis labels.
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_range: None,
            y_range: None,
            series: vec![],
            vlines: vec![],
            note: String::new(),
            legend: LegendPosition::UpperLeft,
        }
    }

    fn ranges(&self) -> Result<(Range, Range), PlotError> {
        let pts = || {
            self.series
                .iter()
                .flat_map(|s| s.points.iter())
                .filter(|p| p.0.is_finite() && p.1.is_finite())
        };
        if pts().next().is_none() {
            return Err(PlotError::Invalid(format!(
                "plot '{}' has no finite data",
                self.title
            )));
        }
        let x = self.x_range.unwrap_or_else(|| {
            let (lo, hi) = pts().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
            if hi > lo { (lo, hi) } else { (lo - 1.0, lo + 1.0) }
        });
        let y = self.y_range.unwrap_or_else(|| {
            let mut lo = f64::MAX;
            let mut hi = f64::MIN;
            for s in &self.series {
                for (k, p) in s.points.iter().enumerate() {
                    if !(p.0.is_finite() && p.1.is_finite()) {
                        continue;
                    }
                    let e = s.error.as_ref().and_then(|e| e.get(k)).copied().unwrap_or(0.0);
                    lo = lo.min(p.1 - e);
                    hi = hi.max(p.1 + e);
                }
            }
            if lo >= 0.0 {
                lo = 0.0;
            }
            let pad = 0.05 * (hi - lo).max(1e-9);
            (if lo == 0.0 { 0.0 } else { lo - pad }, hi + pad)
        });
        Ok((x, y))
    }

    /// Draws the plot into `area`.
    pub fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let ((x0, x1), (y0, y1)) = self.ranges()?;
        let (w, _) = area.dim_in_pixel();
        let center_top = plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Top,
        );
        area.draw(&Text::new(
            self.title.clone(),
            (w as i32 / 2, 6),
            font(fitting_size(&self.title, 18, w.saturating_sub(20))).pos(center_top),
        ))
        .map_err(draw_err)?;
        let note_h = if self.note.is_empty() {
            0
        } else {
            let lines = wrap_text(&self.note, 12, w.saturating_sub(24));
            draw_lines(area, &lines, (w as i32 / 2, 30), 12, RGBColor(90, 90, 90))?
        };
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .margin_top(34 + note_h.max(0) as u32)
            .x_label_area_size(44)
            .y_label_area_size(62)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .x_desc(self.x_label.clone())
            .y_desc(self.y_label.clone())
            .axis_desc_style(font(15))
            .label_style(font(13))
            .x_label_formatter(&|x| tick(*x))
            .y_label_formatter(&|y| tick(*y))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(210, 210, 210))
            .draw()
            .map_err(draw_err)?;
        for (k, v) in self.vlines.iter().enumerate() {
            let grey = RGBColor(120, 120, 120);
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(v.x, y0), (v.x, y1)],
                    grey.stroke_width(1),
                )))
                .map_err(draw_err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    v.label.clone(),
                    (v.x + 0.008 * (x1 - x0), y1 - (0.55 + 0.06 * k as f64) * (y1 - y0)),
                    font(13).color(&grey),
                )))
                .map_err(draw_err)?;
        }
        for (k, s) in self.series.iter().enumerate() {
            let c = series_color(s.color.unwrap_or(k));
            let style = c.stroke_width(2);
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            let anno = if s.dashed {
                chart
                    .draw_series(DashedLineSeries::new(pts.clone(), 8, 5, style))
                    .map_err(draw_err)?
            } else {
                chart
                    .draw_series(LineSeries::new(pts.clone(), style))
                    .map_err(draw_err)?
            };
            let dashed = s.dashed;
            // The legend sample is dashed like its curve (a solid one is a single 20 px dash).
            let (dash, gap) = if dashed { (6, 4) } else { (20, 1) };
            anno.label(s.label.clone()).legend(move |(x, y)| {
                DashedPathElement::new(vec![(x, y), (x + 20, y)], dash, gap, c.stroke_width(2))
            });
            if let Some(err) = &s.error {
                chart
                    .draw_series(
                        s.points
                            .iter()
                            .zip(err)
                            .filter(|(p, e)| p.1.is_finite() && e.is_finite())
                            .map(|(&(x, y), &e)| {
                                PathElement::new(vec![(x, y - e), (x, y + e)], c.stroke_width(1))
                            }),
                    )
                    .map_err(draw_err)?;
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 2, c.filled())))
                    .map_err(draw_err)?;
            }
        }
        if self.series.iter().any(|s| !s.label.is_empty()) {
            chart
                .configure_series_labels()
                .label_font(font(13))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(180, 180, 180))
                .position(match self.legend {
                    LegendPosition::UpperLeft => SeriesLabelPosition::UpperLeft,
                    LegendPosition::UpperRight => SeriesLabelPosition::UpperRight,
                    LegendPosition::LowerLeft => SeriesLabelPosition::LowerLeft,
                    LegendPosition::LowerRight => SeriesLabelPosition::LowerRight,
                })
                .draw()
                .map_err(draw_err)?;
        }
        Ok(())
    }
}

/// A tick label without trailing zeros ("10", "0.25").
fn tick(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.to_string() }
}
