//! The pictures: per-trial trails over the top-down arena, and the side-by-side summary
//! bar charts.

use super::*;

impl ArenaReport {
    /// The side-by-side comparison of the controllers: success rates, success per background,
    /// collisions per minute and time per state.
    pub fn summary_picture(&self) -> Canvas {
        let (pw, ph, top): (i32, i32, i32) = (440, 300, 44);
        let mut c = Canvas::new(3 * pw as usize, (top + 2 * ph) as usize, WHITE);
        let cfg = &self.config;
        let names: Vec<&str> = self.summaries.iter().map(|s| s.controller).collect();
        let title = format!(
            "Arena: {} robots, {} min x {} backgrounds, seed {} - {}",
            cfg.robots,
            cfg.minutes,
            self.summaries.first().map_or(0, |s| s.trials),
            cfg.seed,
            names
                .iter()
                .map(|n| n.to_uppercase())
                .collect::<Vec<_>>()
                .join(" vs ")
        );
        let (tw, _) = Canvas::text_size(&title, 2);
        c.text((3 * pw - tw as i32) / 2, 6, &title, BLACK, 2);
        // legend
        let mut x = 12;
        let series: Vec<(String, Rgb)> = names
            .iter()
            .enumerate()
            .map(|(i, n)| (n.to_string(), colour_cycle(i)))
            .collect();
        for (n, col) in &series {
            c.fill_rect(x, 28, 10, 7, *col);
            c.text(x + 14, 28, n, BLACK, 1);
            x += 14 + Canvas::text_size(n, 1).0 as i32 + 16;
        }
        c.fill_rect(x, 28, 10, 7, lighten(colour_cycle(0)));
        c.text(x + 14, 28, "light: the paper's figure", BLACK, 1);

        let pct_of = |r: Option<f64>| r.map(|r| 100.0 * r);
        // 1: success rates
        let mut groups = vec![
            "all".to_string(),
            "robot-robot".to_string(),
            "robot-wall".to_string(),
        ];
        let mut values: Vec<Vec<Option<f64>>> = vec![
            self.summaries
                .iter()
                .map(|s| pct_of(s.success_rate))
                .collect(),
            self.summaries
                .iter()
                .map(|s| pct_of(s.robot_robot.success_rate))
                .collect(),
            self.summaries
                .iter()
                .map(|s| pct_of(s.robot_wall.success_rate))
                .collect(),
        ];
        let paper: Vec<Option<f64>> = self
            .summaries
            .iter()
            .map(|s| pct_of(s.paper_success_rate))
            .collect();
        if paper.iter().any(Option::is_some) {
            groups.push("paper".into());
            values.push(paper);
        }
        let paper_group = (groups.len() == 4).then_some(3);
        draw_bars(
            &mut c,
            (0, top, pw, ph),
            &Bars {
                title: "Success rate (%), all backgrounds",
                groups,
                series: &series,
                values,
                y_max: 100.0,
                light_group: paper_group,
                decimals: 1,
            },
        );
        // 2: success per background
        let bgs: Vec<String> = self
            .summaries
            .first()
            .map(|s| {
                self.trials
                    .iter()
                    .filter(|t| t.controller == s.controller)
                    .map(|t| t.background.clone())
                    .collect()
            })
            .unwrap_or_default();
        let per_background = |of: &dyn Fn(&Trial) -> Option<f64>| -> Vec<Vec<Option<f64>>> {
            bgs.iter()
                .map(|b| {
                    self.summaries
                        .iter()
                        .map(|s| {
                            self.trials
                                .iter()
                                .find(|t| t.controller == s.controller && &t.background == b)
                                .and_then(of)
                        })
                        .collect()
                })
                .collect()
        };
        let bg_labels: Vec<String> = bgs.iter().map(|b| short_label(b)).collect();
        let values = per_background(&|t| pct_of(t.success_rate));
        draw_bars(
            &mut c,
            (pw, top, pw, ph),
            &Bars {
                title: "Success rate (%) per background",
                groups: bg_labels.clone(),
                series: &series,
                values,
                y_max: 100.0,
                light_group: None,
                decimals: 1,
            },
        );
        // 3: collisions per minute
        let values: Vec<Vec<Option<f64>>> = vec![
            self.summaries
                .iter()
                .map(|s| Some(s.robot_robot.collisions_per_minute))
                .collect(),
            self.summaries
                .iter()
                .map(|s| Some(s.robot_wall.collisions_per_minute))
                .collect(),
        ];
        let most = values
            .iter()
            .flatten()
            .flatten()
            .fold(0.0f64, |a, &b| a.max(b));
        draw_bars(
            &mut c,
            (2 * pw, top, pw, ph),
            &Bars {
                title: "Collisions per minute (whole arena)",
                groups: vec!["robot-robot".into(), "robot-wall".into()],
                series: &series,
                values,
                y_max: nice_ceiling(most),
                light_group: None,
                decimals: 2,
            },
        );
        // 4: time per state
        let states = self.states();
        let values = states
            .iter()
            .map(|st| {
                self.summaries
                    .iter()
                    .map(|s| Some(100.0 * s.state_fraction.get(st).copied().unwrap_or(0.0)))
                    .collect()
            })
            .collect();
        draw_bars(
            &mut c,
            (0, top + ph, pw, ph),
            &Bars {
                title: "Time per controller state (%)",
                groups: states,
                series: &series,
                values,
                y_max: 100.0,
                light_group: None,
                decimals: 1,
            },
        );
        // 5: time pressed against a wall
        let values = per_background(&|t| Some(100.0 * t.wall_contact_fraction));
        draw_bars(
            &mut c,
            (pw, top + ph, pw, ph),
            &Bars {
                title: "Time pressed against a wall (%)",
                groups: bg_labels.clone(),
                series: &series,
                values,
                y_max: 100.0,
                light_group: None,
                decimals: 1,
            },
        );
        // 6: mean speed
        let values = per_background(&|t| Some(t.mean_speed_mm_s));
        let most = values
            .iter()
            .flatten()
            .flatten()
            .fold(0.0f64, |a, &b| a.max(b));
        draw_bars(
            &mut c,
            (2 * pw, top + ph, pw, ph),
            &Bars {
                title: "Mean robot speed (mm/s)",
                groups: bg_labels,
                series: &series,
                values,
                y_max: nice_ceiling(most),
                light_group: None,
                decimals: 0,
            },
        );
        c
    }
}

/// A background's name for a picture: the file name of a picture path, else the spec.
pub(super) fn short_label(spec: &str) -> String {
    if spec.contains('/') || spec.contains('.') {
        Path::new(spec)
            .file_name()
            .map_or(spec.to_string(), |f| f.to_string_lossy().into_owned())
    } else {
        spec.to_string()
    }
}

/// A colour halfway to white.
pub(super) fn lighten(c: Rgb) -> Rgb {
    c.map(|v| ((u16::from(v) + 255) / 2) as u8)
}

/// The smallest 1, 2 or 5 times a power of ten at or above `v` (1 for `v <= 0`).
pub(crate) fn nice_ceiling(v: f64) -> f64 {
    if !(v.is_finite() && v > 0.0) {
        return 1.0;
    }
    let mag = 10f64.powf(v.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * mag)
        .find(|&c| c >= v * 1.0001)
        .unwrap_or(10.0 * mag)
}

/// A grouped bar chart.
pub(crate) struct Bars<'a> {
    pub(crate) title: &'a str,
    pub(crate) groups: Vec<String>,
    pub(crate) series: &'a [(String, Rgb)],
    /// `values[group][series]`.
    pub(crate) values: Vec<Vec<Option<f64>>>,
    pub(crate) y_max: f64,
    /// A group drawn in lighter colours (reference values).
    pub(crate) light_group: Option<usize>,
    pub(crate) decimals: usize,
}

pub(super) const INK: Rgb = [30, 30, 30];
pub(super) const GRID: Rgb = [225, 225, 225];

/// Draws `bars` in the `(x, y, w, h)` box of `c`.
pub(crate) fn draw_bars(c: &mut Canvas, (x, y, w, h): (i32, i32, i32, i32), bars: &Bars) {
    let (tw, _) = Canvas::text_size(bars.title, 1);
    c.text(x + (w - tw as i32) / 2, y + 6, bars.title, INK, 1);
    let (left, right, top, bottom) = (x + 44, x + w - 12, y + 36, y + h - 22);
    let ph = (bottom - top).max(1);
    let y_max = if bars.y_max > 0.0 { bars.y_max } else { 1.0 };
    let py = |v: f64| bottom - ((v / y_max).clamp(0.0, 1.0) * f64::from(ph)).round() as i32;
    for k in 0..=5 {
        let v = y_max * f64::from(k) / 5.0;
        let yy = py(v);
        c.fill_rect(left, yy, right - left, 1, if k == 0 { INK } else { GRID });
        let label = if y_max >= 10.0 {
            format!("{v:.0}")
        } else {
            format!("{v:.1}")
        };
        let (lw, _) = Canvas::text_size(&label, 1);
        c.text(left - 4 - lw as i32, yy - 3, &label, INK, 1);
    }
    c.fill_rect(left, top, 1, bottom - top + 1, INK);
    let n = bars.groups.len().max(1) as i32;
    let gw = (right - left) / n;
    let ns = bars.series.len().max(1) as i32;
    let bw = ((gw * 4 / 5) / ns).max(2);
    for (g, name) in bars.groups.iter().enumerate() {
        let gx = left + g as i32 * gw;
        let (lw, _) = Canvas::text_size(name, 1);
        c.text(gx + (gw - lw as i32) / 2, bottom + 6, name, INK, 1);
        let x0 = gx + (gw - bw * ns) / 2;
        for (s, (_, colour)) in bars.series.iter().enumerate() {
            let bx = x0 + s as i32 * bw;
            let colour = if bars.light_group == Some(g) {
                lighten(*colour)
            } else {
                *colour
            };
            match bars.values.get(g).and_then(|v| v.get(s)).copied().flatten() {
                Some(v) if v.is_finite() => {
                    let yy = py(v);
                    c.fill_rect(bx + 1, yy, bw - 2, bottom - yy, colour);
                    let label = format!("{v:.*}", bars.decimals);
                    let (lw, _) = Canvas::text_size(&label, 1);
                    c.text(bx + (bw - lw as i32) / 2, yy - 10, &label, INK, 1);
                }
                _ => {
                    let (lw, _) = Canvas::text_size("n/a", 1);
                    c.text(bx + (bw - lw as i32) / 2, bottom - 10, "n/a", INK, 1);
                }
            }
        }
    }
}

/// The top-down picture of one trial in `world` (its arena and obstacles): each robot's trail in its own colour from a small cross
/// (start) to its body (end), robot–robot collisions as red x, robot–wall collisions as black x.
pub fn trial_picture(t: &Trial, world: &World) -> Canvas {
    let mut td = TopDown::of_world(world, 0.5);
    td.title(&format!(
        "{} on {} - success {} ({} encounters, {} with a collision)",
        t.controller.to_uppercase(),
        short_label(&t.background),
        pct(t.success_rate),
        t.encounters,
        t.collided_encounters
    ));
    for (i, trail) in t.trails.iter().enumerate() {
        let pts: Vec<(f64, f64)> = trail.iter().map(|p| (p[0], p[1])).collect();
        td.trail(&pts, colour_cycle(i));
    }
    let starts: Vec<(i32, i32)> = t
        .start_poses
        .iter()
        .map(|p| td.to_px(p.x_mm, p.y_mm))
        .collect();
    for (i, p) in t.end_poses.iter().enumerate() {
        td.robot(&Pose::new(p.x_mm, p.y_mm, p.heading_deg), colour_cycle(i));
    }
    for e in &t.collision_events {
        let colour = if e.other_robot.is_some() { RED } else { BLACK };
        td.mark(e.x_mm, e.y_mm, colour);
    }
    let mut arena_pic = td.into_canvas();
    for (i, &(x, y)) in starts.iter().enumerate() {
        arena_pic.cross(x, y, 5, INK);
        arena_pic.cross(x, y, 4, colour_cycle(i));
    }
    let legend = format!(
        "{} robots, {:.1} min, seed {}; {:.0} % of the time pressed against a wall, mean speed {:.0} mm/s\n\
         robot-robot: {} encounters, {} collisions, success {};  robot-wall: {} encounters, {} collisions, success {}\n\
         + start, disc = end; red x = robot-robot collision, black x = robot-wall collision (centre < 42 mm from it)",
        t.robots,
        t.minutes,
        t.seed,
        100.0 * t.wall_contact_fraction,
        t.mean_speed_mm_s,
        t.robot_robot.encounters,
        t.robot_robot.collisions,
        pct(t.robot_robot.success_rate),
        t.robot_wall.encounters,
        t.robot_wall.collisions,
        pct(t.robot_wall.success_rate),
    );
    let (lw, lh) = Canvas::text_size(&legend, 1);
    let width = arena_pic.width.max(lw + 24);
    let mut c = Canvas::new(width, arena_pic.height + lh + 8, WHITE);
    c.blit(&arena_pic, 0, 0);
    c.text(12, arena_pic.height as i32, &legend, INK, 1);
    c
}
