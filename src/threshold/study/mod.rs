//! A threshold study on disk (MODEL §9): what was asked (`study.json`), the
//! fixed protocol's density grid (`grid.json`), and one JSON line per
//! finished sequence (`records*.jsonl`). A study killed at any moment
//! resumes from its records, and a finished one grows by more sequences per
//! box (`--extend`) without rerunning any; shards (`--shard i/n`) write
//! their own record files, in one directory or several, and [`merge`]
//! combines them exactly.
//!
//! The files, each using only those listed before it: `spec` (what
//! determines the records, [`StudySpec`]), `store` (the directory's files:
//! claiming it, shards' record files, reading them back, [`merge`]) and
//! `run` (the pilot grid and the loop over sequences, [`run`]).

mod run;
pub mod spec;
mod store;

pub use run::{PILOT, RunOptions, RunReport, run};
pub use spec::{MotifSet, STUDY_FORMAT, StudySpec};
pub use store::{Grid, GridBox, Shard, in_study_order, merge, read_records, read_spec};
