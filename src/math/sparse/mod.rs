//! Exact rank and random kernel vectors of a large sparse matrix over F_p,
//! by multifrontal elimination.
//!
//! The columns come in groups (the six motion coordinates of one rigid
//! part), and a row touches few groups (a contact touches two parts). Dense
//! elimination of a whole rod system is hopeless (tens of thousands of
//! columns, cubic cost). So the matrix is kept as dense elements over a few
//! groups each ([`quotient`]), and groups are eliminated in minimum-degree
//! order, each in a dense front that absorbs the elements touching it and
//! leaves one new element ([`front`]). Inside a front the work is a dense
//! echelon form, blocked with delayed reduction
//! ([`crate::math::echelon`]). Every step is a row operation, so the number
//! of pivots is the rank; the pivot rows, kept when kernel vectors are
//! asked for, solve for them.
//!
//! [`elimination`] runs it and holds its outcome.

pub mod elimination;
pub mod front;
pub mod quotient;

pub use elimination::{Counts, Deferred, Elimination, Layout, Refused, Step, eliminate, rank};
pub use quotient::SparseRow;
