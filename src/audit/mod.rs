//! Which rigid motifs the engine misses (MODEL §7): the funnel from all
//! connected patterns of a size to the irreducible missed ones, which it
//! writes as rule files for the engine, and the patterns the engine
//! compresses although exact rank says they are not rigid. (The base motifs
//! as rules are `engine::shapes`; whether the engine compresses a pattern is
//! `Engine::compresses`.)
//!
//! The files, each using only those listed before it:
//! * `funnel` — what to audit, the tally of each size and the audit itself
//!   ([`AuditOptions`], [`AuditRow`], [`run`]);
//! * `files` — the tables, the JSON beside them, the rule files, and the
//!   check that an audit replaces only an equal audit's ([`write_outputs`],
//!   [`check_outputs`]);
//! * `redundant` — the rules of any rule files that smaller rules among
//!   them make redundant, by the audit's own test ([`redundant()`]).

mod files;
mod funnel;
mod redundant;

pub use files::{AuditFiles, check_outputs, write_csv, write_outputs};
pub use funnel::{Audit, AuditOptions, AuditRow, FalseRigidity, run, self_check, table};
pub use redundant::{Redundant, redundant};
