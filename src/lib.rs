//! `rgc`: rigidity percolation in random 3-D rod systems.
//!
//! The modules form layers: each one uses only modules declared before it
//! here (a test checks it). `src/ARCHITECTURE.md` draws the diagram and the
//! data flow, and `src/MODEL.md` states the model that the `MODEL §n`
//! references cite.
//!
//! * [`error`] — one error type, every message on one line;
//! * [`usage`] — what the process used and holds (Linux), and the guard of the memory limit;
//! * [`math`] — F_p, matrices, float rank, 3-vectors, statistics;
//! * [`output`] — files written atomically, writable paths checked up front, CSV;
//! * [`stamp`] — what made a results file, and the refusal to replace one made differently;
//! * [`progress`] — how long computations report progress to their caller;
//! * [`rods`] — soft-core spherocylinders in a periodic box;
//! * [`contacts`] — which rods touch (a fine grid of rod covers, robust segment distance);
//! * [`graph`] — the contact graph, its statistics, graph6 and edge lists;
//! * [`body`] — rigid bodies and their planar or spatial class;
//! * [`spanning`] — whether a cluster of rods spans the periodic box;
//! * [`pattern`] — typed contact patterns: rods, planar and spatial bodies;
//! * [`rigidity`] — incidences, realizations and their components, the
//!   rigidity matrix and the exact verdict;
//! * [`truth`] — the exact rigidity of a whole system: forced planes, an
//!   exact realization, sparse exact rank and rigid clusters;
//! * [`moduli`] — the elastic tensor in floats: contact springs, rigid rods,
//!   kept at truth's exact strain rank;
//! * [`enumerate`] — non-isomorphic graphs and typed patterns, canonical forms;
//! * [`rule_file`] — motif rule files, verified by exact rank on load;
//! * [`engine`] — the 3D rigid graph compression (3D-RGC);
//! * [`sample`] — one Monte Carlo system from rods to rigid bodies;
//! * [`vtk`] — rod systems as VTK PolyData, with their bodies, for ParaView;
//! * [`audit`] — which rigid motifs the engine misses; extended rule sets;
//! * [`mine`] — the motifs the engine misses in generated systems, found by truth;
//! * [`stability`] — where float ranks fail against the exact verdict;
//! * [`threshold`] — rod sequences, studies, finite-size scaling, variants;
//! * [`plot`] — charts of what the layers above computed;
//! * [`mod@bench`] — the speed and memory benchmarks behind `rgc bench`.

pub mod error;
pub mod usage;

pub mod math;
pub mod output;
pub mod progress;
pub mod stamp;

pub mod rods;

pub mod contacts;
pub mod graph;
pub mod network;

pub mod body;
pub mod spanning;

pub mod pattern;
pub mod rigidity;
pub mod truth;

pub mod moduli;

pub mod enumerate;
pub mod rule_file;

pub mod engine;
pub mod sample;
pub mod vtk;

pub mod audit;
pub mod mine;
pub mod stability;
pub mod threshold;

pub mod plot;

pub mod bench;

pub use error::{Error, Result};
