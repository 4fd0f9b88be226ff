//! Rods from and to files: a CSV table, JSON, and a LAMMPS dump.
//!
//! The CSV has a header naming the columns `x,y,z,dx,dy,dz,length,radius`
//! (in any order, with `id` if the rods are numbered; other columns are
//! ignored): the centre, the direction (normalized on reading), the core
//! length and the radius; its box and origin come from the options. JSON
//! is an object `{"box": [LX, LY, LZ], "origin": [X, Y, Z], "periodic":
//! "xyz", "rods": [{"center": [..], "direction": [..], "length": ..,
//! "radius": .., "id": ..}, ..]}` whose box, origin, periodicity and ids may
//! be left out. A LAMMPS dump gives its box, origin and boundary flags in
//! each snapshot's header; [`Columns`] says which per-atom column holds
//! which quantity, [`Frame`] which snapshot is read, and atoms may be picked
//! by type. Files are read into rgc's frame and checked ([`read`]'s module)
//! and written back in it.

mod columns;
mod format;
mod json;
mod lammps;
mod read;
mod table;
mod write;

pub use columns::{Columns, KEYS, Source};
pub use format::{FIELDS, Format};
pub use lammps::Frame;
pub use read::{Loaded, ReadOptions, STDIN, parse, placement, read};
pub use write::{save, to_string};
