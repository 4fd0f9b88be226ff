//! Truth: the exact rigidity of a whole contact graph (MODEL §10).
//!
//! 3D-RGC compresses local motifs, which is fast but neither sound on whole
//! graphs (a motif can be forced into a flexible special position by rods
//! outside it) nor complete. Truth decides the rigidity of the whole system
//! on one stated realization family: planes only where the contacts force
//! them, distinct contact points, everything else in general position.
//! [`decide`] runs the steps, each in its module, on a [`Topology`] (the
//! contacts and their images) and gives an [`answer`]:
//!
//! * [`prune`] — the 2-core: a rod held by one contact turns about it, so
//!   it neither is rigid with anything nor holds anything;
//! * [`planes`] — the forced plane classes, each also a rigid body;
//! * [`order`] — an order in which every line can be placed rationally;
//! * [`realize`] — an exact realization over F_p in that order;
//! * [`matrix`] — the rigidity matrix in body frames, six columns per part,
//!   and six strain columns where the box may deform;
//! * [`crate::math::sparse`] — its exact rank and random kernel vectors,
//!   the strain columns ranked last (the strain rank: how many strains of
//!   the box the system resists, 6 for a solid);
//! * [`clusters`] — the rigid clusters those vectors imply;
//! * [`contract`] — those clusters contracted, for the second twin's check.
//!
//! Two independent realizations (twins) are ranked, each in a prime drawn
//! at random; the generic rank is the larger. A realization can only lose
//! rank, so the rank found never exceeds the generic one: a system found
//! rigid (no motion but the trivial ones) is rigid. A flexibility may be an
//! unlucky draw, and no bound proven for whole systems makes that chance
//! small, so the twins check each other and how often they disagree is
//! measured (MODEL §10). The second twin confirms the first's kernel
//! dimension with the first's clusters contracted, and ranks the whole
//! matrix only where the
//! two differ. Where no rational construction order exists, [`fallback`] decides
//! in floats: twin realizations by numerical projection ([`projection`]),
//! the same matrix ranked by its singular values where they show a clear
//! gap, clusters from the kernel basis ([`Decision::Float`]). Where that is
//! not clear either, truth answers "undecided" and says why: never a guess.

pub mod answer;
pub mod clusters;
pub mod contract;
pub mod decide;
pub mod fallback;
pub mod matrix;
pub mod order;
pub mod planes;
pub mod projection;
pub mod prune;
pub mod realize;
pub mod special;

pub use crate::contacts::Offset;
pub use crate::graph::Topology;
pub use answer::{Cluster, Decision, Outcome, Spans, Strain, Strains, Truth, TruthOptions};
pub use decide::{MAX_REALIZATIONS, of_system, realization_ranks, truth, truth_in_floats};
