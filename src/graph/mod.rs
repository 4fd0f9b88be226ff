//! The contact graph: rods as nodes, contacts as edges, in compressed
//! adjacency form shared by the whole crate ([`adjacency`]), with its
//! statistics ([`stats`]) and its file formats ([`io`], [`graphml`]).

pub mod adjacency;
pub mod graphml;
pub mod io;
mod stats;

pub use adjacency::ContactGraph;
pub use stats::{ContactStats, stats};
