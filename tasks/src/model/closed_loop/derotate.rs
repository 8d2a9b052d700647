//! Efference copy of the robot's own turns (a closed-loop mechanism, not in the paper).
//!
//! The robot knows how far it turned between two frames (the yaw it commanded, or its gyro).
//! A turn moves every point of a still scene across the image by a known amount that does not
//! depend on its distance, so the flow it causes can be predicted exactly and cancelled before
//! the correlators see it: the retina's memory of the last frame (`P(t−1)` and the ON/OFF means
//! with their delay line, Eq. 6) is re-registered to the new heading, as if the eye had not
//! turned. A fly does the equivalent with saccade-related efference copies that cancel the
//! expected rotational response of its motion-sensitive neurons (Kim, Fitzgerald and Maimon,
//! Nat. Neurosci. 2015). Translation flow depends on distance and is left to the network:
//! what remains after a turn is what moved relative to the robot's position.
//!
//! Geometry: the pinhole camera of `docs/hardware.md` (the 99x72 window spans [`HFOV_DEG`]
//! between the centres of its outermost columns; square pixels, optical axis level through
//! the image centre). A turn by `δ` (positive = right) shows at new column `x`, bearing
//! `θ = atan((x − c)/f)`, what the old frame had at bearing `θ + δ`:
//!
//! ```text
//! x_old = c + f·(t + T)/(1 − t·T)            t = (x − c)/f,  T = tan δ
//! y_old − c_y = (y − c_y) · cos θ / cos(θ + δ) = (y − c_y) · √((1 + t_old²)/(1 + t²))
//! ```
//!
//! (the vertical factor: a point at horizontal distance `r` is imaged at `−f·z/(r·cos θ)`).
//! The remap is done in place as two separable passes (rows, then columns) fused into one
//! sweep over the columns, each column's row pass gathered into a copy that its column pass
//! reads: `P(t−1)` interpolated between its two nearest source pixels, the cells (four packed
//! means each) from the nearest one.
//! What came into view has no past: the means and delay line there are 0 and `P(t−1)` takes
//! the new frame's pixels ([`Retina::push_row`](crate::model::retina::Retina::push_row)), so
//! new content is not mistaken for motion. The camera sits 19 mm ahead of the wheel axis, so a
//! turn also moves it sideways by a few mm; that parallax is not predicted.

use crate::frame::{CENTRE_X as CX, HEIGHT, PIXELS, WIDTH};
use crate::model::dsp;

/// Horizontal field of view between the centres of the outermost columns, degrees
/// (`docs/hardware.md`: the OV7670 lens's ≈ 70° on the 99-column window).
pub const HFOV_DEG: f32 = 70.0;
/// Focal length in pixels, `c / tan 35°`.
pub const FOCAL_PX: f32 = 69.979_25;
/// Centre row `c_y`, doubled: `2·c_y = HEIGHT − 1`.
const CY2: i32 = HEIGHT as i32 - 1;
/// Largest turn between two frames that is re-registered, degrees (900°/s at 30 fps); a larger
/// one, or a non-finite one, leaves too little of the old frame in view: the network primes
/// again instead.
pub const MAX_TURN_DEG: f32 = 30.0;

/// One turn between two frames, as the remap uses it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turn {
    /// `T = tan δ`.
    tan: f32,
}

impl Turn {
    /// The turn by `deg` degrees (positive = right); `None` if it is not finite or larger than
    /// [`MAX_TURN_DEG`].
    pub fn new(deg: f32) -> Option<Turn> {
        (deg.is_finite() && deg.abs() <= MAX_TURN_DEG).then(|| Turn {
            tan: libm::tanf(deg.to_radians()),
        })
    }

    /// Whether the turn moves no pixel.
    pub fn is_zero(&self) -> bool {
        self.tan == 0.0
    }

    /// Where the old frame's bearing lies, as `t_old = tan(θ + δ)`, for new column `x`
    /// (`None` beyond 90°, where nothing of the old view can be).
    fn source_tan(&self, x: usize) -> Option<f32> {
        let t = (x as f32 - CX) / FOCAL_PX;
        let den = 1.0 - t * self.tan;
        (den > 1e-3).then(|| (t + self.tan) / den)
    }

    /// Where a point of the old frame at `(x, y)` appears in the new one (the inverse map, for
    /// the attention fields' centroids), clamped into the image.
    pub fn moved(&self, x: u8, y: u8) -> (u8, u8) {
        let to = (f32::from(x) - CX) / FOCAL_PX;
        let den = 1.0 + to * self.tan;
        let t = if den > 1e-3 {
            (to - self.tan) / den
        } else if self.tan > 0.0 {
            -1e3
        } else {
            1e3
        };
        let nx = (CX + FOCAL_PX * t).clamp(0.0, (WIDTH - 1) as f32);
        let s = dsp::sqrtf((1.0 + t * t) / (1.0 + to * to));
        let cy = CY2 as f32 / 2.0;
        let ny = (cy + (f32::from(y) - cy) * s).clamp(0.0, (HEIGHT - 1) as f32);
        (libm::roundf(nx) as u8, libm::roundf(ny) as u8)
    }
}

/// A pixel the remap can take from between two source pixels.
pub trait Pixel: Copy {
    /// Take the nearest source pixel rather than interpolate.
    const NEAREST: bool;
    /// Source offsets below this (Q8 pixels) leave a pixel as it is in the column pass.
    const MIN_SHIFT_Q8: u32;
    /// The value `frac` (Q8) of the way from `a` to `b`.
    fn between(a: Self, b: Self, frac: u32) -> Self;
    /// The value at old row `q` (Q8 · 32) of a column `rows` (its row `y` at `rows[y]`):
    /// between rows `⌊q⌋` and `⌊q⌋ + 1`, or the nearest. Indexed modulo [`SPAN`], so no read
    /// needs a bounds test.
    fn sample(rows: &[Self; SPAN + 1], q: u32) -> Self;
}

impl Pixel for u8 {
    /// Grey levels interpolate, so a turn by a fraction of a pixel leaves no change.
    const NEAREST: bool = false;
    /// A sixteenth of a pixel.
    const MIN_SHIFT_Q8: u32 = 16;
    #[inline(always)]
    fn between(a: u8, b: u8, frac: u32) -> u8 {
        let (a, b) = (a as i32, b as i32);
        (a + (((b - a) * frac as i32 + 128) >> 8)) as u8
    }
    #[inline(always)]
    fn sample(rows: &[u8; SPAN + 1], q: u32) -> u8 {
        let i = ((q >> 13) as usize) % SPAN;
        Self::between(rows[i], rows[i + 1], (q >> 5) & 0xFF)
    }
}

impl Pixel for u32 {
    /// A cell packs four means: the nearest.
    const NEAREST: bool = true;
    /// Half a pixel: below it the nearest pixel is the pixel itself.
    const MIN_SHIFT_Q8: u32 = 128;
    #[inline(always)]
    fn between(a: u32, b: u32, frac: u32) -> u32 {
        if frac < 128 {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn sample(rows: &[u32; SPAN + 1], q: u32) -> u32 {
        rows[((q + (128 << 5)) >> 13) as usize % SPAN]
    }
}

/// No source column.
pub const OUTSIDE: u16 = u16::MAX;
const _: () = assert!((OUTSIDE >> 8) as usize >= WIDTH);
/// Entries of the column copy the column pass reads from, a power of two: an index taken
/// modulo `SPAN` (one mask) never needs a bounds test, and every index the pass computes is
/// below it (a column's rows, one down, and what lies outside).
const SPAN: usize = 128;
const _: () = assert!(SPAN.is_power_of_two() && HEIGHT + 2 < SPAN);

/// A turn's remap, per new column: where its pixels come from.
#[derive(Debug, Clone, PartialEq)]
pub struct Map {
    /// Whether the turn is to the right (the row pass's visiting order).
    right: bool,
    /// The old frame's column, Q8 ([`OUTSIDE`] where none).
    src: [u16; WIDTH],
    /// The same to the nearest column (`u8::MAX` where none).
    near: [u8; WIDTH],
    /// The vertical factor, Q12.
    scale: [u16; WIDTH],
}

impl Map {
    /// The map of `turn`.
    pub fn new(turn: &Turn) -> Map {
        let mut m = Map {
            right: turn.tan > 0.0,
            src: [OUTSIDE; WIDTH],
            near: [u8::MAX; WIDTH],
            scale: [4096; WIDTH],
        };
        for x in 0..WIDTH {
            let Some(to) = turn.source_tan(x) else {
                continue;
            };
            let t = (x as f32 - CX) / FOCAL_PX;
            // ≤ 1/cos(35° + 30°) < 2.4 inside the limits; bounded anyway
            let s = dsp::sqrtf((1.0 + to * to) / (1.0 + t * t)).clamp(0.25, 4.0);
            m.scale[x] = (s * 4096.0) as u16;
            let q = (CX + FOCAL_PX * to) * 256.0;
            if (0.0..=((WIDTH - 1) * 256) as f32).contains(&q) {
                let q = libm::roundf(q) as u16;
                m.src[x] = q;
                m.near[x] = ((q + 128) >> 8) as u8;
            }
        }
        m
    }

    /// The old frame's column seen at new column `x`, in pixels (`None` outside).
    pub fn source_column(&self, x: usize) -> Option<f32> {
        self.src
            .get(x)
            .filter(|&&c| c != OUTSIDE)
            .map(|&c| f32::from(c) / 256.0)
    }

    /// The new columns that show nothing of the old frame, as `lo..hi` (empty when none):
    /// they lie at one side, the one the robot turned towards.
    pub fn fresh_columns(&self) -> (u8, u8) {
        let mut lo = WIDTH;
        let mut hi = 0;
        for (x, &c) in self.src.iter().enumerate() {
            if c == OUTSIDE {
                lo = lo.min(x);
                hi = x + 1;
            }
        }
        if lo >= hi {
            (0, 0)
        } else {
            (lo as u8, hi as u8)
        }
    }

    /// Re-registers an image of the old frame to the new heading, in place: the row pass, then
    /// the column pass. Pixels with no source take `fill`, or, with `fill = None`, the nearest
    /// pixel of their row or column.
    ///
    /// Both passes run column by column in one sweep: column `x` of the row pass is gathered
    /// into a copy (from the old columns it reads), then the column pass writes the final
    /// column `x` from that copy. Turning right every source column lies at or right of its
    /// destination (`x_old ≥ x`), so visiting left to right never reads a column already
    /// written; turning left, right to left. No row of the row pass is ever stored.
    pub fn remap<T: Pixel>(&self, img: &mut [T; PIXELS], fill: Option<T>) {
        let Ok(img) = <&mut Rows<T>>::try_from(img.as_chunks_mut::<WIDTH>().0) else {
            return;
        };
        let mut old: Column<T> = [img[0][0]; SPAN + 2];
        let mut one = |x: usize| {
            let runs = Runs::new(self.scale.get(x).map_or(4096, |&s| i32::from(s)));
            self.column_of(img, &mut old, x, fill, &runs);
        };
        if self.right {
            (0..WIDTH).for_each(&mut one);
        } else {
            (0..WIDTH).rev().for_each(one);
        }
    }

    /// [`Map::remap`] of two images in one sweep (the retina's `P(t−1)` and its cells): each
    /// column's runs are bounded once for both.
    pub fn remap_pair<A: Pixel, B: Pixel>(
        &self,
        a: &mut [A; PIXELS],
        fill_a: Option<A>,
        b: &mut [B; PIXELS],
        fill_b: Option<B>,
    ) {
        let (Ok(a), Ok(b)) = (
            <&mut Rows<A>>::try_from(a.as_chunks_mut::<WIDTH>().0),
            <&mut Rows<B>>::try_from(b.as_chunks_mut::<WIDTH>().0),
        ) else {
            return;
        };
        let mut old_a: Column<A> = [a[0][0]; SPAN + 2];
        let mut old_b: Column<B> = [b[0][0]; SPAN + 2];
        let mut one = |x: usize| {
            let runs = Runs::new(self.scale.get(x).map_or(4096, |&s| i32::from(s)));
            self.column_of(a, &mut old_a, x, fill_a, &runs);
            self.column_of(b, &mut old_b, x, fill_b, &runs);
        };
        if self.right {
            (0..WIDTH).for_each(&mut one);
        } else {
            (0..WIDTH).rev().for_each(one);
        }
    }

    /// Both passes of column `x` of `img`, through the copy `old` where it needs one.
    #[inline(always)]
    fn column_of<T: Pixel>(
        &self,
        img: &mut Rows<T>,
        old: &mut Column<T>,
        x: usize,
        fill: Option<T>,
        runs: &Runs,
    ) {
        if T::NEAREST && self.gather(img, x, fill, runs) {
            return;
        }
        self.row_pass(img, old, x, fill);
        old[0] = fill.unwrap_or(old[1]);
        old[HEIGHT + 1] = fill.unwrap_or(old[HEIGHT]);
        column(img, old, x, runs, fill.is_none());
    }

    /// Both passes of column `x` for a nearest pixel, straight from the old image: no copy.
    /// The row pass takes old column `near[x]` whole, so new row `y` takes that column's row
    /// [`column`] would read from its copy. Not taken (false) where column `x` is its own source
    /// (its rows are read as they are written: the copy is needed), nor outside without a fill.
    /// The source column lies beyond `x` in the visiting order, so it is still the old one.
    fn gather<T: Pixel>(&self, img: &mut Rows<T>, x: usize, fill: Option<T>, runs: &Runs) -> bool {
        let Some(&j) = self.near.get(x) else {
            return false;
        };
        let j = usize::from(j);
        if x >= WIDTH || j == x {
            return false;
        }
        if j >= WIDTH {
            // outside: every pixel of the copy, and so of the column, is the fill
            let Some(v) = fill else {
                return false;
            };
            img.iter_mut().for_each(|r| r[x] = v);
            return true;
        }
        let n = moving_rows::<T>(runs.s);
        // the rows that do not move, an even number: two a turn of the loop
        for pair in img[n..HEIGHT - n].chunks_exact_mut(2) {
            if let [a, b] = pair {
                (a[x], b[x]) = (a[j], b[j]);
            }
        }
        if n == 0 {
            return true;
        }
        // the copy's entries: `old[0]`, `old[1]`, `old[HALF_ROWS]`, `old[HALF_ROWS + 1]`,
        // `old[HEIGHT]`, `old[HEIGHT + 1]`
        let (first, last) = (img[0][j], img[HEIGHT - 1][j]);
        let (centre_up, centre_down) = (img[HALF_ROWS - 1][j], img[HALF_ROWS][j]);
        let (above, below) = (fill.unwrap_or(first), fill.unwrap_or(last));
        let (step, q) = (runs.step, runs.q);
        let [a, b, c] = runs.upper(n);
        let upper = &mut img[..n];
        upper[..a].iter_mut().for_each(|r| r[x] = above);
        upper[a..b].iter_mut().for_each(|r| r[x] = first);
        upper[c..].iter_mut().for_each(|r| r[x] = centre_up);
        gather_rows(img, b..c.min(n), x, j, q + b as i32 * step, step);
        let q = q + (HEIGHT - n) as i32 * step;
        let [a, b, c] = runs.lower(n);
        let lower = &mut img[HEIGHT - n..];
        lower[..a].iter_mut().for_each(|r| r[x] = centre_down);
        lower[b..c].iter_mut().for_each(|r| r[x] = last);
        lower[c..].iter_mut().for_each(|r| r[x] = below);
        let y = HEIGHT - n;
        gather_rows(img, y + a..y + b, x, j, q + a as i32 * step, step);
        true
    }

    /// Column `x` of the row pass into `old[1..=HEIGHT]` (row `y` at `[y + 1]`), read from the
    /// old image: between the two source columns around `src[x]`, or the nearest `near[x]`.
    /// What lies outside is `fill`, or without one the old frame's edge column on the side
    /// turned towards (the last one visited).
    fn row_pass<T: Pixel>(&self, img: &Rows<T>, old: &mut Column<T>, x: usize, fill: Option<T>) {
        let (Some(&c), Some(&near)) = (self.src.get(x), self.near.get(x)) else {
            return;
        };
        let Some(col) = old.get_mut(1..=HEIGHT) else {
            return;
        };
        let (i, frac) = if T::NEAREST {
            (usize::from(near), 0)
        } else {
            (usize::from(c >> 8), u32::from(c & 0xFF))
        };
        if i >= WIDTH {
            match fill {
                Some(v) => col.fill(v),
                None => copy_column(img, col, if self.right { WIDTH - 1 } else { 0 }),
            }
        } else if frac == 0 {
            copy_column(img, col, i);
        } else {
            // a fraction only below the last column (`src ≤ (WIDTH − 1)·256`)
            let j = (i + 1).min(WIDTH - 1);
            for (o, row) in col.iter_mut().zip(img.iter()) {
                *o = T::between(row[i], row[j], frac);
            }
        }
    }
}

/// Column `i` of `img` into `col`.
#[inline(always)]
fn copy_column<T: Pixel>(img: &Rows<T>, col: &mut [T], i: usize) {
    if i < WIDTH {
        for (o, row) in col.iter_mut().zip(img.iter()) {
            *o = row[i];
        }
    }
}

/// An image as rows.
type Rows<T> = [[T; WIDTH]; HEIGHT];
/// Rows in each half of the image (the centre line lies between them).
const HALF_ROWS: usize = HEIGHT / 2;
/// The last row, Q8.
const LAST: i32 = (HEIGHT as i32 - 1) << 8;
/// The lower half's first row, Q8.
const HALF: i32 = (HALF_ROWS as i32) << 8;
/// A column of the old image one row down: `[0]` and `[HEIGHT + 1]` what lies outside above
/// and below it, `[y + 1]` row `y`; long enough that `[1..]` takes any index modulo [`SPAN`]
/// and the next ([`Pixel::sample`]).
type Column<T> = [T; SPAN + 2];

/// The column pass on column `x` with vertical factor `s` (Q12): new row `y` takes old row
/// `c_y + (y − c_y)·s` (Q8, between its two neighbours), read from the row pass's column in
/// `old` ([`Column`], its entries `0..=HEIGHT + 1` filled), so the order the rows are written
/// in does not matter. Each half takes only its own rows: a source within half a pixel of the
/// image takes the edge row, one beyond it what lies outside (`old[0]`, `old[HEIGHT + 1]`), one
/// across the centre line the half's own row next to it. Rows whose source lies less than
/// [`Pixel::MIN_SHIFT_Q8`] away (near the centre line) take their own row of `old`.
///
/// The source rises with `y`, so each half's rows fall into runs in that order (outside, edge,
/// between two rows, edge); their bounds are computed once, and no pixel is clamped. With
/// `edges` what lies outside is the edge row (`old[0] = old[1]`, `old[HEIGHT + 1] =
/// old[HEIGHT]`): the edge run takes it too.
fn column<T: Pixel>(img: &mut Rows<T>, old: &Column<T>, x: usize, runs: &Runs, edges: bool) {
    if x >= WIDTH {
        return;
    }
    let n = moving_rows::<T>(runs.s);
    for (r, &o) in img[n..HEIGHT - n].iter_mut().zip(&old[n + 1..]) {
        r[x] = o;
    }
    if n == 0 {
        return;
    }
    let (step, q) = (runs.step, runs.q);
    let [a, b, c] = runs.upper(n);
    let upper = &mut img[..n];
    if edges {
        // what lies outside is the edge row: one run
        upper[..b].iter_mut().for_each(|r| r[x] = old[1]);
    } else {
        upper[..a].iter_mut().for_each(|r| r[x] = old[0]);
        upper[a..b].iter_mut().for_each(|r| r[x] = old[1]);
    }
    between_rows(&mut upper[b..c], old, x, q + b as i32 * step, step);
    upper[c..].iter_mut().for_each(|r| r[x] = old[HALF_ROWS]);
    let q = q + (HEIGHT - n) as i32 * step;
    let [a, b, c] = runs.lower(n);
    let lower = &mut img[HEIGHT - n..];
    lower[..a]
        .iter_mut()
        .for_each(|r| r[x] = old[HALF_ROWS + 1]);
    between_rows(&mut lower[a..b], old, x, q + a as i32 * step, step);
    if edges {
        lower[b..].iter_mut().for_each(|r| r[x] = old[HEIGHT]);
    } else {
        lower[b..c].iter_mut().for_each(|r| r[x] = old[HEIGHT]);
        lower[c..].iter_mut().for_each(|r| r[x] = old[HEIGHT + 1]);
    }
}

/// The rows of each half that move with vertical factor `s_q12` (Q12): the `n` farthest from
/// the centre line, whose source lies at least [`Pixel::MIN_SHIFT_Q8`] away.
#[inline(always)]
fn moving_rows<T: Pixel>(s_q12: i32) -> usize {
    let ds = (s_q12 - 4096).unsigned_abs();
    // the source offset of a row at distance d = |2y − 2c_y| from the centre line is
    // d·|s − 1|/2 pixels = d·ds >> 5 in Q8; the odd distances d from `first` to 71 are the
    // rows that move
    (ds != 0)
        .then(|| (T::MIN_SHIFT_Q8 << 5).div_ceil(ds) | 1)
        .and_then(|first| usize::try_from(first / 2).ok())
        .and_then(|k| HALF_ROWS.checked_sub(k))
        .unwrap_or(0)
}

/// Rows `ys` of column `x`, each the nearest row to its source `q` (Q8 · 32, rising by `step`
/// a row; inside the image) of old column `j`: [`Pixel::sample`] of a nearest pixel, read
/// from the image instead of a copy.
#[inline(always)]
fn gather_rows<T: Pixel>(
    img: &mut Rows<T>,
    ys: core::ops::Range<usize>,
    x: usize,
    j: usize,
    q: i32,
    step: i32,
) {
    let (Ok(mut q), Ok(step)) = (u32::try_from(q), u32::try_from(step)) else {
        return;
    };
    if x >= WIDTH || j >= WIDTH {
        return;
    }
    for y in ys {
        // inside the image: the minimum only spares a bounds test
        let i = (((q + (128 << 5)) >> 13) as usize).min(HEIGHT - 1);
        let v = img[i][j];
        if let Some(r) = img.get_mut(y) {
            r[x] = v;
        }
        q += step;
    }
}

/// A column's runs (see [`column`]) before they are cut to the rows that move: computed once
/// for every image of a column, whatever its pixel's rows that move.
struct Runs {
    /// The vertical factor, Q12.
    s: i32,
    /// Row 0's source, Q8 · 32: `CY2·4096 + (2y − CY2)·s` at `y = 0`.
    q: i32,
    /// What the source rises by a row, `2s`.
    step: i32,
    /// How many rows from row 0 have their source above −½ (outside), row 0 (the edge) and
    /// the centre line's row (between two rows): the upper half's run ends.
    upper: [usize; 3],
    /// The same below the lower half's first row, the last row, and ½ beyond it.
    lower: [usize; 3],
}

impl Runs {
    #[inline(always)]
    fn new(s: i32) -> Runs {
        let (q, step) = ((CY2 << 12) - CY2 * s, 2 * s);
        Runs {
            s,
            q,
            step,
            upper: [-128, 0, HALF - 255].map(|end| rows_below(q, step, end, usize::MAX)),
            lower: [HALF, LAST + 1, LAST + 129].map(|end| rows_below(q, step, end, usize::MAX)),
        }
    }

    /// The upper half's run ends when its `n` outermost rows move (rows from row 0).
    #[inline(always)]
    fn upper(&self, n: usize) -> [usize; 3] {
        self.upper.map(|k| k.min(n))
    }

    /// The lower half's run ends when its `n` outermost rows move (rows from row
    /// `HEIGHT − n`): the source of row `HEIGHT − n` lies `(HEIGHT − n)·step` above row 0's,
    /// so that many fewer rows lie below each end.
    #[inline(always)]
    fn lower(&self, n: usize) -> [usize; 3] {
        self.lower.map(|k| k.saturating_sub(HEIGHT - n).min(n))
    }
}

/// How many of `n` rows, from source `q` (Q8 · 32) rising by `step` > 0 a row, have their
/// source `q >> 5` below `end` (Q8).
#[inline(always)]
fn rows_below(q: i32, step: i32, end: i32, n: usize) -> usize {
    let need = (end << 5) - q;
    if need <= 0 || step <= 0 {
        return 0;
    }
    usize::try_from((need + step - 1) / step).map_or(n, |k| k.min(n))
}

/// Column `x` of `rows`, each between the two rows of the copy `old` around its source `q`
/// (Q8 · 32, rising by `step` a row; inside the half, so both rows lie in the copy). Two rows
/// a turn of the loop: half the jumps back.
#[inline(always)]
fn between_rows<T: Pixel>(rows: &mut [[T; WIDTH]], old: &Column<T>, x: usize, q: i32, step: i32) {
    let (Some(old), Ok(mut q), Ok(step)) =
        (old.last_chunk(), u32::try_from(q), u32::try_from(step))
    else {
        return;
    };
    let mut pairs = rows.chunks_exact_mut(2);
    for pair in &mut pairs {
        if let [a, b] = pair {
            a[x] = T::sample(old, q);
            b[x] = T::sample(old, q + step);
        }
        q += 2 * step;
    }
    for r in pairs.into_remainder() {
        r[x] = T::sample(old, q);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_turn_is_the_identity() {
        let t = Turn::new(0.0).unwrap();
        assert!(t.is_zero());
        let m = Map::new(&t);
        assert!((0..WIDTH).all(|x| m.source_column(x) == Some(x as f32)));
        assert_eq!(m.fresh_columns(), (0, 0));
        let mut img = [0u8; PIXELS];
        for (i, p) in img.iter_mut().enumerate() {
            *p = i as u8;
        }
        let before = img;
        m.remap(&mut img, None);
        assert_eq!(img, before);
    }

    #[test]
    fn a_right_turn_brings_the_right_side_to_the_centre() {
        assert!(Turn::new(35.0).is_none(), "beyond the limit");
        assert!(Turn::new(f32::NAN).is_none());
        let m = Map::new(&Turn::new(10.0).unwrap());
        // at the centre the shift is f·tan 10° ≈ 12.34 px; at the left edge 16.37 px, where
        // the tangent is steeper: 49 + f·tan(−25°)
        let q = |x: usize| m.source_column(x).unwrap();
        assert!((q(49) - 61.34).abs() < 0.01, "{}", q(49));
        assert!((q(0) - 16.37).abs() < 0.01, "{}", q(0));
        assert_eq!((m.near[49], m.near[0]), (61, 16));
        // what lies beyond the old right edge column came into view (column 82 looks at
        // old column 98.45)
        assert_eq!(m.fresh_columns(), (82, WIDTH as u8));
        // the inverse map takes the old column back
        assert_eq!(Turn::new(10.0).unwrap().moved(61, 35).0, 49);
        let left = Map::new(&Turn::new(-10.0).unwrap());
        assert!((left.source_column(49).unwrap() - 36.66).abs() < 0.01);
        assert_eq!(left.fresh_columns(), (0, 17));
    }

    #[test]
    fn no_column_reads_a_column_visited_before_it() {
        // the one sweep of `remap` writes column x after reading the source columns of its
        // row pass: turning right (visited left to right) they must lie at or right of x,
        // turning left at or left of it (a second column only with a fraction)
        for i in -3000..=3000 {
            let deg = i as f32 / 100.0;
            let m = Map::new(&Turn::new(deg).unwrap());
            for x in 0..WIDTH {
                let c = m.src[x];
                if c == OUTSIDE {
                    assert_eq!(m.near[x], u8::MAX);
                    continue;
                }
                let (i, frac, near) = (usize::from(c >> 8), c & 0xFF, usize::from(m.near[x]));
                let last = if frac == 0 { i } else { i + 1 };
                if m.right {
                    assert!(i >= x && near >= x, "turn {deg}, column {x}");
                } else {
                    assert!(last <= x && near <= x, "turn {deg}, column {x}");
                }
            }
        }
    }

    #[test]
    fn the_outermost_columns_lie_at_half_the_field_of_view() {
        let edge = libm::atanf(CX / FOCAL_PX).to_degrees();
        assert!((2.0 * edge - HFOV_DEG).abs() < 1e-3, "{edge}");
    }

    #[test]
    fn off_axis_columns_scale_vertically_as_the_pinhole_does() {
        let t = Turn::new(10.0).unwrap();
        let m = Map::new(&t);
        // the right edge looks at 45° of the old view: cos 35° / cos 45° ≈ 1.158
        let s = f32::from(m.scale[WIDTH - 1]) / 4096.0;
        assert!((s - 1.158).abs() < 0.01, "{s}");
        // a point moved into the new frame maps back to where it was
        let (x, y) = t.moved(90, 5);
        let back = m.source_column(usize::from(x)).unwrap();
        assert!(
            (back - 90.0).abs() <= 1.0 && y > 5,
            "({x}, {y}) from {back}"
        );
    }

    #[test]
    fn a_horizontal_ramp_shifts_by_a_fraction_of_a_pixel() {
        // grey = 2·column: a turn of 0.25 px at the centre shifts the ramp by half a level
        let m = Map::new(&Turn::new(0.2).unwrap());
        let mut img = [0u8; PIXELS];
        for (i, p) in img.iter_mut().enumerate() {
            *p = (2 * (i % WIDTH)) as u8;
        }
        m.remap(&mut img, None);
        let shift = m.source_column(49).unwrap() - 49.0;
        assert!((0.2..0.3).contains(&shift), "{shift}");
        // the centre column now holds the grey of column 49 + shift, rounded
        assert_eq!(img[35 * WIDTH + 49], (2.0 * (49.0 + shift)).round() as u8);
    }

    /// The column pass against its plain definition, for both pixel kinds.
    fn check_column<T: Pixel + Into<u32>>(make: impl Fn(usize) -> T, nearest: bool) {
        for s in [3000, 4000, 4096, 4200, 4700, 6000] {
            let mut img = [[make(0); WIDTH]; HEIGHT];
            for (y, row) in img.iter_mut().enumerate() {
                row[7] = make(y);
            }
            let mut old = [make(255); SPAN + 2];
            for (o, row) in old[1..].iter_mut().zip(img.iter()) {
                *o = row[7];
            }
            column(&mut img, &old, 7, &Runs::new(s), false);
            for (y, row) in img.iter().enumerate() {
                let d = 2 * y as i32 - CY2;
                let q = (d * s + (CY2 << 12)) >> 5;
                let got = row[7].into() as i32;
                let half = if y < HEIGHT / 2 {
                    0..=35 * 256
                } else {
                    36 * 256..=71 * 256
                };
                let moved = (d.unsigned_abs() * (s - 4096).unsigned_abs()) >> 5 >= T::MIN_SHIFT_Q8;
                let want = if !moved {
                    3 * y as i32
                } else if !(-128..=71 * 256 + 128).contains(&q) {
                    make(255).into() as i32
                } else {
                    let q = q.clamp(*half.start(), *half.end());
                    if nearest {
                        3 * ((q + 128).min(*half.end()) >> 8)
                    } else {
                        (3 * q + 128) >> 8
                    }
                };
                assert!((got - want).abs() <= 1, "s {s} y {y}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn the_column_pass_reads_before_it_writes() {
        // a column whose pixels hold 3 × their row: after the pass each holds its source
        // row's value (interpolated or the nearest), whatever the visiting order
        check_column(|y| (3 * y.min(85)) as u8, false);
        check_column(|y| 3 * y as u32, true);
    }

    /// The remap as first written (in place, every read bounds-checked), against which the
    /// faster one is held bit for bit.
    mod plain {
        use super::super::*;

        pub fn remap<T: Pixel>(m: &Map, img: &mut [T; PIXELS], fill: Option<T>) {
            rows(m, img, fill);
            for (x, &s) in m.scale.iter().enumerate() {
                column(img, x, i32::from(s), fill);
            }
        }

        fn rows<T: Pixel>(m: &Map, img: &mut [T; PIXELS], fill: Option<T>) {
            let right = m.right;
            for row in img.chunks_exact_mut(WIDTH) {
                let Ok(row) = <&mut [T; WIDTH]>::try_from(row) else {
                    continue;
                };
                let outside = fill.unwrap_or(row[if right { WIDTH - 1 } else { 0 }]);
                let one = |row: &mut [T; WIDTH], x: usize| {
                    let v = if T::NEAREST {
                        row.get(usize::from(m.near[x])).copied().unwrap_or(outside)
                    } else {
                        let c = m.src[x];
                        let i = usize::from(c >> 8);
                        match row.get(i) {
                            Some(&a) => {
                                let b = row.get(i + 1).copied().unwrap_or(a);
                                T::between(a, b, u32::from(c & 0xFF))
                            }
                            None => outside,
                        }
                    };
                    row[x] = v;
                };
                if right {
                    for x in 0..WIDTH {
                        one(row, x);
                    }
                } else {
                    for x in (0..WIDTH).rev() {
                        one(row, x);
                    }
                }
            }
        }

        fn column<T: Pixel>(img: &mut [T; PIXELS], x: usize, s_q12: i32, fill: Option<T>) {
            let ds = (s_q12 - 4096).unsigned_abs();
            if ds == 0 {
                return;
            }
            let Ok(first) = i32::try_from((T::MIN_SHIFT_Q8 << 5).div_ceil(ds) | 1) else {
                return;
            };
            if s_q12 >= 4096 {
                let mut d = first;
                while d <= CY2 {
                    pair(img, x, d, s_q12, fill);
                    d += 2;
                }
            } else {
                let mut d = CY2;
                while d >= first {
                    pair(img, x, d, s_q12, fill);
                    d -= 2;
                }
            }
        }

        fn pair<T: Pixel>(img: &mut [T; PIXELS], x: usize, d: i32, s_q12: i32, fill: Option<T>) {
            let (top, bottom) = ((CY2 - d) / 2, (CY2 + d) / 2);
            let q = d * s_q12;
            put(img, x, top as usize, ((CY2 << 12) - q) >> 5, true, fill);
            put(img, x, bottom as usize, ((CY2 << 12) + q) >> 5, false, fill);
        }

        fn put<T: Pixel>(
            img: &mut [T; PIXELS],
            x: usize,
            y: usize,
            q: i32,
            upper: bool,
            fill: Option<T>,
        ) {
            const LAST: i32 = (HEIGHT as i32 - 1) << 8;
            const HALF: i32 = (HEIGHT as i32 / 2) << 8;
            let (lo, hi) = if upper { (0, HALF - 256) } else { (HALF, LAST) };
            let v = if (-128..=LAST + 128).contains(&q) {
                let q = q.clamp(lo, hi);
                if T::NEAREST {
                    let i = ((q + 128).min(hi) >> 8) as usize;
                    img.get(i * WIDTH + x).copied()
                } else {
                    let i = (q >> 8) as usize;
                    let j = if q < hi { i + 1 } else { i };
                    match (img.get(i * WIDTH + x), img.get(j * WIDTH + x)) {
                        (Some(&a), Some(&b)) => Some(T::between(a, b, (q & 0xFF) as u32)),
                        _ => None,
                    }
                }
            } else {
                fill.or_else(|| {
                    img.get((if upper { lo } else { hi } >> 8) as usize * WIDTH + x)
                        .copied()
                })
            };
            if let (Some(v), Some(p)) = (v, img.get_mut(y * WIDTH + x)) {
                *p = v;
            }
        }
    }

    #[test]
    fn the_remap_is_its_plain_definition_bit_for_bit() {
        let mut seed = 12_345u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed
        };
        let mut turns = [0.0f32; 50];
        let chosen = [-30.0, -12.0, -0.9, -0.05, 0.05, 0.3, 1.7, 12.0, 29.99, 30.0];
        for (i, t) in turns.iter_mut().enumerate() {
            *t = match chosen.get(i) {
                Some(&c) => c,
                None => (next() % 60_001) as f32 / 1000.0 - 30.0,
            };
        }
        for deg in turns {
            let m = Map::new(&Turn::new(deg).unwrap());
            let grey: [u8; PIXELS] = core::array::from_fn(|_| next() as u8);
            let cells: [u32; PIXELS] = core::array::from_fn(|_| next());
            for fill in [None, Some(77)] {
                let (mut fast, mut plain) = (grey, grey);
                m.remap(&mut fast, fill);
                plain::remap(&m, &mut plain, fill);
                assert!(fast == plain, "grey, turn {deg}, fill {fill:?}");
                let (mut fast, mut plain) = (cells, cells);
                let fill_c = fill.map(u32::from);
                m.remap(&mut fast, fill_c);
                plain::remap(&m, &mut plain, fill_c);
                assert!(fast == plain, "cells, turn {deg}, fill {fill_c:?}");
                // both in one sweep, as the retina does
                let (mut pair_grey, mut pair_cells) = (grey, cells);
                m.remap_pair(&mut pair_grey, fill, &mut pair_cells, fill_c);
                let mut plain_grey = grey;
                plain::remap(&m, &mut plain_grey, fill);
                assert!(
                    pair_grey == plain_grey,
                    "pair, grey, turn {deg}, fill {fill:?}"
                );
                assert!(
                    pair_cells == plain,
                    "pair, cells, turn {deg}, fill {fill_c:?}"
                );
            }
        }
    }
}
