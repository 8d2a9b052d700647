//! The recordings' extraction (issue 29) on snapshots drawn by this test, the committed data,
//! bad input, and the statistics' comparison.

use alvs_host::recordings::calibration::{find_floor, Calibration, Homography};
use alvs_host::recordings::compare::{ks_critical, ks_distance};
use alvs_host::recordings::runs::{list_snapshots, RUNS};
use alvs_host::recordings::snapshot::{
    find_marker, path_pixels, Mask, Rgb8, MARKER_BLUE, PATH_GREEN, SNAPSHOT_SIZE,
};
use alvs_host::recordings::stats::structure;
use alvs_host::recordings::track::{Extractor, LINE_WIDTH_PX};
use alvs_host::recordings::{self, compare, track_from_trail, Drawing, PathStats};

/// Floor corners of the synthetic snapshot (px) and the floor's size (mm): 1.3 px/mm.
const CORNERS: [(f64, f64); 4] = [
    (110.0, 30.0),
    (1810.0, 30.0),
    (1810.0, 1010.0),
    (110.0, 1010.0),
];
const FLOOR_MM: (f64, f64) = (1700.0 / 1.3, 980.0 / 1.3);

/// A snapshot as the tracker draws one: white surround, dark floor, the path so far in green
/// and the robot (white disc, blue ellipse) at its end.
fn snapshot(path: &[(f64, f64)]) -> Rgb8 {
    let (w, h) = SNAPSHOT_SIZE;
    let mut img = Rgb8::filled(w, h, [250, 250, 250]);
    for y in 30..1010 {
        for x in 110..1810 {
            img.set(x, y, [62, 55, 50]);
        }
    }
    let mut mask = Mask::new(w, h);
    for p in path.windows(2) {
        mask.thick_line(p[0], p[1], LINE_WIDTH_PX);
    }
    for (i, &on) in mask.bits.iter().enumerate() {
        if on {
            img.pixels[i] = PATH_GREEN;
        }
    }
    let &(rx, ry) = path.last().expect("a path");
    for dy in -30i64..=30 {
        for dx in -30i64..=30 {
            let d = ((dx * dx + dy * dy) as f64).sqrt();
            let (x, y) = (rx as i64 + dx, ry as i64 + dy);
            if d <= 27.0 {
                img.set(x, y, [245, 245, 245]);
            }
            // The tracker's ellipse outline, 2 px wide, radii 18 and 16.
            let e = ((dx as f64 / 18.0).powi(2) + (dy as f64 / 16.0).powi(2)).sqrt();
            if (0.9..=1.0).contains(&e) {
                img.set(x, y, MARKER_BLUE);
            }
        }
    }
    img
}

fn calibration() -> Calibration {
    let to = [(0.0, 0.0), (FLOOR_MM.0, 0.0), FLOOR_MM, (0.0, FLOOR_MM.1)];
    Calibration {
        homography: Homography::from_points(CORNERS, to).expect("a quadrilateral"),
        nadir_px: (960.0, 540.0),
        top_shrink: 1.0,
    }
}

#[test]
fn synthetic_snapshots_give_back_their_floor_marker_and_segments() {
    // A path in px: three straight runs, the second snapshot adds the third.
    let first = [(300.0, 200.0), (1500.0, 260.0), (1400.0, 800.0)];
    let full = [
        (300.0, 200.0),
        (1500.0, 260.0),
        (1400.0, 800.0),
        (500.0, 700.0),
    ];
    let shots = [snapshot(&first), snapshot(&full)];

    let quad = find_floor(&shots[0]).expect("the floor");
    for (got, want) in quad.corners.iter().zip(CORNERS) {
        assert!(
            (got.0 - want.0).abs() < 1.5 && (got.1 - want.1).abs() < 1.5,
            "{got:?} vs {want:?}"
        );
    }
    let m = find_marker(&shots[1]).expect("the marker");
    assert!(
        (m.x - 500.0).abs() <= 1.0 && (m.y - 700.0).abs() <= 1.0,
        "{m:?}"
    );

    let cal = calibration();
    let mut ex = Extractor::new(|x, y| cal.top_mm(x, y), 1.3);
    for (k, img) in shots.iter().enumerate() {
        let p = path_pixels(img);
        assert_eq!(p.ambiguous, 0);
        let m = find_marker(img).map(|m| (m.x, m.y, m.radius));
        let robot = m.map(|(x, y, _)| cal.top_mm(x, y));
        ex.push(
            k as u64 * 900,
            k as f64 * 30.0,
            p.mask,
            m,
            robot,
            p.ambiguous,
        );
    }
    let track = ex.finish();
    let len = |a: (f64, f64), b: (f64, f64)| ((a.0 - b.0).hypot(a.1 - b.1)) / 1.3;
    // Each run loses what the robot's disc (27 px) covers at the snapshot that ends it and
    // what the previous marker's zone (its box's half-diagonal + 4 px) skipped at its start.
    let disc = 27.0 / 1.3;
    let zone = ((36.0f64.hypot(32.0)) / 2.0 + 4.0) / 1.3;
    let want = [
        (len(full[0], full[1]), 0),
        (len(full[1], full[2]) - disc, 0),
        (len(full[2], full[3]) - disc - zone, 1),
    ];
    for (l, snap) in want {
        let found = track
            .segments
            .iter()
            .find(|s| s.snapshot == snap && (s.length_mm() - l).abs() < 6.0);
        assert!(
            found.is_some(),
            "no segment of {l:.0} mm in snapshot {snap}: {:?}",
            track.segments
        );
    }
    let s = structure(&track);
    assert_eq!(s.turns.len(), 2, "{:?}", s.turns);
    assert_eq!(track.snapshots[1].vanished_px, 0);
}

#[test]
fn a_simulated_square_gives_known_statistics() {
    // 90 mm from every wall, 60 s per lap at 10 trail points per second, two laps.
    let (w, h) = (1200.0, 700.0);
    let corners: [(f64, f64); 4] = [(90.0, 90.0), (1110.0, 90.0), (1110.0, 610.0), (90.0, 610.0)];
    let perimeter = 2.0 * (1020.0 + 520.0);
    let mut trail = Vec::new();
    for i in 0..=1200 {
        let t = i as f64 / 10.0;
        let mut s = (t / 60.0).fract() * perimeter;
        let mut p = corners[0];
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let l = (b.0 - a.0).hypot(b.1 - a.1);
            if s <= l {
                p = (a.0 + (b.0 - a.0) * s / l, a.1 + (b.1 - a.1) * s / l);
                break;
            }
            s -= l;
        }
        trail.push((t, p.0, p.1));
    }
    let drawing = Drawing {
        arena_mm: (w, h),
        px_per_mm: 1.3,
        snapshot_every_s: 30.0,
        marker_radius_px: 25.0,
    };
    let track = track_from_trail(&trail, &drawing);
    let st = PathStats::of(&track, (w, h));
    // The second lap retraces the first: its pixels are old, so only one lap is drawn.
    assert!(
        (st.path_mm - perimeter).abs() < 0.08 * perimeter,
        "{}",
        st.path_mm
    );
    // Every turn is 90 mm from two walls.
    assert!(st.turn_wall_mm.n >= 3, "{:?}", st.turn_wall_mm);
    assert!(
        (st.turn_wall_mm.median - 90.0).abs() < 8.0,
        "{:?}",
        st.turn_wall_mm
    );
    assert_eq!(st.share_within_50mm, 0.0);
    assert_eq!(st.share_within_100mm, 1.0);
    assert_eq!(st.pressed_share, 0.0);
    // The long sides are 1020 mm, the short ones 520 mm.
    assert!(
        st.run_mm.sample.iter().any(|&l| (l - 1020.0).abs() < 40.0),
        "{:?}",
        st.run_mm.sample
    );
    assert!(
        st.run_mm.sample.iter().any(|&l| (l - 520.0).abs() < 40.0),
        "{:?}",
        st.run_mm.sample
    );
    // Identical statistics pass every test; a slower robot fails the speed.
    assert!(compare(&st, &st).iter().all(|v| v.pass));
    let mut slow = st.clone();
    slow.mean_speed_mm_s *= 0.7;
    let v = compare(&st, &slow);
    assert!(v
        .iter()
        .any(|v| v.statistic.starts_with("mean speed") && !v.pass));
}

#[test]
fn the_committed_data_loads_and_gives_the_documented_figures() {
    let arena = recordings::arena().expect("arena.json");
    // docs/recordings.md: 1309 x 751 mm, 1.293 px/mm, 13 of the 15 obstacles found.
    assert!(
        (arena.size_x_mm - 1308.6).abs() < 1.0,
        "{}",
        arena.size_x_mm
    );
    assert!((arena.size_y_mm - 751.4).abs() < 1.0, "{}", arena.size_y_mm);
    assert!((arena.px_per_mm - 1.2927).abs() < 0.001);
    assert_eq!(arena.obstacles.len(), 13);
    assert!((arena.obstacle_k.expect("k") - 0.0364).abs() < 0.0005);
    assert!(arena.camera_shift_px < 5.0);
    let runs = recordings::all_runs().expect("the runs");
    assert_eq!(runs.len(), RUNS.len());
    let r = &runs[0];
    assert_eq!(r.run, "v10.9_9m43s");
    assert_eq!(r.track.snapshots.len(), 23);
    assert!(r.provenance.files.iter().all(|f| f.sha256.len() == 64));
    let st = r.stats(&arena);
    assert_eq!(st.run_mm.n, 263);
    assert!(
        (st.turns_per_min - 19.3).abs() < 0.05,
        "{}",
        st.turns_per_min
    );
    assert!((st.coverage - 0.78).abs() < 0.005, "{}", st.coverage);
    assert!(recordings::run("nope").is_err());
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let dir = std::env::temp_dir().join(format!("alvs-rec-{}", std::process::id()));
    let run = &RUNS[0];
    let e = list_snapshots(&dir, run).expect_err("missing folder");
    assert!(e.to_string().contains("no such folder"), "{e}");
    let folder = dir.join(run.folder);
    std::fs::create_dir_all(&folder).expect("temp dir");
    std::fs::write(folder.join("notes.txt"), "x").expect("write");
    let e = list_snapshots(&dir, run).expect_err("a non-PNG");
    assert!(e.to_string().contains("not a <frame number>.png"), "{e}");
    std::fs::remove_file(folder.join("notes.txt")).expect("rm");
    std::fs::write(folder.join("100.png"), "not a png").expect("write");
    let files = list_snapshots(&dir, run).expect("one file");
    let e = Rgb8::load_snapshot(&files[0].path).expect_err("not a PNG");
    assert!(e.to_string().contains("not a readable PNG"), "{e}");
    image::RgbImage::new(64, 48)
        .save(folder.join("100.png"))
        .expect("png");
    let e = Rgb8::load_snapshot(&files[0].path).expect_err("wrong size");
    assert!(e.to_string().contains("64x48 px"), "{e}");
    // A snapshot with no floor is an error too.
    assert!(find_floor(&Rgb8::filled(1920, 1080, [250, 250, 250])).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ks_distance_on_known_samples() {
    assert_eq!(
        ks_distance(&[1.0, 2.0, 3.0, 4.0], &[3.0, 4.0, 5.0, 6.0]),
        0.5
    );
    assert_eq!(ks_distance(&[1.0, 2.0, 3.0], &[1.0, 2.0, 3.0]), 0.0);
    assert_eq!(ks_distance(&[1.0, 2.0], &[5.0, 6.0]), 1.0);
    assert_eq!(ks_distance(&[], &[1.0]), 1.0);
    assert!((ks_critical(100, 100) - 1.358 * 0.02f64.sqrt()).abs() < 1e-12);
}
