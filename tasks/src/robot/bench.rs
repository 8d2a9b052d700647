//! One frame of perception and control as a single call, with its stages time-stamped: the
//! body of the firmware's exported `alvs_bench_step` (run on the board it prints DWT cycles;
//! run on the host's Cortex-M4 model it proves the deadline) and of its host twin, which the
//! cycle-model test holds the emulated one to, bit for bit.
//!
//! The frame enters row by row, as the camera delivers it on the robot.

use crate::frame::Frame;
use crate::model::closed_loop::movers::Movers;
use crate::model::network::{Network, Stage};
use crate::robot::control::Control;

/// Time stamps of a step: the start, then the end of each [`Stage`], then the end of control.
pub const STAMPS: usize = 6;

/// What one step leaves for the caller: time stamps and outputs, all 32-bit words in a fixed
/// order (`#[repr(C)]`), so an emulator reads it from memory as [`Report::WORDS`] words.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Report {
    /// Clock readings: start, end of retina, attention, motion, visuomotor, control.
    pub stamps: [u32; STAMPS],
    /// [`Network::digest`] after the step.
    pub digest: u32,
    /// Frame index of the perception.
    pub frame: u32,
    /// Attention fields standing.
    pub afs: u32,
    /// `ΣLPLC2`.
    pub lplc2_sum: u32,
    /// Alert (0/1).
    pub alert: u32,
    /// FSM state after the step ([`crate::model::fsm::State`] as its index).
    pub state: u32,
    /// Left and right wheel speeds commanded, as `f32` bits.
    pub wheels: [u32; 2],
    /// Motor frames produced and their bytes' FNV-1a digest.
    pub motor_frames: u32,
    /// Digest of the motor frames' bytes.
    pub motor_digest: u32,
}

impl Report {
    /// Size in 32-bit words.
    pub const WORDS: usize = STAMPS + 10;

    /// Rebuilds a report from its words (as read from an emulator's memory).
    pub fn from_words(w: &[u32; Report::WORDS]) -> Report {
        let mut stamps = [0; STAMPS];
        stamps.copy_from_slice(&w[..STAMPS]);
        let r = &w[STAMPS..];
        Report {
            stamps,
            digest: r[0],
            frame: r[1],
            afs: r[2],
            lplc2_sum: r[3],
            alert: r[4],
            state: r[5],
            wheels: [r[6], r[7]],
            motor_frames: r[8],
            motor_digest: r[9],
        }
    }

    /// Cycles of each stage (stamp differences): retina, attention, motion, visuomotor,
    /// control.
    pub fn stage_cycles(&self) -> [u32; STAMPS - 1] {
        let s = self.stamps;
        core::array::from_fn(|i| s[i + 1].wrapping_sub(s[i]))
    }

    /// The outputs without the time stamps (what must agree between builds).
    pub fn outputs(&self) -> Report {
        Report {
            stamps: [0; STAMPS],
            ..*self
        }
    }
}

const _: () = assert!(core::mem::size_of::<Report>() == 4 * Report::WORDS);

/// One frame: the turn of the last control step reported to the network (its efference copy,
/// timed with the retina), the network's step fed row by row, then the motor-control step with
/// the motors enabled (with the swarm's look on `movers`, if given, as motor control runs it). `clock` is read before and after each stage (the DWT cycle counter on a
/// Cortex-M4; anything, or a constant, elsewhere).
pub fn step(
    network: &mut Network,
    control: &mut Control,
    movers: Option<&mut Movers>,
    frame: &Frame,
    clock: &mut impl FnMut() -> u32,
) -> Report {
    let mut stamps = [0u32; STAMPS];
    stamps[0] = clock();
    network.turned(control.last_turn_deg());
    network.driving(control.last_forward_mm_s());
    let perception = network.step_marked(frame, &mut |s| {
        let i = match s {
            Stage::Retina => 1,
            Stage::Attention => 2,
            Stage::Motion => 3,
            Stage::Visuomotor => 4,
        };
        stamps[i] = clock();
    });
    // The priming frame ends after the retina: the later stages take no time.
    for i in 2..5 {
        if stamps[i] == 0 {
            stamps[i] = stamps[i - 1];
        }
    }
    // the swarm's look, as motor control runs it; none in escape
    let look_change = crate::model::param_table::off0(network.params().swarm.look_change);
    let look = movers.map(|m| (m, network.frame(), look_change));
    let (command, frames) = control.step_seeing(&perception.vm, look, true);
    stamps[5] = clock();
    let mut h = crate::model::network::Fnv::new();
    for f in &frames {
        h.bytes(f);
    }
    Report {
        stamps,
        digest: network.digest(),
        frame: perception.frame,
        afs: perception.afs.len() as u32,
        lplc2_sum: perception.vm.lplc2_sum,
        alert: u32::from(perception.vm.alert),
        state: command.state as u32,
        wheels: [command.left_mm_s.to_bits(), command.right_mm_s.to_bits()],
        motor_frames: frames.len() as u32,
        motor_digest: h.finish(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{PIXELS, WIDTH};
    use crate::model::fsm::{Behaviour, FsmParams};

    #[test]
    fn stamps_bracket_each_stage_and_words_round_trip() {
        let mut n = Network::alvs();
        let mut c = Control::new(FsmParams::default(), Behaviour::Escape);
        let mut t = 0u32;
        let mut clock = || {
            t += 10;
            t
        };
        let prime = step(&mut n, &mut c, None, &[100; PIXELS], &mut clock);
        assert_eq!(prime.frame, 0);
        assert_eq!(
            prime.stage_cycles(),
            [10, 0, 0, 0, 10],
            "priming: retina and control only"
        );
        let mut f = [100u8; PIXELS];
        f[30 * WIDTH..40 * WIDTH].fill(0);
        let r = step(&mut n, &mut c, None, &f, &mut clock);
        assert_eq!(r.stage_cycles(), [10; 5]);
        assert_eq!(r.frame, 1);
        assert_eq!(r.digest, n.digest());
        assert!(r.motor_frames > 0, "the enable sequence and powers");
        // as an emulator would read it
        let w: [u32; Report::WORDS] = core::array::from_fn(|i| match i {
            0..STAMPS => r.stamps[i],
            _ => [
                r.digest,
                r.frame,
                r.afs,
                r.lplc2_sum,
                r.alert,
                r.state,
                r.wheels[0],
                r.wheels[1],
                r.motor_frames,
                r.motor_digest,
            ][i - STAMPS],
        });
        assert_eq!(Report::from_words(&w), r);
    }

    #[test]
    fn the_constant_networks_are_the_validated_ones() {
        for (a, p) in [
            (Network::paper(), crate::Params::PAPER),
            (Network::alvs(), crate::Params::ALVS),
        ] {
            let b = Network::new(p).unwrap();
            assert_eq!(a.params(), b.params());
            assert_eq!(a.weights(), b.weights());
            assert_eq!(a.lm_scale(), b.lm_scale());
            assert_eq!(a.digest(), b.digest());
        }
    }
}
