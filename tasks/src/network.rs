//! One perception step of the aLPLC2 network: the body of the firmware's perception task.
//!
//! Per frame, in the paper's order: retina and ON/OFF means (Eqs. 1–2), a new attention field
//! (Eq. 3), centroids (Eq. 4), fusion (Eq. 5), T4/T5 local motion and LPLC2 per field
//! (Eqs. 6–9), retirement (Eq. 10), then the visuomotor convergence (Eqs. 11–15).
//! The first frame only primes the retina and never alerts.
//!
//! State is fixed-size: the previous frame (7 KB), the ON/OFF maps at `t` (14 KB), their
//! delayed copies (14 KB, Eq. 6's `t − C_d`), and at most [`MAX_AFS`] fields.

use crate::attention::Fields;
use crate::frame::{Frame, PIXELS};
use crate::hrc::{LmScale, Maps};
use crate::lplc2::{self, Lplc2};
use crate::params::{ParamError, Params};
use crate::retina::{self, Weights};
use crate::visuomotor::Visuomotor;

/// Attention fields the network can hold at once. With Table I's `R_AF` = 36 on a 99x72
/// retina at most 3 x 2 field centres can lie outside each other's squares, so the
/// capacity is never the limit with the paper's parameters.
pub const MAX_AFS: usize = 6;

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
    /// `LPLC2_k(t)`, Eq. (9).
    pub lplc2: u32,
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

/// The aLPLC2 network.
#[derive(Clone)]
pub struct Network {
    params: Params,
    weights: Weights,
    scale: LmScale,
    prev: Frame,
    on: [u8; PIXELS],
    off: [u8; PIXELS],
    on_d: [u8; PIXELS],
    off_d: [u8; PIXELS],
    /// Delay-filter gain `1/C_d` in Q8.
    delay_q8: i32,
    frames: u32,
    fields: Fields,
}

impl Network {
    /// A network with validated parameters, waiting for its priming frame.
    pub fn new(params: Params) -> Result<Self, ParamError> {
        params.validate()?;
        Ok(Network {
            params,
            weights: Weights::new(&params),
            scale: LmScale::new(&params),
            prev: [0; PIXELS],
            on: [0; PIXELS],
            off: [0; PIXELS],
            on_d: [0; PIXELS],
            off_d: [0; PIXELS],
            delay_q8: delay_q8(&params),
            frames: 0,
            fields: Fields::default(),
        })
    }

    /// Replaces the parameters, keeping the state (fields, history).
    pub fn set_params(&mut self, params: Params) -> Result<(), ParamError> {
        params.validate()?;
        self.params = params;
        self.delay_q8 = delay_q8(&params);
        self.weights = Weights::new(&params);
        self.scale = LmScale::new(&params);
        Ok(())
    }

    /// Forgets everything seen: the next frame primes again (e.g. after a dropped frame).
    pub fn reset(&mut self) {
        self.frames = 0;
        self.on = [0; PIXELS];
        self.off = [0; PIXELS];
        self.on_d = [0; PIXELS];
        self.off_d = [0; PIXELS];
        self.fields.clear();
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
        Maps {
            on: &self.on,
            off: &self.off,
            on_d: &self.on_d,
            off_d: &self.off_d,
        }
    }

    /// Fixed-point weights of the ON/OFF maps (for pictures of `L̂_ON`, `L̂_OFF`, `L̂_t`).
    pub fn weights(&self) -> &Weights {
        &self.weights
    }

    /// Fixed-point factors of the local motion (for pictures of `LM_v`).
    pub fn lm_scale(&self) -> &LmScale {
        &self.scale
    }

    /// Processes one frame: the perception task's body.
    pub fn step(&mut self, frame: &Frame) -> Perception {
        let index = self.frames;
        self.frames = self.frames.saturating_add(1);
        if index == 0 {
            self.prev = *frame;
            return Perception {
                frame: index,
                afs: heapless::Vec::new(),
                vm: Visuomotor::from_fields(core::iter::empty(), &self.params),
            };
        }
        let p = self.params;
        // Eq. (6)'s delay line takes the maps of t − 1, then Eqs. (1)–(2) give those of t.
        delay(&mut self.on_d, &self.on, self.delay_q8);
        delay(&mut self.off_d, &self.off, self.delay_q8);
        retina::on_off_mean(frame, &self.prev, &mut self.on, &mut self.off);
        self.prev = *frame;

        // Eqs. (3)–(5).
        let (on, off) = (&self.on, &self.off);
        self.fields.spawn(on, off, &self.weights, &p);
        self.fields.recentre(on, off, &self.weights, &p);
        self.fields.fuse(p.r_af);

        // Eqs. (6)–(9) per field, then Eq. (10).
        let maps = self.maps();
        let regions: heapless::Vec<lplc2::Region, MAX_AFS> = self
            .fields
            .iter()
            .map(|f| {
                let (cols, rows) = f.square(p.r_af);
                let centre = (usize::from(f.x), usize::from(f.y));
                lplc2::Region { centre, cols, rows }
            })
            .collect();
        let mut lplc = [Lplc2::default(); MAX_AFS];
        lplc2::integrate_all(
            &maps,
            &self.scale,
            &regions,
            p.q_floor,
            p.q_balance,
            &mut lplc,
        );
        // (id, result) of every field alive during this frame, before Eq. (10) retires some
        let results: heapless::Vec<(u32, Lplc2), MAX_AFS> = self
            .fields
            .iter()
            .zip(lplc.iter())
            .map(|(f, l)| (f.id, *l))
            .collect();
        for (f, l) in self.fields.iter_mut().zip(lplc.iter()) {
            f.push_response(l.response);
        }
        self.fields.retire(p.d, p.t_d);

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
        let vm = Visuomotor::from_fields(afs.iter().map(|a| (a.x, a.lplc2)), &p);
        Perception {
            frame: index,
            afs,
            vm,
        }
    }
}

/// `1/C_d` in Q8 (256 = a pure one-frame delay).
fn delay_q8(p: &Params) -> i32 {
    (256.0 / p.c_d + 0.5) as i32
}

/// First-order low-pass delay line: `D ← D + (L − D)/C_d`, rounded to nearest but moving at
/// least one grey level while `D ≠ L` (8-bit rounding would otherwise leave `D` stuck up to
/// `C_d/2` levels off a steady input: a ghost the correlators would see). With `C_d = 1`
/// it copies `L`: the pure one-frame delay of the paper's Eq. (6); larger `C_d` delays by `C_d`
/// frames on average, tuning the correlators to slower motion at no extra memory.
pub fn delay(d: &mut [u8; PIXELS], l: &[u8; PIXELS], gain_q8: i32) {
    for (d, &l) in d.iter_mut().zip(l.iter()) {
        let diff = i32::from(l) - i32::from(*d);
        // |step| ≤ |diff| for gain ≤ 256 (C_d ≥ 1), so D never overshoots L nor leaves 0..=255;
        // and at least one grey level towards L, so D never sticks short of a steady input
        let step = (diff * gain_q8 + 128) >> 8;
        let step = if step == 0 { diff.signum() } else { step };
        *d = (i32::from(*d) + step) as u8;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::WIDTH;

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
