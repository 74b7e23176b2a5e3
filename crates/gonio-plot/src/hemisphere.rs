//! Hemisphere images: the disks of a BSDF slice in an azimuthal projection, with a colour bar,
//! θ rings, azimuth labels and markers for the fixed direction and for delta lobes.

use super::{PlotError, Raster, colormap, draw_err, draw_lines, fitting_size, font, line_height, wrap_text};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The values of one disk, `resolution²` pixels, row 0 at the top (+y), column 0 at −x.
#[derive(Clone, Debug, PartialEq)]
pub enum Pixels {
    /// Scalar values mapped through the colour map over [`HemispherePlot::value_range`].
    Scalar {
        /// Pixels across.
        resolution: usize,
        /// Values; `None` outside the disk.
        values: Vec<Option<f32>>,
    },
    /// Display colours (sRGB-encoded, 0–1), for `--rgb` slices.
    Rgb {
        /// Pixels across.
        resolution: usize,
        /// Colours; `None` outside the disk.
        values: Vec<Option<[f32; 3]>>,
    },
}

/// What a marker stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkerKind {
    /// The fixed direction of the slice.
    Fixed,
    /// A delta lobe (no value on the image: marked instead).
    Delta,
}

/// A marked point on a disk, in disk coordinates (x right, y up, |p| ≤ 1).
#[derive(Clone, Debug, PartialEq)]
pub struct DiskMarker {
    /// Position on the disk.
    pub pos: (f32, f32),
    /// Text next to it.
    pub label: String,
    /// Its kind (shape and colour).
    pub kind: MarkerKind,
}

/// One disk of the figure.
#[derive(Clone, Debug, PartialEq)]
pub struct DiskImage {
    /// Caption under the disk ("reflection side (z > 0)").
    pub label: String,
    /// The values.
    pub pixels: Pixels,
    /// Markers on it.
    pub markers: Vec<DiskMarker>,
}

/// A hemisphere-slice panel.
#[derive(Clone, Debug, PartialEq)]
pub struct HemispherePlot {
    /// Panel title.
    pub title: String,
    /// One or two disks.
    pub disks: Vec<DiskImage>,
    /// Colour-bar range for scalar pixels.
    pub value_range: (f32, f32),
    /// Colour-bar label, with units (e.g. "f  [1/sr]").
    pub colorbar_label: String,
    /// Small print under the disks: the projection and how to read the picture.
    pub note: String,
    /// θ circles: (disk radius, label).
    pub rings: Vec<(f32, String)>,
}

struct Layout {
    disks: Vec<(i32, i32, u32)>,
    bar: (i32, i32, u32, u32),
}

const TOP: i32 = 44;
const BAR_W: u32 = 110;

impl HemispherePlot {
    fn layout(&self, (w, h): (u32, u32)) -> Layout {
        let n = self.disks.len().max(1) as i32;
        let has_bar = self
            .disks
            .iter()
            .any(|d| matches!(d.pixels, Pixels::Scalar { .. }));
        let avail_w = w as i32 - if has_bar { BAR_W as i32 } else { 0 } - 20;
        // Room for the note's lines beyond the first, which the 80 pixels below the disks hold.
        let note_lines = wrap_text(&self.note, 12, w.saturating_sub(24)).len() as i32;
        let extra = (note_lines - 1).max(0) * line_height(12);
        let d = ((avail_w / n - 100).min(h as i32 - TOP - 80 - extra)).max(16);
        let gap = (avail_w - n * d) / (n + 1);
        let disks = (0..n)
            .map(|k| (10 + gap + k * (d + gap), TOP + 20, d as u32))
            .collect();
        let bar = (w as i32 - BAR_W as i32, TOP + 20, BAR_W, d as u32);
        Layout { disks, bar }
    }

    /// The disk images as rasters (panel coordinates).
    pub(crate) fn rasters(&self, size: (u32, u32)) -> Vec<Raster> {
        let l = self.layout(size);
        let (lo, hi) = self.value_range;
        let span = if hi > lo { hi - lo } else { 1.0 };
        self.disks
            .iter()
            .zip(&l.disks)
            .map(|(disk, &(x, y, d))| {
                let mut rgb = Vec::with_capacity((d * d) as usize);
                for py in 0..d {
                    for px in 0..d {
                        let pick = |res: usize| {
                            let c = ((px as f32 + 0.5) / d as f32 * res as f32) as usize;
                            let r = ((py as f32 + 0.5) / d as f32 * res as f32) as usize;
                            r.min(res - 1) * res + c.min(res - 1)
                        };
                        rgb.push(match &disk.pixels {
                            Pixels::Scalar { resolution, values } => {
                                values[pick(*resolution)].map(|v| colormap((v - lo) / span))
                            }
                            Pixels::Rgb { resolution, values } => values[pick(*resolution)]
                                .map(|c| c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)),
                        });
                    }
                }
                Raster {
                    x,
                    y,
                    width: d,
                    height: d,
                    rgb,
                }
            })
            .collect()
    }

    /// Draws the vector parts (frame, rings, labels, markers, colour bar) into `area`.
    pub fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let size = area.dim_in_pixel();
        let l = self.layout(size);
        let center = |p: Pos| p;
        let ct = center(Pos::new(HPos::Center, VPos::Top));
        let cc = Pos::new(HPos::Center, VPos::Center);
        area.draw(&Text::new(
            self.title.clone(),
            (size.0 as i32 / 2, 8),
            font(fitting_size(&self.title, 18, size.0.saturating_sub(20))).pos(ct),
        ))
        .map_err(draw_err)?;
        let grey = RGBColor(150, 150, 150);
        for (disk, &(x, y, d)) in self.disks.iter().zip(&l.disks) {
            let r = d as f32 / 2.0;
            let (cx, cy) = (x + r as i32, y + r as i32);
            let to_px = |p: (f32, f32)| (cx + (p.0 * r).round() as i32, cy - (p.1 * r).round() as i32);
            // θ rings and the horizon.
            for (rad, label) in &self.rings {
                let pts: Vec<(i32, i32)> = (0..=96)
                    .map(|k| {
                        let a = k as f32 / 96.0 * std::f32::consts::TAU;
                        to_px((rad * a.cos(), rad * a.sin()))
                    })
                    .collect();
                area.draw(&PathElement::new(pts, WHITE.mix(0.5).stroke_width(1)))
                    .map_err(draw_err)?;
                area.draw(&Text::new(
                    label.clone(),
                    to_px((rad * 0.71, rad * 0.71)),
                    font(11).color(&WHITE),
                ))
                .map_err(draw_err)?;
            }
            area.draw(&Circle::new((cx, cy), r as i32, BLACK.stroke_width(1)))
                .map_err(draw_err)?;
            // Azimuth labels.
            for (deg, dx, dy, pos) in [
                (0, 1.0, 0.0, Pos::new(HPos::Left, VPos::Center)),
                (90, 0.0, 1.0, Pos::new(HPos::Center, VPos::Bottom)),
                (180, -1.0, 0.0, Pos::new(HPos::Right, VPos::Center)),
                (270, 0.0, -1.0, Pos::new(HPos::Center, VPos::Top)),
            ] {
                let (px, py) = to_px((dx * 1.04, dy * 1.04));
                area.draw(&Text::new(
                    format!("{deg}°"),
                    (px, py),
                    font(12).color(&grey).pos(pos),
                ))
                .map_err(draw_err)?;
            }
            area.draw(&Text::new(
                disk.label.clone(),
                (cx, y + d as i32 + 22),
                font(14).pos(ct),
            ))
            .map_err(draw_err)?;
            for m in &disk.markers {
                let (px, py) = to_px(m.pos);
                match m.kind {
                    MarkerKind::Fixed => {
                        area.draw(&Cross::new((px, py), 7, WHITE.stroke_width(4)))
                            .map_err(draw_err)?;
                        area.draw(&Cross::new((px, py), 7, BLACK.stroke_width(2)))
                            .map_err(draw_err)?;
                    }
                    MarkerKind::Delta => {
                        let red = RGBColor(220, 20, 60);
                        area.draw(&Circle::new((px, py), 9, WHITE.stroke_width(4)))
                            .map_err(draw_err)?;
                        area.draw(&Circle::new((px, py), 9, red.stroke_width(2)))
                            .map_err(draw_err)?;
                        area.draw(&Circle::new((px, py), 2, red.filled()))
                            .map_err(draw_err)?;
                    }
                }
                let color = if m.kind == MarkerKind::Delta {
                    RGBColor(220, 20, 60)
                } else {
                    BLACK
                };
                let (tx, ty) = (px + 12, py - 12);
                let bg = font(13).color(&WHITE);
                for (ox, oy) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                    area.draw(&Text::new(m.label.clone(), (tx + ox, ty + oy), bg.clone()))
                        .map_err(draw_err)?;
                }
                area.draw(&Text::new(m.label.clone(), (tx, ty), font(13).color(&color)))
                    .map_err(draw_err)?;
            }
        }
        if !self.note.is_empty() {
            let y = l
                .disks
                .first()
                .map(|d| d.1 + d.2 as i32 + 46)
                .unwrap_or(size.1 as i32 - 20);
            let lines = wrap_text(&self.note, 12, size.0.saturating_sub(24));
            draw_lines(area, &lines, (size.0 as i32 / 2, y), 12, RGBColor(80, 80, 80))?;
        }
        if self
            .disks
            .iter()
            .any(|d| matches!(d.pixels, Pixels::Scalar { .. }))
        {
            let (bx, by, bw, bh) = l.bar;
            let bar = area.clone().shrink((bx, by - 8), (bw, bh + 16));
            let (lo, hi) = self.value_range;
            let hi = if hi > lo { hi } else { lo + 1.0 };
            let mut chart = ChartBuilder::on(&bar)
                .margin_top(8)
                .margin_bottom(8)
                .margin_right(14)
                .y_label_area_size(62)
                .build_cartesian_2d(0f32..1f32, lo..hi)
                .map_err(draw_err)?;
            let steps = 96;
            chart
                .draw_series((0..steps).map(|k| {
                    let a = lo + (hi - lo) * k as f32 / steps as f32;
                    let b = lo + (hi - lo) * (k + 1) as f32 / steps as f32;
                    let c = colormap((k as f32 + 0.5) / steps as f32);
                    Rectangle::new([(0.0, a), (1.0, b)], RGBColor(c[0], c[1], c[2]).filled())
                }))
                .map_err(draw_err)?;
            chart
                .configure_mesh()
                .disable_x_mesh()
                .disable_y_mesh()
                .disable_x_axis()
                .y_labels(6)
                .label_style(font(12))
                .draw()
                .map_err(draw_err)?;
            area.draw(&Text::new(
                self.colorbar_label.clone(),
                (bx + bw as i32 / 2, by - 14),
                font(13).pos(cc),
            ))
            .map_err(draw_err)?;
        }
        Ok(())
    }
}
