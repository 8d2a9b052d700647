//! The paper's model: the aLPLC2 network and the escape behaviour it drives, one module per
//! neural stage. Equation numbers refer to the paper (see `docs/model.md`):
//!
//! | stage | module | paper |
//! |---|---|---|
//! | Table I parameters and documented choices | [`params`] | Table I |
//! | retina, ON/OFF, 3x3 mean | [`retina`] | Eqs. (1)–(2) |
//! | multi-attention fields | [`attention`] | Eqs. (3)–(5), (10) |
//! | T4/T5 correlators, local motion | [`hrc`] | Eqs. (6)–(7) |
//! | quadrants and LPLC2 gate | [`lplc2`] | Eqs. (8)–(9) |
//! | one perception step | [`network`] | Sec. II-A |
//! | strength, threat centroid, escape angles | [`visuomotor`] | Eqs. (11)–(15) |
//! | escape FSM (and the swarm variant) | [`fsm`] | Sec. II-B, IV-D |
//! | Cortex-M4 DSP instructions of the pixel loops, with their plain meaning | [`dsp`] | — |
//!
//! The closed-loop mechanisms the project adds to the paper (the default model's, each a
//! parameter that is off in `--model paper`) are apart, in [`closed_loop`].

/// Attention fields the network can hold at once. With Table I's `R_AF` = 36 on a 99x72
/// retina at most 3 x 2 field centres can lie outside each other's squares, so the
/// capacity is never the limit with the paper's parameters. It sizes the stages' field arrays
/// ([`attention`], [`lplc2`], [`params`]) and the network that composes them ([`network`]),
/// so it lives here, above all of them.
pub const MAX_AFS: usize = 6;

pub mod attention;
pub mod closed_loop;
pub mod dsp;
pub mod fsm;
pub mod hrc;
pub mod lplc2;
pub mod network;
pub mod param_table;
pub mod params;
pub mod retina;
pub mod visuomotor;
