//! What `recordings stats` shows: a table of the runs' statistics, and per run a picture of
//! the extracted path in floor mm with histograms of its straight runs and turns.

use alvs_sim::canvas::{Canvas, Rgb};
use alvs_sim::{Arena, Pose, TopDown};

use super::stats::{structure, Distribution, PathStats};
use super::{ArenaGeometry, RunFile};

/// The statistics table (GitHub markdown), one row per run.
pub fn table(rows: &[(&RunFile, PathStats)]) -> String {
    let mut s = String::from(
        "| run | speed cm/s | duration s | fps | path m | runs | run mm mean (q1/med/q3) | turns/min | wall mm at turns (med) | ≤50 mm | ≤100 mm | pressed | coverage | mean speed mm/s | skipped px (hidden/leftover/ambiguous) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (run, st) in rows {
        let snaps = &run.track.snapshots;
        let sum = |f: fn(&super::SnapshotFix) -> usize| snaps.iter().map(f).sum::<usize>();
        let new = sum(|s| s.new_px).max(1) as f64;
        s.push_str(&format!(
            "| {} | {} | {:.0} | {:.1} | {:.1} | {} | {:.0} ({:.0}/{:.0}/{:.0}) | {:.1} | {:.0} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1} | {:.1} % / {:.1} % / {} |\n",
            run.run,
            run.speed_cm_s,
            st.duration_s,
            run.tracker_fps.0,
            st.path_mm / 1000.0,
            st.run_mm.n,
            st.run_mm.mean,
            st.run_mm.q1,
            st.run_mm.median,
            st.run_mm.q3,
            st.turns_per_min,
            st.turn_wall_mm.median,
            st.share_within_50mm,
            st.share_within_100mm,
            st.pressed_share,
            st.coverage,
            st.mean_speed_mm_s,
            100.0 * sum(|s| s.hidden_px) as f64 / (new + sum(|s| s.hidden_px) as f64),
            100.0 * sum(|s| s.leftover_px) as f64 / new,
            sum(|s| s.ambiguous_px),
        ));
    }
    s
}

/// Blue (early) to red (late).
fn time_colour(f: f64) -> Rgb {
    let f = f.clamp(0.0, 1.0);
    [(40.0 + 200.0 * f) as u8, 60, (230.0 - 200.0 * f) as u8]
}

/// The run's path: segments coloured by the snapshot they appeared in, obstacles as circles,
/// turns as crosses, the robot at each snapshot as a disc.
pub fn path_picture(run: &RunFile, arena: &ArenaGeometry) -> Canvas {
    let mut td = TopDown::new(&Arena::new(arena.size_x_mm, arena.size_y_mm), 0.5);
    td.title(&format!(
        "{}: {} segments, {} straight runs, colour = time (blue early, red late)",
        run.run,
        run.track.segments.len(),
        structure(&run.track).runs.len()
    ));
    for o in &arena.obstacles {
        let r = o.diameter_mm / 2.0;
        let ring: Vec<(f64, f64)> = (0..=36)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / 36.0;
                (o.x_mm + r * a.cos(), o.y_mm + r * a.sin())
            })
            .collect();
        td.wide_trail(&ring, [90, 90, 90], 2);
    }
    let last = run.track.snapshots.len().max(2) - 1;
    for s in &run.track.segments {
        td.trail(&[s.a, s.b], time_colour(s.snapshot as f64 / last as f64));
    }
    for (x, y) in structure(&run.track).turns {
        td.mark(x, y, [0, 150, 0]);
    }
    // The robot at each snapshot (its heading is not recorded: the tick points right).
    for f in &run.track.snapshots {
        if let Some((x, y)) = f.robot_mm {
            td.robot(&Pose::new(x, y, 0.0), [250, 250, 250]);
        }
    }
    td.into_canvas()
}

/// A histogram of `d` in `bins` bins up to `max`, with a title and axis labels.
pub fn histogram(title: &str, d: &Distribution, max: f64, bins: usize) -> Canvas {
    let (w, h) = (360usize, 220usize);
    let mut c = Canvas::new(w, h, [255, 255, 255]);
    c.text(8, 4, title, [20, 20, 20], 1);
    let mut counts = vec![0usize; bins];
    for &v in &d.sample {
        let b = ((v / max) * bins as f64)
            .floor()
            .clamp(0.0, bins as f64 - 1.0) as usize;
        counts[b] += 1;
    }
    let top = counts.iter().copied().max().unwrap_or(1).max(1) as f64;
    let (x0, y0, pw, ph) = (30i32, 24i32, (w - 44) as i32, (h - 56) as i32);
    let bw = pw / bins as i32;
    for (i, &n) in counts.iter().enumerate() {
        let bh = (n as f64 / top * ph as f64).round() as i32;
        c.fill_rect(x0 + i as i32 * bw, y0 + ph - bh, bw - 1, bh, [70, 110, 200]);
    }
    c.line(x0, y0 + ph, x0 + bw * bins as i32, y0 + ph, [20, 20, 20]);
    c.text(x0, y0 + ph + 4, "0", [20, 20, 20], 1);
    let m = format!("{max:.0} mm");
    c.text(
        x0 + bw * bins as i32 - (Canvas::text_size(&m, 1).0 as i32),
        y0 + ph + 4,
        &m,
        [20, 20, 20],
        1,
    );
    c.text(
        x0,
        y0 + ph + 16,
        &format!(
            "n {}  mean {:.0}  median {:.0}  max count {}",
            d.n, d.mean, d.median, top as usize
        ),
        [20, 20, 20],
        1,
    );
    c
}

/// The run's picture: the path above, the two histograms below.
pub fn run_picture(run: &RunFile, arena: &ArenaGeometry, st: &PathStats) -> Canvas {
    let path = path_picture(run, arena);
    let hist = Canvas::side_by_side(&[
        histogram(
            "straight-run length (last bin: and longer)",
            &st.run_mm,
            1200.0,
            24,
        ),
        histogram(
            "wall distance at turns (last bin: and more)",
            &st.turn_wall_mm,
            350.0,
            14,
        ),
    ]);
    Canvas::stacked(&[path, hist])
}
