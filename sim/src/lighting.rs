//! Uneven light across the arena (the robustness suite's lighting gradient): one lamp or window
//! off one end of the arena lights the near end more than the far one.
//!
//! To first order the illuminance falls linearly along the arena's length: everything lit in
//! the arena (the floor, the walls' inner faces, the robots and obstacles) is multiplied by
//! [`LightGradient::gain`], `1 + amplitude` at `x = 0` down to `1 − amplitude` at
//! `x = size_x`. The room seen above the walls and its ceiling are the lab itself, not lit by
//! that lamp, and keep their greys.

use super::world::Arena;

/// A linear fall of the light along the arena's `x` axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightGradient {
    /// Relative excess of light at `x = 0` and deficit at `x = size_x` (0.25: 1.25 to 0.75,
    /// the ends differ by a factor 5/3).
    pub amplitude: f32,
}

impl LightGradient {
    /// The factor on what is lit at `x_mm` in `arena` (clamped to the arena).
    pub fn gain(&self, arena: &Arena, x_mm: f32) -> f32 {
        let t = (x_mm / arena.size_x_mm as f32).clamp(0.0, 1.0);
        1.0 + self.amplitude * (1.0 - 2.0 * t)
    }

    /// Checks the amplitude (one line): in 0..1, so nothing is lit negatively.
    pub fn check(&self) -> anyhow::Result<()> {
        anyhow::ensure!(
            self.amplitude.is_finite() && (0.0..1.0).contains(&self.amplitude),
            "lighting gradient amplitude must be in 0..1, got {}",
            self.amplitude
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_light_falls_linearly_along_x() {
        let a = Arena::new(1000.0, 500.0);
        let g = LightGradient { amplitude: 0.25 };
        assert_eq!(g.gain(&a, 0.0), 1.25);
        assert_eq!(g.gain(&a, 500.0), 1.0);
        assert_eq!(g.gain(&a, 1000.0), 0.75);
        assert_eq!(g.gain(&a, -50.0), 1.25, "clamped");
        assert!(LightGradient { amplitude: 1.0 }.check().is_err());
        assert!(g.check().is_ok());
    }
}
