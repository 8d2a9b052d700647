//! Real against simulated path statistics: each statistic with a stated tolerance, pass or
//! fail. Distributions by the two-sample Kolmogorov-Smirnov test at α = 0.05, means and
//! rates within ±20 %, shares within ±20 % or an absolute band where they are near 0.

use serde::{Deserialize, Serialize};

use super::stats::{Distribution, PathStats};

/// Two-sample Kolmogorov-Smirnov distance: the largest gap between the empirical CDFs.
pub fn ks_distance(a: &[f64], b: &[f64]) -> f64 {
    let mut a: Vec<f64> = a.iter().copied().filter(|v| v.is_finite()).collect();
    let mut b: Vec<f64> = b.iter().copied().filter(|v| v.is_finite()).collect();
    if a.is_empty() || b.is_empty() {
        return 1.0;
    }
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (mut i, mut j, mut d) = (0, 0, 0.0f64);
    while i < a.len() && j < b.len() {
        let v = a[i].min(b[j]);
        while i < a.len() && a[i] <= v {
            i += 1;
        }
        while j < b.len() && b[j] <= v {
            j += 1;
        }
        d = d.max((i as f64 / a.len() as f64 - j as f64 / b.len() as f64).abs());
    }
    d
}

/// The KS distance two samples of sizes `n`, `m` from one distribution exceed with
/// probability 5 %: c(α) √((n+m)/(n·m)), c(0.05) = 1.358.
pub fn ks_critical(n: usize, m: usize) -> f64 {
    if n == 0 || m == 0 {
        return 0.0;
    }
    1.358 * ((n + m) as f64 / (n as f64 * m as f64)).sqrt()
}

/// One statistic compared.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    pub statistic: String,
    pub real: f64,
    pub sim: f64,
    /// KS distance for distributions, |sim - real| otherwise.
    pub distance: f64,
    /// The largest distance that passes.
    pub limit: f64,
    /// How the limit was set.
    pub tolerance: String,
    pub pass: bool,
}

/// ±20 % of the real value, or `band` when that is wider (shares near 0).
fn relative(name: &str, real: f64, sim: f64, band: f64) -> Verdict {
    let limit = (0.2 * real.abs()).max(band);
    let distance = (sim - real).abs();
    Verdict {
        statistic: name.into(),
        real,
        sim,
        distance,
        limit,
        tolerance: if band > 0.0 {
            format!("±20 % or ±{band}")
        } else {
            "±20 %".into()
        },
        pass: distance <= limit,
    }
}

fn ks(name: &str, real: &Distribution, sim: &Distribution) -> Verdict {
    let distance = ks_distance(&real.sample, &sim.sample);
    let limit = ks_critical(real.n, sim.n);
    Verdict {
        statistic: name.into(),
        real: real.median,
        sim: sim.median,
        distance,
        limit,
        tolerance: "KS, α = 0.05 (real/sim: medians)".into(),
        pass: real.n > 0 && sim.n > 0 && distance <= limit,
    }
}

/// Every statistic of `sim` against `real`, pass or fail.
pub fn compare(real: &PathStats, sim: &PathStats) -> Vec<Verdict> {
    vec![
        relative(
            "share within 50 mm",
            real.share_within_50mm,
            sim.share_within_50mm,
            0.03,
        ),
        relative(
            "share within 100 mm",
            real.share_within_100mm,
            sim.share_within_100mm,
            0.03,
        ),
        ks(
            "wall distance at turns (mm)",
            &real.turn_wall_mm,
            &sim.turn_wall_mm,
        ),
        ks("straight-run length (mm)", &real.run_mm, &sim.run_mm),
        relative(
            "turns per minute",
            real.turns_per_min,
            sim.turns_per_min,
            0.0,
        ),
        relative(
            "pressed against a wall",
            real.pressed_share,
            sim.pressed_share,
            0.05,
        ),
        relative("floor coverage", real.coverage, sim.coverage, 0.03),
        relative(
            "mean speed (mm/s)",
            real.mean_speed_mm_s,
            sim.mean_speed_mm_s,
            0.0,
        ),
    ]
}
