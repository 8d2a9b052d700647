//! Independent trials on a few worker threads. Each trial is a pure function of its index, so
//! results never depend on the number of threads or on scheduling, only the wall-clock does.

use std::sync::atomic::{AtomicUsize, Ordering};

/// The number of worker threads when none is asked for: the available parallelism.
pub fn default_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// `f(0), f(1), …, f(n − 1)` on up to `jobs` threads (0 = [`default_jobs`]), in index order.
/// Work is handed out one index at a time, so long and short trials balance. A panic in `f` is
/// passed on to the caller.
pub fn map<R: Send>(n: usize, jobs: usize, f: impl Fn(usize) -> R + Sync) -> Vec<R> {
    if n == 0 {
        return Vec::new();
    }
    let jobs = if jobs == 0 { default_jobs() } else { jobs }.clamp(1, n);
    let next = AtomicUsize::new(0);
    let mut done: Vec<(usize, R)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..jobs)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= n {
                            break;
                        }
                        mine.push((i, f(i)));
                    }
                    mine
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| match w.join() {
                Ok(v) => v,
                Err(panic) => std::panic::resume_unwind(panic),
            })
            .collect()
    });
    done.sort_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, r)| r).collect()
}
