//! Records the git commit the host tools are built from (`ALVS_GIT_COMMIT`), so that `alvs
//! merge` can refuse shards made by different builds of the program. Outside a git checkout
//! (a source tarball) the commit is "unknown" and only the package version tells builds apart.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    (out.status.success() && !text.trim().is_empty()).then(|| text.trim().to_string())
}

fn main() {
    let commit = git(&["rev-parse", "HEAD"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=ALVS_GIT_COMMIT={commit}");
    // a new commit or a checkout moves HEAD or the branch it points to (paths work in
    // worktrees). Only files that exist: cargo takes a missing one (packed-refs, often) for a
    // change, and would rebuild the crate on every `cargo alvs`.
    for path in ["HEAD", "packed-refs"]
        .into_iter()
        .filter_map(|p| git(&["rev-parse", "--git-path", p]))
        .chain(
            git(&["symbolic-ref", "-q", "HEAD"])
                .and_then(|r| git(&["rev-parse", "--git-path", &r])),
        )
        .filter(|p| std::path::Path::new(p).exists())
    {
        println!("cargo:rerun-if-changed={path}");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
