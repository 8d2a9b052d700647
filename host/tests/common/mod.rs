//! What the CLI tests share: the `alvs` binary, a scratch folder, a run that must succeed and
//! the JSON file it wrote.

// each test crate uses part of this module
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `alvs` binary of this build.
pub fn alvs() -> Command {
    Command::new(env!("CARGO_BIN_EXE_alvs"))
}

/// A fresh, empty scratch folder for the test `name`.
pub fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("alvs-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `cmd`, which must succeed (its stderr is the failure message), and returns its output.
pub fn succeed(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Runs `cmd`, which must fail with one line on stderr containing `expect` (no panic) and
/// nothing on stdout: how every subcommand refuses bad input. Returns that line.
pub fn fails_in_one_line(cmd: &mut Command, expect: &str) -> String {
    let out = cmd.output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "{cmd:?} succeeded");
    assert!(err.contains(expect), "{cmd:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{cmd:?}: {err}");
    assert!(!err.contains("panicked"), "{cmd:?}: {err}");
    assert!(out.stdout.is_empty(), "{cmd:?}");
    err
}

/// The JSON document in `path`.
pub fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}
