//! One error type for the library: every message names the problem, so the CLI
//! can print it on one line and exit with code 2.

use std::path::PathBuf;

/// Everything that can go wrong in `rgc`, phrased for the person who caused it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A numeric parameter out of its physical range (non-positive, NaN, too large ...).
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// A graph6 string that does not decode to a graph.
    #[error("malformed graph6 {input:?}: {reason}")]
    Graph6 { input: String, reason: String },
    /// A contact edge list that does not parse.
    #[error("malformed edge list {path}: line {line}: {reason}")]
    EdgeList {
        path: PathBuf,
        line: usize,
        reason: String,
    },
    /// A data file (GraphML, rods) that does not parse: its format, and where.
    #[error("malformed {format} file {path}: line {line}: {reason}")]
    Malformed {
        format: &'static str,
        path: PathBuf,
        line: usize,
        reason: String,
    },
    /// Data a finite-size-scaling analysis cannot use (all spanning, too few
    /// box sizes, a fit that does not converge ...).
    #[error("cannot analyse: {0}")]
    Analysis(String),
    /// Work refused up front because its estimate is over the memory limit.
    #[error("over the memory limit: {0}")]
    Memory(String),
    /// A threshold study directory that does not match the command (another
    /// study's checkpoint, overlapping shards, a corrupt record ...).
    #[error("study {path}: {reason}")]
    Study { path: PathBuf, reason: String },
    /// A file that cannot be read or written.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl Error {
    /// Wraps an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// An analysis that cannot go on with the data it has.
    pub fn analysis(msg: impl Into<String>) -> Self {
        Error::Analysis(msg.into())
    }
}

pub type Result<T> = std::result::Result<T, Error>;

/// A number for a message, as written when that is short, else in
/// scientific notation: a box of 1e300 is not 301 digits.
pub fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 16 {
        plain
    } else {
        format!("{x:.4e}")
    }
}

/// A computed number for a message: four decimals in the usual range,
/// scientific notation outside it.
pub fn four(x: f64) -> String {
    if x == 0.0 || (1e-4..1e6).contains(&x.abs()) {
        format!("{x:.4}")
    } else {
        format!("{x:.4e}")
    }
}

#[cfg(test)]
mod short_tests {
    use super::{four, short};

    #[test]
    fn numbers_in_messages_stay_short() {
        assert_eq!(short(40.0), "40");
        assert_eq!(short(0.02), "0.02");
        assert_eq!(short(1e300), "1.0000e300");
        assert_eq!(four(2.0869565217391304), "2.0870");
        assert_eq!(four(4e300), "4.0000e300");
        assert_eq!(four(0.0), "0.0000");
    }
}
