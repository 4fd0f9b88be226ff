//! One Monte Carlo sequence (MODEL §8): the seeded random rods of a box in
//! their order, whose first `n` rods are the `n`-rod system; the number of
//! rods at which it first spans by contacts (one union-find sweep) and
//! rigidly (bisection over the number of rods), and the paper's
//! fixed-density protocol on the same sequence.

pub mod bisection;
pub mod protocol;
pub mod record;
pub mod rods;
pub mod setup;
pub mod step;
pub mod verdict;

pub use protocol::{fixed, nested};
pub use record::Record;
pub use rods::Sequence;
pub use setup::{Kind, Setup};
pub use step::Step;
pub use verdict::{truth_spanning, truth_spans};
