//! A small, dependency-light RGB raster canvas for ALVS pictures: retina maps, attention-field
//! overlays, labels in embedded-graphics' 5x7 bitmap font, simple line plots, and 8-bit RGB PNG
//! output.
//!
//! Coordinates are `i32` with (0, 0) at the top-left; every drawing call clips to the canvas,
//! so drawing partly or wholly off-canvas never panics.

use std::{convert::Infallible, io, ops::Range, path::Path};

use embedded_graphics::{
    mono_font::{ascii::FONT_5X7, MonoFont, MonoTextStyle},
    pixelcolor::BinaryColor,
    prelude::{DrawTarget, Drawable, OriginDimensions, Pixel, Point, Size},
    text::{Baseline, LineHeight, Text, TextStyleBuilder},
};

mod histogram;
pub use histogram::Histogram;

/// An 8-bit RGB colour.
pub type Rgb = [u8; 3];

pub const BLACK: Rgb = [0, 0, 0];
pub const WHITE: Rgb = [255, 255, 255];
/// The colour of plot markers (e.g. alerts).
pub const RED: Rgb = [220, 20, 20];

/// The labels' font: embedded-graphics' ASCII 5x7 (X11 misc-fixed); its 5-pixel cells hold
/// 4-pixel-wide glyphs and the gap, so it adds no spacing of its own.
const LABEL_FONT: MonoFont<'static> = FONT_5X7;
/// Pixels the font puts between two character cells at scale 1.
const CHAR_SPACING: usize = LABEL_FONT.character_spacing as usize;
/// Horizontal advance of one character at scale 1 (the font's cell width and spacing).
pub const CHAR_ADVANCE: usize = LABEL_FONT.character_size.width as usize + CHAR_SPACING;
/// Glyph (cell) height at scale 1.
pub const CHAR_HEIGHT: usize = LABEL_FONT.character_size.height as usize;
/// Distance between text lines at scale 1 (2 blank rows between lines).
const LINE_ADVANCE: usize = CHAR_HEIGHT + 2;

/// An RGB raster image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Canvas {
    pub width: usize,
    pub height: usize,
    /// `width * height` pixels, row after row.
    pub pixels: Vec<Rgb>,
}

/// `[lo, lo + len) ∩ [0, max)` as an index range (empty if `len <= 0`).
fn clip(lo: i64, len: i64, max: usize) -> Range<usize> {
    let max = max as i64;
    lo.clamp(0, max) as usize..lo.saturating_add(len.max(0)).clamp(0, max) as usize
}

impl Canvas {
    /// A `width` x `height` canvas filled with `background`.
    pub fn new(width: usize, height: usize, background: Rgb) -> Self {
        let pixels = vec![background; width * height];
        Self {
            width,
            height,
            pixels,
        }
    }

    fn index(&self, x: i64, y: i64) -> Option<usize> {
        let inside = (0..self.width as i64).contains(&x) && (0..self.height as i64).contains(&y);
        inside.then(|| y as usize * self.width + x as usize)
    }

    /// The pixel at (x, y), or `None` off-canvas.
    pub fn get(&self, x: i32, y: i32) -> Option<Rgb> {
        self.index(x.into(), y.into()).map(|i| self.pixels[i])
    }

    /// Sets one pixel (ignored off-canvas).
    pub fn set(&mut self, x: i32, y: i32, colour: Rgb) {
        self.fill64(x.into(), y.into(), 1, 1, colour);
    }

    fn fill64(&mut self, x: i64, y: i64, w: i64, h: i64, colour: Rgb) {
        let xs = clip(x, w, self.width);
        for row in clip(y, h, self.height) {
            self.pixels[row * self.width..][xs.clone()].fill(colour);
        }
    }

    /// Fills the `w` x `h` rectangle whose top-left corner is (x, y).
    pub fn fill_rect(&mut self, x: i32, y: i32, w: i32, h: i32, colour: Rgb) {
        self.fill64(x.into(), y.into(), w.into(), h.into(), colour);
    }

    /// Draws the 1-pixel border of the `w` x `h` rectangle at (x, y), inside that rectangle.
    pub fn rect_outline(&mut self, x: i32, y: i32, w: i32, h: i32, colour: Rgb) {
        let [x, y, w, h] = [x, y, w, h].map(i64::from);
        if w > 0 && h > 0 {
            self.fill64(x, y, w, 1, colour);
            self.fill64(x, y + h - 1, w, 1, colour);
            self.fill64(x, y, 1, h, colour);
            self.fill64(x + w - 1, y, 1, h, colour);
        }
    }

    /// Draws a Bresenham line from (x0, y0) to (x1, y1), both ends included.
    pub fn line(&mut self, x0: i32, y0: i32, x1: i32, y1: i32, colour: Rgb) {
        let Some([x0, y0, x1, y1]) = self.clip_line([x0, y0, x1, y1].map(i64::from)) else {
            return;
        };
        let (dx, sx) = ((x1 - x0).abs(), (x1 - x0).signum());
        let (dy, sy) = (-(y1 - y0).abs(), (y1 - y0).signum());
        let (mut x, mut y, mut err) = (x0, y0, dx + dy);
        loop {
            if let Some(i) = self.index(x, y) {
                self.pixels[i] = colour;
            }
            if x == x1 && y == y1 {
                break;
            }
            let e2 = 2 * err;
            if e2 >= dy {
                (err, x) = (err + dy, x + sx);
            }
            if e2 <= dx {
                (err, y) = (err + dx, y + sy);
            }
        }
    }

    /// Lines with ends near the canvas are drawn exactly (clipped per pixel); lines reaching far
    /// outside are first cut to the canvas (Liang-Barsky) so that their cost stays bounded.
    fn clip_line(&self, [x0, y0, x1, y1]: [i64; 4]) -> Option<[i64; 4]> {
        let (w, h) = (self.width as i64, self.height as i64);
        let m = 2 * (w + h);
        let near = |v: i64, lim: i64| (-m..=lim + m).contains(&v);
        if near(x0, w) && near(x1, w) && near(y0, h) && near(y1, h) {
            return Some([x0, y0, x1, y1]);
        }
        let [fx, fy, dx, dy] = [x0, y0, x1 - x0, y1 - y0].map(|v| v as f64);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let (right, bottom) = ((w - 1) as f64 - fx, (h - 1) as f64 - fy);
        for (p, q) in [(-dx, fx), (dx, right), (-dy, fy), (dy, bottom)] {
            match p {
                0.0 if q < 0.0 => return None,
                0.0 => {}
                _ if p < 0.0 => t0 = t0.max(q / p),
                _ => t1 = t1.min(q / p),
            }
        }
        let at = |t: f64| [(fx + t * dx).round() as i64, (fy + t * dy).round() as i64];
        let ([a, b], [c, d]) = (at(t0), at(t1));
        (t0 <= t1 && w > 0 && h > 0).then_some([a, b, c, d])
    }

    /// A plus-shaped marker centred on (x, y) with arms `size` pixels long (e.g. a centroid).
    pub fn cross(&mut self, x: i32, y: i32, size: i32, colour: Rgb) {
        let (x, y, s) = (i64::from(x), i64::from(y), i64::from(size.max(0)));
        self.fill64(x - s, y, 2 * s + 1, 1, colour);
        self.fill64(x, y - s, 1, 2 * s + 1, colour);
    }

    /// Writes `s` in embedded-graphics' 5x7 font with its top-left corner at (x, y); each font
    /// pixel is `scale` x `scale` canvas pixels (0 counts as 1). `'\n'` starts a new line (a
    /// `'\r'` before it is dropped); characters outside printable ASCII are drawn as `'?'`.
    pub fn text(&mut self, x: i32, y: i32, s: &str, colour: Rgb, scale: usize) {
        let k = scale.clamp(1, 1024) as i64;
        let mut view = Scaled {
            canvas: self,
            origin: (x.into(), y.into()),
            k,
            colour,
        };
        let Ok(_) = label_text(s).draw(&mut view);
    }

    /// The (width, height) in pixels that [`Canvas::text`] covers for `s` at `scale`: the widest
    /// line's cells (without spacing after the last) by the lines' advance and one cell height.
    pub fn text_size(s: &str, scale: usize) -> (usize, usize) {
        let k = scale.clamp(1, 1024);
        let line_len = |l: &str| l.strip_suffix('\r').unwrap_or(l).chars().count();
        let widest = s.split('\n').map(line_len).max().unwrap_or(0);
        let lines = s.split('\n').count();
        let w = (widest * CHAR_ADVANCE).saturating_sub(CHAR_SPACING) * k;
        let h = ((lines - 1) * LINE_ADVANCE + CHAR_HEIGHT) * k;
        if s.is_empty() {
            (0, 0)
        } else {
            (w, h)
        }
    }

    /// Copies `other` onto this canvas with its top-left corner at (x, y), clipped.
    pub fn blit(&mut self, other: &Canvas, x: i32, y: i32) {
        let (x, y) = (i64::from(x), i64::from(y));
        let xs = clip(x, other.width as i64, self.width);
        let sx = (xs.start as i64 - x) as usize;
        for row in clip(y, other.height as i64, self.height).filter(|_| !xs.is_empty()) {
            let src = (row as i64 - y) as usize * other.width + sx;
            let src = &other.pixels[src..][..xs.len()];
            self.pixels[row * self.width..][xs.clone()].copy_from_slice(src);
        }
    }

    /// `panels` left to right on one white canvas as tall as the tallest (at least 1x1).
    pub fn side_by_side(panels: &[Canvas]) -> Canvas {
        let w: usize = panels.iter().map(|p| p.width).sum();
        let h = panels.iter().map(|p| p.height).max().unwrap_or(1);
        let mut c = Canvas::new(w.max(1), h, WHITE);
        let mut x = 0;
        for p in panels {
            c.blit(p, x, 0);
            x += p.width as i32;
        }
        c
    }

    /// `panels` top to bottom on one white canvas as wide as the widest (at least 1x1).
    pub fn stacked(panels: &[Canvas]) -> Canvas {
        let w = panels.iter().map(|p| p.width).max().unwrap_or(1);
        let h: usize = panels.iter().map(|p| p.height).sum();
        let mut c = Canvas::new(w.max(1), h.max(1), WHITE);
        let mut y = 0;
        for p in panels {
            c.blit(p, 0, y);
            y += p.height as i32;
        }
        c
    }

    /// Saves the canvas as an 8-bit RGB PNG file (PNG encoding errors become `io::Error`s).
    pub fn save_png(&self, path: impl AsRef<Path>) -> io::Result<()> {
        let dim = |v: usize| u32::try_from(v).map_err(|_| io::Error::other("canvas too large"));
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, dim(self.width)?, dim(self.height)?);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(self.pixels.as_flattened())?;
        writer.finish()?;
        std::fs::write(path, bytes)
    }
}

/// `s` laid out by embedded-graphics in [`LABEL_FONT`], top-left corner at font pixel (0, 0),
/// lines [`LINE_ADVANCE`] apart.
fn label_text(s: &str) -> Text<'_, MonoTextStyle<'static, BinaryColor>> {
    let style = MonoTextStyle::new(&LABEL_FONT, BinaryColor::On);
    let layout = TextStyleBuilder::new()
        .baseline(Baseline::Top)
        .line_height(LineHeight::Pixels(LINE_ADVANCE as u32))
        .build();
    Text::with_text_style(s, Point::zero(), style, layout)
}

/// The canvas as embedded-graphics sees it when drawing text: font pixel (0, 0) is canvas pixel
/// `origin`, and each font pixel a `k` x `k` block of `colour` (clipped like every drawing call).
struct Scaled<'a> {
    canvas: &'a mut Canvas,
    origin: (i64, i64),
    k: i64,
    colour: Rgb,
}

impl DrawTarget for Scaled<'_> {
    type Color = BinaryColor;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<BinaryColor>>,
    {
        let ((x, y), k) = (self.origin, self.k);
        for Pixel(p, _) in pixels.into_iter().filter(|p| p.1.is_on()) {
            let (px, py) = (x + i64::from(p.x) * k, y + i64::from(p.y) * k);
            self.canvas.fill64(px, py, k, k, self.colour);
        }
        Ok(())
    }
}

impl OriginDimensions for Scaled<'_> {
    /// The font pixels from the origin to the canvas' right and bottom edges (drawing elsewhere
    /// is clipped, not refused).
    fn size(&self) -> Size {
        let fit = |len: usize, at: i64| {
            let px = (len as i64 - at).max(0);
            u32::try_from((px + self.k - 1) / self.k).unwrap_or(u32::MAX)
        };
        let (w, h) = (self.canvas.width, self.canvas.height);
        Size::new(fit(w, self.origin.0), fit(h, self.origin.1))
    }
}

/// A `w*scale` x `h*scale` map of `values` (row-major), each value painted by
/// `paint(value, level)` with `level = 255 * |value| / max|values|`.
fn map_values(values: &[i32], w: usize, h: usize, k: usize, paint: fn(i32, u32) -> Rgb) -> Canvas {
    assert_eq!(values.len(), w * h, "a {w}x{h} map needs {} values", w * h);
    let (k, abs) = (k.max(1), |v: i32| u64::from(v.unsigned_abs()));
    let max = values.iter().map(|&v| abs(v)).max().unwrap_or(0).max(1);
    let level = |v: i32| ((abs(v) * 255 + max / 2) / max) as u32;
    let mut canvas = Canvas::new(w * k, h * k, BLACK);
    for (i, px) in canvas.pixels.iter_mut().enumerate() {
        let v = values[(i / (w * k) / k) * w + i % (w * k) / k];
        *px = paint(v, level(v));
    }
    canvas
}

/// Grey-level map of `w * h` row-major values, each a `scale` x `scale` block: 0 is black, the
/// largest magnitude white, linear in `|v|` (so negative values show by magnitude; see
/// [`signed_map`]). All-zero input gives a black image. Panics unless `values.len() == w * h`.
pub fn grey_map(values: &[i32], w: usize, h: usize, scale: usize) -> Canvas {
    map_values(values, w, h, scale, |_, l| [l as u8; 3])
}

/// Like [`grey_map`] but signed, symmetric around 0 (black): positive values go red then
/// yellow, negative values blue then cyan, both normalised by the largest magnitude.
pub fn signed_map(values: &[i32], w: usize, h: usize, scale: usize) -> Canvas {
    map_values(values, w, h, scale, |v, l| {
        let (strong, extra) = ((2 * l).min(255) as u8, (2 * l).saturating_sub(255) as u8);
        if v >= 0 {
            [strong, extra, 0]
        } else {
            [0, extra, strong]
        }
    })
}

/// Distinct colours for attention fields 0..=6 and plot series (cycling after 8), readable on
/// dark maps and white plots alike; none is the marker [`RED`].
pub fn colour_cycle(i: usize) -> Rgb {
    #[rustfmt::skip]
    const PALETTE: [Rgb; 8] = [[31, 119, 230], [255, 127, 14], [44, 170, 44], [160, 90, 220],
        [0, 175, 175], [225, 60, 170], [170, 120, 30], [120, 120, 120]];
    PALETTE[i % PALETTE.len()]
}

const INK: Rgb = [30, 30, 30];
const GRID: Rgb = [228, 228, 228];

/// A line plot on white of named series over x = sample index, with tick labels, a legend, a
/// title and optional markers (thin red ticks along the bottom, e.g. frames where an alert
/// fired). Non-finite values are skipped and break the line.
#[derive(Clone, Debug, Default)]
pub struct Plot {
    pub title: String,
    pub x_label: String,
    pub series: Vec<(String, Vec<f32>)>,
    /// Legend text for the markers.
    pub marker_label: String,
    /// x positions (sample indices) of the markers.
    pub markers: Vec<usize>,
    /// Fixed y range (used if finite with lo < hi); `None` fits the data.
    pub y_range: Option<(f32, f32)>,
    /// A strip along the top of the plot area, one colour per sample (`None`: blank), e.g. a
    /// state machine's state.
    pub band: Vec<Option<Rgb>>,
    /// The band's legend: a name per colour.
    pub band_legend: Vec<(String, Rgb)>,
}

/// A "nice" step (1, 2 or 5 times a power of ten) cutting `span > 0` into about `parts` pieces.
fn nice_step(span: f64, parts: f64) -> f64 {
    let mag = 10f64.powf((span / parts).log10().floor());
    let f = span / parts / mag;
    let nice = [1.0, 2.0, 5.0, 10.0];
    mag * nice.into_iter().find(|&n| f <= n * 1.0001).unwrap_or(10.0)
}

/// Tick values `k * step` inside `[lo, hi]` (at most 100).
fn ticks(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step - 1e-9).ceil();
    let tick = |i: u8| (first + f64::from(i)) * step + 0.0; // + 0.0 turns -0 into 0
    let inside = |v: &f64| *v <= hi + step * 1e-9;
    (0..100).map(tick).take_while(inside).collect()
}

impl Plot {
    /// An empty plot with a title.
    pub fn new(title: &str) -> Self {
        Self {
            title: title.into(),
            ..Self::default()
        }
    }

    /// Adds a named series (y values at x = 0, 1, 2, ...).
    pub fn series(mut self, name: &str, ys: &[f32]) -> Self {
        self.series.push((name.into(), ys.to_vec()));
        self
    }

    /// Adds markers at the given x positions, called `label` in the legend.
    pub fn markers(mut self, label: &str, xs: &[usize]) -> Self {
        self.marker_label = label.into();
        self.markers.extend_from_slice(xs);
        self
    }

    /// Adds a band: `colours[i]` over sample i, `legend` naming the colours.
    pub fn band(mut self, colours: &[Option<Rgb>], legend: &[(&str, Rgb)]) -> Self {
        self.band = colours.to_vec();
        self.band_legend = legend.iter().map(|&(n, c)| (n.into(), c)).collect();
        self
    }

    /// Sets the x-axis label.
    pub fn x_label(mut self, label: &str) -> Self {
        self.x_label = label.into();
        self
    }

    /// Fixes the y range (ignored unless finite with `lo < hi`).
    pub fn y_range(mut self, lo: f32, hi: f32) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// The y range to draw, and its tick step.
    fn y_axis(&self) -> (f64, f64, f64) {
        let valid = |(l, h): &(f32, f32)| l.is_finite() && h.is_finite() && l < h;
        if let Some((lo, hi)) = self.y_range.filter(valid) {
            let (lo, hi) = (f64::from(lo), f64::from(hi));
            return (lo, hi, nice_step(hi - lo, 5.0));
        }
        let all = self.series.iter().flat_map(|s| &s.1);
        let ys = all.filter(|v| v.is_finite());
        let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(f64::from(v)), h.max(f64::from(v)))
        });
        let d = if lo.abs() < 1e-9 { 1.0 } else { lo.abs() * 0.1 };
        let (lo, hi) = match lo.partial_cmp(&hi) {
            Some(std::cmp::Ordering::Less) => (lo, hi),
            Some(_) => (lo - d, hi + d), // a flat series
            None => (0.0, 1.0),          // no finite data
        };
        let (lo, hi) = (lo - (hi - lo) * 0.04, hi + (hi - lo) * 0.04); // keep data off the frame
        let step = nice_step(hi - lo, 5.0);
        ((lo / step).floor() * step, (hi / step).ceil() * step, step)
    }

    /// Draws the plot on a new `width` x `height` canvas; text is doubled from 900 x 450 up.
    pub fn render(&self, width: usize, height: usize) -> Canvas {
        let mut c = Canvas::new(width, height, WHITE);
        let k: usize = if width >= 900 && height >= 450 { 2 } else { 1 };
        let (w, h, s) = (width as i32, height as i32, k as i32);
        let (line_h, margin, tick, row) = (10 * s, 6 * s, 3 * s, 12 * s);
        let text_w = |t: &str| Canvas::text_size(t, k).0 as i32;
        c.text((w - text_w(&self.title)) / 2, margin, &self.title, INK, k);
        let mut top = margin + if self.title.is_empty() { 0 } else { row };

        // Legend: a swatch and a name per series (then the markers, then the band's colours),
        // wrapped into rows.
        let names = self.series.iter().map(|s| s.0.as_str());
        let mut entries: Vec<_> = names
            .zip((0..).map(|i| Swatch::Line(colour_cycle(i))))
            .collect();
        if !self.markers.is_empty() {
            entries.push((self.marker_label.as_str(), Swatch::Marker));
        }
        for (name, colour) in &self.band_legend {
            entries.push((name.as_str(), Swatch::Block(*colour)));
        }
        let mut x = margin;
        for (name, colour) in &entries {
            if x > margin && x + 14 * s + text_w(name) > w - margin {
                (x, top) = (margin, top + line_h);
            }
            match colour {
                Swatch::Line(colour) => c.fill_rect(x, top + 3 * s, 10 * s, 2 * s, *colour),
                Swatch::Marker => c.fill_rect(x + 4 * s, top, s, 7 * s, RED),
                Swatch::Block(colour) => c.fill_rect(x, top, 10 * s, 7 * s, *colour),
            }
            c.text(x + 14 * s, top, name, INK, k);
            x += 26 * s + text_w(name);
        }
        top += if entries.is_empty() { 0 } else { row };

        // Ranges, ticks and the plot area.
        let lens = self.series.iter().map(|s| s.1.len());
        let n = lens
            .chain(self.markers.iter().map(|m| m + 1))
            .chain([self.band.len()]);
        let x_max = n.max().unwrap_or(0).saturating_sub(1).max(1) as f64;
        let x_ticks = ticks(0.0, x_max, nice_step(x_max, 6.0).max(1.0));
        let (y_lo, y_hi, y_step) = self.y_axis();
        let y_ticks = ticks(y_lo, y_hi, y_step);
        let decimals = (-y_step.log10().floor()).clamp(0.0, 8.0) as usize;
        let y_labels: Vec<String> = y_ticks.iter().map(|v| format!("{v:.decimals$}")).collect();
        let x_labels: Vec<String> = x_ticks.iter().map(|v| format!("{v:.0}")).collect();
        let left = margin + y_labels.iter().map(|l| text_w(l)).max().unwrap_or(0) + 2 * tick;
        let right = w - margin - x_labels.last().map_or(0, |l| text_w(l) / 2);
        let bottom = h - margin - line_h - tick - if self.x_label.is_empty() { 0 } else { line_h };
        let (pw, ph) = (right - left, bottom - top);
        if pw < 8 || ph < 8 {
            return c;
        }
        // Positions inside the plot area.
        let (x_scale, y_scale) = (f64::from(pw - 1) / x_max, f64::from(ph - 1) / (y_hi - y_lo));
        let px = |v: f64| (v * x_scale).round() as i32;
        let py = |v: f64| ((y_hi - v) * y_scale).clamp(-1e7, 1e7).round() as i32;

        // The plot area is drawn on its own canvas, which clips the data to it.
        let mut area = Canvas::new(pw as usize, ph as usize, WHITE);
        for &v in &x_ticks {
            area.line(px(v), 0, px(v), ph, GRID);
        }
        for &v in &y_ticks {
            area.line(0, py(v), pw, py(v), GRID);
        }
        let band_h = (ph / 16).max(4 * s);
        for (j, colour) in self.band.iter().enumerate() {
            if let Some(colour) = colour {
                let (x0, x1) = (px(j as f64), px(j as f64 + 1.0));
                area.fill_rect(x0, 0, (x1 - x0).max(1), band_h, *colour);
            }
        }
        let marker_h = (ph / 10).max(4 * s);
        for &m in &self.markers {
            area.fill_rect(px(m as f64), ph - marker_h, s, marker_h, RED);
        }
        for (colour, (_, ys)) in (0..).map(colour_cycle).zip(&self.series) {
            let mut prev = None;
            for (j, &v) in ys.iter().enumerate() {
                let p = (px(j as f64), py(f64::from(v)));
                let q = prev.unwrap_or(p);
                if !v.is_finite() {
                    prev = None;
                    continue;
                } else if prev.is_none() && ys.get(j + 1).is_none_or(|v| !v.is_finite()) {
                    area.cross(p.0, p.1, s, colour); // an isolated point
                }
                for t in 0..s {
                    area.line(q.0, q.1 + t, p.0, p.1 + t, colour);
                }
                prev = Some(p);
            }
        }
        c.blit(&area, left, top);

        // Axes, ticks and labels.
        c.fill_rect(left - 1, top, 1, ph + 1, INK);
        c.fill_rect(left - 1, bottom, pw + 1, 1, INK);
        for (&v, label) in y_ticks.iter().zip(&y_labels) {
            let (y, x) = (top + py(v), left - 1 - tick);
            c.fill_rect(x, y, tick, 1, INK);
            c.text(x - 2 * s - text_w(label), y - 3 * s, label, INK, k);
        }
        for (&v, label) in x_ticks.iter().zip(&x_labels) {
            let x = left + px(v);
            c.fill_rect(x, bottom + 1, 1, tick, INK);
            c.text(x - text_w(label) / 2, bottom + tick + 3 * s, label, INK, k);
        }
        let (xl, xl_y) = (&self.x_label, bottom + tick + 3 * s + line_h);
        c.text(left + (pw - text_w(xl)) / 2, xl_y, xl, INK, k);
        c
    }
}

/// A legend entry's mark: a series' line, the markers' tick, a band's colour.
enum Swatch {
    Line(Rgb),
    Marker,
    Block(Rgb),
}

#[cfg(test)]
mod tests {
    use super::*;

    fn count(c: &Canvas, colour: Rgb) -> usize {
        c.pixels.iter().filter(|&&p| p == colour).count()
    }

    #[test]
    fn stacked_panels_keep_their_order_and_pad_with_white() {
        let (top, bottom) = (Canvas::new(6, 2, BLACK), Canvas::new(3, 4, RED));
        let c = Canvas::stacked(&[top, bottom]);
        assert_eq!((c.width, c.height), (6, 6));
        assert_eq!(c.get(5, 1), Some(BLACK));
        assert_eq!(c.get(0, 2), Some(RED));
        assert_eq!(c.get(2, 5), Some(RED));
        assert_eq!(c.get(3, 5), Some(WHITE), "narrower panel padded");
        let empty = Canvas::stacked(&[]);
        assert_eq!((empty.width, empty.height), (1, 1));
    }

    #[test]
    fn drawing_off_canvas_changes_nothing() {
        let (mut c, other) = (Canvas::new(10, 8, BLACK), Canvas::new(4, 4, WHITE));
        let (min, max) = (i32::MIN, i32::MAX);
        c.fill_rect(-5, -5, 3, 3, WHITE);
        c.fill_rect(max - 1, max - 1, max, max, WHITE);
        c.rect_outline(20, 2, 5, 5, WHITE);
        c.rect_outline(min, min, max, max, WHITE);
        c.line(-100, -100, -5, 50, WHITE);
        c.line(min, min, max, min, WHITE);
        c.line(min, 20, max, 9, WHITE);
        c.cross(-10, -10, 3, WHITE);
        c.cross(max, min, max, WHITE);
        c.text(100, 0, "L_ON t=37", WHITE, 3);
        c.text(max, max, "AF1", WHITE, usize::MAX);
        c.blit(&other, -4, 0);
        c.blit(&other, max, min);
        c.set(10, 0, WHITE);
        c.set(-1, 3, WHITE);
        assert_eq!(count(&c, WHITE), 0);
        assert_eq!(c.get(10, 0), None);
    }

    #[test]
    fn partly_visible_shapes_are_clipped() {
        let mut c = Canvas::new(10, 8, BLACK);
        c.fill_rect(-3, 5, 6, 10, WHITE);
        assert_eq!(count(&c, WHITE), 3 * 3);
        let mut c = Canvas::new(10, 8, BLACK);
        c.blit(&Canvas::new(4, 4, WHITE), 8, -1);
        assert_eq!((count(&c, WHITE), c.get(9, 2)), (2 * 3, Some(WHITE)));
        let mut c = Canvas::new(10, 8, BLACK);
        c.line(-1_000_000_000, 4, 1_000_000_000, 4, WHITE);
        assert_eq!(count(&c, WHITE), 10);
        assert!((0..10).all(|x| c.get(x, 4) == Some(WHITE)));
    }

    #[test]
    fn shapes_set_the_expected_pixels() {
        for [x0, y0, x1, y1] in [
            [1, 1, 8, 3],
            [8, 6, 2, 0],
            [3, 7, 4, 0],
            [5, 5, 5, 5],
            [0, 7, 9, 0],
        ] {
            let mut c = Canvas::new(10, 8, BLACK);
            c.line(x0, y0, x1, y1, WHITE);
            assert_eq!((c.get(x0, y0), c.get(x1, y1)), (Some(WHITE), Some(WHITE)));
            let len = (x1 - x0).abs().max((y1 - y0).abs()) + 1;
            assert_eq!(count(&c, WHITE), len as usize);
        }
        let mut c = Canvas::new(10, 8, BLACK);
        c.rect_outline(1, 1, 4, 3, WHITE);
        assert_eq!((count(&c, WHITE), c.get(2, 2)), (10, Some(BLACK)));
        let mut c = Canvas::new(10, 8, BLACK);
        c.cross(5, 4, 2, WHITE);
        assert_eq!(count(&c, WHITE), 9);
    }

    #[test]
    fn maps_normalise_by_the_largest_magnitude() {
        let c = grey_map(&[0, 5, -10, 10], 2, 2, 3);
        assert_eq!(
            (c.width, c.height, c.get(2, 2), c.get(3, 0)),
            (6, 6, Some(BLACK), Some([128; 3]))
        );
        assert_eq!((c.get(0, 5), c.get(5, 5)), (Some(WHITE), Some(WHITE)));
        assert_eq!(count(&grey_map(&[0; 6], 3, 2, 1), BLACK), 6);
        assert_eq!(grey_map(&[i32::MIN, 0], 2, 1, 0).get(0, 0), Some(WHITE));
        let c = signed_map(&[-4, 0, 2, 4], 4, 1, 1);
        assert_eq!(c.pixels, [[0, 255, 255], BLACK, [255, 1, 0], [255, 255, 0]]);
        assert_eq!(count(&signed_map(&[0; 4], 2, 2, 2), BLACK), 16);
        let colours: Vec<Rgb> = (0..7).map(colour_cycle).collect();
        assert!((0..7).all(|i| (i + 1..7).all(|j| colours[i] != colours[j])));
        assert!(!colours.contains(&RED));
    }

    #[test]
    fn font_covers_the_label_characters() {
        let labels = ('0'..='9')
            .chain('A'..='Z')
            .chain('a'..='z')
            .chain(".,:;-+_=()/%#<>[]".chars());
        let mut seen: Vec<(char, Vec<Rgb>)> = Vec::new();
        for ch in labels {
            let mut c = Canvas::new(CHAR_ADVANCE + 2, CHAR_HEIGHT + 2, BLACK);
            c.text(1, 1, &ch.to_string(), WHITE, 1);
            assert!(count(&c, WHITE) > 0, "{ch:?} draws nothing");
            if let Some((other, _)) = seen.iter().find(|(_, p)| *p == c.pixels) {
                panic!("{other:?} and {ch:?} draw the same pixels");
            }
            seen.push((ch, c.pixels));
        }
    }

    #[test]
    fn text_stays_inside_its_box() {
        for (s, scale) in [
            ("L_ON t=37", 1),
            ("AF1 LPLC2", 2),
            ("frame\n[0]", 1),
            ("gq?~", 3),
        ] {
            let mut c = Canvas::new(200, 70, BLACK);
            c.text(3, 2, s, WHITE, scale);
            let (w, h) = Canvas::text_size(s, scale);
            assert!(count(&c, WHITE) > 0);
            for (i, p) in c.pixels.iter().enumerate() {
                let (x, y) = (i % c.width, i / c.width);
                let inside = (3..3 + w).contains(&x) && (2..2 + h).contains(&y);
                assert!(
                    *p == BLACK || inside,
                    "{s:?} drew outside its box at ({x}, {y})"
                );
            }
        }
        assert_eq!(Canvas::text_size("", 1), (0, 0));
    }

    #[test]
    fn text_size_matches_the_layout() {
        use embedded_graphics::prelude::Dimensions;
        for s in [
            "L_ON t=37",
            "frame\n[0]",
            "a\n\nlonger line",
            "x\r\nyz",
            "\u{e9}t\u{e9}",
        ] {
            let b = label_text(s).bounding_box();
            assert_eq!(b.top_left, Point::zero(), "{s:?}");
            let (w, h) = (b.size.width as usize, b.size.height as usize);
            assert_eq!(Canvas::text_size(s, 1), (w, h), "{s:?}");
            assert_eq!(Canvas::text_size(s, 3), (3 * w, 3 * h), "{s:?}");
        }
    }

    #[test]
    fn png_round_trip() {
        let mut c = Canvas::new(7, 5, [10, 20, 30]);
        c.set(3, 2, [200, 100, 50]);
        let path = std::env::temp_dir().join(format!("alvs_canvas_{}.png", std::process::id()));
        c.save_png(&path).unwrap();
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        let mut reader = png::Decoder::new(file).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(
            (info.width, info.height, info.color_type),
            (7, 5, png::ColorType::Rgb)
        );
        assert_eq!(
            (&buf[(2 * 7 + 3) * 3..][..3], &buf[..3]),
            (&[200, 100, 50][..], &[10, 20, 30][..])
        );
    }

    #[test]
    fn plots_of_awkward_series_render() {
        let plots = [
            Plot::new("empty"),
            Plot::new("").series("none", &[]),
            Plot::new("nan")
                .series("nan", &[f32::NAN; 5])
                .markers("alert", &[2]),
            Plot::new("flat")
                .series("flat", &[3.0; 10])
                .x_label("frame"),
            Plot::new("mixed").series("a", &[1.0, f32::NAN, 2.0, f32::INFINITY, -1.0, 5.0]),
            Plot::new("one").series("a", &[0.0]).markers("m", &[40]),
            Plot::new("huge")
                .series("a", &[f32::MAX, f32::MIN])
                .y_range(0.0, 0.0),
            Plot::new("fixed")
                .series("a", &[-5.0, 5.0])
                .y_range(0.0, 1.0),
        ];
        for plot in &plots {
            for (w, h) in [(0, 0), (5, 5), (40, 30), (320, 200), (1000, 500)] {
                let c = plot.render(w, h);
                assert_eq!((c.width, c.height, c.pixels.len()), (w, h, w * h));
            }
        }
        assert!(count(&plots[3].render(320, 200), colour_cycle(0)) > 100);
        assert!(count(&plots[2].render(320, 200), RED) > 0);
    }

    #[test]
    fn a_band_colours_its_samples_and_names_its_colours() {
        let (a, b) = ([10, 200, 10], [200, 10, 200]);
        let band: Vec<Option<Rgb>> = (0..40).map(|i| [Some(a), None, Some(b)][i / 14]).collect();
        let plot = Plot::new("band")
            .series("y", &[1.0; 40])
            .band(&band, &[("first", a), ("last", b)]);
        let c = plot.render(320, 200);
        // a third of the samples each, a strip of the area's height / 16, plus the legend
        assert!(
            count(&c, a) > 200 && count(&c, b) > 200,
            "{} {}",
            count(&c, a),
            count(&c, b)
        );
        let without = Plot::new("band").series("y", &[1.0; 40]).render(320, 200);
        assert_eq!(count(&without, a), 0);
        for (w, h) in [(0, 0), (5, 5), (40, 30)] {
            assert_eq!(plot.render(w, h).pixels.len(), w * h);
        }
    }
}
