//! The whole network: its state, one frame through steps 1–9, and its outputs and layers.

use alvs_tasks::{Frame, HEIGHT, PIXELS, WIDTH};

use super::g_layer::{g_layer_with, GParams};
use super::grid::padded_len;
use super::inhibition::lateral_inhibition_with;
use super::on_off::on_off_layer;
use super::params::{lowpass_coefficient, sfa_coefficient, Kernel3, Lgmd2Params};
use super::photoreceptors::{inhibition_biases, mean_abs, p_layer, pm_update};
use super::s_layer::{s_layer, SWeights};
use super::spikes::{sfa_update, sigmoid, spike_count, SpikeCounter};

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
