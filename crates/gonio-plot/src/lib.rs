//! # gonio-plot
//!
//! Plots for the lecture's instruments, as PNG and SVG through `plotters`. Depends only on
//! `gonio-core`, and does no file I/O: it returns encoded bytes, which the caller writes (the
//! `gonio` binary writes them atomically with `gonio_render::output::write_atomically`).
//!
//! * Text is drawn with DejaVu Sans, embedded in the binary (`assets/fonts`, Bitstream Vera
//!   licence beside it), so a PNG is the same on every machine and needs no system font. SVG
//!   files name the family `sans-serif` and let the viewer draw the text.
//! * Every figure is a [`Figure`]: a list of panels ([`LinePlot`], [`HemispherePlot`],
//!   [`PolarPlot`]) laid out in a grid. [`encode`] picks the format from the file extension
//!   (`.png` or `.svg`, or both for any other name) and returns each file's name and bytes.
//! * Raster content (the hemisphere images) is composited under the vector drawing: copied into
//!   the bitmap for PNG, embedded as a base64 PNG `<image>` for SVG.
//!
//! ```
//! use gonio_plot::figures::fresnel_dielectric_figure;
//!
//! // R_s, R_p and R of glass against the angle of incidence, with Brewster's angle marked.
//! let figure = fresnel_dielectric_figure(1.5, "glass");
//! let png = figure.to_png().unwrap();
//! assert!(png.starts_with(b"\x89PNG"));
//! assert!(figure.to_svg().unwrap().contains("<svg"));
//! ```

#![warn(missing_docs)]

mod colormap;
pub mod diffuse_figures;
pub mod figures;
mod hemisphere;
mod line;
mod polar;

pub use colormap::{colormap, cyclic, diverging, to_rgb8, viridis};
pub use hemisphere::{DiskImage, DiskMarker, HemispherePlot, MarkerKind, Pixels};
pub use line::{LegendPosition, LinePlot, Series, VLine};
pub use polar::{PolarArrow, PolarCurve, PolarPlot};

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// The font family name every plot uses.
pub const FONT: &str = "sans-serif";
static FONT_BYTES: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// Registers the embedded font with plotters (once per process).
pub fn ensure_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_err() {
            // The font is compiled in; failing to parse it is a build defect, tested below.
            panic!("the embedded DejaVu Sans font does not parse");
        }
    });
}

/// Errors from drawing or writing a plot.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The output path names no file.
    #[error("{0}: not a file name for a plot (use NAME.png, NAME.svg or NAME for both)")]
    UnknownFormat(PathBuf),
    /// plotters reported an error.
    #[error("drawing failed: {0}")]
    Draw(String),
    /// Nothing to draw, or inconsistent input.
    #[error("{0}")]
    Invalid(String),
}

fn draw_err<E: std::fmt::Debug>(e: E) -> PlotError {
    PlotError::Draw(format!("{e:?}"))
}

/// An RGB raster to composite at pixel position (x, y) of the figure.
#[derive(Clone, Debug, PartialEq)]
pub struct Raster {
    /// Left edge, pixels.
    pub x: i32,
    /// Top edge, pixels.
    pub y: i32,
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// RGB8, row-major; `None` pixels stay as they are (transparent).
    pub rgb: Vec<Option<[u8; 3]>>,
}

/// One panel of a figure.
#[derive(Clone, Debug)]
pub enum Panel {
    /// Curves against an x axis.
    Line(LinePlot),
    /// Disks of a hemisphere slice with a colour bar.
    Hemisphere(HemispherePlot),
    /// Lobes in the plane of incidence.
    Polar(PolarPlot),
}

/// A figure: a title and panels in a grid of `columns` columns, each panel `panel_size` pixels.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Printed above the panels (may be empty).
    pub title: String,
    /// The panels, row by row.
    pub panels: Vec<Panel>,
    /// Panels per row.
    pub columns: usize,
    /// Size of each panel, pixels.
    pub panel_size: (u32, u32),
}

const TITLE_H: u32 = 40;

impl Figure {
    /// A figure of one panel.
    pub fn single(panel: Panel, size: (u32, u32)) -> Self {
        Self {
            title: String::new(),
            panels: vec![panel],
            columns: 1,
            panel_size: size,
        }
    }

    /// Total size in pixels.
    pub fn size(&self) -> (u32, u32) {
        let cols = self.columns.clamp(1, self.panels.len().max(1));
        let rows = self.panels.len().div_ceil(cols).max(1);
        let title = if self.title.is_empty() { 0 } else { TITLE_H };
        (
            self.panel_size.0 * cols as u32,
            self.panel_size.1 * rows as u32 + title,
        )
    }

    fn panel_origin(&self, k: usize) -> (i32, i32) {
        let cols = self.columns.clamp(1, self.panels.len().max(1));
        let title = if self.title.is_empty() { 0 } else { TITLE_H };
        (
            (k % cols) as i32 * self.panel_size.0 as i32,
            (k / cols) as i32 * self.panel_size.1 as i32 + title as i32,
        )
    }

    /// The rasters of all panels, in figure pixel coordinates.
    fn rasters(&self) -> Vec<Raster> {
        let mut out = vec![];
        for (k, p) in self.panels.iter().enumerate() {
            if let Panel::Hemisphere(h) = p {
                let (ox, oy) = self.panel_origin(k);
                for mut r in h.rasters(self.panel_size) {
                    r.x += ox;
                    r.y += oy;
                    out.push(r);
                }
            }
        }
        out
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        ensure_font();
        let (w, _) = self.size();
        let area = if self.title.is_empty() {
            root.clone()
        } else {
            let (top, rest) = root.split_vertically(TITLE_H);
            let size = fitting_size(&self.title, 22, w.saturating_sub(20));
            top.draw(&Text::new(
                self.title.clone(),
                (w as i32 / 2, 10),
                TextStyle::from((FONT, size).into_font()).pos(plotters::style::text_anchor::Pos::new(
                    plotters::style::text_anchor::HPos::Center,
                    plotters::style::text_anchor::VPos::Top,
                )),
            ))
            .map_err(draw_err)?;
            rest
        };
        for (k, p) in self.panels.iter().enumerate() {
            let (ox, oy) = self.panel_origin(k);
            let title = if self.title.is_empty() { 0 } else { TITLE_H as i32 };
            let sub = area
                .clone()
                .shrink((ox, oy - title), (self.panel_size.0, self.panel_size.1));
            match p {
                Panel::Line(l) => l.draw(&sub)?,
                Panel::Hemisphere(h) => h.draw(&sub)?,
                Panel::Polar(pp) => pp.draw(&sub)?,
            }
        }
        Ok(())
    }

    /// Renders to PNG bytes.
    pub fn to_png(&self) -> Result<Vec<u8>, PlotError> {
        let (w, h) = self.size();
        let mut buf = vec![255u8; (w * h * 3) as usize];
        for r in self.rasters() {
            blit(&mut buf, w, h, &r);
        }
        {
            let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
            self.draw(&root)?;
            root.present().map_err(draw_err)?;
        }
        encode_png(&buf, w, h)
    }

    /// Renders to an SVG document.
    pub fn to_svg(&self) -> Result<String, PlotError> {
        let (w, h) = self.size();
        let mut s = String::new();
        {
            let root = SVGBackend::with_string(&mut s, (w, h)).into_drawing_area();
            self.draw(&root)?;
            root.present().map_err(draw_err)?;
        }
        // Background and rasters go first, under everything plotters drew.
        let mut under = format!(r##"<rect x="0" y="0" width="{w}" height="{h}" fill="#FFFFFF"/>"##);
        for r in self.rasters() {
            let (png, rw, rh) = raster_png(&r)?;
            under.push_str(&format!(
                r#"<image x="{}" y="{}" width="{rw}" height="{rh}" image-rendering="pixelated" href="data:image/png;base64,{}"/>"#,
                r.x,
                r.y,
                base64(&png)
            ));
        }
        let Some(open_end) = s.find("<svg").and_then(|i| s[i..].find('>').map(|j| i + j + 1)) else {
            return Err(PlotError::Draw("plotters produced no <svg> element".into()));
        };
        s.insert_str(open_end, &under);
        Ok(s)
    }
}

fn blit(buf: &mut [u8], w: u32, h: u32, r: &Raster) {
    for y in 0..r.height {
        for x in 0..r.width {
            let (px, py) = (r.x + x as i32, r.y + y as i32);
            if px < 0 || py < 0 || px >= w as i32 || py >= h as i32 {
                continue;
            }
            if let Some(c) = r.rgb[(y * r.width + x) as usize] {
                let k = ((py as u32 * w + px as u32) * 3) as usize;
                buf[k..k + 3].copy_from_slice(&c);
            }
        }
    }
}

fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, PlotError> {
    png_bytes(rgb, w, h, png::ColorType::Rgb)
}

/// A raster as an RGBA PNG (transparent where `None`).
fn raster_png(r: &Raster) -> Result<(Vec<u8>, u32, u32), PlotError> {
    let mut rgba = Vec::with_capacity(r.rgb.len() * 4);
    for p in &r.rgb {
        match p {
            Some([a, b, c]) => rgba.extend([*a, *b, *c, 255]),
            None => rgba.extend([0, 0, 0, 0]),
        }
    }
    Ok((
        png_bytes(&rgba, r.width, r.height, png::ColorType::Rgba)?,
        r.width,
        r.height,
    ))
}

/// 8-bit samples of `color` as PNG bytes.
fn png_bytes(samples: &[u8], w: u32, h: u32, color: png::ColorType) -> Result<Vec<u8>, PlotError> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, w, h);
    encoder.set_color(color);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(draw_err)?;
    writer.write_image_data(samples).map_err(draw_err)?;
    writer.finish().map_err(draw_err)?;
    Ok(out)
}

/// Decodes an 8-bit RGB PNG of ours (the tests read figures back): (width, height, samples).
#[cfg(test)]
fn decode_rgb_png(png_bytes: &[u8]) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::Cursor::new(png_bytes));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(
        (info.color_type, info.bit_depth),
        (png::ColorType::Rgb, png::BitDepth::Eight)
    );
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

/// Standard base64 (RFC 4648 §4, padded), for PNGs embedded in SVG `data:` URIs.
fn base64(data: &[u8]) -> String {
    use ::base64::Engine;
    ::base64::engine::general_purpose::STANDARD.encode(data)
}

/// The files a figure is saved as, each with its encoded bytes: PNG or SVG chosen by `path`'s
/// extension. Any other path (no extension, or another one such as `glass-1.5`) gives both
/// `path.png` and `path.svg`, in that order. Nothing is written: the caller writes the files.
pub fn encode(figure: &Figure, path: &Path) -> Result<Vec<(PathBuf, Vec<u8>)>, PlotError> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
    {
        Some(e) if e == "png" => Ok(vec![(path.to_path_buf(), figure.to_png()?)]),
        Some(e) if e == "svg" => Ok(vec![(path.to_path_buf(), figure.to_svg()?.into_bytes())]),
        _ => {
            if path.file_name().is_none() {
                return Err(PlotError::UnknownFormat(path.to_path_buf()));
            }
            let with = |ext: &str| {
                let mut s = path.as_os_str().to_owned();
                s.push(ext);
                PathBuf::from(s)
            };
            Ok(vec![
                (with(".png"), figure.to_png()?),
                (with(".svg"), figure.to_svg()?.into_bytes()),
            ])
        }
    }
}

/// The colours of successive series (Okabe–Ito, readable by colour-blind viewers).
pub fn series_color(k: usize) -> RGBColor {
    const C: [(u8, u8, u8); 8] = [
        (0, 114, 178),
        (213, 94, 0),
        (0, 158, 115),
        (204, 121, 167),
        (230, 159, 0),
        (86, 180, 233),
        (0, 0, 0),
        (240, 228, 66),
    ];
    let (r, g, b) = C[k % C.len()];
    RGBColor(r, g, b)
}

/// A text style of the plot font.
pub(crate) fn font(size: u32) -> TextStyle<'static> {
    TextStyle::from((FONT, size).into_font())
}

/// Width in pixels of `text` in the plot font at `size` (an estimate of 0.6 em per character
/// if the font cannot measure it).
pub fn text_width(text: &str, size: u32) -> u32 {
    ensure_font();
    FontDesc::new(FontFamily::Name(FONT), size as f64, FontStyle::Normal)
        .box_size(text)
        .map(|(w, _)| w)
        .unwrap_or((text.chars().count() as f64 * size as f64 * 0.6).ceil() as u32)
}

/// `text` broken into lines no wider than `max_width` pixels at font `size`: preferably after a
/// clause's "; " (so a phrase stays on one line), else at spaces (a single word wider than that
/// keeps a line of its own). Joining the lines with spaces gives `text` back.
pub fn wrap_text(text: &str, size: u32, max_width: u32) -> Vec<String> {
    let fits = |s: &str| text_width(s, size) <= max_width;
    let mut lines: Vec<String> = vec![];
    let mut line = String::new();
    let clauses: Vec<String> = {
        let parts: Vec<&str> = text.split("; ").collect();
        let n = parts.len();
        parts
            .iter()
            .enumerate()
            .map(|(k, c)| if k + 1 < n { format!("{c};") } else { c.to_string() })
            .collect()
    };
    for clause in clauses.iter().filter(|c| !c.trim().is_empty()) {
        let joined = if line.is_empty() {
            clause.clone()
        } else {
            format!("{line} {clause}")
        };
        if fits(&joined) {
            line = joined;
            continue;
        }
        if fits(clause) {
            if !line.is_empty() {
                lines.push(std::mem::take(&mut line));
            }
            line = clause.clone();
            continue;
        }
        // A clause longer than a line: break it at spaces.
        for word in clause.split(' ').filter(|w| !w.is_empty()) {
            let candidate = if line.is_empty() {
                word.to_string()
            } else {
                format!("{line} {word}")
            };
            if line.is_empty() || fits(&candidate) {
                line = candidate;
            } else {
                lines.push(std::mem::replace(&mut line, word.to_string()));
            }
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// The largest font size ≤ `size` (and ≥ 9) at which `text` fits in `max_width` pixels.
pub fn fitting_size(text: &str, size: u32, max_width: u32) -> u32 {
    let mut s = size;
    while s > 9 && text_width(text, s) > max_width {
        s -= 1;
    }
    s
}

/// Line height of wrapped small print at font `size`.
pub(crate) fn line_height(size: u32) -> i32 {
    (size as f64 * 1.3).ceil() as i32
}

/// Draws `lines` centred on `x`, the first line's top at `y`; returns the height used.
pub(crate) fn draw_lines<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    lines: &[String],
    (x, y): (i32, i32),
    size: u32,
    color: RGBColor,
) -> Result<i32, PlotError> {
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let lh = line_height(size);
    for (k, l) in lines.iter().enumerate() {
        area.draw(&Text::new(
            l.clone(),
            (x, y + k as i32 * lh),
            font(size).color(&color).pos(Pos::new(HPos::Center, VPos::Top)),
        ))
        .map_err(draw_err)?;
    }
    Ok(lines.len() as i32 * lh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    #[test]
    fn the_embedded_font_parses() {
        ensure_font();
        let f = FontDesc::new(FontFamily::Name(FONT), 12.0, FontStyle::Normal);
        let (w, _) = f.box_size("gonio").unwrap();
        assert!(w > 10, "text has a width: {w}");
    }
}
