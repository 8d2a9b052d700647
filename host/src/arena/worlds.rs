//! The built-in worlds a command names with `--world`.

use super::world::World;

/// A built-in world.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BuiltinWorld {
    /// The recorded arena's replica ([`super::replica`]): its size, low ribbed walls, dark
    /// floor, 15 obstacles, the room above the walls, the contact turn.
    Fu2019,
    /// The built-in 1200 x 900 mm arena with 250 mm clutter walls, no obstacles, rigid walls
    /// ([`World::default`]).
    Lab,
}

impl BuiltinWorld {
    /// The world.
    pub fn world(self) -> World {
        match self {
            BuiltinWorld::Fu2019 => super::replica::world(),
            BuiltinWorld::Lab => World::default(),
        }
    }

    /// Its name on the command line and in reports.
    pub const fn label(self) -> &'static str {
        match self {
            BuiltinWorld::Fu2019 => "fu2019",
            BuiltinWorld::Lab => "lab",
        }
    }
}
