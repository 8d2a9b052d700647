//! A histogram on white: counts of values in equal bins over a range, with tick labels, a
//! title, and vertical marks at named values (a deadline, a model's figure).

use super::{nice_step, ticks, Canvas, Rgb, INK, WHITE};

/// A histogram of `values` in `bins` bins over `range`; values outside fall in the first or
/// last bin (the x label should say so). Non-finite values are left out.
#[derive(Clone, Debug, Default)]
pub struct Histogram {
    pub title: String,
    pub x_label: String,
    pub values: Vec<f64>,
    pub bins: usize,
    pub range: (f64, f64),
    /// Vertical lines at values, named in the legend.
    pub marks: Vec<(String, f64, Rgb)>,
    pub colour: Rgb,
}

impl Histogram {
    /// `bins` bins over `range` (at least one bin; an empty or reversed range becomes 0..1).
    pub fn new(title: &str, values: &[f64], bins: usize, range: (f64, f64)) -> Self {
        Histogram {
            title: title.into(),
            values: values.to_vec(),
            bins: bins.max(1),
            range,
            colour: [70, 110, 200],
            ..Histogram::default()
        }
    }

    /// Sets the x-axis label.
    pub fn x_label(mut self, label: &str) -> Self {
        self.x_label = label.into();
        self
    }

    /// A vertical line at `x`, called `label` in the legend.
    pub fn mark(mut self, label: &str, x: f64, colour: Rgb) -> Self {
        self.marks.push((label.into(), x, colour));
        self
    }

    /// The counts per bin.
    pub fn counts(&self) -> Vec<usize> {
        let (lo, hi) = self.span();
        let mut counts = vec![0usize; self.bins];
        for v in self.values.iter().filter(|v| v.is_finite()) {
            let b = ((v - lo) / (hi - lo) * self.bins as f64).floor();
            counts[b.clamp(0.0, self.bins as f64 - 1.0) as usize] += 1;
        }
        counts
    }

    fn span(&self) -> (f64, f64) {
        let (lo, hi) = self.range;
        if lo.is_finite() && hi.is_finite() && lo < hi {
            (lo, hi)
        } else {
            (0.0, 1.0)
        }
    }

    /// Draws it on a new `width` x `height` canvas; text is doubled from 900 x 450 up.
    pub fn render(&self, width: usize, height: usize) -> Canvas {
        let mut c = Canvas::new(width, height, WHITE);
        let k: usize = if width >= 900 && height >= 450 { 2 } else { 1 };
        let (w, h, s) = (width as i32, height as i32, k as i32);
        let (line_h, margin, tick) = (10 * s, 6 * s, 3 * s);
        let text_w = |t: &str| Canvas::text_size(t, k).0 as i32;
        c.text((w - text_w(&self.title)) / 2, margin, &self.title, INK, k);
        let mut top = margin + 2 * line_h;
        let mut x = margin;
        for (name, _, colour) in &self.marks {
            if x > margin && x + 10 * s + text_w(name) > w - margin {
                (x, top) = (margin, top + line_h + 2 * s);
            }
            c.fill_rect(x + 4 * s, top, 2 * s, 7 * s, *colour);
            c.text(x + 10 * s, top, name, INK, k);
            x += 20 * s + text_w(name);
        }
        if !self.marks.is_empty() {
            top += line_h + margin;
        }
        let counts = self.counts();
        let most = counts.iter().copied().max().unwrap_or(0).max(1) as f64;
        let y_step = nice_step(most, 4.0).max(1.0);
        let y_ticks = ticks(0.0, (most / y_step).ceil() * y_step, y_step);
        let y_hi = y_ticks.last().copied().unwrap_or(1.0).max(1.0);
        let y_labels: Vec<String> = y_ticks.iter().map(|v| format!("{v:.0}")).collect();
        let (lo, hi) = self.span();
        let x_step = nice_step(hi - lo, 5.0);
        let x_ticks = ticks(lo, hi, x_step);
        let decimals = (-x_step.log10().floor()).clamp(0.0, 8.0) as usize;
        let x_labels: Vec<String> = x_ticks.iter().map(|v| format!("{v:.decimals$}")).collect();
        let left = margin + y_labels.iter().map(|l| text_w(l)).max().unwrap_or(0) + 2 * tick;
        let right = w - margin - x_labels.last().map_or(0, |l| text_w(l) / 2);
        let bottom = h - margin - 2 * line_h - tick;
        let (pw, ph) = (right - left, bottom - top);
        if pw < 8 || ph < 8 {
            return c;
        }
        let px = |v: f64| left + ((v - lo) / (hi - lo) * f64::from(pw)).round() as i32;
        let py = |n: f64| bottom - (n / y_hi * f64::from(ph)).round() as i32;
        let bin_w = (hi - lo) / self.bins as f64;
        for (i, &n) in counts.iter().enumerate() {
            let (x0, x1) = (px(lo + i as f64 * bin_w), px(lo + (i + 1) as f64 * bin_w));
            let y = py(n as f64);
            c.fill_rect(x0, y, (x1 - x0 - 1).max(1), bottom - y, self.colour);
        }
        for (_, v, colour) in &self.marks {
            if (lo..=hi).contains(v) {
                c.fill_rect(px(*v) - s / 2, top, s.max(1), ph, *colour);
            }
        }
        c.fill_rect(left - 1, top, 1, ph + 1, INK);
        c.fill_rect(left - 1, bottom, pw + 1, 1, INK);
        for (&v, label) in y_ticks.iter().zip(&y_labels) {
            let y = py(v);
            c.fill_rect(left - 1 - tick, y, tick, 1, INK);
            c.text(
                left - 1 - tick - 2 * s - text_w(label),
                y - 3 * s,
                label,
                INK,
                k,
            );
        }
        for (&v, label) in x_ticks.iter().zip(&x_labels) {
            let x = px(v);
            c.fill_rect(x, bottom + 1, 1, tick, INK);
            c.text(x - text_w(label) / 2, bottom + tick + 3 * s, label, INK, k);
        }
        let xl = &self.x_label;
        c.text(
            left + (pw - text_w(xl)) / 2,
            bottom + tick + 3 * s + line_h,
            xl,
            INK,
            k,
        );
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_fall_in_their_bins_and_outliers_in_the_ends() {
        let h = Histogram::new(
            "h",
            &[0.0, 0.5, 1.9, 2.0, 9.9, 11.0, -3.0, f64::NAN],
            5,
            (0.0, 10.0),
        );
        assert_eq!(h.counts(), [4, 1, 0, 0, 2]);
        let flat = Histogram::new("flat", &[5.0], 0, (3.0, 3.0));
        assert_eq!(flat.counts(), [1], "one bin over 0..1 at least");
    }

    #[test]
    fn marks_and_bars_are_drawn_at_any_size() {
        let red = [220, 20, 20];
        let h = Histogram::new("cycles", &[1.0, 2.0, 2.5, 7.0], 10, (0.0, 10.0))
            .x_label("x")
            .mark("deadline", 6.0, red);
        let c = h.render(400, 240);
        let n = |colour: Rgb| c.pixels.iter().filter(|&&p| p == colour).count();
        assert!(n(red) > 100, "the mark's line");
        assert!(n(h.colour) > 100, "the bars");
        for (w, hh) in [(0, 0), (3, 3), (30, 20), (1000, 500)] {
            assert_eq!(h.render(w, hh).pixels.len(), w * hh);
        }
        let empty = Histogram::new("none", &[], 4, (0.0, 1.0)).render(200, 120);
        assert_eq!(empty.pixels.len(), 200 * 120);
    }
}
