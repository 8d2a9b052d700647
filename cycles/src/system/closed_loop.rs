//! The firmware in the arena's loop: a host [`Controller`] whose brain is the release firmware
//! on the virtual board. Each arena frame becomes the camera's next frame; the board runs one
//! frame period; the motor frames that left UART4 meanwhile, decoded by the bottom board's
//! register model (`tasks::robot::motor::BoardModel`), set the wheel speeds. The board runs on
//! its own thread (the emulator is not `Send`); the controller talks to it over channels. A
//! robot held by the experiment ([`Controller::command_not_applied`]) is held on the board too:
//! `h` typed on the firmware's RTT control channel, `g` when it is let go. The experiment
//! decides about a frame after the board ran it, so each is typed one frame late: the board is
//! held from its second frame (it is still priming then, motors off) and let go one frame
//! after the host's robot would be.

use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Mutex};

use alvs_sim::{Command, Controller, Seen};
use alvs_tasks::model::fsm::State;
use alvs_tasks::robot::motor::{self, BoardModel};
use alvs_tasks::robot::telemetry::Record;
use alvs_tasks::Frame;

use super::board::{Board, Config};

/// The bottom board at the end of UART4: it gathers the bytes into frames and applies each
/// complete one to its motor registers. A malformed frame changes nothing, as on the board.
#[derive(Debug, Default)]
pub struct BottomBoard {
    registers: BoardModel,
    pending: Vec<u8>,
}

impl BottomBoard {
    /// Takes bytes as they arrive; a frame ends with [`motor::END`].
    pub fn hear(&mut self, bytes: impl IntoIterator<Item = u8>) {
        for b in bytes {
            self.pending.push(b);
            if b == motor::END {
                let _ = self.registers.apply(&self.pending);
                self.pending.clear();
            }
        }
    }

    /// The motor registers as the frames heard so far left them.
    pub fn registers(&self) -> &BoardModel {
        &self.registers
    }
}

/// What the board did in one frame period.
#[derive(Clone, Copy, Debug)]
struct Step {
    left_mm_s: f32,
    right_mm_s: f32,
    /// The FSM state, `ΣLPLC2` and `X̄` of the last telemetry record.
    state: State,
    sum: u32,
    threat_x: Option<f32>,
}

/// A camera frame for the board, and a hold to type first (`Some(true)`: `h`, `Some(false)`:
/// `g`).
type Input = (Frame, Option<bool>);

/// A robot driven by the firmware on a virtual board.
pub struct FirmwareRobot {
    frames: Sender<Input>,
    steps: Receiver<Step>,
    last: Step,
    error: Arc<Mutex<Option<String>>>,
    /// The experiment held the robot over the last frame.
    held: bool,
    /// What the board was last told (held or not).
    told_held: bool,
}

/// Cycles the board runs before the first arena frame: boot, self-benchmark, camera set-up.
pub const BOOT_CYCLES: u64 = 90_000_000;

impl FirmwareRobot {
    /// Returns the controller of the firmware `elf`, with a handle on the board's error, if it
    /// fails. The board boots at the first frame (for [`BOOT_CYCLES`], looking at that frame).
    pub fn new(elf: Vec<u8>, config: Config) -> (FirmwareRobot, Arc<Mutex<Option<String>>>) {
        let (frames_tx, frames_rx) = channel::<Input>();
        let (steps_tx, steps_rx) = channel::<Step>();
        let error = Arc::new(Mutex::new(None));
        let fail = Arc::clone(&error);
        std::thread::spawn(move || {
            if let Err(e) = serve(&elf, config, &frames_rx, &steps_tx) {
                *fail.lock().unwrap_or_else(|p| p.into_inner()) = Some(e);
            }
        });
        let robot = FirmwareRobot {
            frames: frames_tx,
            steps: steps_rx,
            last: Step {
                left_mm_s: 0.0,
                right_mm_s: 0.0,
                state: State::Wander,
                sum: 0,
                threat_x: None,
            },
            error: Arc::clone(&error),
            held: false,
            told_held: false,
        };
        (robot, error)
    }
}

fn serve(
    elf: &[u8],
    config: Config,
    frames: &Receiver<Input>,
    steps: &Sender<Step>,
) -> Result<(), String> {
    let period = config.camera.frame_cycles;
    // the robot boots looking at its first view, as a real one does (a grey card taken away
    // at the first frame would be a whole-scene onset the trial is not about)
    // the first frame carries no hold: the experiment has not seen the board yet
    let Ok((first, _)) = frames.recv() else {
        return Ok(());
    };
    let slot = Arc::new(Mutex::new(first.to_vec()));
    let camera = Arc::clone(&slot);
    let source = Box::new(move |_| camera.lock().map(|f| f.clone()).unwrap_or_default());
    let mut board = Board::new(elf, config, source).map_err(|e| e.to_string())?;
    board.run_for(BOOT_CYCLES).map_err(|e| e.to_string())?;
    let mut wheels = BottomBoard::default();
    // the bottom board hears everything from power-on (the enable sequence comes at priming)
    let (mut bytes_seen, mut text_seen) = (0, board.rtt(1).len());
    let mut seen = (State::Wander, 0, None);
    for (frame, hold) in core::iter::once((first, None)).chain(frames.iter()) {
        if let Some(on) = hold {
            board.rtt_type(if on { b"h" } else { b"g" });
        }
        if let Ok(mut s) = slot.lock() {
            s.copy_from_slice(&frame);
        }
        board.run_for(period).map_err(|e| e.to_string())?;
        wheels.hear(board.uart_sent()[bytes_seen..].iter().map(|&(_, b)| b));
        bytes_seen = board.uart_sent().len();
        let text = &board.rtt(1)[text_seen..];
        if let Some(line) = text.lines().rfind(|l| l.starts_with("F ")) {
            if let Ok(r) = Record::parse_line(line) {
                seen = (r.state, r.lplc2_sum, r.threat_x());
            }
        }
        text_seen = board.rtt(1).len();
        let (l, r) = wheels.registers().wheel_powers();
        let step = Step {
            left_mm_s: f32::from(l) / motor::POWER_PER_MM_S,
            right_mm_s: f32::from(r) / motor::POWER_PER_MM_S,
            state: seen.0,
            sum: seen.1,
            threat_x: seen.2,
        };
        if steps.send(step).is_err() {
            break;
        }
    }
    Ok(())
}

impl Controller for FirmwareRobot {
    fn name(&self) -> &'static str {
        "firmware"
    }

    fn command_not_applied(&mut self) {
        self.held = true;
    }

    fn step(&mut self, frame: &Frame, _heading_deg: f32) -> Command {
        let failed = self.error.lock().map_or(true, |e| e.is_some());
        let hold = (self.held != self.told_held).then_some(self.held);
        self.told_held = self.held;
        self.held = false;
        if !failed && self.frames.send((*frame, hold)).is_ok() {
            if let Ok(step) = self.steps.recv() {
                self.last = step;
            }
        } else {
            // the board stopped: so do the wheels
            self.last.left_mm_s = 0.0;
            self.last.right_mm_s = 0.0;
        }
        let state = self.last.state;
        Command {
            left_mm_s: self.last.left_mm_s,
            right_mm_s: self.last.right_mm_s,
            state: state.name(),
            // the firmware's FSM leaves wander on an alert
            alert: state != State::Wander,
            seen: Seen {
                response: self.last.sum,
                threat_x: self.last.threat_x,
                fields: 0,
                short_mode: false,
            },
        }
    }
}

/// The outcome of [`evasion_trial`].
pub struct Evasion {
    pub result: alvs_sim::encounter::EncounterResult,
    /// Turned away from the obstacle (for one dead ahead: by at least 90° either way), the
    /// criterion of `cargo alvs evasion`.
    pub correct_side: bool,
    /// The board's error, if it stopped.
    pub error: Option<String>,
}

/// The evasion trial of `cargo alvs evasion --world lab` (obstacle from `bearing_deg` at 500
/// mm, 100 mm/s, realistic motors and camera) with the firmware as the tested robot's brain.
pub fn evasion_trial(
    elf: Vec<u8>,
    config: Config,
    bearing_deg: f64,
    texture: alvs_sim::WallTexture,
    seed: u64,
) -> Evasion {
    use alvs_sim::encounter::{
        self, Encounter, Side, Threat, DEFAULT_DISTANCE_MM, DEFAULT_SPEED_MM_S,
    };
    let (robot, error) = FirmwareRobot::new(elf, config);
    let e = Encounter {
        kind: alvs_sim::Kind::Alvs,
        threats: vec![Threat {
            bearing_deg,
            distance_mm: DEFAULT_DISTANCE_MM,
            speed_mm_s: DEFAULT_SPEED_MM_S,
        }],
        seed,
        params: alvs_tasks::Params::ALVS,
        fsm: alvs_tasks::model::fsm::FsmParams::default(),
        // the lab as `cargo alvs evasion --world lab` stages it (its designed start)
        world: alvs_sim::World::with_texture(texture),
        start: encounter::tested_start(),
        noise: true,
        exposure: 0.0,
        gain: alvs_sim::GainModel::default(),
        trace: false,
    };
    let result = encounter::run_with(&e, Box::new(robot), &|_| {});
    let correct_side = match Side::away_from(bearing_deg) {
        Side::None => result.escape_turn_deg.abs() >= 90.0,
        away => away == result.side(),
    };
    let error = error.lock().map_or(None, |e| e.clone());
    Evasion {
        result,
        correct_side,
        error,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes(frames: &motor::MotorFrames) -> Vec<u8> {
        frames.iter().flatten().copied().collect()
    }

    #[test]
    fn the_bottom_board_applies_frames_split_anywhere_and_skips_malformed_ones() {
        let wheels = bytes(&motor::wheel_frames(100.0, -50.0));
        let mut expected = BoardModel::new();
        expected.apply_all(&motor::enable_sequence()).unwrap();
        expected
            .apply_all(&motor::wheel_frames(100.0, -50.0))
            .unwrap();
        let mut board = BottomBoard::default();
        board.hear(bytes(&motor::enable_sequence()));
        // a malformed frame between two good ones, then frames cut across two reads
        board.hear([0x00, 0x42, motor::END]);
        let cut = wheels.len() - 3;
        board.hear(wheels[..cut].iter().copied());
        assert_eq!(
            board.registers().wheel_powers(),
            (0, 0),
            "the cut frame waits"
        );
        board.hear(wheels[cut..].iter().copied());
        assert!(board.registers().enabled());
        assert_eq!(board.registers().wheel_powers(), expected.wheel_powers());
        assert_ne!(expected.wheel_powers(), (0, 0));
    }
}
