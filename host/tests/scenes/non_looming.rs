//! Non-looming motion and disturbances: never an alert.

use super::*;
use alvs_tasks::model::params::ShortGates;
use core::num::NonZeroU8;

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

/// Horizontal square-wave gratings of period 28–40 px moving down at 1–2 px/frame. This was a
/// known limitation (1–3 of 60 frames alerted, `ΣLPLC2` up to 9717: a field rode an edge, its
/// centroid jumped back to the next edge and for one frame all four arms passed the gate); with
/// today's defaults none alerts (re-measured when the tests were split by topic).
#[test]
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

/// Full-range strobing (±100 grey levels every 2 frames), and a textured scene driven into
/// clipping every frame: whole-field luminance events (`Params::flicker_pct`), never an alert.
/// This was a known limitation of the paper's model, which still has it (next test).
#[test]
fn strobing_flicker_does_not_alert() {
    assert_never_alerts(strobing());
}

fn strobing() -> [(String, Vec<Frame>); 2] {
    [
        (
            "±100 every 2 frames".to_string(),
            flicker(&Canvas::plain(128.0), 100.0, 2),
        ),
        (
            "clipped ±100 every frame".to_string(),
            flicker(&Canvas::textured(150.0, 20, 6, 7), 100.0, 1),
        ),
    ]
}

/// The paper's model on the same strobing: 12 of 60 frames alert with `ΣLPLC2` 1,899 (the
/// rounding of the 8-bit delay line and of the 3x3 means at the borders is not separable in
/// space and time); clipped, 28 of 60.
#[test]
fn the_paper_model_alerts_on_strobing_flicker() {
    let counts: Vec<usize> = strobing()
        .iter()
        .map(|(name, frames)| {
            let mut net = Network::new(Params::PAPER).unwrap();
            let outs: Vec<Perception> = frames.iter().map(|f| net.step(f)).collect();
            report(&format!("paper model, {name}"), &outs)
        })
        .collect();
    assert_eq!(counts, [12, 28]);
}

/// Motion adaptation (`Params::adapt_frames`): a steady stimulus — here the fine grating the
/// known limitation above alerts on — holds the paper's model in short mode from frame 4 to
/// the end; the default's short mode switches off once the running mean has caught up with the
/// steady response (frame 24, 0.7 s) and stays off but for single frames (the alerts remain:
/// adaptation gates only the short mode).
#[test]
fn a_steady_stimulus_adapts_out_of_short_mode() {
    let frames = grating(8.0, 1.5, 128.0, 60.0, false, true);
    let short = |p: Params| {
        let mut net = Network::new(p).unwrap();
        let outs: Vec<Perception> = frames.iter().map(|f| net.step(f)).collect();
        let on: Vec<usize> = (0..outs.len()).filter(|&i| outs[i].short_mode()).collect();
        (on, alerts(&outs))
    };
    let (paper, paper_alerts) = short(Params::PAPER);
    let (adapted, alvs_alerts) = short(Params {
        short: ShortGates {
            adapt_frames: NonZeroU8::new(30),
            ..Params::default().short
        },
        ..Params::default()
    });
    println!(
        "short mode: paper {paper:?}, default {adapted:?}; alerts {paper_alerts} / {alvs_alerts}"
    );
    assert!(
        paper.len() >= 50,
        "steady short mode without adaptation: {paper:?}"
    );
    let late = adapted.iter().filter(|&&i| i >= 30).count();
    assert!(late <= 3, "adapted after a second: {adapted:?}");
    assert!(alvs_alerts >= 40, "still seen: {alvs_alerts}");
}

/// One whole-frame brightness step (issue 31, selectivity), its size and sign varied (±20, ±40,
/// ±80, ±120 grey levels) and its timing against the warm-up (`Params::warmup`, 4 frames): on
/// frames 1 to 11, on a plain and a textured scene, 40 frames each. Issue 31 reported an alert
/// on the frame after a step (the delayed channels still carrying it); measured again over
/// these 176 scenes none alerts, nor with the paper's model, nor with the default without
/// `flicker` or without `warmup`: a guard against the model learning to.
#[test]
fn single_brightness_steps_never_alert() {
    let backgrounds = [
        ("plain", Canvas::plain(128.0)),
        ("textured", Canvas::textured(128.0, 20, 6, 11)),
    ];
    let mut scenes = Vec::new();
    for (what, bg) in &backgrounds {
        for d in [-120.0f32, -80.0, -40.0, -20.0, 20.0, 40.0, 80.0, 120.0] {
            let (before, after) = (bg.frame(), bg.offset(d).frame());
            for at in 1..12usize {
                let frames = (0..40)
                    .map(|t| if t < at { before } else { after })
                    .collect();
                scenes.push((format!("{what} step {d:+} at frame {at}"), frames));
            }
        }
    }
    assert_never_alerts(scenes);
}

/// An object a few centimetres from the camera receding fast (issue 31, selectivity): a disc
/// of 20 mm radius from 25, 40, 60 and 100 mm away at 0.1, 0.3 and 0.6 m/s until 600 mm, bright
/// on dark, dark on light and dark on texture, at the left, centre and right. At 25 mm it fills
/// the view. None alerts (nor with the paper's model).
#[test]
fn close_objects_receding_fast_never_alert() {
    let cases = [
        ("bright", Canvas::plain(20.0), 220.0),
        ("dark", Canvas::plain(200.0), 30.0),
        ("textured", Canvas::textured(150.0, 20, 6, 7), 20.0),
    ];
    let mut scenes = Vec::new();
    for (what, bg, grey) in &cases {
        for cx in POSITIONS {
            for v in [0.1f32, 0.3, 0.6] {
                for d0 in [0.025f32, 0.04, 0.06, 0.1] {
                    scenes.push((
                        format!("{what} disc at x = {cx} receding at {v} m/s from {d0} m"),
                        looming_disc(bg, cx, 36.0, *grey, 0.02, -v, d0, 0.6),
                    ));
                }
            }
        }
    }
    let reversed: Vec<(String, Vec<Frame>)> = scenes
        .iter()
        .map(|(n, f)| (n.clone(), f.iter().rev().copied().collect()))
        .collect();
    // played backwards the same frames approach: they are stimuli the network does see
    // (105 of the 108 alert)
    let approaching = alerting_under(Params::default(), reversed);
    assert!(
        approaching >= 100,
        "{approaching} of 108 approaching scenes alert"
    );
    assert_never_alerts(scenes);
}

/// `frames` with their frames `at..at + n` replaced by random noise of amplitude `amp` around
/// grey 128, seeded.
fn burst(frames: &[Frame], at: usize, n: usize, amp: i32, seed: u64) -> Vec<Frame> {
    let mut out = frames.to_vec();
    let grey = [Canvas::plain(128.0).frame()];
    out.splice(at..at + n, add_noise(&grey.repeat(n), amp, seed));
    out
}

/// Frames of random noise (issue 31, selectivity), with the noise's contrast, mean and seed
/// varied: 60 frames of new noise every frame, ±24 to ±255 grey levels around 80, 128 and
/// 176; and bursts of 1 or 3 noise frames (±32, ±255) from the priming frame to frame 12
/// (the warm-up ends at 4) into a still textured scene, a square driving across and a
/// drifting grating. None alerts: each noise frame, and the frame measured against it, is
/// silenced and leaves nothing in the delay line (`Params::noise_pct`). Before that mechanism
/// every noise scene alerted on 56 of 60 frames, in short mode; the paper's model still does
/// (below).
#[test]
fn random_noise_frames_never_alert() {
    let mut scenes = Vec::new();
    for seed in 0..2u64 {
        for mean in [80.0, 128.0, 176.0] {
            for amp in [24, 32, 64, 128, 255] {
                let frames = add_noise(&[Canvas::plain(mean).frame()].repeat(60), amp, seed);
                scenes.push((format!("noise ±{amp} around {mean}, seed {seed}"), frames));
            }
        }
    }
    let backgrounds = [
        (
            "still texture",
            vec![Canvas::textured(128.0, 20, 6, 3).frame(); 40],
        ),
        (
            "square driving across",
            translating_square(&Canvas::plain(200.0), 36.0, 8.0, 2.0, 40.0),
        ),
        (
            "drifting grating",
            grating(24.0, 1.0, 128.0, 60.0, false, true),
        ),
    ];
    for (what, frames) in &backgrounds {
        for n in [1, 3] {
            for amp in [32, 255] {
                for at in [0, 2, 4, 7, 12] {
                    let name = format!("{what}: {n} noise frames ±{amp} at frame {at}");
                    scenes.push((name, burst(&frames[..40], at, n, amp, at as u64)));
                }
            }
        }
    }
    assert_never_alerts(scenes);
}

/// What `Params::noise_pct` costs and does: without it (the paper's model, or the default with
/// it off) noise alerts; a noise frame in the middle of an approach silences the threat on that
/// frame, the frame after (measured against it) and the next (the delay line refilling, as
/// after a start), 100 ms, and the alert is back on the third frame after.
#[test]
fn noise_frames_cost_a_looming_object_three_frames() {
    let grey = [Canvas::plain(128.0).frame()];
    let noise = add_noise(&grey.repeat(30), 64, 5);
    assert!(alerts(&run_with(Params::PAPER, &noise)) > 20);
    let off = Params {
        mechanisms: alvs_tasks::model::params::Mechanisms {
            noise_pct: None,
            ..Params::ALVS.mechanisms
        },
        ..Params::ALVS
    };
    assert!(alerts(&run_with(off, &noise)) > 20);
    let obj = Looming::square(49.0, 36.0, 1.0, 40.0);
    let approach = looming_scene(&Canvas::plain(200.0), &[obj], 16);
    let clean = run(&approach);
    let hit = run(&burst(&approach, LEAD + 6, 1, 255, 9));
    for t in LEAD + 4..approach.len() {
        let expect = clean[t].alert() && !(LEAD + 6..=LEAD + 8).contains(&t);
        assert_eq!(hit[t].alert(), expect, "frame {t}");
    }
}
