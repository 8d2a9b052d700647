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
//! | step | what | function | file |
//! |---|---|---|---|
//! | 1 | P layer, `P = L(t) − L(t−1)` | [`p_layer`] | `photoreceptors.rs` |
//! | 2 | adaptive inhibition (PM pathway) | [`mean_abs`], [`pm_update`], [`inhibition_biases`] | `photoreceptors.rs` |
//! | 3 | ON/OFF split with carry-over | [`on_off_layer`] | `on_off.rs` |
//! | 4 | delayed lateral inhibition, 3x3 kernels | [`lateral_inhibition`] | `inhibition.rs` |
//! | 5 | S layer | [`s_layer`] | `s_layer.rs` |
//! | 6 | G layer, `Ce`, threshold, MP | [`g_layer`] | `g_layer.rs` |
//! | 7 | SMP sigmoid | [`sigmoid`] | `spikes.rs` |
//! | 8 | spike-frequency adaptation | [`sfa_update`] | `spikes.rs` |
//! | 9 | spikes, accumulation, collision | [`spike_count`], [`SpikeCounter`] | `spikes.rs` |
//!
//! The parameter sets are in `params.rs`, the padded 3x3 neighbourhoods and lane sums that
//! several layers share in `grid.rs`, and the network that runs them in order in `network.rs`.
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
//!    project's `tasks::robot::camera` notes the same 7 bits); ON/OFF are integers; each kernel
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

mod g_layer;
mod grid;
mod inhibition;
mod network;
mod on_off;
mod params;
mod photoreceptors;
mod s_layer;
mod spikes;

pub use g_layer::*;
pub use inhibition::*;
pub use network::*;
pub use on_off::*;
pub use params::*;
pub use photoreceptors::*;
pub use s_layer::*;
pub use spikes::*;
