//! The robot adapter (`arena::controller::Lgmd2Controller`).

use super::*;

/// One camera frame of an `Lgmd2Controller` whose wheel commands turn `pose` (ideal motors).
fn drive(
    c: &mut alvs_sim::controller::Lgmd2Controller,
    pose: &mut alvs_sim::Pose,
    frame: &Frame,
) -> alvs_sim::Command {
    use alvs_sim::controller::Controller;
    use alvs_sim::kinematics::{advance, body_rates, FRAME_DT_S};
    let cmd = c.step(frame, pose.heading_deg as f32);
    let track = f64::from(alvs_tasks::model::fsm::FsmParams::default().motion.track_mm);
    let (v, w) = body_rates(f64::from(cmd.left_mm_s), f64::from(cmd.right_mm_s), track);
    advance(pose, v, w, FRAME_DT_S);
    cmd
}

#[test]
fn lgmd2_robot_turns_then_goes_straight_on_with_its_perception_live() {
    // docs/lgmd2.md, "On the robot": a turn of random sign and magnitude, then straight on; the
    // authors' firmware queues a long turn and drives on at its cruise speed, the LGMD2 running on
    // every frame
    let p = alvs_tasks::model::fsm::FsmParams::default();
    for seed in 1..=4 {
        let mut c = alvs_sim::controller::Lgmd2Controller::new(Lgmd2Params::colias(), p, seed);
        let mut pose = alvs_sim::Pose::new(600.0, 450.0, 0.0);
        let still = [128u8; PIXELS];
        // a looming square alerts: the random turn begins
        let mut t = 0;
        let cmd = loop {
            let cmd = drive(&mut c, &mut pose, &looming(t));
            if cmd.alert {
                break cmd;
            }
            t += 1;
            assert!(t < 30, "seed {seed}: no alert");
        };
        assert_eq!(cmd.state, "long_takeoff", "seed {seed}");
        let h0 = pose.heading_deg;
        // a still scene until the turn is done
        let mut n = 0;
        while drive(&mut c, &mut pose, &still).state == "long_takeoff" {
            n += 1;
            assert!(
                n <= p.timing.takeoff_timeout_frames + 2,
                "seed {seed}: endless turn"
            );
        }
        let turned = alvs_tasks::model::fsm::heading_error_deg(pose.heading_deg as f32, h0 as f32);
        assert!(turned.abs() >= 45.0, "seed {seed}: turned only {turned}°");
        // then straight on at the cruise speed, not a sprint
        for f in 0..10 {
            let cmd = drive(&mut c, &mut pose, &still);
            let v = 0.5 * (cmd.left_mm_s + cmd.right_mm_s);
            assert_eq!(cmd.state, "wander", "seed {seed} frame {f} after the turn");
            assert!(
                (v - p.motion.cruise_mm_s).abs() < 1.0,
                "seed {seed}: {v} mm/s after the turn"
            );
        }
        // and the perception is live: the next looming object starts the next turn at once
        // (within the 1 s that an escape ignoring the LGMD2 would last)
        let next = (0..p.timing.min_escape_frames as usize)
            .position(|t| drive(&mut c, &mut pose, &looming(t)).state == "long_takeoff");
        assert!(
            next.is_some(),
            "seed {seed}: an alert after the turn was ignored"
        );
    }
}
