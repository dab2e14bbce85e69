//! Cancelling a running sweep or stage from another thread (the Python binding's Ctrl-C).
//!
//! A [`Cancel`] token is a shared flag; [`Cancel::control`] is the [`RunControl`] that stops
//! when it is set, the one argument every stoppable function takes. The sweep asks it before
//! each point it has not started and before each geometry of the static-cache fill; the points
//! already running ask it before each static contact solve and each point of the dynamic curve. Once set, no
//! new point or FEM condensation starts, the running points stop within one solve or curve
//! point and save nothing (a rerun computes them), and the sweep returns
//! [`super::SweepRunError::Cancelled`] without writing `results.csv` or the charts. Not
//! interrupted: an FEM factorisation (seconds for the default strip), a mesh generation (gmsh),
//! the whole slider's static solve and the coupled dynamic model; a cancel takes effect after
//! the one of these that is running.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::pipeline::RunControl;

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

    /// A run control that stops once this token (or a clone) is cancelled:
    /// `run_pipeline(scene, options, &cancel.control())`.
    pub fn control(&self) -> RunControl {
        let token = self.clone();
        RunControl::none().with_stop(move || token.is_cancelled())
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
        let control = token.control();
        assert!(
            !control.should_stop(),
            "its run control does not stop before the cancel"
        );
        token.cancel();
        assert!(seen_by_worker.is_cancelled(), "the clone sees the cancel");
        assert!(
            control.should_stop(),
            "its run control stops after the cancel"
        );
    }
}
