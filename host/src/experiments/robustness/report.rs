//! The suite's report: one row per (perturbation, controller), as a table, JSON and a picture.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;
use serde::Serialize;

use super::{Perturbation, RobustTrial, RobustnessConfig, SuiteController, SLOW_SHARE};
use crate::experiments::arena::{self, draw_bars, Bars, Trial};
use crate::experiments::Report;
use alvs_sim::canvas::{colour_cycle, Canvas, Rgb, BLACK, WHITE};

/// One (perturbation, controller) over its seeds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    /// The perturbation.
    pub perturbation: Perturbation,
    /// The controller.
    pub controller: SuiteController,
    /// Seeds pooled (one trial each).
    pub seeds: usize,
    /// Encounters without a collision / encounters, all seeds pooled; `null` without any.
    pub success_rate: Option<f64>,
    /// Encounters, all seeds.
    pub encounters: u64,
    /// Encounters with a collision, all seeds.
    pub collided_encounters: u64,
    /// Lowest and highest success rate of one seed (seeds with encounters).
    pub success_range: Option<(f64, f64)>,
    /// Mean robot speed, mean over the seeds, mm/s.
    pub mean_speed_mm_s: f64,
    /// Standard deviation of the seeds' mean speeds, mm/s.
    pub speed_sd_mm_s: f64,
    /// The controller's cruise speed, mm/s.
    pub cruise_mm_s: f64,
    /// `mean_speed_mm_s / cruise_mm_s`.
    pub speed_share: f64,
    /// Below [`SLOW_SHARE`] of the cruise speed.
    pub slow: bool,
    /// Fraction of robot time pressed against a wall or obstacle, mean over the seeds.
    pub wall_contact_fraction: f64,
    /// Lowest and highest of one seed.
    pub wall_contact_range: (f64, f64),
    /// Success rate minus the same controller's unperturbed one, percentage points (`null`
    /// without a `none` row or without encounters).
    pub success_change_pp: Option<f64>,
    /// Mean speed over the same controller's unperturbed one, minus 1.
    pub speed_change: Option<f64>,
}

impl Row {
    /// Pools `trials` (one per seed) of one perturbation and controller.
    fn new(p: Perturbation, c: SuiteController, trials: &[&Trial]) -> Row {
        let s = arena::summarise(c.kind().name(), trials);
        let rates: Vec<f64> = trials.iter().filter_map(|t| t.success_rate).collect();
        let speeds: Vec<f64> = trials.iter().map(|t| t.mean_speed_mm_s).collect();
        let walls: Vec<f64> = trials.iter().map(|t| t.wall_contact_fraction).collect();
        let cruise = f64::from(c.fsm().motion.cruise_mm_s);
        let share = s.mean_speed_mm_s / cruise;
        Row {
            perturbation: p,
            controller: c,
            seeds: trials.len(),
            success_rate: s.success_rate,
            encounters: s.encounters,
            collided_encounters: s.collided_encounters,
            success_range: range(&rates),
            mean_speed_mm_s: s.mean_speed_mm_s,
            speed_sd_mm_s: sd(&speeds),
            cruise_mm_s: cruise,
            speed_share: share,
            slow: share < SLOW_SHARE,
            wall_contact_fraction: s.wall_contact_fraction,
            wall_contact_range: range(&walls).unwrap_or((0.0, 0.0)),
            success_change_pp: None,
            speed_change: None,
        }
    }
}

/// The lowest and highest of `v`; `None` if empty.
fn range(v: &[f64]) -> Option<(f64, f64)> {
    let lo = v.iter().copied().reduce(f64::min)?;
    let hi = v.iter().copied().reduce(f64::max)?;
    Some((lo, hi))
}

/// The sample standard deviation of `v` (0 for fewer than two).
fn sd(v: &[f64]) -> f64 {
    if v.len() < 2 {
        return 0.0;
    }
    let m = arena::mean(v.iter().copied());
    (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct RobustnessReport {
    /// What ran.
    pub config: RobustnessConfig,
    /// One per (perturbation, controller), perturbation-major in the configuration's order.
    pub rows: Vec<Row>,
    /// Every trial, in plan order.
    pub trials: Vec<RobustTrial>,
    /// Wall-clock seconds of the run.
    pub wall_clock_s: f64,
    /// Worker threads used.
    pub jobs: usize,
}

impl RobustnessReport {
    /// Pools `trials` into rows.
    pub fn new(
        config: RobustnessConfig,
        trials: Vec<RobustTrial>,
        wall_clock_s: f64,
        jobs: usize,
    ) -> Self {
        let (ps, cs) = (
            super::unique(&config.perturbations),
            super::unique(&config.controllers),
        );
        let mut rows: Vec<Row> = Vec::new();
        for &p in &ps {
            for &c in &cs {
                let mine: Vec<&Trial> = trials
                    .iter()
                    .filter(|t| t.perturbation == p && t.controller == c)
                    .map(|t| &t.trial)
                    .collect();
                rows.push(Row::new(p, c, &mine));
            }
        }
        let reference: Vec<Row> = rows
            .iter()
            .filter(|r| r.perturbation == Perturbation::None)
            .cloned()
            .collect();
        for r in &mut rows {
            if let Some(base) = reference.iter().find(|b| b.controller == r.controller) {
                r.success_change_pp = r
                    .success_rate
                    .zip(base.success_rate)
                    .map(|(a, b)| 100.0 * (a - b));
                r.speed_change = (base.mean_speed_mm_s > 0.0)
                    .then(|| r.mean_speed_mm_s / base.mean_speed_mm_s - 1.0);
            }
        }
        RobustnessReport {
            config,
            rows,
            trials,
            wall_clock_s,
            jobs,
        }
    }

    /// The seeds as a short list: `11-20` when consecutive.
    fn seeds_label(&self) -> String {
        let s = super::unique(&self.config.seeds);
        let consecutive = s.windows(2).all(|w| w[1] == w[0] + 1);
        match (s.first(), s.last()) {
            (Some(a), Some(b)) if consecutive && s.len() > 2 => format!("{a}-{b}"),
            _ => s.iter().map(u64::to_string).collect::<Vec<_>>().join(","),
        }
    }
}

fn pct(r: Option<f64>) -> String {
    r.map_or("n/a".into(), |r| format!("{:.1} %", 100.0 * r))
}

impl Report for RobustnessReport {
    fn table(&self) -> String {
        let c = &self.config;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "robustness: world {}, {} robots, {} min per trial, seeds {}, {} perturbations x {} \
             controllers = {} trials on {} threads, {:.0} s",
            c.world.label(),
            c.robots,
            c.minutes,
            self.seeds_label(),
            super::unique(&c.perturbations).len(),
            super::unique(&c.controllers).len(),
            self.trials.len(),
            self.jobs,
            self.wall_clock_s
        );
        let _ = writeln!(
            s,
            "success: encounters without a collision / encounters, seeds pooled (the arena's \
             counting); range: one seed's lowest-highest\n\
             speed: mean robot speed (sd over seeds) and its share of the cruise speed, SLOW \
             below {:.0} %\n\
             at wall: share of robot time pressed against a wall or obstacle (mean over seeds; \
             one seed's highest)\n\
             change: from the same controller's unperturbed (none) row",
            100.0 * SLOW_SHARE
        );
        let _ = writeln!(s);
        // (label, width) of each column, and the groups above them
        const COLUMNS: [(&str, usize); 13] = [
            ("perturbation", 16),
            ("controller", 10),
            ("rate", 8),
            ("enc", 6),
            ("range", 12),
            ("change", 7),
            ("mm/s", 7),
            ("(sd)", 6),
            ("cruise", 6),
            ("change", 7),
            ("mean", 6),
            ("max", 6),
            ("flag", 4),
        ];
        // more space after the success, the speed and the wall columns
        let gap = |k: usize| match k {
            5 | 9 => 3,
            11 => 2,
            _ => 1,
        };
        let line = |cells: [String; 13]| -> String {
            let mut l = String::new();
            for (k, (cell, (_, w))) in cells.iter().zip(COLUMNS).enumerate() {
                if k < 2 || k == 12 {
                    let _ = write!(l, "{cell:<w$}");
                } else {
                    let _ = write!(l, "{cell:>w$}");
                }
                l.push_str(&" ".repeat(gap(k)));
            }
            l.trim_end().to_string()
        };
        let head = line(COLUMNS.map(|(label, _)| label.to_string()));
        let start = |k: usize| -> usize {
            COLUMNS[..k]
                .iter()
                .enumerate()
                .map(|(j, (_, w))| w + gap(j))
                .sum()
        };
        let mut groups = String::new();
        for (label, from, to) in [
            (" success ", 2, 5),
            (" speed ", 6, 9),
            (" at wall % ", 10, 11),
        ] {
            let (a, b) = (start(from), start(to) + COLUMNS[to].1);
            groups.push_str(&" ".repeat(a.saturating_sub(groups.len())));
            let w = b - a;
            let _ = write!(groups, "{label:-^w$}");
        }
        let _ = writeln!(s, "{groups}");
        let _ = writeln!(s, "{head}");
        let _ = writeln!(s, "{}", "-".repeat(head.len()));
        let mut last = None;
        for r in &self.rows {
            if last.is_some_and(|p| p != r.perturbation) {
                let _ = writeln!(s);
            }
            last = Some(r.perturbation);
            let perturbed = r.perturbation != Perturbation::None;
            let cells = [
                r.perturbation.name().to_string(),
                r.controller.name().to_string(),
                pct(r.success_rate),
                r.encounters.to_string(),
                r.success_range.map_or("n/a".into(), |(lo, hi)| {
                    format!("{:.1}-{:.1}", 100.0 * lo, 100.0 * hi)
                }),
                r.success_change_pp
                    .filter(|_| perturbed)
                    .map_or("".into(), |d| format!("{d:+.1}")),
                format!("{:.1}", r.mean_speed_mm_s),
                format!("({:.1})", r.speed_sd_mm_s),
                format!("{:.0} %", 100.0 * r.speed_share),
                r.speed_change
                    .filter(|_| perturbed)
                    .map_or("".into(), |d| format!("{:+.0} %", 100.0 * d)),
                format!("{:.1}", 100.0 * r.wall_contact_fraction),
                format!("{:.1}", 100.0 * r.wall_contact_range.1),
                (if r.slow { "SLOW" } else { "" }).to_string(),
            ];
            let _ = writeln!(s, "{}", line(cells));
        }
        let _ = writeln!(s);
        for p in super::unique(&c.perturbations) {
            let _ = writeln!(s, "{:<16} {}", p.name(), p.what());
        }
        s
    }

    fn json(&self) -> serde_json::Value {
        let c = &self.config;
        serde_json::json!({
            "config": {
                "world": c.world.label(),
                "seeds": c.seeds,
                "robots": c.robots,
                "minutes": c.minutes,
                "perturbations": c.perturbations.iter().map(|p| serde_json::json!({
                    "name": p.name(),
                    "what": p.what(),
                })).collect::<Vec<_>>(),
                "controllers": c.controllers.iter().map(|k| k.name()).collect::<Vec<_>>(),
                "slow_share": SLOW_SHARE,
            },
            "rows": self.rows,
            "trials": self.trials,
            "wall_clock_s": self.wall_clock_s,
            "jobs": self.jobs,
        })
    }

    fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        crate::experiments::write_summary(dir, &self.summary_picture())
    }
}

impl RobustnessReport {
    /// Success rate and speed (% of cruise) per perturbation, a bar per controller.
    pub fn summary_picture(&self) -> Canvas {
        let ps = super::unique(&self.config.perturbations);
        let cs = super::unique(&self.config.controllers);
        let title = format!(
            "Robustness in {}: {} robots, {} min, seeds {}",
            self.config.world.label(),
            self.config.robots,
            self.config.minutes,
            self.seeds_label()
        );
        let (tw, _) = Canvas::text_size(&title, 2);
        let (ph, top) = (300, 44);
        let w = (120 * ps.len() as i32 + 60).max(tw as i32 + 24);
        let mut c = Canvas::new(w as usize, (top + 2 * ph) as usize, WHITE);
        c.text((w - tw as i32) / 2, 6, &title, BLACK, 2);
        let series: Vec<(String, Rgb)> = cs
            .iter()
            .enumerate()
            .map(|(i, k)| (k.name().to_string(), colour_cycle(i)))
            .collect();
        let mut x = 12;
        for (n, col) in &series {
            c.fill_rect(x, 28, 10, 7, *col);
            c.text(x + 14, 28, n, BLACK, 1);
            x += 14 + Canvas::text_size(n, 1).0 as i32 + 16;
        }
        let value = |f: &dyn Fn(&Row) -> Option<f64>| -> Vec<Vec<Option<f64>>> {
            ps.iter()
                .map(|&p| {
                    cs.iter()
                        .map(|&k| {
                            self.rows
                                .iter()
                                .find(|r| r.perturbation == p && r.controller == k)
                                .and_then(f)
                        })
                        .collect()
                })
                .collect()
        };
        let groups: Vec<String> = ps.iter().map(|p| p.name().to_string()).collect();
        draw_bars(
            &mut c,
            (0, top, w, ph),
            &Bars {
                title: "Success rate (%), seeds pooled",
                groups: groups.clone(),
                series: &series,
                values: value(&|r| r.success_rate.map(|s| 100.0 * s)),
                y_max: 100.0,
                light_group: None,
                decimals: 1,
            },
        );
        let speeds = value(&|r| Some(100.0 * r.speed_share));
        let most = speeds
            .iter()
            .flatten()
            .flatten()
            .fold(100.0f64, |a, &b| a.max(b));
        let title = format!(
            "Mean speed (% of cruise; below {:.0} flagged SLOW)",
            100.0 * SLOW_SHARE
        );
        draw_bars(
            &mut c,
            (0, top + ph, w, ph),
            &Bars {
                title: &title,
                groups,
                series: &series,
                values: speeds,
                y_max: arena::nice_ceiling(most),
                light_group: None,
                decimals: 0,
            },
        );
        c
    }
}
