//! Sweeps past one machine: `--shard I/N` runs one slice of an experiment's trials and writes
//! them as a shard file; `alvs merge` pools the shard files into the report an unsharded run
//! gives (docs/sweeps.md).
//!
//! **Slicing.** Trial `k` (0-based, in the experiment's plan order, controller-major) belongs
//! to shard `(k mod N) + 1`: consecutive trials go to different shards, so the long and the
//! short ones (a controller, a background that runs slower) spread over all shards.
//!
//! **A shard file** carries what a merge needs and what it must check: the experiment, the
//! program's version (package version and git commit), the command line that made it (to
//! rebuild the configuration), the configuration's fingerprint (its `Debug` text: every field,
//! floats round-trip exactly), I and N, the number of trials in the whole plan, and this
//! slice's trials with their indices. Trials are pure functions of the configuration and their
//! index, so the pooled trials are exactly those of an unsharded run.

use std::path::Path;

use anyhow::{bail, ensure, Context, Result};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::Report;

/// What the program is: shards of different builds may not be pooled (a trial's numbers may
/// differ between them).
pub const VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "+", env!("ALVS_GIT_COMMIT"));

/// Top-level key of a shard file (tells it from an experiment's ordinary `--json`).
const KEY: &str = "alvs_shard";

/// One slice of `N` (`--shard I/N`, `I` from 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// 1..=count.
    pub index: usize,
    /// Shards in the sweep.
    pub count: usize,
}

impl Shard {
    /// Whether trial `k` (from 0) is this shard's: `k mod N = I − 1`.
    pub fn owns(&self, k: usize) -> bool {
        k % self.count == self.index - 1
    }
}

impl std::str::FromStr for Shard {
    type Err = String;

    /// `I/N` with 1 ≤ I ≤ N.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let bad = || format!("{s:?} is not I/N with 1 <= I <= N (e.g. 2/8)");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse::<usize>().map_err(|_| bad())?,
            n.trim().parse::<usize>().map_err(|_| bad())?,
        );
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// An experiment whose trials are independent: it runs any slice of them and builds its report
/// from all of them.
pub trait Sweep: std::fmt::Debug {
    /// The subcommand (`arena`, `evasion`, ...).
    const NAME: &'static str;
    /// One trial's outcome, as the shard file carries it.
    type Trial: Serialize + DeserializeOwned + Send;
    /// The report of a whole run.
    type Report: Report;

    /// Trials in the whole plan.
    fn trial_count(&self) -> usize;

    /// Runs the trials of `shard` (all without one) on `jobs` threads (0 = all cores), in
    /// index order; `progress` is told of simulated camera frames.
    fn run_slice(
        &self,
        jobs: usize,
        shard: Option<Shard>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<(usize, Self::Trial)>>;

    /// The report of all trials, in index order.
    fn report(&self, trials: Vec<Self::Trial>, wall_clock_s: f64, jobs: usize) -> Self::Report;

    /// What tells two configurations apart: every field.
    fn fingerprint(&self) -> String {
        format!("{self:?}")
    }
}

/// Runs the whole plan of `config` and reports it.
pub fn run_all<S: Sweep>(
    config: &S,
    jobs: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<S::Report> {
    let t0 = std::time::Instant::now();
    let trials = config.run_slice(jobs, None, progress)?;
    let n = trials.len().max(1);
    let jobs = if jobs == 0 {
        super::parallel::default_jobs()
    } else {
        jobs
    };
    Ok(config.report(
        trials.into_iter().map(|(_, t)| t).collect(),
        t0.elapsed().as_secs_f64(),
        jobs.min(n),
    ))
}

/// The head of a shard file.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Header {
    /// The subcommand that made it.
    pub experiment: String,
    /// [`VERSION`] of the program that made it.
    pub version: String,
    /// Its arguments after the subcommand, as given (the merge rebuilds the configuration).
    pub args: Vec<String>,
    /// [`Sweep::fingerprint`] of its configuration.
    pub config: String,
    /// Which slice.
    pub shard: Shard,
    /// Trials in the whole plan.
    pub trials: usize,
    /// Wall-clock seconds of this shard.
    pub wall_clock_s: f64,
    /// Worker threads it used.
    pub jobs: usize,
}

/// One trial in a shard file.
#[derive(Serialize, Deserialize)]
struct Entry<T> {
    index: usize,
    result: T,
}

/// Runs the slice `shard` of `config` and returns its shard file's JSON.
pub fn run_shard<S: Sweep>(
    config: &S,
    args: &[String],
    shard: Shard,
    jobs: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<serde_json::Value> {
    let t0 = std::time::Instant::now();
    let trials = config.run_slice(jobs, Some(shard), progress)?;
    let jobs = if jobs == 0 {
        super::parallel::default_jobs()
    } else {
        jobs
    };
    let header = Header {
        experiment: S::NAME.into(),
        version: VERSION.into(),
        args: args.to_vec(),
        config: config.fingerprint(),
        shard,
        trials: config.trial_count(),
        wall_clock_s: t0.elapsed().as_secs_f64(),
        jobs: jobs.clamp(1, trials.len().max(1)),
    };
    let entries: Vec<Entry<S::Trial>> = trials
        .into_iter()
        .map(|(index, result)| Entry { index, result })
        .collect();
    Ok(serde_json::json!({ KEY: header, "trials": entries }))
}

/// A shard file read back: its head and its trials still as JSON (their type depends on the
/// experiment the head names).
pub struct ShardFile {
    /// Where it was read from (for messages).
    pub path: String,
    /// Its head.
    pub header: Header,
    trials: Vec<Entry<serde_json::Value>>,
}

/// Reads a shard file; every failure is one line naming the file.
pub fn read(path: &Path) -> Result<ShardFile> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {name}"))?;
    #[derive(Deserialize)]
    struct File {
        alvs_shard: Header,
        trials: Vec<Entry<serde_json::Value>>,
    }
    let file: File = serde_json::from_str(&text).map_err(|e| {
        anyhow::anyhow!("{name}: not a shard file of `alvs <experiment> --shard I/N` ({e})")
    })?;
    Ok(ShardFile {
        path: name,
        header: file.alvs_shard,
        trials: file.trials,
    })
}

/// Checks that `files` are the N shards of one run made by this build, each once; returns the
/// head they share. Each failure is one line.
pub fn check(files: &[ShardFile]) -> Result<&Header> {
    let Some(first) = files.first() else {
        bail!("no shard file to merge");
    };
    let h = &first.header;
    for f in files {
        let g = &f.header;
        let differ = |what: &str| {
            anyhow::anyhow!(
                "{} and {} are shards of different {what}; merge the shards of one run",
                first.path,
                f.path
            )
        };
        if g.experiment != h.experiment {
            return Err(differ("experiments"));
        }
        if g.version != h.version {
            bail!(
                "{} was made by alvs {} but {} by alvs {}; run every shard with the same build",
                first.path,
                h.version,
                f.path,
                g.version
            );
        }
        if g.config != h.config || g.trials != h.trials {
            return Err(differ("configurations"));
        }
        if g.shard.count != h.shard.count {
            return Err(differ("splits (N differs)"));
        }
    }
    // the report is this build's code: pooled by another build, it might not be what the
    // shards' build would have printed
    ensure!(
        h.version == VERSION,
        "the shards were made by alvs {} but this is alvs {VERSION}; merge with the build that \
         ran them",
        h.version
    );
    let n = h.shard.count;
    let mut seen: Vec<Option<&str>> = vec![None; n];
    for f in files {
        let i = f.header.shard.index;
        ensure!(
            (1..=n).contains(&i),
            "{}: shard {i} of {n} does not exist",
            f.path
        );
        if let Some(other) = seen[i - 1] {
            bail!("shard {i}/{n} is given twice: {other} and {}", f.path);
        }
        seen[i - 1] = Some(&f.path);
    }
    let missing: Vec<String> = (1..=n)
        .filter(|i| seen[i - 1].is_none())
        .map(|i| i.to_string())
        .collect();
    ensure!(
        missing.is_empty(),
        "missing shard{} {} of {n} (of `alvs {}`)",
        if missing.len() == 1 { "" } else { "s" },
        missing.join(", "),
        h.experiment
    );
    Ok(h)
}

/// Pools checked shard `files` (see [`check`]) of `config`'s run into its report. Fails (one
/// line) when `config` is not the shards' or a trial is missing, misplaced or unreadable.
pub fn merge<S: Sweep>(config: &S, files: &[ShardFile]) -> Result<S::Report> {
    let h = check(files)?;
    ensure!(
        h.experiment == S::NAME && h.config == config.fingerprint(),
        "the shards' configuration cannot be rebuilt from their command line by this build"
    );
    let n = config.trial_count();
    ensure!(
        h.trials == n,
        "the shards hold a plan of {} trials, not {n}",
        h.trials
    );
    let mut trials: Vec<Option<S::Trial>> = (0..n).map(|_| None).collect();
    for f in files {
        let shard = f.header.shard;
        for e in &f.trials {
            let k = e.index;
            ensure!(
                k < n && shard.owns(k),
                "{}: trial {k} is not one of shard {shard}'s",
                f.path
            );
            ensure!(trials[k].is_none(), "{}: trial {k} is given twice", f.path);
            let t = S::Trial::deserialize(&e.result)
                .map_err(|err| anyhow::anyhow!("{}: trial {k} is unreadable ({err})", f.path))?;
            trials[k] = Some(t);
        }
    }
    let mut all = Vec::with_capacity(n);
    for (k, t) in trials.into_iter().enumerate() {
        let shard = Shard {
            index: k % h.shard.count + 1,
            count: h.shard.count,
        };
        all.push(t.with_context(|| format!("trial {k} is missing from shard {shard}"))?);
    }
    // the shards ran side by side: the sweep took as long as its longest shard, on all their
    // threads
    let wall = files
        .iter()
        .map(|f| f.header.wall_clock_s)
        .fold(0.0, f64::max);
    let jobs = files.iter().map(|f| f.header.jobs).sum();
    Ok(config.report(all, wall, jobs))
}

/// A name kept as `&'static str` in results. The alias is for serde's derive, which would make
/// a field spelled `&'static str` borrow from the input (and its results readable only from
/// `'static` text); [`static_name`] reads one instead.
pub type StaticName = &'static str;

/// Deserialises a name the results keep as `&'static str` (a controller, an FSM state) back to
/// the program's own: shard files hold no other names.
pub fn static_name<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<&'static str, D::Error> {
    use alvs_sim::Kind;
    use alvs_tasks::model::fsm::State;
    let s = String::deserialize(d)?;
    let kinds = [Kind::Alvs, Kind::Swarm, Kind::Lgmd2].map(Kind::name);
    let states = State::ALL.map(State::name);
    kinds
        .into_iter()
        .chain(states)
        .find(|n| *n == s)
        .ok_or_else(|| serde::de::Error::custom(format!("unknown name {s:?}")))
}

/// [`static_name`] for an optional name.
pub fn static_name_opt<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<&'static str>, D::Error> {
    #[derive(Deserialize)]
    struct Name(#[serde(deserialize_with = "static_name")] StaticName);
    Ok(Option::<Name>::deserialize(d)?.map(|n| n.0))
}
