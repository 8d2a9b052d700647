//! `alvs budget` and `alvs virtual`: pass-throughs to the binaries of alvs-cycles (and the
//! `cargo run` that `alvs log` uses for the cycle model's prediction).

use std::path::Path;

use anyhow::{Context, Result};

/// Runs a binary of the crate alvs-cycles (`alvs-budget`, `alvs-virtual`) through cargo, so that
/// the host tools themselves never need the emulator's C build. It runs in the caller's folder
/// (its relative paths are the caller's); when it fails it has said why on stderr, in one line,
/// and `alvs` exits with its status without a second message.
pub fn run_cycles_bin(bin: &str, args: &[String]) -> Result<()> {
    let status = cycles_bin(bin, args).status().context("running cargo")?;
    if !status.success() {
        return Err(Exit(status.code().unwrap_or(1).clamp(1, 255) as u8).into());
    }
    Ok(())
}

/// `cargo run` of a binary of alvs-cycles, from the workspace's manifest, in the current folder.
pub fn cycles_bin(bin: &str, args: &[String]) -> std::process::Command {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap_or(Path::new(".."))
        .join("Cargo.toml");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut c = std::process::Command::new(cargo);
    c.args([
        "run",
        "--quiet",
        "--target",
        "host-tuple",
        "--manifest-path",
    ])
    .arg(manifest)
    .args(["-p", "alvs-cycles", "--bin", bin, "--"])
    .args(args);
    c
}

/// The exit status of a failed child that reported its own error: `alvs` exits with it and
/// prints nothing more.
#[derive(Debug)]
pub struct Exit(pub u8);

impl std::fmt::Display for Exit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "exit status {}", self.0)
    }
}

impl std::error::Error for Exit {}
