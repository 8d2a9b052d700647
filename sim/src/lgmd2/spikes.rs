//! docs/lgmd2.md steps 7–9: the sigmoid output SMP, spike-frequency adaptation, spikes and the
//! collision count.

/// docs/lgmd2.md 7: `SMP = 1 / (1 + exp(−MP / (N_cell·c_sig)))`.
pub fn sigmoid(mp: f32, n_cell: usize, c_sig: f32) -> f32 {
    1.0 / (1.0 + (-mp / (n_cell as f32 * c_sig)).exp())
}

/// docs/lgmd2.md 8, spike-frequency adaptation: with `ΔSMP = SMP(t) − SMP(t−1)`,
/// `SFA = hp·(SFA(t−1) + ΔSMP)` if `ΔSMP ≤ T_sfa`, else `hp·SMP(t)`; never below `floor`.
pub fn sfa_update(sfa_prev: f32, smp_prev: f32, smp: f32, hp: f32, t_sfa: f32, floor: f32) -> f32 {
    let d = smp - smp_prev;
    let v = if d <= t_sfa {
        hp * (sfa_prev + d)
    } else {
        hp * smp
    };
    v.max(floor)
}

/// docs/lgmd2.md 9: `n = ⌊exp(C_spi·(SFA − T_sp))⌋` spikes this frame (a byte in both sources:
/// capped at 255).
pub fn spike_count(sfa: f32, c_spi: f32, t_sp: f32) -> u32 {
    // `clamp` keeps a NaN, and `as` sends it to 0
    (c_spi * (sfa - t_sp)).exp().clamp(0.0, 255.0) as u32
}

/// docs/lgmd2.md 9, spike accumulation over the current burst (module doc, interpretations 11–12).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SpikeCounter {
    count: u32,
}

impl SpikeCounter {
    /// Adds this frame's spikes: a silent frame empties the count, otherwise it grows.
    /// Returns the count this frame is judged on and whether it is a collision
    /// (`count ≥ n_sp`); with `reset_after_alert` a collision empties the count for the
    /// next frame.
    pub fn push(&mut self, spikes: u32, n_sp: u32, reset_after_alert: bool) -> (u32, bool) {
        self.count = if spikes == 0 {
            0
        } else {
            self.count.saturating_add(spikes)
        };
        let judged = self.count;
        let collision = judged >= n_sp;
        if collision && reset_after_alert {
            self.count = 0;
        }
        (judged, collision)
    }

    /// The count carried to the next frame.
    pub fn count(&self) -> u32 {
        self.count
    }
}
