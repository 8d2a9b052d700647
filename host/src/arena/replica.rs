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
/// Radius of the cylinder obstacles, mm.
pub const OBSTACLE_RADIUS_MM: f64 = 23.0;
/// Height of the cylinder obstacles, mm.
pub const OBSTACLE_HEIGHT_MM: f64 = 50.0;
/// The obstacles' sides: the walls' ribs around a cylinder (circumference / period pairs).
pub const OBSTACLE_PATTERN: RobotPattern = RobotPattern::Stripes {
    count: 26,
    dark: 170,
    light: 230,
};
/// Centres of the obstacles, mm.
pub const OBSTACLES_MM: [(f64, f64); 15] = [
    (25.0, 25.0),
    (369.0, 22.0),
    (651.0, 15.0),
    (951.0, 20.0),
    (1285.0, 25.0),
    (15.0, 363.0),
    (1295.0, 384.0),
    (323.0, 410.0),
    (623.0, 375.0),
    (926.0, 361.0),
    (25.0, 726.0),
    (318.0, 729.0),
    (611.0, 735.0),
    (900.0, 735.0),
    (1285.0, 726.0),
];

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
