//! Every parameter of the aLPLC2 network in one place: the paper's Table I with its defaults,
//! and the values the paper leaves unstated, each a documented choice (`docs/model.md`).

use crate::frame::HEIGHT;
use crate::model::network::MAX_AFS;

/// Largest number of connected neurons `n` per correlator (Eq. 6).
pub const MAX_N: u8 = 4;
/// Largest reach `n * s` of a correlator, in pixels.
pub const MAX_REACH: u8 = 8;
/// Largest averaging window `d` (Eq. 10), in frames.
pub const MAX_D: u8 = 16;

/// The parameters of the aLPLC2 network and visuomotor pathway.
///
/// [`Params::PAPER`] is the paper's Table I plus the choices documented in `docs/model.md`;
/// `Params::default()` is [`Params::ALVS`], that plus the closed-loop mechanisms;
/// [`Params::FIRMWARE`] is what the authors' public firmware runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    /// `w`: weight of the ON channel, Eq. (1). Table I: 0.25.
    pub w: f32,
    /// `n`: connected neurons per correlator, Eq. (6). Table I: 3.
    pub n: u8,
    /// `R_AF`: half side of an attention field's square, in pixels. Table I: 36.
    pub r_af: u8,
    /// `T_a`: threshold on `L̂_ON + L̂_OFF` for a new attention field, Eq. (3). Table I: 100.
    pub t_a: u32,
    /// `T_d`: mean LPLC2 over `d` frames below which a field retires, Eq. (10). Table I: 5000.
    pub t_d: u32,
    /// `d`: frames over which the LPLC2 response is averaged, Eq. (10). Table I: 4.
    pub d: u8,
    /// `w_s`: weight in the strength sigmoid, Eq. (11). Table I: 4000.
    pub w_s: f32,
    /// `α`: degrees per pixel from the horizontal centroid to an angle, Eqs. (13)–(15). Table I: 0.707.
    pub alpha: f32,
    /// `T_s`: global threat `ΣLPLC2` above which the short-mode escape starts. Table I: 7000,
    /// in the paper's model and the default alike. (5500 was tried for an obstacle first seen
    /// late, 71–97 mm away at the edge of the view; on the held-out seeds Table I's 7000 did
    /// better, `docs/ablation.md`.)
    pub t_s: u32,
    /// `C_d`: correlator delay in frames, Eq. (6). Unstated in the paper. Realised as the
    /// classic HRC delay filter, a first-order low-pass with mean delay `C_d` frames (exactly
    /// the previous frame when `C_d = 1`), so any delay costs one map per channel.
    pub c_d: f32,
    /// `s`: spacing of the connected neurons in pixels, Eq. (6). Unstated; 1.
    pub s: u8,
    /// Retina gain: luminance enters the model as `gain * Y8`. Unstated; 4, a 10-bit scale,
    /// the smallest gain at which a full-contrast ON edge (weight `w`) can reach `T_a`.
    pub gain: u8,
    /// Local-motion scale: correlator products are divided by `2^lm_shift` so that LPLC2
    /// responses live on the scale of `T_d`, `T_s` and `w_s`. Unstated; see `docs/model.md`.
    pub lm_shift: u8,
    /// Half side of the window in which a centroid is re-estimated, Eq. (4); at most `R_AF`.
    /// The paper uses the whole field; its authors' simulator uses a window of half `R_AF`.
    pub r_c: u8,
    /// Relative saliency floor of the centroid moments, Eq. (4), in percent of the window's peak:
    /// weaker pixels do not pull the centroid. Unstated; the paper's firmware thresholds its OFF
    /// map before the moments in the same spirit (`docs/model.md`).
    pub c_frac: u8,
    /// Noise floor of a quadrant, Eq. (9): a quadrant counts as excited only above it.
    /// Unstated in the paper (its firmware uses a similar `T_cardinal`); see `docs/model.md`.
    pub q_floor: u32,
    /// Balance of the quadrants, Eq. (9), in percent: each must reach this share of the
    /// strongest one to count as excited. Unstated; see `docs/model.md`.
    pub q_balance: u8,
    /// Excited quadrants needed to open the gate, Eq. (9). The paper's product `∏Q` needs all
    /// 4 ([`Params::PAPER`]); the authors' firmware opens at 3 of 4 ("expansion edges"), and so
    /// does the default, together with `q_grow_pct`; see `docs/model.md`.
    pub q_arms: u8,
    /// Frames after a start or restart (a torn or dropped frame) during which no field is
    /// reported stimulated: the delay line of Eq. (6) and the `d`-frame history of Eq. (10)
    /// are still filling, so early responses compare a frame with an empty past. Not in the
    /// paper (0 there); see `docs/model.md`, "Closed-loop mechanisms".
    pub warmup: u8,
    /// Whole-field luminance events: when at least this percent of the retina brightens (or
    /// darkens) in one frame while next to nothing changes the other way, the change
    /// is the light or the sensor's automatic exposure, not motion, and no field is reported
    /// stimulated in that frame. 0 turns it off (the paper). See `docs/model.md`,
    /// "Closed-loop mechanisms".
    pub flicker_pct: u8,
    /// Blocked way (efference copy): the escape FSM turns around when it commanded forward
    /// travel but the coarse view changed by less than this many grey levels on average
    /// ([`crate::model::progress`]). 0 turns it off (the paper). The default, 2, is below
    /// every free robot's change on the six arena walls measured (the soft `outdoor_2`
    /// photograph changes by less than 6 levels on 39 % of its free frames, never below 2) and
    /// above most of a pressed robot's (`docs/experiments.md`, "Closed-loop mechanisms").
    /// Off in the default: no robot stayed pressed in the validated world, so it changed
    /// nothing (`docs/ablation.md`); a floor that grips, or a body that catches on an edge,
    /// may want it.
    pub blocked_change: u8,
    /// Efference copy of turns: 1 re-registers the retina's memory to each turn the robot
    /// reports ([`crate::Network::turned`]), so a turn causes no motion signal
    /// ([`crate::model::derotate`]); 0 ignores the reports (the paper). See `docs/model.md`,
    /// "Closed-loop mechanisms".
    pub derotate: u8,
    /// Motion adaptation of the short mode: with `N` > 0 the short mode also needs `ΣLPLC2`
    /// above twice its running mean over about `N` frames, so a steady response (the robot's
    /// own translation past textured walls) does not keep it on while a growing one (looming)
    /// does. 0 turns it off (the paper and the default: it changed nothing there and cost the
    /// paper's model 20 points of arena success, `docs/ablation.md`). See `docs/model.md`,
    /// "Closed-loop mechanisms".
    pub adapt_frames: u8,
    /// Growth of a partial opening: when fewer than four quadrants are excited (an opening
    /// that `q_arms` < 4 allows), the field's quadrant sum must also have grown by at least
    /// this many percent since the last frame, at the same place
    /// ([`crate::model::lplc2::GROW_SHIFT_PX`]). A looming object's drive grows; a receding
    /// one's, and the residue a finished threat leaves, do not. 0 turns it off (the paper); the
    /// default is 50 with `q_arms` = 3. See `docs/model.md`, "Closed-loop mechanisms".
    pub q_grow_pct: u8,
    /// Attention threshold of a quiet scene: `T_a` (Eq. 3) falls towards this value as the
    /// share of the retina that changes falls below [`crate::model::attention::BUSY_PCT`], so
    /// a small object's faint edges can open a field when little else moves, while a scene
    /// full of motion keeps Table I's `T_a`. 0 turns it off (the paper). See `docs/model.md`,
    /// "Closed-loop mechanisms".
    pub t_a_quiet: u32,
    /// Fields centred above this row are silent while the robot drives forward (its efference
    /// copy, [`crate::Network::driving`]): driving, the expansion of the scene above the
    /// body's height is the robot's own translation, and anything that can touch a ground robot
    /// also reaches into the rows below. Standing, every field responds. 0 turns it off (the
    /// paper; the default 27, measured in `docs/experiments.md`). See `docs/model.md`,
    /// "Closed-loop mechanisms".
    pub band_row: u8,
    /// While the robot drives forward, an obstacle whose foot (where it meets the floor) lies
    /// at or below this row inside the robot's path is reported ([`crate::model::floor`]),
    /// and alerts on a frame no field alerts on: with the camera at a fixed height over a flat
    /// floor, the row is the distance. 0 turns it off (the paper; the default 52, measured in
    /// `docs/experiments.md`); rows at or above the horizon (≤ 35) find nothing either. See
    /// `docs/model.md`, "Closed-loop mechanisms".
    pub floor_row: u8,
    /// While the robot drives forward, the short mode needs the threat's `X̄` within this many
    /// columns of the centre: driving, everything beside the path expands with the robot's
    /// own translation, and only what lies in the path can be imminent. 23 is the path's
    /// half-width seen at the robots' encounter distance (126 mm), with the half-width then taken
    /// as one body diameter (42 mm): 70 · 42 / 126. Alerts off the path still start a long
    /// takeoff. 0 turns it off (the paper and the default: like `short_row` it only repeats
    /// what the escape saccade does, `docs/ablation.md`). See `docs/model.md`, "Closed-loop
    /// mechanisms".
    pub short_cols: u8,
    /// While the robot drives forward, the short mode also needs the threat's foot (where it
    /// meets the floor, [`crate::model::floor::nearest_foot`] at `X̄`) at or below this row:
    /// within about one second of travel. Driving, a wall or robot still far ahead expands
    /// with the robot's own speed; the floor line gives its distance. Row 50 is 97 mm from the
    /// camera (20 mm above the floor), one second at the cruise speed of 100 mm/s. The alert
    /// still starts a long takeoff. 0 turns it off (the paper); 1–36 only need a foot
    /// somewhere below the horizon (a threat with none within 3 columns is held back). Blind
    /// spot: a wall so close that it covers the bottom row's middle has no foot (as for the
    /// floor line) and loses the short mode; the floor line covers it. Off in the default:
    /// like `short_cols` it keeps a short mode from turning an escaping robot back, which the
    /// escape saccade (`FsmParams::escape_saccade`) already does; the paper's model, which has
    /// no escape saccade, gains 4 points of arena success with it (`docs/ablation.md`). See
    /// `docs/model.md`, "Closed-loop mechanisms".
    pub short_row: u8,
    /// The swarm's look ([`crate::model::movers`], run beside the network by whatever runs
    /// the swarm behaviour): while the wheels are commanded to stand, the band of rows where
    /// robots appear is compared over 0.4 s, and the column where most pixels changed by more
    /// than this many grey levels is reported: something that moves, another robot, since a
    /// standing robot has no flow of its own. 0 turns it off (the paper); 25 is far above the
    /// camera's noise (2 grey levels per pixel, 2 % gain flicker, at most 5 at full white):
    /// 15 took noise for movers (`docs/experiments.md`, "Swarm"). Only the swarm behaviour acts
    /// on it (`FsmParams::look_every`); the escape and the firmware never look.
    pub look_change: u8,
    /// The most attention fields alive at once, 1..=[`MAX_AFS`]: with that many, no new field
    /// opens (Eq. 3) until one retires. The paper's fields are as many as fit ([`MAX_AFS`]);
    /// the authors' firmware has one (`NUM_AF 1`, [`Params::FIRMWARE`]).
    pub max_fields: u8,
    /// A field's output over time, the authors' firmware's `T_LPLC2`. 0 (the paper): a field
    /// is stimulated on a frame when its gate opens (Eq. 9, `LPLC2_k > 0`) and passes on that
    /// frame's response. Above 0: it passes on the mean of its last `d` responses (the frames
    /// before its birth counting 0, as the firmware's ring of 4 outputs), and only while that
    /// mean exceeds this value; a frame on which the field is silenced (`warmup`,
    /// `flicker_pct`, `band_row`) passes on 0. `ΣLPLC2`, `X̄`, `S` and the short mode are
    /// made of these outputs. See `docs/model.md`, "The authors' firmware".
    pub t_lplc2: u32,
    /// Eq. (10) as the authors' firmware runs it: every field is judged from its first frame,
    /// on the mean of its last `d` responses with the frames before its birth counting 0, and
    /// the last field retires too (a new one may open on the next frame). `false` (the paper):
    /// a field is not judged before it has lived `d` frames, and the strongest always remains
    /// ("at least one AF is always retained").
    pub strict_retire: bool,
    /// Eq. (6)'s correlator form. `true` (the paper): the opponent HRC the paper cites, a
    /// change travelling along the preferred direction minus one travelling against it.
    /// `false` (the authors' firmware, whose subtracted terms are commented out): only the
    /// preferred-direction product `L(q,t)·L(p,t−C_d)`, which a change that does not move
    /// (flicker, a translating edge's own pixels) excites too. Taken by the general
    /// pixel-by-pixel path (the row kernel is opponent only).
    pub opponent: bool,
}

impl Params {
    /// Table I of the paper plus the documented choices.
    pub const PAPER: Params = Params {
        w: 0.25,
        n: 3,
        r_af: 36,
        t_a: 100,
        t_d: 5000,
        d: 4,
        w_s: 4000.0,
        alpha: 0.707,
        t_s: 7000,
        c_d: 2.0,
        s: 1,
        gain: 4,
        lm_shift: 8,
        r_c: 36,
        c_frac: 50,
        q_floor: 250,
        q_balance: 15,
        q_arms: 4,
        warmup: 0,
        flicker_pct: 0,
        blocked_change: 0,
        derotate: 0,
        adapt_frames: 0,
        q_grow_pct: 0,
        t_a_quiet: 0,
        band_row: 0,
        floor_row: 0,
        short_cols: 0,
        short_row: 0,
        look_change: 0,
        max_fields: MAX_AFS as u8,
        t_lplc2: 0,
        strict_retire: false,
        opponent: true,
    };

    /// The default: the paper's model ([`Params::PAPER`]) with Table I unchanged, plus the
    /// mechanisms a robot in closed loop needs that the paper leaves out, each a parameter
    /// that earns its place on the held-out seeds (`docs/ablation.md`). The firmware runs
    /// these. The options that did not earn it (`blocked_change`, `adapt_frames`,
    /// `short_cols`, `short_row`) stay off.
    pub const ALVS: Params = Params {
        warmup: 4,
        flicker_pct: 50,
        derotate: 1,
        q_arms: 3,
        q_grow_pct: 50,
        t_a_quiet: 30,
        band_row: 27,
        floor_row: 52,
        look_change: 25,
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
        // DELAY_WINDOW 2: exactly the last frame
        c_d: 1.0,
        // T_cardinal
        q_floor: 50_000,
        q_balance: 0,
        // T_ExpansionEdgeNum = 3
        q_arms: 3,
        // NUM_AF 1
        max_fields: 1,
        // T_LPLC2 = 3 · T_cardinal
        t_lplc2: 150_000,
        strict_retire: true,
        // the subtracted products commented out
        opponent: false,
        ..Params::PAPER
    };

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

    /// Names accepted by [`Params::set`], in the order of the paper.
    pub const NAMES: [&'static str; 34] = [
        "w",
        "n",
        "r_af",
        "t_a",
        "t_d",
        "d",
        "w_s",
        "alpha",
        "t_s",
        "c_d",
        "s",
        "gain",
        "lm_shift",
        "r_c",
        "c_frac",
        "q_floor",
        "q_balance",
        "q_arms",
        "warmup",
        "flicker_pct",
        "blocked_change",
        "derotate",
        "adapt_frames",
        "q_grow_pct",
        "t_a_quiet",
        "band_row",
        "floor_row",
        "short_cols",
        "short_row",
        "look_change",
        "max_fields",
        "t_lplc2",
        "strict_retire",
        "opponent",
    ];

    /// The values each parameter of [`Params::NAMES`] may take (same order): the range the
    /// model can compute with, without a panic or an overflow. `s` is further bounded by
    /// `n · s ≤ MAX_REACH`.
    pub const RANGES: [Range; 34] = [
        Range::Real(0.0, 4.0),
        Range::Int(1, MAX_N as i64),
        Range::Int(1, 99),
        Range::Int(0, u32::MAX as i64),
        Range::Int(0, u32::MAX as i64),
        Range::Int(1, MAX_D as i64),
        Range::Real(1e-3, 1e9),
        Range::Real(-10.0, 10.0),
        Range::Int(0, u32::MAX as i64),
        Range::Real(1.0, 16.0),
        Range::Int(1, MAX_REACH as i64),
        Range::Int(1, 16),
        Range::Int(0, 24),
        Range::Int(1, 99),
        Range::Int(0, 100),
        Range::Int(0, u32::MAX as i64),
        Range::Int(0, 100),
        Range::Int(1, 4),
        Range::Int(0, 255),
        Range::Int(0, 100),
        Range::Int(0, 255),
        Range::Int(0, 1),
        Range::Int(0, 255),
        Range::Int(0, 255),
        Range::Int(0, u32::MAX as i64),
        Range::Int(0, HEIGHT as i64 - 1),
        Range::Int(0, HEIGHT as i64 - 1),
        Range::Int(0, 49),
        Range::Int(0, HEIGHT as i64 - 1),
        Range::Int(0, 255),
        Range::Int(1, MAX_AFS as i64),
        Range::Int(0, u32::MAX as i64),
        // switches: 0 (false) or 1 (true)
        Range::Int(0, 1),
        Range::Int(0, 1),
    ];

    /// The allowed values of the parameter `name`, `None` for an unknown name.
    pub fn range(name: &str) -> Option<Range> {
        let i = Params::NAMES.iter().position(|n| *n == name)?;
        Params::RANGES.get(i).copied()
    }

    /// Checks every value is in the range the model can compute with (no panic, no overflow).
    pub fn validate(&self) -> Result<(), ParamError> {
        check_f32("w", self.w)?;
        check_int("n", self.n.into())?;
        check_int("r_af", self.r_af.into())?;
        check_int("t_a", self.t_a.into())?;
        check_int("t_d", self.t_d.into())?;
        check_int("r_c", self.r_c.into())?;
        check_int("c_frac", self.c_frac.into())?;
        check_int("q_floor", self.q_floor.into())?;
        check_int("q_balance", self.q_balance.into())?;
        check_int("q_arms", self.q_arms.into())?;
        check_int("warmup", self.warmup.into())?;
        check_int("flicker_pct", self.flicker_pct.into())?;
        check_int("blocked_change", self.blocked_change.into())?;
        check_int("derotate", self.derotate.into())?;
        check_int("adapt_frames", self.adapt_frames.into())?;
        check_int("q_grow_pct", self.q_grow_pct.into())?;
        check_int("t_a_quiet", self.t_a_quiet.into())?;
        check_int("band_row", self.band_row.into())?;
        check_int("floor_row", self.floor_row.into())?;
        check_int("short_cols", self.short_cols.into())?;
        check_int("short_row", self.short_row.into())?;
        check_int("look_change", self.look_change.into())?;
        check_int("max_fields", self.max_fields.into())?;
        check_int("t_lplc2", self.t_lplc2.into())?;
        check_int("d", self.d.into())?;
        check_f32("w_s", self.w_s)?;
        check_f32("alpha", self.alpha)?;
        check_int("t_s", self.t_s.into())?;
        check_f32("c_d", self.c_d)?;
        check_int("s", self.s.into())?;
        if u32::from(self.n) * u32::from(self.s) > u32::from(MAX_REACH) {
            return Err(ParamError::OutOfRange {
                name: "s",
                min: 1,
                max: i64::from(MAX_REACH / self.n),
            });
        }
        check_int("gain", self.gain.into())?;
        check_int("lm_shift", self.lm_shift.into())?;
        Ok(())
    }

    /// Sets one parameter by name from its text value, as given on a command line.
    pub fn set(&mut self, name: &str, value: &str) -> Result<(), ParamError> {
        let name: &'static str = Params::NAMES
            .into_iter()
            .find(|n| *n == name)
            .ok_or(ParamError::Unknown)?;
        let mut p = *self;
        let v = value.trim();
        match name {
            "w" => p.w = real(name, v)?,
            "n" => p.n = int(name, v)?,
            "r_af" => p.r_af = int(name, v)?,
            "t_a" => p.t_a = int(name, v)?,
            "t_d" => p.t_d = int(name, v)?,
            "d" => p.d = int(name, v)?,
            "w_s" => p.w_s = real(name, v)?,
            "alpha" => p.alpha = real(name, v)?,
            "t_s" => p.t_s = int(name, v)?,
            "c_d" => p.c_d = real(name, v)?,
            "s" => p.s = int(name, v)?,
            "gain" => p.gain = int(name, v)?,
            "lm_shift" => p.lm_shift = int(name, v)?,
            "r_c" => p.r_c = int(name, v)?,
            "c_frac" => p.c_frac = int(name, v)?,
            "q_floor" => p.q_floor = int(name, v)?,
            "q_balance" => p.q_balance = int(name, v)?,
            "q_arms" => p.q_arms = int(name, v)?,
            "warmup" => p.warmup = int(name, v)?,
            "flicker_pct" => p.flicker_pct = int(name, v)?,
            "blocked_change" => p.blocked_change = int(name, v)?,
            "derotate" => p.derotate = int(name, v)?,
            "adapt_frames" => p.adapt_frames = int(name, v)?,
            "q_grow_pct" => p.q_grow_pct = int(name, v)?,
            "t_a_quiet" => p.t_a_quiet = int(name, v)?,
            "band_row" => p.band_row = int(name, v)?,
            "floor_row" => p.floor_row = int(name, v)?,
            "short_cols" => p.short_cols = int(name, v)?,
            "short_row" => p.short_row = int(name, v)?,
            "look_change" => p.look_change = int(name, v)?,
            "max_fields" => p.max_fields = int(name, v)?,
            "t_lplc2" => p.t_lplc2 = int(name, v)?,
            "strict_retire" => p.strict_retire = int::<u8>(name, v)? != 0,
            // the last of NAMES; every other name matched above
            _ => p.opponent = int::<u8>(name, v)? != 0,
        }
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

impl core::fmt::Display for ParamError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            ParamError::Unknown => write!(f, "unknown parameter (known: {})", NamesList),
            ParamError::NotANumber { name } => match Params::range(name) {
                Some(Range::Int(min, max)) => {
                    write!(
                        f,
                        "parameter {name} must be a whole number in {min}..={max}"
                    )
                }
                Some(Range::Real(min, max)) => {
                    write!(
                        f,
                        "parameter {name} must be a finite number in [{min}, {max}]"
                    )
                }
                None => write!(f, "parameter {name}: not a number"),
            },
            ParamError::OutOfRange { name, min, max } => {
                write!(f, "parameter {name} must lie in {min}..={max}")
            }
            ParamError::OutOfRangeReal { name, min, max } => {
                write!(
                    f,
                    "parameter {name} must be a finite number in [{min}, {max}]"
                )
            }
        }
    }
}

struct NamesList;
impl core::fmt::Display for NamesList {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        for (i, n) in Params::NAMES.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            f.write_str(n)?;
        }
        Ok(())
    }
}

/// The values a parameter may take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Range {
    /// A whole number in `min..=max`.
    Int(i64, i64),
    /// A finite real number in `[min, max]`.
    Real(f32, f32),
}

/// An integer parameter from text: a whole number (with an optional sign) outside the
/// parameter's range, however many digits it has, is out of range; anything else that does
/// not parse is not a number.
fn int<T: TryFrom<i64>>(name: &'static str, v: &str) -> Result<T, ParamError> {
    let Some(Range::Int(min, max)) = Params::range(name) else {
        return Err(ParamError::NotANumber { name });
    };
    let out = ParamError::OutOfRange { name, min, max };
    let digits = v.strip_prefix(['+', '-']).unwrap_or(v);
    let x: i64 = match v.parse() {
        Ok(x) => x,
        Err(_) if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) => {
            return Err(out)
        }
        Err(_) => return Err(ParamError::NotANumber { name }),
    };
    if !(min..=max).contains(&x) {
        return Err(out);
    }
    T::try_from(x).map_err(|_| out)
}

/// A real parameter from text (its range is checked by `validate`).
fn real(name: &'static str, v: &str) -> Result<f32, ParamError> {
    v.parse().map_err(|_| ParamError::NotANumber { name })
}

fn check_int(name: &'static str, v: i64) -> Result<(), ParamError> {
    match Params::range(name) {
        Some(Range::Int(min, max)) if (min..=max).contains(&v) => Ok(()),
        Some(Range::Int(min, max)) => Err(ParamError::OutOfRange { name, min, max }),
        _ => Err(ParamError::NotANumber { name }),
    }
}

fn check_f32(name: &'static str, v: f32) -> Result<(), ParamError> {
    match Params::range(name) {
        Some(Range::Real(min, max)) if v.is_finite() && v >= min && v <= max => Ok(()),
        Some(Range::Real(min, max)) => Err(ParamError::OutOfRangeReal { name, min, max }),
        _ => Err(ParamError::NotANumber { name }),
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::format;
    use std::string::ToString;

    #[test]
    fn defaults_are_table_one() {
        let p = Params::PAPER;
        assert_eq!((p.w, p.n, p.r_af, p.t_a, p.t_d), (0.25, 3, 36, 100, 5000));
        assert_eq!((p.d, p.w_s, p.alpha, p.t_s), (4, 4000.0, 0.707, 7000));
        assert_eq!(p.validate(), Ok(()));
        // the default keeps Table I
        let d = Params::default();
        assert_eq!((d.w, d.n, d.r_af, d.t_a, d.t_d), (0.25, 3, 36, 100, 5000));
        assert_eq!((d.d, d.w_s, d.alpha, d.t_s), (4, 4000.0, 0.707, 7000));
    }

    #[test]
    fn the_default_is_the_paper_plus_the_closed_loop_mechanisms_only() {
        let (paper, alvs) = (Params::PAPER, Params::ALVS);
        assert_eq!(
            (
                paper.warmup,
                paper.flicker_pct,
                paper.blocked_change,
                paper.derotate,
                paper.adapt_frames,
                paper.q_grow_pct,
                paper.q_arms,
                paper.t_a_quiet,
                paper.band_row,
                paper.floor_row,
                paper.short_cols,
                paper.short_row
            ),
            (0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 0, 0),
            "the paper has none"
        );
        assert_eq!(
            (
                alvs.warmup,
                alvs.flicker_pct,
                alvs.blocked_change,
                alvs.derotate,
                alvs.adapt_frames,
                alvs.q_grow_pct,
                alvs.q_arms,
                alvs.t_a_quiet,
                alvs.band_row,
                alvs.floor_row,
                alvs.short_cols,
                alvs.short_row
            ),
            (4, 50, 0, 1, 0, 50, 3, 30, 27, 52, 0, 0)
        );
        assert_eq!((paper.look_change, alvs.look_change), (0, 25));
        // the firmware's switches keep the paper's and the default's behaviour
        for p in [paper, alvs] {
            assert_eq!((p.max_fields, p.t_lplc2, p.strict_retire), (6, 0, false));
            assert!(p.opponent);
        }
        // everything else is the paper's
        assert_eq!(
            Params {
                warmup: 0,
                flicker_pct: 0,
                blocked_change: 0,
                derotate: 0,
                adapt_frames: 0,
                q_grow_pct: 0,
                q_arms: 4,
                t_a_quiet: 0,
                band_row: 0,
                floor_row: 0,
                short_cols: 0,
                short_row: 0,
                look_change: 0,
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
        assert_eq!(Params { t_a: 99, ..alvs }.preset_name(), "custom");
    }

    #[test]
    fn the_firmware_is_the_paper_with_the_documented_values_only() {
        let (paper, fw) = (Params::PAPER, Params::FIRMWARE);
        // docs/notes/2026-11-27-authors-firmware.md: each value and its source line
        assert_eq!(
            (fw.w, fw.n, fw.t_a, fw.t_d, fw.w_s),
            (0.0, 2, 80, 12_500, 20_000.0)
        );
        assert_eq!((fw.t_s, fw.c_d), (750_000, 1.0));
        assert_eq!((fw.q_floor, fw.q_balance, fw.q_arms), (50_000, 0, 3));
        assert_eq!(
            (fw.max_fields, fw.t_lplc2, fw.strict_retire),
            (1, 150_000, true)
        );
        assert!(!fw.opponent);
        // everything else is the paper's: no closed-loop mechanism
        assert_eq!(
            Params {
                w: paper.w,
                n: paper.n,
                t_a: paper.t_a,
                t_d: paper.t_d,
                w_s: paper.w_s,
                t_s: paper.t_s,
                c_d: paper.c_d,
                q_floor: paper.q_floor,
                q_balance: paper.q_balance,
                q_arms: paper.q_arms,
                max_fields: paper.max_fields,
                t_lplc2: paper.t_lplc2,
                strict_retire: paper.strict_retire,
                opponent: paper.opponent,
                ..fw
            },
            paper
        );
        assert_eq!(fw.validate(), Ok(()));
        assert_eq!(Params::preset("firmware"), Some(fw));
        assert_eq!(fw.preset_name(), "firmware");
        assert_eq!(Params { n: 3, ..fw }.preset_name(), "custom");
    }

    #[test]
    fn the_firmwares_switches_are_set_by_name() {
        let mut p = Params::PAPER;
        assert_eq!(p.set("max_fields", "1"), Ok(()));
        assert_eq!(p.set("t_lplc2", "150000"), Ok(()));
        assert_eq!(p.set("strict_retire", "1"), Ok(()));
        assert_eq!(
            (p.max_fields, p.t_lplc2, p.strict_retire),
            (1, 150_000, true)
        );
        assert_eq!(p.set("strict_retire", "0"), Ok(()));
        assert!(!p.strict_retire);
        assert_eq!(p.set("opponent", "0"), Ok(()));
        assert!(!p.opponent);
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
            "parameter max_fields must lie in 1..=6"
        );
        assert_eq!(
            msg("max_fields", "7"),
            "parameter max_fields must lie in 1..=6"
        );
        assert_eq!(
            msg("strict_retire", "2"),
            "parameter strict_retire must lie in 0..=1"
        );
        assert_eq!(
            msg("strict_retire", "yes"),
            "parameter strict_retire must be a whole number in 0..=1"
        );
        assert!(Params { max_fields: 0, ..p }.validate().is_err());
    }

    #[test]
    fn set_by_name_checks_name_type_and_range() {
        let mut p = Params::default();
        assert_eq!(p.set("t_a", "120"), Ok(()));
        assert_eq!(p.t_a, 120);
        assert_eq!(p.set("nope", "1"), Err(ParamError::Unknown));
        assert_eq!(p.set("n", "x"), Err(ParamError::NotANumber { name: "n" }));
        assert!(matches!(
            p.set("n", "0"),
            Err(ParamError::OutOfRange { name: "n", .. })
        ));
        assert_eq!(
            p.set("w", "NaN"),
            Err(ParamError::OutOfRangeReal {
                name: "w",
                min: 0.0,
                max: 4.0
            })
        );
        let e = Params::default().set("w_s", "0").unwrap_err();
        assert_eq!(
            format!("{e}"),
            "parameter w_s must be a finite number in [0.001, 1000000000]"
        );
        // n * s may not exceed the correlator reach
        assert!(matches!(
            p.set("s", "3"),
            Err(ParamError::OutOfRange { name: "s", .. })
        ));
        // a refused value leaves the parameters unchanged
        assert_eq!(p.n, 3);
        assert_eq!(p.t_a, 120);
    }

    #[test]
    fn refusals_say_the_allowed_range() {
        let msg = |name: &str, v: &str| Params::default().set(name, v).unwrap_err().to_string();
        // whole numbers outside the type used to read as "not a number"
        assert_eq!(msg("t_a", "-5"), "parameter t_a must lie in 0..=4294967295");
        assert_eq!(msg("r_af", "100000"), "parameter r_af must lie in 1..=99");
        assert_eq!(msg("r_af", "-1"), "parameter r_af must lie in 1..=99");
        assert_eq!(
            msg("q_floor", "99999999999999999999999"),
            "parameter q_floor must lie in 0..=4294967295"
        );
        assert_eq!(msg("n", "x"), "parameter n must be a whole number in 1..=4");
        assert_eq!(
            msg("n", "2.5"),
            "parameter n must be a whole number in 1..=4"
        );
        assert_eq!(msg("n", "-"), "parameter n must be a whole number in 1..=4");
        assert_eq!(
            msg("c_d", "two"),
            "parameter c_d must be a finite number in [1, 16]"
        );
        assert_eq!(
            msg("c_d", "40"),
            "parameter c_d must be a finite number in [1, 16]"
        );
    }

    #[test]
    fn every_parameter_has_a_range_whose_ends_are_accepted() {
        assert_eq!(Params::NAMES.len(), Params::RANGES.len());
        for name in Params::NAMES {
            let (lo, hi) = match Params::range(name).unwrap() {
                Range::Int(lo, hi) => (format!("{lo}"), format!("{hi}")),
                Range::Real(lo, hi) => (format!("{lo}"), format!("{hi}")),
            };
            // s reaches its end only with n = 1 (n·s ≤ MAX_REACH)
            let mut p = Params::default();
            if name == "s" {
                p.n = 1;
            }
            let mut q = p;
            assert_eq!(p.set(name, &lo), Ok(()), "{name}={lo}");
            assert_eq!(q.set(name, &hi), Ok(()), "{name}={hi}");
        }
        assert_eq!(Params::range("nope"), None);
    }
}
