//! Cancelling a running sweep from another thread (the Python binding's Ctrl-C).
//!
//! A [`Cancel`] token is a shared flag. The sweep checks it before each point it has not started
//! and before each geometry of the static-cache fill: once set, no new point or FEM condensation
//! starts, the points already running finish and are saved (a rerun resumes them), and the sweep
//! returns [`super::SweepRunError::Cancelled`] without writing `results.csv` or the charts. Points
//! in flight are not interrupted: the stages inside a point have no cancellation point, so a
//! cancel takes effect within one point's wall time.

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
