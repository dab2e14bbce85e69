//! Cancelling a running sweep or stage from another thread (the Python binding's Ctrl-C).
//!
//! A [`Cancel`] token is a shared flag. The sweep checks it before each point it has not started
//! and before each geometry of the static-cache fill; the points already running see it through
//! the pipeline's stop hook ([`Cancel::should_stop`], the library crates' `ShouldStop`), which
//! is asked before each static contact solve and each point of the dynamic curve. Once set, no
//! new point or FEM condensation starts, the running points stop within one solve or curve
//! point and save nothing (a rerun computes them), and the sweep returns
//! [`super::SweepRunError::Cancelled`] without writing `results.csv` or the charts. Not
//! interrupted: an FEM factorisation (seconds for the default strip), a mesh generation (gmsh),
//! the whole slider's static solve and the coupled dynamic model; a cancel takes effect after
//! the one of these that is running.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A cancellation flag shared between the thread that runs a sweep and the threads that may stop
/// it. Clones share the flag. The default token is never cancelled unless [`Cancel::cancel`] is
/// called on it or a clone.
#[derive(Debug, Clone, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A token not cancelled yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Ask every holder of the token to stop at its next check.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether [`Cancel::cancel`] was called on this token or a clone.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// The token as the pipeline's stop hook ([`crate::pipeline::ShouldStop`]):
    /// `run_pipeline_cancellable(scene, options, &cancel.should_stop())`.
    pub fn should_stop(&self) -> impl Fn() -> bool + Sync + '_ {
        || self.is_cancelled()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cancel_reaches_every_clone() {
        let token = Cancel::new();
        let seen_by_worker = token.clone();
        assert!(
            !seen_by_worker.is_cancelled(),
            "a new token is not cancelled"
        );
        token.cancel();
        assert!(seen_by_worker.is_cancelled(), "the clone sees the cancel");
    }
}
