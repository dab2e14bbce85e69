//! Long calls: the work runs on its own thread while the calling thread waits without the GIL,
//! wakes every [`TICK`] to let Python handle signals (Ctrl-C raises `KeyboardInterrupt` at once)
//! and to report progress.
//!
//! Interrupted calls leave no half-written results: a call's result (and the staged results
//! folder it may carry) is handed back over a channel, and only the calling thread commits it.
//! After an interrupt the receiver is gone, so the result is dropped when the work ends, and a
//! staged folder with it (`StagedDir` removes itself when dropped uncommitted).
//!
//! Cancellation: an interrupt also sets the job's [`Cancel`] token, which the jobs hand to the
//! library as its run control ([`Cancel::control`]): the pipeline asks it between the stages,
//! before each static contact solve and each dynamic curve point (transient run); a sweep before
//! each point and inside the running ones. A stopped job ends with the library's `Cancelled`
//! error, which nobody reads. Not interrupted (the job ends after them): an FEM factorisation
//! (seconds for the default strip), a gmsh mesh generation, the whole slider's static solve,
//! the coupled dynamic model, and UQ/design runs.

use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::mpsc::{RecvTimeoutError, Sender, channel};
use std::time::{Duration, Instant};

use pyo3::prelude::*;
use sawdrive::sweep::Cancel;

use crate::errors::{Failure, Kind};

/// How often the waiting thread wakes to check for Ctrl-C and report progress. Unit: ms.
/// Short enough that an interrupt feels immediate, long enough to cost nothing. Default 100.
const TICK_MS: u64 = 100;
/// [`TICK_MS`] as a duration.
const TICK: Duration = Duration::from_millis(TICK_MS);

/// What a progress report counts besides the elapsed time: files of finished sweep points in
/// `folder` (ending `.json`) out of `total`.
#[derive(Debug, Clone)]
pub struct PointCount {
    /// Folder holding one `.json` per finished point.
    pub folder: PathBuf,
    /// Number of points.
    pub total: usize,
}

impl PointCount {
    fn done(&self) -> usize {
        let count = std::fs::read_dir(&self.folder).map_or(0, |entries| {
            entries
                .filter_map(Result::ok)
                .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
                .count()
        });
        count.min(self.total)
    }
}

/// Work for a worker thread (it sends its own outcome).
type Job = Box<dyn FnOnce() + Send>;

/// Queues of the idle worker threads. Threads are kept between calls: starting one costs tens
/// of microseconds, a few percent of a millisecond-long dynamic stage. A call that finds none
/// idle starts one, so calls from several Python threads never wait for each other.
static IDLE_WORKERS: Mutex<Vec<Sender<Job>>> = Mutex::new(Vec::new());

/// Hand `job` to an idle worker thread, or to a new one.
fn dispatch(mut job: Job) -> std::io::Result<()> {
    while let Some(worker) = IDLE_WORKERS.lock().ok().and_then(|mut idle| idle.pop()) {
        match worker.send(job) {
            Ok(()) => return Ok(()),
            Err(returned) => job = returned.0,
        }
    }
    let (queue, jobs) = channel::<Job>();
    // Queued before the thread starts; a failed spawn drops it with the receiver.
    let _ = queue.send(job);
    std::thread::Builder::new()
        .name("sawdrive-worker".into())
        .spawn(move || {
            for job in jobs.iter() {
                job();
                if let Ok(mut idle) = IDLE_WORKERS.lock() {
                    idle.push(queue.clone());
                }
            }
        })
        .map(drop)
}

/// Run `job` on a worker thread; call `progress(elapsed_s, done, total)` every tick (done and
/// total are `None` without a `count`). Returns the job's value, or raises its failure, the
/// progress callback's exception, or `KeyboardInterrupt`; the latter two cancel the job's token.
pub fn run<T: Send + 'static>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    count: Option<PointCount>,
    job: impl FnOnce(&Cancel) -> Result<T, Failure> + Send + 'static,
) -> PyResult<T> {
    let cancel = Cancel::new();
    let result = wait(py, progress, count, cancel.clone(), job);
    if result.is_err() {
        // Interrupted, or the job failed (then it has ended: the cancel is a no-op).
        cancel.cancel();
    }
    result
}

/// [`run`] with its token.
fn wait<T: Send + 'static>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    count: Option<PointCount>,
    cancel: Cancel,
    job: impl FnOnce(&Cancel) -> Result<T, Failure> + Send + 'static,
) -> PyResult<T> {
    let (sender, mut receiver) = channel();
    let work: Job = Box::new(move || {
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| job(&cancel)))
            .unwrap_or_else(|payload| Err(panic_failure(payload.as_ref())));
        // After an interrupt nobody listens: the outcome (and any staged folder) is dropped.
        let _ = sender.send(outcome);
    });
    if let Err(e) = dispatch(work) {
        return Err(
            Failure::text(Kind::Pipeline, format!("cannot start a worker thread: {e}"))
                .into_pyerr(py),
        );
    }
    let start = Instant::now();
    loop {
        // The receiver is moved through the GIL-free section (it is `Send`, not `Sync`).
        let (received, back) = py.detach(move || (receiver.recv_timeout(TICK), receiver));
        receiver = back;
        match received {
            Ok(outcome) => return outcome.map_err(|f| f.into_pyerr(py)),
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => {
                let f = Failure::text(Kind::Pipeline, "the worker thread ended without a result");
                return Err(f.into_pyerr(py));
            }
        }
        py.check_signals()?;
        if let Some(callback) = progress {
            let (done, total) = match &count {
                Some(c) => (Some(c.done()), Some(c.total)),
                None => (None, None),
            };
            callback.call1((start.elapsed().as_secs_f64(), done, total))?;
        }
    }
}

/// Run `job` on the calling thread with the GIL released. For the dynamic stage with η given
/// (no FEM): milliseconds for the period average, where the hand-over to a worker thread would
/// cost more than the stage on a loaded machine. Ctrl-C is raised when the job returns (its
/// result discarded) rather than at once.
pub fn run_inline<T: Send>(
    py: Python<'_>,
    job: impl FnOnce() -> Result<T, Failure> + Send,
) -> PyResult<T> {
    let outcome = py.detach(move || {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(job))
            .unwrap_or_else(|payload| Err(panic_failure(payload.as_ref())))
    });
    py.check_signals()?;
    outcome.map_err(|f| f.into_pyerr(py))
}

/// A panic in the library, as a failure naming it (a bug, not bad input).
fn panic_failure(payload: &(dyn std::any::Any + Send)) -> Failure {
    let message = payload
        .downcast_ref::<String>()
        .map(String::as_str)
        .or_else(|| payload.downcast_ref::<&str>().copied())
        .unwrap_or("unknown panic");
    Failure::text(
        Kind::Pipeline,
        format!("internal error (please report): {message}"),
    )
}

/// Stop a job whose token is cancelled (its caller was interrupted and discards the failure).
pub fn check(cancel: &Cancel) -> Result<(), Failure> {
    match cancel.is_cancelled() {
        true => Err(Failure::text(Kind::Pipeline, "cancelled")),
        false => Ok(()),
    }
}
