//! Behaviour of the whole aLPLC2 network (paper Sec. II) on synthetic scenes rendered here,
//! always with `Params::default()` (Table I plus the documented choices): nothing is calibrated
//! to the scenes.
//!
//! Scenes are 99 x 72 frames at 30 fps. Pixel `(x, y)` is centred on the integer point `(x, y)`;
//! squares are drawn with their exact area coverage, discs with 4x4 supersampling. Every scene
//! starts with `LEAD` still frames (the first one primes the network).
//!
//! Every test prints its numbers (alerts per scene, `X̄`, AF counts, peak `ΣLPLC2`):
//! `cargo test --target host-tuple -p alvs-host --test scenes -- --nocapture`.
//!
//! Limitations of the model that these scenes expose are kept at the end as `#[ignore]`d tests
//! that state the wanted behaviour, with the measured numbers; they fail today
//! (`-- --ignored` runs them).

use alvs_tasks::{Network, Params, Perception, HEIGHT, PIXELS, WIDTH};

type Frame = [u8; PIXELS];

/// Horizontal centre of the retina (`X̄ = 49` is straight ahead).
const CENTRE: f32 = 49.0;

/// Still frames before a stimulus starts: the priming frame plus a few quiet ones.
const LEAD: usize = 5;

// ---------------------------------------------------------------------------------------------
// Rendering
// ---------------------------------------------------------------------------------------------

/// Small deterministic PRNG (xorshift64*): seeded scenes without another dependency.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform integer in `lo..=hi`.
    fn range(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as i32
    }
}

/// A grey-level picture in f32, rounded and clipped to 0..=255 only when it becomes a frame.
#[derive(Clone)]
struct Canvas(Vec<f32>);

impl Canvas {
    fn plain(g: f32) -> Self {
        Canvas(vec![g; PIXELS])
    }

    /// Random blocks of `cell` x `cell` pixels with grey levels `mean ± amp`, seeded.
    fn textured(mean: f32, amp: i32, cell: usize, seed: u64) -> Self {
        let mut rng = Rng::new(seed);
        let cw = WIDTH.div_ceil(cell);
        let cells: Vec<f32> = (0..cw * HEIGHT.div_ceil(cell))
            .map(|_| mean + rng.range(-amp, amp) as f32)
            .collect();
        let mut c = Canvas::plain(0.0);
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                c.0[y * WIDTH + x] = cells[(y / cell) * cw + x / cell];
            }
        }
        c
    }

    /// The rectangle `[x0, x1) x [y0, y1)` in continuous coordinates, blended by covered area.
    fn rect(&mut self, x0: f32, x1: f32, y0: f32, y1: f32, g: f32) {
        let cover = |lo: f32, hi: f32, p: usize| {
            let p = p as f32;
            (hi.min(p + 0.5) - lo.max(p - 0.5)).clamp(0.0, 1.0)
        };
        let span = |lo: f32, hi: f32, n: usize| {
            let a = (lo + 0.5).floor().clamp(0.0, n as f32) as usize;
            let b = ((hi + 0.5).ceil().max(0.0) as usize).min(n);
            (a, b)
        };
        let ((xa, xb), (ya, yb)) = (span(x0, x1, WIDTH), span(y0, y1, HEIGHT));
        for y in ya..yb {
            let cy = cover(y0, y1, y);
            for x in xa..xb {
                let a = cy * cover(x0, x1, x);
                let v = &mut self.0[y * WIDTH + x];
                *v = *v * (1.0 - a) + g * a;
            }
        }
    }

    /// Square of half side `h` centred on `(cx, cy)`.
    fn square(&mut self, cx: f32, cy: f32, h: f32, g: f32) {
        self.rect(cx - h, cx + h, cy - h, cy + h, g);
    }

    /// Disc of radius `r` centred on `(cx, cy)`.
    fn disc(&mut self, cx: f32, cy: f32, r: f32, g: f32) {
        let lo = |c: f32| (c - r).floor().max(0.0) as usize;
        let hi = |c: f32, n: usize| ((c + r).ceil() + 1.0).clamp(0.0, n as f32) as usize;
        for y in lo(cy)..hi(cy, HEIGHT) {
            for x in lo(cx)..hi(cx, WIDTH) {
                let mut hits = 0;
                for sy in 0..4 {
                    for sx in 0..4 {
                        let px = x as f32 + (sx as f32 - 1.5) / 4.0 - cx;
                        let py = y as f32 + (sy as f32 - 1.5) / 4.0 - cy;
                        hits += usize::from(px * px + py * py <= r * r);
                    }
                }
                let a = hits as f32 / 16.0;
                let v = &mut self.0[y * WIDTH + x];
                *v = *v * (1.0 - a) + g * a;
            }
        }
    }

    /// The same picture `d` grey levels brighter.
    fn offset(&self, d: f32) -> Canvas {
        Canvas(self.0.iter().map(|v| v + d).collect())
    }

    fn frame(&self) -> Frame {
        let mut f = [0u8; PIXELS];
        for (o, &v) in f.iter_mut().zip(self.0.iter()) {
            *o = v.round().clamp(0.0, 255.0) as u8;
        }
        f
    }
}

/// Adds seeded uniform sensor noise of `±amp` grey levels to every pixel of every frame.
fn add_noise(frames: &[Frame], amp: i32, seed: u64) -> Vec<Frame> {
    let mut rng = Rng::new(seed);
    frames
        .iter()
        .map(|f| {
            let mut g = *f;
            for v in g.iter_mut() {
                *v = (i32::from(*v) + rng.range(-amp, amp)).clamp(0, 255) as u8;
            }
            g
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------------------------

/// Frames `f(t)` for t = 0..n.
fn scene(n: usize, f: impl Fn(usize) -> Canvas) -> Vec<Frame> {
    (0..n).map(|t| f(t).frame()).collect()
}

/// Frames since the stimulus started moving: 0 during the lead, then 1, 2, ...
fn moving(t: usize) -> f32 {
    t.saturating_sub(LEAD - 1) as f32
}

/// An object whose half size changes linearly: `h0 + rate·k` at the k-th frame of motion.
#[derive(Clone, Copy, Debug)]
struct Looming {
    cx: f32,
    cy: f32,
    h0: f32,
    /// Pixels per frame per edge; negative for a receding object.
    rate: f32,
    grey: f32,
}

impl Looming {
    /// An approaching square, 2 px in half size (5 px wide with the 3x3 retina blur) at onset.
    fn square(cx: f32, cy: f32, rate: f32, grey: f32) -> Self {
        Looming {
            cx,
            cy,
            h0: 2.0,
            rate,
            grey,
        }
    }

    fn half(&self, t: usize) -> f32 {
        (self.h0 + self.rate * moving(t)).max(0.5)
    }
}

/// `LEAD` still frames, then `n` frames of expansion (or contraction) of every object.
fn looming_scene(bg: &Canvas, objs: &[Looming], n: usize) -> Vec<Frame> {
    scene(LEAD + n, |t| {
        let mut c = bg.clone();
        for o in objs {
            c.square(o.cx, o.cy, o.half(t), o.grey);
        }
        c
    })
}

/// A disc of radius `r` metres approaching at `v` m/s from `d0` to `d1` metres at 30 fps, its
/// image size from the retina's α = 0.707°/px.
#[allow(clippy::too_many_arguments)]
fn looming_disc(
    bg: &Canvas,
    cx: f32,
    cy: f32,
    grey: f32,
    r: f32,
    v: f32,
    d0: f32,
    d1: f32,
) -> Vec<Frame> {
    let focal = 1.0 / 0.707f32.to_radians().tan();
    let n = ((d0 - d1) / v * 30.0) as usize;
    scene(LEAD + n, |t| {
        let d = d0 - v * moving(t) / 30.0;
        let mut c = bg.clone();
        c.disc(cx, cy, focal * r / d, grey);
        c
    })
}

/// A bar of `width` px crossing the whole retina at `speed` px/frame: vertical bars travel
/// left to right (right to left when `speed < 0`), horizontal bars top to bottom.
fn bar(bg: &Canvas, speed: f32, width: f32, grey: f32, vertical: bool) -> Vec<Frame> {
    let extent = if vertical { WIDTH } else { HEIGHT } as f32;
    let n = ((extent + 2.0 * width) / speed.abs()) as usize + LEAD;
    scene(n, |t| {
        let travelled = speed.abs() * moving(t);
        let a = if speed > 0.0 {
            -0.5 - width + travelled
        } else {
            extent - 0.5 - travelled
        };
        let mut c = bg.clone();
        if vertical {
            c.rect(a, a + width, -0.5, HEIGHT as f32, grey);
        } else {
            c.rect(-0.5, WIDTH as f32, a, a + width, grey);
        }
        c
    })
}

/// A square of half side `h` crossing the retina left to right along row `y`.
fn translating_square(bg: &Canvas, y: f32, h: f32, speed: f32, grey: f32) -> Vec<Frame> {
    let n = ((WIDTH as f32 + 4.0 * h) / speed) as usize + LEAD;
    scene(n, |t| {
        let mut c = bg.clone();
        c.square(-2.0 * h + speed * moving(t), y, h, grey);
        c
    })
}

/// 60 frames of a drifting grating: sine (`mean ± amp`) or square wave (`mean − amp` and
/// `mean + amp` half periods); vertical stripes drift rightwards, horizontal ones downwards.
fn grating(
    period: f32,
    speed: f32,
    mean: f32,
    amp: f32,
    square: bool,
    vertical: bool,
) -> Vec<Frame> {
    scene(60, |t| {
        let phase = speed * t as f32;
        if square {
            let mut c = Canvas::plain(mean - amp);
            let extent = if vertical { WIDTH } else { HEIGHT } as f32;
            let mut a = phase % period - period - 0.5;
            while a < extent {
                if vertical {
                    c.rect(a, a + period / 2.0, -0.5, HEIGHT as f32, mean + amp);
                } else {
                    c.rect(-0.5, WIDTH as f32, a, a + period / 2.0, mean + amp);
                }
                a += period;
            }
            c
        } else {
            let mut c = Canvas::plain(0.0);
            for y in 0..HEIGHT {
                for x in 0..WIDTH {
                    let u = if vertical { x } else { y } as f32 - phase;
                    c.0[y * WIDTH + x] = mean + amp * (u * std::f32::consts::TAU / period).sin();
                }
            }
            c
        }
    })
}

/// 60 frames of a still scene whose brightness steps between `−amp` and `+amp` every
/// `half_period` frames.
fn flicker(bg: &Canvas, amp: f32, half_period: usize) -> Vec<Frame> {
    let (lo, hi) = (bg.offset(-amp).frame(), bg.offset(amp).frame());
    (0..60)
        .map(|t| {
            if (t / half_period).is_multiple_of(2) {
                lo
            } else {
                hi
            }
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Running and reporting
// ---------------------------------------------------------------------------------------------

/// Runs the frames through a fresh network with `Params::default()`.
fn run(frames: &[Frame]) -> Vec<Perception> {
    let mut net = Network::new(Params::default()).unwrap();
    frames.iter().map(|f| net.step(f)).collect()
}

fn alerts(outs: &[Perception]) -> usize {
    outs.iter().filter(|o| o.alert()).count()
}

/// Prints one line per scene: alerts, AFs, peak `ΣLPLC2` and the mean `X̄` of alert frames.
fn report(name: &str, outs: &[Perception]) -> usize {
    let xs: Vec<f32> = outs.iter().filter_map(|o| o.vm.threat_x).collect();
    let mean_x = (!xs.is_empty()).then(|| xs.iter().sum::<f32>() / xs.len() as f32);
    let n = alerts(outs);
    println!(
        "{name}: alerts {n}/{} | max AFs {} | peak ΣLPLC2 {} | mean X̄ {}",
        outs.len(),
        outs.iter().map(|o| o.afs.len()).max().unwrap_or(0),
        outs.iter().map(|o| o.vm.lplc2_sum).max().unwrap_or(0),
        mean_x.map_or("-".into(), |x| format!("{x:.1}")),
    );
    n
}

/// Runs many scenes that must never alert; prints each and fails listing those that did.
fn assert_never_alerts(scenes: impl IntoIterator<Item = (String, Vec<Frame>)>) {
    let (mut failed, mut total, mut count) = (Vec::new(), 0, 0);
    for (name, frames) in scenes {
        let outs = run(&frames);
        let n = report(&name, &outs);
        total += outs.len();
        count += 1;
        if n > 0 {
            failed.push(format!("{name}: {n}/{}", outs.len()));
        }
    }
    println!("{count} scenes, {total} frames, alerting: {failed:?}");
    assert!(failed.is_empty(), "alerts in: {failed:#?}");
}

/// The most stimulated field of a frame.
fn strongest(o: &Perception) -> Option<&alvs_tasks::AfReport> {
    o.afs.iter().max_by_key(|a| a.lplc2)
}

/// What one approaching object (`obj`, expanding for `n` frames after the lead) must produce:
/// silence while still, alerts on at least 2/3 of the expansion frames starting within 3
/// frames of the onset, and on every alert frame `X̄` and the strongest field within 6 px of
/// the object's centre, the escape turning away from the object's side, `S` and short mode
/// consistent with `ΣLPLC2`.
fn check_approach(name: &str, outs: &[Perception], obj: &Looming, n: usize) {
    report(name, outs);
    assert_eq!(alerts(&outs[..LEAD]), 0, "{name}: alert before the onset");
    let during = &outs[LEAD..LEAD + n];
    let first = during.iter().position(|o| o.alert());
    let count = alerts(during);
    println!("  first alert {first:?} frames after onset, {count}/{n} expansion frames alert");
    assert!(
        first.is_some_and(|k| k <= 2),
        "{name}: late onset {first:?}"
    );
    assert!(
        3 * count >= 2 * n,
        "{name}: only {count}/{n} expansion frames alert"
    );
    let p = Params::default();
    for o in outs.iter().filter(|o| o.alert()) {
        let vm = &o.vm;
        let x = vm.threat_x.expect("an alert has a threat centroid");
        let af = strongest(o).unwrap();
        let at = format!(
            "{name}, frame {}: X̄ {x}, AF ({}, {}), {vm:?}",
            o.frame, af.x, af.y
        );
        assert!((x - obj.cx).abs() <= 6.0, "{at}");
        assert!((f32::from(af.x) - obj.cx).abs() <= 6.0, "{at}");
        assert!((f32::from(af.y) - obj.cy).abs() <= 6.0, "{at}");
        let long = vm.theta_long.unwrap();
        let [s1, s2] = vm.theta_short.unwrap();
        if obj.cx < CENTRE - 10.0 {
            // threat on the left: turn right, ending 145°..180° away
            assert!(x < CENTRE && long > 145.0 && long <= 180.0, "{at}");
            assert!(s1 > 0.0 && s2 > 0.0, "{at}");
        } else if obj.cx > CENTRE + 10.0 {
            assert!(x > CENTRE && long < -145.0 && long > -180.0, "{at}");
            assert!(s1 < 0.0 && s2 < 0.0, "{at}");
        } else {
            // ahead: turn (almost) around; 10 px off centre is 7.07°
            assert!((x - CENTRE).abs() <= 10.0 && long.abs() >= 172.9, "{at}");
        }
        assert!(vm.strength > 0.5 && vm.strength <= 1.0, "{at}");
        assert_eq!(vm.short_mode, vm.lplc2_sum > p.t_s, "{at}");
    }
}

/// Prints a scene frame by frame (for the reader of a failure).
fn trace(outs: &[Perception]) {
    for o in outs {
        let afs: Vec<String> = o
            .afs
            .iter()
            .map(|a| format!("#{}({},{}) L{}", a.id, a.x, a.y, a.lplc2))
            .collect();
        println!(
            "  frame {:3}: ΣLPLC2 {:6} X̄ {:5} | {}",
            o.frame,
            o.vm.lplc2_sum,
            o.vm.threat_x.map_or("-".into(), |x| format!("{x:.1}")),
            afs.join(" ")
        );
    }
}

const POSITIONS: [f32; 3] = [20.0, 49.0, 78.0];

// ---------------------------------------------------------------------------------------------
// Approaching objects
// ---------------------------------------------------------------------------------------------

/// A dark square (40 on 200) expanding 1 px/frame per edge, half size 2 → 18 px, at the
/// left, centre and right of the field.
#[test]
fn dark_square_approaching_left_centre_and_right() {
    let bg = Canvas::plain(200.0);
    for cx in POSITIONS {
        let obj = Looming::square(cx, 36.0, 1.0, 40.0);
        let outs = run(&looming_scene(&bg, &[obj], 16));
        check_approach(&format!("dark square at x = {cx}"), &outs, &obj, 16);
    }
}

/// The same over a textured background (blocks of 150 ± 20), square at 20.
#[test]
fn dark_square_approaching_over_texture() {
    let bg = Canvas::textured(150.0, 20, 6, 7);
    for cx in POSITIONS {
        let obj = Looming::square(cx, 36.0, 1.0, 20.0);
        let outs = run(&looming_scene(&bg, &[obj], 16));
        check_approach(
            &format!("dark square over texture at x = {cx}"),
            &outs,
            &obj,
            16,
        );
    }
}

/// A bright square (220 on 20) seen by the ON channel alone (weight `w` = 0.25), expanding
/// 2 px/frame per edge, half size 2 → 18 px. (At 1 px/frame the ON channel cannot reach `T_a`:
/// see `slow_bright_approach_alerts` below.)
#[test]
fn bright_square_approaching_on_a_dark_background() {
    let bg = Canvas::plain(20.0);
    for cx in POSITIONS {
        let obj = Looming::square(cx, 36.0, 2.0, 220.0);
        let outs = run(&looming_scene(&bg, &[obj], 8));
        check_approach(&format!("bright square at x = {cx}"), &outs, &obj, 8);
    }
}

/// An approach is still seen, in the right place, through ±10 grey levels of sensor noise.
#[test]
fn approach_through_sensor_noise() {
    let bg = Canvas::plain(200.0);
    for (cx, seed) in [(20.0, 1), (49.0, 2), (78.0, 3)] {
        let obj = Looming::square(cx, 30.0, 1.0, 40.0);
        let outs = run(&add_noise(&looming_scene(&bg, &[obj], 16), 10, seed));
        check_approach(&format!("noisy dark square at x = {cx}"), &outs, &obj, 16);
    }
}

/// A dark disc of radius 10 cm approaching at constant speed from 2 m to 0.3 m (its image
/// grows hyperbolically, 4 → 27 px in radius): the alert starts well before the end, never
/// stops once started, `ΣLPLC2` and `S` grow towards contact and the threat is on the left.
#[test]
fn disc_approaching_at_constant_speed() {
    let bg = Canvas::plain(200.0);
    let cx = 32.0;
    for speed in [1.0, 2.0] {
        let outs = run(&looming_disc(&bg, cx, 36.0, 40.0, 0.1, speed, 2.0, 0.3));
        let name = format!("disc at {speed} m/s");
        report(&name, &outs);
        assert_eq!(alerts(&outs[..LEAD]), 0, "{name}");
        let first = outs.iter().position(|o| o.alert()).expect("no alert");
        let before_end = outs.len() - first;
        let d_first = 2.0 - speed * moving(first) / 30.0;
        println!("  first alert {before_end} frames before the end, at {d_first:.2} m");
        assert!(
            before_end >= 10,
            "{name}: first alert only {before_end} frames before the end"
        );
        assert!(
            outs[first..].iter().all(|o| o.alert()),
            "{name}: the alert drops out"
        );
        let (start, end) = (&outs[first].vm, &outs[outs.len() - 1].vm);
        println!(
            "  ΣLPLC2 {} → {}, S {} → {}",
            start.lplc2_sum, end.lplc2_sum, start.strength, end.strength
        );
        assert!(end.lplc2_sum > 10 * start.lplc2_sum, "{name}");
        assert!(end.strength > 0.99 && end.short_mode, "{name}");
        for o in &outs[first..] {
            let x = o.vm.threat_x.unwrap();
            assert!((x - cx).abs() <= 6.0, "{name}, frame {}: X̄ {x}", o.frame);
            assert!(
                o.vm.theta_long.unwrap() > 145.0,
                "{name}, frame {}",
                o.frame
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Non-looming motion and disturbances: never an alert
// ---------------------------------------------------------------------------------------------

/// Squares shrinking 18 → 2 px in half size: dark on light and over texture at 1 px/frame,
/// bright on dark at 2 px/frame, at the left, centre and right.
#[test]
fn receding_squares_never_alert() {
    let (light, dark) = (Canvas::plain(200.0), Canvas::plain(20.0));
    let tex = Canvas::textured(150.0, 20, 6, 7);
    let mut scenes = Vec::new();
    for cx in POSITIONS {
        let shrink = |rate: f32, grey: f32| Looming {
            h0: 18.0,
            rate,
            ..Looming::square(cx, 36.0, 0.0, grey)
        };
        let cases = [
            ("dark", &light, shrink(-1.0, 40.0), 16),
            ("textured", &tex, shrink(-1.0, 20.0), 16),
            ("bright", &dark, shrink(-2.0, 220.0), 8),
        ];
        for (what, bg, obj, n) in cases {
            scenes.push((
                format!("receding {what} square at x = {cx}"),
                looming_scene(bg, &[obj], n + 10),
            ));
        }
    }
    assert_never_alerts(scenes);
}

/// Full-height bars 4 and 10 px wide crossing the field at 1, 1.5 and 2 px/frame (dark on
/// light, bright on dark, dark over texture), a bar going right to left, a horizontal bar going
/// down, and squares of half side 3, 6 and 10 px crossing at the same speeds.
#[test]
fn translating_bars_and_squares_never_alert() {
    let (light, dark) = (Canvas::plain(200.0), Canvas::plain(30.0));
    let tex = Canvas::textured(150.0, 20, 6, 7);
    let looks = [
        ("dark", &light, 40.0),
        ("bright", &dark, 230.0),
        ("textured", &tex, 20.0),
    ];
    let mut scenes = Vec::new();
    for (what, bg, grey) in looks {
        for speed in [1.0, 1.5, 2.0] {
            for width in [4.0, 10.0] {
                let name = format!("{what} bar {width} px at {speed} px/frame");
                scenes.push((name, bar(bg, speed, width, grey, true)));
            }
            for h in [3.0, 6.0, 10.0] {
                let name = format!("{what} square h {h} at {speed} px/frame");
                scenes.push((name, translating_square(bg, 36.0, h, speed, grey)));
            }
        }
        scenes.push((
            format!("{what} bar right to left"),
            bar(bg, -1.5, 6.0, grey, true),
        ));
        scenes.push((
            format!("{what} bar downwards"),
            bar(bg, 1.5, 6.0, grey, false),
        ));
    }
    assert_never_alerts(scenes);
}

/// Sine gratings (128 ± 60) of period 12–48 px and square-wave gratings (68 / 188) of period
/// 12–24 px drifting at 0.5–2 px/frame, stripes vertical and horizontal. Finer and coarser
/// square waves do alert: see the ignored tests below.
#[test]
fn drifting_gratings_never_alert() {
    let mut scenes = Vec::new();
    for speed in [0.5, 1.0, 1.5, 2.0] {
        for vertical in [true, false] {
            let o = if vertical { "vertical" } else { "horizontal" };
            for period in [12.0, 16.0, 24.0, 32.0, 48.0] {
                let name = format!("sine grating {period} px {o} at {speed} px/frame");
                scenes.push((name, grating(period, speed, 128.0, 60.0, false, vertical)));
            }
            for period in [12.0, 16.0, 24.0] {
                let name = format!("square grating {period} px {o} at {speed} px/frame");
                scenes.push((name, grating(period, speed, 128.0, 60.0, true, vertical)));
            }
        }
    }
    assert_never_alerts(scenes);
}

/// Whole-frame brightness steps of ±20, ±40 and ±60 grey levels (steps of 40–120 levels)
/// every 1, 2, 3, 5 and 10 frames, on a plain and a textured scene.
#[test]
fn global_flicker_never_alerts() {
    let plain = Canvas::plain(128.0);
    let tex = Canvas::textured(128.0, 20, 6, 11);
    let mut scenes = Vec::new();
    for amp in [20.0, 40.0, 60.0] {
        for hp in [1, 2, 3, 5, 10] {
            for (what, bg) in [("plain", &plain), ("textured", &tex)] {
                let name = format!("{what} flicker ±{amp} every {hp} frames");
                scenes.push((name, flicker(bg, amp, hp)));
            }
        }
    }
    assert_never_alerts(scenes);
}

/// A still scene with ±10 grey levels of uniform noise on every pixel, 120 frames per seed:
/// plain, textured, and with a dark square and bar standing in it.
#[test]
fn sensor_noise_on_a_still_scene_never_alerts() {
    let mut objects = Canvas::textured(150.0, 20, 6, 3);
    objects.square(30.0, 30.0, 10.0, 30.0);
    objects.rect(70.0, 76.0, -0.5, 72.0, 230.0);
    let backgrounds = [
        ("plain", Canvas::plain(128.0)),
        ("textured", Canvas::textured(128.0, 20, 6, 5)),
        ("objects", objects),
    ];
    let mut scenes = Vec::new();
    for (what, bg) in &backgrounds {
        let still = vec![bg.frame(); 120];
        for seed in 0..5 {
            scenes.push((
                format!("{what} ±10 noise, seed {seed}"),
                add_noise(&still, 10, seed),
            ));
        }
    }
    assert_never_alerts(scenes);
}

// ---------------------------------------------------------------------------------------------
// Several threats
// ---------------------------------------------------------------------------------------------

/// Fields stimulated in a frame, as (x, y).
fn stimulated(o: &Perception) -> Vec<(u8, u8)> {
    o.afs
        .iter()
        .filter(|a| a.lplc2 > 0)
        .map(|a| (a.x, a.y))
        .collect()
}

/// Whether every object has a stimulated field within 6 px of its centre.
fn each_has_a_field(o: &Perception, objs: &[Looming]) -> bool {
    let fields = stimulated(o);
    objs.iter().all(|b| {
        fields
            .iter()
            .any(|&(x, y)| (f32::from(x) - b.cx).abs() <= 6.0 && (f32::from(y) - b.cy).abs() <= 6.0)
    })
}

/// Two squares 68 px apart expanding together: two fields, one on each, stimulated at once
/// for most of the approach; the symmetric pair puts `X̄` straight ahead.
#[test]
fn two_simultaneous_approaches() {
    let bg = Canvas::plain(200.0);
    let objs = [
        Looming::square(15.0, 36.0, 1.0, 40.0),
        Looming::square(83.0, 36.0, 1.0, 40.0),
    ];
    let n = 12;
    let outs = run(&looming_scene(&bg, &objs, n));
    report("two squares", &outs);
    let both = outs.iter().filter(|o| each_has_a_field(o, &objs)).count();
    println!("  frames with a stimulated field on each square: {both}/{n}");
    if both < n / 2 {
        trace(&outs);
    }
    assert!(both >= n / 2, "{both}/{n}");
    assert!(outs.iter().all(|o| o.afs.len() <= 2));
    for o in outs.iter().filter(|o| stimulated(o).len() == 2) {
        let x = o.vm.threat_x.unwrap();
        assert!((x - CENTRE).abs() <= 3.0, "frame {}: X̄ {x}", o.frame);
    }
}

/// Three squares at the upper left, upper right and lower middle, more than R_AF + their
/// size apart: three fields stimulated at once.
#[test]
fn three_simultaneous_approaches() {
    let bg = Canvas::plain(200.0);
    let objs = [
        Looming::square(12.0, 12.0, 1.0, 40.0),
        Looming::square(86.0, 12.0, 1.0, 40.0),
        Looming::square(49.0, 62.0, 1.0, 40.0),
    ];
    let n = 8;
    let outs = run(&looming_scene(&bg, &objs, n));
    report("three squares", &outs);
    let all = outs.iter().filter(|o| each_has_a_field(o, &objs)).count();
    println!("  frames with a stimulated field on each square: {all}/{n}");
    if all < n / 2 {
        trace(&outs);
    }
    assert!(all >= n / 2, "{all}/{n}");
    for o in outs.iter().filter(|o| each_has_a_field(o, &objs)) {
        let x = o.vm.threat_x.unwrap();
        assert!((x - CENTRE).abs() <= 3.0, "frame {}: X̄ {x}", o.frame);
    }
}

/// Of two simultaneous approaches the faster (2 vs 0.5 px/frame) or the larger (closer: half
/// size 6 vs 2 px at the same 1 px/frame) pulls `X̄` to its side on at least 80 % of the alert
/// frames, whichever side it is on.
#[test]
fn the_closer_of_two_threats_dominates_the_centroid() {
    let bg = Canvas::plain(200.0);
    for (left, right) in [(15.0, 83.0), (83.0, 15.0)] {
        let fast = Looming::square(left, 36.0, 2.0, 40.0);
        let slow = Looming::square(right, 36.0, 0.5, 40.0);
        let large = Looming {
            h0: 6.0,
            ..Looming::square(left, 36.0, 1.0, 40.0)
        };
        let small = Looming::square(right, 36.0, 1.0, 40.0);
        for (what, objs) in [("faster", [fast, slow]), ("larger", [large, small])] {
            let outs = run(&looming_scene(&bg, &objs, 8));
            let name = format!("{what} square at x = {left}, other at {right}");
            report(&name, &outs);
            let xs: Vec<f32> = outs.iter().filter_map(|o| o.vm.threat_x).collect();
            let on_side = xs
                .iter()
                .filter(|&&x| (x < CENTRE) == (left < CENTRE))
                .count();
            println!("  X̄ on its side {on_side}/{}: {xs:.1?}", xs.len());
            assert!(xs.len() >= 5, "{name}");
            assert!(
                5 * on_side >= 4 * xs.len(),
                "{name}: {on_side}/{}",
                xs.len()
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Strength of the response
// ---------------------------------------------------------------------------------------------

/// The same square (40 on 200) growing from half size 2 to 18 px at 0.5, 1, 1.5 and 2
/// px/frame: the faster the approach, the larger the peak `ΣLPLC2` and the larger `ΣLPLC2`
/// when the square passes half size 10.
#[test]
fn a_faster_approach_gives_a_larger_response() {
    let bg = Canvas::plain(200.0);
    let mut last = (0, 0);
    for rate in [0.5, 1.0, 1.5, 2.0] {
        let obj = Looming::square(49.0, 36.0, rate, 40.0);
        let n = (16.0 / rate) as usize;
        let outs = run(&looming_scene(&bg, &[obj], n));
        let peak = outs.iter().map(|o| o.vm.lplc2_sum).max().unwrap();
        let at10 = outs[(LEAD..outs.len()).find(|&t| obj.half(t) >= 10.0).unwrap()]
            .vm
            .lplc2_sum;
        report(&format!("approach at {rate} px/frame"), &outs);
        println!("  peak ΣLPLC2 {peak}, ΣLPLC2 at half size 10: {at10}");
        assert!(
            peak > last.0 && at10 > last.1,
            "{rate} px/frame: {peak} {at10} after {last:?}"
        );
        last = (peak, at10);
    }
}

/// At a constant 1 px/frame, `ΣLPLC2` grows with the square's size (never falls, and is
/// several times larger at half size 17 than at 4), and grows with contrast.
#[test]
fn the_response_grows_with_size_and_contrast() {
    let bg = Canvas::plain(200.0);
    let mut peaks = Vec::new();
    for grey in [100.0, 40.0] {
        let obj = Looming::square(49.0, 36.0, 1.0, grey);
        let outs = run(&looming_scene(&bg, &[obj], 16));
        let sums: Vec<u32> = outs[LEAD + 1..].iter().map(|o| o.vm.lplc2_sum).collect();
        report(&format!("square of grey {grey} on 200"), &outs);
        println!("  ΣLPLC2 per frame: {sums:?}");
        assert!(sums.windows(2).all(|w| w[1] >= w[0]), "{sums:?}");
        assert!(sums[sums.len() - 1] > 4 * sums[1], "{sums:?}");
        peaks.push(sums[sums.len() - 1]);
    }
    assert!(peaks[1] > peaks[0], "contrast 160 vs 100: {peaks:?}");
}

// ---------------------------------------------------------------------------------------------
// Known limitations (measured with the defaults; these fail today)
// ---------------------------------------------------------------------------------------------

/// Sine and square gratings of period 8 px drifting at 1.5 px/frame alert on 54–56 of 60
/// frames with `ΣLPLC2` up to ~4·10⁵ (and period 10 px at 2 px/frame on 55/60): the
/// per-pixel rectified correlators pass ~25 % of the grating's motion to the opposite arms,
/// above `q_balance` = 15 %.
#[test]
#[ignore = "known limitation: fine gratings alert"]
fn fine_gratings_do_not_alert() {
    let mut scenes = Vec::new();
    for square in [false, true] {
        for vertical in [true, false] {
            let name = format!("8 px grating (square {square}, vertical {vertical})");
            scenes.push((name, grating(8.0, 1.5, 128.0, 60.0, square, vertical)));
        }
    }
    assert_never_alerts(scenes);
}

/// Horizontal square-wave gratings of period 28–48 px moving down at 1–2 px/frame alert on 1–3
/// of 60 frames (`ΣLPLC2` up to 9717, above `T_s`): the field rides an edge, then its centroid
/// jumps back to the next edge and for one frame all four arms pass the gate.
#[test]
#[ignore = "known limitation: coarse square gratings alert now and then"]
fn coarse_square_gratings_do_not_alert() {
    let mut scenes = Vec::new();
    for period in [28.0, 32.0, 40.0] {
        for speed in [1.0, 1.5, 2.0] {
            let name = format!("square grating {period} px at {speed} px/frame");
            scenes.push((name, grating(period, speed, 125.0, 65.0, true, false)));
        }
    }
    assert_never_alerts(scenes);
}

/// Full-range strobing (±100 grey levels every 2 frames) alerts on 12 of 60 frames with
/// `ΣLPLC2` 1899 (rounding in the 8-bit delay line and the truncated 3x3 mean at the borders
/// are not separable in space and time); with clipping (texture 150 ± 20, ±100 every frame)
/// 28 of 60 frames alert.
#[test]
#[ignore = "known limitation: strobing flicker alerts"]
fn strobing_flicker_does_not_alert() {
    let scenes = [
        (
            "±100 every 2 frames".to_string(),
            flicker(&Canvas::plain(128.0), 100.0, 2),
        ),
        (
            "clipped ±100 every frame".to_string(),
            flicker(&Canvas::textured(150.0, 20, 6, 7), 100.0, 1),
        ),
    ];
    assert_never_alerts(scenes);
}

/// A bright square expanding 1 px/frame makes no field at all, whatever its contrast (up to
/// 235 on 20): the ON saliency of a 1 px edge is `gain·w·contrast/3` ≤ 85 < `T_a` = 100.
/// From 1.5 px/frame (contrast ≥ 160) it alerts.
#[test]
#[ignore = "known limitation: slow bright approaches are invisible"]
fn slow_bright_approach_alerts() {
    let bg = Canvas::plain(20.0);
    let obj = Looming::square(49.0, 36.0, 1.0, 235.0);
    let outs = run(&looming_scene(&bg, &[obj], 16));
    check_approach("slow bright square", &outs, &obj, 16);
}
