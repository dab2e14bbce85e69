//! Cancellation inside the pipeline's stages: a stop request set from another thread ends the
//! static stage before its next contact solve and the dynamic stage before its next curve
//! point, with a `cancelled` error and nothing written (no cache entry, no results folder).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use sawdrive::pipeline::{RunControl, RunOptions, run_pipeline, run_static, scene_springs};
use sawdrive::scene::{Scene, load_scene};
use sawdrive::sweep::Cancel;

/// A stop hook over a [`Cancel`] token that another thread cancels when the hook is asked for
/// the `at`-th time (joined before the hook answers: no timing in the test).
struct CancelFromThread {
    asked: AtomicUsize,
    at: usize,
    token: Cancel,
}

impl CancelFromThread {
    fn new(at: usize) -> Self {
        Self {
            asked: AtomicUsize::new(0),
            at,
            token: Cancel::new(),
        }
    }

    fn ask(&self) -> bool {
        if self.asked.fetch_add(1, Ordering::SeqCst) + 1 == self.at {
            let token = self.token.clone();
            std::thread::spawn(move || token.cancel()).join().unwrap();
        }
        self.token.is_cancelled()
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

/// The small end-to-end scene (10 × 10 posts, committed 10-post strip mesh) with `overrides`.
fn small_scene(overrides: &[&str]) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/scenes/small-strip.toml");
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    load_scene(Some(&path), &overrides).unwrap()
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .map(|entries| entries.map(|e| e.unwrap().path()).collect())
        .unwrap_or_default()
}

#[test]
fn a_static_stage_cancelled_at_its_first_contact_solve_stops_there_and_caches_nothing() {
    let scene = small_scene(&[]);
    let springs = scene_springs(&scene).unwrap();
    let cache = tempfile::tempdir().unwrap();
    // Asked: 1 before the stage, 2 before the strip's condensation, 3 before the first phase.
    let stop = Arc::new(CancelFromThread::new(3));
    let error =
        run_static(&scene, &springs, Some(cache.path()), true, &stop.control()).unwrap_err();
    assert!(error.is_cancelled(), "a cancel, not a failure: {error}");
    assert!(
        error.to_string().contains("phase 1 of"),
        "the static stage names the contact solve it did not start: {error}"
    );
    assert_eq!(
        stop.asked(),
        3,
        "no contact solve is asked for after the cancel"
    );
    let entries: Vec<PathBuf> = files_in(cache.path())
        .into_iter()
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("static-")
        })
        .collect();
    assert!(
        entries.is_empty(),
        "no static cache entry after a cancel: {entries:?}"
    );
}

#[test]
fn a_run_cancelled_in_the_dynamic_curve_leaves_the_earlier_results_folder_as_it_was() {
    let scene = small_scene(&["effective_ratio=0.36"]);
    let out = tempfile::tempdir().unwrap();
    let folder = out.path().join(&scene.name);
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(folder.join(atomic_files::RESULT_MARKER), "run\n").unwrap();
    std::fs::write(folder.join("summary.json"), "earlier").unwrap();
    let options = RunOptions {
        out_dir: out.path().to_owned(),
        cache_dir: None,
        write_files: true,
    };
    let stop = Arc::new(CancelFromThread::new(4));
    let error = run_pipeline(&scene, &options, &stop.control()).unwrap_err();
    assert!(error.is_cancelled(), "a cancel, not a failure: {error}");
    assert!(
        error.to_string().contains("curve point"),
        "the dynamic stage names the curve point it did not start: {error}"
    );
    assert_eq!(
        stop.asked(),
        4,
        "no curve point is asked for after the cancel"
    );
    assert_eq!(
        std::fs::read_to_string(folder.join("summary.json")).unwrap(),
        "earlier",
        "the earlier summary.json is kept"
    );
    assert_eq!(
        files_in(out.path()),
        vec![folder],
        "no staging folder is left beside the results"
    );
}
