//! Cancellation inside the dynamic model: a stop request set from another thread ends the run
//! at the next curve point (transient run), with `Cancelled` and no result; a hook that never
//! stops changes nothing.

#[path = "support/johnson.rs"]
mod johnson;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use stick_slip::{DynamicScene, ModelChoice, RunControl, StickSlipError, solve_with_histories};

/// A stop hook whose flag another thread sets when the hook is asked for the `at`-th time
/// (the thread is joined before the hook answers, so the test does not depend on timing).
struct StopFromThread {
    asked: AtomicUsize,
    at: usize,
    flag: Arc<AtomicBool>,
}

impl StopFromThread {
    fn new(at: usize) -> Self {
        Self {
            asked: AtomicUsize::new(0),
            at,
            flag: Arc::new(AtomicBool::new(false)),
        }
    }

    fn ask(&self) -> bool {
        if self.asked.fetch_add(1, Ordering::SeqCst) + 1 == self.at {
            let flag = Arc::clone(&self.flag);
            std::thread::spawn(move || flag.store(true, Ordering::SeqCst))
                .join()
                .unwrap();
        }
        self.flag.load(Ordering::SeqCst)
    }

    fn asked(&self) -> usize {
        self.asked.load(Ordering::SeqCst)
    }

    /// A run control whose stop request is this hook.
    fn control(self: &Arc<Self>) -> RunControl {
        let hook = Arc::clone(self);
        RunControl::none().with_stop(move || hook.ask())
    }
}

fn paper_scene() -> DynamicScene {
    let (k_n, k_t) = johnson::springs(10e-6);
    DynamicScene::paper_default(k_n, k_t)
}

#[test]
fn a_period_average_cancelled_at_the_third_curve_point_stops_there_with_no_result() {
    let scene = paper_scene();
    let stop = Arc::new(StopFromThread::new(3));
    let error = solve_with_histories(&scene, &stop.control()).unwrap_err();
    assert!(
        matches!(&error, StickSlipError::Cancelled { before } if before.starts_with("curve point 3 of")),
        "cancel before the third speed of the curve: {error}"
    );
    assert_eq!(
        stop.asked(),
        3,
        "no further curve point (speed) is asked for after the cancel"
    );
}

#[test]
fn a_transient_cancelled_after_its_operating_point_runs_no_curve_load() {
    let mut scene = paper_scene();
    scene.model = ModelChoice::Transient;
    scene.options.transient.periods = 20.0;
    scene.options.transient.average_periods = 5.0;
    let stop = Arc::new(StopFromThread::new(2));
    let error = solve_with_histories(&scene, &stop.control()).unwrap_err();
    assert!(
        matches!(&error, StickSlipError::Cancelled { before } if before.starts_with("the curve run at load")),
        "cancel before the first curve load of the transient: {error}"
    );
    assert_eq!(stop.asked(), 2, "no transient run after the cancel");
}

#[test]
fn a_hook_that_never_stops_gives_the_uncancellable_result_bit_for_bit() {
    let scene = paper_scene();
    let (expected, _) = solve_with_histories(&scene, &RunControl::none()).unwrap();
    let asked = Arc::new(AtomicUsize::new(0));
    let counter = Arc::clone(&asked);
    let control = RunControl::none().with_stop(move || {
        counter.fetch_add(1, Ordering::SeqCst);
        false
    });
    let (result, _) = solve_with_histories(&scene, &control).unwrap();
    assert_eq!(
        result.stall_thrust_n.to_bits(),
        expected.stall_thrust_n.to_bits(),
        "stall thrust with a hook"
    );
    assert_eq!(
        result.curve, expected.curve,
        "speed–thrust curve with a hook"
    );
    assert!(
        asked.load(Ordering::SeqCst) >= result.curve.len(),
        "the hook is asked at least once per curve point"
    );
}
