//! End-to-end tests of how results reach the disk: a run killed between the two renames of its
//! commit (the next run restores the earlier results), the default output folder of `validate
//! springs`, and the bound on `sweep --jobs`.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::{sawdrive, sawdrive_err, sawdrive_ok};

const SMALL_SCENE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/scenes/small-strip.toml"
);
const SMALL_SWEEP: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/sweeps/small-preload.toml"
);

/// Longest wait for a run to reach the pause between its renames (s); it takes ≈ 1 s.
const PAUSE_TIMEOUT_S: u64 = 120;

/// `sawdrive run` of the small scene with η given (no FEM: fast) into `out`.
fn run_args(out: &Path) -> Vec<String> {
    [
        "run",
        SMALL_SCENE,
        "--set",
        "effective_ratio=0.36",
        "--out",
        out.to_str().unwrap(),
    ]
    .map(String::from)
    .to_vec()
}

/// Start the run with the test hook that stops its commit between the renames; wait until it is
/// there (the earlier results moved aside to `.small-strip.previous-PID`) and return the child
/// and that folder.
fn run_paused_between_renames(out: &Path) -> (Child, PathBuf) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_sawdrive"))
        .args(run_args(out))
        .env("SAWDRIVE_TEST_PAUSE_COMMIT", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("sawdrive starts");
    let previous = out.join(format!(".small-strip.previous-{}", child.id()));
    let start = Instant::now();
    while !previous.is_dir() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the paused run exited ({status}) before reaching its commit");
        }
        assert!(
            start.elapsed().as_secs() < PAUSE_TIMEOUT_S,
            "run never reached the commit"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    (child, previous)
}

fn kill(mut child: Child) {
    child.kill().expect("SIGKILL the paused run");
    child.wait().unwrap();
}

fn hidden_names(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".small-strip"))
        .collect()
}

#[test]
fn results_of_a_run_killed_between_the_commit_renames_are_restored_by_the_next_run() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path();
    let results = out.join("small-strip");
    sawdrive_ok(&run_args(out).iter().map(String::as_str).collect::<Vec<_>>());
    // Mark the earlier results so that they can be recognised after the restore.
    std::fs::write(results.join("earlier.txt"), "earlier results").unwrap();

    let (child, previous) = run_paused_between_renames(out);
    kill(child);
    assert!(
        !results.exists(),
        "the kill left the results moved aside (the defect's state)"
    );
    assert!(previous.join("earlier.txt").is_file());

    // The next run restores them before it starts: killed again at the same point, the folder
    // it had moved aside holds the earlier results.
    let (child, previous) = run_paused_between_renames(out);
    assert!(
        previous.join("earlier.txt").is_file() && previous.join("summary.json").is_file(),
        "the next run restored the earlier results before committing its own"
    );
    kill(child);

    let next = sawdrive(&run_args(out).iter().map(String::as_str).collect::<Vec<_>>());
    let stderr = String::from_utf8_lossy(&next.stderr);
    assert!(next.status.success(), "run after the kill: {stderr}");
    assert!(
        stderr.contains("restored the earlier results"),
        "the user is told: {stderr}"
    );
    assert!(
        results.join("summary.json").is_file(),
        "new results committed"
    );
    assert!(
        !results.join("earlier.txt").exists(),
        "and replaced the restored ones"
    );
    assert_eq!(
        hidden_names(out),
        Vec::<String>::new(),
        "no hidden folders left"
    );
}

#[test]
fn validate_springs_writes_under_out_in_the_current_folder_by_default() {
    if Command::new("gmsh").arg("--version").output().is_err() {
        eprintln!("gmsh is not installed (scripts/install-deps.sh): skipped");
        return;
    }
    let cwd = tempfile::tempdir().unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_sawdrive"))
        .args(["validate", "springs", "--level", "smoke", "--json"])
        .current_dir(cwd.path())
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        cwd.path()
            .join("out/validation/springs/results/cases.json")
            .is_file(),
        "cases.json in ./out/validation/springs/results"
    );
}

#[test]
fn sweep_with_unbounded_jobs_is_refused_naming_the_limit() {
    let out = tempfile::tempdir().unwrap();
    let stderr = sawdrive_err(
        &[
            "sweep",
            SMALL_SWEEP,
            "--jobs",
            "100000",
            "--out",
            out.path().to_str().unwrap(),
        ],
        "--jobs 100000: must be between 1 and 256",
    );
    assert_eq!(stderr.lines().count(), 1, "one-line error: {stderr}");
    assert_eq!(
        std::fs::read_dir(out.path()).unwrap().count(),
        0,
        "nothing written"
    );
}
