//! The 3D rigid graph compression (3D-RGC) engine (MODEL §5).
//!
//! Compression repeatedly finds a rigid motif and merges its nodes into one
//! body. Work is driven by a worklist of tasks drawn in random order: every
//! rod first (for the rods-only motifs), then every pair of nodes whose
//! relation a merge changed (for the motifs with bodies). A new motif
//! instance always contains the merged node and one of those changed pairs,
//! so nothing is missed and nothing far away is looked at again.

mod assignment;
mod ball;
mod base;
pub mod certify;
mod compression;
mod demand;
pub mod examples;
mod index;
mod induced;
mod matcher;
mod motif;
mod rule;
mod ruleset;
mod run;
pub mod shapes;
mod sound;
mod state;

pub use compression::Compression;
pub use motif::{Motif, MotifCounts};
pub use rule::CompiledRule;
pub use ruleset::RuleSet;
pub use run::{Engine, Matching, compress, compress_from, compress_runs, run_seed};
