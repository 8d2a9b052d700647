//! # The LGMD2 baseline: the collision detector ALVS is compared against
//!
//! The LGMD2 visual neural network of Fu, Hu, Peng, Rind and Yue, "A Robust Collision Perception
//! Visual Neural Network with Specific Selectivity to Darker Objects" (IEEE Trans. Cybernetics,
//! 2019), written from `docs/lgmd2.md`, on the robot's 99x72 Y8 frames. The paper compares
//! ALVS against "a state-of-the-art LGMD2-based embedded system": that is [`Lgmd2Params::colias`],
//! the default. [`Lgmd2Params::reference`] is the authors' open-source C# reference.
//!
//! Step numbers ("docs/lgmd2.md 4") refer to the numbered list of `docs/lgmd2.md`:
//!
//! | step | what | function |
//! |---|---|---|
//! | 1 | P layer, `P = L(t) − L(t−1)` | [`p_layer`] |
//! | 2 | adaptive inhibition (PM pathway) | [`mean_abs`], [`pm_update`], [`inhibition_biases`] |
//! | 3 | ON/OFF split with carry-over | [`on_off_layer`] |
//! | 4 | delayed lateral inhibition, 3x3 kernels | [`lateral_inhibition`] |
//! | 5 | S layer | [`s_layer`] |
//! | 6 | G layer, `Ce`, threshold, MP | [`g_layer`] |
//! | 7 | SMP sigmoid | [`sigmoid`] |
//! | 8 | spike-frequency adaptation | [`sfa_update`] |
//! | 9 | spikes, accumulation, collision | [`spike_count`], [`SpikeCounter`] |
//!
//! [`Lgmd2`] runs one frame through all of them: `Lgmd2::new(params)`, `step(&frame)`,
//! `reset()`. It never panics, on any frame or any parameter values (nonsensical parameters give
//! nonsensical but finite-or-saturated outputs; [`Lgmd2Params::validate`] says what is wrong),
//! and it is deterministic: the same frames give the same outputs, bit for bit.
//!
//! ## Interpretations (where docs/lgmd2.md leaves a choice, or where the two sources differ)
//!
//! The two sources checked are the authors' C# reference (GitHub `fuqinbing/LGMD2-open-source`,
//! `lgmd2OpenSource.cs`) and the authors' Colias LGMD2 firmware (`coliasSense_LGMD.c`, Fu 2019,
//! published in `Ryannnice/Supplementary_Materials_FFI_ON_OFF`). No code was copied.
//!
//! 1. **Δt** = `1000 / fps` in *integer* milliseconds, 33 ms at 30 fps: both sources compute
//!    it with integer division, so every time constant below is turned into a coefficient with
//!    Δt = 33, not 33.3.
//! 2. **First frame primes**: it only stores the luminance; its output is the resting state
//!    (MP 0, SMP 0.5 = sigmoid(0), SFA 0.5 = the SFA floor, no spike, no collision). The
//!    delayed ON/OFF layers and the PM start at zero, as in both sources, so the first
//!    processed frames of an already-moving scene are barely inhibited: a start-up transient
//!    (with `colias()`, an alert at frame 2 of the grating, translating and receding
//!    clips). A controller should create (or reset) the model once and keep stepping it.
//! 3. **Borders replicate the edge pixel** (docs/lgmd2.md) for every 3x3 operation, in both
//!    parameter sets. (The firmware skips the 1-pixel frame border instead, leaving S = G = 0
//!    there: 338 of 7128 cells.)
//! 4. **G layer**: both sources (and the paper) scale by `ω = Δ_C + max|Ce| / C_w` with
//!    `C_w = 4`, and keep G where `G·C_de ≥ T_de` with `C_de = 0.5`, `T_de = 15` (that is
//!    G ≥ 30); docs/lgmd2.md step 6 says it that way. (One version of the reference divides by
//!    `0.01 + max|Ce|/4`, the same thing.) The Colias "G threshold 35" is the firmware's
//!    `CdeTde = 35` compared with G directly: `C_de = 1`, `T_de = 35`.
//! 5. **Colias `K_spi = 0.5` is the sigmoid's coefficient**: the firmware computes
//!    `SMP = 1 / (1 + exp(−MP / (N_cell · K_spi)))` and keeps the spike coefficient at 4
//!    (`a4 = 4`). So `colias()` has `c_sig = 0.5` (the reference's `C_sig = 1`) and
//!    `c_spi = 4`. (Read as the spike coefficient, 0.5 would cap the output at one spike a
//!    frame, which is not what the robot ran.)
//! 6. **"uint8 layers, kernels as shifts"** ([`Arithmetic::Uint8`], in `colias()`): the
//!    firmware's integer arithmetic is modelled where it truncates: P is a 7-bit signed
//!    difference (the firmware takes the 16-bit YUV word with Y in its high byte and shifts the
//!    difference right by 9, i.e. `ΔY >> 1`, clamped to ±127: [`Lgmd2Params::p_shift`] = 1; the
//!    project's `tasks::camera` notes the same 7 bits); ON/OFF are integers; each kernel
//!    product is a shift of one neighbour's integer value (`×2`, `>>1`, `>>2` for ON; `×1`,
//!    `>>2`, `>>3` for OFF), i.e. rounded down before summing; the inhibition is truncated to
//!    an integer; S is truncated to uint8; Ce is the integer mean `⌊Σ/9⌋`; G is truncated to
//!    uint8. Where the firmware's float-to-uint8 conversion can overflow (G = S·Ce/ω can exceed
//!    255, which is undefined behaviour in C), we saturate at 255. MP, SMP and SFA are floats,
//!    as in the firmware.
//! 7. **PM low-pass**: docs/lgmd2.md's recursive low-pass `pm(t) = α·mean|P| + (1−α)·pm(t−1)`, in
//!    both parameter sets (the reference's form). The firmware blends the current mean with the
//!    previous *unfiltered* mean instead (a two-tap filter); for sustained motion both settle to
//!    the same value.
//! 8. **ON/OFF split**: `P ≥ clip` (0.1) goes to ON, the rest to OFF; P is an integer, so
//!    P = 0 takes the OFF branch and adds |0| = 0: it excites neither. Colias has no
//!    carry-over (`dc = 0`).
//! 9. **Delayed inhibition**: `I = Σ_3x3 W·[α·X(t) + (1−α)·X(t−1)]`, `X(t−1)` being the
//!    previous ON (OFF) layer, with α per kernel position (centre / nearest / diagonal).
//! 10. **Spike count**: `n = ⌊exp(C_spi·(SFA − T_sp))⌋`, stored in a byte by both sources: capped
//!     at 255 here (it never gets near: SFA ≤ 1 gives at most 2 spikes a frame with the
//!     reference values, 3 with Colias').
//! 11. **The spike window is the "burst window"** ([`SpikeCounter`]): spikes accumulate over
//!     consecutive frames that each have at least one spike, and one silent frame (33 ms
//!     without a spike) empties the count. Both sources do exactly this (the reference's
//!     `Nsp`, the firmware's `n`), so the "short window" has no fixed length: it lasts as long
//!     as SFA stays above `T_sp`, which the SFA high-pass (τ_sfa) keeps short for anything but
//!     a steady rise of excitation. A fixed sliding window would be our invention. With ≤ 2
//!     (reference) or ≤ 3 (Colias) spikes a frame, an alert needs an unbroken burst of ≥ 4
//!     frames (133 ms) for the reference's 8 spikes and ≥ 2 frames (67 ms) for Colias' 4.
//!     Consequence: footage of a lower frame rate repeated at 30 fps (near-duplicate frames,
//!     MP = 0) breaks every burst, so it rarely alerts however strongly each real change fires.
//! 12. **Collision**: `accumulated ≥ n_sp`. The reference keeps reporting a collision on every
//!     frame of the burst from then on; the firmware raises its flag for one frame and empties
//!     the count (`reset_after_alert`), so a long burst alerts again every few frames.
//!     [`Lgmd2Output::accumulated`] is the count this frame was judged on (before that reset).

use alvs_tasks::{Frame, HEIGHT, PIXELS, WIDTH};

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
    fn store(self, v: f32, max: f32) -> f32 {
        match self {
            Arithmetic::Float => v,
            Arithmetic::Uint8 => truncate(v, max),
        }
    }
}

/// The firmware's float-to-integer conversion of a layer value: truncation toward 0 of a
/// non-negative value, saturating at `max` (≤ 65,535); a negative value or NaN gives 0.
#[inline(always)]
fn truncate(v: f32, max: f32) -> f32 {
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

/// docs/lgmd2.md 1, P layer: `P = (L(t) − L(t−1)) >> shift`, clamped to `±(255 >> shift)`
/// (the firmware's int8 range for shift 1). Only the common length of the slices is written.
pub fn p_layer(cur: &[u8], prev: &[u8], shift: u32, p: &mut [f32]) {
    let shift = shift.min(7);
    let lim = 255i16 >> shift;
    for ((o, &c), &q) in p.iter_mut().zip(cur).zip(prev) {
        // arithmetic shift: rounds toward −∞, like the firmware's `>> 9` on a signed int
        *o = ((c as i16 - q as i16) >> shift).clamp(-lim, lim) as f32;
    }
}

/// docs/lgmd2.md 2: the mean of |P| over the layer (0 for an empty layer).
pub fn mean_abs(p: &[f32]) -> f32 {
    if p.is_empty() {
        return 0.0;
    }
    lanes_sum(p, f32::abs) / p.len() as f32
}

/// `Σ f(v)` over 8 interleaved partial sums, which vectorise (a fixed order: deterministic;
/// exact for integer-valued layers, whose sums stay far below 2^24).
fn lanes_sum(v: &[f32], f: impl Fn(f32) -> f32) -> f32 {
    let mut acc = [0.0f32; 8];
    let chunks = v.chunks_exact(8);
    let tail: f32 = chunks.remainder().iter().map(|&x| f(x)).sum();
    for c in chunks {
        for (a, &x) in acc.iter_mut().zip(c) {
            *a += f(x);
        }
    }
    acc.iter().sum::<f32>() + tail
}

/// `max(0, max |v|)` over 8 interleaved partial maxima (NaN ignored).
fn lanes_max_abs(v: &[f32]) -> f32 {
    let mut acc = [0.0f32; 8];
    let chunks = v.chunks_exact(8);
    let tail = chunks
        .remainder()
        .iter()
        .fold(0.0f32, |m, x| m.max(x.abs()));
    for c in chunks {
        for (a, &x) in acc.iter_mut().zip(c) {
            *a = a.max(x.abs());
        }
    }
    acc.iter().fold(tail, |m, &a| m.max(a))
}

/// docs/lgmd2.md 2: `pm(t) = α·mean|P| + (1 − α)·pm(t−1)` with `α = Δt / (Δt + τ_PM)`.
pub fn pm_update(pm_prev: f32, mean_abs_p: f32, alpha: f32) -> f32 {
    alpha * mean_abs_p + (1.0 - alpha) * pm_prev
}

/// docs/lgmd2.md 2: `(W_i_on, W_i_off) = (max(pm / T_pm, on_base), max(pm / T_pm, off_base))`.
pub fn inhibition_biases(pm: f32, t_pm: f32, on_base: f32, off_base: f32) -> (f32, f32) {
    let r = pm / t_pm;
    // f32::max ignores a NaN (T_pm = 0 with pm = 0): the bases hold
    (r.max(on_base), r.max(off_base))
}

/// docs/lgmd2.md 3, ON/OFF split with carry-over:
/// `ON = P + dc·ON(t−1)` if `P ≥ clip` else `dc·ON(t−1)`;
/// `OFF = |P| + dc·OFF(t−1)` if `P < clip` else `dc·OFF(t−1)`.
/// In [`Arithmetic::Uint8`] the results are truncated to uint8.
#[allow(clippy::too_many_arguments)]
pub fn on_off_layer(
    p: &[f32],
    prev_on: &[f32],
    prev_off: &[f32],
    clip: f32,
    dc: f32,
    arithmetic: Arithmetic,
    on: &mut [f32],
    off: &mut [f32],
) {
    let cells = on
        .iter_mut()
        .zip(off.iter_mut())
        .zip(p)
        .zip(prev_on)
        .zip(prev_off);
    for ((((on, off), &p), &pon), &poff) in cells {
        let (exc_on, exc_off) = if p >= clip { (p, 0.0) } else { (0.0, p.abs()) };
        *on = arithmetic.store(exc_on + dc * pon, 255.0);
        *off = arithmetic.store(exc_off + dc * poff, 255.0);
    }
}

/// Cells of the `(width + 2) x (height + 2)` padded copy of a `width` x `height` grid.
fn padded_len(width: usize, height: usize) -> usize {
    (width + 2) * (height + 2)
}

/// Fills the 1-cell ring of a padded grid (row stride `width + 2`) from its interior: borders
/// replicate the edge cell (docs/lgmd2.md), so every 3x3 neighbourhood is a plain offset.
fn replicate_ring(pad: &mut [f32], width: usize, height: usize) {
    let wp = width + 2;
    for y in 1..=height {
        let row = &mut pad[y * wp..(y + 1) * wp];
        row[0] = row[1];
        row[width + 1] = row[width];
    }
    pad.copy_within(wp..2 * wp, 0);
    pad.copy_within(height * wp..(height + 1) * wp, (height + 1) * wp);
}

/// Row `r` of a padded grid from column `dx` on, `width` cells: element `x` is the cell at
/// column `x − 1 + dx` of row `r − 1` of the grid, so `(r, dx)` in `{y, y+1, y+2} x {0, 1, 2}`
/// are the 3x3 neighbourhood of row `y`, as slices of equal length (which vectorise).
fn shifted_row(pad: &[f32], width: usize, r: usize, dx: usize) -> &[f32] {
    let start = r * (width + 2) + dx;
    &pad[start..start + width]
}

/// Copies a grid into the interior of a padded grid and fills its ring.
fn pad_grid(src: &[f32], width: usize, height: usize, pad: &mut [f32]) {
    let wp = width + 2;
    for (y, row) in src.chunks_exact(width).take(height).enumerate() {
        pad[(y + 1) * wp + 1..(y + 1) * wp + 1 + width].copy_from_slice(row);
    }
    replicate_ring(pad, width, height);
}

/// docs/lgmd2.md 4, delayed lateral inhibition of one pathway:
/// `I = Σ_3x3 W · [α·X(t) + (1 − α)·X(t−1)]`, α = `alpha[0|1|2]` for the centre, the 4
/// nearest and the 4 diagonal cells; borders replicate the edge cell.
///
/// In [`Arithmetic::Uint8`] each product `W·X` is rounded down per cell (the firmware's
/// shifts) and the sum is truncated to an integer. Grids are `width` x `height`, row-major;
/// if a slice is shorter than that, nothing is written.
#[allow(clippy::too_many_arguments)]
pub fn lateral_inhibition(
    width: usize,
    height: usize,
    cur: &[f32],
    prev: &[f32],
    kernel: &Kernel3,
    alpha: [f32; 3],
    arithmetic: Arithmetic,
    out: &mut [f32],
) {
    let mut scratch = vec![0.0; 2 * padded_len(width, height)];
    lateral_inhibition_with(
        width,
        height,
        cur,
        prev,
        kernel,
        alpha,
        arithmetic,
        &mut scratch,
        out,
    );
}

/// [`lateral_inhibition`] with caller-provided scratch of `2·padded_len(width, height)`
/// cells (nothing is written if it is shorter).
#[allow(clippy::too_many_arguments)]
fn lateral_inhibition_with(
    width: usize,
    height: usize,
    cur: &[f32],
    prev: &[f32],
    kernel: &Kernel3,
    alpha: [f32; 3],
    arithmetic: Arithmetic,
    scratch: &mut [f32],
    out: &mut [f32],
) {
    let (n, np) = (width * height, padded_len(width, height));
    if n == 0 || cur.len() < n || prev.len() < n || out.len() < n || scratch.len() < 2 * np {
        return;
    }
    // one branch-free loop per arithmetic
    match arithmetic {
        Arithmetic::Float => {
            lateral::<false>(width, height, cur, prev, kernel, alpha, scratch, out)
        }
        Arithmetic::Uint8 => lateral::<true>(width, height, cur, prev, kernel, alpha, scratch, out),
    }
}

/// Truncation of a non-negative value when `Q` (the firmware's float-to-integer conversion,
/// saturating at `max`, NaN to 0), identity otherwise.
#[inline(always)]
fn store<const Q: bool>(v: f32, max: f32) -> f32 {
    if Q {
        truncate(v, max)
    } else {
        v
    }
}

/// The body of [`lateral_inhibition`]; `Q` = uint8 arithmetic. Checked sizes.
#[allow(clippy::too_many_arguments)]
fn lateral<const Q: bool>(
    width: usize,
    height: usize,
    cur: &[f32],
    prev: &[f32],
    kernel: &Kernel3,
    alpha: [f32; 3],
    scratch: &mut [f32],
    out: &mut [f32],
) {
    // the delayed, weighted contribution `α·W·X(t) + (1 − α)·W·X(t−1)` of a cell, each
    // product rounded down in uint8 arithmetic (the firmware's shifts); products stay far
    // below 65,535 (at most 2 · 255)
    let delayed = |weight: f32, a: f32, x: f32, xp: f32| {
        a * store::<Q>(weight * x, 65_535.0) + (1.0 - a) * store::<Q>(weight * xp, 65_535.0)
    };
    let (wp, np) = (width + 2, padded_len(width, height));
    // every cell's contribution as a nearest and as a diagonal cell, padded
    let (near, diag) = scratch.split_at_mut(np);
    for y in 0..height {
        let row = y * width..(y + 1) * width;
        let prow = (y + 1) * wp + 1..(y + 1) * wp + 1 + width;
        let cells = near[prow.clone()]
            .iter_mut()
            .zip(&mut diag[prow])
            .zip(&cur[row.clone()])
            .zip(&prev[row]);
        for (((n, d), &x), &xp) in cells {
            *n = delayed(kernel.near, alpha[1], x, xp);
            *d = delayed(kernel.diag, alpha[2], x, xp);
        }
    }
    replicate_ring(near, width, height);
    replicate_ring(diag, width, height);
    for y in 0..height {
        let row = y * width..(y + 1) * width;
        let shifted = |pad, r, dx| shifted_row(pad, width, y + r, dx);
        let (n_u, n_l, n_r, n_d) = (
            shifted(near, 0, 1),
            shifted(near, 1, 0),
            shifted(near, 1, 2),
            shifted(near, 2, 1),
        );
        let (d_ul, d_ur, d_dl, d_dr) = (
            shifted(diag, 0, 0),
            shifted(diag, 0, 2),
            shifted(diag, 2, 0),
            shifted(diag, 2, 2),
        );
        let (cur, prev, out) = (&cur[row.clone()], &prev[row.clone()], &mut out[row]);
        for x in 0..width {
            let centre = delayed(kernel.centre, alpha[0], cur[x], prev[x]);
            let nearest = n_u[x] + n_d[x] + n_l[x] + n_r[x];
            let diagonal = d_ul[x] + d_ur[x] + d_dl[x] + d_dr[x];
            out[x] = store::<Q>(centre + nearest + diagonal, 65_535.0);
        }
    }
}

/// The S layer's weights and the inhibition biases of one frame (docs/lgmd2.md 5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SWeights {
    /// W_i_on from [`inhibition_biases`].
    pub w_i_on: f32,
    /// W_i_off from [`inhibition_biases`].
    pub w_i_off: f32,
    /// Weight of S_on.
    pub w_on: f32,
    /// Weight of S_off.
    pub w_off: f32,
    /// Weight of S_on·S_off.
    pub w_onoff: f32,
}

/// docs/lgmd2.md 5, S layer: `S_x = max(0, X − W_i_x·I_x)` for ON and OFF, then
/// `S = w_on·S_on + w_off·S_off + w_onoff·S_on·S_off` (truncated to uint8 in
/// [`Arithmetic::Uint8`]).
pub fn s_layer(
    on: &[f32],
    off: &[f32],
    i_on: &[f32],
    i_off: &[f32],
    k: &SWeights,
    arithmetic: Arithmetic,
    s: &mut [f32],
) {
    let cells = s.iter_mut().zip(on).zip(off).zip(i_on).zip(i_off);
    for ((((s, &on), &off), &ion), &ioff) in cells {
        // f32::max(NaN, 0) is 0: a degenerate bias cannot poison the layer
        let s_on = (on - k.w_i_on * ion).max(0.0);
        let s_off = (off - k.w_i_off * ioff).max(0.0);
        *s = arithmetic.store(
            k.w_on * s_on + k.w_off * s_off + k.w_onoff * s_on * s_off,
            255.0,
        );
    }
}

/// G-layer constants (docs/lgmd2.md 6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GParams {
    /// Δ_C.
    pub delta_c: f32,
    /// C_w.
    pub c_w: f32,
    /// C_de.
    pub c_de: f32,
    /// T_de.
    pub t_de: f32,
}

/// docs/lgmd2.md 6, G layer: `Ce` = 3x3 mean of S (replicated border; `⌊Σ/9⌋` in
/// [`Arithmetic::Uint8`]), `ω = Δ_C + max|Ce| / C_w`, `G = S·Ce·(1/ω)` (truncated to uint8
/// in [`Arithmetic::Uint8`]), `G = 0` where `G·C_de < T_de`. Writes `ce` and `g`, returns
/// `MP = ΣG`. If a slice is shorter than `width·height`, nothing is written and MP is 0.
pub fn g_layer(
    width: usize,
    height: usize,
    s: &[f32],
    k: &GParams,
    arithmetic: Arithmetic,
    ce: &mut [f32],
    g: &mut [f32],
) -> f32 {
    let mut pad = vec![0.0; padded_len(width, height)];
    g_layer_with(width, height, s, k, arithmetic, &mut pad, ce, g)
}

/// [`g_layer`] with caller-provided scratch of `padded_len(width, height)` cells.
#[allow(clippy::too_many_arguments)]
fn g_layer_with(
    width: usize,
    height: usize,
    s: &[f32],
    k: &GParams,
    arithmetic: Arithmetic,
    pad: &mut [f32],
    ce: &mut [f32],
    g: &mut [f32],
) -> f32 {
    let n = width * height;
    if n == 0 || s.len() < n || ce.len() < n || g.len() < n || pad.len() < padded_len(width, height)
    {
        return 0.0;
    }
    pad_grid(s, width, height, pad);
    for (y, ce) in ce.chunks_exact_mut(width).take(height).enumerate() {
        // the 3x3 box sum from the padded rows y − 1, y, y + 1 shifted by −1, 0, +1 columns
        let rows = [0, 1, 2].map(|r| [0, 1, 2].map(|dx| shifted_row(pad, width, y + r, dx)));
        for (x, ce) in ce.iter_mut().enumerate() {
            let sum: f32 = rows.iter().flatten().map(|r| r[x]).sum();
            *ce = match arithmetic {
                Arithmetic::Float => sum / 9.0,
                // the integer division of an integer sum (≤ 9·255: exact in f32)
                Arithmetic::Uint8 => truncate(sum / 9.0, 255.0),
            };
        }
    }
    // both sources multiply by the reciprocal of the scale
    let inv_omega = 1.0 / (k.delta_c + lanes_max_abs(&ce[..n]) / k.c_w);
    for ((g, &s), &ce) in g.iter_mut().zip(s).zip(ce.iter()).take(n) {
        let v = arithmetic.store(s * ce * inv_omega, 255.0);
        // a NaN (a degenerate scale) fails the comparison and is dropped
        *g = if v * k.c_de >= k.t_de { v } else { 0.0 };
    }
    lanes_sum(&g[..n], |v| v)
}

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

/// What one frame gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lgmd2Output {
    /// PM (low-passed mean |P|) of this frame (docs/lgmd2.md 2).
    pub pm: f32,
    /// MP = ΣG (docs/lgmd2.md 6).
    pub mp: f32,
    /// Sigmoid membrane potential, 0.5..1 (docs/lgmd2.md 7).
    pub smp: f32,
    /// SMP after spike-frequency adaptation, ≥ 0.5 (docs/lgmd2.md 8).
    pub sfa: f32,
    /// Spikes this frame (docs/lgmd2.md 9).
    pub spikes: u32,
    /// Spikes of the current burst, this frame's included: what the collision is judged on.
    pub accumulated: u32,
    /// Collision alert: `accumulated ≥ n_sp`.
    pub collision: bool,
}

impl Lgmd2Output {
    /// The resting output (first frame, no motion).
    fn resting(sfa_floor: f32) -> Self {
        Lgmd2Output {
            pm: 0.0,
            mp: 0.0,
            smp: 0.5,
            sfa: sfa_floor,
            spikes: 0,
            accumulated: 0,
            collision: false,
        }
    }
}

/// Borrowed views of the layers of the last frame, 99x72 row-major (for pictures).
#[derive(Debug, Clone, Copy)]
pub struct Lgmd2Layers<'a> {
    /// P layer.
    pub p: &'a [f32],
    /// ON cells.
    pub on: &'a [f32],
    /// OFF cells.
    pub off: &'a [f32],
    /// ON inhibition.
    pub i_on: &'a [f32],
    /// OFF inhibition.
    pub i_off: &'a [f32],
    /// S layer.
    pub s: &'a [f32],
    /// G layer (after the threshold).
    pub g: &'a [f32],
}

/// Coefficients derived once from the parameters.
#[derive(Debug, Clone, Copy)]
struct Coefficients {
    alpha_pm: f32,
    alpha_on: [f32; 3],
    alpha_off: [f32; 3],
    hp_sfa: f32,
}

impl Coefficients {
    fn new(p: &Lgmd2Params) -> Self {
        let dt = p.dt_ms();
        let lp = |k: &Kernel3| k.tau_ms.map(|t| lowpass_coefficient(dt, t));
        Coefficients {
            alpha_pm: lowpass_coefficient(dt, p.tau_pm_ms),
            alpha_on: lp(&p.on_kernel),
            alpha_off: lp(&p.off_kernel),
            hp_sfa: sfa_coefficient(dt, p.tau_sfa_ms),
        }
    }
}

fn layer() -> Box<[f32]> {
    vec![0.0; PIXELS].into_boxed_slice()
}

/// The LGMD2 network on 99x72 frames: `new`, `step` each frame, `reset` between runs.
#[derive(Clone)]
pub struct Lgmd2 {
    params: Lgmd2Params,
    k: Coefficients,
    prev_frame: Box<Frame>,
    primed: bool,
    p: Box<[f32]>,
    on: Box<[f32]>,
    off: Box<[f32]>,
    on_prev: Box<[f32]>,
    off_prev: Box<[f32]>,
    i_on: Box<[f32]>,
    i_off: Box<[f32]>,
    s: Box<[f32]>,
    ce: Box<[f32]>,
    g: Box<[f32]>,
    /// scratch of the 3x3 operations: two padded layers
    scratch: Box<[f32]>,
    pm: f32,
    smp: f32,
    sfa: f32,
    counter: SpikeCounter,
}

impl std::fmt::Debug for Lgmd2 {
    /// The parameters and the scalar state, not the layers.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Lgmd2")
            .field("params", &self.params)
            .field("primed", &self.primed)
            .field("pm", &self.pm)
            .field("smp", &self.smp)
            .field("sfa", &self.sfa)
            .field("spike_count", &self.counter.count())
            .finish_non_exhaustive()
    }
}

impl Default for Lgmd2 {
    fn default() -> Self {
        Self::new(Lgmd2Params::default())
    }
}

impl Lgmd2 {
    /// A network at rest; the next frame primes it. Never panics, whatever the parameters.
    pub fn new(params: Lgmd2Params) -> Self {
        Lgmd2 {
            k: Coefficients::new(&params),
            smp: 0.5,
            sfa: params.sfa_floor,
            params,
            prev_frame: Box::new([0; PIXELS]),
            primed: false,
            p: layer(),
            on: layer(),
            off: layer(),
            on_prev: layer(),
            off_prev: layer(),
            i_on: layer(),
            i_off: layer(),
            s: layer(),
            ce: layer(),
            g: layer(),
            scratch: vec![0.0; 2 * padded_len(WIDTH, HEIGHT)].into_boxed_slice(),
            pm: 0.0,
            counter: SpikeCounter::default(),
        }
    }

    /// Back to the state of [`Lgmd2::new`]: the next frame primes again.
    pub fn reset(&mut self) {
        for l in [
            &mut self.p,
            &mut self.on,
            &mut self.off,
            &mut self.on_prev,
            &mut self.off_prev,
            &mut self.i_on,
            &mut self.i_off,
            &mut self.s,
            &mut self.ce,
            &mut self.g,
        ] {
            l.fill(0.0);
        }
        self.prev_frame.fill(0);
        self.primed = false;
        self.pm = 0.0;
        self.smp = 0.5;
        self.sfa = self.params.sfa_floor;
        self.counter = SpikeCounter::default();
    }

    /// The parameters.
    pub fn params(&self) -> &Lgmd2Params {
        &self.params
    }

    /// The layers of the last frame.
    pub fn layers(&self) -> Lgmd2Layers<'_> {
        Lgmd2Layers {
            p: &self.p,
            on: &self.on,
            off: &self.off,
            i_on: &self.i_on,
            i_off: &self.i_off,
            s: &self.s,
            g: &self.g,
        }
    }

    /// One frame through docs/lgmd2.md steps 1–9. The first frame after `new`/`reset` only primes
    /// (interpretation 2) and returns the resting output.
    pub fn step(&mut self, frame: &Frame) -> Lgmd2Output {
        let prm = &self.params;
        let ar = prm.arithmetic;
        if !self.primed {
            self.prev_frame.copy_from_slice(frame);
            self.primed = true;
            return Lgmd2Output::resting(prm.sfa_floor);
        }

        // 1. P layer
        p_layer(frame, &self.prev_frame[..], prm.p_shift, &mut self.p);
        self.prev_frame.copy_from_slice(frame);

        // 2. adaptive inhibition
        self.pm = pm_update(self.pm, mean_abs(&self.p), self.k.alpha_pm);
        let (w_i_on, w_i_off) =
            inhibition_biases(self.pm, prm.t_pm, prm.w_i_on_base, prm.w_i_off_base);

        // 3. ON/OFF (the current layers become the delayed ones)
        std::mem::swap(&mut self.on, &mut self.on_prev);
        std::mem::swap(&mut self.off, &mut self.off_prev);
        on_off_layer(
            &self.p,
            &self.on_prev,
            &self.off_prev,
            prm.clip,
            prm.dc,
            ar,
            &mut self.on,
            &mut self.off,
        );

        // 4. delayed lateral inhibition
        lateral_inhibition_with(
            WIDTH,
            HEIGHT,
            &self.on,
            &self.on_prev,
            &prm.on_kernel,
            self.k.alpha_on,
            ar,
            &mut self.scratch,
            &mut self.i_on,
        );
        lateral_inhibition_with(
            WIDTH,
            HEIGHT,
            &self.off,
            &self.off_prev,
            &prm.off_kernel,
            self.k.alpha_off,
            ar,
            &mut self.scratch,
            &mut self.i_off,
        );

        // 5. S layer
        let sw = SWeights {
            w_i_on,
            w_i_off,
            w_on: prm.w_on,
            w_off: prm.w_off,
            w_onoff: prm.w_onoff,
        };
        s_layer(
            &self.on,
            &self.off,
            &self.i_on,
            &self.i_off,
            &sw,
            ar,
            &mut self.s,
        );

        // 6. G layer and MP
        let gp = GParams {
            delta_c: prm.delta_c,
            c_w: prm.c_w,
            c_de: prm.c_de,
            t_de: prm.t_de,
        };
        let mp = g_layer_with(
            WIDTH,
            HEIGHT,
            &self.s,
            &gp,
            ar,
            &mut self.scratch,
            &mut self.ce,
            &mut self.g,
        );

        // 7. SMP
        let smp = sigmoid(mp, PIXELS, prm.c_sig);

        // 8. SFA
        let sfa = sfa_update(
            self.sfa,
            self.smp,
            smp,
            self.k.hp_sfa,
            prm.t_sfa,
            prm.sfa_floor,
        );
        self.smp = smp;
        self.sfa = sfa;

        // 9. spikes and collision
        let spikes = spike_count(sfa, prm.c_spi, prm.t_sp);
        let (accumulated, collision) = self.counter.push(spikes, prm.n_sp, prm.reset_after_alert);

        Lgmd2Output {
            pm: self.pm,
            mp,
            smp,
            sfa,
            spikes,
            accumulated,
            collision,
        }
    }
}
