#![doc = include_str!("../README.md")]

use std::fmt;
use std::sync::Arc;

/// A stop hook: answers whether the caller asked the computation to stop.
type StopHook = Arc<dyn Fn() -> bool + Send + Sync>;
/// A progress sink.
type ProgressHook = Arc<dyn Fn(Progress<'_>) + Send + Sync>;

/// One progress report of a running computation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress<'a> {
    /// A stage starts; the text names it for a display ("static FEM contact (η)").
    Stage(&'a str),
    /// `done` of `total` items of the running stage are finished (sweep points).
    Count {
        /// Items finished.
        done: usize,
        /// Items in the stage.
        total: usize,
    },
}

impl fmt::Display for Progress<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Progress::Stage(stage) => f.write_str(stage),
            Progress::Count { done, total } => write!(f, "{done} of {total}"),
        }
    }
}

/// The caller's control of a running computation: a stop request and a progress sink, both
/// optional. Cheap to clone (two shared pointers); clones share the hooks.
///
/// The stop request is asked at the computation's safe points (each crate documents its own:
/// before each static contact solve, each dynamic curve point, each sweep point). Once it
/// answers `true` the computation ends with its crate's `Cancelled` error, naming the step it
/// did not start, and writes nothing.
#[derive(Clone, Default)]
pub struct RunControl {
    stop: Option<StopHook>,
    progress: Option<ProgressHook>,
}

impl RunControl {
    /// A control that never stops and reports to nobody (the `Default`).
    pub fn none() -> Self {
        Self::default()
    }

    /// This control, stopped when `stop()` returns true.
    pub fn with_stop(mut self, stop: impl Fn() -> bool + Send + Sync + 'static) -> Self {
        self.stop = Some(Arc::new(stop));
        self
    }

    /// This control, reporting progress to `sink`.
    pub fn with_progress(mut self, sink: impl Fn(Progress<'_>) + Send + Sync + 'static) -> Self {
        self.progress = Some(Arc::new(sink));
        self
    }

    /// The same stop request without the progress sink: for work that runs beside other work
    /// (the points of a sweep), whose stage messages would interleave.
    pub fn without_progress(&self) -> Self {
        Self {
            stop: self.stop.clone(),
            progress: None,
        }
    }

    /// Whether the caller asked to stop.
    pub fn should_stop(&self) -> bool {
        self.stop.as_ref().is_some_and(|stop| stop())
    }

    /// Report `progress` to the sink, if any.
    pub fn report(&self, progress: Progress<'_>) {
        if let Some(sink) = &self.progress {
            sink(progress);
        }
    }

    /// Report that the stage named `stage` starts.
    pub fn stage(&self, stage: &str) {
        self.report(Progress::Stage(stage));
    }
}

impl fmt::Debug for RunControl {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RunControl")
            .field("stop", &self.stop.is_some())
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;
    use std::sync::atomic::{AtomicBool, Ordering};

    #[test]
    fn a_stop_request_is_seen_by_every_clone() {
        let flag = Arc::new(AtomicBool::new(false));
        let seen = Arc::clone(&flag);
        let control = RunControl::none().with_stop(move || seen.load(Ordering::Relaxed));
        let clone = control.without_progress();
        assert!(!clone.should_stop(), "not stopped before the request");
        flag.store(true, Ordering::Relaxed);
        assert!(control.should_stop(), "the control sees the request");
        assert!(
            clone.should_stop(),
            "a clone without progress keeps the stop request"
        );
    }

    #[test]
    fn progress_reaches_the_sink_and_not_the_control_without_progress() {
        let seen = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&seen);
        let control =
            RunControl::none().with_progress(move |p| sink.lock().unwrap().push(p.to_string()));
        control.stage("dynamics");
        control.report(Progress::Count { done: 2, total: 5 });
        control.without_progress().stage("hidden");
        assert_eq!(
            *seen.lock().unwrap(),
            ["dynamics", "2 of 5"],
            "the reports received"
        );
    }
}
