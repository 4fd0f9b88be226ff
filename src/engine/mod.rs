//! The 3D rigid graph compression (3D-RGC) engine (DESIGN §5).

use serde::{Deserialize, Serialize};

use crate::contacts::ContactGraph;

/// Which motif conditions the engine applies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Rules {
    /// The published conditions, except that two planar bodies are never
    /// joined by 3D2A (their shared contacts lie on one line: a hinge).
    #[default]
    Sound,
    /// The published conditions verbatim.
    Paper,
}

/// Geometric class of a body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyClass {
    /// All rods in one plane: a 3-clique community, grown by rods touching it twice.
    Planar,
    /// Anything else.
    Spatial,
}

/// A rigid body found by compression: two or more rods.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Body {
    /// Member rods, sorted.
    pub rods: Vec<u32>,
    pub class: BodyClass,
}

/// The outcome of one compression run.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Compression {
    /// Bodies, largest first (ties by smallest rod).
    pub bodies: Vec<Body>,
    /// Nodes left: bodies plus rods in no body.
    pub components: usize,
}

/// Compresses `graph` once with a random motif order drawn from `seed`.
pub fn compress(graph: &ContactGraph, rules: Rules, seed: u64) -> Compression {
    let _ = (graph, rules, seed);
    todo!()
}
