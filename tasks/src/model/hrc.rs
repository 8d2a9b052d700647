//! T4 (ON) and T5 (OFF) Hassenstein–Reichardt correlators and local motion: Eqs. (6)–(7).
//!
//! For a preferred direction `v` with unit step `(dx, dy)`, pixel `p` and its `c`-th connected
//! neuron `q = p + c·s·(dx, dy)`:
//!
//! `T(p,t) = Σ_{c=1..n} [ L(q,t)·L(p,t−C_d) − L(q,t−C_d)·L(p,t) ]`
//!
//! The paper prints the second term as `L(p,t)·L(q,t)`, which has no delay and would make the
//! detector respond to flicker; this is the standard opponent HRC it cites (`docs/model.md`).
//! A change that travels from `p` to `q` makes the first term win: `T > 0` is motion along `v`.
//! Neurons that fall outside the retina contribute 0.
//!
//! Local motion, Eq. (7): `LM_v = T4_v + T5_v` in model units (`L̂_ON = gain·w·on`,
//! `L̂_OFF = gain·off`), scaled by `2^−lm_shift`, then half-wave rectified: T4/T5 synapses only
//! excite (`docs/model.md` explains why rectification is per pixel).

use crate::frame::{HEIGHT, PIXELS, WIDTH};
use crate::model::params::Params;

/// The four cardinal directions of the lobula plate layers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Rightward (+x).
    Right,
    /// Leftward (−x).
    Left,
    /// Downward (+y, rows grow downwards).
    Down,
    /// Upward (−y).
    Up,
}

impl Direction {
    /// All four, in the paper's order r, l, d, u.
    pub const ALL: [Direction; 4] = [
        Direction::Right,
        Direction::Left,
        Direction::Down,
        Direction::Up,
    ];

    /// Unit step `(dx, dy)` of the direction.
    pub const fn step(self) -> (isize, isize) {
        match self {
            Direction::Right => (1, 0),
            Direction::Left => (-1, 0),
            Direction::Down => (0, 1),
            Direction::Up => (0, -1),
        }
    }

    /// One-letter name used in pictures and logs.
    pub const fn letter(self) -> char {
        match self {
            Direction::Right => 'r',
            Direction::Left => 'l',
            Direction::Down => 'd',
            Direction::Up => 'u',
        }
    }
}

/// One pixel's four stored values in a word, one byte each: `on | off << 8 | on_d << 16 |
/// off_d << 24` (the ON and OFF means at `t` and at `t − C_d`).
///
/// Why interleaved: one word load gives a pixel's whole state, and the byte order makes each
/// channel's `t` and `t − C_d` values the two 16-bit lanes the correlators multiply,
/// `[on | on_d << 16] = c & 0x00FF00FF` and `[off | off_d << 16] = c >> 8 & 0x00FF00FF`
/// (one `UXTB16` each on the Cortex-M4), while attention reads `on`, `off` from the low half.
/// Four byte maps take the same 28.5 KB.
pub type Cells = [u32; PIXELS];

/// Which byte of a [`Cells`] word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layer {
    /// ON mean at `t`.
    On = 0,
    /// OFF mean at `t`.
    Off = 1,
    /// ON mean at `t − C_d`.
    OnD = 2,
    /// OFF mean at `t − C_d`.
    OffD = 3,
}

impl Layer {
    /// All four, in byte order.
    pub const ALL: [Layer; 4] = [Layer::On, Layer::Off, Layer::OnD, Layer::OffD];
}

/// The cell of one pixel from its four values.
#[inline(always)]
pub const fn cell(on: u8, off: u8, on_d: u8, off_d: u8) -> u32 {
    u32::from_le_bytes([on, off, on_d, off_d])
}

/// Cells from four byte maps, in [`Layer`] order (tests, pictures).
pub fn cells_of(planes: [&[u8; PIXELS]; 4]) -> Cells {
    let [on, off, on_d, off_d] = planes;
    core::array::from_fn(|i| cell(on[i], off[i], on_d[i], off_d[i]))
}

/// The ON and OFF maps at `t` and `t − C_d` that the correlators read, as [`Cells`].
#[derive(Clone, Copy)]
pub struct Maps<'a> {
    /// One word per pixel, row-major.
    pub cells: &'a Cells,
}

impl<'a> Maps<'a> {
    /// The maps held in `cells`.
    pub const fn new(cells: &'a Cells) -> Self {
        Maps { cells }
    }

    /// `layer` at pixel index `i` (0 off the retina).
    #[inline(always)]
    pub fn get(&self, layer: Layer, i: usize) -> u8 {
        self.cells
            .get(i)
            .map_or(0, |&c| (c >> (8 * layer as u32)) as u8)
    }

    /// `on` at pixel index `i`.
    #[inline(always)]
    pub fn on(&self, i: usize) -> u8 {
        self.get(Layer::On, i)
    }

    /// `off` at pixel index `i`.
    #[inline(always)]
    pub fn off(&self, i: usize) -> u8 {
        self.get(Layer::Off, i)
    }

    /// `on_d` at pixel index `i`.
    #[inline(always)]
    pub fn on_d(&self, i: usize) -> u8 {
        self.get(Layer::OnD, i)
    }

    /// `off_d` at pixel index `i`.
    #[inline(always)]
    pub fn off_d(&self, i: usize) -> u8 {
        self.get(Layer::OffD, i)
    }

    /// One layer as a byte map (tests, pictures).
    pub fn plane(&self, layer: Layer) -> [u8; PIXELS] {
        core::array::from_fn(|i| self.get(layer, i))
    }
}

/// Fixed-point factors of Eq. (7), set once per parameter set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LmScale {
    /// `(gain·w)²` in Q16: weight of T4 (built from unweighted stored bytes). Q16 keeps a
    /// small ON weight from rounding to 0 (Q8 would at `gain·w < 1/32`).
    pub t4_q16: i64,
    /// `gain²` in Q16: weight of T5.
    pub t5_q16: i64,
    /// `16 + lm_shift`.
    pub shift: u32,
    /// Connected neurons `n`.
    pub n: usize,
    /// Spacing `s` in pixels.
    pub s: usize,
    /// Eq. (6)'s opponent subtraction (`Params::opponent`); without it only the
    /// preferred-direction products `L(q,t)·L(p,t−C_d)` are summed.
    pub opponent: bool,
}

impl LmScale {
    /// Factors for `p` (assumed validated).
    pub const fn new(p: &Params) -> Self {
        let gw = p.choices.gain as f32 * p.table1.w;
        LmScale {
            t4_q16: (gw * gw * 65536.0 + 0.5) as i64,
            t5_q16: p.choices.gain as i64 * p.choices.gain as i64 * 65536,
            shift: 16 + p.choices.lm_shift as u32,
            n: p.table1.n as usize,
            s: p.choices.s as usize,
            opponent: p.firmware.opponent,
        }
    }
}

/// Eq. (6) for one channel: the opponent correlator sum at pixel `(x, y)` along `dir`, on the
/// stored byte maps (grey-level² units).
#[inline]
pub fn correlate(
    now: &[u8; PIXELS],
    delayed: &[u8; PIXELS],
    x: usize,
    y: usize,
    dir: Direction,
    n: usize,
    s: usize,
) -> i32 {
    let (dx, dy) = dir.step();
    let p = y * WIDTH + x;
    let (a_now, a_del) = (i32::from(now[p]), i32::from(delayed[p]));
    let mut t = 0i32;
    for c in 1..=n {
        let reach = (c * s) as isize;
        let qx = x as isize + dx * reach;
        let qy = y as isize + dy * reach;
        if qx < 0 || qy < 0 || qx >= WIDTH as isize || qy >= HEIGHT as isize {
            break; // farther neurons are outside too
        }
        let q = qy as usize * WIDTH + qx as usize;
        t += i32::from(now[q]) * a_del - i32::from(delayed[q]) * a_now;
    }
    t
}

/// Eq. (7), rectified: `max(0, T4 + T5)` at `(x, y)` along `dir`, in model units.
///
/// Both channels in one loop over the neurons that lie on the retina (the same sums as
/// [`correlate`], which stays the plain reference). Without `sc.opponent` (the authors'
/// firmware) the subtracted products are left out: `T = Σ_c L(q,t)·L(p,t−C_d)`, which a change
/// that does not move excites too.
#[inline]
pub fn local_motion(m: &Maps, sc: &LmScale, x: usize, y: usize, dir: Direction) -> u32 {
    let s = sc.s.max(1);
    let (room, stride) = match dir {
        Direction::Right => (WIDTH - 1 - x, 1isize),
        Direction::Left => (x, -1),
        Direction::Down => (HEIGHT - 1 - y, WIDTH as isize),
        Direction::Up => (y, -(WIDTH as isize)),
    };
    let count = sc.n.min(room / s);
    let step = stride * s as isize;
    let p = y * WIDTH + x;
    let (on_p, on_dp) = (i32::from(m.on(p)), i32::from(m.on_d(p)));
    let (off_p, off_dp) = (i32::from(m.off(p)), i32::from(m.off_d(p)));
    // preferred-direction and subtracted (null) products, per channel
    let (mut t4, mut t5, mut n4, mut n5) = (0i32, 0i32, 0i32, 0i32);
    let mut q = p as isize;
    for _ in 0..count {
        q += step;
        let qi = q as usize; // on the retina: count ≤ room / s
        t4 += i32::from(m.on(qi)) * on_dp;
        n4 += i32::from(m.on_d(qi)) * on_p;
        t5 += i32::from(m.off(qi)) * off_dp;
        n5 += i32::from(m.off_d(qi)) * off_p;
    }
    if sc.opponent {
        (t4, t5) = (t4 - n4, t5 - n5);
    }
    let lm = (sc.t4_q16 * i64::from(t4) + sc.t5_q16 * i64::from(t5)) >> sc.shift;
    lm.clamp(0, i64::from(u32::MAX)) as u32
}

/// The rectified local-motion map of one direction over the whole retina (for pictures).
pub fn motion_map(m: &Maps, sc: &LmScale, dir: Direction, out: &mut [u32; PIXELS]) {
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            out[y * WIDTH + x] = local_motion(m, sc, x, y, dir);
        }
    }
}

/// Four pseudo-random byte maps (on, off, on_d, off_d) with motion in every direction, for
/// tests that compare fast paths against the plain references.
#[cfg(test)]
pub(crate) fn random_maps(seed: u32) -> [[u8; PIXELS]; 4] {
    let mut seed = seed;
    let mut maps = [[0u8; PIXELS]; 4];
    for v in maps.iter_mut().flat_map(|m| m.iter_mut()) {
        seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12345);
        *v = (seed >> 16) as u8;
    }
    maps
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::params::{Choices, TableOne};

    /// A bright vertical bar at column `x0` (rows 30..40) and its position one frame earlier.
    fn bar(x0: usize, y0: usize, vertical: bool) -> [u8; PIXELS] {
        let mut m = [0u8; PIXELS];
        for k in 0..10 {
            let (x, y) = if vertical { (x0, y0 + k) } else { (x0 + k, y0) };
            m[y * WIDTH + x] = 100;
        }
        m
    }

    fn response(dir: Direction, from: (usize, usize), to: (usize, usize), vertical: bool) -> i32 {
        // the edge was at `from` at t−1 and is at `to` now; sum the correlator over the retina
        let now = bar(to.0, to.1, vertical);
        let del = bar(from.0, from.1, vertical);
        let mut sum = 0;
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                sum += correlate(&now, &del, x, y, dir, 3, 1);
            }
        }
        sum
    }

    #[test]
    fn an_edge_moving_right_excites_right_and_inhibits_left() {
        let r = response(Direction::Right, (40, 30), (41, 30), true);
        let l = response(Direction::Left, (40, 30), (41, 30), true);
        assert!(r > 0 && l < 0, "r {r} l {l}");
        // by hand: 10 rows x one neighbour (c = 1): 100·100 each
        assert_eq!(r, 10 * 100 * 100);
        assert_eq!(l, -r);
        assert_eq!(response(Direction::Up, (40, 30), (41, 30), true), 0);
    }

    #[test]
    fn each_direction_is_selective() {
        // (dir, from, to, bar orientation) for a one-pixel step in each direction
        let cases = [
            (Direction::Right, (40, 30), (41, 30), true),
            (Direction::Left, (41, 30), (40, 30), true),
            (Direction::Down, (40, 30), (40, 31), false),
            (Direction::Up, (40, 31), (40, 30), false),
        ];
        for (pref, from, to, vertical) in cases {
            for d in Direction::ALL {
                let r = response(d, from, to, vertical);
                let (pdx, pdy) = pref.step();
                let (dx, dy) = d.step();
                match pdx * dx + pdy * dy {
                    1 => assert!(r > 0, "{pref:?} seen by {d:?}: {r}"),
                    -1 => assert!(r < 0, "{pref:?} seen by {d:?}: {r}"),
                    _ => assert_eq!(r, 0, "{pref:?} seen by {d:?}"),
                }
            }
        }
    }

    #[test]
    fn a_steady_or_flickering_field_gives_no_motion() {
        let flat_now = [80u8; PIXELS];
        let flat_del = [20u8; PIXELS];
        for d in Direction::ALL {
            for (x, y) in [(0, 0), (50, 30), (98, 71)] {
                assert_eq!(correlate(&flat_now, &flat_del, x, y, d, 3, 1), 0);
            }
        }
    }

    #[test]
    fn neurons_outside_the_retina_are_silent() {
        let now = [50u8; PIXELS];
        let del = [0u8; PIXELS];
        // at the right border the rightward correlator has no neuron: 0
        assert_eq!(correlate(&now, &del, 98, 10, Direction::Right, 3, 1), 0);
        // one column in, one neuron: 50·0 − 0·50 = 0 too, but with a delayed signal at p:
        let mut del2 = [0u8; PIXELS];
        del2[10 * WIDTH + 97] = 10;
        assert_eq!(
            correlate(&now, &del2, 97, 10, Direction::Right, 3, 1),
            50 * 10
        );
    }

    #[test]
    fn local_motion_scales_and_rectifies() {
        let p = Params::default();
        let sc = LmScale::new(&p);
        assert_eq!(
            (sc.t4_q16, sc.t5_q16, sc.shift),
            (65536, 16 * 65536, 16 + u32::from(p.choices.lm_shift))
        );
        let now = bar(41, 30, true);
        let del = bar(40, 30, true);
        let zero = [0u8; PIXELS];
        // ON only: T4 = 100·100 at (40,y) for c = 1; model units: (gain·w)² = 1
        let cells = cells_of([&now, &zero, &del, &zero]);
        let m = Maps::new(&cells);
        let expect = (100 * 100) >> p.choices.lm_shift;
        assert_eq!(local_motion(&m, &sc, 40, 33, Direction::Right), expect);
        assert_eq!(local_motion(&m, &sc, 40, 33, Direction::Left), 0);
        // OFF only: gain² = 16 times more
        let cells = cells_of([&zero, &now, &zero, &del]);
        let m = Maps::new(&cells);
        assert_eq!(
            local_motion(&m, &sc, 40, 33, Direction::Right),
            (16 * 100 * 100) >> p.choices.lm_shift
        );
    }

    #[test]
    fn without_the_opponent_term_a_change_that_does_not_move_excites_too() {
        // the same two OFF pixels dark in both frames: no motion, the opponent terms cancel
        let mut still = [0u8; PIXELS];
        still[33 * WIDTH + 40] = 50;
        still[33 * WIDTH + 41] = 50;
        let zero = [0u8; PIXELS];
        let cells = cells_of([&zero, &still, &zero, &still]);
        let m = Maps::new(&cells);
        let paper = LmScale::new(&Params::PAPER);
        assert_eq!(local_motion(&m, &paper, 40, 33, Direction::Right), 0);
        // the authors' firmware sums the preferred product alone: gain² · 50 · 50 >> lm_shift
        let half = LmScale {
            opponent: false,
            ..paper
        };
        assert_eq!(
            local_motion(&m, &half, 40, 33, Direction::Right),
            (16 * 50 * 50) >> 8
        );
        // both forms agree on what moves the other way: nothing preferred, nothing summed
        assert_eq!(local_motion(&m, &half, 41, 33, Direction::Right), 0);
    }

    #[test]
    fn the_fused_loop_equals_the_reference_correlators() {
        let maps = random_maps(99);
        let cells = cells_of([&maps[0], &maps[1], &maps[2], &maps[3]]);
        let m = Maps::new(&cells);
        for (n, s) in [(3u8, 1u8), (1, 1), (4, 2), (2, 4)] {
            let p = Params {
                table1: TableOne {
                    n,
                    ..Params::default().table1
                },
                choices: Choices {
                    s,
                    ..Params::default().choices
                },
                ..Params::default()
            };
            let sc = LmScale::new(&p);
            for y in 0..HEIGHT {
                for x in 0..WIDTH {
                    for d in Direction::ALL {
                        let t4 = correlate(&maps[0], &maps[2], x, y, d, sc.n, sc.s);
                        let t5 = correlate(&maps[1], &maps[3], x, y, d, sc.n, sc.s);
                        let lm =
                            (sc.t4_q16 * i64::from(t4) + sc.t5_q16 * i64::from(t5)) >> sc.shift;
                        let want = lm.clamp(0, i64::from(u32::MAX)) as u32;
                        assert_eq!(
                            local_motion(&m, &sc, x, y, d),
                            want,
                            "({x},{y}) {d:?} n{n} s{s}"
                        );
                    }
                }
            }
        }
    }
}
