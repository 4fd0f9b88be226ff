//! Percolation thresholds (DESIGN §8, §9): Monte Carlo rod sequences, their
//! critical densities, and finite-size scaling to `L -> inf`.

pub mod compare;
pub mod fss;
pub mod montecarlo;
pub mod report;
pub mod study;
