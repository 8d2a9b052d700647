//! Straight approaches to the replica's wall: how far from the wall the LGMD2 baseline first
//! alerts when a robot drives straight at it, at the recordings' speeds. The recorded robots
//! turn 59–98 mm (median, centre to wall) from the wall at every speed and are never seen
//! pressed against one; this probe shows what the simulated network makes of the same
//! approach without any closed loop (`cargo alvs validate --approaches`).

use alvs_sim::lgmd2::{Lgmd2, Lgmd2Params};
use alvs_sim::world::ROBOT_RADIUS_MM;
use alvs_sim::{
    Camera, CameraMount, Pose, RenderOptions, Renderer, SensorNoise, World, FRAME_DT_S,
};

/// Frames the network runs before an alert counts (its layers start from the first frame).
const WARM_UP_FRAMES: usize = 10;
/// Distance from the wall at which each approach starts, mm.
pub const START_MM: f64 = 500.0;
/// Angles between the heading and the wall, degrees (90 = square on).
pub const ANGLES_DEG: [f64; 6] = [90.0, 75.0, 60.0, 45.0, 30.0, 15.0];
/// Where along the bottom wall the approaches aim, mm (clear of the obstacles).
pub const AIM_X_MM: [f64; 5] = [450.0, 500.0, 560.0, 750.0, 800.0];

/// The approaches at one speed.
#[derive(Debug, Clone, PartialEq)]
pub struct ApproachRow {
    pub speed_mm_s: f64,
    pub approaches: usize,
    /// Approaches in which the LGMD2 alerted before the body touched the wall.
    pub alerted: usize,
    /// Of those, per angle of [`ANGLES_DEG`] (of [`AIM_X_MM`]`.len()` approaches each).
    pub alerted_by_angle: Vec<usize>,
    /// Median gap between the body and the wall at the first alert, mm.
    pub median_gap_mm: Option<f64>,
}

/// The gap to the nearest wall or obstacle at the first LGMD2 alert of one straight drive
/// from `start` at `speed_mm_s`; `None` if it touches first.
fn first_alert_gap(
    world: &World,
    r: &Renderer,
    start: Pose,
    speed_mm_s: f64,
    seed: u64,
) -> Option<f64> {
    let mut cam = Camera::new(SensorNoise::typical(), seed);
    let mut m = Lgmd2::new(Lgmd2Params::default());
    let mut frame = [0u8; alvs_tasks::PIXELS];
    let (fx, fy) = start.forward();
    for f in 0..2000 {
        let d = speed_mm_s * f as f64 * FRAME_DT_S;
        let p = Pose::new(start.x_mm + d * fx, start.y_mm + d * fy, start.heading_deg);
        let gap = world.static_distance(p.x_mm, p.y_mm) - ROBOT_RADIUS_MM;
        if gap <= 0.0 {
            return None;
        }
        cam.capture(r, &[p], 0, &mut frame);
        if m.step(&frame).collision && f >= WARM_UP_FRAMES {
            return Some(gap);
        }
    }
    None
}

/// Every angle × aim point at each speed, toward the wall at `y = size_y`, the camera at
/// `mount`.
pub fn approaches(world: &World, mount: CameraMount, speeds_mm_s: &[f64]) -> Vec<ApproachRow> {
    let options = RenderOptions {
        mount,
        ..RenderOptions::default()
    };
    let r = Renderer::with_options(world, &options);
    let y0 = world.arena.size_y_mm - START_MM;
    speeds_mm_s
        .iter()
        .map(|&speed| {
            let mut gaps = Vec::new();
            let mut n = 0;
            let mut alerted_by_angle = Vec::with_capacity(ANGLES_DEG.len());
            for &angle in &ANGLES_DEG {
                let before = gaps.len();
                for (k, &x) in AIM_X_MM.iter().enumerate() {
                    // start left of the aim point so that shallower approaches still end near it
                    let x0 = x - 200.0 * (90.0 - angle) / 75.0;
                    n += 1;
                    gaps.extend(first_alert_gap(
                        world,
                        &r,
                        Pose::new(x0, y0, angle),
                        speed,
                        k as u64 + 1,
                    ));
                }
                alerted_by_angle.push(gaps.len() - before);
            }
            gaps.sort_by(f64::total_cmp);
            ApproachRow {
                speed_mm_s: speed,
                approaches: n,
                alerted: gaps.len(),
                alerted_by_angle,
                median_gap_mm: gaps.get(gaps.len() / 2).copied(),
            }
        })
        .collect()
}
