//! Properties of the aLPLC2 network that hold for every frame sequence and every parameter set
//! `Params::validate` accepts: no panic, outputs within their documented ranges and consistent
//! with each other (Eqs. 9, 11–15), invalid parameters refused with an error, determinism.
//!
//! Frames are generated from small descriptions (uniform, noise, checkerboards, squares,
//! gradients) so that cases stay cheap and shrink to readable counterexamples. Failures are
//! not persisted to disk (the seed is printed instead).
//!
//! One file per subject: `frames` (the frame strategies), `params` (the valid-parameter
//! strategies), `invariants` (`check`, every documented bound of one output), `network` (the
//! properties of the network run on frames), `refusal` (invalid parameters refused, and
//! `Params::set` on arbitrary text).

use alvs_tasks::model::param_table::off0;
use alvs_tasks::{Network, Params, Perception, HEIGHT, MAX_AFS, PIXELS, WIDTH};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRng, TestRunner};

mod frames;
mod invariants;
mod network;
mod params;
mod refusal;

use frames::*;
use invariants::*;
use params::*;

type Frame = [u8; PIXELS];

fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }
}
