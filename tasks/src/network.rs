//! One perception step of the aLPLC2 network (being written).

/// Attention fields the network can hold at once. With Table I's `R_AF` = 36 on a 99x72
/// retina at most 3 x 2 field centres can lie outside each other's squares, so the
/// capacity is never the limit with the paper's parameters.
pub const MAX_AFS: usize = 6;
