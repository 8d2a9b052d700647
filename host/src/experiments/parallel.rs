//! Independent trials on a few worker threads (rayon). Each trial is a pure function of its
//! index, so results never depend on the number of threads or on scheduling, only the
//! wall-clock does.

use anyhow::{Context, Result};
use rayon::prelude::*;

use super::sweep::Shard;

/// The number of worker threads when none is asked for: the available parallelism.
pub fn default_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The trials of `shard` (all `n` without one) as `(index, f(index))`, in index order, on up to
/// `jobs` threads (0 = [`default_jobs`]). A pool of its own rather than rayon's global one, so
/// `--jobs` is exactly the threads a run takes.
pub fn slice<R: Send>(
    n: usize,
    jobs: usize,
    shard: Option<Shard>,
    f: impl Fn(usize) -> R + Sync,
) -> Result<Vec<(usize, R)>> {
    let mine: Vec<usize> = (0..n)
        .filter(|&k| shard.is_none_or(|s| s.owns(k)))
        .collect();
    if mine.is_empty() {
        return Ok(Vec::new());
    }
    let jobs = if jobs == 0 { default_jobs() } else { jobs }.clamp(1, mine.len());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .thread_name(|i| format!("alvs-trial-{i}"))
        .build()
        .context("cannot start the worker threads")?;
    // one trial per task (with_max_len(1)), so long and short trials balance; collect keeps
    // the index order whatever thread finished first
    Ok(pool.install(|| {
        mine.par_iter()
            .with_max_len(1)
            .map(|&k| (k, f(k)))
            .collect()
    }))
}
