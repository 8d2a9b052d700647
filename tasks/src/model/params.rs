//! Every parameter of the aLPLC2 network in one place: the paper's Table I with its defaults,
//! and the values the paper leaves unstated, each a documented choice (`docs/model.md`),
//! grouped by what they are; one declaration gives each its name (`group.field`, or the field
//! alone), type, range and setter ([`crate::model::param_table`]).

use core::num::{NonZeroU16, NonZeroU32, NonZeroU8};

use crate::frame::HEIGHT;
use crate::model::param_table::{param_groups, write_list, Refusal};
pub use crate::model::param_table::{Range, Value};
use crate::model::MAX_AFS;

/// Largest number of connected neurons `n` per correlator (Eq. 6).
pub const MAX_N: u8 = 4;
/// Largest reach `n * s` of a correlator, in pixels.
pub const MAX_REACH: u8 = 8;
/// Largest averaging window `d` (Eq. 10), in frames.
pub const MAX_D: u8 = 16;

param_groups! {
    /// The parameters of the aLPLC2 network and visuomotor pathway.
    ///
    /// [`Params::PAPER`] is the paper's Table I plus the choices documented in `docs/model.md`;
    /// `Params::default()` is [`Params::ALVS`], that plus the closed-loop mechanisms;
    /// [`Params::FIRMWARE`] is what the authors' public firmware runs.
    ///
    /// Each field's range is the range the model can compute with, without a panic or an
    /// overflow; `choices.s` is further bounded by `n · s ≤ MAX_REACH`. A mechanism the paper
    /// lacks is an `Option` (`None`: off, the paper); a switch is a `bool`.
    pub struct Params {
        /// Table I of the paper: the values it states, the paper's and the default's alike.
        table1: TableOne {
            /// `w`: weight of the ON channel, Eq. (1). Table I: 0.25.
            w: f32 = Range::Real(0.0, 4.0),
            /// `n`: connected neurons per correlator, Eq. (6). Table I: 3.
            n: u8 = Range::Int(1, MAX_N as i64),
            /// `R_AF`: half side of an attention field's square, in pixels. Table I: 36.
            r_af: u8 = Range::Int(1, 99),
            /// `T_a`: threshold on `L̂_ON + L̂_OFF` for a new attention field, Eq. (3). Table I: 100.
            /// A `u16`: `L̂_ON + L̂_OFF` of a pixel is at most `255 · (gain · w + gain)` = 20,400
            /// (`gain` ≤ 16, `w` ≤ 4), so every larger `T_a` already opens no field.
            t_a: u16 = Range::Int(0, u16::MAX as i64),
            /// `T_d`: mean LPLC2 over `d` frames below which a field retires, Eq. (10). Table I: 5000.
            /// A `u16` (at most 65,535: 13 times Table I's, 5 times the authors' firmware's 12,500),
            /// so that Table I's group packs without padding.
            t_d: u16 = Range::Int(0, u16::MAX as i64),
            /// `d`: frames over which the LPLC2 response is averaged, Eq. (10). Table I: 4.
            d: u8 = Range::Int(1, MAX_D as i64),
            /// `w_s`: weight in the strength sigmoid, Eq. (11). Table I: 4000.
            w_s: f32 = Range::Real(1e-3, 1e9),
            /// `α`: degrees per pixel from the horizontal centroid to an angle, Eqs. (13)–(15). Table I: 0.707.
            alpha: f32 = Range::Real(-10.0, 10.0),
            /// `T_s`: global threat `ΣLPLC2` above which the short-mode escape starts. Table I: 7000,
            /// in the paper's model and the default alike. (5500 was tried for an obstacle first seen
            /// late, 71–97 mm away at the edge of the view; on the held-out seeds Table I's 7000 did
            /// better, `docs/ablation.md`.)
            t_s: u32 = Range::Int(0, u32::MAX as i64),
        },
        /// The values the paper leaves unstated, each a documented choice (`docs/model.md`).
        choices: Choices {
            /// `C_d`: correlator delay in frames, Eq. (6). Unstated in the paper. Realised as the
            /// classic HRC delay filter, a first-order low-pass with mean delay `C_d` frames (exactly
            /// the previous frame when `C_d = 1`), so any delay costs one map per channel.
            c_d: f32 = Range::Real(1.0, 16.0),
            /// `s`: spacing of the connected neurons in pixels, Eq. (6). Unstated; 1.
            s: u8 = Range::Int(1, MAX_REACH as i64),
            /// Retina gain: luminance enters the model as `gain * Y8`. Unstated; 4, a 10-bit scale,
            /// the smallest gain at which a full-contrast ON edge (weight `w`) can reach `T_a`.
            gain: u8 = Range::Int(1, 16),
            /// Local-motion scale: correlator products are divided by `2^lm_shift` so that LPLC2
            /// responses live on the scale of `T_d`, `T_s` and `w_s`. Unstated; see `docs/model.md`.
            lm_shift: u8 = Range::Int(0, 24),
            /// Half side of the window in which a centroid is re-estimated, Eq. (4); at most `R_AF`.
            /// The paper uses the whole field; its authors' simulator uses a window of half `R_AF`.
            r_c: u8 = Range::Int(1, 99),
            /// Half side of the exclusion zone around a field's centroid: no new field is born
            /// inside it (Eq. 3), and a field whose centroid enters another's is discarded
            /// (Eq. 5). `None` (0): `R_AF`, the paper's text, where the field's square is its
            /// exclusion zone. The authors' multi-field simulator gives it a size of its own
            /// (`AF_Radius_Exclusive`, `docs/model.md`, "Capacity").
            r_x: Option<NonZeroU8> = Range::Int(0, 99),
            /// Relative saliency floor of the centroid moments, Eq. (4), in percent of the window's peak:
            /// weaker pixels do not pull the centroid. Unstated; the paper's firmware thresholds its OFF
            /// map before the moments in the same spirit (`docs/model.md`).
            c_frac: u8 = Range::Int(0, 100),
            /// Noise floor of a quadrant, Eq. (9): a quadrant counts as excited only above it.
            /// Unstated in the paper (its firmware uses a similar `T_cardinal`); see `docs/model.md`.
            q_floor: u32 = Range::Int(0, u32::MAX as i64),
            /// Balance of the quadrants, Eq. (9), in percent: each must reach this share of the
            /// strongest one to count as excited. Unstated; see `docs/model.md`.
            q_balance: u8 = Range::Int(0, 100),
            /// Excited quadrants needed to open the gate, Eq. (9). The paper's product `∏Q` needs all
            /// 4 ([`Params::PAPER`]); the authors' firmware opens at 3 of 4 ("expansion edges"), and so
            /// does the default, together with `q_grow_pct`; see `docs/model.md`.
            q_arms: u8 = Range::Int(1, 4),
        },
        /// Closed-loop mechanisms of the network's own signal (not in the paper: all `None` in
        /// [`Params::PAPER`]; `docs/model.md`, "Closed-loop mechanisms").
        mechanisms: Mechanisms {
            /// Frames after a start or restart (a torn or dropped frame) during which no field is
            /// reported stimulated: the delay line of Eq. (6) and the `d`-frame history of Eq. (10)
            /// are still filling, so early responses compare a frame with an empty past. Not in the
            /// paper (0 there); see `docs/model.md`, "Closed-loop mechanisms".
            warmup: Option<NonZeroU8> = Range::Int(0, 255),
            /// Whole-field luminance events: when at least this percent of the retina brightens (or
            /// darkens) in one frame while next to nothing changes the other way, the change
            /// is the light or the sensor's automatic exposure, not motion, and no field is reported
            /// stimulated in that frame. `None` (0) turns it off (the paper). See `docs/model.md`,
            /// "Closed-loop mechanisms".
            flicker_pct: Option<NonZeroU8> = Range::Int(0, 100),
            /// Noise frames: when neighbouring pixels correlate below this percent both along the
            /// rows and down the columns (and differ by more than the sensor's grain), the frame
            /// is no picture a lens could make (a corrupted transfer, interference), and no field
            /// is reported stimulated in it or in the frame after, which is measured against it
            /// ([`crate::model::closed_loop::noise_frames`]). The recorded clips measure 55 % and
            /// more, random pixels 0. `None` (0) turns it off (the paper). See `docs/model.md`,
            /// "Closed-loop mechanisms".
            noise_pct: Option<NonZeroU8> = Range::Int(0, 100),
            /// Growth of a partial opening: when fewer than four quadrants are excited (an opening
            /// that `q_arms` < 4 allows), the field's quadrant sum must also have grown by at least
            /// this many percent since the last frame, at the same place
            /// ([`crate::model::lplc2::GROW_SHIFT_PX`]). A looming object's drive grows; a receding
            /// one's, and the residue a finished threat leaves, do not. `None` (0) turns it off (the paper); the
            /// default is 50 with `q_arms` = 3. See `docs/model.md`, "Closed-loop mechanisms".
            q_grow_pct: Option<NonZeroU8> = Range::Int(0, 255),
            /// Growth in a row: a partial opening also stands once the field's quadrant sum has
            /// grown, at the same place, on this many frames in a row. An object already close when
            /// the robot starts looking approaches steadily, its drive growing some 10 % a frame,
            /// short of `q_grow_pct`'s per-frame step, which only an approach's onset or its last
            /// few frames reach; a receding object's or a residue's drive does not keep growing.
            /// `None` (0): only `q_grow_pct`'s step (the paper has neither); the default is 3. See
            /// `docs/model.md`, "Closed-loop mechanisms".
            q_grow_run: Option<NonZeroU8> = Range::Int(0, 255),
            /// Attention threshold of a quiet scene: `T_a` (Eq. 3) falls towards this value as the
            /// share of the retina that changes falls below [`crate::model::attention::BUSY_PCT`], so
            /// a small object's faint edges can open a field when little else moves, while a scene
            /// full of motion keeps Table I's `T_a`. `None` (0) turns it off (the paper). See `docs/model.md`,
            /// "Closed-loop mechanisms".
            t_a_quiet: Option<NonZeroU16> = Range::Int(0, u16::MAX as i64),
            /// Arms cut off by the camera's side borders: the 70° view ends at the retina's first
            /// and last columns, so for a field centred within `R_AF / 2` of one, most of the two
            /// quadrants on that side lie outside the picture, blind rather than silent. An object
            /// approaching from the edge of the view shows only its inner half, and its missing
            /// arms keep Eq. (9)'s gate shut until it is at the robot (`docs/model.md`). With
            /// `true`, while the robot stands (no forward travel, [`crate::Network::driving`]),
            /// such a blind quadrant counts as excited when its mirror image across the field's
            /// vertical axis is, in a field that has lived Eq. (10)'s `d` frames; the drive passed
            /// on is still what the retina saw, and an opening with fewer than four quadrants
            /// excited by themselves still needs `q_grow_pct`'s growth. Driving, the robot's own
            /// translation expands everything at the borders, so the mirror would read it as
            /// looming. `false`: the paper. See `docs/model.md`, "Closed-loop mechanisms".
            border_arms: bool = Range::Int(0, 1),
            /// With `border_arms`: a side counts as cut as soon as the field's square (half side
            /// `R_AF`) crosses the side border, not only when less than half of that half side lies
            /// in the picture. An obstacle first seen close fills a third of the view or more, and
            /// the attention centroid sits on its visible edges: a field 18–35 columns from the
            /// border still has its outer quadrants partly beyond it, and the gate stayed shut
            /// (`lplc2::cut_sides`). `false`: `R_AF / 2`; the default is `true`. See
            /// `docs/model.md`, "Closed-loop mechanisms".
            border_crossing: bool = Range::Int(0, 1),
        },
        /// Efference copies: what the robot's own turns and travel tell the network (not in the
        /// paper: off in [`Params::PAPER`]; `docs/model.md`, "Closed-loop mechanisms").
        efference: Efference {
            /// Efference copy of turns: `true` re-registers the retina's memory to each turn the robot
            /// reports ([`crate::Network::turned`]), so a turn causes no motion signal
            /// ([`crate::model::closed_loop::derotate`]); `false` ignores the reports (the paper). See `docs/model.md`,
            /// "Closed-loop mechanisms".
            derotate: bool = Range::Int(0, 1),
            /// Blocked way (efference copy): the escape FSM turns around when it commanded forward
            /// travel but the coarse view changed by less than this many grey levels on average
            /// ([`crate::model::closed_loop::progress`]). `None` (0) turns it off (the paper). The default, 2, is below
            /// every free robot's change on the six arena walls measured (the soft `outdoor_2`
            /// photograph changes by less than 6 levels on 39 % of its free frames, never below 2) and
            /// above most of a pressed robot's (`docs/experiments.md`, "Closed-loop mechanisms").
            /// Off in the default: no robot stayed pressed in the validated world, so it changed
            /// nothing (`docs/ablation.md`); a floor that grips, or a body that catches on an edge,
            /// may want it.
            blocked_change: Option<NonZeroU8> = Range::Int(0, 255),
            /// Fields centred above this row are silent while the robot drives forward (its efference
            /// copy, [`crate::Network::driving`]): driving, the expansion of the scene above the
            /// body's height is the robot's own translation, and anything that can touch a ground robot
            /// also reaches into the rows below. Standing, every field responds. `None` (0) turns it off (the
            /// paper; the default 27, measured in `docs/experiments.md`). See `docs/model.md`,
            /// "Closed-loop mechanisms".
            band_row: Option<NonZeroU8> = Range::Int(0, HEIGHT as i64 - 1),
            /// While the robot drives forward, an obstacle whose foot (where it meets the floor) lies
            /// at or below this row inside the robot's path is reported ([`crate::model::closed_loop::floor`]),
            /// and alerts on a frame no field alerts on: with the camera at a fixed height over a flat
            /// floor, the row is the distance. `None` (0) turns it off (the paper; the default 52, measured in
            /// `docs/experiments.md`); rows at or above the horizon (≤ 35) find nothing either. See
            /// `docs/model.md`, "Closed-loop mechanisms".
            floor_row: Option<NonZeroU8> = Range::Int(0, HEIGHT as i64 - 1),
        },
        /// The short mode's test: the gates a threat above `T_s` must also pass to start one, and
        /// how cut fields count (not in the paper, all off there; off in the default too,
        /// `docs/ablation.md`, `docs/model.md`).
        short: ShortGates {
            /// Motion adaptation of the short mode: with `N` > 0 the short mode also needs `ΣLPLC2`
            /// above twice its running mean over about `N` frames, so a steady response (the robot's
            /// own translation past textured walls) does not keep it on while a growing one (looming)
            /// does. `None` (0) turns it off (the paper and the default: it changed nothing there and cost the
            /// paper's model 20 points of arena success, `docs/ablation.md`). See `docs/model.md`,
            /// "Closed-loop mechanisms".
            adapt_frames: Option<NonZeroU8> = Range::Int(0, 255),
            /// While the robot drives forward, the short mode needs the threat's `X̄` within this many
            /// columns of the centre: driving, everything beside the path expands with the robot's
            /// own translation, and only what lies in the path can be imminent. 23 is the path's
            /// half-width seen at the robots' encounter distance (126 mm), with the half-width then taken
            /// as one body diameter (42 mm): 70 · 42 / 126. Alerts off the path still start a long
            /// takeoff. `None` (0) turns it off (the paper and the default: like `short_row` it only repeats
            /// what the escape saccade does, `docs/ablation.md`). See `docs/model.md`, "Closed-loop
            /// mechanisms".
            short_cols: Option<NonZeroU8> = Range::Int(0, 49),
            /// While the robot drives forward, the short mode also needs the threat's foot (where it
            /// meets the floor, [`crate::model::closed_loop::floor::nearest_foot`] at `X̄`) at or below this row:
            /// within about one second of travel. Driving, a wall or robot still far ahead expands
            /// with the robot's own speed; the floor line gives its distance. Row 50 is 97 mm from the
            /// camera (20 mm above the floor), one second at the cruise speed of 100 mm/s. The alert
            /// still starts a long takeoff. `None` (0) turns it off (the paper); 1–36 only need a foot
            /// somewhere below the horizon (a threat with none within 3 columns is held back). Blind
            /// spot: a wall so close that it covers the bottom row's middle has no foot (as for the
            /// floor line) and loses the short mode; the floor line covers it. Off in the default:
            /// like `short_cols` it keeps a short mode from turning an escaping robot back, which the
            /// escape saccade (`FsmParams::escape_saccade`) already does; the paper's model, which has
            /// no escape saccade, gains 4 points of arena success with it (`docs/ablation.md`). See
            /// `docs/model.md`, "Closed-loop mechanisms".
            short_row: Option<NonZeroU8> = Range::Int(0, HEIGHT as i64 - 1),
            /// While the robot does not drive forward (as for `border_arms`), the short mode's test
            /// counts a field that a side border of the retina cuts at the whole field's size: its
            /// response times its square's width over the columns the retina shows of it
            /// ([`crate::model::lplc2::uncut_response`]; with `r_af` 36 every field centred off
            /// columns 36–62). The camera's 70° view ends where the fly's eye does not; an object
            /// at the border is at least as big as its visible part, and Eq. (9) sums only what
            /// is visible. Driving, the border's responses are mostly the robot's own flow.
            /// Alerts, `X̄` and `S` are unchanged. `false`: the paper. In the default with
            /// `FsmParams::gamma_turn`, without which it costs two threats; see
            /// `docs/model.md`, "Closed-loop mechanisms".
            short_uncut: bool = Range::Int(0, 1),
            /// While the robot does not drive forward (as for `short_uncut`), the short mode is also
            /// on when a field alerts within its first `d` frames (Table I's `d`, the frames Eq. (10)
            /// needs before it can judge a field): an object that alerts as soon as it is attended
            /// was first seen close, too late for the long takeoff's turn. A field born in the
            /// warm-up (`warmup`), when no field can alert, counts from the warm-up's end
            /// ([`crate::model::network::AfReport::alerts_young`]). Age separates the
            /// obstacle first seen close from one seen approaching from afar, whatever the wall's
            /// contrast: at the view's edge their distances and responses at the first alert
            /// overlap, their fields' ages do not (docs/notes/2026-11-28-first-seen-close-on-textured-walls.md).
            /// Driving, new fields come from the robot's own flow all the time, so age says nothing.
            /// It needs a distant mover's field born early, as `t_a_quiet`'s lower `T_a` in a still
            /// scene has it: without that, two threats collide 22 times as often
            /// (`docs/ablation.md`). `false`: the paper; the default: `true`.
            short_young: bool = Range::Int(0, 1),
        },
        /// The swarm's look, run beside the network ([`crate::model::closed_loop::movers`]).
        swarm: SwarmLook {
            /// The swarm's look ([`crate::model::closed_loop::movers`], run beside the network by whatever runs
            /// the swarm behaviour): while the wheels are commanded to stand, the band of rows where
            /// robots appear is compared over 0.4 s, and the column where most pixels changed by more
            /// than this many grey levels is reported: something that moves, another robot, since a
            /// standing robot has no flow of its own. `None` (0) turns it off (the paper); 25 is far above the
            /// camera's noise (2 grey levels per pixel and a 0.3 % gain draw; the worlds' former
            /// 2 % draw, at most 5 at full white): 15 took noise for movers with the 2 % draw
            /// (`docs/experiments.md`, "Swarm"). Only the swarm behaviour acts
            /// on it (`FsmParams::look_every`); the escape and the firmware never look.
            look_change: Option<NonZeroU8> = Range::Int(0, 255),
        },
        /// Where the authors' firmware differs from the paper ([`Params::FIRMWARE`]); the paper's
        /// and the default's values keep the paper's behaviour.
        firmware: FirmwareVariant {
            /// The most attention fields alive at once, 1..=[`MAX_AFS`]: with that many, no new field
            /// opens (Eq. 3) until one retires. The paper's fields are as many as fit ([`MAX_AFS`]);
            /// the authors' firmware has one (`NUM_AF 1`, [`Params::FIRMWARE`]).
            max_fields: u8 = Range::Int(1, MAX_AFS as i64),
            /// A field's output over time, the authors' firmware's `T_LPLC2`. `None` (0, the paper): a field
            /// is stimulated on a frame when its gate opens (Eq. 9, `LPLC2_k > 0`) and passes on that
            /// frame's response. `Some(T)`: it passes on the mean of its last `d` responses (the frames
            /// before its birth counting 0, as the firmware's ring of 4 outputs), and only while that
            /// mean exceeds this value; a frame on which the field is silenced (`warmup`,
            /// `flicker_pct`, `band_row`) passes on 0. `ΣLPLC2`, `X̄`, `S` and the short mode are
            /// made of these outputs. See `docs/model.md`, "The authors' firmware".
            t_lplc2: Option<NonZeroU32> = Range::Int(0, u32::MAX as i64),
            /// Eq. (10) as the authors' firmware runs it: every field is judged from its first frame,
            /// on the mean of its last `d` responses with the frames before its birth counting 0, and
            /// the last field retires too (a new one may open on the next frame). `false` (the paper):
            /// a field is not judged before it has lived `d` frames, and the strongest always remains
            /// ("at least one AF is always retained").
            strict_retire: bool = Range::Int(0, 1),
            /// Eq. (6)'s correlator form. `true` (the paper): the opponent HRC the paper cites, a
            /// change travelling along the preferred direction minus one travelling against it.
            /// `false` (the authors' firmware, whose subtracted terms are commented out): only the
            /// preferred-direction product `L(q,t)·L(p,t−C_d)`, which a change that does not move
            /// (flicker, a translating edge's own pixels) excites too. Taken by the general
            /// pixel-by-pixel path (the row kernel is opponent only).
            opponent: bool = Range::Int(0, 1),
        },
    }
}

impl Params {
    /// Table I of the paper plus the documented choices.
    pub const PAPER: Params = Params {
        table1: TableOne {
            w: 0.25,
            n: 3,
            r_af: 36,
            t_a: 100,
            t_d: 5000,
            d: 4,
            w_s: 4000.0,
            alpha: 0.707,
            t_s: 7000,
        },
        choices: Choices {
            c_d: 2.0,
            s: 1,
            gain: 4,
            lm_shift: 8,
            r_c: 36,
            r_x: None,
            c_frac: 50,
            q_floor: 250,
            q_balance: 15,
            q_arms: 4,
        },
        mechanisms: Mechanisms {
            warmup: None,
            flicker_pct: None,
            noise_pct: None,
            q_grow_pct: None,
            q_grow_run: None,
            t_a_quiet: None,
            border_arms: false,
            border_crossing: false,
        },
        efference: Efference {
            derotate: false,
            blocked_change: None,
            band_row: None,
            floor_row: None,
        },
        short: ShortGates {
            adapt_frames: None,
            short_cols: None,
            short_row: None,
            short_uncut: false,
            short_young: false,
        },
        swarm: SwarmLook { look_change: None },
        firmware: FirmwareVariant {
            max_fields: MAX_AFS as u8,
            t_lplc2: None,
            strict_retire: false,
            opponent: true,
        },
    };

    /// The default: the paper's model ([`Params::PAPER`]) with Table I unchanged, plus the
    /// mechanisms a robot in closed loop needs that the paper leaves out, each a parameter
    /// that earns its place on the held-out seeds (`docs/ablation.md`). The firmware runs
    /// these. The options that did not earn it (`blocked_change`, `adapt_frames`,
    /// `short_cols`, `short_row`) stay off.
    pub const ALVS: Params = Params {
        choices: Choices {
            q_arms: 3,
            ..Params::PAPER.choices
        },
        mechanisms: Mechanisms {
            warmup: NonZeroU8::new(4),
            flicker_pct: NonZeroU8::new(50),
            noise_pct: NonZeroU8::new(25),
            q_grow_pct: NonZeroU8::new(50),
            q_grow_run: NonZeroU8::new(3),
            t_a_quiet: NonZeroU16::new(30),
            border_arms: true,
            border_crossing: true,
        },
        short: ShortGates {
            short_uncut: true,
            short_young: true,
            ..Params::PAPER.short
        },
        efference: Efference {
            derotate: true,
            band_row: NonZeroU8::new(27),
            floor_row: NonZeroU8::new(52),
            ..Params::PAPER.efference
        },
        swarm: SwarmLook {
            look_change: NonZeroU8::new(25),
        },
        ..Params::PAPER
    };

    /// What the authors' public firmware runs (`Ryannnice/neuro-life-project`,
    /// `micro_embodied/colias_core`; `docs/notes/2026-11-27-authors-firmware.md` gives each
    /// value's source line): [`Params::PAPER`] with one attention field, OFF only, a one-frame
    /// delay, two connected neurons, its quadrant threshold `T_cardinal` and 3-of-4 gate
    /// without balance, its output the 4-frame mean above `T_LPLC2`, its retirement, strength
    /// weight and short-mode threshold, and its correlator (OFF only, not opponent). Its
    /// correlator products have our units (`ΔY²/16`), so its thresholds are taken as they are.
    pub const FIRMWARE: Params = Params {
        table1: TableOne {
            // W_ON = 0: no ON channel in attention or the correlators
            w: 0.0,
            // Nc = 2
            n: 2,
            // t = 10 on half grey levels: 20 levels, 80 on the 10-bit scale
            t_a: 80,
            // AF_Threshold = T_cardinal / 4
            t_d: 12_500,
            w_s: 20_000.0,
            // T_SHORT_TAKEOFF = 5 · T_LPLC2
            t_s: 750_000,
            ..Params::PAPER.table1
        },
        choices: Choices {
            // DELAY_WINDOW 2: exactly the last frame
            c_d: 1.0,
            // T_cardinal
            q_floor: 50_000,
            q_balance: 0,
            // T_ExpansionEdgeNum = 3
            q_arms: 3,
            ..Params::PAPER.choices
        },
        firmware: FirmwareVariant {
            // NUM_AF 1
            max_fields: 1,
            // T_LPLC2 = 3 · T_cardinal
            t_lplc2: NonZeroU32::new(150_000),
            strict_retire: true,
            // the subtracted products commented out
            opponent: false,
        },
        ..Params::PAPER
    };

    /// Half side of a field's exclusion zone, Eqs. (3) and (5): `choices.r_x`, or `R_AF`.
    pub fn exclusion(&self) -> u8 {
        self.choices.r_x.map_or(self.table1.r_af, NonZeroU8::get)
    }

    /// The preset these parameters are, `"paper"`, `"alvs"` or `"firmware"`, or `"custom"`.
    pub fn preset_name(&self) -> &'static str {
        if *self == Params::ALVS {
            "alvs"
        } else if *self == Params::PAPER {
            "paper"
        } else if *self == Params::FIRMWARE {
            "firmware"
        } else {
            "custom"
        }
    }

    /// A preset by name: `paper` ([`Params::PAPER`]), `alvs` ([`Params::ALVS`]) or `firmware`
    /// ([`Params::FIRMWARE`]).
    pub fn preset(name: &str) -> Option<Params> {
        match name {
            "paper" => Some(Params::PAPER),
            "alvs" => Some(Params::ALVS),
            "firmware" => Some(Params::FIRMWARE),
            _ => None,
        }
    }

    /// The allowed values of the parameter `name` (`group.field` or the field alone), `None`
    /// for an unknown name.
    pub fn range(name: &str) -> Option<Range> {
        Params::position(name).map(|i| Params::RANGES[i])
    }

    /// Checks every value is in the range the model can compute with (no panic, no overflow).
    pub fn validate(&self) -> Result<(), ParamError> {
        if let Some((name, range)) = self.out_of_range() {
            return Err(ParamError::out_of(name, range));
        }
        let (n, s) = (self.table1.n, self.choices.s);
        if u32::from(n) * u32::from(s) > u32::from(MAX_REACH) {
            return Err(ParamError::OutOfRange {
                name: "choices.s",
                min: 1,
                max: i64::from(MAX_REACH / n),
            });
        }
        Ok(())
    }

    /// Sets one parameter by name (`group.field` or the field alone, [`Params::NAMES`],
    /// [`Params::FIELDS`]) from its text value, as given on a command line. A switch takes
    /// `true`/`false` (or `1`/`0`, `on`/`off`), a mechanism the paper lacks `0`, `none` or
    /// `off` for off. A refused value leaves the parameters unchanged.
    pub fn set(&mut self, name: &str, value: &str) -> Result<(), ParamError> {
        let i = Params::position(name).ok_or(ParamError::Unknown)?;
        let (name, range) = (Params::NAMES[i], Params::RANGES[i]);
        let mut p = *self;
        p.parse_field(name, value.trim()).map_err(|r| match r {
            Refusal::NotANumber => ParamError::NotANumber { name },
            Refusal::OutOfRange => ParamError::out_of(name, range),
        })?;
        p.validate()?;
        *self = p;
        Ok(())
    }
}

impl Default for Params {
    /// [`Params::ALVS`].
    fn default() -> Self {
        Params::ALVS
    }
}

/// Why a parameter value was refused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamError {
    /// No parameter has that name (see [`Params::NAMES`]).
    Unknown,
    /// The text is not a number of the parameter's type (a whole number for the integer
    /// parameters); the message gives the allowed range.
    NotANumber {
        /// Parameter name.
        name: &'static str,
    },
    /// A real value is not finite or outside the range the model supports.
    OutOfRangeReal {
        /// Parameter name.
        name: &'static str,
        /// Smallest allowed value.
        min: f32,
        /// Largest allowed value.
        max: f32,
    },
    /// The value is outside the range the model supports.
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// Smallest allowed value.
        min: i64,
        /// Largest allowed value.
        max: i64,
    },
}

impl ParamError {
    /// `name` (as in [`Params::NAMES`]) refused for lying outside `range`.
    fn out_of(name: &'static str, range: Range) -> ParamError {
        match range {
            Range::Int(min, max) => ParamError::OutOfRange { name, min, max },
            Range::Real(min, max) => ParamError::OutOfRangeReal { name, min, max },
        }
    }
}

impl core::fmt::Display for ParamError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let words = |name: &str| Params::position(name).map_or("", |i| Params::WORDS[i]);
        match *self {
            ParamError::Unknown => {
                f.write_str("unknown parameter (known: ")?;
                write_list(f, Params::NAMES)?;
                f.write_str(")")
            }
            ParamError::NotANumber { name } => match Params::range(name) {
                Some(range) => write!(f, "parameter {name} must be {range}{}", words(name)),
                None => write!(f, "parameter {name}: not a number"),
            },
            ParamError::OutOfRange { name, min, max } => {
                write!(
                    f,
                    "parameter {name} must lie in {min}..={max}{}",
                    words(name)
                )
            }
            ParamError::OutOfRangeReal { name, min, max } => {
                write!(f, "parameter {name} must be {}", Range::Real(min, max))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::model::param_table::off0;
    use std::format;
    use std::string::ToString;

    #[test]
    fn defaults_are_table_one() {
        let p = Params::PAPER.table1;
        assert_eq!((p.w, p.n, p.r_af, p.t_a, p.t_d), (0.25, 3, 36, 100, 5000));
        assert_eq!((p.d, p.w_s, p.alpha, p.t_s), (4, 4000.0, 0.707, 7000));
        assert_eq!(Params::PAPER.validate(), Ok(()));
        // the default keeps Table I
        assert_eq!(Params::default().table1, p);
    }

    #[test]
    fn the_default_is_the_paper_plus_the_closed_loop_mechanisms_only() {
        let (paper, alvs) = (Params::PAPER, Params::ALVS);
        let mechanisms = |p: Params| {
            (
                off0(p.mechanisms.warmup),
                off0(p.mechanisms.flicker_pct),
                off0(p.efference.blocked_change),
                p.efference.derotate,
                off0(p.short.adapt_frames),
                off0(p.mechanisms.q_grow_pct),
                p.choices.q_arms,
                off0(p.mechanisms.t_a_quiet),
                off0(p.efference.band_row),
                off0(p.efference.floor_row),
                off0(p.short.short_cols),
                off0(p.short.short_row),
            )
        };
        assert_eq!(
            mechanisms(paper),
            (0, 0, 0, false, 0, 0, 4, 0, 0, 0, 0, 0),
            "the paper has none"
        );
        assert_eq!(
            mechanisms(alvs),
            (4, 50, 0, true, 0, 50, 3, 30, 27, 52, 0, 0)
        );
        assert_eq!(
            (paper.swarm.look_change, off0(alvs.swarm.look_change)),
            (None, 25)
        );
        // the firmware's switches keep the paper's and the default's behaviour
        for p in [paper, alvs] {
            let f = p.firmware;
            assert_eq!((f.max_fields, f.t_lplc2, f.strict_retire), (6, None, false));
            assert!(f.opponent);
        }
        // everything else is the paper's
        assert_eq!(
            Params {
                choices: Choices {
                    q_arms: 4,
                    ..alvs.choices
                },
                mechanisms: paper.mechanisms,
                efference: paper.efference,
                short: paper.short,
                swarm: paper.swarm,
                ..alvs
            },
            paper
        );
        assert_eq!(Params::default(), alvs);
        assert_eq!(alvs.validate(), Ok(()));
        assert_eq!(Params::preset("paper"), Some(paper));
        assert_eq!(Params::preset("alvs"), Some(alvs));
        assert_eq!(Params::preset("ALVS"), None);
        assert_eq!((paper.preset_name(), alvs.preset_name()), ("paper", "alvs"));
        let mut custom = alvs;
        custom.table1.t_a = 99;
        assert_eq!(custom.preset_name(), "custom");
    }

    #[test]
    fn the_firmware_is_the_paper_with_the_documented_values_only() {
        let (paper, fw) = (Params::PAPER, Params::FIRMWARE);
        // docs/notes/2026-11-27-authors-firmware.md: each value and its source line
        let (t, c, f) = (fw.table1, fw.choices, fw.firmware);
        assert_eq!(
            (t.w, t.n, t.t_a, t.t_d, t.w_s),
            (0.0, 2, 80, 12_500, 20_000.0)
        );
        assert_eq!((t.t_s, c.c_d), (750_000, 1.0));
        assert_eq!((c.q_floor, c.q_balance, c.q_arms), (50_000, 0, 3));
        assert_eq!(
            (f.max_fields, off0(f.t_lplc2), f.strict_retire),
            (1, 150_000, true)
        );
        assert!(!f.opponent);
        // everything else is the paper's: no closed-loop mechanism
        let mut back = fw;
        back.table1 = TableOne {
            r_af: t.r_af,
            d: t.d,
            alpha: t.alpha,
            ..paper.table1
        };
        back.choices = Choices {
            s: c.s,
            gain: c.gain,
            lm_shift: c.lm_shift,
            r_c: c.r_c,
            c_frac: c.c_frac,
            ..paper.choices
        };
        back.firmware = paper.firmware;
        assert_eq!(back, paper);
        assert_eq!(fw.validate(), Ok(()));
        assert_eq!(Params::preset("firmware"), Some(fw));
        assert_eq!(fw.preset_name(), "firmware");
        let mut custom = fw;
        custom.table1.n = 3;
        assert_eq!(custom.preset_name(), "custom");
    }

    #[test]
    fn the_firmwares_switches_are_set_by_name() {
        let mut p = Params::PAPER;
        assert_eq!(p.set("max_fields", "1"), Ok(()));
        assert_eq!(p.set("t_lplc2", "150000"), Ok(()));
        assert_eq!(p.set("firmware.strict_retire", "1"), Ok(()));
        let f = p.firmware;
        assert_eq!(
            (f.max_fields, off0(f.t_lplc2), f.strict_retire),
            (1, 150_000, true)
        );
        assert_eq!(p.set("strict_retire", "0"), Ok(()));
        assert!(!p.firmware.strict_retire);
        assert_eq!(p.set("strict_retire", "true"), Ok(()));
        assert!(p.firmware.strict_retire);
        assert_eq!(p.set("opponent", "false"), Ok(()));
        assert!(!p.firmware.opponent);
        assert_eq!(p.set("firmware.t_lplc2", "none"), Ok(()));
        assert_eq!(p.firmware.t_lplc2, None);
        let msg = |name: &str, v: &str| {
            {
                let mut p = Params::PAPER;
                p.set(name, v)
            }
            .unwrap_err()
            .to_string()
        };
        assert_eq!(
            msg("max_fields", "0"),
            "parameter firmware.max_fields must lie in 1..=6"
        );
        assert_eq!(
            msg("firmware.max_fields", "7"),
            "parameter firmware.max_fields must lie in 1..=6"
        );
        assert_eq!(
            msg("strict_retire", "2"),
            "parameter firmware.strict_retire must lie in 0..=1 (or true/false)"
        );
        assert_eq!(
            msg("strict_retire", "yes"),
            "parameter firmware.strict_retire must be a whole number in 0..=1 (or true/false)"
        );
        assert_eq!(
            msg("t_lplc2", "-1"),
            "parameter firmware.t_lplc2 must lie in 0..=4294967295 (0, none or off: off)"
        );
        let mut bad = p;
        bad.firmware.max_fields = 0;
        assert!(bad.validate().is_err());
    }

    #[test]
    fn a_mechanism_is_turned_off_by_0_none_or_off() {
        for off in ["0", "none", "off", " None "] {
            let mut p = Params::ALVS;
            assert_eq!(p.set("efference.band_row", off), Ok(()), "{off}");
            assert_eq!(p.efference.band_row, None);
            assert_eq!(p.set("warmup", off), Ok(()), "{off}");
            assert_eq!(p.mechanisms.warmup, None);
        }
        let mut p = Params::PAPER;
        assert_eq!(p.set("warmup", "4"), Ok(()));
        assert_eq!(off0(p.mechanisms.warmup), 4);
        assert_eq!(p.set("derotate", "1"), Ok(()));
        assert!(p.efference.derotate);
        assert_eq!(p.set("efference.derotate", "off"), Ok(()));
        assert!(!p.efference.derotate);
    }

    #[test]
    fn set_by_name_checks_name_type_and_range() {
        let mut p = Params::default();
        assert_eq!(p.set("t_a", "120"), Ok(()));
        assert_eq!(p.table1.t_a, 120);
        assert_eq!(p.set("table1.t_a", "121"), Ok(()));
        assert_eq!(p.table1.t_a, 121);
        assert_eq!(p.set("nope", "1"), Err(ParamError::Unknown));
        assert_eq!(p.set("choices.t_a", "1"), Err(ParamError::Unknown));
        assert_eq!(
            p.set("n", "x"),
            Err(ParamError::NotANumber { name: "table1.n" })
        );
        assert!(matches!(
            p.set("n", "0"),
            Err(ParamError::OutOfRange {
                name: "table1.n",
                ..
            })
        ));
        assert_eq!(
            p.set("w", "NaN"),
            Err(ParamError::OutOfRangeReal {
                name: "table1.w",
                min: 0.0,
                max: 4.0
            })
        );
        let e = Params::default().set("w_s", "0").unwrap_err();
        assert_eq!(
            format!("{e}"),
            "parameter table1.w_s must be a finite number in [0.001, 1000000000]"
        );
        // n * s may not exceed the correlator reach
        assert!(matches!(
            p.set("s", "3"),
            Err(ParamError::OutOfRange {
                name: "choices.s",
                ..
            })
        ));
        // a refused value leaves the parameters unchanged
        assert_eq!(p.table1.n, 3);
        assert_eq!(p.table1.t_a, 121);
    }

    #[test]
    fn refusals_say_the_allowed_range() {
        let msg = |name: &str, v: &str| Params::default().set(name, v).unwrap_err().to_string();
        // whole numbers outside the type used to read as "not a number"
        assert_eq!(
            msg("t_a", "-5"),
            "parameter table1.t_a must lie in 0..=65535"
        );
        assert_eq!(
            msg("r_af", "100000"),
            "parameter table1.r_af must lie in 1..=99"
        );
        assert_eq!(
            msg("r_af", "-1"),
            "parameter table1.r_af must lie in 1..=99"
        );
        assert_eq!(
            msg("q_floor", "99999999999999999999999"),
            "parameter choices.q_floor must lie in 0..=4294967295"
        );
        assert_eq!(
            msg("n", "x"),
            "parameter table1.n must be a whole number in 1..=4"
        );
        assert_eq!(
            msg("n", "2.5"),
            "parameter table1.n must be a whole number in 1..=4"
        );
        assert_eq!(
            msg("n", "-"),
            "parameter table1.n must be a whole number in 1..=4"
        );
        assert_eq!(
            msg("c_d", "two"),
            "parameter choices.c_d must be a finite number in [1, 16]"
        );
        assert_eq!(
            msg("c_d", "40"),
            "parameter choices.c_d must be a finite number in [1, 16]"
        );
        assert_eq!(
            msg("warmup", "256"),
            "parameter mechanisms.warmup must lie in 0..=255 (0, none or off: off)"
        );
        assert!(ParamError::Unknown
            .to_string()
            .contains("efference.derotate"));
    }

    #[test]
    fn every_parameter_has_a_range_whose_ends_are_accepted() {
        assert_eq!(Params::NAMES.len(), Params::RANGES.len());
        assert_eq!(Params::NAMES.len(), Params::FIELDS.len());
        assert_eq!(Params::NAMES.len(), Params::WORDS.len());
        assert_eq!(Params::NAMES.len(), 41);
        for (name, field) in Params::NAMES.iter().zip(Params::FIELDS) {
            assert_eq!(name.split_once('.').map(|(_, f)| f), Some(*field));
            assert_eq!(Params::range(name), Params::range(field));
            let (lo, hi) = match Params::range(name).unwrap() {
                Range::Int(lo, hi) => (format!("{lo}"), format!("{hi}")),
                Range::Real(lo, hi) => (format!("{lo}"), format!("{hi}")),
            };
            // s reaches its end only with n = 1 (n·s ≤ MAX_REACH)
            let mut p = Params::default();
            if *field == "s" {
                p.table1.n = 1;
            }
            let mut q = p;
            assert_eq!(p.set(name, &lo), Ok(()), "{name}={lo}");
            assert_eq!(q.set(field, &hi), Ok(()), "{field}={hi}");
        }
        assert_eq!(Params::range("nope"), None);
    }

    #[test]
    fn the_groups_cost_no_ram() {
        // the flat struct before the groups took 64 bytes; each group pads to its alignment,
        // and `T_a`, `T_d` as `u16`s leave Table I's group none; `t_a_quiet`, which acts only
        // below `T_a`, is a `u16` too, so `noise_pct` fits the mechanisms' group. 64 bytes
        // until `short_uncut`'s byte took the whole past a multiple of its 4-byte alignment: 68
        assert_eq!(core::mem::size_of::<Params>(), 68);
    }
}
