//! What the tests of the firmware ELF share: the workspace root and the release build.

// each test crate uses part of this module
#![allow(dead_code)]

use std::path::Path;

use alvs_cycles::budget::{build_firmware, BuildError};

pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("root")
}

/// The release firmware's ELF, built if needed; `None` (the test skips, saying so) without the
/// thumbv7em target.
pub fn firmware() -> Option<Vec<u8>> {
    match build_firmware(root()) {
        Ok(path) => Some(std::fs::read(path).expect("firmware ELF")),
        Err(BuildError::TargetMissing) => {
            println!("SKIPPED: {}", BuildError::TargetMissing);
            None
        }
        Err(e) => panic!("{e}"),
    }
}
