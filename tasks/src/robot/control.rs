//! The motor-control task's body: the escape FSM once per frame, steered by a heading estimate,
//! and the UART frames that set the bottom board's wheel powers.
//!
//! The heading estimate is behind [`HeadingEstimator`]: [`Odometry`] from the commanded wheel
//! speeds by default (what the firmware has until the IMU is wired), a simulated gyro in the
//! arena. It advances with what the wheels were *allowed* to do: nothing while the safety
//! policy holds the motors.

use crate::frame::Frame;
use crate::model::closed_loop::movers::Movers;
use crate::model::fsm::{Behaviour, Fsm, FsmParams, HeadingEstimator, MotorCommand, Odometry};
use crate::model::visuomotor::{wrap_deg, Visuomotor};
use crate::robot::motor::{MotorFrames, MotorOutput};

/// Camera frame period, seconds (30 fps): the period of [`Control::step`].
pub const FRAME_PERIOD_S: f32 = 1.0 / 30.0;

/// FSM, heading estimate and motor output of one robot.
#[derive(Debug, Clone)]
pub struct Control<H = Odometry> {
    fsm: Fsm,
    heading: H,
    motors: MotorOutput,
    /// How far the heading estimate turned in the last step, degrees: the efference copy the
    /// network takes before the next frame (`Network::turned`).
    turn_deg: f32,
    /// The forward speed the wheels were given in the last step, mm/s: the efference copy of
    /// forward motion (`Network::driving`).
    forward_mm_s: f32,
    /// The FSM commanded standing still for this frame (the swarm's look's input).
    standing: bool,
}

impl Control<Odometry> {
    /// Odometry over the FSM's wheel track, starting at heading 0.
    pub fn new(params: FsmParams, behaviour: Behaviour) -> Self {
        let heading = Odometry::new(params.motion.track_mm, 0.0);
        Control::with_heading(Fsm::new(params, behaviour), heading)
    }
}

impl<H: HeadingEstimator> Control<H> {
    /// Any FSM and heading estimate; the motors start disabled.
    pub fn with_heading(fsm: Fsm, heading: H) -> Self {
        Control {
            fsm,
            heading,
            motors: MotorOutput::new(),
            turn_deg: 0.0,
            forward_mm_s: 0.0,
            standing: false,
        }
    }

    /// Switches the behaviour (escape or the swarm's spin): a fresh FSM with the same
    /// parameters, in Wander; the heading estimate and the motors' state carry on. (The
    /// swarm's look starts over by itself: it restarts whenever the robot was not standing.)
    pub fn set_behaviour(&mut self, behaviour: Behaviour) {
        self.fsm = Fsm::new(*self.fsm.params(), behaviour);
        self.standing = false;
    }

    /// [`Control::step`] with the frame perception just processed (`Network::frame`): in
    /// [`Behaviour::Swarm`] the look at other robots (`movers`, kept by the caller: 2.6 KB
    /// that escape never needs) runs on it first, with `look_change` (`Params::look_change`),
    /// as the simulator's swarm robot does; in escape, or without a look, it does not run.
    pub fn step_seeing(
        &mut self,
        vm: &Visuomotor,
        look: Option<(&mut Movers, &Frame, u8)>,
        enable: bool,
    ) -> (MotorCommand, MotorFrames) {
        let mut vm = *vm;
        if let Some((movers, frame, look_change)) = look {
            if self.fsm.behaviour() == Behaviour::Swarm {
                vm.sighting = movers.step(frame, self.standing, look_change);
            }
        }
        let (c, frames) = self.step(&vm, enable);
        self.standing = c.stands();
        (c, frames)
    }

    /// One frame: the FSM's transition on `vm` and its wheel speeds, and the frames to send.
    /// With `enable` false (priming, a fault) the frames stop the motors and the heading
    /// estimate sees still wheels; the FSM still runs, so it is current when motion resumes,
    /// and is told its command was not carried out (`Fsm::command_not_applied`): a robot
    /// whose motors are off has not driven into anything.
    pub fn step(&mut self, vm: &Visuomotor, enable: bool) -> (MotorCommand, MotorFrames) {
        let c = self.fsm.step(vm, self.heading.heading_deg());
        let frames = self.motors.update(enable, c.left_mm_s, c.right_mm_s);
        let (l, r) = if enable {
            (c.left_mm_s, c.right_mm_s)
        } else {
            self.fsm.command_not_applied();
            (0.0, 0.0)
        };
        let before = self.heading.heading_deg();
        self.heading.update(l, r, FRAME_PERIOD_S);
        self.turn_deg = wrap_deg(self.heading.heading_deg() - before);
        self.forward_mm_s = (l + r) / 2.0;
        (c, frames)
    }

    /// The frames that stop the motors now (a fault between frames). The robot no longer
    /// drives: [`Control::last_forward_mm_s`] reads 0 from here on (a network parked before
    /// the stop hears it after the next frame's control step).
    pub fn stop(&mut self) -> MotorFrames {
        self.forward_mm_s = 0.0;
        self.motors.update(false, 0.0, 0.0)
    }

    /// How far the robot turned in the last step by its heading estimate, degrees (positive =
    /// right): what the network is told before the next frame ([`crate::Network::turned`]).
    pub fn last_turn_deg(&self) -> f32 {
        self.turn_deg
    }

    /// The forward speed the wheels were given in the last step, mm/s (0 while the motors
    /// are off): what the network is told before the next frame ([`crate::Network::driving`]).
    pub fn last_forward_mm_s(&self) -> f32 {
        self.forward_mm_s
    }

    /// The FSM.
    pub fn fsm(&self) -> &Fsm {
        &self.fsm
    }

    /// The heading estimate.
    pub fn heading(&self) -> &H {
        &self.heading
    }

    /// Whether the motors were last left enabled.
    pub fn motors_enabled(&self) -> bool {
        self.motors.enabled()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::fsm::State;
    use crate::robot::motor::{BoardModel, POWER_PER_MM_S};

    fn quiet() -> Visuomotor {
        Visuomotor::from_fields(core::iter::empty(), &crate::Params::PAPER)
    }

    #[test]
    fn wanders_at_cruise_power_once_enabled_and_stops_when_disabled() {
        let mut c = Control::new(FsmParams::default(), Behaviour::Escape);
        let mut board = BoardModel::new();
        let (cmd, frames) = c.step(&quiet(), false);
        board.apply_all(&frames).unwrap();
        assert_eq!(cmd.state, State::Wander);
        assert!(!board.enabled() && board.powers() == (0, 0));
        let (_, frames) = c.step(&quiet(), true);
        board.apply_all(&frames).unwrap();
        let cruise = (100.0 * POWER_PER_MM_S) as i16;
        assert!(board.enabled());
        assert_eq!(board.wheel_powers(), (cruise, cruise));
        assert_eq!(c.heading().heading_deg(), 0.0, "straight ahead");
        board.apply_all(&c.stop()).unwrap();
        assert!(!board.enabled() && !c.motors_enabled());
    }

    #[test]
    fn a_switch_of_behaviour_starts_a_fresh_fsm_and_keeps_the_heading() {
        let mut c = Control::new(FsmParams::default(), Behaviour::Escape);
        let alert = Visuomotor::from_fields([(10u8, 90_000u32)].into_iter(), &crate::Params::PAPER);
        let frame = [0u8; crate::PIXELS];
        let mut movers = Movers::new();
        for _ in 0..10 {
            c.step_seeing(&alert, Some((&mut movers, &frame, 25)), true);
        }
        assert_ne!(c.fsm().state(), State::Wander, "escaping");
        let heading = c.heading().heading_deg();
        assert_ne!(heading, 0.0, "it turned");
        c.set_behaviour(Behaviour::Swarm);
        assert_eq!(c.fsm().behaviour(), Behaviour::Swarm);
        assert_eq!(c.fsm().state(), State::Wander);
        assert_eq!(c.heading().heading_deg(), heading);
        let (cmd, _) = c.step_seeing(&alert, Some((&mut movers, &frame, 25)), true);
        assert_eq!(cmd.state, State::Spin, "the swarm spins on the same alert");
    }

    #[test]
    fn the_heading_only_moves_with_enabled_wheels() {
        let mut c = Control::new(FsmParams::default(), Behaviour::Swarm);
        // a strong alert makes the swarm variant spin
        let alert = Visuomotor::from_fields([(10u8, 90_000u32)].into_iter(), &crate::Params::PAPER);
        assert!(alert.alert);
        c.step(&alert, false);
        assert_eq!(c.heading().heading_deg(), 0.0, "held motors: no turn");
        assert_eq!(c.last_turn_deg(), 0.0);
        c.step(&alert, true);
        assert!(c.heading().heading_deg().abs() > 1.0, "spinning");
        // the turn of the step is the heading's change: the spin rate for one frame (6°)
        assert_eq!(c.last_turn_deg(), c.heading().heading_deg());
        let frame_turn = FsmParams::default().swarm.spin_deg_s / 30.0;
        assert!(
            (c.last_turn_deg().abs() - frame_turn).abs() < 0.5,
            "{}",
            c.last_turn_deg()
        );
    }
}
