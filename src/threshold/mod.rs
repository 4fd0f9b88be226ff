//! Percolation thresholds (MODEL §8, §9): Monte Carlo rod sequences and
//! their critical numbers of rods, checkpointed studies, finite-size scaling
//! to `L -> inf`, variants of the engine compared on shared sequences and
//! against the exact truth, thresholds across aspect ratios, and studies
//! run from a row or signac workspace.

pub mod aspect;
pub mod bias;
pub mod experiment;
pub mod fss;
pub mod horizon;
pub mod journal;
pub mod locality;
pub mod logistic;
pub mod paired;
pub mod planes;
pub mod report;
pub mod sequence;
pub mod stiffening;
pub mod study;
pub mod tradeoff;
pub mod transition;
pub mod twins;
pub mod variants;
pub mod workspace;
