//! Sweeps past one machine (`--shard I/N`, `alvs merge`): the shards of a split run pool into
//! exactly the unsharded run's JSON and pictures, whatever the number of shards and threads;
//! a merge refuses what is not the shards of one run with one line.

use std::path::{Path, PathBuf};

use alvs_host::experiments::arena::ArenaConfig;
use alvs_host::experiments::stimuli::StimuliConfig;
use alvs_host::experiments::swarm::SwarmConfig;
use alvs_host::experiments::sweep::{self, Shard, Sweep};
use alvs_host::experiments::two_threats::TwoThreatConfig;
use alvs_host::experiments::Report;
use alvs_sim::Kind;
use serde_json::Value;

mod common;
use common::{alvs, read_json, succeed, tmp};

/// `v` without the wall-clock times (the only numbers allowed to vary between runs).
fn numbers(mut v: Value) -> Value {
    fn strip(v: &mut Value) {
        match v {
            Value::Object(m) => {
                m.remove("wall_clock_s");
                m.values_mut().for_each(strip);
            }
            Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    strip(&mut v);
    v
}

/// Two controllers on two backgrounds, 0.2 simulated minutes: four trials.
fn small_arena() -> ArenaConfig {
    ArenaConfig {
        robots: 3,
        minutes: 0.2,
        backgrounds: vec!["clutter:1".into(), "stripes:40".into()],
        controllers: vec![Kind::Alvs, Kind::Lgmd2],
        seed: 5,
        ..ArenaConfig::default()
    }
}

/// Runs every shard of `n` (on `jobs` threads each), writes the files into `dir` and reads
/// them back.
fn shard_files<S: Sweep>(config: &S, n: usize, jobs: usize, dir: &Path) -> Vec<sweep::ShardFile> {
    (1..=n)
        .map(|index| {
            let shard = Shard { index, count: n };
            let v = sweep::run_shard(config, &[], shard, jobs, &|_| {}).unwrap();
            let path = dir.join(format!("{}-{index}.json", S::NAME));
            std::fs::write(&path, serde_json::to_string(&v).unwrap()).unwrap();
            sweep::read(&path).unwrap()
        })
        .collect()
}

#[test]
fn shard_slices_partition_the_trials_round_robin() {
    for n in 1..=7 {
        for k in 0..30 {
            let owners: Vec<usize> = (1..=n)
                .filter(|&index| Shard { index, count: n }.owns(k))
                .collect();
            assert_eq!(owners, vec![k % n + 1], "trial {k} of {n} shards");
        }
    }
    assert_eq!("2/8".parse(), Ok(Shard { index: 2, count: 8 }));
    for bad in ["0/8", "9/8", "8", "a/b", "1/0", "-1/2", ""] {
        assert!(bad.parse::<Shard>().is_err(), "{bad}");
    }
}

/// The acceptance test of the item: merging the shards of a split arena run gives the JSON of
/// the unsharded run, also with more shards than trials (empty shards) and any thread count.
#[test]
fn merged_arena_shards_are_the_unsharded_run() {
    let config = small_arena();
    let whole = numbers(sweep::run_all(&config, 2, &|_| {}).unwrap().json());
    let dir = tmp("sweep-arena");
    for (n, jobs) in [(1, 1), (3, 1), (4, 2), (6, 1)] {
        let files = shard_files(&config, n, jobs, &dir);
        let merged = sweep::merge(&config, &files).unwrap();
        assert_eq!(
            numbers(merged.json()),
            whole,
            "{n} shards on {jobs} threads"
        );
        assert_eq!(merged.trials.len(), 4);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn merged_two_threats_and_swarm_shards_are_the_unsharded_run() {
    let dir = tmp("sweep-two-swarm");
    let two = TwoThreatConfig {
        runs: 3,
        ..TwoThreatConfig::default()
    };
    let whole = numbers(sweep::run_all(&two, 1, &|_| {}).unwrap().json());
    let merged = sweep::merge(&two, &shard_files(&two, 4, 2, &dir)).unwrap();
    assert_eq!(numbers(merged.json()), whole);
    let swarm = SwarmConfig {
        minutes: 0.1,
        ..SwarmConfig::default()
    };
    let whole = numbers(sweep::run_all(&swarm, 2, &|_| {}).unwrap().json());
    let merged = sweep::merge(&swarm, &shard_files(&swarm, 2, 1, &dir)).unwrap();
    assert_eq!(numbers(merged.json()), whole);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A merged stimuli run has its JSON, and draws the tracks only (the layer pictures replay
/// camera frames that stay with the shards).
#[test]
fn merged_stimuli_shards_are_the_unsharded_json_and_its_tracks() {
    let dir = tmp("sweep-stimuli");
    let config = StimuliConfig::default();
    let whole = sweep::run_all(&config, 2, &|_| {}).unwrap();
    let merged = sweep::merge(&config, &shard_files(&config, 3, 1, &dir)).unwrap();
    assert_eq!(numbers(merged.json()), numbers(whole.json()));
    merged.write_pictures(&dir.join("png")).unwrap();
    let mut drawn: Vec<String> = std::fs::read_dir(dir.join("png"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    drawn.sort();
    let tracks =
        ["approach", "double", "recede", "translate", "triple"].map(|s| format!("{s}_tracks.png"));
    assert_eq!(drawn, tracks);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_slice_does_not_depend_on_the_threads() {
    let config = small_arena();
    let shard = Some(Shard { index: 1, count: 2 });
    let trials = |jobs| {
        let t = config.run_slice(jobs, shard, &|_| {}).unwrap();
        numbers(serde_json::to_value(t).unwrap())
    };
    let one = trials(1);
    assert_eq!(one.as_array().map(Vec::len), Some(2));
    assert_eq!(one[0][0], 0);
    assert_eq!(one[1][0], 2);
    assert_eq!(trials(3), one);
}

/// `alvs <experiment> ARGS --shard I/N --json FILE` for I = 1..N in `dir`; returns the files.
fn cli_shards(dir: &Path, args: &[&str], n: usize) -> Vec<PathBuf> {
    (1..=n)
        .map(|i| {
            let path = dir.join(format!("shard-{i}.json"));
            let out = succeed(
                alvs()
                    .args(args)
                    .args(["--shard", &format!("{i}/{n}"), "--jobs", "1", "--json"])
                    .arg(&path),
            );
            let stdout = String::from_utf8_lossy(&out.stdout);
            assert!(stdout.contains(&format!("shard {i}/{n}")), "{stdout}");
            path
        })
        .collect()
}

/// The command line end to end, on the evasion experiment: the merge prints the same table
/// (but for the wall-clock), writes the same JSON and draws the same picture, byte for byte.
#[test]
fn cli_merged_evasion_shards_are_the_unsharded_run() {
    let dir = tmp("sweep-cli-evasion");
    let args = ["evasion", "--controller", "alvs", "--seed", "3"];
    let whole = succeed(
        alvs()
            .args(args)
            .args(["--jobs", "2", "--json"])
            .arg(dir.join("whole.json"))
            .arg("--png")
            .arg(dir.join("whole")),
    );
    let files = cli_shards(&dir, &args, 4);
    let merged = succeed(
        alvs()
            .arg("merge")
            .args(files.iter().rev())
            .arg("--json")
            .arg(dir.join("merged.json"))
            .arg("--png")
            .arg(dir.join("merged")),
    );
    assert_eq!(
        numbers(read_json(&dir.join("merged.json"))),
        numbers(read_json(&dir.join("whole.json")))
    );
    assert_eq!(
        std::fs::read(dir.join("merged/evasion.png")).unwrap(),
        std::fs::read(dir.join("whole/evasion.png")).unwrap()
    );
    // the tables differ only in the first line's wall-clock and in where the outputs went
    let body = |out: &std::process::Output| -> Vec<String> {
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .skip(1)
            .filter(|l| !l.contains(" in "))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(body(&merged), body(&whole));
    assert!(body(&whole).len() > 9);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `alvs merge FILES` fails with one line containing `expect`.
fn merge_fails(files: &[&Path], expect: &str) {
    let out = alvs().arg("merge").args(files).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{files:?} merged");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(expect), "{files:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// `path`'s JSON, changed by `edit`, written to `to`.
fn edited(path: &Path, to: &Path, edit: impl FnOnce(&mut Value)) -> PathBuf {
    let mut v = read_json(path);
    edit(&mut v);
    std::fs::write(to, serde_json::to_string(&v).unwrap()).unwrap();
    to.to_path_buf()
}

#[test]
fn merge_refuses_what_is_not_one_runs_shards() {
    let dir = tmp("sweep-cli-errors");
    let args = ["swarm", "--minutes", "0.05"];
    let files = cli_shards(&dir, &args, 2);
    let (a, b) = (files[0].as_path(), files[1].as_path());
    merge_fails(&[a], "missing shard 2 of 2");
    merge_fails(&[a, a, b], "shard 1/2 is given twice");
    let other = dir.join("other");
    std::fs::create_dir_all(&other).unwrap();
    let seed2 = cli_shards(&other, &["swarm", "--minutes", "0.05", "--seed", "2"], 2);
    merge_fails(&[a, &seed2[1]], "different configurations");
    let split3 = dir.join("split3");
    std::fs::create_dir_all(&split3).unwrap();
    let three = cli_shards(&split3, &["swarm", "--minutes", "0.05"], 3);
    merge_fails(&[a, &three[1]], "different splits");
    let old = edited(b, &dir.join("old.json"), |v| {
        v["alvs_shard"]["version"] = "0.0.1+0000".into()
    });
    merge_fails(&[a, &old], "same build");
    let old_a = edited(a, &dir.join("old-a.json"), |v| {
        v["alvs_shard"]["version"] = "0.0.1+0000".into()
    });
    merge_fails(&[&old_a, &old], "merge with the build that ran them");
    let moved = edited(b, &dir.join("moved.json"), |v| {
        v["trials"][0]["index"] = 0.into()
    });
    merge_fails(&[a, &moved], "not one of shard 2/2's");
    let broken = edited(b, &dir.join("broken.json"), |v| {
        v["trials"][0]["result"]["controller"] = "nobody".into()
    });
    merge_fails(&[a, &broken], "unreadable");
    let text = dir.join("text.json");
    std::fs::write(&text, "{\"alvs\": 1").unwrap();
    merge_fails(&[a, &text], "not a shard file");
    merge_fails(&[a, &dir.join("absent.json")], "cannot read");
    // the run's own errors
    for (extra, expect) in [
        (&["--shard", "1/2"][..], "needs --json"),
        (&["--shard", "3/2", "--json", "x.json"][..], "1 <= I <= N"),
    ] {
        let out = alvs().args(args).args(extra).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(expect), "{err}");
    }
    let out = alvs()
        .args(["evasion", "--shard", "1/2", "--json"])
        .arg(dir.join("t.json"))
        .arg("--trace")
        .arg(dir.join("t.csv"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("--trace cannot be sharded"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cli_helps_with_shard_and_merge() {
    for cmd in ["arena", "evasion", "two-threats", "swarm", "stimuli"] {
        let out = succeed(alvs().args([cmd, "--help"]));
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(help.contains("--shard <I/N>"), "{cmd}: {help}");
    }
    let out = succeed(alvs().args(["merge", "--help"]));
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(help.contains("docs/sweeps.md"), "{help}");
}
