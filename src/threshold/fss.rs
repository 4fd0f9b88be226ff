//! Finite-size scaling (DESIGN §8, the paper's numerics protocol): from the
//! observations of each box size to the threshold, `nu` and their intervals.

use serde::{Deserialize, Serialize};

/// Contact numbers measured on one system of a realization.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactPoint {
    pub density: f64,
    pub c0: f64,
    pub c1: f64,
    pub c2: f64,
}

/// What one realization (one random rod sequence in one box) contributes;
/// the unit of the bootstrap's case resampling.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Observation {
    /// The density at which the sequence first spans (nested protocol).
    pub critical: Option<f64>,
    /// Whether it spans at each density of the fixed grid (fixed protocol).
    pub fixed: Vec<(f64, bool)>,
    /// Contact numbers measured along the way.
    pub contacts: Vec<ContactPoint>,
}

/// The observations of one box size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoxData {
    pub box_len: f64,
    pub observations: Vec<Observation>,
}
