//! A simulated yaw gyro (the MPU9250 of the 2025 Colias firmware, docs/hardware.md) integrated into
//! a heading, behind the firmware's own interface `alvs_tasks::model::fsm::HeadingEstimator`.
//!
//! The physics feeds it the body's true yaw rate every step ([`SimGyro::sense`]); it integrates
//! `rate · (1 + scale error) + bias + white noise`, with the bias drifting as a random walk.
//! The controller then calls `HeadingEstimator::update(left, right, dt)` once per frame exactly
//! as on the robot and reads the heading: the wheel commands passed there are ignored, because a
//! gyro measures the rotation that actually happened (including any the wheels did not intend),
//! not the one that was commanded. The estimate starts at the robot's true initial heading (the
//! firmware's estimate starts at 0; only heading differences matter to the FSM).

use alvs_tasks::model::fsm::HeadingEstimator;

use super::rng::Rng;
use super::world::wrap_deg;

/// Gyro imperfections. Angles in degrees, times in seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroParams {
    /// White rate noise density, °/s/√Hz (MPU9250 datasheet: 0.01).
    pub noise_density: f64,
    /// Standard deviation of the bias left after the start-up calibration, °/s (a choice).
    pub bias_sigma: f64,
    /// Bias random walk, °/s per √s (a choice: ≈ 0.1 °/s drift of the bias over 10 minutes).
    pub bias_walk: f64,
    /// Standard deviation of the scale-factor error, relative (MPU9250: ±3 % tolerance before
    /// calibration; 1 % left).
    pub scale_sigma: f64,
}

impl Default for GyroParams {
    fn default() -> Self {
        GyroParams {
            noise_density: 0.01,
            bias_sigma: 0.1,
            bias_walk: 0.005,
            scale_sigma: 0.01,
        }
    }
}

impl GyroParams {
    /// A perfect gyro: the estimate is the true heading.
    pub fn ideal() -> Self {
        GyroParams {
            noise_density: 0.0,
            bias_sigma: 0.0,
            bias_walk: 0.0,
            scale_sigma: 0.0,
        }
    }
}

/// The gyro of one robot and the heading integrated from it.
#[derive(Debug, Clone)]
pub struct SimGyro {
    params: GyroParams,
    heading_deg: f64,
    bias_deg_s: f64,
    scale: f64,
    rng: Rng,
}

impl SimGyro {
    /// A gyro whose estimate starts at `heading_deg`; bias and scale error are drawn from `rng`.
    pub fn new(params: GyroParams, heading_deg: f64, mut rng: Rng) -> Self {
        let bias_deg_s = params.bias_sigma * f64::from(rng.normal());
        let scale = 1.0 + params.scale_sigma * f64::from(rng.normal());
        SimGyro {
            params,
            heading_deg: wrap_deg(heading_deg),
            bias_deg_s,
            scale,
            rng,
        }
    }

    /// Integrates one physics step of `dt_s` during which the body turned at `true_rate_rad_s`
    /// (positive = right).
    pub fn sense(&mut self, true_rate_rad_s: f64, dt_s: f64) {
        let p = self.params;
        let mut d = (true_rate_rad_s.to_degrees() * self.scale + self.bias_deg_s) * dt_s;
        if p.noise_density > 0.0 {
            d += p.noise_density * dt_s.sqrt() * f64::from(self.rng.normal());
        }
        if p.bias_walk > 0.0 {
            self.bias_deg_s += p.bias_walk * dt_s.sqrt() * f64::from(self.rng.normal());
        }
        self.heading_deg = wrap_deg(self.heading_deg + d);
    }

    /// The current bias, °/s.
    pub fn bias_deg_s(&self) -> f64 {
        self.bias_deg_s
    }

    /// The heading estimate, degrees (full precision).
    pub fn heading(&self) -> f64 {
        self.heading_deg
    }
}

impl HeadingEstimator for SimGyro {
    /// Returns the integrated heading; the commanded speeds are not used (see the module
    /// documentation): the physics has already fed the true rotation through
    /// [`SimGyro::sense`].
    fn update(&mut self, _left_mm_s: f32, _right_mm_s: f32, _dt_s: f32) -> f32 {
        self.heading_deg as f32
    }

    fn heading_deg(&self) -> f32 {
        self.heading_deg as f32
    }
}
