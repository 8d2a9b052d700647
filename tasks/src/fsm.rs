//! Escape finite-state machine (paper Sec. II-B, Fig. 2d) and the swarm variant (Sec. IV-D).
//! (being written)

/// Motion state of the robot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    /// Forward at constant speed.
    Wander,
    /// Turning in place to `θ_long`.
    LongTakeoff,
    /// Straight away from the threat.
    Escape,
    /// The two-phase γ path of the short mode.
    ShortTakeoff,
    /// Swarm variant: spinning in place on an approaching object.
    Spin,
}

impl State {
    /// Lower-case name used in JSON and telemetry.
    pub const fn name(self) -> &'static str {
        match self {
            State::Wander => "wander",
            State::LongTakeoff => "long_takeoff",
            State::Escape => "escape",
            State::ShortTakeoff => "short_takeoff",
            State::Spin => "spin",
        }
    }

    /// Inverse of [`State::name`].
    pub fn from_name(s: &str) -> Option<State> {
        [
            State::Wander,
            State::LongTakeoff,
            State::Escape,
            State::ShortTakeoff,
            State::Spin,
        ]
        .into_iter()
        .find(|st| st.name() == s)
    }
}
