//! The contact graph: rods as nodes, contacts as edges, in compressed
//! adjacency form shared by the whole crate ([`adjacency`]), with its
//! statistics (`stats`), its file formats ([`io`], [`graphml`]), and its
//! topology in a periodic box, each contact's image ([`topology`]).

pub mod adjacency;
pub mod graphml;
pub mod io;
mod stats;
pub mod topology;

pub use adjacency::ContactGraph;
pub use stats::{ContactStats, stats};
pub use topology::Topology;
