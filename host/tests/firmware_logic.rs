//! The firmware's task chain on the host, end to end: YUV422 frames of a synthetic looming
//! scene → line-by-line luminance extraction streamed into the aLPLC2 `Network` under the
//! capture policy → the rest of the step at frame complete → `Control` (escape `Fsm` with
//! `Odometry`) under the safety policy → motor frames, decoded back by a model of the bottom
//! board. Only the register accesses are missing.
//!
//! Checks: stopped while the model primes, wander at cruise power, on an alert the wheel
//! powers turn away from the threat, and a camera stall (no frame for 150 ms) sends stop
//! frames, the network primes again when frames return.

use alvs_host::scenes::{demo_scenes, Scene};
use alvs_tasks::model::fsm::{Behaviour, FsmParams, HeadingEstimator, State};
use alvs_tasks::robot::camera::{
    self, Capture, FrameEnd, BYTES_PER_PIXEL, FRAME_BYTES, LINE_BYTES,
};
use alvs_tasks::robot::control::Control;
use alvs_tasks::robot::health::{Decision, Fault, Safety, SummaryWindow, PRIME_FRAMES, STALL_MS};
use alvs_tasks::robot::motor::{self, BoardModel, Head, MotorFrames};
use alvs_tasks::{Frame, Network, Perception, PIXELS, WIDTH};

/// Camera frame period, ms (30 fps, rounded down).
const FRAME_MS: u32 = 33;
/// Still frames before the scene starts: priming, then wander.
const LEAD: usize = 10;
/// Period of the safety tick while no frame arrives, ms.
const TICK_MS: u32 = 10;

/// Y frame → YUV422 in the sensor's byte order: luminance at `Y_OFFSET` of each pixel, the
/// chroma bytes alternating U = 0x70, V = 0x90 (so that reading the wrong byte shows).
fn to_yuv422(y: &Frame) -> Vec<u8> {
    let mut out = vec![0u8; FRAME_BYTES];
    for (i, px) in out.chunks_exact_mut(BYTES_PER_PIXEL).enumerate() {
        px[camera::Y_OFFSET] = y[i];
        px[1 - camera::Y_OFFSET] = if i % 2 == 0 { 0x70 } else { 0x90 };
    }
    out
}

/// What the motor side did in one period.
#[derive(Debug, Clone, Copy)]
struct Step {
    state: State,
    decision: Decision,
    /// Wheel powers the board applies after this period's frames.
    powers: (i16, i16),
    /// Odometry heading after this period, degrees (positive = turned right).
    heading: f32,
}

/// The firmware's tasks and the bottom board, on the host.
struct Robot {
    now: u32,
    capture: Capture,
    network: Network,
    /// Whether the network is parked (free for the camera) rather than perception's.
    parked: bool,
    /// The supervisor asked for a fresh start of the model (after a fault).
    reset_requested: bool,
    control: Control,
    safety: Safety,
    summary: SummaryWindow,
    board: BoardModel,
    state: State,
}

impl Robot {
    fn new() -> Self {
        Robot {
            now: 0,
            capture: Capture::new(),
            network: Network::alvs(),
            parked: true,
            reset_requested: false,
            control: Control::new(FsmParams::default(), Behaviour::Escape),
            safety: Safety::new(),
            summary: SummaryWindow::new(),
            board: BoardModel::new(),
            state: State::Wander,
        }
    }

    /// DCMI and DMA interrupts: one YUV422 frame, line by line, streamed into the network.
    fn camera_frame(&mut self, yuv: &[u8]) -> FrameEnd {
        let start = self.capture.frame_start(self.parked);
        assert!(!start.cut_short);
        if start.accepted && std::mem::take(&mut self.reset_requested) {
            self.network.reset();
        }
        for line in yuv.chunks_exact(LINE_BYTES) {
            if let Some(_row) = self.capture.line() {
                let mut y = [0u8; WIDTH];
                camera::luma_line(line, &mut y).unwrap();
                self.network.push_row(&y).unwrap();
            }
        }
        let end = self.capture.frame_complete();
        match end {
            FrameEnd::Deliver { .. } => self.parked = false,
            FrameEnd::Invalid(_) => self.network.abort_frame(),
            FrameEnd::Dropped { .. } => {}
        }
        end
    }

    /// Perception: the rest of the step, then the network is parked again.
    fn perceive(&mut self) -> Perception {
        let p = self
            .network
            .end_frame()
            .expect("a delivered frame is whole");
        self.parked = true;
        self.summary.record_frame(1_500_000);
        self.safety.frame(self.now);
        p
    }

    fn send(&mut self, frames: &MotorFrames) {
        for f in frames {
            let d = motor::decode(f).expect("the motor task sends well-formed frames");
            assert_eq!(d.head, Head::Write);
            self.board.apply(f).unwrap();
        }
    }

    /// Motor control at frame rate: the safety decision, the FSM, frames to the board.
    fn motor_control(&mut self, p: &Perception) -> Step {
        let decision = self.safety.tick(self.now);
        let (c, frames) = self.control.step(&p.vm, decision.motors_enabled);
        self.state = c.state;
        self.send(&frames);
        self.step(decision)
    }

    /// Supervisor tick between frames: faults stop the motors and ask the model to restart.
    fn supervise(&mut self) -> Step {
        let decision = self.safety.tick(self.now);
        if decision.fault.is_some() {
            self.reset_requested = true;
        }
        if !decision.motors_enabled && self.control.motors_enabled() {
            let frames = self.control.stop();
            self.send(&frames);
        }
        self.step(decision)
    }

    fn step(&self, decision: Decision) -> Step {
        Step {
            state: self.state,
            decision,
            powers: self.board.wheel_powers(),
            heading: self.control.heading().heading_deg(),
        }
    }

    /// One camera frame period.
    fn frame(&mut self, y: &Frame) -> Step {
        self.now = self.now.wrapping_add(FRAME_MS);
        assert!(matches!(
            self.camera_frame(&to_yuv422(y)),
            FrameEnd::Deliver { .. }
        ));
        let p = self.perceive();
        self.motor_control(&p)
    }

    /// `ms` without frames, the supervisor ticking every `TICK_MS`.
    fn stall(&mut self, ms: u32) -> Vec<Step> {
        (0..ms / TICK_MS)
            .map(|_| {
                self.now = self.now.wrapping_add(TICK_MS);
                self.supervise()
            })
            .collect()
    }
}

fn scene(name: &str) -> Scene {
    demo_scenes()
        .into_iter()
        .find(|s| s.name == name)
        .expect("demo scene")
}

/// Runs `LEAD` still frames then the scene; returns every step.
fn run(robot: &mut Robot, s: &Scene) -> Vec<Step> {
    let still = s.render(0);
    let mut steps: Vec<Step> = (0..LEAD).map(|_| robot.frame(&still)).collect();
    steps.extend((0..s.frames).map(|t| robot.frame(&s.render(t))));
    steps
}

#[test]
fn yuv_encoding_inverts_the_extraction() {
    let y = scene("approach_centre").render(20);
    let mut back = [0u8; PIXELS];
    camera::luma_frame(&to_yuv422(&y), &mut back).unwrap();
    assert_eq!(back, y);
}

/// Stopped while priming, cruising while nothing looms, then on the first alert the wheels
/// turn the robot away from a threat on the `right` side (or left).
fn escapes_away(name: &str, threat_on_right: bool) {
    let mut robot = Robot::new();
    let steps = run(&mut robot, &scene(name));
    let cruise = motor::power(FsmParams::default().motion.cruise_mm_s);
    assert_eq!(cruise, 250);

    let primed = PRIME_FRAMES as usize;
    for (i, s) in steps[..primed - 1].iter().enumerate() {
        assert!(
            !s.decision.motors_enabled,
            "{name}: frame {i} moves while priming"
        );
        assert_eq!(s.powers, (0, 0), "{name}: frame {i}");
    }
    let first_alert = steps
        .iter()
        .position(|s| s.state != State::Wander)
        .expect("the looming square triggers an escape");
    println!(
        "{name}: first non-wander frame {first_alert} ({:?})",
        steps[first_alert].state
    );
    assert!(first_alert > LEAD, "{name}: alert on still frames");
    for (i, s) in steps[primed - 1..first_alert].iter().enumerate() {
        assert!(
            s.decision.motors_enabled,
            "{name}: frame {}",
            i + primed - 1
        );
        assert_eq!(
            s.powers,
            (cruise, cruise),
            "{name}: frame {}",
            i + primed - 1
        );
    }
    // the takeoff turns away from the threat, in place (long mode) or reversing (short
    // mode): the wheel on the threat's side is the faster one, and the heading moves away
    let away = |(l, r): (i16, i16)| if threat_on_right { l < r } else { l > r };
    let takeoff = &steps[first_alert..first_alert + 5];
    let mut heading = steps[first_alert - 1].heading;
    for s in takeoff {
        println!(
            "  {:?} powers {:?} heading {:.1}°",
            s.state, s.powers, s.heading
        );
        assert!(s.decision.motors_enabled);
        assert!(
            away(s.powers),
            "{name}: {:?} turns towards the threat",
            s.powers
        );
        let turn = s.heading - heading;
        assert!(
            if threat_on_right {
                turn < -1.0
            } else {
                turn > 1.0
            },
            "{name}: turn {turn}"
        );
        heading = s.heading;
    }
    assert!(
        if threat_on_right {
            heading < -30.0
        } else {
            heading > 30.0
        },
        "{name}: heading {heading}"
    );

    let summary = robot.summary.close(robot.capture.counters(), 0);
    assert_eq!(summary.processed as usize, steps.len());
    assert_eq!((summary.frames as usize, summary.dropped), (steps.len(), 0));
}

#[test]
fn a_threat_on_the_right_turns_the_robot_left() {
    escapes_away("approach_right", true);
}

#[test]
fn a_threat_on_the_left_turns_the_robot_right() {
    escapes_away("approach_left", false);
}

#[test]
fn a_camera_stall_sends_stop_frames() {
    let mut robot = Robot::new();
    let still = scene("recede").render(0);
    for _ in 0..LEAD {
        robot.frame(&still);
    }
    assert_eq!(robot.board.wheel_powers(), (250, 250));
    let steps = robot.stall(150);
    for (i, s) in steps.iter().enumerate() {
        let ms = (i as u32 + 1) * TICK_MS;
        if ms < STALL_MS {
            assert!(s.decision.motors_enabled, "{ms} ms");
            assert_eq!(s.powers, (250, 250));
        } else {
            assert_eq!(s.decision.fault, Some(Fault::CameraStall), "{ms} ms");
            assert!(!s.decision.motors_enabled && !s.decision.feed_watchdog);
            assert_eq!(s.powers, (0, 0), "{ms} ms");
            assert!(!robot.board.enabled());
        }
    }
    // the bytes of one stalled period: zero powers, then the motor drivers off
    let frames = robot.control.stop();
    let decoded: Vec<_> = frames.iter().map(|f| motor::decode(f).unwrap()).collect();
    assert_eq!(decoded[0].address, motor::REG_POWER_LEFT);
    assert_eq!(decoded[0].data.as_slice(), &[0, 0, 0, 0]);
    assert_eq!(decoded[1].address, motor::REG_CONTROL);
    assert_eq!(decoded[1].data.as_slice(), &[motor::CONTROL_DISABLE]);

    // frames return: stopped while the model primes again, then cruising
    let after: Vec<Step> = (0..LEAD).map(|_| robot.frame(&still)).collect();
    assert!(after[..PRIME_FRAMES as usize - 1]
        .iter()
        .all(|s| s.powers == (0, 0) && s.decision.fault.is_none()));
    assert_eq!(after[LEAD - 1].powers, (250, 250));
}
