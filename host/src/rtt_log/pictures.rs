//! The log's pictures (`cargo alvs log --png DIR`): the LPLC2 sum and the alerts over the
//! records with the FSM state as a band (`timeline.png`), the attention fields' centroids over
//! the records (`fields.png`), and the histogram of cycles per frame with the deadline and the
//! model's worst frame marked (`cycles.png`).

use std::path::{Path, PathBuf};

use alvs_tasks::model::fsm::State;
use alvs_tasks::robot::telemetry::Record;
use alvs_tasks::{HEIGHT, MAX_AFS, WIDTH};
use anyhow::{Context, Result};

use super::report::LogReport;
use super::Log;
use alvs_sim::canvas::{Canvas, Histogram, Plot, Rgb, RED};

/// The band's colour of each state (light, so the series over it stay readable).
pub fn state_colour(s: State) -> Rgb {
    match s {
        State::Wander => [200, 225, 200],
        State::LongTakeoff => [250, 210, 150],
        State::Escape => [245, 170, 170],
        State::ShortTakeoff => [225, 180, 240],
        State::Spin => [170, 215, 245],
        State::Look => [215, 215, 215],
        State::Stop => [240, 240, 190],
    }
}

const X_LABEL: &str = "telemetry record (one per processed frame, 30 a second)";

/// LPLC2 sum and alerts per record, the state as a band, with a gap where the frame count
/// restarts (a reset, or the model priming again after a fault).
pub fn timeline(records: &[&Record]) -> Canvas {
    let sums: Vec<f32> = records.iter().map(|r| r.lplc2_sum as f32).collect();
    let alerts: Vec<usize> = (0..records.len()).filter(|&i| records[i].alert()).collect();
    let band: Vec<Option<Rgb>> = records
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let restart = i > 0 && r.frame <= records[i - 1].frame;
            (!restart).then(|| state_colour(r.state))
        })
        .collect();
    let legend: Vec<(&str, Rgb)> = State::ALL
        .iter()
        .filter(|s| records.iter().any(|r| r.state == **s))
        .map(|&s| (s.name(), state_colour(s)))
        .collect();
    let top = sums.iter().copied().fold(0.0, f32::max).max(1.0) * 1.1;
    Plot::new("LPLC2 sum per frame, alerts, and the FSM state (band)")
        .series("LPLC2 sum", &sums)
        .y_range(0.0, top)
        .markers("alert", &alerts)
        .band(&band, &legend)
        .x_label(X_LABEL)
        .render(1000, 500)
}

/// The fields' centroid columns and rows per record: series k is the k-th field of each
/// record (the network's order, oldest first).
pub fn fields(records: &[&Record]) -> Canvas {
    let slot = |k: usize, coord: fn(&alvs_tasks::robot::telemetry::AfTelemetry) -> u8| {
        records
            .iter()
            .map(|r| r.afs.get(k).map_or(f32::NAN, |a| f32::from(coord(a))))
            .collect::<Vec<f32>>()
    };
    let used = records
        .iter()
        .map(|r| r.afs.len())
        .max()
        .unwrap_or(0)
        .max(1);
    let panel = |title: &str, coord: fn(&alvs_tasks::robot::telemetry::AfTelemetry) -> u8, max| {
        let mut p = Plot::new(title).x_label(X_LABEL).y_range(0.0, max as f32);
        for k in 0..used.min(MAX_AFS) {
            p = p.series(&format!("field {}", k + 1), &slot(k, coord));
        }
        p.render(1000, 450)
    };
    Canvas::stacked(&[
        panel(
            "attention-field centroids: column (0 left, 98 right)",
            |a| a.x,
            WIDTH - 1,
        ),
        panel(
            "attention-field centroids: row (0 top, 71 bottom)",
            |a| a.y,
            HEIGHT - 1,
        ),
    ])
}

/// Cycles per frame in millions, the deadline and the model's worst frame marked.
pub fn cycles(records: &[&Record], report: &LogReport) -> Canvas {
    let m = |c: f64| c / 1e6;
    let values: Vec<f64> = records.iter().map(|r| m(f64::from(r.cycles))).collect();
    let period = m(f64::from(alvs_tasks::robot::health::FRAME_BUDGET_CYCLES));
    let most = values.iter().copied().fold(period, f64::max);
    let mut h = Histogram::new(
        "cycles per processed frame",
        &values,
        70,
        (0.0, (most * 1.1 * 10.0).ceil() / 10.0),
    )
    .x_label("million cycles (1 M = 5.6 ms at 180 MHz)")
    .mark(
        &format!("deadline: the frame period, {period:.1} M = 33.3 ms"),
        period,
        RED,
    );
    if let Some(w) = &report.worst_case {
        h = h.mark(
            &format!(
                "the model's worst frame, {:.2} M pessimistic ({})",
                m(w.pessimistic as f64),
                w.source
            ),
            m(w.pessimistic as f64),
            [30, 150, 30],
        );
    }
    h.render(1000, 500)
}

/// Writes the three pictures into `dir` (created if missing); returns their paths.
pub fn write(log: &Log, report: &LogReport, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let records: Vec<&Record> = log.records().collect();
    let pictures = [
        ("timeline.png", timeline(&records)),
        ("fields.png", fields(&records)),
        ("cycles.png", cycles(&records, report)),
    ];
    pictures
        .into_iter()
        .map(|(name, c)| {
            let path = dir.join(name);
            c.save_png(&path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            Ok(path)
        })
        .collect()
}
