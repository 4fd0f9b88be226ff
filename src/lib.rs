//! `rgc`: rigidity percolation in random 3-D rod systems.
//!
//! The data flows through the modules in the order of the model
//! (see `DESIGN.md` in the project's shared notes):
//!
//! * [`rods`] — random soft-core spherocylinders in a periodic box;
//! * [`contacts`] — which rods touch (cell list, robust segment distance),
//!   the contact graph and its statistics;
//! * [`spanning`] — whether a cluster of rods spans the periodic box;
//! * [`engine`] — the 3D rigid graph compression (3D-RGC) with the base motifs;
//! * [`sample`] — one Monte Carlo sample from rods to rigid clusters;
//! * [`enumerate`] — non-isomorphic connected graphs and typed patterns, canonical forms;
//! * [`motifs`] — typed contact patterns: what is enumerated, checked and loaded as rules;
//! * [`realization`] — exact realizations of a pattern and their components;
//! * [`rigidity`] — the rigidity matrix and the exact verdict over components;
//! * [`rank`] — exact rank over the prime field F_p;
//! * [`stability`] — where float ranks fail against the exact verdict, and their speed;
//! * [`plot`] — charts of the stability study and of the thresholds (SVG, and PNG with an embedded font);
//! * [`graphio`] — graph6 and edge-list input and output;
//! * [`audit`] — which rigid motifs the engine misses; base and extended rule sets;
//! * [`threshold`] — Monte Carlo critical densities and finite-size scaling;
//! * [`bench`] — the speed and memory benchmark behind `rgc bench`.

pub mod audit;
pub mod bench;
pub mod contacts;
pub mod engine;
pub mod enumerate;
pub mod error;
pub mod graphio;
pub mod motifs;
pub mod plot;
pub mod rank;
pub mod realization;
pub mod rigidity;
pub mod rods;
pub mod sample;
pub mod spanning;
pub mod stability;
pub mod threshold;

pub use error::{Error, Result};
