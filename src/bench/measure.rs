//! How the benchmarks measure: on one thread, so the figures are per core
//! whatever the machine, and in child processes, whose failures become one
//! line each.

use std::path::Path;
use std::process::{Command, Output};

use crate::{Error, Result};

/// Runs `f` on a pool of one thread: the figures are per core, whatever the
/// machine.
pub fn one_thread<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool")
        .install(f)
}

/// Runs `command` (the program `program`, named `what` in errors) to its
/// end; a start that fails or a non-zero exit is an error with the child's
/// own message.
pub fn run_child(command: &mut Command, program: &Path, what: &str) -> Result<Output> {
    let child = command.output().map_err(|e| Error::io(program, e))?;
    if !child.status.success() {
        return Err(failed(what, &child));
    }
    Ok(child)
}

/// The error of a child `what` that failed or said something unreadable:
/// its standard error.
pub fn failed(what: &str, child: &Output) -> Error {
    Error::io(
        what,
        std::io::Error::other(String::from_utf8_lossy(&child.stderr).trim().to_string()),
    )
}
