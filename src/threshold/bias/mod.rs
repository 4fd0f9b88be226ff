//! Every 3D-RGC variant against the exact truth (MODEL §10): the design,
//! the paired bias per box and the false spans, their tables, and truth's
//! monotonicity scan.

pub mod design;
pub mod measure;
pub mod outcome;
pub mod scan;
pub mod table;

#[cfg(test)]
mod fixtures;

pub use design::{check_design, truth_design};
pub use measure::measure;
pub use outcome::{BoxBias, VariantBias};
pub use scan::{Scan, scan, scan_csv, scan_summary};
pub use table::{csv, markdown};
