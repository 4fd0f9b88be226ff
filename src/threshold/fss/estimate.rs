//! A point estimate and its bootstrap percentile interval, the form every
//! result of the analysis takes.

use serde::{Deserialize, Serialize};

/// A point estimate with its bootstrap percentile interval (absent without
/// bootstrap or when no resample succeeded).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    pub value: f64,
    pub lo: Option<f64>,
    pub hi: Option<f64>,
}

impl Estimate {
    pub(super) fn with(value: f64, interval: Option<(f64, f64)>) -> Self {
        Estimate {
            value,
            lo: interval.map(|i| i.0),
            hi: interval.map(|i| i.1),
        }
    }
}
