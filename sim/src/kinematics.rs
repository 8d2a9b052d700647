//! Differential drive of a Colias: wheel-speed commands in, body motion out, through a
//! first-order motor lag and a slowly varying speed error.
//!
//! # Model
//!
//! Each wheel's ground speed follows its command with a first-order lag of time constant
//! [`MotorParams::lag_s`] (discretised exactly: `v += (cmd − v)(1 − e^(−dt/τ))`), then is
//! scaled by `1 + ε`, where `ε` is a zero-mean Ornstein–Uhlenbeck process of standard deviation
//! [`MotorParams::speed_noise`] and correlation time [`MotorParams::noise_corr_s`] (one per wheel,
//! independent): unequal motors, slip and battery sag make a real robot drift off a straight line
//! over seconds, not flicker at the physics rate. A stopped wheel stays stopped (the error is
//! relative). A lasting difference between the two motors, [`MotorParams::asymmetry`] (none by
//! default; the robustness suite's), makes the right wheel that much slower than the left for
//! the same command: driven open loop, the robot circles to the right with radius
//! `track · (2 − a) / (2a)` ([`MotorParams::open_loop_radius_mm`]).
//!
//! The body then moves like a unicycle: forward speed `v = (left + right)/2`, yaw rate
//! `ω = (left − right)/track` (rad/s, positive = right, as `alvs_tasks::model::fsm::mix` and
//! `Odometry` assume), integrated with the mid-point heading over each physics step
//! [`PHYSICS_DT_S`] (exact for a constant-rate arc up to O(dt³)).
//!
//! # Steps
//!
//! The camera runs at [`FRAME_RATE_HZ`]; the physics takes [`PHYSICS_SUBSTEPS`] steps per frame,
//! [`PHYSICS_DT_S`] = 1/600 s. At the fastest wheel speed (400 mm/s) a body moves 0.67 mm per
//! step, and two bodies close in at most 1.3 mm: far less than a radius (21 mm), so no contact
//! can be stepped over ("tunnelling"), and the motor lag (50 ms by default) is resolved by 30
//! steps.

use super::rng::Rng;
use super::world::{wrap_deg, Pose};

/// Distance between the wheels, mm (docs/hardware.md; `FsmParams::track_mm`).
pub const TRACK_MM: f64 = 48.0;
/// Camera frames per second (docs/hardware.md: 30 fps, ≈ 32 ms frame interval).
pub const FRAME_RATE_HZ: f64 = 30.0;
/// One camera frame, s.
pub const FRAME_DT_S: f64 = 1.0 / FRAME_RATE_HZ;
/// Camera frames in `minutes` of simulated time, at least one.
pub fn frames_in(minutes: f64) -> u64 {
    ((minutes * 60.0 / FRAME_DT_S).round() as u64).max(1)
}

/// Physics steps per camera frame.
pub const PHYSICS_SUBSTEPS: usize = 20;
/// One physics step, s (1/600 s ≈ 1.67 ms).
pub const PHYSICS_DT_S: f64 = FRAME_DT_S / PHYSICS_SUBSTEPS as f64;

/// Motors and wheels of one robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorParams {
    /// Distance between the wheels, mm.
    pub track_mm: f64,
    /// Time constant of each wheel's first-order response to its command, s (0 = instant).
    pub lag_s: f64,
    /// Standard deviation of the relative speed error of each wheel (0.05 = 5 %).
    pub speed_noise: f64,
    /// Correlation time of the speed error, s.
    pub noise_corr_s: f64,
    /// Commands are limited to ± this, mm/s (the FSM never asks for more than 300).
    pub max_wheel_mm_s: f64,
    /// Fraction by which the right wheel runs slower than the left for the same command (0.05:
    /// 5 %), one motor weaker than the other for good; 0 = matched motors.
    pub asymmetry: f64,
}

impl Default for MotorParams {
    /// Choices, not measurements (the paper and docs/hardware.md give none): 50 ms lag, typical of
    /// a geared micro DC motor with the bottom board's speed loop; 5 % speed error with 1 s
    /// correlation, so that a robot told to go straight curves gently, as small robots do.
    fn default() -> Self {
        MotorParams {
            track_mm: TRACK_MM,
            lag_s: 0.05,
            speed_noise: 0.05,
            noise_corr_s: 1.0,
            max_wheel_mm_s: 400.0,
            asymmetry: 0.0,
        }
    }
}

impl MotorParams {
    /// Perfect motors: no lag, no noise.
    pub fn ideal() -> Self {
        MotorParams {
            lag_s: 0.0,
            speed_noise: 0.0,
            ..MotorParams::default()
        }
    }

    /// The radius of the circle the robot drives when both wheels are told the same speed, mm,
    /// with no other error: `track · (2 − a) / (2a)`; infinite for matched motors.
    pub fn open_loop_radius_mm(&self) -> f64 {
        let a = self.asymmetry;
        if a == 0.0 {
            f64::INFINITY
        } else {
            self.track_mm * (2.0 - a) / (2.0 * a)
        }
    }
}

/// The two wheels of one robot: commanded speeds, their lagged and perturbed ground speeds.
#[derive(Debug, Clone)]
pub struct Drive {
    params: MotorParams,
    command: [f64; 2],
    lagged: [f64; 2],
    error: [f64; 2],
    rng: Rng,
}

impl Drive {
    /// Stopped wheels; the speed errors start from their stationary distribution.
    pub fn new(params: MotorParams, mut rng: Rng) -> Self {
        let sigma = params.speed_noise.max(0.0);
        let error = if sigma > 0.0 {
            [
                sigma * f64::from(rng.normal()),
                sigma * f64::from(rng.normal()),
            ]
        } else {
            [0.0; 2]
        };
        Drive {
            params,
            command: [0.0; 2],
            lagged: [0.0; 2],
            error,
            rng,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &MotorParams {
        &self.params
    }

    /// Sets the wheel speed commands, mm/s (forward positive), limited to
    /// `±max_wheel_mm_s`; non-finite commands stop the wheel.
    pub fn command(&mut self, left_mm_s: f64, right_mm_s: f64) {
        let lim = self.params.max_wheel_mm_s.abs();
        let f = |v: f64| {
            if v.is_finite() {
                v.clamp(-lim, lim)
            } else {
                0.0
            }
        };
        self.command = [f(left_mm_s), f(right_mm_s)];
    }

    /// The commands in force, mm/s.
    pub fn commanded(&self) -> (f64, f64) {
        (self.command[0], self.command[1])
    }

    /// The wheels' ground speeds now, mm/s.
    pub fn speeds(&self) -> (f64, f64) {
        (
            self.lagged[0] * (1.0 + self.error[0]),
            self.lagged[1] * (1.0 + self.error[1]) * (1.0 - self.params.asymmetry),
        )
    }

    /// Advances the motors by `dt_s` and returns the wheels' ground speeds over that step.
    pub fn step(&mut self, dt_s: f64) -> (f64, f64) {
        let p = self.params;
        let k = if p.lag_s > 0.0 {
            1.0 - (-dt_s / p.lag_s).exp()
        } else {
            1.0
        };
        let sigma = p.speed_noise.max(0.0);
        let (decay, kick) = if sigma > 0.0 && p.noise_corr_s > 0.0 {
            let d = (-dt_s / p.noise_corr_s).exp();
            (d, sigma * (1.0 - d * d).sqrt())
        } else {
            (1.0, 0.0)
        };
        for w in 0..2 {
            self.lagged[w] += (self.command[w] - self.lagged[w]) * k;
            if kick > 0.0 {
                self.error[w] = self.error[w] * decay + kick * f64::from(self.rng.normal());
            }
        }
        self.speeds()
    }
}

/// Forward speed (mm/s) and yaw rate (rad/s, positive = right) of wheel speeds on `track_mm`.
pub fn body_rates(left_mm_s: f64, right_mm_s: f64, track_mm: f64) -> (f64, f64) {
    (
        0.5 * (left_mm_s + right_mm_s),
        (left_mm_s - right_mm_s) / track_mm,
    )
}

/// Moves `pose` for `dt_s` at forward speed `v_mm_s` and yaw rate `omega_rad_s` (mid-point
/// heading rule).
pub fn advance(pose: &mut Pose, v_mm_s: f64, omega_rad_s: f64, dt_s: f64) {
    let h = pose.heading_deg.to_radians();
    let mid = h + 0.5 * omega_rad_s * dt_s;
    pose.x_mm += v_mm_s * mid.cos() * dt_s;
    pose.y_mm += v_mm_s * mid.sin() * dt_s;
    pose.heading_deg = wrap_deg((h + omega_rad_s * dt_s).to_degrees());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn substeps_divide_a_frame() {
        assert!((PHYSICS_DT_S * PHYSICS_SUBSTEPS as f64 - FRAME_DT_S).abs() < 1e-15);
    }

    #[test]
    fn ideal_drive_follows_commands_at_once_and_clamps() {
        let mut d = Drive::new(MotorParams::ideal(), Rng::new(1));
        d.command(100.0, f64::NAN);
        assert_eq!(d.step(0.01), (100.0, 0.0));
        d.command(1e9, -1e9);
        assert_eq!(d.step(0.01), (400.0, -400.0));
    }

    #[test]
    fn arc_integration_is_accurate() {
        // Quarter circle of radius 100 mm at 100 mm/s: 1 rad/s for π/2 s.
        let mut p = Pose::new(0.0, 0.0, 0.0);
        let n = 1000;
        let dt = std::f64::consts::FRAC_PI_2 / n as f64;
        for _ in 0..n {
            advance(&mut p, 100.0, 1.0, dt);
        }
        // Turning right from +x in the y-down frame ends at (100, 100) heading +90°.
        assert!(
            (p.x_mm - 100.0).abs() < 1e-3 && (p.y_mm - 100.0).abs() < 1e-3,
            "{p:?}"
        );
        assert!((p.heading_deg - 90.0).abs() < 1e-9);
    }
}
