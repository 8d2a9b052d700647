//! Parameters of the LGMD2 network: the two sets (reference, Colias), the 3x3 kernels, the
//! rounding mode, and the coefficients derived from time constants.

/// How the layers round.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arithmetic {
    /// Real-valued layers (the C# reference).
    Float,
    /// The Colias firmware's integer layers: values are truncated where the firmware stores
    /// them in integer types (module doc, interpretation 6).
    Uint8,
}

impl Arithmetic {
    /// Rounds a non-negative layer value as the firmware stores it (`max` = the type's top).
    #[inline(always)]
    pub(super) fn store(self, v: f32, max: f32) -> f32 {
        match self {
            Arithmetic::Float => v,
            Arithmetic::Uint8 => truncate(v, max),
        }
    }
}

/// The firmware's float-to-integer conversion of a layer value: truncation toward 0 of a
/// non-negative value, saturating at `max` (≤ 65,535); a negative value or NaN gives 0.
#[inline(always)]
pub(super) fn truncate(v: f32, max: f32) -> f32 {
    // `f32::max` ignores a NaN
    let v = v.max(0.0).min(max);
    // round to the nearest integer by adding and removing 2^23 (exact below 2^23), then step
    // down if that went up: ⌊v⌋ with plain float operations, which vectorise
    let r = (v + 8_388_608.0) - 8_388_608.0;
    if r > v {
        r - 1.0
    } else {
        r
    }
}

/// One 3x3 lateral-inhibition kernel and the delays of its three kinds of position
/// (docs/lgmd2.md 4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kernel3 {
    /// Weight of the centre cell.
    pub centre: f32,
    /// Weight of each of the 4 nearest cells.
    pub near: f32,
    /// Weight of each of the 4 diagonal cells.
    pub diag: f32,
    /// Low-pass time constants in ms, `[centre, nearest, diagonal]`.
    pub tau_ms: [f32; 3],
}

impl Kernel3 {
    /// The ON kernel `[.25 .5 .25; .5 2 .5; .25 .5 .25]`, τ = 15 / 30 / 45 ms.
    pub const ON: Kernel3 = Kernel3 {
        centre: 2.0,
        near: 0.5,
        diag: 0.25,
        tau_ms: [15.0, 30.0, 45.0],
    };
    /// The OFF kernel `W_on / 2`, τ = 60 / 120 / 180 ms.
    pub const OFF: Kernel3 = Kernel3 {
        centre: 1.0,
        near: 0.25,
        diag: 0.125,
        tau_ms: [60.0, 120.0, 180.0],
    };
}

/// Parameters of the LGMD2 network; see [`Lgmd2Params::reference`] and
/// [`Lgmd2Params::colias`] (the default).
#[derive(Debug, Clone, PartialEq)]
pub struct Lgmd2Params {
    /// Frames per second; Δt = `1000 / fps` integer ms (interpretation 1).
    pub fps: u32,
    /// Real or firmware-integer layers.
    pub arithmetic: Arithmetic,
    /// P = `(L(t) − L(t−1)) >> p_shift`, clamped to `±(255 >> p_shift)`: 0 (reference),
    /// 1 (Colias' 7-bit difference, interpretation 6).
    pub p_shift: u32,
    /// τ_PM in ms (docs/lgmd2.md 2): 90.
    pub tau_pm_ms: f32,
    /// T_pm (docs/lgmd2.md 2): 8 (reference), 10 (Colias).
    pub t_pm: f32,
    /// Floor of the ON inhibition bias W_i_on: 1.
    pub w_i_on_base: f32,
    /// Floor of the OFF inhibition bias W_i_off: 0.5.
    pub w_i_off_base: f32,
    /// ON/OFF clip point (docs/lgmd2.md 3): 0.1.
    pub clip: f32,
    /// ON/OFF carry-over dc (docs/lgmd2.md 3): 0.1 (reference), 0 (Colias).
    pub dc: f32,
    /// ON inhibition kernel.
    pub on_kernel: Kernel3,
    /// OFF inhibition kernel.
    pub off_kernel: Kernel3,
    /// S = w_on·S_on + w_off·S_off + w_onoff·S_on·S_off (docs/lgmd2.md 5): 1, 1, 1 (reference);
    /// 0.5, 1, 0 (Colias).
    pub w_on: f32,
    /// See [`Lgmd2Params::w_on`].
    pub w_off: f32,
    /// See [`Lgmd2Params::w_on`].
    pub w_onoff: f32,
    /// Δ_C in the G-layer scale ω = Δ_C + max|Ce| / C_w: 0.01.
    pub delta_c: f32,
    /// C_w in the G-layer scale: 4.
    pub c_w: f32,
    /// C_de: G is kept where G·C_de ≥ T_de: 0.5 (reference), 1 (Colias).
    pub c_de: f32,
    /// T_de: 15 (reference), 35 (Colias).
    pub t_de: f32,
    /// Sigmoid coefficient: SMP = 1 / (1 + exp(−MP / (N_cell·c_sig))): 1 (reference),
    /// 0.5 (Colias' K_spi, interpretation 5).
    pub c_sig: f32,
    /// τ_sfa in ms (docs/lgmd2.md 8): 800 (reference), 500 (Colias).
    pub tau_sfa_ms: f32,
    /// T_sfa (docs/lgmd2.md 8): 0.003.
    pub t_sfa: f32,
    /// Floor of SFA: 0.5.
    pub sfa_floor: f32,
    /// C_spi (docs/lgmd2.md 9): 4.
    pub c_spi: f32,
    /// T_sp (docs/lgmd2.md 9): 0.78 (reference), 0.63 (Colias).
    pub t_sp: f32,
    /// Spikes in one burst that make a collision: 8 (reference), 4 (Colias).
    pub n_sp: u32,
    /// Empty the spike count after an alert (Colias firmware) or keep counting (reference).
    pub reset_after_alert: bool,
}

impl Default for Lgmd2Params {
    /// [`Lgmd2Params::colias`]: the robot baseline the paper compares against.
    fn default() -> Self {
        Self::colias()
    }
}

impl Lgmd2Params {
    /// The authors' C# reference (`lgmd2OpenSource.cs`), docs/lgmd2.md steps 1–9 as written.
    pub fn reference() -> Self {
        Lgmd2Params {
            fps: 30,
            arithmetic: Arithmetic::Float,
            p_shift: 0,
            tau_pm_ms: 90.0,
            t_pm: 8.0,
            w_i_on_base: 1.0,
            w_i_off_base: 0.5,
            clip: 0.1,
            dc: 0.1,
            on_kernel: Kernel3::ON,
            off_kernel: Kernel3::OFF,
            w_on: 1.0,
            w_off: 1.0,
            w_onoff: 1.0,
            delta_c: 0.01,
            c_w: 4.0,
            c_de: 0.5,
            t_de: 15.0,
            c_sig: 1.0,
            tau_sfa_ms: 800.0,
            t_sfa: 0.003,
            sfa_floor: 0.5,
            c_spi: 4.0,
            t_sp: 0.78,
            n_sp: 8,
            reset_after_alert: false,
        }
    }

    /// The authors' Colias embedded variant (docs/lgmd2.md, last paragraph): T_pm 10, no ON/OFF
    /// carry-over, uint8 layers with kernels as shifts, S = 0.5·S_on + S_off, G threshold 35,
    /// K_spi 0.5 (the sigmoid's), τ_sfa 500 ms, T_sp 0.63, collision at ≥ 4 accumulated
    /// spikes.
    pub fn colias() -> Self {
        Lgmd2Params {
            arithmetic: Arithmetic::Uint8,
            p_shift: 1,
            t_pm: 10.0,
            dc: 0.0,
            w_on: 0.5,
            w_off: 1.0,
            w_onoff: 0.0,
            c_de: 1.0,
            t_de: 35.0,
            c_sig: 0.5,
            tau_sfa_ms: 500.0,
            t_sp: 0.63,
            n_sp: 4,
            reset_after_alert: true,
            ..Self::reference()
        }
    }

    /// Δt in ms: `1000 / fps` with integer division, as both sources (interpretation 1).
    pub fn dt_ms(&self) -> f32 {
        (1000 / self.fps.max(1)) as f32
    }

    /// Says what makes these parameters meaningless, if anything.
    pub fn validate(&self) -> Result<(), String> {
        let mut bad = Vec::new();
        if self.fps == 0 || self.fps > 1000 {
            bad.push(format!("fps {} (must be 1..=1000)", self.fps));
        }
        let positive = [
            ("t_pm", self.t_pm),
            ("c_w", self.c_w),
            ("c_sig", self.c_sig),
            ("delta_c", self.delta_c),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                bad.push(format!("{name} {v} (must be > 0)"));
            }
        }
        let mut non_negative = vec![
            ("tau_pm_ms", self.tau_pm_ms),
            ("tau_sfa_ms", self.tau_sfa_ms),
            ("dc", self.dc),
            ("c_de", self.c_de),
        ];
        for k in [&self.on_kernel, &self.off_kernel] {
            non_negative.extend(k.tau_ms.iter().map(|&t| ("kernel tau_ms", t)));
        }
        for (name, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                bad.push(format!("{name} {v} (must be >= 0)"));
            }
        }
        if self.n_sp == 0 {
            bad.push("n_sp 0 (every frame would be a collision)".into());
        }
        if self.p_shift > 7 {
            bad.push(format!("p_shift {} (must be <= 7)", self.p_shift));
        }
        if bad.is_empty() {
            Ok(())
        } else {
            Err(bad.join(", "))
        }
    }
}

/// Low-pass coefficient `Δt / (Δt + τ)` (docs/lgmd2.md 2, 4); 1 (no delay) if that is undefined.
pub fn lowpass_coefficient(dt_ms: f32, tau_ms: f32) -> f32 {
    let a = dt_ms / (dt_ms + tau_ms);
    if a.is_finite() {
        a.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// High-pass coefficient of the SFA `τ_sfa / (τ_sfa + Δt)` (docs/lgmd2.md 8); 0 if undefined.
pub fn sfa_coefficient(dt_ms: f32, tau_sfa_ms: f32) -> f32 {
    let hp = tau_sfa_ms / (tau_sfa_ms + dt_ms);
    if hp.is_finite() {
        hp.clamp(0.0, 1.0)
    } else {
        0.0
    }
}
