//! The camera's gain models (`alvs_sim::GainModel`) on rendered views: the documented AEC holds
//! its exposure in a steady view and steps it, 1/16 a frame, when a dark robot close ahead
//! darkens the view; the steady camera never changes it; the jitter draws a new gain each frame,
//! and the real clips' camera a smaller one, the one the recorded real clips measure.
//!
//! `cargo test --target host-tuple -p alvs-sim --test camera_aec`.

use alvs_sim::render::CAMERA_FORWARD_MM;
use alvs_sim::worlds::BuiltinWorld;
use alvs_sim::{Camera, GainModel, Pose, Renderer, SensorNoise};

/// The mean grey of each of 40 frames of a robot in the replica facing a wall across the
/// arena; from frame 10 on, a robot stands 50 mm ahead of its camera.
fn means(model: GainModel) -> Vec<f64> {
    let world = BuiltinWorld::Fu2019.world();
    let r = Renderer::new(&world);
    let eye = Pose::new(300.0, 380.0, 0.0);
    let near = Pose::new(300.0 + CAMERA_FORWARD_MM + 50.0, 380.0, 90.0);
    let mut noise = SensorNoise {
        pixel_sigma: 0.0,
        ..SensorNoise::typical()
    };
    model.apply(&mut noise);
    let mut cam = Camera::new(noise, 3);
    let mut frame = [0u8; alvs_tasks::PIXELS];
    (0..40)
        .map(|i| {
            let bodies = if i < 10 { vec![eye] } else { vec![eye, near] };
            cam.capture(&r, &bodies, 0, &mut frame);
            frame.iter().map(|&v| f64::from(v)).sum::<f64>() / frame.len() as f64
        })
        .collect()
}

#[test]
fn the_aec_holds_in_a_steady_view_and_steps_back_toward_its_region_when_it_darkens() {
    let (aec, steady) = (means(GainModel::Aec), means(GainModel::Steady));
    // a steady view: the same pictures as a camera whose exposure never moves
    assert_eq!(aec[..11], steady[..11]);
    // the robot ahead darkens the view by more than the stable region's 8.3 %
    let (before, after) = (steady[9], steady[10]);
    assert!(after < 0.9 * before, "{before:.1} → {after:.1}");
    assert_eq!(steady[10..].iter().fold(f64::NAN, |a, &b| a.max(b)), after);
    // the AEC brightens the next frames by 1/16 a step until the mean is back inside the region
    let gain = aec[11] / steady[11];
    assert!((gain - 17.0 / 16.0).abs() < 0.01, "first step {gain:.3}");
    let last = aec[39];
    assert!(
        last >= (1.0 - 18.0 / 216.0) * before - 1.0 && last <= before + 1.0,
        "settled at {last:.1} (first view {before:.1})"
    );
    // and holds there
    assert_eq!(aec[35..].iter().fold(f64::NAN, |a, &b| a.max(b)), last);
}

#[test]
fn the_jitter_moves_every_frame() {
    let jitter = means(GainModel::Jitter);
    let changed = jitter[..10].windows(2).filter(|w| w[0] != w[1]).count();
    assert_eq!(changed, 9, "{jitter:?}");
}

/// The real clips' camera (`clips`, the worlds') draws a gain every frame too, about a seventh
/// as large as the former 2 % draw: the frame means of the steady view move, by less than 1 % a
/// frame.
#[test]
fn the_clips_camera_moves_by_a_fraction_of_the_jitter() {
    let (clips, jitter) = (means(GainModel::Clips), means(GainModel::Jitter));
    let steps = |m: &[f64]| -> Vec<f64> {
        m[..10]
            .windows(2)
            .map(|w| (w[1] / w[0] - 1.0).abs())
            .collect()
    };
    let (small, large) = (steps(&clips), steps(&jitter));
    assert!(small.iter().filter(|&&s| s > 0.0).count() >= 5, "{clips:?}");
    assert!(small.iter().all(|&s| s < 0.01), "{small:?}");
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    assert!(
        mean(&small) < mean(&large) / 3.0,
        "{small:?} against {large:?}"
    );
}

/// The frame-to-frame gain's standard deviation of one recorded clip: per pair of frames the
/// least-squares gain `Σ P(t)·P(t−1) / Σ P(t−1)²` over the pixels that barely change
/// (`P(t−1)` in 40–215, not clipped, `|P(t) − P(t−1)|` ≤ 12 grey levels: what moves is left
/// out), as `docs/notes/2026-11-28-camera-gain.md` measures it.
fn clip_gain_sd(name: &str) -> f64 {
    let path = format!("{}/../data/clips/{name}.y8", env!("CARGO_MANIFEST_DIR"));
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let frames: Vec<&[u8]> = bytes.chunks_exact(alvs_tasks::PIXELS).collect();
    let gains: Vec<f64> = frames
        .windows(2)
        .filter_map(|w| {
            let (mut pq, mut qq) = (0.0f64, 0.0f64);
            for (&q, &p) in w[0].iter().zip(w[1]) {
                let (q, p) = (f64::from(q), f64::from(p));
                if q > 40.0 && q < 215.0 && (p - q).abs() <= 12.0 {
                    pq += p * q;
                    qq += q * q;
                }
            }
            (qq > 0.0).then(|| pq / qq)
        })
        .collect();
    let n = gains.len() as f64;
    let mean = gains.iter().sum::<f64>() / n;
    (gains.iter().map(|g| (g - mean) * (g - mean)).sum::<f64>() / n).sqrt()
}

/// The worlds' camera gain (`clips`, `CLIPS_GAIN_SIGMA`) is what the ten recorded real clips
/// measure: their frame-to-frame gain varies by 0.08–0.34 % in 8 of 10, and the median of all
/// ten (0.32 %) is within a quarter of the constant (0.3 %); the former 2 % is not.
#[test]
fn the_clips_gain_is_what_the_real_clips_measure() {
    let names = [
        "real_UAV_outdoor_1",
        "real_UAV_outdoor_1_slow",
        "real_UAV_outdoor_2",
        "real_UAV_outdoor_black_rectangle",
        "real_bear_attack",
        "real_bird_attack",
        "real_bird_attack_2",
        "real_bird_attack_2_slow",
        "real_car_attack",
        "real_helmet_attack",
    ];
    let mut sd: Vec<f64> = names.iter().map(|n| clip_gain_sd(n)).collect();
    sd.sort_by(f64::total_cmp);
    assert!(sd.iter().filter(|&&s| s < 0.004).count() >= 8, "{sd:?}");
    let median = (sd[4] + sd[5]) / 2.0;
    let sigma = f64::from(alvs_sim::aec::CLIPS_GAIN_SIGMA);
    assert!(
        (median - sigma).abs() < sigma / 4.0,
        "median {median} against {sigma}: {sd:?}"
    );
}
