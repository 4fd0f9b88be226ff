//! Soft-core spherocylinders in a box (MODEL §1): the paper's ensemble
//! (equal rods, isotropic, a periodic cube), the wider ensembles of
//! [`ensemble`], and rods read from files ([`file`](mod@file)).
//!
//! Lengths are in units of the paper's core length `l = 1`. Rods are
//! generated one after another from a single seeded stream, so the first `n`
//! rods of a system are exactly the `n`-rod system of the same seed and box:
//! one Monte Carlo sequence is a nested series of systems.

pub mod ensemble;
pub mod file;
mod system;

pub use system::*;
