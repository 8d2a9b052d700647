//! The escape FSM's parameters ([`FsmParams`]): one `param_groups!` declaration generating
//! their names, ranges and setters, with each value's documentation; the three presets
//! ([`FsmParams::PAPER`], [`FsmParams::ALVS`], [`FsmParams::FIRMWARE`]) and the parsing of a
//! command line's `NAME=VALUE`. Re-exported from [`crate::model::fsm`], where the state machine
//! that reads them lives.

use core::num::NonZeroU32;

use crate::model::param_table::{param_groups, write_list, Range};

/// A real number ≥ 0, finite.
const NON_NEG: Range = Range::Real(0.0, f32::MAX);
/// A real number ≥ 0, or `inf`.
const NON_NEG_INF: Range = Range::Real(0.0, f32::INFINITY);
/// A count of frames.
const FRAMES: Range = Range::Int(0, u32::MAX as i64);

param_groups! {
    /// Parameters of the FSM, grouped by what they are. The paper gives only the wander speed
    /// (≈10 cm/s); the rest are choices for a 4 cm Colias at 30 fps. Units: mm, mm/s, degrees,
    /// frames. Each is named `group.field` (or the field alone) on the command line (`--fsm`);
    /// a switch is a `bool`, a mechanism the paper lacks that can be off an `Option`.
    pub struct FsmParams {
        /// The robot's motion: speeds, the wheels, the heading controller.
        motion: Motion {
            /// Wander speed, mm/s. Paper: constant velocity ≈10 cm/s.
            cruise_mm_s: f32 = NON_NEG,
            /// Escape speed at `S = 1`, mm/s; the escape runs at `S · max` with `S ∈ [0.5, 1)` (Eq. 11).
            max_escape_mm_s: f32 = NON_NEG,
            /// Reverse speed of short phase 1 at `S = 1`, mm/s (also scaled by `S`).
            retreat_mm_s: f32 = NON_NEG,
            /// Hard limit on each wheel's speed, mm/s. Turning has priority: forward speed is cut so
            /// that `|v| + |ω|·track/2` stays below it.
            max_wheel_mm_s: f32 = NON_NEG,
            /// Distance between the wheels, mm.
            track_mm: f32 = NON_NEG,
            /// Heading P-gain, 1/s: `ω = gain · error`.
            heading_gain: f32 = NON_NEG,
            /// Yaw-rate limit of the heading controller, °/s.
            max_yaw_deg_s: f32 = NON_NEG,
            /// A set-point counts as reached when `|error| ≤` this, degrees.
            align_tol_deg: f32 = NON_NEG,
        },
        /// How long the escape's states last, and how many alert frames start one.
        timing: Timing {
            /// Frames short phase 1 reverses at most; then it turns in place until aligned with `sp¹`.
            /// The camera looks forward: reversing is blind. Default `u32::MAX`: the paper's γ path,
            /// which reverses until aligned; 6 cuts wall collisions on the built-in walls but lowers
            /// the success rate on the outdoor photographs (`docs/experiments.md`, "Closed-loop
            /// mechanisms").
            retreat_frames: u32 = FRAMES,
            /// Escape lasts at least this many frames before a new alert or the quiet count act.
            min_escape_frames: u32 = FRAMES,
            /// Consecutive frames without alert that count as "escaped successfully" → Wander.
            quiet_frames: u32 = FRAMES,
            /// A takeoff (long, or the whole short γ path) gives up turning after this many frames and
            /// escapes anyway, so that stuck wheels or a bad heading estimate cannot spin it forever.
            takeoff_timeout_frames: u32 = FRAMES,
            /// Consecutive alert frames before the FSM acts on an alert or on the short mode. 1 acts
            /// on a single frame; the paper's firmware waits for 3 frames above its threshold.
            alert_frames: u32 = FRAMES,
        },
        /// Saccadic suppression (an efference copy): perception ignored while, and just after,
        /// the robot turns fast.
        suppression: Suppression {
            /// While the robot turns faster than this (the yaw rate it commanded on the previous
            /// frame, an efference copy), alerts and short mode are ignored. A turn at hundreds of
            /// °/s sweeps the scene many pixels per frame; the correlators alias and every
            /// quadrant fires, with a threat centroid made of self-motion. Flies suppress visual
            /// responses during their own saccades for the same reason. `f32::INFINITY` (`inf`)
            /// disables it.
            saccade_yaw_deg_s: f32 = NON_NEG_INF,
            /// Frames of perception also ignored after a fast turn has slowed below
            /// `saccade_yaw_deg_s`: the network still holds the turn in its delay line (`C_d`) and
            /// its fields' LPLC2 history, so the first frames after a saccade report self-motion.
            settle_frames: u32 = FRAMES,
        },
        /// Blocked way (efference copy, [`crate::model::closed_loop::progress`]): the robot drove but the view
        /// did not change.
        blocked: Blocked {
            /// Frames between two views compared. Active only when the network reports views
            /// (`Params::mechanisms.blocked_change` set).
            blocked_frames: u32 = FRAMES,
            /// Forward travel the FSM must have commanded over those frames, mm.
            blocked_travel_mm: f32 = NON_NEG,
            /// ... while its heading changed by at most this, degrees.
            blocked_yaw_deg: f32 = NON_NEG,
        },
        /// The escape's closed-loop mechanisms, beyond the paper's FSM.
        escape: Escape {
            /// Moving while turning in the long takeoff: the robot drives at this fraction of the
            /// escape speed times `cos(heading error)`, so its motion along the escape set-point is
            /// never towards the threat: it reverses while the set-point is behind it and moves
            /// forward once within 90°. 0 is the paper's turn in place ([`FsmParams::PAPER`]); the
            /// default 0.5 gets the robot out of the obstacle's path while it turns (evasion
            /// collisions 2/9 → 1/9 on the textured walls, 1/9 → 0/9 on plain ones). The escape
            /// saccade always turns in place: driving there put the robots against the walls
            /// (`docs/experiments.md`, "Closed-loop mechanisms").
            takeoff_drive: f32 = NON_NEG,
            /// Heading gain of the long takeoff's turn and of the saccades (the escape saccade, the
            /// turn away from an obstacle close ahead), as a multiple of `heading_gain` (wander, the
            /// escape's run and the γ path keep `heading_gain`, unless `gamma_turn`: the γ path's
            /// retreat and forward arc need wheel speed a saturated turn would take). 1 turns like
            /// every other turn (the paper's model); the default 3, with `takeoff_yaw_deg_s` at the wheels'
            /// limit, turns 150° in about 0.3 s instead of 0.7 s: with a P controller of 4/s the last
            /// tens of degrees take most of a turn, and an obstacle first seen about a second before
            /// contact arrives while the robot is still turning (issue 30's trace of two threats,
            /// `docs/ablation.md`). Flies' saccades and takeoff turns take 50–100 ms.
            takeoff_gain: f32 = NON_NEG,
            /// Yaw-rate limit of those turns, °/s. The paper's model keeps `max_yaw_deg_s` (360); the
            /// default, `f32::INFINITY` (`inf`), leaves only the wheels' limit (`max_wheel_mm_s` over
            /// half the track: 716°/s for 300 mm/s and 48 mm), what the robot can do.
            takeoff_yaw_deg_s: f32 = NON_NEG_INF,
            /// How the escape strength `S(t)` of Eq. (11) sets the speed. 0, the default: `S` is
            /// latched when a takeoff starts, so its escape (and its γ path) runs at the speed of the
            /// trigger. 1: `S` follows the live response on every Escape frame whose perception is not
            /// suppressed, Eq. (11)'s time argument taken literally (with nothing looming `S` = 0.5 and
            /// the escape slows to half `max_escape_mm_s`). 2: also during the γ path. Measured in
            /// `docs/experiments.md` ("Closed-loop mechanisms"): better on the built-in walls, worse on
            /// the outdoor photographs, so it stays opt-in.
            live_strength: u8 = Range::Int(0, 2),
            /// Short mode during an Escape: `false` starts the paper's γ path (a new takeoff,
            /// reversing first; [`FsmParams::PAPER`]); `true`, the default, starts a saccade
            /// instead, a long takeoff to `θ¹_short` (90° away from the threat's side, in place),
            /// then the escape goes on at the new heading. Short mode during the saccade starts a
            /// new saccade. A fly that has taken off answers looming ahead with a
            /// collision-avoidance saccade away from the expanding side, not with another takeoff;
            /// and every γ path ends 180° from an `X̄` that lies ahead, so a γ path during an
            /// escape turns the robot back towards the threat it is fleeing. Measured in
            /// `docs/experiments.md` ("Closed-loop mechanisms"). (The floor line's obstacle
            /// saccade, `Params::efference.floor_row`, does not depend on it: `--model paper
            /// --param floor_row=52` makes it too.)
            escape_saccade: bool = Range::Int(0, 1),
            /// The takeoff's jump: a takeoff from standing, started by a field's response (not by
            /// the floor line), begins its escape with this many frames at full strength
            /// (`S = 1`, `max_escape_mm_s`) before the latched `S` sets the speed. A fly's
            /// takeoff, long or short, is launched by a jump at full thrust; a robot already
            /// moving (wandering, escaping) has no takeoff to make and keeps `S`. 6 frames
            /// (0.2 s) carry the robot one body length (40 mm) at 200 mm/s. `S` latched at the
            /// first alert frame is small (ΣLPLC2 1,000–6,000: `S` 0.56–0.82), and a robot 200
            /// mm/s fast first seen 0.5 s away caught the standing robot before it had run one
            /// body length (two threats, issue 30; `docs/ablation.md`). The authors' robot
            /// escapes at full speed after every alert (its `S` > 0.9995 above its alert
            /// threshold, `docs/notes/2026-11-27-authors-firmware.md`). `None`: `S` from the
            /// start (the paper).
            jump_frames: Option<NonZeroU32> = FRAMES,
            /// The γ path's turns take the long takeoff's gain (`takeoff_gain` times
            /// `heading_gain`) but keep the yaw limit `max_yaw_deg_s`, so that its retreat and
            /// forward arc keep their wheel speed (the takeoff's unbounded turn would take it
            /// all). `false`: `heading_gain`, as every turn of the paper's model. A short mode is
            /// a threat close by; a P controller of 4/s spends most of a turn on its last tens
            /// of degrees and leaves the robot facing a fast robot for most of a second (two
            /// threats; `docs/model.md`, "Visuomotor and FSM choices").
            gamma_turn: bool = Range::Int(0, 1),
        },
        /// The swarm behaviour: the spin, and the looks for moving objects.
        swarm: Swarm {
            /// The spin lasts this many frames after the last alert.
            spin_frames: u32 = FRAMES,
            /// Yaw rate of the spin, °/s (positive = spin right). 180: perception is ignored
            /// while the robot spins (saccadic suppression), so a spin lasts `spin_frames` = 1 s and
            /// turns the robot half round: it leaves facing away from what it saw, as every escape
            /// of the paper ends 180° from the threat. A full turn (360°/s) sends it back into what it
            /// saw, and the group does not cluster (`docs/experiments.md`, "Swarm").
            spin_deg_s: f32 = NON_NEG,
            /// Frames of wandering before the robot stops to look for moving objects (it also
            /// looks after every spin). A look stands until the look beside the network reports what
            /// it saw (`Params::look_change`, [`crate::model::closed_loop::movers`]: 22 standing frames, 0.73 s; at
            /// most [`LOOK_TIMEOUT_FRAMES`]); the robot then wanders towards the mover, or, with
            /// nothing in view, turns 90° in place and looks again, up to `look_scans` times, and
            /// wanders on. A value much below a look's length leaves little wandering. Spinning and
            /// driving robots are the movers a standing robot sees, so the group gathers where the
            /// others spin (the paper's robots "moved toward a swarm leader", Sec. IV-D). `None`
            /// (0, `none` or `off`) never looks (the paper). Measured in `docs/experiments.md`,
            /// "Swarm".
            ///
            /// [`LOOK_TIMEOUT_FRAMES`]: super::LOOK_TIMEOUT_FRAMES
            look_every: Option<NonZeroU32> = FRAMES,
            /// Further looks, each 90° on, after a look that saw nothing; at most
            /// [`MAX_LOOK_SCANS`] (a full circle; more act as that many).
            ///
            /// [`MAX_LOOK_SCANS`]: super::MAX_LOOK_SCANS
            look_scans: u32 = FRAMES,
        },
        /// What the authors' public firmware's state machine does differently from the paper.
        firmware: FirmwareFsm {
            /// The short mode starts the γ path only in a long takeoff (the authors' firmware: an
            /// alert in Wander or Stop starts a long takeoff, and a threat above `T_s` during it a
            /// short one). `false` (the paper): "the current state is overridden by the short takeoff
            /// state" (Sec. II-B), whatever it is. The escape saccade (`escape_saccade`) is not
            /// affected.
            short_from_long: bool = Range::Int(0, 1),
            /// After this many frames of wandering without an alert the robot stops ([`State::Stop`])
            /// and stands until a threat comes (the authors' firmware: 1000 frames, 33 s). `None`
            /// (the paper): it wanders on.
            ///
            /// [`State::Stop`]: super::State::Stop
            wander_stop_frames: Option<u32> = FRAMES,
        },
    }
}

impl Default for FsmParams {
    /// [`FsmParams::ALVS`], what the firmware runs.
    fn default() -> Self {
        FsmParams::ALVS
    }
}

impl FsmParams {
    /// The motion of the paper's model (`--model paper`): the paper's FSM (Sec. II-B, γ paths
    /// from every state) with the choices the paper leaves open (speeds, rates, durations;
    /// `docs/model.md`).
    pub const PAPER: FsmParams = FsmParams {
        motion: Motion {
            cruise_mm_s: 100.0,
            max_escape_mm_s: 200.0,
            retreat_mm_s: 150.0,
            max_wheel_mm_s: 300.0,
            track_mm: 48.0,
            heading_gain: 4.0,
            max_yaw_deg_s: 360.0,
            align_tol_deg: 10.0,
        },
        timing: Timing {
            retreat_frames: u32::MAX,
            min_escape_frames: 30,
            quiet_frames: 15,
            takeoff_timeout_frames: 90,
            alert_frames: 1,
        },
        suppression: Suppression {
            saccade_yaw_deg_s: 45.0,
            settle_frames: 0,
        },
        blocked: Blocked {
            blocked_frames: 15,
            blocked_travel_mm: 40.0,
            blocked_yaw_deg: 10.0,
        },
        escape: Escape {
            takeoff_drive: 0.0,
            takeoff_gain: 1.0,
            takeoff_yaw_deg_s: 360.0,
            live_strength: 0,
            escape_saccade: false,
            jump_frames: None,
            gamma_turn: false,
        },
        swarm: Swarm {
            spin_frames: 30,
            spin_deg_s: 180.0,
            look_every: None,
            look_scans: 3,
        },
        firmware: FirmwareFsm {
            short_from_long: false,
            wander_stop_frames: None,
        },
    };

    /// The default (`--model alvs`, the firmware's): [`FsmParams::PAPER`] plus the closed-loop
    /// mechanisms of the FSM that are measured to help (`docs/experiments.md`, "Closed-loop
    /// mechanisms"): the escape saccade, a takeoff that moves at half the escape speed while
    /// it turns, takeoff turns three times as brisk and limited by the wheels only, the
    /// takeoff's jump, a γ path that turns as briskly under the yaw limit, and the swarm's
    /// looks.
    pub const ALVS: FsmParams = FsmParams {
        escape: Escape {
            escape_saccade: true,
            takeoff_drive: 0.5,
            takeoff_gain: 3.0,
            takeoff_yaw_deg_s: f32::INFINITY,
            jump_frames: NonZeroU32::new(6),
            gamma_turn: true,
            ..FsmParams::PAPER.escape
        },
        swarm: Swarm {
            look_every: NonZeroU32::new(45),
            ..FsmParams::PAPER.swarm
        },
        ..FsmParams::PAPER
    };

    /// What the authors' public firmware's state machine does (`visuomotor_LPLC2.c`;
    /// `docs/notes/2026-11-27-authors-firmware.md` gives each value's source line):
    /// [`FsmParams::PAPER`] acting on three alert frames in a row (its spike count), the γ
    /// path only out of a long takeoff, the stop after 1000 frames of wandering, an escape of
    /// one frame after a long takeoff, no takeoff timeout and no saccadic suppression, its
    /// escape and reverse speed (4.5 of its units where wandering is 2.5: 180 mm/s) and its
    /// heading PID's gain and limit in the same units.
    pub const FIRMWARE: FsmParams = FsmParams {
        motion: Motion {
            max_escape_mm_s: 180.0,
            retreat_mm_s: 180.0,
            max_wheel_mm_s: 180.0,
            heading_gain: 6.2,
            max_yaw_deg_s: 239.0,
            ..FsmParams::PAPER.motion
        },
        escape: Escape {
            // its takeoffs turn with the same PID
            takeoff_yaw_deg_s: 239.0,
            ..FsmParams::PAPER.escape
        },
        timing: Timing {
            min_escape_frames: 0,
            quiet_frames: 0,
            takeoff_timeout_frames: u32::MAX,
            alert_frames: 3,
            ..FsmParams::PAPER.timing
        },
        suppression: Suppression {
            saccade_yaw_deg_s: f32::INFINITY,
            ..FsmParams::PAPER.suppression
        },
        firmware: FirmwareFsm {
            short_from_long: true,
            wander_stop_frames: Some(1000),
        },
        ..FsmParams::PAPER
    };

    /// The preset these parameters are, `"alvs"`, `"paper"` or `"firmware"`, or `"custom"`.
    pub fn preset_name(&self) -> &'static str {
        if *self == FsmParams::ALVS {
            "alvs"
        } else if *self == FsmParams::PAPER {
            "paper"
        } else if *self == FsmParams::FIRMWARE {
            "firmware"
        } else {
            "custom"
        }
    }

    /// The allowed values of the parameter `name` (`group.field` or the field alone), `None`
    /// for an unknown name.
    pub fn range(name: &str) -> Option<Range> {
        FsmParams::position(name).map(|i| FsmParams::RANGES[i])
    }

    /// Checks every value is in its range; the name (`group.field`) of the first that is not.
    pub fn validate(&self) -> Result<(), FsmParamError> {
        match self.out_of_range() {
            Some((name, _)) => Err(FsmParamError::Invalid { name }),
            None => Ok(()),
        }
    }

    /// Sets one parameter by name (`group.field` or the field alone, [`FsmParams::NAMES`],
    /// [`FsmParams::FIELDS`]) from its text value (a command line's `NAME=VALUE`). Reals must
    /// be finite and non-negative (`saccade_yaw_deg_s` may be `inf`: no suppression;
    /// `takeoff_yaw_deg_s` too: the wheels' limit); counts are whole frames; `live_strength`
    /// is 0, 1 or 2; a switch (`escape_saccade`, `short_from_long`) takes `true`/`false` (or
    /// `1`/`0`, `on`/`off`); `look_every` and `jump_frames` 0, `none` or `off` for never; `wander_stop_frames`
    /// a count or `none`. A refused value leaves the parameters unchanged.
    pub fn set(&mut self, name: &str, value: &str) -> Result<(), FsmParamError> {
        let i = FsmParams::position(name).ok_or(FsmParamError::Unknown)?;
        let name = FsmParams::NAMES[i];
        let mut p = *self;
        p.parse_field(name, value.trim())
            .map_err(|_| FsmParamError::Invalid { name })?;
        *self = p;
        Ok(())
    }
}

/// Why [`FsmParams::set`] refused a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FsmParamError {
    /// No FSM parameter has that name (see [`FsmParams::NAMES`]).
    Unknown,
    /// Not a value in the parameter's range ([`FsmParams::RANGES`]); the message says which.
    Invalid {
        /// Parameter name, `group.field`.
        name: &'static str,
    },
}

impl core::fmt::Display for FsmParamError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            FsmParamError::Unknown => {
                f.write_str("unknown FSM parameter (known: ")?;
                write_list(f, FsmParams::NAMES)?;
                f.write_str(")")
            }
            FsmParamError::Invalid { name } => match FsmParams::position(name) {
                Some(i) => write!(
                    f,
                    "FSM parameter {name} must be {}{}",
                    FsmParams::RANGES[i],
                    FsmParams::WORDS[i]
                ),
                None => write!(f, "FSM parameter {name}: not a valid value"),
            },
        }
    }
}
