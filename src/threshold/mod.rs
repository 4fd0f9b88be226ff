//! Percolation thresholds (MODEL §8, §9): Monte Carlo rod sequences and
//! their critical numbers of rods, checkpointed studies, finite-size scaling
//! to `L -> inf`, and variants of the engine compared on shared sequences.

pub mod fss;
pub mod report;
pub mod sequence;
pub mod study;
pub mod variants;
