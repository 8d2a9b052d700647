//! The recorded arena: a replica of the arena of the authors' group's LGMD2 Colias recordings
//! (public repository `fuqinbing/LGMD2-open-source`), the world the simulator is validated in
//! (`cargo alvs validate`). Every figure comes from the recordings' top-down snapshots; how
//! each was measured, and its uncertainty, is in docs/recordings.md.

use super::contacts::SurfaceContact;
use super::world::{Arena, FloorShade, Obstacle, RobotPattern, Room, WallTexture, World};

/// Distance from the arena's walls to the lab's walls, mm.
pub const ROOM_MARGIN_MM: f64 = 1500.0;
/// Height of the lab's walls (its ceiling), mm.
pub const ROOM_HEIGHT_MM: f64 = 2500.0;

/// Inner size of the arena along `x` (the snapshots' horizontal), mm.
pub const SIZE_X_MM: f64 = 1309.0;
/// Inner size along `y`, mm.
pub const SIZE_Y_MM: f64 = 751.0;
/// Height of the walls, mm.
pub const WALL_HEIGHT_MM: f64 = 72.0;
/// The walls: white corrugated plastic, ribs every 5 mm.
pub const WALL_RIBS: WallTexture = WallTexture::Ribs {
    period_mm: 5.6,
    dark: 170,
    light: 230,
};
/// The floor: a dark board, brighter at a grazing view.
pub const FLOOR: FloorShade = FloorShade {
    near_grey: 60.0,
    far_grey: 80.0,
};
/// Radius of the cylinder obstacles, mm (measured diameter 46.1 mm).
pub const OBSTACLE_RADIUS_MM: f64 = 23.0;
/// Height of the cylinder obstacles, mm (measured 52.7 mm).
pub const OBSTACLE_HEIGHT_MM: f64 = 53.0;
/// The obstacles' sides: the walls' ribs around a cylinder (circumference / period pairs).
pub const OBSTACLE_PATTERN: RobotPattern = RobotPattern::Stripes {
    count: 26,
    dark: 170,
    light: 230,
};
/// Centres of the obstacles, mm: the 13 found in the snapshots (host/data/fu2019/arena.json,
/// rounded), then the two hidden under the tracker's drawings, placed by the arena's
/// regularity: the top-right corner mirrors the top-left one, and the bottom row's fourth sits
/// as far left of the top row's fourth as the bottom row's second and third do of theirs
/// (45 mm), at the bottom row's mean `y`.
pub const OBSTACLES_MM: [(f64, f64); 15] = [
    (23.0, 363.0),
    (23.0, 29.0),
    (369.0, 24.0),
    (623.0, 375.0),
    (651.0, 23.0),
    (926.0, 361.0),
    (951.0, 22.0),
    (23.0, 723.0),
    (318.0, 729.0),
    (323.0, 410.0),
    (611.0, 728.0),
    (1286.0, 723.0),
    (1287.0, 384.0),
    (1286.0, 29.0),
    (906.0, 726.0),
];
/// How many of [`OBSTACLES_MM`] were measured (the rest are placed by symmetry).
pub const MEASURED_OBSTACLES: usize = 13;

/// The recorded arena as a simulated world.
pub fn world() -> World {
    World {
        arena: Arena::new(SIZE_X_MM, SIZE_Y_MM),
        wall_height_mm: WALL_HEIGHT_MM,
        texture: WALL_RIBS,
        robot_pattern: RobotPattern::default(),
        floor: FLOOR,
        obstacles: OBSTACLES_MM
            .iter()
            .map(|&(x_mm, y_mm)| Obstacle {
                x_mm,
                y_mm,
                radius_mm: OBSTACLE_RADIUS_MM,
                height_mm: OBSTACLE_HEIGHT_MM,
            })
            .collect(),
        obstacle_pattern: OBSTACLE_PATTERN,
        contact: SurfaceContact::default(),
        room: Some(Room {
            margin_mm: ROOM_MARGIN_MM,
            height_mm: ROOM_HEIGHT_MM,
            texture: WallTexture::Clutter { seed: 7 },
        }),
    }
}
