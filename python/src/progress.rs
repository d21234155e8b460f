//! Work done with the GIL released, reporting its progress to an optional Python callback.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::ProgressBar;
use pyo3::prelude::*;

/// How often the callback is called while the work runs.
const EVERY: Duration = Duration::from_millis(100);

/// Runs `work` with the GIL released (other Python threads run meanwhile), handing it a
/// hidden progress bar that the library advances. When `callback` is given, a watcher thread
/// calls `callback(done, total)` every 100 ms and once at the end. An exception the callback
/// raises stops the calls and is raised once the work is done.
pub fn with_progress<T: Send>(
    py: Python<'_>,
    callback: Option<Py<PyAny>>,
    work: impl FnOnce(&ProgressBar) -> T + Send,
) -> PyResult<T> {
    let pb = ProgressBar::hidden();
    let finished = AtomicBool::new(false);
    let (result, raised) = py.detach(|| {
        std::thread::scope(|scope| {
            let watcher = callback.as_ref().map(|callback| {
                let (pb, finished) = (&pb, &finished);
                scope.spawn(move || {
                    let mut last = Instant::now();
                    while !finished.load(Ordering::Acquire) {
                        std::thread::sleep(Duration::from_millis(5));
                        if last.elapsed() >= EVERY {
                            last = Instant::now();
                            let called = Python::attach(|py| {
                                callback.call1(py, (pb.position(), pb.length().unwrap_or(0)))
                            });
                            if let Err(e) = called {
                                return Some(e);
                            }
                        }
                    }
                    None
                })
            });
            let result = work(&pb);
            finished.store(true, Ordering::Release);
            let raised = watcher.and_then(|w| w.join().ok().flatten());
            (result, raised)
        })
    });
    if let Some(e) = raised {
        return Err(e);
    }
    if let Some(callback) = callback {
        callback.call1(py, (pb.position(), pb.length().unwrap_or(0)))?;
    }
    Ok(result)
}
