//! The 3D rigid graph compression (3D-RGC) engine (MODEL §5).
//!
//! Compression repeatedly finds a rigid motif and merges its nodes into one
//! body. Work is driven by a worklist of tasks drawn in random order: every
//! rod first (for the rods-only motifs), then every pair of nodes whose
//! relation a merge changed (for the motifs with bodies). A new motif
//! instance always contains the merged node and one of those changed pairs,
//! so nothing is missed and nothing far away is looked at again.
//!
//! The files form layers, each using only those listed before it:
//!
//! - `state`: the multigraph of rods and bodies over the original contacts.
//! - `ruleset`, `motif`, `compression`: the rule sets, the motifs and their
//!   counts, and the outcome of one run.
//! - `demand`: what a pattern node demands of its host and the host's
//!   neighbours (class, contacts, Hall conditions).
//! - `rule`: a loaded rule compiled for matching, with the steps of the
//!   plain search from each start.
//! - `ball`: a rod task's free rods as bit sets, where the index replays the
//!   plain search of a rods-only rule.
//! - `cores`, `sieve`, `trie`, `catalog`: the free rods' k-cores; which
//!   rods-only attempts a rod task admits; their plans as one trie; and a
//!   rule set's tables (with the containments between its rules), built
//!   once and shared.
//! - `index`: host nodes' neighbours and profiles, checked against the
//!   demands so the matcher skips attempts that cannot match.
//! - `induced`: exact verdicts of the patterns matched parts induce.
//! - `assignment`: pattern contacts assigned to host contacts, with no
//!   collinearity the pattern did not assume.
//! - `matcher`: loaded rules matched in the compression state.
//! - `sound`: the verified base rules `sound` checks 3D3A, 3D3B and 3D4
//!   against.
//! - `base`: the base motifs, each found from an anchor.
//! - `certify`: `sound` bodies checked against truth.
//! - `run`: the [`Engine`], its worklist, and seeded runs.
//! - `pattern`: whether the engine compresses a pattern to one node in
//!   some (or every) motif order.
//! - `shapes`: the base motifs derived as verified rules (by running the
//!   engine).
//! - `examples`: every base motif's example and excluded variants.

mod assignment;
mod ball;
mod base;
mod catalog;
pub mod certify;
mod compression;
mod cores;
mod demand;
pub mod examples;
mod index;
mod induced;
mod matcher;
mod motif;
mod pattern;
mod rule;
mod ruleset;
mod run;
pub mod shapes;
mod sieve;
mod sound;
mod state;
mod trie;

pub use catalog::prepare;
pub use compression::Compression;
pub use motif::{Motif, MotifCounts};
pub use rule::CompiledRule;
pub use ruleset::RuleSet;
pub use run::{
    Engine, MAX_RUNS, Matching, Work, check_runs_memory, compress, compress_from, compress_runs,
    run_seed, runs_memory,
};
