//! Long work off the GIL. The job runs on its own thread; the calling thread, which
//! holds the GIL between short waits, polls `check_signals` (Ctrl-C raises
//! `KeyboardInterrupt` only in the thread that holds the GIL, and only when it runs
//! Python code) and reports progress to a Python callable. On an exception it sets the
//! cancel flag and waits for the job to stop before raising.

use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::time::Duration;

/// How often signals and progress are looked at: well under the half second a user
/// waits after Ctrl-C before it feels ignored.
const POLL: Duration = Duration::from_millis(50);

/// Progress of a job: units done (added from any thread) out of a total.
pub struct Counter {
    done: AtomicU64,
    pub total: u64,
}

impl Counter {
    pub fn new(total: u64) -> Counter {
        Counter {
            done: AtomicU64::new(0),
            total,
        }
    }

    pub fn add(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }

    fn done(&self) -> u64 {
        self.done.load(Ordering::Relaxed).min(self.total)
    }
}

/// Calls `callback(done, total)` when `done` changed since the last call.
fn report(
    callback: Option<&Bound<'_, PyAny>>,
    done: u64,
    total: u64,
    last: &mut u64,
) -> PyResult<()> {
    if let Some(cb) = callback
        && done != *last
    {
        *last = done;
        cb.call1((done, total))?;
    }
    Ok(())
}

/// Runs `job` on another thread with the GIL released, serving signals and progress
/// until it returns. `cancel` must be the flag the job stops on.
pub fn run<T: Send>(
    py: Python<'_>,
    cancel: &AtomicBool,
    counter: &Counter,
    callback: Option<&Bound<'_, PyAny>>,
    job: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    run_ticking(py, cancel, counter, callback, &mut || Ok(()), job)
}

/// [`run`], calling `tick` (with the GIL) at each poll while the job runs: a live
/// preview's refresh.
pub fn run_ticking<T: Send>(
    py: Python<'_>,
    cancel: &AtomicBool,
    counter: &Counter,
    callback: Option<&Bound<'_, PyAny>>,
    tick: &mut dyn FnMut() -> PyResult<()>,
    job: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    std::thread::scope(|s| {
        let (tx, rx) = channel();
        s.spawn(move || {
            let _ = tx.send(job());
        });
        let mut rx: Receiver<T> = rx;
        let mut last = u64::MAX;
        loop {
            let (back, got) = py.detach(move || {
                let got = rx.recv_timeout(POLL);
                (rx, got)
            });
            rx = back;
            match got {
                Ok(out) => {
                    report(callback, counter.total, counter.total, &mut last)?;
                    return Ok(out);
                }
                Err(RecvTimeoutError::Timeout) => {}
                // The job panicked: leaving the scope re-raises its panic, which PyO3
                // turns into a PanicException.
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(pyo3::exceptions::PyRuntimeError::new_err("render failed"));
                }
            }
            let served = py
                .check_signals()
                .and_then(|()| report(callback, counter.done(), counter.total, &mut last))
                .and_then(|()| tick());
            if let Err(e) = served {
                cancel.store(true, Ordering::Relaxed);
                // Rows already started finish; the rest are skipped.
                let _ = py.detach(move || rx.recv());
                return Err(e);
            }
        }
    })
}
