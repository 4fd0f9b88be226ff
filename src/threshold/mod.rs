//! Percolation thresholds (MODEL §8, §9): Monte Carlo rod sequences and
//! their critical numbers of rods, checkpointed studies, finite-size scaling
//! to `L -> inf`, variants of the engine compared on shared sequences and
//! against the exact truth, and thresholds across aspect ratios.

pub mod aspect;
pub mod bias;
pub mod experiment;
pub mod fss;
pub mod logistic;
pub mod paired;
pub mod planes;
pub mod report;
pub mod sequence;
pub mod study;
pub mod transition;
pub mod twins;
pub mod variants;
