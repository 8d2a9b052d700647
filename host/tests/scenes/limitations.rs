//! Known limitations (measured with the defaults; these fail today).

use super::*;

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

/// Frames of full-contrast random noise (issue 31, selectivity): every pixel uniform over
/// ±255, ±128 or ±64 grey levels around 128, new on every frame, 60 frames, six seeds; and 1–3
/// such frames bursting into a still textured scene. Measured with the defaults: every noise
/// scene alerts from the first frame after the warm-up on 56 of 60 frames, all in short mode
/// (ΣLPLC2 3·10⁵–2.7·10⁶); a single noise frame alerts once, in short mode. The correlators
/// see motion in every direction in every quadrant, and Eq. (8) sums only the outward
/// directions: nothing in the model weighs the inward motion that a looming object lacks
/// and noise has as much of (the fly's LPLC2 is inhibited by it, through LPi neurons).
#[test]
#[ignore = "known limitation: random noise frames alert"]
fn random_noise_frames_do_not_alert() {
    let grey = [Canvas::plain(128.0).frame()];
    let mut scenes = Vec::new();
    for seed in 0..6u64 {
        for amp in [255, 128, 64] {
            let frames = add_noise(&grey.repeat(60), amp, seed);
            scenes.push((format!("noise ±{amp}, seed {seed}"), frames));
        }
        let still = Canvas::textured(128.0, 20, 6, seed).frame();
        for burst in 1..4usize {
            let mut frames = vec![still; 40];
            frames.splice(
                10..10 + burst,
                add_noise(&grey.repeat(burst), 128, seed + 100),
            );
            scenes.push((format!("{burst} noise frames, seed {seed}"), frames));
        }
    }
    assert_never_alerts(scenes);
}
