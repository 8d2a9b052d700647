//! `cargo alvs tables`: the headline figures of `stimuli`, `evasion`, `two-threats`, `arena`
//! and `swarm` in one world over several seeds (the report seeds 11–20 by default), as the
//! markdown tables docs/experiments.md quotes, so that each table there is one command to
//! regenerate when the world changes. Every row is the experiment's own run with its defaults
//! in that world and that seed (`cargo alvs <experiment> --world W --seed S`, and for the
//! arena's paper row `--model paper --controller alvs`); nothing is computed that the
//! experiment's report does not hold. `--firmware` adds the authors' firmware (`--model
//! firmware`) to the arena's table, beside the paper's model; `--camera-gain` runs every
//! experiment with another camera (as each experiment's own option does).

use std::fmt::Write;

use anyhow::{ensure, Result};
use serde::{Deserialize, Serialize};

use super::arena::{self, ArenaConfig, Trial};
use super::evasion::{self, EvasionConfig};
use super::stimuli::{self, StimuliConfig};
use super::swarm::{self, SwarmConfig};
use super::two_threats::{self, TwoThreatConfig};
use alvs_sim::{BuiltinWorld, GainModel, Kind};

/// An experiment `tables` covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Experiment {
    /// Experiment 1.
    Stimuli,
    /// Experiment 2.
    Evasion,
    /// Experiment 3.
    TwoThreats,
    /// Experiment 4.
    Arena,
    /// Experiment 5.
    Swarm,
}

impl Experiment {
    /// All five, in the paper's order.
    pub const ALL: [Experiment; 5] = [
        Experiment::Stimuli,
        Experiment::Evasion,
        Experiment::TwoThreats,
        Experiment::Arena,
        Experiment::Swarm,
    ];

    /// Its subcommand.
    pub const fn name(self) -> &'static str {
        match self {
            Experiment::Stimuli => "stimuli",
            Experiment::Evasion => "evasion",
            Experiment::TwoThreats => "two-threats",
            Experiment::Arena => "arena",
            Experiment::Swarm => "swarm",
        }
    }
}

/// What to tabulate.
#[derive(Debug, Clone, PartialEq)]
pub struct TablesConfig {
    /// The world every run is in.
    pub world: BuiltinWorld,
    /// One row (or one run pooled) per seed.
    pub seeds: Vec<u64>,
    /// Which experiments, in the table's order.
    pub experiments: Vec<Experiment>,
    /// Simulated minutes of an arena trial (its default 10).
    pub arena_minutes: f64,
    /// Simulated minutes of a swarm trial (its default 5).
    pub swarm_minutes: f64,
    /// The arena's table also has a column for the authors' firmware (ALVS with `--model
    /// firmware`).
    pub firmware: bool,
    /// Every run's camera gain (`--camera-gain`; the worlds' camera by default).
    pub gain: GainModel,
}

impl Default for TablesConfig {
    /// Every experiment in the replica, seeds 11–20, the experiments' own durations.
    fn default() -> Self {
        TablesConfig {
            world: BuiltinWorld::Fu2019,
            seeds: super::robustness::REPORT_SEEDS.collect(),
            experiments: Experiment::ALL.to_vec(),
            arena_minutes: ArenaConfig::default().minutes,
            swarm_minutes: SwarmConfig::default().minutes,
            firmware: false,
            gain: GainModel::default(),
        }
    }
}

impl TablesConfig {
    /// The command line that makes these tables (defaults left out).
    pub fn command(&self) -> String {
        let d = TablesConfig::default();
        let mut c = format!("cargo alvs tables --world {}", self.world.label());
        if self.seeds != d.seeds {
            for s in &self.seeds {
                let _ = write!(c, " --seed {s}");
            }
        }
        if self.experiments != d.experiments {
            for e in &self.experiments {
                let _ = write!(c, " --experiment {}", e.name());
            }
        }
        let has = |e: Experiment| self.experiments.contains(&e);
        if has(Experiment::Arena) && self.arena_minutes != d.arena_minutes {
            let _ = write!(c, " --arena-minutes {}", self.arena_minutes);
        }
        if has(Experiment::Swarm) && self.swarm_minutes != d.swarm_minutes {
            let _ = write!(c, " --swarm-minutes {}", self.swarm_minutes);
        }
        if has(Experiment::Arena) && self.firmware {
            c.push_str(" --firmware");
        }
        if self.gain != d.gain {
            let _ = write!(c, " --camera-gain {}", self.gain.name());
        }
        c
    }

    /// Checks the configuration (one error line).
    pub fn validate(&self) -> Result<()> {
        ensure!(!self.seeds.is_empty(), "no seed to run");
        ensure!(!self.experiments.is_empty(), "no experiment to run");
        for (name, m) in [
            ("--arena-minutes", self.arena_minutes),
            ("--swarm-minutes", self.swarm_minutes),
        ] {
            ensure!(
                m.is_finite() && m > 0.0 && m <= 1000.0,
                "{name} must be a positive number of minutes up to 1000, got {m}"
            );
        }
        Ok(())
    }
}

/// The tables of `config` in markdown, each headed by its experiment and the command that
/// makes it; the experiments' runs use `jobs` threads; `progress` is told of each run as it
/// starts.
pub fn tables(config: &TablesConfig, jobs: usize, progress: &dyn Fn(&str)) -> Result<String> {
    config.validate()?;
    let mut out = String::new();
    for &e in &config.experiments {
        let _ = writeln!(
            out,
            "#### `{}` in `{}`, seeds {}\n\n`{}`\n",
            e.name(),
            config.world.label(),
            seed_list(&config.seeds),
            TablesConfig {
                experiments: vec![e],
                ..config.clone()
            }
            .command()
        );
        let t = match e {
            Experiment::Stimuli => stimuli_table(config, jobs, progress)?,
            Experiment::Evasion => evasion_table(config, jobs, progress)?,
            Experiment::TwoThreats => two_threats_table(config, jobs, progress)?,
            Experiment::Arena => arena_table(config, jobs, progress)?,
            Experiment::Swarm => swarm_table(config, jobs, progress)?,
        };
        let _ = writeln!(out, "{t}");
    }
    Ok(out)
}

/// `11–20` for consecutive seeds, else `11, 13, 17`.
fn seed_list(seeds: &[u64]) -> String {
    let consecutive = seeds.windows(2).all(|w| w[1] == w[0] + 1);
    match (seeds.first(), seeds.last()) {
        (Some(a), Some(b)) if consecutive && seeds.len() > 2 => format!("{a}–{b}"),
        _ => seeds
            .iter()
            .map(u64::to_string)
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// `lo–hi` of `v` (`lo` alone when equal, `–` when empty).
fn range<T: PartialOrd + Copy + std::fmt::Display>(v: &[T]) -> String {
    let lo = v.iter().copied().reduce(|a, b| if b < a { b } else { a });
    let hi = v.iter().copied().reduce(|a, b| if b > a { b } else { a });
    match (lo, hi) {
        (Some(a), Some(b)) if a == b => format!("{a}"),
        (Some(a), Some(b)) => format!("{a}–{b}"),
        _ => "–".into(),
    }
}

fn pct(r: Option<f64>) -> String {
    r.map_or("–".into(), |r| format!("{:.1} %", 100.0 * r))
}

fn stimuli_table(c: &TablesConfig, jobs: usize, progress: &dyn Fn(&str)) -> Result<String> {
    let mut runs = Vec::new();
    for &seed in &c.seeds {
        progress(&format!("stimuli, seed {seed}"));
        let config = StimuliConfig {
            world: c.world,
            gain: c.gain,
            seed,
            ..StimuliConfig::default()
        };
        runs.push(stimuli::run(&config, jobs)?);
    }
    let mut t = String::new();
    if let Some(r) = runs.first() {
        let _ = writeln!(t, "Observer {}.\n", r.placement.describe());
    }
    let n = runs.len();
    let _ = writeln!(
        t,
        "| scene | objects | seeds with an alert | alert frames | first alert (frame) | short-mode frames | most fields | seeds with every object localised | seeds with every object in a field of its own | frames with every object in view in a field of its own |\n|---|---:|---:|---|---|---|---|---:|---:|---|"
    );
    for (k, s) in stimuli::scenes().iter().enumerate() {
        let of = |f: &dyn Fn(&stimuli::SceneResult) -> u32| -> Vec<u32> {
            runs.iter().map(|r| f(&r.scenes[k])).collect()
        };
        let firsts: Vec<u32> = runs
            .iter()
            .filter_map(|r| r.scenes[k].first_alert_frame)
            .collect();
        let objects = runs.first().map_or(0, |r| r.scenes[k].objects);
        let _ = writeln!(
            t,
            "| {} | {} | {}/{n} | {} | {} | {} | {} | {}/{n} | {}/{n} | {} |",
            s.name,
            objects,
            firsts.len(),
            range(&of(&|s| s.alert_frames)),
            range(&firsts),
            range(&of(&|s| s.short_mode_frames)),
            range(&of(&|s| s.max_afs as u32)),
            runs.iter()
                .filter(|r| r.scenes[k].localised == objects)
                .count(),
            runs.iter().filter(|r| r.scenes[k].own == objects).count(),
            range(&of(&|s| s.own_frames)),
        );
    }
    Ok(t)
}

/// A table of counts, a row per seed: `columns` heads the cells after the seed; `run` gives
/// a seed's description (the first seed's heads the table) and its cells, each a count of
/// some number; the last row sums them, the `bold` columns in bold.
fn counts_table(
    c: &TablesConfig,
    columns: &[&str],
    bold: &[usize],
    mut run: impl FnMut(u64) -> Result<(String, Vec<(usize, usize)>)>,
) -> Result<String> {
    let (mut head, mut rows) = (String::new(), String::new());
    let mut total = vec![(0, 0); columns.len()];
    for &seed in &c.seeds {
        let (about, cells) = run(seed)?;
        if head.is_empty() {
            head = about;
        }
        let _ = write!(rows, "| {seed} |");
        for ((k, n), t) in cells.into_iter().zip(total.iter_mut()) {
            let _ = write!(rows, " {k}/{n} |");
            *t = (t.0 + k, t.1 + n);
        }
        let _ = writeln!(rows);
    }
    let mut t = format!("{head}\n\n| seed | {} |\n|---|", columns.join(" | "));
    t.push_str(&"---:|".repeat(columns.len()));
    let _ = write!(t, "\n{rows}| **all** |");
    for (i, (k, n)) in total.into_iter().enumerate() {
        let b = if bold.contains(&i) { "**" } else { "" };
        let _ = write!(t, " {b}{k}/{n}{b} |");
    }
    Ok(t + "\n")
}

fn evasion_table(c: &TablesConfig, jobs: usize, progress: &dyn Fn(&str)) -> Result<String> {
    let columns = [
        "ALVS correct side",
        "ALVS collisions",
        "ALVS γ path first",
        "LGMD2 correct side",
        "LGMD2 collisions",
    ];
    counts_table(c, &columns, &[0, 1], |seed| {
        progress(&format!("evasion, seed {seed}"));
        let config = EvasionConfig {
            world: c.world,
            gain: c.gain,
            seed,
            ..EvasionConfig::default()
        };
        let r = evasion::run(&config, jobs, &|_| {})?;
        let about = format!(
            "Obstacle {} mm away at {} mm/s; tested robot {}.",
            r.distance_mm,
            config.speed_mm_s,
            r.setting.placement.describe()
        );
        let (a, l) = (&r.controllers[0], &r.controllers[1]);
        let n = a.angles;
        let cells = [
            a.correct_side,
            a.collisions,
            a.gamma_paths().unwrap_or(0),
            l.correct_side,
            l.collisions,
        ];
        Ok((about, cells.map(|k| (k, n)).to_vec()))
    })
}

fn two_threats_table(c: &TablesConfig, jobs: usize, progress: &dyn Fn(&str)) -> Result<String> {
    let columns = [
        "ALVS away from the faster",
        "ALVS collisions",
        "LGMD2 away from the faster",
        "LGMD2 collisions",
    ];
    counts_table(c, &columns, &[0, 2], |seed| {
        progress(&format!("two-threats, seed {seed}"));
        let config = TwoThreatConfig {
            world: c.world,
            gain: c.gain,
            seed,
            ..TwoThreatConfig::default()
        };
        let r = two_threats::run(&config, jobs, &|_| {})?;
        let about = format!(
            "{} runs per seed; tested robot {}.",
            config.runs,
            r.setting.placement.describe()
        );
        let (a, l) = (&r.controllers[0], &r.controllers[1]);
        let cells = [
            a.away_from_faster,
            a.collisions,
            l.away_from_faster,
            l.collisions,
        ];
        Ok((about, cells.map(|k| (k, a.runs)).to_vec()))
    })
}

fn arena_table(c: &TablesConfig, jobs: usize, progress: &dyn Fn(&str)) -> Result<String> {
    use alvs_tasks::model::fsm::FsmParams;
    use alvs_tasks::Params;
    let base = ArenaConfig {
        world: c.world,
        gain: c.gain,
        minutes: c.arena_minutes,
        ..ArenaConfig::default()
    };
    // ALVS, the paper's model (ALVS with --model paper), the authors' firmware (ALVS with
    // --model firmware, with --firmware), LGMD2: their trials over the seeds
    let mut models = vec![(Params::PAPER, FsmParams::PAPER)];
    let mut heads = vec!["ALVS", "the paper's model"];
    if c.firmware {
        models.push((Params::FIRMWARE, FsmParams::FIRMWARE));
        heads.push("the authors' firmware");
    }
    heads.push("LGMD2");
    let mut per: Vec<Vec<Trial>> = vec![Vec::new(); heads.len()];
    let mut rows = String::new();
    for &seed in &c.seeds {
        progress(&format!("arena, seed {seed}"));
        let r = arena::run(
            &ArenaConfig {
                seed,
                ..base.clone()
            },
            jobs,
            &|_| {},
        )?;
        let by = |trials: &[Trial], k: Kind| -> Vec<Trial> {
            trials
                .iter()
                .filter(|t| t.controller == k.name())
                .cloned()
                .collect()
        };
        let mut seed_trials = vec![by(&r.trials, Kind::Alvs)];
        for &(params, fsm) in &models {
            let m = arena::run(
                &ArenaConfig {
                    seed,
                    controllers: vec![Kind::Alvs],
                    params,
                    fsm,
                    ..base.clone()
                },
                jobs,
                &|_| {},
            )?;
            seed_trials.push(by(&m.trials, Kind::Alvs));
        }
        seed_trials.push(by(&r.trials, Kind::Lgmd2));
        let _ = write!(rows, "| {seed} |");
        for (k, trials) in seed_trials.into_iter().enumerate() {
            let s = arena::summarise("", &trials.iter().collect::<Vec<_>>());
            let _ = write!(rows, " {} ({}) |", pct(s.success_rate), s.encounters);
            per[k].extend(trials);
        }
        let _ = writeln!(rows);
    }
    let pooled: Vec<arena::ControllerSummary> = per
        .iter()
        .map(|trials| arena::summarise("", &trials.iter().collect::<Vec<_>>()))
        .collect();
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{} robots, {} min, background{} {}; success (encounters); pooled: encounters summed, \
         time pressed against a wall or obstacle and speed the mean over the seeds.\n",
        base.robots,
        base.minutes,
        if base.background_specs().len() > 1 {
            "s"
        } else {
            ""
        },
        base.background_specs().join(", ")
    );
    let _ = writeln!(
        t,
        "| seed | {} |\n|---|{}",
        heads.join(" | "),
        "---:|".repeat(heads.len())
    );
    t.push_str(&rows);
    let cells = |f: &dyn Fn(&arena::ControllerSummary) -> String| -> String {
        pooled.iter().map(f).collect::<Vec<_>>().join(" | ")
    };
    let _ = writeln!(
        t,
        "| **pooled** | {} |",
        cells(&|p| format!("**{}** ({})", pct(p.success_rate), p.encounters))
    );
    let _ = writeln!(
        t,
        "| at a wall, speed | {} |",
        cells(&|p| format!(
            "{:.1} %, {:.0} mm/s",
            100.0 * p.wall_contact_fraction,
            p.mean_speed_mm_s
        ))
    );
    // LGMD2 (the last column) has no short takeoff
    let alvs = &pooled[..pooled.len() - 1];
    let _ = writeln!(
        t,
        "| short takeoffs (near a threat) | {} | – |",
        alvs.iter()
            .map(|p| format!("{} ({})", p.short_takeoffs, p.short_takeoffs_in_encounter))
            .collect::<Vec<_>>()
            .join(" | ")
    );
    Ok(t)
}

fn swarm_table(c: &TablesConfig, jobs: usize, progress: &dyn Fn(&str)) -> Result<String> {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{} robots, {} min; spread (RMS distance from the centroid) at the start → over the \
         last minute, mm, and its share of the start; nearest neighbour over the last minute.\n",
        SwarmConfig::default().robots,
        c.swarm_minutes
    );
    let _ = writeln!(
        t,
        "| seed | swarm spread | nearest neighbour | spin / look | escaping (`alvs`) spread |\n|---|---|---:|---|---|"
    );
    let (mut swarm_share, mut escape_share) = (Vec::new(), Vec::new());
    for &seed in &c.seeds {
        progress(&format!("swarm, seed {seed}"));
        let config = SwarmConfig {
            world: c.world,
            gain: c.gain,
            seed,
            minutes: c.swarm_minutes,
            ..SwarmConfig::default()
        };
        let r = swarm::run(&config, jobs, &|_| {})?;
        let (s, e) = (&r.trials[0], &r.trials[1]);
        let share = |t: &swarm::SwarmTrial| t.spread_last_minute_mm / t.spread_start_mm;
        swarm_share.push(share(s));
        escape_share.push(share(e));
        let state = |n: &str| 100.0 * s.state_fraction.get(n).copied().unwrap_or(0.0);
        let _ = writeln!(
            t,
            "| {seed} | {:.0} → {:.0} ({:.0} %) | {:.0} | {:.0} / {:.0} % | {:.0} → {:.0} ({:.0} %) |",
            s.spread_start_mm,
            s.spread_last_minute_mm,
            100.0 * share(s),
            s.nearest_last_minute_mm,
            state("spin"),
            state("look"),
            e.spread_start_mm,
            e.spread_last_minute_mm,
            100.0 * share(e)
        );
    }
    let pcts = |v: &[f64]| -> Vec<u32> { v.iter().map(|x| (100.0 * x).round() as u32).collect() };
    let _ = writeln!(
        t,
        "| **all** | **{} %** of the start | | | {} % |",
        range(&pcts(&swarm_share)),
        range(&pcts(&escape_share))
    );
    Ok(t)
}
