//! One perception step of the aLPLC2 network: the body of the firmware's perception task.
//!
//! Per frame, in the paper's order: retina and ON/OFF means (Eqs. 1–2), a new attention field
//! (Eq. 3), centroids (Eq. 4), fusion (Eq. 5), T4/T5 local motion and LPLC2 per field
//! (Eqs. 6–9), retirement (Eq. 10), then the visuomotor convergence (Eqs. 11–15).
//! The first frame only primes the retina and never alerts.
//!
//! State is fixed-size: the previous frame (7 KB), the ON/OFF maps at `t` (14 KB), their
//! delayed copies (14 KB, Eq. 6's `t − C_d`), and at most [`MAX_AFS`] fields.
//!
//! A frame enters either whole ([`Network::step`]) or row by row as the camera delivers it
//! ([`Network::push_row`] then [`Network::end_frame`]); both run the same code and give the
//! same output. Streaming is what lets the firmware keep no frame buffer (docs/firmware.md).

use crate::frame::{Frame, CENTRE_X, WIDTH};
use crate::model::attention::{self, Fields};
use crate::model::closed_loop::derotate::Turn;
use crate::model::closed_loop::floor;
use crate::model::closed_loop::luminance;
use crate::model::closed_loop::noise_frames;
use crate::model::closed_loop::progress;
use crate::model::hrc::{LmScale, Maps};
use crate::model::lplc2::{self, Lplc2};
use crate::model::param_table::off0;
use crate::model::params::{ParamError, Params};
use crate::model::retina::{delay_q8, Retina, RowError, Weights};
use crate::model::visuomotor::Visuomotor;

use crate::model::MAX_AFS;

/// Motion adaptation (`Params::adapt_frames`): the short mode needs `ΣLPLC2` above this many
/// times its running mean.
pub const ADAPT_RATIO: f32 = 2.0;

/// Forward speed above which the robot counts as driving (`Network::driving`), mm/s.
pub const DRIVING_MM_S: f32 = 20.0;

/// One attention field's output for a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AfReport {
    /// Field identifier, stable while the field lives.
    pub id: u32,
    /// Centroid column `x̄_k`.
    pub x: u8,
    /// Centroid row `ȳ_k`.
    pub y: u8,
    /// Frames the field has lived.
    pub age: u32,
    /// `Q1..Q4`, Eq. (8).
    pub quadrants: [u32; 4],
    /// `LPLC2_k(t)`, Eq. (9); with `Params::t_lplc2`, the field's output: its mean over `d`
    /// frames while above that threshold, else 0.
    pub lplc2: u32,
}

impl AfReport {
    /// Whether this field alerts within its first `d` frames that could alert
    /// (`Params::short_young`), on frame `frame` of the network (`Perception::frame`): the
    /// warm-up's frames (`Params::warmup`) do not count, since no field can alert in them.
    pub fn alerts_young(&self, frame: u32, p: &Params) -> bool {
        let after_warmup = frame
            .saturating_add(1)
            .saturating_sub(u32::from(off0(p.mechanisms.warmup)));
        self.lplc2 > 0 && self.age.min(after_warmup) <= u32::from(p.table1.d)
    }
}

/// Everything the perception task hands to motor control and telemetry for one frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Perception {
    /// Index of the frame (0 = the priming frame).
    pub frame: u32,
    /// The attention fields standing after this frame, oldest first.
    pub afs: heapless::Vec<AfReport, MAX_AFS>,
    /// The visuomotor signals: `ΣLPLC2`, `S`, `X̄`, `alert`, `short_mode`, escape angles.
    pub vm: Visuomotor,
}

impl Perception {
    /// This frame triggers an escape (some field is stimulated).
    pub fn alert(&self) -> bool {
        self.vm.alert
    }

    /// The short-mode escape is on (`ΣLPLC2 > T_s`).
    pub fn short_mode(&self) -> bool {
        self.vm.short_mode
    }
}

/// The stages of a step, in order, as [`Network::end_frame_marked`] reports their ends
/// (the firmware and the cycle model time them with the DWT cycle counter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Retina, ON/OFF, 3x3 mean and delay line, Eqs. (1)–(2), (6) (all rows).
    Retina,
    /// New fields, centroids, fusion, Eqs. (3)–(5).
    Attention,
    /// T4/T5 correlators, quadrants, LPLC2 gate, Eqs. (6)–(9).
    Motion,
    /// Retirement and the visuomotor convergence, Eqs. (10)–(15).
    Visuomotor,
}

/// The aLPLC2 network.
#[derive(Clone)]
pub struct Network {
    params: Params,
    weights: Weights,
    scale: LmScale,
    retina: Retina,
    frames: u32,
    fields: Fields,
    /// Running mean of `ΣLPLC2` (`Params::adapt_frames`).
    adapted: f32,
    /// The efference copy of forward motion for the next frame (`Network::driving`).
    driving: bool,
    /// The last frame was noise (`Params::noise_pct`): this one is measured against it.
    after_noise: bool,
}

impl Network {
    /// A network with validated parameters, waiting for its priming frame.
    pub fn new(params: Params) -> Result<Self, ParamError> {
        params.validate()?;
        Ok(Network {
            params,
            weights: Weights::new(&params),
            scale: LmScale::new(&params),
            retina: Retina::new(delay_q8(&params)),
            frames: 0,
            fields: Fields::default(),
            adapted: 0.0,
            driving: false,
            after_noise: false,
        })
    }

    /// The network with the paper's parameters ([`Params::PAPER`]), as a constant.
    pub const fn paper() -> Self {
        const P: Params = Params::PAPER;
        Self::with_valid(P)
    }

    /// The network with the default parameters ([`Params::ALVS`]), as a constant: the
    /// firmware places it in a `static` without building 35 KB on the stack first.
    pub const fn alvs() -> Self {
        const P: Params = Params::ALVS;
        Self::with_valid(P)
    }

    /// A network with parameters known to validate (the presets; a test holds them to it).
    const fn with_valid(p: Params) -> Self {
        Network {
            params: p,
            weights: Weights::new(&p),
            scale: LmScale::new(&p),
            retina: Retina::new(delay_q8(&p)),
            frames: 0,
            fields: Fields::new(),
            adapted: 0.0,
            driving: false,
            after_noise: false,
        }
    }

    /// Replaces the parameters, keeping the state (fields, history).
    pub fn set_params(&mut self, params: Params) -> Result<(), ParamError> {
        params.validate()?;
        self.params = params;
        self.retina.set_delay_q8(delay_q8(&params));
        self.weights = Weights::new(&params);
        self.scale = LmScale::new(&params);
        Ok(())
    }

    /// Forgets everything seen: the next frame primes again (e.g. after a dropped frame).
    pub fn reset(&mut self) {
        self.frames = 0;
        self.retina.reset();
        self.fields.clear();
        self.adapted = 0.0;
        self.after_noise = false;
    }

    /// The parameters in use.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Frames processed so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// The attention fields, oldest first.
    pub fn fields(&self) -> &Fields {
        &self.fields
    }

    /// The newest ON/OFF mean maps and those `C_d` frames older, as the correlators read them.
    pub fn maps(&self) -> Maps<'_> {
        self.retina.maps()
    }

    /// The last whole frame, exactly as it came in, until the efference copy of a turn
    /// ([`Network::turned`]) re-registers it for the next one: what the swarm's look reads
    /// after a step (the firmware keeps no other copy of a frame).
    pub fn frame(&self) -> &Frame {
        self.retina.prev()
    }

    /// Fixed-point weights of the ON/OFF maps (for pictures of `L̂_ON`, `L̂_OFF`, `L̂_t`).
    pub fn weights(&self) -> &Weights {
        &self.weights
    }

    /// Fixed-point factors of the local motion (for pictures of `LM_v`).
    pub fn lm_scale(&self) -> &LmScale {
        &self.scale
    }

    /// Processes one whole frame: [`Network::push_row`] for each row, then
    /// [`Network::end_frame`]. A streamed frame left unfinished is dropped first.
    pub fn step(&mut self, frame: &Frame) -> Perception {
        self.step_marked(frame, &mut |_| {})
    }

    /// [`Network::step`], calling `mark` as each [`Stage`] ends.
    pub fn step_marked(&mut self, frame: &Frame, mark: &mut impl FnMut(Stage)) -> Perception {
        self.abort_frame();
        for row in frame.chunks_exact(WIDTH) {
            if let Ok(row) = <&[u8; WIDTH]>::try_from(row) {
                let _ = self.retina.push_row(row);
            }
        }
        // `HEIGHT` rows went in, so the frame cannot end short.
        self.end_frame_marked(mark).unwrap_or_default()
    }

    /// The next row of a streamed frame (top to bottom): the retina stage runs as rows arrive.
    pub fn push_row(&mut self, row: &[u8; WIDTH]) -> Result<(), RowError> {
        self.retina.push_row(row)
    }

    /// Efference copy: the robot turned by `yaw_deg` degrees (positive = right) since the last
    /// frame; call it between frames, before the next frame's first row. With
    /// `Params::derotate` the retina's memory and the fields' centroids are re-registered to
    /// the new heading, so the turn itself causes no motion signal ([`crate::model::closed_loop::derotate`]);
    /// a turn beyond [`crate::model::closed_loop::derotate::MAX_TURN_DEG`] or not finite starts over (the
    /// next frame primes). Without it (the paper) the report is ignored. Returns false, doing
    /// nothing, while a streamed frame is half in.
    pub fn turned(&mut self, yaw_deg: f32) -> bool {
        if self.retina.rows() != 0 {
            return false;
        }
        if !self.params.efference.derotate {
            return true;
        }
        match Turn::new(yaw_deg) {
            Some(t) if t.is_zero() => {}
            Some(t) => {
                self.retina.turn(&t);
                for f in self.fields.iter_mut() {
                    (f.x, f.y) = t.moved(f.x, f.y);
                    f.drive_at = t.moved(f.drive_at.0, f.drive_at.1);
                }
            }
            None => self.reset(),
        }
        true
    }

    /// The efference copy of forward motion: the robot's forward speed, mm/s, until the next
    /// frame. Above [`DRIVING_MM_S`] the robot drives, and the mechanisms that need it apply to
    /// that frame: `Params::band_row`, `Params::floor_row`, `Params::short_cols` and
    /// `Params::short_row`. A robot that never reports
    /// (a camera on a stand, a clip) stands.
    pub fn driving(&mut self, forward_mm_s: f32) {
        self.driving = forward_mm_s > DRIVING_MM_S;
    }

    /// Drops a partly streamed frame. The rows taken have already replaced part of the
    /// previous frame and of the maps, so the network starts over (fields forgotten, the next
    /// frame primes).
    pub fn abort_frame(&mut self) {
        if self.retina.rows() != 0 {
            self.reset();
        }
    }

    /// Ends a streamed frame and runs the rest of the step. A frame with fewer than `HEIGHT`
    /// rows is refused and the network starts over ([`Network::abort_frame`]).
    pub fn end_frame(&mut self) -> Result<Perception, RowError> {
        self.end_frame_marked(&mut |_| {})
    }

    /// [`Network::end_frame`], calling `mark` as each [`Stage`] ends.
    pub fn end_frame_marked(
        &mut self,
        mark: &mut impl FnMut(Stage),
    ) -> Result<Perception, RowError> {
        let primed = match self.retina.end_frame() {
            Ok(primed) => primed,
            Err(e) => {
                self.reset();
                return Err(e);
            }
        };
        let index = self.frames;
        self.frames = self.frames.saturating_add(1);
        // `Params::noise_pct`: this frame, and the next one measured against it, show no image;
        // their change leaves the delay line, so later frames are not correlated with it
        let noise = self.params.mechanisms.noise_pct.is_some_and(|pct| {
            noise_frames::is_noise(&noise_frames::grain(self.retina.prev()), pct.get())
        });
        let after_noise = core::mem::replace(&mut self.after_noise, noise);
        if noise || after_noise {
            self.retina.forget_change();
        }
        mark(Stage::Retina);
        if !primed {
            return Ok(Perception {
                frame: index,
                afs: heapless::Vec::new(),
                vm: Visuomotor::from_fields(core::iter::empty(), &self.params),
            });
        }
        let p = self.params;

        // Eqs. (3)–(5).
        let maps = self.retina.maps();
        // changing pixels, counted once for `Params::t_a_quiet` and `Params::flicker_pct`
        let changing = if p.mechanisms.t_a_quiet.is_some() || p.mechanisms.flicker_pct.is_some() {
            luminance::changing(maps.cells)
        } else {
            (0, 0, 0)
        };
        let t_a = attention::spawn_threshold(changing, &p);
        self.fields.spawn_above(&maps, &self.weights, &p, t_a);
        self.fields.recentre(&maps, &self.weights, &p);
        self.fields.fuse(p.exclusion());
        mark(Stage::Attention);

        // Eqs. (6)–(9) per field, then Eq. (10).
        let regions: heapless::Vec<lplc2::Region, MAX_AFS> = self
            .fields
            .iter()
            .map(|f| {
                let (cols, rows) = f.square(p.table1.r_af);
                let centre = (usize::from(f.x), usize::from(f.y));
                lplc2::Region { centre, cols, rows }
            })
            .collect();
        let mut lplc = [Lplc2::default(); MAX_AFS];
        lplc2::integrate_all(
            &maps,
            &self.scale,
            &regions,
            &lplc2::Gate::of(&p),
            &mut lplc,
        );
        mark(Stage::Motion);
        // `Params::q_grow_pct`: a partial opening needs a growing drive at the same place
        let gate = lplc2::Gate::of(&p);
        // fields silenced on this frame (`Params::t_lplc2` passes on 0 for them)
        let mut muted = [false; MAX_AFS];
        for ((f, l), muted) in self.fields.iter_mut().zip(lplc.iter_mut()).zip(&mut muted) {
            // `Params::border_arms`: standing, a quadrant the side border cuts off is blind
            let history = f.age >= u32::from(p.table1.d);
            if p.mechanisms.border_arms && !self.driving && history && l.response == 0 {
                let cut = lplc2::cut_sides(
                    usize::from(f.x),
                    p.table1.r_af,
                    p.mechanisms.border_crossing,
                );
                if lplc2::excited_at_border(l.quadrants, &gate, cut) >= usize::from(gate.arms) {
                    l.response = lplc2::drive(l.quadrants);
                }
            }
            let last = (f.shift_since_drive() <= lplc2::GROW_SHIFT_PX).then_some(f.drive);
            let now = lplc2::drive(l.quadrants);
            f.drive_run = lplc2::growth_run(f.drive_run, last, now);
            // `Params::q_grow_run`: a steady approach's run of growth stands as well
            let grew_in_a_row = p
                .mechanisms
                .q_grow_run
                .is_some_and(|n| f.drive_run >= n.get());
            if !grew_in_a_row
                && !lplc2::partial_opening_grows(
                    l.quadrants,
                    &gate,
                    last,
                    off0(p.mechanisms.q_grow_pct),
                )
            {
                l.response = 0;
            }
            f.drive = now;
            f.drive_at = (f.x, f.y);
            // `Params::band_row`: driving, the scene above the body's height is its own flow
            if self.driving && p.efference.band_row.is_some_and(|row| f.y < row.get()) {
                l.response = 0;
                *muted = true;
            }
        }
        // Closed-loop mechanisms (`Params::warmup`, `Params::flicker_pct`, `Params::noise_pct`):
        // while the history fills after a (re)start, on a whole-field luminance event, and on
        // a noise frame and the frame after it, no field is stimulated (and the floor line says
        // nothing either).
        let silent = index < u32::from(off0(p.mechanisms.warmup))
            || luminance::is_event_of(changing, off0(p.mechanisms.flicker_pct))
            || noise
            || after_noise;
        if silent {
            for l in lplc.iter_mut() {
                l.response = 0;
            }
        }
        // (id, result) of every field alive during this frame, before Eq. (10) retires some
        let mut results: heapless::Vec<(u32, Lplc2), MAX_AFS> = self
            .fields
            .iter()
            .zip(lplc.iter())
            .map(|(f, l)| (f.id, *l))
            .collect();
        for (f, l) in self.fields.iter_mut().zip(lplc.iter()) {
            f.push_response(l.response);
        }
        if let Some(t_lplc2) = p.firmware.t_lplc2 {
            // `Params::t_lplc2`: a field passes on its mean over `d` frames while above it
            for ((f, (_, l)), muted) in self.fields.iter().zip(results.iter_mut()).zip(muted) {
                let mean = f.window_mean(p.table1.d);
                l.response = if mean > t_lplc2.get() && !muted && !silent {
                    mean
                } else {
                    0
                };
            }
        }
        if p.firmware.strict_retire {
            self.fields
                .retire_strict(p.table1.d, u32::from(p.table1.t_d));
        } else {
            self.fields.retire(p.table1.d, u32::from(p.table1.t_d));
        }

        let mut afs: heapless::Vec<AfReport, MAX_AFS> = heapless::Vec::new();
        for f in self.fields.iter() {
            if let Some((_, l)) = results.iter().find(|(id, _)| *id == f.id) {
                let _ = afs.push(AfReport {
                    id: f.id,
                    x: f.x,
                    y: f.y,
                    age: f.age,
                    quadrants: l.quadrants,
                    lplc2: l.response,
                });
            }
        }
        let mut vm = Visuomotor::from_fields(afs.iter().map(|a| (a.x, a.lplc2)), &p);
        if p.short.short_uncut && !self.driving {
            // `Params::short_uncut`: not driving, a field cut by a side border counts whole
            let uncut = afs.iter().fold(0u32, |acc, a| {
                acc.saturating_add(lplc2::uncut_response(
                    a.lplc2,
                    usize::from(a.x),
                    p.table1.r_af,
                ))
            });
            // the uncut sum is at least ΣLPLC2: the short mode only widens
            vm.short_mode |= uncut > p.table1.t_s;
        }
        if p.short.short_young && !self.driving {
            // `Params::short_young`: not driving, an alert in a field's first `d` frames
            // (a field born in the warm-up counts from its end)
            vm.short_mode |= afs.iter().any(|a| a.alerts_young(index, &p));
        }
        if let Some(frames) = p.short.adapt_frames {
            // motion adaptation: the short mode needs a response above twice its recent mean
            let sum = vm.lplc2_sum as f32;
            vm.short_mode &= sum > ADAPT_RATIO * self.adapted;
            self.adapted += (sum - self.adapted) / f32::from(frames.get());
        }
        if let Some(cols) = p.short.short_cols.filter(|_| self.driving) {
            // `Params::short_cols`: driving, only a threat in the path is imminent
            let cols = f32::from(cols.get());
            vm.short_mode &= vm.threat_x.is_some_and(|x| (x - CENTRE_X).abs() <= cols);
        }
        if let Some(near) = p.short.short_row.filter(|_| self.driving && vm.short_mode) {
            // `Params::short_row`: driving, only a threat within a second's travel is imminent
            // (the short mode has a threat: ΣLPLC2 > T_s). X̄ is truncated to its column: rounding
            // changed 1 of 10 arena runs (seeds 1–5, both wall sets), by one collision more.
            let prev = self.retina.prev();
            vm.short_mode &= vm.threat_x.is_some_and(|x| {
                floor::nearest_foot(prev, x as u8).is_some_and(|row| row >= near.get())
            });
        }
        if let Some(change) = p.efference.blocked_change {
            vm.view = Some((progress::view(self.retina.prev()), change.get()));
        }
        if self.driving && p.efference.floor_row.is_some() && !silent {
            if let Some(x) = self.floor_line() {
                vm.ahead(x, &p);
            }
        }
        mark(Stage::Visuomotor);
        Ok(Perception {
            frame: index,
            afs,
            vm,
        })
    }

    /// `Params::floor_row`: the column of an obstacle close ahead. Kept out of the frame step
    /// so that its locals do not add to the step's frame under the deepest path (the
    /// firmware's stack budget).
    #[inline(never)]
    fn floor_line(&self) -> Option<u8> {
        floor::obstacle_ahead(self.retina.prev(), off0(self.params.efference.floor_row))
    }

    /// FNV-1a digest of the whole state (maps, previous frame, fields, counters): equal
    /// digests after equal inputs prove two builds of this code (host, Cortex-M4) agree bit
    /// for bit.
    pub fn digest(&self) -> u32 {
        let mut h = Fnv::new();
        h.bytes(self.retina.prev());
        for &c in self.retina.maps().cells {
            h.u32(c);
        }
        h.u32(self.frames);
        for f in self.fields.iter() {
            h.u32(f.id);
            h.bytes(&[f.x, f.y]);
            h.u32(f.age);
            h.u32(f.response());
        }
        h.finish()
    }
}

/// 32-bit FNV-1a.
pub struct Fnv(u32);

impl Fnv {
    /// The offset basis.
    pub fn new() -> Self {
        Fnv(0x811c_9dc5)
    }

    /// Hashes bytes.
    pub fn bytes(&mut self, b: &[u8]) {
        for &b in b {
            self.0 = (self.0 ^ u32::from(b)).wrapping_mul(0x0100_0193);
        }
    }

    /// Hashes a word, little-endian.
    pub fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }

    /// The digest.
    pub fn finish(&self) -> u32 {
        self.0
    }
}

impl Default for Fnv {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::PIXELS;
    use crate::model::params::Mechanisms;
    use crate::model::retina::delay;

    #[test]
    fn the_first_frame_primes_and_never_alerts() {
        let mut n = Network::new(Params::default()).unwrap();
        let out = n.step(&[0; PIXELS]);
        assert_eq!(out.frame, 0);
        assert!(!out.alert() && out.afs.is_empty());
        assert_eq!(out.vm.strength, 0.5, "S of an empty field set, Eq. (11)");
        // a huge change on the second frame is seen
        let out = n.step(&[255; PIXELS]);
        assert_eq!(out.frame, 1);
        assert_eq!(out.afs.len(), 1, "global flicker makes a field");
        assert!(!out.alert(), "but no looming");
    }

    #[test]
    fn the_delay_line_is_a_pure_delay_at_c_d_1_and_a_low_pass_beyond() {
        let mut d = [0u8; PIXELS];
        let l = [200u8; PIXELS];
        delay(&mut d, &l, 256);
        assert_eq!(d[0], 200);
        let mut d = [0u8; PIXELS];
        // C_d = 2: 100, 150, 175, ... towards 200
        for expect in [100, 150, 175, 188] {
            delay(&mut d, &l, 128);
            assert_eq!(d[7], expect);
        }
        let mut d = [255u8; PIXELS];
        delay(&mut d, &[0; PIXELS], 16);
        assert_eq!(d[0], 239, "falls by (255·16 − 128)/256 rounded");
        // small differences still converge: no ghost left in the delayed map
        for gain in [128, 16] {
            let mut d = [9u8; PIXELS];
            for _ in 0..40 {
                delay(&mut d, &[0; PIXELS], gain);
            }
            assert_eq!(d[0], 0, "gain {gain}");
            let mut d = [0u8; PIXELS];
            for _ in 0..200 {
                delay(&mut d, &[200; PIXELS], gain);
            }
            assert_eq!(d[0], 200, "gain {gain}");
        }
    }

    /// `short_young` counts a field's frames from the warm-up's end: a field born in the
    /// warm-up, when nothing can alert, is as young as the frames it could have alerted in.
    #[test]
    fn a_fields_youth_counts_from_the_warm_ups_end() {
        let p = Params::default();
        let (d, warmup) = (u32::from(p.table1.d), u32::from(off0(p.mechanisms.warmup)));
        assert_eq!((d, warmup), (4, 4), "Table I's d; the default's warm-up");
        let alerting = |age| AfReport {
            age,
            lplc2: 1,
            ..AfReport::default()
        };
        // born on frame 1, in the warm-up: young until its 4th frame after it
        assert!(alerting(7).alerts_young(7, &p), "frames 4..=7 could alert");
        assert!(!alerting(8).alerts_young(8, &p), "frames 4..=8 could alert");
        // born after the warm-up: its own age
        assert!(alerting(4).alerts_young(20, &p));
        assert!(!alerting(5).alerts_young(20, &p));
        assert!(
            !AfReport::default().alerts_young(5, &p),
            "silent fields are never young"
        );
        // without a warm-up every frame counts
        let no_warmup = Params {
            mechanisms: Mechanisms {
                warmup: None,
                ..p.mechanisms
            },
            ..p
        };
        assert!(!alerting(7).alerts_young(7, &no_warmup));
    }

    fn square(t: usize) -> Frame {
        let mut f = [200u8; PIXELS];
        let half = 3 + 2 * t;
        for y in 36usize.saturating_sub(half)..(36 + half).min(72) {
            for x in 49usize.saturating_sub(half)..(49 + half).min(WIDTH) {
                f[y * WIDTH + x] = 20;
            }
        }
        f
    }

    #[test]
    fn streamed_rows_and_whole_frames_give_the_same_perception() {
        let mut whole = Network::new(Params::default()).unwrap();
        let mut rows = Network::new(Params::default()).unwrap();
        for t in 0..12 {
            let f = square(t);
            let a = whole.step(&f);
            for r in f.chunks_exact(WIDTH) {
                rows.push_row(r.try_into().unwrap()).unwrap();
            }
            let b = rows.end_frame().unwrap();
            assert_eq!(a, b, "frame {t}");
            assert_eq!(whole.digest(), rows.digest());
        }
        assert!(whole.fields().len() == 1, "the square is tracked");
    }

    #[test]
    fn a_torn_frame_is_refused_and_the_network_starts_over() {
        let mut n = Network::new(Params::default()).unwrap();
        for t in 0..6 {
            n.step(&square(t));
        }
        assert!(!n.fields().is_empty());
        for r in square(6).chunks_exact(WIDTH).take(40) {
            n.push_row(r.try_into().unwrap()).unwrap();
        }
        assert_eq!(n.end_frame(), Err(RowError::Short { rows: 40 }));
        assert!(n.fields().is_empty() && n.frames() == 0);
        let out = n.step(&square(7));
        assert_eq!(out.frame, 0, "the next frame primes");
        // and a frame left half-streamed before a whole step is dropped the same way
        n.push_row(&[0; WIDTH]).unwrap();
        assert_eq!(n.step(&square(8)).frame, 0);
    }

    #[test]
    fn stages_are_marked_in_order_once_each() {
        let mut n = Network::new(Params::default()).unwrap();
        let mut seen = heapless::Vec::<Stage, 8>::new();
        n.step_marked(&square(0), &mut |s| seen.push(s).unwrap());
        assert_eq!(&seen[..], &[Stage::Retina], "priming ends after the retina");
        seen.clear();
        n.step_marked(&square(1), &mut |s| seen.push(s).unwrap());
        let all = [
            Stage::Retina,
            Stage::Attention,
            Stage::Motion,
            Stage::Visuomotor,
        ];
        assert_eq!(&seen[..], &all);
    }

    #[test]
    fn the_digest_sees_every_part_of_the_state() {
        let mut a = Network::new(Params::default()).unwrap();
        let d0 = a.digest();
        a.step(&square(0));
        let d1 = a.digest();
        assert_ne!(d0, d1, "previous frame");
        let mut b = a.clone();
        a.step(&square(1));
        b.step(&square(2));
        assert_ne!(a.digest(), b.digest());
        assert_eq!(Network::new(Params::default()).unwrap().digest(), d0);
    }

    #[test]
    fn an_expanding_dark_square_alerts() {
        let mut n = Network::new(Params::default()).unwrap();
        let mut alerts = 0;
        for t in 0..20usize {
            let mut f = [200u8; PIXELS];
            let half = 3 + 2 * t;
            for y in 36usize.saturating_sub(half)..(36 + half).min(72) {
                for x in 49usize.saturating_sub(half)..(49 + half).min(WIDTH) {
                    f[y * WIDTH + x] = 20;
                }
            }
            alerts += usize::from(n.step(&f).alert());
        }
        assert!(alerts > 5, "{alerts}");
    }
}
