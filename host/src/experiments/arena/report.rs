//! The report: the table on stdout, the JSON, the trace file and the pictures' paths.

use super::*;
use crate::experiments::Report;

/// Controller states in the order tables and pictures list them.
pub(super) const STATE_ORDER: [&str; 7] = [
    "wander",
    "long_takeoff",
    "escape",
    "short_takeoff",
    "spin",
    "look",
    "stop",
];

/// Short column heads of the states.
pub(super) fn state_head(s: &str) -> &str {
    match s {
        "long_takeoff" => "long_to",
        "short_takeoff" => "short_to",
        other => other,
    }
}

pub(super) fn pct(r: Option<f64>) -> String {
    r.map_or("n/a".into(), |r| format!("{:.1} %", 100.0 * r))
}

pub(super) fn slug(s: &str) -> String {
    let name = Path::new(s)
        .file_stem()
        .filter(|_| s.contains('/') || s.contains('.'))
        .map_or(s.to_string(), |f| f.to_string_lossy().into_owned());
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect()
}

impl ArenaReport {
    /// The states that occur anywhere in the run, in [`STATE_ORDER`] then alphabetical order.
    pub(super) fn states(&self) -> Vec<String> {
        let mut all: Vec<String> = self
            .trials
            .iter()
            .flat_map(|t| t.state_frames.keys().cloned())
            .collect();
        all.sort_by_key(|s| {
            (
                STATE_ORDER
                    .iter()
                    .position(|o| o == s)
                    .unwrap_or(usize::MAX),
                s.clone(),
            )
        });
        all.dedup();
        all
    }
}

impl Report for ArenaReport {
    /// `{"alvs": {...}, "lgmd2": {...}, "trials": [...]}`: one key per controller run (its
    /// [`ControllerSummary`]) and every [`Trial`].
    fn json(&self) -> serde_json::Value {
        let mut map = serde_json::Map::new();
        for s in &self.summaries {
            map.insert(
                s.controller.to_string(),
                serde_json::to_value(s).expect("summaries serialise"),
            );
        }
        map.insert(
            "trials".into(),
            serde_json::to_value(&self.trials).expect("trials serialise"),
        );
        // the ALVS perception preset: "alvs", "paper" or "custom" (--param)
        map.insert("model".into(), self.config.params.preset_name().into());
        // the motion (FSM) preset: "alvs", "paper" or "custom" (--fsm)
        map.insert("fsm".into(), self.config.fsm.preset_name().into());
        map.insert("world".into(), self.config.world.label().into());
        serde_json::Value::Object(map)
    }

    /// The human summary: one line per trial, then one per controller with the paper's figure.
    fn table(&self) -> String {
        use std::fmt::Write;
        let c = &self.config;
        let states = self.states();
        let mut out = String::new();
        let frames = self.trials.first().map_or(0, |t| t.frames);
        let _ = writeln!(
            out,
            "arena: {} robots in {}, {} min per trial ({} camera frames per robot), seed {}, ALVS model {}, FSM {}, {} trials on {} threads, {:.1} s",
            c.robots,
            c.world.label(),
            c.minutes,
            frames,
            c.seed,
            c.params.preset_name(),
            c.fsm.preset_name(),
            self.trials.len(),
            self.jobs,
            self.wall_clock_s
        );
        let _ = writeln!(
            out,
            "collision: centre distance < 42 mm (robot-robot and robot-wall); encounter: bodies \
             within 2 diameters; success = encounters without collision / encounters"
        );
        let _ = writeln!(out);
        let mut head = format!(
            "{:<10} {:<14} {:>6} {:>6} {:>9}  {:>16} {:>16}  {:>7} {:>7} {:>7} {:>8} {:>6}",
            "controller",
            "background",
            "enc",
            "coll",
            "success",
            "robot-robot",
            "robot-wall",
            "rr/min",
            "rw/min",
            "touches",
            "at wall",
            "mm/s"
        );
        for s in &states {
            let _ = write!(head, " {:>8}", state_head(s));
        }
        let _ = write!(head, " {:>7}", "wall s");
        let rule = "-".repeat(head.len());
        let _ = writeln!(out, "{head}");
        let _ = writeln!(
            out,
            "{:51}{:>16} {:>16}  {:23} {:>8} {:>6} (% of time per state)",
            "", "enc/coll/succ", "enc/coll/succ", "", "% time", "speed"
        );
        let _ = writeln!(out, "{rule}");
        let tally = |t: &TallyStats| {
            format!(
                "{}/{}/{}",
                t.encounters,
                t.collided_encounters,
                t.success_rate
                    .map_or("-".into(), |r| format!("{:.1}", 100.0 * r))
            )
        };
        let line = |out: &mut String,
                    name: &str,
                    bg: &str,
                    (enc, coll, succ): (u64, u64, Option<f64>),
                    (rr, rw): (&TallyStats, &TallyStats),
                    (touches, at_wall, speed): (u64, f64, f64),
                    fractions: &BTreeMap<String, f64>,
                    wall_s: f64| {
            let _ = write!(
                out,
                "{:<10} {:<14} {:>6} {:>6} {:>9}  {:>16} {:>16}  {:>7.2} {:>7.2} {:>7} {:>8.1} {:>6.0}",
                name,
                bg,
                enc,
                coll,
                pct(succ),
                tally(rr),
                tally(rw),
                rr.collisions_per_minute,
                rw.collisions_per_minute,
                touches,
                100.0 * at_wall,
                speed
            );
            for s in &states {
                let f = fractions.get(s).copied().unwrap_or(0.0);
                let _ = write!(out, " {:>8.1}", 100.0 * f);
            }
            let _ = writeln!(out, " {wall_s:>7.1}");
        };
        for t in &self.trials {
            line(
                &mut out,
                t.controller,
                &t.background,
                (t.encounters, t.collisions, t.success_rate),
                (&t.robot_robot, &t.robot_wall),
                (t.wall_touches, t.wall_contact_fraction, t.mean_speed_mm_s),
                &t.state_fraction,
                t.wall_clock_s,
            );
        }
        let _ = writeln!(out, "{rule}");
        for s in &self.summaries {
            line(
                &mut out,
                s.controller,
                &format!("all ({})", s.trials),
                (s.encounters, s.collisions, s.success_rate),
                (&s.robot_robot, &s.robot_wall),
                (s.wall_touches, s.wall_contact_fraction, s.mean_speed_mm_s),
                &s.state_fraction,
                s.wall_clock_s,
            );
        }
        let _ = writeln!(out);
        let _ = writeln!(
            out,
            "{:<10} {:>9} {:>9}  {:>12} {:>12}  {:>24}",
            "controller", "success", "paper", "rr coll/min", "rw coll/min", "short takeoffs near"
        );
        for s in &self.summaries {
            let near = match s.short_takeoffs {
                0 => "-".to_string(),
                n => format!(
                    "{} of {n} ({:.0} %)",
                    s.short_takeoffs_in_encounter,
                    100.0 * s.short_takeoffs_in_encounter as f64 / n as f64
                ),
            };
            let _ = writeln!(
                out,
                "{:<10} {:>9} {:>9}  {:>12.2} {:>12.2}  {near:>24}",
                s.controller,
                pct(s.success_rate),
                pct(s.paper_success_rate),
                s.robot_robot.collisions_per_minute,
                s.robot_wall.collisions_per_minute
            );
        }
        let _ = writeln!(
            out,
            "(enc/coll/succ: encounters / encounters with a collision / success %; coll: collision \
             episodes; at wall: % of robot time pressed against a wall; speed: mean robot speed; \
             short takeoffs near: started inside an encounter, a wall within 105 mm or a robot \
             within 126 mm)"
        );
        out
    }

    /// Writes every trial's trace as CSV ([`trace_header`], then the trials in order; empty
    /// unless the run had [`ArenaConfig::trace`]).
    fn write_trace(&self, path: &Path) -> Result<()> {
        let leads: Vec<String> = self
            .trials
            .iter()
            .map(|t| format!("{},{}", t.controller, csv_field(&t.background)))
            .collect();
        encounter::write_csv(
            path,
            &trace_header(),
            leads
                .iter()
                .zip(&self.trials)
                .map(|(lead, t)| (lead.as_str(), t.trace.as_slice())),
        )
    }

    /// Writes one top-down trajectory picture per trial (`<controller>_<background>.png`) and
    /// `summary.png` into `dir` (created); returns their paths.
    fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let mut paths = Vec::new();
        let world = self.config.world.world();
        for t in &self.trials {
            let path = dir.join(format!("{}_{}.png", t.controller, slug(&t.background)));
            trial_picture(t, &world)
                .save_png(&path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            paths.push(path);
        }
        let path = dir.join("summary.png");
        self.summary_picture()
            .save_png(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        paths.push(path);
        Ok(paths)
    }
}
