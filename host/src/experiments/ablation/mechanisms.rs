//! The closed-loop mechanisms, one entry per thing the project adds to the paper's model —
//! those the default runs and the options it leaves off because they did not earn their place
//! — and the variants the ablation runs: the default, the paper's model, the default without
//! one of its mechanisms or with one option, the paper's model with one mechanism.
//!
//! A mechanism is the set of parameters that only work together (`q_arms` 3 needs
//! `q_grow_pct`; the swarm's look needs both its perception and its motion half). Removing it
//! sets those parameters to the paper's values; adding it sets them to their values in
//! [`Model::ALL`]. The test below holds the list complete: removing every mechanism from the
//! default gives the paper's model exactly, adding every one to it gives [`Model::ALL`], and
//! each one changes something.

use alvs_tasks::model::fsm::FsmParams;
use alvs_tasks::model::params::{Efference, Mechanisms, ShortGates, TableOne};
use alvs_tasks::Params;
use core::num::NonZeroU8;
use serde::Serialize;

use alvs_sim::Kind;

/// A model: its perception and its motion parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    /// Perception.
    pub params: Params,
    /// Motion (the FSM).
    pub fsm: FsmParams,
}

impl Model {
    /// The default (`--model alvs`).
    pub const ALVS: Model = Model {
        params: Params::ALVS,
        fsm: FsmParams::ALVS,
    };
    /// The paper's model (`--model paper`).
    pub const PAPER: Model = Model {
        params: Params::PAPER,
        fsm: FsmParams::PAPER,
    };
    /// The default with every option on too, at the values they had while they were in the
    /// default (before the ablation on the held-out seeds took them out), `q_grow_run` at the
    /// 3 frames its note measured, `border_crossing` on.
    pub const ALL: Model = Model {
        params: Params {
            table1: TableOne {
                t_s: 5500,
                ..Params::ALVS.table1
            },
            mechanisms: Mechanisms {
                q_grow_run: NonZeroU8::new(3),
                border_crossing: true,
                ..Params::ALVS.mechanisms
            },
            efference: Efference {
                blocked_change: NonZeroU8::new(2),
                ..Params::ALVS.efference
            },
            short: ShortGates {
                adapt_frames: NonZeroU8::new(30),
                short_cols: NonZeroU8::new(23),
                short_row: NonZeroU8::new(50),
                ..Params::ALVS.short
            },
            ..Params::ALVS
        },
        fsm: FsmParams::ALVS,
    };
}

/// One mechanism of the default.
#[derive(Debug, Clone, Copy)]
pub struct Mechanism {
    /// Its name in variant names (`alvs-NAME`, `paper+NAME`).
    pub name: &'static str,
    /// What it does, in a few words.
    pub what: &'static str,
    /// The parameters it sets.
    pub fields: &'static str,
    /// Whether the escape experiments can see it at all (the swarm's look acts only in the
    /// swarm behaviour).
    pub escape: bool,
    /// Copies its parameters from the second model into the first.
    copy: fn(&mut Model, &Model),
}

impl Mechanism {
    /// `m` with this mechanism's parameters at the paper's values.
    pub fn removed_from(&self, m: Model) -> Model {
        let mut out = m;
        (self.copy)(&mut out, &Model::PAPER);
        out
    }

    /// `m` with this mechanism's parameters at their values in [`Model::ALL`].
    pub fn added_to(&self, m: Model) -> Model {
        let mut out = m;
        (self.copy)(&mut out, &Model::ALL);
        out
    }

    /// Whether the default runs it (otherwise it is an option, off).
    pub fn in_default(&self) -> bool {
        self.removed_from(Model::ALVS) != Model::ALVS
    }
}

/// Every mechanism the project adds to the paper's model, in the default or an option,
/// perception first (in the order of `Params`), then motion (`FsmParams`).
pub const MECHANISMS: [Mechanism; 24] = [
    Mechanism {
        name: "warmup",
        what: "no field stimulated while the delay line refills",
        fields: "warmup",
        escape: true,
        copy: |m, s| m.params.mechanisms.warmup = s.params.mechanisms.warmup,
    },
    Mechanism {
        name: "flicker",
        what: "a whole-field brightness step is not motion",
        fields: "flicker_pct",
        escape: true,
        copy: |m, s| m.params.mechanisms.flicker_pct = s.params.mechanisms.flicker_pct,
    },
    Mechanism {
        name: "noise",
        what: "a frame of random pixels is no image (nor the frame after)",
        fields: "noise_pct",
        escape: true,
        copy: |m, s| m.params.mechanisms.noise_pct = s.params.mechanisms.noise_pct,
    },
    Mechanism {
        name: "blocked",
        what: "turn around when driving changes nothing (efference copy)",
        fields: "blocked_change",
        escape: true,
        copy: |m, s| m.params.efference.blocked_change = s.params.efference.blocked_change,
    },
    Mechanism {
        name: "derotate",
        what: "re-register the retina to each turn (efference copy)",
        fields: "derotate",
        escape: true,
        copy: |m, s| m.params.efference.derotate = s.params.efference.derotate,
    },
    Mechanism {
        name: "adapt",
        what: "short mode needs a response growing above its running mean",
        fields: "adapt_frames",
        escape: true,
        copy: |m, s| m.params.short.adapt_frames = s.params.short.adapt_frames,
    },
    Mechanism {
        name: "three-arms",
        what: "3 of 4 quadrants open the gate if their drive grows",
        fields: "q_arms, q_grow_pct",
        escape: true,
        copy: |m, s| {
            m.params.choices.q_arms = s.params.choices.q_arms;
            m.params.mechanisms.q_grow_pct = s.params.mechanisms.q_grow_pct;
        },
    },
    Mechanism {
        name: "grow-run",
        what: "a partial opening also stands after its drive grew 3 frames in a row",
        fields: "q_grow_run",
        escape: true,
        copy: |m, s| m.params.mechanisms.q_grow_run = s.params.mechanisms.q_grow_run,
    },
    Mechanism {
        name: "quiet-attention",
        what: "a lower T_a when little of the scene moves",
        fields: "t_a_quiet",
        escape: true,
        copy: |m, s| m.params.mechanisms.t_a_quiet = s.params.mechanisms.t_a_quiet,
    },
    Mechanism {
        name: "border",
        what: "a quadrant the view's side border cuts off is blind, not silent",
        fields: "border_arms",
        escape: true,
        copy: |m, s| m.params.mechanisms.border_arms = s.params.mechanisms.border_arms,
    },
    Mechanism {
        name: "border-crossing",
        what: "with border: a side is cut once the field's square crosses it",
        fields: "border_crossing",
        escape: true,
        copy: |m, s| m.params.mechanisms.border_crossing = s.params.mechanisms.border_crossing,
    },
    Mechanism {
        name: "band",
        what: "driving, fields above the body's height are silent",
        fields: "band_row",
        escape: true,
        copy: |m, s| m.params.efference.band_row = s.params.efference.band_row,
    },
    Mechanism {
        name: "floor",
        what: "an obstacle's foot near in the path alerts (floor line)",
        fields: "floor_row",
        escape: true,
        copy: |m, s| m.params.efference.floor_row = s.params.efference.floor_row,
    },
    Mechanism {
        name: "short-path",
        what: "driving, short mode only for a threat in the path",
        fields: "short_cols",
        escape: true,
        copy: |m, s| m.params.short.short_cols = s.params.short.short_cols,
    },
    Mechanism {
        name: "short-near",
        what: "driving, short mode only for a threat whose foot is near",
        fields: "short_row",
        escape: true,
        copy: |m, s| m.params.short.short_row = s.params.short.short_row,
    },
    Mechanism {
        name: "uncut",
        what: "standing, a field the view's side border cuts counts whole for T_s",
        fields: "short_uncut",
        escape: true,
        copy: |m, s| m.params.short.short_uncut = s.params.short.short_uncut,
    },
    Mechanism {
        name: "young",
        what: "standing, an alert in a field's first d frames starts the short mode",
        fields: "short_young",
        escape: true,
        copy: |m, s| m.params.short.short_young = s.params.short.short_young,
    },
    Mechanism {
        name: "t-s",
        what: "T_s 5500 instead of Table I's 7000",
        fields: "t_s",
        escape: true,
        copy: |m, s| m.params.table1.t_s = s.params.table1.t_s,
    },
    Mechanism {
        name: "escape-saccade",
        what: "short mode while escaping turns away in place, no new γ path",
        fields: "escape_saccade",
        escape: true,
        copy: |m, s| m.fsm.escape.escape_saccade = s.fsm.escape.escape_saccade,
    },
    Mechanism {
        name: "takeoff-drive",
        what: "the long takeoff moves along its set-point while it turns",
        fields: "takeoff_drive",
        escape: true,
        copy: |m, s| m.fsm.escape.takeoff_drive = s.fsm.escape.takeoff_drive,
    },
    Mechanism {
        name: "brisk-turns",
        what: "an escape's turns three times as brisk, limited by the wheels only",
        fields: "takeoff_gain, takeoff_yaw_deg_s",
        escape: true,
        copy: |m, s| {
            m.fsm.escape.takeoff_gain = s.fsm.escape.takeoff_gain;
            m.fsm.escape.takeoff_yaw_deg_s = s.fsm.escape.takeoff_yaw_deg_s;
        },
    },
    Mechanism {
        name: "jump",
        what: "a takeoff from standing escapes at full strength for its first 0.2 s",
        fields: "jump_frames",
        escape: true,
        copy: |m, s| m.fsm.escape.jump_frames = s.fsm.escape.jump_frames,
    },
    Mechanism {
        name: "gamma-turn",
        what: "the γ path turns with the takeoff's gain, under the yaw limit",
        fields: "gamma_turn",
        escape: true,
        copy: |m, s| m.fsm.escape.gamma_turn = s.fsm.escape.gamma_turn,
    },
    Mechanism {
        name: "swarm-look",
        what: "swarm: stand and look for movers, wander towards them",
        fields: "look_change, look_every",
        escape: false,
        copy: |m, s| {
            m.params.swarm.look_change = s.params.swarm.look_change;
            m.fsm.swarm.look_every = s.fsm.swarm.look_every;
        },
    },
];

/// A mechanism by name.
pub fn mechanism(name: &str) -> Option<&'static Mechanism> {
    MECHANISMS.iter().find(|m| m.name == name)
}

/// What one row of the ablation runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(into = "String")]
pub enum Variant {
    /// The default.
    Alvs,
    /// The paper's model.
    Paper,
    /// The LGMD2 baseline, as the arena runs it.
    Lgmd2,
    /// The default without `MECHANISMS[i]` (one it runs).
    Without(usize),
    /// The default with `MECHANISMS[i]` (an option it leaves off).
    Plus(usize),
    /// The paper's model with `MECHANISMS[i]`.
    With(usize),
}

impl From<Variant> for String {
    fn from(v: Variant) -> String {
        v.name()
    }
}

impl Variant {
    /// Its name: `alvs`, `paper`, `lgmd2`, `alvs-MECHANISM`, `alvs+OPTION`, `paper+MECHANISM`.
    pub fn name(self) -> String {
        match self {
            Variant::Alvs => "alvs".into(),
            Variant::Paper => "paper".into(),
            Variant::Lgmd2 => "lgmd2".into(),
            Variant::Without(i) => format!("alvs-{}", MECHANISMS[i].name),
            Variant::Plus(i) => format!("alvs+{}", MECHANISMS[i].name),
            Variant::With(i) => format!("paper+{}", MECHANISMS[i].name),
        }
    }

    /// Inverse of [`Variant::name`]; the error lists what is known.
    pub fn from_name(s: &str) -> Result<Variant, String> {
        let index = |m: &str| MECHANISMS.iter().position(|x| x.name == m);
        let v = match s {
            "alvs" => Some(Variant::Alvs),
            "paper" => Some(Variant::Paper),
            "lgmd2" => Some(Variant::Lgmd2),
            _ => s
                .strip_prefix("alvs-")
                .and_then(index)
                .map(Variant::Without)
                .or_else(|| s.strip_prefix("alvs+").and_then(index).map(Variant::Plus))
                .or_else(|| s.strip_prefix("paper+").and_then(index).map(Variant::With)),
        };
        let names = |default: bool| -> String {
            let n: Vec<&str> = MECHANISMS
                .iter()
                .filter(|m| m.in_default() == default)
                .map(|m| m.name)
                .collect();
            n.join(", ")
        };
        match v {
            Some(Variant::Without(i)) if !MECHANISMS[i].in_default() => Err(format!(
                "{s:?}: the default does not run {0}; alvs+{0} adds it",
                MECHANISMS[i].name
            )),
            Some(Variant::Plus(i)) if MECHANISMS[i].in_default() => Err(format!(
                "{s:?}: the default already runs {0}; alvs-{0} removes it",
                MECHANISMS[i].name
            )),
            Some(v) => Ok(v),
            None => Err(format!(
                "unknown variant {s:?}: alvs, paper, lgmd2, alvs-M with M one of the default's \
                 mechanisms ({}), alvs+O with O one of its options ({}), or paper+M with M any \
                 of them",
                names(true),
                names(false)
            )),
        }
    }

    /// The default plan: the default, the paper's model and LGMD2, then for each mechanism the
    /// escape experiments can see the default without it (or, for an option, with it), then
    /// the paper's model with each.
    pub fn all() -> Vec<Variant> {
        let escape = || (0..MECHANISMS.len()).filter(|&i| MECHANISMS[i].escape);
        [Variant::Alvs, Variant::Paper, Variant::Lgmd2]
            .into_iter()
            .chain(escape().map(Variant::on_the_default))
            .chain(escape().map(Variant::With))
            .collect()
    }

    /// The default without `MECHANISMS[i]` if it runs it, with it if not.
    pub fn on_the_default(i: usize) -> Variant {
        if MECHANISMS[i].in_default() {
            Variant::Without(i)
        } else {
            Variant::Plus(i)
        }
    }

    /// The controller the tested robots run.
    pub fn kind(self) -> Kind {
        match self {
            Variant::Lgmd2 => Kind::Lgmd2,
            _ => Kind::Alvs,
        }
    }

    /// Its model (LGMD2 takes its cruise, turn and alignment from the default's motion, as
    /// the arena gives it).
    pub fn model(self) -> Model {
        match self {
            Variant::Alvs | Variant::Lgmd2 => Model::ALVS,
            Variant::Paper => Model::PAPER,
            Variant::Without(i) => MECHANISMS[i].removed_from(Model::ALVS),
            Variant::Plus(i) => MECHANISMS[i].added_to(Model::ALVS),
            Variant::With(i) => MECHANISMS[i].added_to(Model::PAPER),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mechanisms_are_exactly_what_the_default_adds_to_the_paper() {
        let all_removed = MECHANISMS
            .iter()
            .fold(Model::ALVS, |m, x| x.removed_from(m));
        assert_eq!(all_removed, Model::PAPER);
        let all_added = MECHANISMS.iter().fold(Model::PAPER, |m, x| x.added_to(m));
        assert_eq!(all_added, Model::ALL);
        let options = MECHANISMS.iter().filter(|m| !m.in_default());
        assert_eq!(
            options.fold(Model::ALL, |m, x| x.removed_from(m)),
            Model::ALVS
        );
        for m in &MECHANISMS {
            assert_ne!(m.added_to(Model::PAPER), Model::PAPER, "{}", m.name);
            assert_eq!(
                m.added_to(Model::ALVS) == Model::ALVS,
                m.in_default(),
                "{}",
                m.name
            );
        }
        // the options the ablation on the held-out seeds took out of the default
        let off: Vec<&str> = MECHANISMS
            .iter()
            .filter(|m| !m.in_default())
            .map(|m| m.name)
            .collect();
        assert_eq!(off, ["blocked", "adapt", "short-path", "short-near", "t-s"]);
    }

    #[test]
    fn variant_names_round_trip_and_unknown_ones_are_refused() {
        for v in Variant::all() {
            assert_eq!(Variant::from_name(&v.name()), Ok(v));
        }
        assert_eq!(Variant::from_name("alvs-floor"), Ok(Variant::Without(12)));
        assert_eq!(Variant::from_name("alvs+blocked"), Ok(Variant::Plus(3)));
        let e = Variant::from_name("alvs-wings").unwrap_err();
        assert!(e.contains("floor") && e.contains("alvs-M"), "{e}");
        assert!(Variant::from_name("paper+").is_err());
        let e = Variant::from_name("alvs-blocked").unwrap_err();
        assert!(e.contains("alvs+blocked"), "{e}");
        let e = Variant::from_name("alvs+floor").unwrap_err();
        assert!(e.contains("alvs-floor"), "{e}");
    }
}
