//! The stiffness across the critical rod (MODEL §10, elastic moduli): on
//! the sequences of finished truth studies, the elastic moduli of the first
//! `n_c - 1` and `n_c` rods, `n_c` the study's critical number (where a true
//! cluster first wraps the box, or where the rods first resist every strain
//! for a study of the solid criterion). The largest cluster jumps at that
//! rod ([`super::transition`]); whether the shear modulus jumps with it is
//! what tells a rigidity transition that stiffens at once from one whose
//! moduli rise continuously, as Chubynsky and Thorpe found for central
//! forces. At given densities too, the moduli against the density (the
//! stiffening curve `G(rho)`, `K(rho)`) beside the largest true cluster's
//! share of the rods. Each sequence is one line of `stiffening.jsonl` (a
//! [`super::journal`]), so a killed run resumes, and a sequence in
//! progress is saved after each side (hours at large boxes), so it resumes
//! from its last side.
//!
//! [`record`] holds what one line stores, [`summary`] what the lines say
//! per box and across boxes, and [`measure`] measures the lines and calls
//! the summary.

pub mod measure;
pub mod record;
pub mod summary;

pub use measure::{read, run};
pub use record::{SequenceStiffening, Side, StiffeningSpec};
pub use summary::{
    Exponent, GridPoint, Mean, ShearDecay, Stiffening, StiffeningSummary, shear_decay, summarize,
    write,
};
