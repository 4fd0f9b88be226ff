//! Which rods touch (MODEL §1): an O(N) periodic grid of rod covers
//! (`grid`) over a robust segment–segment distance (`segment`), with
//! the O(N^2) all-pairs reference (`pair`).

mod grid;
mod pair;
mod segment;

pub use grid::detect;
pub use pair::{Contact, Offset, detect_all_pairs};
pub use segment::{Closest, closest_points};
