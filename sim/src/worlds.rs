//! The built-in worlds a command names with `--world`, and how an experiment's wall texture
//! combines with them.

use super::world::{WallTexture, World};

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

/// The wall textures the `lab` world's experiments run on by default: procedural clutter,
/// vertical stripes and a checkerboard (built in, so a default run needs no file).
pub const LAB_BACKGROUNDS: [&str; 3] = ["clutter:1", "stripes:40", "checker:60"];

/// The `fu2019` world's own walls as a background specification: `ribs` is exactly the
/// replica's [`super::replica::WALL_RIBS`].
pub const FU2019_BACKGROUNDS: [&str; 1] = ["ribs"];

impl BuiltinWorld {
    /// Both, the default (`fu2019`) first.
    pub const ALL: [BuiltinWorld; 2] = [BuiltinWorld::Fu2019, BuiltinWorld::Lab];

    /// The world.
    pub fn world(self) -> World {
        match self {
            BuiltinWorld::Fu2019 => super::replica::world(),
            BuiltinWorld::Lab => World::default(),
        }
    }

    /// The world with its walls showing `texture`: everything else (size, wall height, floor,
    /// obstacles, room, contact) is the world's own. `lab` with a texture is
    /// [`World::with_texture`]; `fu2019` with [`FU2019_BACKGROUNDS`]' `ribs` is the replica
    /// unchanged.
    pub fn with_walls(self, texture: WallTexture) -> World {
        World {
            texture,
            ..self.world()
        }
    }

    /// The backgrounds (wall texture specifications) an experiment runs on when none is given:
    /// the `lab`'s three built-in textures ([`LAB_BACKGROUNDS`]; a one-background experiment
    /// takes the first, `clutter:1`), the replica's own ribbed walls in `fu2019`.
    pub const fn default_backgrounds(self) -> &'static [&'static str] {
        match self {
            BuiltinWorld::Fu2019 => &FU2019_BACKGROUNDS,
            BuiltinWorld::Lab => &LAB_BACKGROUNDS,
        }
    }

    /// The background of a one-background experiment when none is given (the first of
    /// [`BuiltinWorld::default_backgrounds`]).
    pub const fn default_background(self) -> &'static str {
        self.default_backgrounds()[0]
    }

    /// The background an experiment's walls show: `given`, else the world's own
    /// ([`BuiltinWorld::default_background`]).
    pub fn background(self, given: Option<&str>) -> &str {
        given.unwrap_or(self.default_background())
    }

    /// Its name on the command line and in reports.
    pub const fn label(self) -> &'static str {
        match self {
            BuiltinWorld::Fu2019 => "fu2019",
            BuiltinWorld::Lab => "lab",
        }
    }
}

/// The world a one-background experiment runs in: `world` with its walls showing `background`
/// (a `--background` specification), or its own walls without one
/// ([`BuiltinWorld::default_background`]); and the specification used.
pub fn world_with(
    world: BuiltinWorld,
    background: Option<&str>,
) -> anyhow::Result<(String, World)> {
    let spec = world.background(background);
    Ok((
        spec.to_string(),
        world.with_walls(crate::texture::parse(spec)?),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_world_keeps_everything_but_its_walls_and_its_default_walls_are_its_own() {
        for w in BuiltinWorld::ALL {
            let own = WallTexture::from_spec(w.default_background()).unwrap();
            assert_eq!(w.with_walls(own), w.world(), "{}", w.label());
            let plain = w.with_walls(WallTexture::Plain(200));
            assert_eq!(
                World {
                    texture: w.world().texture,
                    ..plain
                },
                w.world()
            );
        }
        assert_eq!(
            BuiltinWorld::Lab.with_walls(WallTexture::Checker { size_mm: 60.0 }),
            World::with_texture(WallTexture::Checker { size_mm: 60.0 })
        );
    }
}
