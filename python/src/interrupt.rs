//! Long calls that Ctrl-C stops: the work runs on a thread of its own (with
//! a rayon pool of its own) while the calling thread waits with the
//! interpreter released, a twentieth of a second at a time, and checks for
//! signals between waits.
//!
//! The library has no way to stop truth or a compression midway, so an
//! interrupted call returns at once with `KeyboardInterrupt` and its work
//! is abandoned: it finishes on its own threads and its answer is dropped.
//! Its own pool keeps it from delaying the calls that come after it.

use std::sync::mpsc::{RecvTimeoutError, sync_channel};
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often the waiting thread checks for signals.
const SLICE: Duration = Duration::from_millis(50);

/// `work`'s answer, or the exception a signal handler raised (Ctrl-C's
/// `KeyboardInterrupt`) within about a slice of the signal.
pub(crate) fn run<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(rayon::current_num_threads())
        .thread_name(|i| format!("rgc-{i}"))
        .build()
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start rgc's threads: {e}")))?;
    let (tx, rx) = sync_channel(1);
    std::thread::Builder::new()
        .name("rgc".into())
        .spawn(move || {
            // The receiver is gone when the call was interrupted.
            let _ = tx.send(pool.install(work));
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start rgc's thread: {e}")))?;
    let mut rx = rx;
    loop {
        // The receiver goes into the released section and comes back out.
        let (got, back) = py.detach(move || (rx.recv_timeout(SLICE), rx));
        rx = back;
        match got {
            Ok(answer) => return Ok(answer),
            Err(RecvTimeoutError::Timeout) => py.check_signals()?,
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "rgc stopped on an internal error (a panic, printed above): please report it",
                ));
            }
        }
    }
}
