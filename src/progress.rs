//! Progress of long computations, reported to whoever asked for them.
//!
//! The library only counts: the audit and the threshold studies call a
//! [`Progress`] the caller hands in, so a terminal bar, a line in a batch
//! log or nothing at all is the caller's choice, and the library needs no
//! terminal crate.

/// Receives the progress of a computation made of stages (an audit size, a
/// study's sequences), each counted in units of the caller's choosing.
///
/// `Sync` because the units are counted from rayon's threads.
pub trait Progress: Sync {
    /// A stage of `total` units begins; `label` says what it is.
    fn start(&self, label: &str, total: u64);
    /// `units` more units of the current stage are done.
    fn advance(&self, units: u64);
    /// The current stage is over.
    fn finish(&self);
    /// A line worth showing between stages (which study runs next).
    fn note(&self, line: &str);
}

/// Reports nothing: for tests, and for output that must stay clean.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn start(&self, _label: &str, _total: u64) {}
    fn advance(&self, _units: u64) {}
    fn finish(&self) {}
    fn note(&self, _line: &str) {}
}
