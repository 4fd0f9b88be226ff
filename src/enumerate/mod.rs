//! Enumeration of small graphs (MODEL §7): non-isomorphic connected simple
//! graphs with the audit's filters pushed into generation, canonical forms,
//! and typed multigraph patterns for mixed motifs ([`typed_patterns`]).
//! `small` holds the bitmask graphs, their filters and canonical forms,
//! `connected` the generator.

mod canon;
mod connected;
mod small;
mod typed;

pub use connected::{
    connected_graphs, connected_small_graphs, count_connected, for_each_connected,
    par_fold_connected, par_for_each_connected, write_connected_graph6,
};
pub use small::{GraphFilter, MAX_ORDER, SmallGraph, canonical_graph6, maxwell_rod_edges};
pub use typed::{
    MAX_MULTIPLICITY, MAX_TYPED_NODES, TypedFilter, canonical_pattern, typed_patterns,
};
