//! Escape finite-state machine (paper Sec. II-B, Fig. 2d) and the swarm variant (Sec. IV-D).
//!
//! [`Fsm::step`] runs once per camera frame (30 fps): it takes the frame's [`Visuomotor`]
//! signals and the current absolute heading estimate and returns the wheel speeds of a
//! differential drive. Headings follow the paper: degrees, wrapped to (−180°, 180°], positive =
//! turned right. The angles of [`Visuomotor`] are relative to the heading of the frame that
//! produced them, so every set-point is latched as `wrap(heading + θ)` when a state is entered
//! and then held in absolute terms while the robot turns.
//!
//! Escape behaviour (Sec. II-B):
//!
//! | state | input | next |
//! |---|---|---|
//! | any but ShortTakeoff | short mode (`θ_short` known) | ShortTakeoff, latch `sp¹`, `sp²` (Eqs. 14–15) |
//! | Wander | alert | LongTakeoff, latch `θ_long` (Eq. 13) |
//! | LongTakeoff | aligned or timeout | Escape holding the set-point |
//! | Escape (≥ min. duration) | alert | LongTakeoff, new `θ_long` |
//! | Escape (< min. duration) | obstacle close ahead (floor line) | saccade to `θ¹_short` |
//! | Escape (≥ min. duration) | `quiet` frames without alert | Wander |
//! | ShortTakeoff / Retreat | aligned with `sp¹` | ShortTakeoff / Turn |
//! | ShortTakeoff / Turn | aligned with `sp²` (or timeout) | Escape holding `sp²` |
//! | Wander (`wander_stop_frames`) | that many frames without alert | Stop (stands) |
//! | Stop | alert | LongTakeoff |
//!
//! With `FsmParams::short_from_long` (the authors' firmware) the short mode starts the γ path
//! only in a LongTakeoff: an alert in Wander or Stop starts a long takeoff first.
//!
//! Swarm behaviour (Sec. IV-D): Wander → Spin on alert or short mode (and, with the floor
//! line, on an obstacle close ahead); Spin → Wander once `spin_frames` frames have passed
//! without alert. It never escapes. With `FsmParams::look_every` (the default, not the
//! paper) the robot also stops to look for moving objects: Spin → Look, and Wander → Look
//! every `look_every` frames; Look → Wander towards a mover, or → Look 90° on (at most
//! `look_scans` times) when it saw none, or → Wander; a threat in Look spins.
//!
//! The parameters, [`FsmParams`] with its groups and presets, are declared in `fsm/params.rs`
//! and re-exported here.

use crate::model::closed_loop::movers::Sighting;
use crate::model::closed_loop::progress::{self, Progress};
use crate::model::visuomotor::{wrap_deg, Visuomotor};

mod params;
pub use params::{
    Blocked, Escape, FirmwareFsm, FsmParamError, FsmParams, Motion, Suppression, Swarm, Timing,
};

/// Swarm: the turn in place between two looks that saw nothing, degrees (the camera sees 70°).
pub const LOOK_TURN_DEG: f32 = 90.0;

/// Swarm: at most this many further looks after one that saw nothing (`FsmParams::look_scans`
/// is clamped to it): four looks 90° apart go round once; more would look where it has looked.
pub const MAX_LOOK_SCANS: u32 = 3;

/// Swarm: a look (the turn to its direction included) ends after this many frames without a
/// report from the look beside the network (one that never reports: `Params::look_change` 0):
/// 3 s, against 0.73 s for a look ([`crate::model::closed_loop::movers::SETTLE_FRAMES`] +
/// [`crate::model::closed_loop::movers::SPAN_FRAMES`] standing frames) and ≈ 0.5 s for the 90° turn before
/// it.
pub const LOOK_TIMEOUT_FRAMES: u32 = 90;

/// Motion state of the robot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    /// Forward at constant speed.
    Wander,
    /// Turning in place to `θ_long`.
    LongTakeoff,
    /// Straight away from the threat.
    Escape,
    /// The two-phase γ path of the short mode.
    ShortTakeoff,
    /// Swarm variant: spinning in place on an approaching object.
    Spin,
    /// Swarm variant: standing still to look for moving objects, or turning in place to the
    /// next direction to look in (`FsmParams::look_every`).
    Look,
    /// Standing still after `FsmParams::wander_stop_frames` frames of wandering without a
    /// threat, until one comes (the authors' firmware).
    Stop,
}

impl State {
    /// Every state, in declaration order.
    pub const ALL: [State; 7] = [
        State::Wander,
        State::LongTakeoff,
        State::Escape,
        State::ShortTakeoff,
        State::Spin,
        State::Look,
        State::Stop,
    ];

    /// Lower-case name used in JSON and telemetry.
    pub const fn name(self) -> &'static str {
        match self {
            State::Wander => "wander",
            State::LongTakeoff => "long_takeoff",
            State::Escape => "escape",
            State::ShortTakeoff => "short_takeoff",
            State::Spin => "spin",
            State::Look => "look",
            State::Stop => "stop",
        }
    }

    /// Inverse of [`State::name`].
    pub fn from_name(s: &str) -> Option<State> {
        State::ALL.into_iter().find(|st| st.name() == s)
    }
}

/// What the robot does about an approaching object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Behaviour {
    /// Collision avoidance, Sec. II-B: long/short takeoff, then escape.
    #[default]
    Escape,
    /// Sec. IV-D: spin in place on an approaching object instead of escaping.
    Swarm,
}

impl Behaviour {
    /// Its name in logs ("escape", "swarm").
    pub const fn name(self) -> &'static str {
        match self {
            Behaviour::Escape => "escape",
            Behaviour::Swarm => "swarm",
        }
    }
}

/// The two phases of the short-mode γ path (Sec. II-B).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShortPhase {
    /// Phase 1: reverse while turning until the heading is `θ¹` (90° off the threat).
    Retreat,
    /// Phase 2: forward while turning until the heading is `θ²` (180° opposite the threat).
    Turn,
}

/// One frame's output of the FSM.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorCommand {
    /// State after this frame's transition.
    pub state: State,
    /// Phase of the γ path, `Some` only in [`State::ShortTakeoff`].
    pub short_phase: Option<ShortPhase>,
    /// Absolute heading the controller steers to, degrees (in Spin: the heading at entry,
    /// which is not tracked).
    pub heading_setpoint_deg: f32,
    /// Left wheel speed, mm/s (positive = forward).
    pub left_mm_s: f32,
    /// Right wheel speed, mm/s (positive = forward).
    pub right_mm_s: f32,
}

impl MotorCommand {
    /// Both wheels are told to stand still: the efference copy of standing that the swarm's
    /// look waits for ([`crate::model::closed_loop::movers::Movers::step`]).
    pub fn stands(&self) -> bool {
        self.left_mm_s == 0.0 && self.right_mm_s == 0.0
    }
}

/// `x` limited to `±lim`; NaN `x` or a nonsensical `lim` give 0 / a zero limit, never a panic
/// (unlike `f32::clamp`).
fn limit(x: f32, lim: f32) -> f32 {
    let lim = if lim.is_finite() && lim > 0.0 {
        lim
    } else {
        0.0
    };
    if x.is_nan() {
        0.0
    } else if x > lim {
        lim
    } else if x < -lim {
        -lim
    } else {
        x
    }
}

/// Heading error `wrap(set-point − heading)`, degrees: the shortest turn, positive = turn right.
pub fn heading_error_deg(setpoint_deg: f32, heading_deg: f32) -> f32 {
    wrap_deg(setpoint_deg - heading_deg)
}

/// P heading controller: `ω = clamp(gain · error, ±max yaw rate)`, in rad/s, positive = right.
pub fn yaw_rate_rad_s(error_deg: f32, p: &FsmParams) -> f32 {
    limit(p.motion.heading_gain * error_deg, p.motion.max_yaw_deg_s).to_radians()
}

/// Differential-drive mixing: `left = v + ω·track/2`, `right = v − ω·track/2` (ω in rad/s,
/// positive = right turn), in mm/s. Each wheel stays within `max_wheel_mm_s`; the turn keeps
/// priority over the forward speed so that heading control survives saturation.
pub fn mix(v_mm_s: f32, omega_rad_s: f32, p: &FsmParams) -> (f32, f32) {
    let half_track = if p.motion.track_mm.is_finite() && p.motion.track_mm > 0.0 {
        p.motion.track_mm / 2.0
    } else {
        0.0
    };
    let max = limit(p.motion.max_wheel_mm_s, f32::MAX).abs();
    let turn = limit(omega_rad_s * half_track, max);
    let v = limit(v_mm_s, max - turn.abs());
    (v + turn, v - turn)
}

/// The escape FSM of Sec. II-B (or its swarm variant, Sec. IV-D).
#[derive(Debug, Clone)]
pub struct Fsm {
    params: FsmParams,
    behaviour: Behaviour,
    state: State,
    short_phase: Option<ShortPhase>,
    /// Set-point of the current state: Wander heading, `θ_long`, `sp¹`, or the escape heading.
    setpoint: f32,
    /// `sp²` of the γ path.
    setpoint2: f32,
    /// Wander has a heading to hold (false until the first valid frame).
    latched: bool,
    /// The current long takeoff is a saccade: an escape saccade (`FsmParams::escape_saccade`)
    /// or the turn away from an obstacle close ahead. Both turn in place.
    saccade: bool,
    /// `S` latched at the trigger, in [0, 1].
    strength: f32,
    /// The current takeoff started from standing on a field's response: its escape begins with
    /// the jump (`FsmParams::jump_frames`).
    jump: bool,
    /// Frames since entering the state (Spin: since the last alert; Look: since the last turn
    /// to a new direction).
    frames: u32,
    /// Looks left in the current scan (`FsmParams::look_scans`).
    scans: u32,
    /// Consecutive frames without alert (Escape).
    quiet: u32,
    /// |yaw rate| commanded on the previous frame, °/s (the efference copy).
    last_yaw_deg_s: f32,
    /// Frames of the settle period left after a fast turn.
    settle: u32,
    /// Consecutive unsuppressed frames with an alert.
    alert_run: u32,
    /// Forward speed commanded on the previous frame, mm/s (the efference copy).
    last_forward_mm_s: f32,
    /// The blocked-way test's period.
    progress: Progress,
}

impl Fsm {
    /// A new FSM in Wander; it latches its heading at the first [`Fsm::step`].
    pub fn new(params: FsmParams, behaviour: Behaviour) -> Self {
        Fsm {
            params,
            behaviour,
            state: State::Wander,
            short_phase: None,
            setpoint: 0.0,
            setpoint2: 0.0,
            latched: false,
            saccade: false,
            strength: 0.5,
            jump: false,
            frames: 0,
            scans: 0,
            quiet: 0,
            last_yaw_deg_s: 0.0,
            settle: 0,
            alert_run: 0,
            last_forward_mm_s: 0.0,
            progress: Progress::NEW,
        }
    }

    /// Current state.
    pub fn state(&self) -> State {
        self.state
    }

    /// Current phase of the γ path (`Some` only in ShortTakeoff).
    pub fn short_phase(&self) -> Option<ShortPhase> {
        self.short_phase
    }

    /// The parameters.
    pub fn params(&self) -> &FsmParams {
        &self.params
    }

    /// The behaviour.
    pub fn behaviour(&self) -> Behaviour {
        self.behaviour
    }

    /// One camera frame: transition on `vm`, then the wheel speeds that steer from
    /// `heading_deg` (absolute, wrapped, positive = right) toward the new state's set-point.
    ///
    /// A non-finite heading or non-finite `vm` field gives a stopped command and leaves the
    /// FSM untouched (the frame is skipped): a corrupt sensor must not move the robot.
    pub fn step(&mut self, vm: &Visuomotor, heading_deg: f32) -> MotorCommand {
        if !heading_deg.is_finite() || !vm_is_finite(vm) {
            self.last_yaw_deg_s = 0.0;
            return self.command(0.0, 0.0);
        }
        let h = wrap_deg(heading_deg);
        if !self.latched {
            self.enter_wander(h);
        }
        let ignored = self.suppressed();
        if self.last_yaw_deg_s > self.params.suppression.saccade_yaw_deg_s {
            self.settle = self.params.suppression.settle_frames;
        } else {
            self.settle = self.settle.saturating_sub(1);
        }
        self.alert_run = if vm.alert && !ignored {
            self.alert_run.saturating_add(1)
        } else {
            0
        };
        let acts = self.alert_run >= self.params.timing.alert_frames.max(1);
        let gated;
        let vm = if !acts {
            gated = Visuomotor {
                alert: false,
                short_mode: false,
                ..*vm
            };
            &gated
        } else {
            vm
        };
        if self.follows_strength(ignored) {
            self.latch_strength(vm);
        }
        let blocked = self.blocked(vm, h);
        match self.behaviour {
            // the way ahead is blocked: turn around, as from a threat dead ahead
            Behaviour::Escape if blocked && matches!(self.state, State::Wander | State::Escape) => {
                self.enter_turn(h, 180.0);
            }
            Behaviour::Escape => self.transition_escape(vm, h),
            Behaviour::Swarm => self.transition_swarm(vm, h),
        }
        self.output(h)
    }

    /// The blocked-way test ([`progress`]): every `blocked_frames` frames, whether the FSM
    /// commanded at least `blocked_travel_mm` forward with at most `blocked_yaw_deg` of turn
    /// since the last view compared, and the view barely changed.
    fn blocked(&mut self, vm: &Visuomotor, h: f32) -> bool {
        let p = self.params;
        let Some((view, level)) = vm.view.filter(|_| p.blocked.blocked_frames > 0) else {
            self.progress = Progress::NEW;
            return false;
        };
        let g = &mut self.progress;
        g.frames = g.frames.saturating_add(1);
        // efference copy: the travel this FSM commanded over the last frame (30 fps)
        g.travel_mm += self.last_forward_mm_s / 30.0;
        if g.snapshot.is_some() && g.frames < p.blocked.blocked_frames {
            return false;
        }
        let blocked = g.snapshot.is_some_and(|old| {
            g.travel_mm >= p.blocked.blocked_travel_mm
                && heading_error_deg(g.heading_deg, h).abs() <= p.blocked.blocked_yaw_deg
                && progress::change(&old, &view) < level
        });
        *g = Progress {
            snapshot: Some(view),
            frames: 0,
            travel_mm: 0.0,
            heading_deg: h,
        };
        blocked
    }

    /// The wheels did not carry out the last command (motors disabled, or the robot held):
    /// the efference copies of the next step, the forward travel of the blocked way and the
    /// yaw rate of the saccadic suppression, count what the wheels did, nothing. Without it a
    /// held robot's FSM "drives" 50 mm in 15 frames, sees its view unchanged and turns round.
    pub fn command_not_applied(&mut self) {
        self.last_forward_mm_s = 0.0;
        self.last_yaw_deg_s = 0.0;
    }

    /// Whether the next frame's perception will be ignored (the robot is turning fast, or
    /// settling after a fast turn).
    pub fn suppressed(&self) -> bool {
        self.last_yaw_deg_s > self.params.suppression.saccade_yaw_deg_s || self.settle > 0
    }

    /// Takes this frame's `S(t)` as the escape strength, clamped to [0, 1].
    fn latch_strength(&mut self, vm: &Visuomotor) {
        self.strength = limit(vm.strength, 1.0).max(0.0);
    }

    /// Whether this frame's `S(t)` replaces the latched strength (`FsmParams::live_strength`).
    fn follows_strength(&self, ignored: bool) -> bool {
        let live = self.params.escape.live_strength;
        !ignored
            && match self.state {
                State::Escape => live >= 1,
                State::ShortTakeoff => live >= 2,
                _ => false,
            }
    }

    fn enter_wander(&mut self, h: f32) {
        self.state = State::Wander;
        self.short_phase = None;
        self.setpoint = h;
        self.latched = true;
        self.frames = 0;
        self.quiet = 0;
    }

    fn enter_stop(&mut self, h: f32) {
        self.state = State::Stop;
        self.short_phase = None;
        self.setpoint = h;
        self.frames = 0;
        self.quiet = 0;
    }

    fn enter_long(&mut self, vm: &Visuomotor, h: f32) {
        // An alert without a bearing (not produced by `Visuomotor::from_fields`) is taken as a
        // threat dead ahead: turn around.
        self.enter_turn(h, vm.theta_long.unwrap_or(180.0));
        self.latch_strength(vm);
    }

    /// A long takeoff to `h + theta` (the escape strength stays as latched).
    fn enter_turn(&mut self, h: f32, theta: f32) {
        self.state = State::LongTakeoff;
        self.saccade = false;
        self.jump = false;
        self.short_phase = None;
        self.setpoint = wrap_deg(h + theta);
        self.frames = 0;
        self.quiet = 0;
    }

    /// A saccade to `h + theta`: a long takeoff that turns in place.
    fn enter_saccade(&mut self, h: f32, theta: f32) {
        self.enter_turn(h, theta);
        self.saccade = true;
    }

    fn enter_escape(&mut self, setpoint: f32) {
        self.state = State::Escape;
        self.short_phase = None;
        self.setpoint = setpoint;
        self.frames = 0;
        self.quiet = 0;
    }

    fn transition_escape(&mut self, vm: &Visuomotor, h: f32) {
        // `FsmParams::escape_saccade`: short mode during an escape, or during the saccade it
        // started, starts a (new) saccade to θ¹ instead of a γ path.
        let in_flight =
            self.state == State::Escape || (self.state == State::LongTakeoff && self.saccade);
        if vm.short_mode && in_flight && self.params.escape.escape_saccade {
            if let Some([t1, _]) = vm.theta_short {
                self.enter_saccade(h, t1);
                self.latch_strength(vm);
                return;
            }
        }
        // Short mode overrides every state (Sec. II-B) but does not re-latch an ongoing γ path:
        // θ_short is relative to the heading, so re-latching each frame while the robot turns
        // would move the set-points with it and the path would never end.
        // `FsmParams::short_from_long`: only a long takeoff turns into a short one
        let may_short = !self.params.firmware.short_from_long || self.state == State::LongTakeoff;
        if vm.short_mode && self.state != State::ShortTakeoff && may_short {
            if let Some([t1, t2]) = vm.theta_short {
                self.state = State::ShortTakeoff;
                self.jump = false;
                self.short_phase = Some(ShortPhase::Retreat);
                self.setpoint = wrap_deg(h + t1);
                self.setpoint2 = wrap_deg(h + t2);
                self.latch_strength(vm);
                self.frames = 0;
                self.quiet = 0;
                return;
            }
        }
        let p = self.params;
        let aligned = |sp: f32| heading_error_deg(sp, h).abs() <= p.motion.align_tol_deg;
        match self.state {
            // Spin and Look belong to the swarm behaviour; should one be current here, act as
            // Wander.
            State::Wander | State::Spin | State::Look | State::Stop => {
                if vm.alert {
                    // standing: the wheels did nothing on the last frame (efference copy)
                    let stood = self.last_forward_mm_s == 0.0 && self.last_yaw_deg_s == 0.0;
                    self.enter_long(vm, h);
                    self.jump = stood && vm.lplc2_sum > 0;
                } else if matches!(self.state, State::Spin | State::Look) {
                    self.enter_wander(h);
                } else if self.state == State::Wander {
                    // `FsmParams::wander_stop_frames`: a long quiet wander ends standing
                    self.frames = self.frames.saturating_add(1);
                    if p.firmware
                        .wander_stop_frames
                        .is_some_and(|n| self.frames > n)
                    {
                        self.enter_stop(h);
                    }
                }
            }
            State::LongTakeoff => {
                self.frames = self.frames.saturating_add(1);
                if aligned(self.setpoint) || self.frames >= p.timing.takeoff_timeout_frames {
                    self.enter_escape(self.setpoint);
                }
            }
            State::Escape => {
                self.frames = self.frames.saturating_add(1);
                self.quiet = if vm.alert {
                    0
                } else {
                    self.quiet.saturating_add(1)
                };
                // An obstacle close ahead (the floor line) is a distance, not a guess: it
                // cuts the escape's minimum short, or the robot runs blind into the wall. It
                // starts a saccade 90° away from the obstacle's side, not a takeoff: a turn
                // 180° from something ahead heads back towards what the robot flees. Saccades
                // may follow one another: in a corner that is how the robot finds the way out
                // (bounding them at 3 or 8 in a row cost 0.6–1.9 points of success).
                if self.frames < p.timing.min_escape_frames {
                    if let Some(t1) = vm.obstacle {
                        self.enter_saccade(h, t1);
                        return;
                    }
                }
                if self.frames >= p.timing.min_escape_frames {
                    if vm.alert {
                        self.enter_long(vm, h);
                    } else if self.quiet >= p.timing.quiet_frames {
                        self.enter_wander(h);
                    }
                }
            }
            State::ShortTakeoff => {
                self.frames = self.frames.saturating_add(1);
                if self.short_phase == Some(ShortPhase::Retreat) && aligned(self.setpoint) {
                    self.short_phase = Some(ShortPhase::Turn);
                }
                let done = self.short_phase == Some(ShortPhase::Turn) && aligned(self.setpoint2);
                // The timeout covers the whole γ path: either phase may be stuck.
                if done || self.frames >= p.timing.takeoff_timeout_frames {
                    self.enter_escape(self.setpoint2);
                }
            }
        }
    }

    fn transition_swarm(&mut self, vm: &Visuomotor, h: f32) {
        // an obstacle close ahead on the floor line approaches as surely as a looming field
        let threat = vm.alert || vm.short_mode || vm.obstacle.is_some();
        let p = self.params;
        match self.state {
            State::Spin => {
                // The spin lasts `spin_frames` after the last alert.
                self.frames = if threat {
                    0
                } else {
                    self.frames.saturating_add(1)
                };
                if self.frames >= p.swarm.spin_frames {
                    self.enter_look_or_wander(h);
                }
            }
            _ if threat => {
                self.state = State::Spin;
                self.short_phase = None;
                self.setpoint = h;
                self.frames = 0;
                self.quiet = 0;
            }
            State::Look => {
                self.frames = self.frames.saturating_add(1);
                match vm.sighting.map(Sighting::bearing_deg) {
                    // towards the mover
                    Some(Some(b)) => {
                        self.enter_wander(h);
                        self.setpoint = wrap_deg(h + b);
                    }
                    // nothing here: turn on and look again
                    // (from the last direction, not the heading: the turn stops within
                    // `align_tol_deg` of it, and four short turns would not go round)
                    Some(None) if self.scans > 0 => {
                        self.scans -= 1;
                        self.setpoint = wrap_deg(self.setpoint + LOOK_TURN_DEG);
                        self.frames = 0;
                    }
                    Some(None) => self.enter_wander(h),
                    // a look that never reports (`Params::look_change` 0) ends
                    None if self.frames >= LOOK_TIMEOUT_FRAMES => self.enter_wander(h),
                    None => {}
                }
            }
            State::Wander => {
                self.frames = self.frames.saturating_add(1);
                if p.swarm.look_every.is_some_and(|n| self.frames >= n.get()) {
                    self.enter_look(h);
                }
            }
            // Only Wander, Spin and Look occur in the swarm behaviour.
            _ => self.enter_wander(h),
        }
    }

    fn enter_look_or_wander(&mut self, h: f32) {
        if self.params.swarm.look_every.is_some() {
            self.enter_look(h);
        } else {
            self.enter_wander(h);
        }
    }

    fn enter_look(&mut self, h: f32) {
        self.state = State::Look;
        self.short_phase = None;
        self.setpoint = h;
        self.frames = 0;
        self.scans = self.params.swarm.look_scans.min(MAX_LOOK_SCANS);
    }

    /// Wheel speeds of the current state.
    fn output(&mut self, h: f32) -> MotorCommand {
        let p = &self.params;
        let s = self.strength;
        let (v, omega) = match self.state {
            State::Wander => (p.motion.cruise_mm_s, self.steer(self.setpoint, h)),
            // a saccade turns in place; a takeoff may drive while it turns
            State::LongTakeoff if self.saccade => (0.0, self.takeoff_turn(self.setpoint, h)),
            State::LongTakeoff => {
                let err = heading_error_deg(self.setpoint, h).to_radians();
                let v = p.escape.takeoff_drive * s * p.motion.max_escape_mm_s * libm::cosf(err);
                (v, self.takeoff_turn(self.setpoint, h))
            }
            State::Escape => {
                let jumping =
                    self.jump && p.escape.jump_frames.is_some_and(|n| self.frames < n.get());
                let s = if jumping { 1.0 } else { s };
                (s * p.motion.max_escape_mm_s, self.steer(self.setpoint, h))
            }
            State::ShortTakeoff => match self.short_phase {
                Some(ShortPhase::Turn) => (
                    s * p.motion.max_escape_mm_s,
                    self.gamma_yaw(self.setpoint2, h),
                ),
                // phase 1: reverse for at most `retreat_frames` (frames count from the entry)
                _ if self.frames >= p.timing.retreat_frames => {
                    (0.0, self.gamma_yaw(self.setpoint, h))
                }
                _ => (-s * p.motion.retreat_mm_s, self.gamma_yaw(self.setpoint, h)),
            },
            State::Spin => (0.0, p.swarm.spin_deg_s.to_radians()),
            // stand to look once facing the direction to look in
            State::Look if heading_error_deg(self.setpoint, h).abs() <= p.motion.align_tol_deg => {
                (0.0, 0.0)
            }
            State::Look => (0.0, self.steer(self.setpoint, h)),
            State::Stop => (0.0, 0.0),
        };
        let yaw = omega.to_degrees().abs();
        self.last_yaw_deg_s = if yaw.is_finite() { yaw } else { 0.0 };
        self.last_forward_mm_s = if v.is_finite() { v } else { 0.0 };
        let (l, r) = mix(v, omega, p);
        self.command(l, r)
    }

    fn steer(&self, setpoint: f32, h: f32) -> f32 {
        yaw_rate_rad_s(heading_error_deg(setpoint, h), &self.params)
    }

    /// The yaw rate of the γ path's turns, rad/s: the heading controller's ([`Fsm::steer`]), or
    /// with `FsmParams::gamma_turn` the takeoff's gain under the same limit, so the retreat
    /// keeps its speed.
    fn gamma_yaw(&self, setpoint: f32, h: f32) -> f32 {
        let p = &self.params;
        if !p.escape.gamma_turn {
            return self.steer(setpoint, h);
        }
        let yaw = p.escape.takeoff_gain * p.motion.heading_gain * heading_error_deg(setpoint, h);
        limit(yaw, p.motion.max_yaw_deg_s).to_radians()
    }

    /// The yaw rate of an escape's turn (`FsmParams::takeoff_gain`, `takeoff_yaw_deg_s`), rad/s.
    fn takeoff_turn(&self, setpoint: f32, h: f32) -> f32 {
        let p = &self.params;
        let yaw = p.escape.takeoff_gain * p.motion.heading_gain * heading_error_deg(setpoint, h);
        // an unbounded limit leaves the turn to the wheels' (`mix`)
        let yaw = if p.escape.takeoff_yaw_deg_s == f32::INFINITY && !yaw.is_nan() {
            yaw
        } else {
            limit(yaw, p.escape.takeoff_yaw_deg_s)
        };
        yaw.to_radians()
    }

    fn command(&self, left: f32, right: f32) -> MotorCommand {
        let finite = left.is_finite() && right.is_finite();
        MotorCommand {
            state: self.state,
            short_phase: self.short_phase,
            heading_setpoint_deg: match (self.state, self.short_phase) {
                (State::ShortTakeoff, Some(ShortPhase::Turn)) => self.setpoint2,
                _ => self.setpoint,
            },
            left_mm_s: if finite { left } else { 0.0 },
            right_mm_s: if finite { right } else { 0.0 },
        }
    }
}

fn vm_is_finite(vm: &Visuomotor) -> bool {
    vm.strength.is_finite()
        && vm.threat_x.is_none_or(f32::is_finite)
        && vm.theta_long.is_none_or(f32::is_finite)
        && vm
            .theta_short
            .is_none_or(|t| t.iter().all(|a| a.is_finite()))
}

/// A source of the absolute heading for [`Fsm::step`]: odometry on the host, a gyro or wheel
/// encoders on the robot.
pub trait HeadingEstimator {
    /// Advances the estimate by one period of `dt_s` seconds during which the wheels were
    /// commanded to `left_mm_s`, `right_mm_s`; returns the new heading (degrees, wrapped).
    fn update(&mut self, left_mm_s: f32, right_mm_s: f32, dt_s: f32) -> f32;
    /// Current heading, degrees, wrapped to (−180°, 180°], positive = turned right.
    fn heading_deg(&self) -> f32;
}

/// Dead reckoning of the heading from the commanded wheel speeds: `dθ = (left − right)/track ·
/// dt` (radians). Good enough for the simulator and as a fallback; it cannot see wheel slip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Odometry {
    track_mm: f32,
    heading_deg: f32,
}

impl Odometry {
    /// Starts at `heading_deg` (wrapped) with the wheel track `track_mm`.
    pub fn new(track_mm: f32, heading_deg: f32) -> Self {
        Odometry {
            track_mm,
            heading_deg: wrap_deg(heading_deg),
        }
    }
}

impl HeadingEstimator for Odometry {
    /// Non-finite speeds, a non-positive `dt_s` or track leave the heading unchanged.
    fn update(&mut self, left_mm_s: f32, right_mm_s: f32, dt_s: f32) -> f32 {
        let d_rad = (left_mm_s - right_mm_s) / self.track_mm * dt_s;
        if self.track_mm > 0.0 && dt_s > 0.0 && d_rad.is_finite() {
            self.heading_deg = wrap_deg(self.heading_deg + d_rad.to_degrees());
        }
        self.heading_deg
    }

    fn heading_deg(&self) -> f32 {
        self.heading_deg
    }
}

#[cfg(test)]
mod tests;
