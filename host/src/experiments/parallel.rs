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
    if jobs == 1 {
        // on this thread: a pool's `install` called from another pool's worker (the ablation
        // runs whole experiments as its trials) waits by stealing that pool's next trial onto
        // the same stack, and enough of them overflowed it
        return Ok(mine.into_iter().map(|k| (k, f(k))).collect());
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    thread_local! {
        /// Trials running on this thread now, and the most at once.
        static DEPTH: Cell<(usize, usize)> = const { Cell::new((0, 0)) };
    }

    /// A trial that runs a one-thread slice of its own, as the ablation's trials run whole
    /// experiments: its inner work stays on its thread, and no other outer trial is stolen
    /// onto the same stack while it waits (which nested trials until the stack overflowed).
    #[test]
    fn a_one_thread_slice_inside_a_trial_nests_nothing() {
        let outer = slice(64, 2, None, |k| {
            DEPTH.with(|d| {
                let (now, most) = d.get();
                d.set((now + 1, most.max(now + 1)));
            });
            let inner = slice(3, 1, None, |i| {
                std::thread::sleep(std::time::Duration::from_millis(1));
                k + i
            })
            .unwrap();
            let most = DEPTH.with(|d| {
                let (now, most) = d.get();
                d.set((now - 1, most));
                most
            });
            (inner.iter().map(|&(_, v)| v).sum::<usize>(), most)
        })
        .unwrap();
        let sums: Vec<usize> = outer.iter().map(|(_, (s, _))| *s).collect();
        assert_eq!(sums, (0..64).map(|k| 3 * k + 3).collect::<Vec<_>>());
        assert!(
            outer.iter().all(|(_, (_, most))| *most == 1),
            "trials nested"
        );
    }
}
