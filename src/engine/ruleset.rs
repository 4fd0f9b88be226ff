//! The rule sets: which motif conditions the engine applies.

use serde::{Deserialize, Serialize};

/// Which motif conditions the engine applies (MODEL §5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum RuleSet {
    /// The published conditions minus what exact rank refutes: two planar
    /// bodies are never joined by 3D2A (their shared contacts lie on one
    /// line: a hinge), also when one of them is a plane kept inside a
    /// spatial body; 3D4 is refused on a planar body whose rod path closes
    /// a triangle (the prism's hinge); and every 3D3A, 3D3B and 3D4 instance
    /// must have an induced pattern that is rigid by exact rank on every
    /// realization component.
    #[default]
    Sound,
    /// The published conditions verbatim.
    Paper,
    /// `sound`, then every body checked against the exact truth of the
    /// whole graph and split where truth refutes it (MODEL §10): never a
    /// false body.
    Certified,
}

impl std::fmt::Display for RuleSet {
    /// The name on the command line and in files.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            RuleSet::Sound => "sound",
            RuleSet::Paper => "paper",
            RuleSet::Certified => "certified",
        })
    }
}
