//! The ablation's report: per part (each arena perturbation, each evasion wall, two threats)
//! one row per variant, seeds pooled, with the change from its reference (the default for
//! `alvs-M` and `alvs+O`, the paper's model for `paper+M`); a table, JSON and a picture.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;
use serde::Serialize;

use super::{AblationConfig, AblationTrial, Measured, Part, Variant, MECHANISMS};
use crate::experiments::arena::{draw_bars, nice_ceiling, Bars};
use crate::experiments::Report;
use alvs_sim::canvas::{colour_cycle, Canvas, Rgb, BLACK, WHITE};

/// One variant on one part, seeds pooled.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cell {
    /// Seeds pooled.
    pub seeds: usize,
    /// What they measured, pooled: counts summed, shares and speeds the mean over seeds.
    pub pooled: Measured,
    /// The worst seed: the arena's lowest success rate, evasion's and two threats' most
    /// collisions.
    pub worst_seed: Option<f64>,
    /// Evasion: seeds with every bearing on the correct side and at most one collision.
    pub seeds_at_goal: Option<usize>,
}

/// The report.
#[derive(Debug, Clone)]
pub struct AblationReport {
    /// What ran.
    pub config: AblationConfig,
    /// `cells[part][variant]`.
    pub cells: Vec<Vec<Cell>>,
    /// Wall-clock seconds.
    pub wall_clock_s: f64,
    /// Worker threads.
    pub jobs: usize,
}

impl Measured {
    /// The success rate of an arena record.
    pub fn success(&self) -> Option<f64> {
        match *self {
            Measured::Arena {
                encounters,
                collided,
                ..
            } if encounters > 0 => Some(1.0 - collided as f64 / encounters as f64),
            _ => None,
        }
    }

    /// Collisions per trial of an open-loop record (evasion, two threats).
    fn collision_share(&self) -> Option<f64> {
        match *self {
            Measured::Evasion {
                angles, collisions, ..
            } => Some(collisions as f64 / angles.max(1) as f64),
            Measured::TwoThreats {
                runs, collisions, ..
            } => Some(collisions as f64 / runs.max(1) as f64),
            Measured::Arena { .. } | Measured::Clips(_) => None,
        }
    }
}

/// Pools one variant's seeds on one part.
fn pool(ms: &[&Measured]) -> Cell {
    let n = ms.len().max(1) as f64;
    let first = ms.first().map(|m| (*m).clone());
    let pooled = match first {
        Some(Measured::Clips(c)) => Measured::Clips(c),
        Some(Measured::Arena { .. }) | None => {
            let (mut e, mut c, mut v, mut w, mut x) = (0, 0, 0.0, 0.0, 0.0);
            for m in ms {
                if let Measured::Arena {
                    encounters,
                    collided,
                    speed_mm_s,
                    at_wall,
                    escaping,
                } = **m
                {
                    (e, c) = (e + encounters, c + collided);
                    (v, w, x) = (v + speed_mm_s, w + at_wall, x + escaping);
                }
            }
            Measured::Arena {
                encounters: e,
                collided: c,
                speed_mm_s: v / n,
                at_wall: w / n,
                escaping: x / n,
            }
        }
        Some(Measured::Evasion { .. }) => {
            let (mut a, mut r, mut c, mut g) = (0, 0, 0, 0);
            for m in ms {
                if let Measured::Evasion {
                    angles,
                    correct,
                    collisions,
                    gamma,
                } = **m
                {
                    (a, r, c, g) = (a + angles, r + correct, c + collisions, g + gamma);
                }
            }
            Measured::Evasion {
                angles: a,
                correct: r,
                collisions: c,
                gamma: g,
            }
        }
        Some(Measured::TwoThreats { .. }) => {
            let (mut n, mut a, mut c) = (0, 0, 0);
            for m in ms {
                if let Measured::TwoThreats {
                    runs,
                    away,
                    collisions,
                } = **m
                {
                    (n, a, c) = (n + runs, a + away, c + collisions);
                }
            }
            Measured::TwoThreats {
                runs: n,
                away: a,
                collisions: c,
            }
        }
    };
    let worst_seed = match pooled {
        Measured::Clips(_) => None,
        Measured::Arena { .. } => ms.iter().filter_map(|m| m.success()).reduce(f64::min),
        _ => ms
            .iter()
            .filter_map(|m| m.collision_share())
            .reduce(f64::max),
    };
    let seeds_at_goal = matches!(pooled, Measured::Evasion { .. }).then(|| {
        ms.iter()
            .filter(|m| {
                matches!(**m, Measured::Evasion { angles, correct, collisions, .. }
                    if correct == angles && *collisions <= 1)
            })
            .count()
    });
    Cell {
        seeds: ms.len(),
        pooled,
        worst_seed,
        seeds_at_goal,
    }
}

impl AblationReport {
    /// Pools `trials` by part and variant.
    pub fn new(
        config: AblationConfig,
        trials: Vec<AblationTrial>,
        wall_clock_s: f64,
        jobs: usize,
    ) -> Self {
        let cells = config
            .parts()
            .iter()
            .map(|part| {
                (0..config.variants.len())
                    .map(|v| {
                        let ms: Vec<&Measured> = trials
                            .iter()
                            .filter(|t| t.variant == v && &t.part == part)
                            .map(|t| &t.measured)
                            .collect();
                        pool(&ms)
                    })
                    .collect()
            })
            .collect();
        AblationReport {
            config,
            cells,
            wall_clock_s,
            jobs,
        }
    }

    /// The row a variant is compared with: the default for `alvs-M` and `alvs+O`, the paper's model for
    /// `paper+M` (when it ran).
    fn reference(&self, v: Variant) -> Option<usize> {
        let r = match v {
            Variant::Without(_) | Variant::Plus(_) => Variant::Alvs,
            Variant::With(_) => Variant::Paper,
            _ => return None,
        };
        self.config.variants.iter().position(|&x| x == r)
    }

    fn seeds_label(&self) -> String {
        let s = &self.config.seeds;
        match (s.first(), s.last()) {
            (Some(a), Some(b)) if s.len() > 2 && s.windows(2).all(|w| w[1] == w[0] + 1) => {
                format!("{a}-{b}")
            }
            _ => s.iter().map(u64::to_string).collect::<Vec<_>>().join(","),
        }
    }

    fn part_title(&self, part: &Part) -> String {
        let c = &self.config;
        match part {
            Part::Arena { perturbation } => format!(
                "arena, {} robots, {} min, perturbation {}",
                c.robots,
                c.minutes,
                perturbation.name()
            ),
            Part::Evasion { wall, from_mm } => format!(
                "evasion{}, 9 bearings, wall {}",
                from_mm.map_or(String::new(), |d| format!(
                    " from {d:.0} mm (the obstacle first seen close)"
                )),
                wall.as_deref().unwrap_or("(the world's own)")
            ),
            Part::TwoThreats => format!("two threats, {} runs per seed", c.two_threat_runs),
            Part::Clips => "the recorded clips (open loop, standing)".into(),
        }
    }
}

/// Looming clips detected, the other clips that alerted, and the first alerts against the
/// reference's.
fn clips_rows(t: &mut String, r: &AblationReport, p: usize) {
    let _ = writeln!(
        t,
        "{:<24} {:>9} {:>14} {:>13} {:>24}",
        "variant", "looming", "first alert", "others alert", "first alert vs reference"
    );
    for (v, &variant) in r.config.variants.iter().enumerate() {
        let Measured::Clips(clips) = &r.cells[p][v].pooled else {
            continue;
        };
        if clips.is_empty() {
            continue;
        }
        let looming: Vec<_> = clips.iter().filter(|c| c.looming).collect();
        let detected = looming.iter().filter(|c| c.alerts > 0).count();
        let mut firsts: Vec<u32> = looming.iter().filter_map(|c| c.first_alert).collect();
        firsts.sort_unstable();
        let median = firsts
            .get(firsts.len() / 2)
            .map_or("-".into(), |f| format!("median {f}"));
        let others: Vec<_> = clips.iter().filter(|c| !c.looming).collect();
        let false_alarms = others.iter().filter(|c| c.alerts > 0).count();
        let vs = r
            .reference(variant)
            .and_then(|rv| match &r.cells[p][rv].pooled {
                Measured::Clips(reference) => Some(reference),
                _ => None,
            });
        let vs = vs.map_or(String::new(), |reference| {
            let (mut earlier, mut later, mut lost, mut gained) = (0, 0, 0, 0);
            for (a, b) in clips.iter().zip(reference).filter(|(a, _)| a.looming) {
                match (a.first_alert, b.first_alert) {
                    (Some(x), Some(y)) if x < y => earlier += 1,
                    (Some(x), Some(y)) if x > y => later += 1,
                    (None, Some(_)) => lost += 1,
                    (Some(_), None) => gained += 1,
                    _ => {}
                }
            }
            format!("{earlier} earlier {later} later {lost} lost {gained} new")
        });
        let _ = writeln!(
            t,
            "{:<24} {:>9} {:>14} {:>13} {:>24}",
            variant.name(),
            format!("{detected}/{}", looming.len()),
            median,
            format!("{false_alarms}/{}", others.len()),
            vs
        );
    }
}

fn signed(v: f64, decimals: usize) -> String {
    if v.abs() < 0.5 * 10f64.powi(-(decimals as i32)) {
        "0".into()
    } else {
        format!("{v:+.decimals$}")
    }
}

impl Report for AblationReport {
    fn table(&self) -> String {
        let c = &self.config;
        let mut t = String::new();
        let _ = writeln!(
            t,
            "ablation: world {}, seeds {}, {} variants x {} parts = {} trials on {} threads, {:.0} s",
            c.world.label(),
            self.seeds_label(),
            c.variants.len(),
            c.parts().len(),
            c.variants.len() * c.seeds.len() * c.parts().len(),
            self.jobs,
            self.wall_clock_s
        );
        let _ = writeln!(
            t,
            "change: from the default (alvs-M, alvs+O) or the paper's model (paper+M); a mechanism earns its place where removing it makes the default worse, an option where adding it makes the default better"
        );
        for (p, part) in c.parts().iter().enumerate() {
            let _ = writeln!(t, "\n{}", self.part_title(part));
            let row = |v: usize| &self.cells[p][v];
            match part {
                Part::Arena { .. } => {
                    let _ = writeln!(
                        t,
                        "{:<24} {:>8} {:>6} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7}",
                        "variant",
                        "success",
                        "enc",
                        "worst",
                        "change",
                        "mm/s",
                        "cruise",
                        "change",
                        "wall %",
                        "esc %"
                    );
                    for (v, &variant) in c.variants.iter().enumerate() {
                        let Measured::Arena {
                            encounters,
                            speed_mm_s,
                            at_wall,
                            escaping,
                            ..
                        } = row(v).pooled
                        else {
                            continue;
                        };
                        let success = row(v).pooled.success();
                        let cruise = f64::from(variant.model().fsm.motion.cruise_mm_s);
                        let reference = self.reference(variant).map(|r| &row(r).pooled);
                        let d_success = match (success, reference.and_then(|r| r.success())) {
                            (Some(a), Some(b)) => signed(100.0 * (a - b), 1),
                            _ => String::new(),
                        };
                        let d_speed = match reference {
                            Some(Measured::Arena { speed_mm_s: b, .. }) if *b > 0.0 => {
                                format!("{} %", signed(100.0 * (speed_mm_s / b - 1.0), 0))
                            }
                            _ => String::new(),
                        };
                        let pct =
                            |r: Option<f64>| r.map_or("-".into(), |r| format!("{:.1}", 100.0 * r));
                        let _ = writeln!(
                            t,
                            "{:<24} {:>8} {:>6} {:>7} {:>7} {:>7.1} {:>6.0}% {:>7} {:>7.1} {:>7.1}",
                            variant.name(),
                            pct(success),
                            encounters,
                            pct(row(v).worst_seed),
                            d_success,
                            speed_mm_s,
                            100.0 * speed_mm_s / cruise,
                            d_speed,
                            100.0 * at_wall,
                            100.0 * escaping
                        );
                    }
                }
                Part::Evasion { .. } => {
                    let _ = writeln!(
                        t,
                        "{:<24} {:>9} {:>7} {:>11} {:>7} {:>7} {:>7} {:>7} {:>11}",
                        "variant",
                        "correct",
                        "change",
                        "collisions",
                        "change",
                        "γ first",
                        "change",
                        "worst",
                        "seeds 9/9,<=1"
                    );
                    for (v, &variant) in c.variants.iter().enumerate() {
                        let Measured::Evasion {
                            angles,
                            correct,
                            collisions,
                            gamma,
                        } = row(v).pooled
                        else {
                            continue;
                        };
                        let reference = self.reference(variant).map(|r| &row(r).pooled);
                        let (dc, dk, dg) = match reference {
                            Some(Measured::Evasion {
                                correct: rc,
                                collisions: rk,
                                gamma: rg,
                                ..
                            }) => (
                                signed(correct as f64 - *rc as f64, 0),
                                signed(collisions as f64 - *rk as f64, 0),
                                signed(gamma as f64 - *rg as f64, 0),
                            ),
                            _ => (String::new(), String::new(), String::new()),
                        };
                        let worst = row(v)
                            .worst_seed
                            .map_or("-".into(), |w| format!("{:.0}/9", 9.0 * w));
                        let _ = writeln!(
                            t,
                            "{:<24} {:>9} {:>7} {:>11} {:>7} {:>7} {:>7} {:>7} {:>11}",
                            variant.name(),
                            format!("{correct}/{angles}"),
                            dc,
                            format!("{collisions}/{angles}"),
                            dk,
                            format!("{gamma}/{angles}"),
                            dg,
                            worst,
                            format!("{}/{}", row(v).seeds_at_goal.unwrap_or(0), row(v).seeds)
                        );
                    }
                }
                Part::Clips => clips_rows(&mut t, self, p),
                Part::TwoThreats => {
                    let _ = writeln!(
                        t,
                        "{:<24} {:>9} {:>7} {:>11} {:>7} {:>11}",
                        "variant", "away", "change", "collisions", "change", "worst seed"
                    );
                    for (v, &variant) in c.variants.iter().enumerate() {
                        let Measured::TwoThreats {
                            runs,
                            away,
                            collisions,
                        } = row(v).pooled
                        else {
                            continue;
                        };
                        let reference = self.reference(variant).map(|r| &row(r).pooled);
                        let (da, dk) = match reference {
                            Some(Measured::TwoThreats {
                                away: ra,
                                collisions: rk,
                                ..
                            }) => (
                                signed(away as f64 - *ra as f64, 0),
                                signed(collisions as f64 - *rk as f64, 0),
                            ),
                            _ => (String::new(), String::new()),
                        };
                        let worst = row(v).worst_seed.map_or("-".into(), |w| {
                            format!("{:.0}/{}", w * c.two_threat_runs as f64, c.two_threat_runs)
                        });
                        let _ = writeln!(
                            t,
                            "{:<24} {:>9} {:>7} {:>11} {:>7} {:>11}",
                            variant.name(),
                            format!("{away}/{runs}"),
                            da,
                            format!("{collisions}/{runs}"),
                            dk,
                            worst
                        );
                    }
                }
            }
        }
        let _ = writeln!(t, "\nmechanisms:");
        for m in &MECHANISMS {
            let role = if m.in_default() { "default" } else { "option" };
            let _ = writeln!(t, "{:<16} {:<8} {} ({})", m.name, role, m.what, m.fields);
        }
        t
    }

    fn json(&self) -> serde_json::Value {
        let c = &self.config;
        let parts: Vec<serde_json::Value> = c
            .parts()
            .iter()
            .enumerate()
            .map(|(p, part)| {
                let rows: serde_json::Map<String, serde_json::Value> = c
                    .variants
                    .iter()
                    .enumerate()
                    .map(|(v, variant)| {
                        (
                            variant.name(),
                            serde_json::to_value(&self.cells[p][v]).unwrap_or_default(),
                        )
                    })
                    .collect();
                serde_json::json!({ "part": part, "rows": rows })
            })
            .collect();
        serde_json::json!({
            "world": c.world.label(),
            "seeds": c.seeds,
            "robots": c.robots,
            "minutes": c.minutes,
            "two_threat_runs": c.two_threat_runs,
            "parts": parts,
            "mechanisms": MECHANISMS.iter().map(|m| serde_json::json!({
                "name": m.name, "what": m.what, "fields": m.fields, "escape": m.escape,
                "in_default": m.in_default(),
            })).collect::<Vec<_>>(),
            "wall_clock_s": self.wall_clock_s,
        })
    }

    fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        crate::experiments::write_summary(dir, &self.summary_picture())
    }
}

impl AblationReport {
    /// One panel per part: per mechanism, the default without it and the paper's model with
    /// it (the first group: the default and the paper's model themselves).
    pub fn summary_picture(&self) -> Canvas {
        let c = &self.config;
        let index = |v: Variant| c.variants.iter().position(|&x| x == v);
        let mut groups = vec!["model".to_string()];
        let mut pairs = vec![(index(Variant::Alvs), index(Variant::Paper))];
        for (i, m) in MECHANISMS.iter().enumerate() {
            let pair = (index(Variant::on_the_default(i)), index(Variant::With(i)));
            if pair != (None, None) {
                groups.push(m.name.to_string());
                pairs.push(pair);
            }
        }
        let series: Vec<(String, Rgb)> = vec![
            (
                "the default (alvs), without the mechanism (with the option)".into(),
                colour_cycle(0),
            ),
            (
                "the paper's model, with the mechanism".into(),
                colour_cycle(1),
            ),
        ];
        let title = format!(
            "Ablation in {}, seeds {} (first group: the models themselves)",
            c.world.label(),
            self.seeds_label()
        );
        // the clips have no collisions to draw; their figures are in the table
        let parts = c.seeded_parts();
        let (ph, top) = (260, 44);
        let (tw, _) = Canvas::text_size(&title, 2);
        let w = (84 * groups.len() as i32 + 60).max(tw as i32 + 24);
        let arena = matches!(parts.first(), Some(Part::Arena { .. }));
        let panels = parts.len() as i32 + i32::from(arena);
        let mut canvas = Canvas::new(w as usize, (top + panels * ph) as usize, WHITE);
        canvas.text((w - tw as i32) / 2, 6, &title, BLACK, 2);
        let mut x = 12;
        for (n, col) in &series {
            canvas.fill_rect(x, 28, 10, 7, *col);
            canvas.text(x + 14, 28, n, BLACK, 1);
            x += 14 + Canvas::text_size(n, 1).0 as i32 + 16;
        }
        let values = |p: usize, f: &dyn Fn(&Cell) -> Option<f64>| -> Vec<Vec<Option<f64>>> {
            pairs
                .iter()
                .map(|&(a, b)| {
                    [a, b]
                        .iter()
                        .map(|v| v.and_then(|v| f(&self.cells[p][v])))
                        .collect()
                })
                .collect()
        };
        let mut y = top;
        for (p, part) in parts.iter().enumerate() {
            let (title, vals, y_max) = match part {
                Part::Arena { .. } => (
                    format!("Success rate (%): {}", self.part_title(part)),
                    values(p, &|cell| cell.pooled.success().map(|s| 100.0 * s)),
                    100.0,
                ),
                _ => {
                    let v = values(p, &|cell| cell.pooled.collision_share().map(|s| 100.0 * s));
                    (
                        format!("Collisions (% of trials): {}", self.part_title(part)),
                        v,
                        100.0,
                    )
                }
            };
            draw_bars(
                &mut canvas,
                (0, y, w, ph),
                &Bars {
                    title: &title,
                    groups: groups.clone(),
                    series: &series,
                    values: vals,
                    y_max,
                    light_group: Some(0),
                    decimals: 0,
                },
            );
            y += ph;
            if p == 0 && arena {
                // the arena's speed right after its success
                let speeds = values(p, &|cell| match cell.pooled {
                    Measured::Arena { speed_mm_s, .. } => Some(speed_mm_s),
                    _ => None,
                });
                let most = speeds
                    .iter()
                    .flatten()
                    .flatten()
                    .fold(1.0f64, |a, &b| a.max(b));
                draw_bars(
                    &mut canvas,
                    (0, y, w, ph),
                    &Bars {
                        title: "Mean speed (mm/s) in the arena",
                        groups: groups.clone(),
                        series: &series,
                        values: speeds,
                        y_max: nice_ceiling(most),
                        light_group: Some(0),
                        decimals: 0,
                    },
                );
                y += ph;
            }
        }
        canvas
    }
}
