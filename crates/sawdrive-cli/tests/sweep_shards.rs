//! Sweeps on a cluster (`sawdrive sweep FILE --shard K/N`, `--merge`): shards run as separate
//! processes on this machine, sharing one results folder and one FEM cache as they would on a
//! shared file system.

#[path = "../../../tests/common.rs"]
mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::{sawdrive_err, sawdrive_ok};

/// The small end-to-end scene (10 × 10 posts, committed strip mesh).
fn small_scene() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/scenes/small-strip.toml"
    )
    .to_owned()
}

/// Dynamics model of the fast sweeps: the period average (milliseconds a point).
const FAST: &str = "periodic-average";
/// Dynamics model of the slow sweep: the transient (about a second a point), so that a shard can
/// be killed between two points.
const SLOW: &str = "transient";

/// A sweep named `name` of `preloads` × 2 frictions with a chart, on the small scene with the
/// dynamics `model`; `eta`: `effective_ratio = 0.36` (dynamic stage only) or η from the FEM.
fn write_sweep(dir: &Path, name: &str, preloads: usize, model: &str, eta: bool) -> PathBuf {
    let values: Vec<String> = (1..=preloads)
        .map(|i| format!("\"{:.2} N\"", 0.1 * i as f64))
        .collect();
    let eta = if eta { "effective_ratio = 0.36\n" } else { "" };
    let text = format!(
        "name = \"{name}\"\nscene = \"{}\"\n[set]\n{eta}\"model.dynamics\" = \"{model}\"\n\
         [grid]\npreload = [{}]\nfriction = [0.2, 0.3]\n\
         [[charts]]\nx = \"preload_n\"\ny = \"stall_thrust_n\"\nseries = \"friction\"\n",
        small_scene(),
        values.join(", ")
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// A given-η sweep (dynamic stage only, period average) of `preloads` × 2 frictions.
fn eta_sweep(dir: &Path, preloads: usize) -> PathBuf {
    write_sweep(dir, "eta-grid", preloads, FAST, true)
}

fn arg(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Start `sawdrive sweep SWEEP --out OUT --jobs 1 --shard K/N` (stdout captured).
fn spawn_shard(sweep: &Path, out: &Path, shard: &str) -> Child {
    Command::new(env!("CARGO_BIN_EXE_sawdrive"))
        .args(["sweep", arg(sweep), "--out", arg(out), "--jobs", "1"])
        .args(["--shard", shard])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sawdrive starts")
}

/// Run all `count` shards at once as separate processes; returns each one's stdout.
fn run_shards_together(sweep: &Path, out: &Path, count: usize) -> Vec<String> {
    let children: Vec<Child> = (1..=count)
        .map(|k| spawn_shard(sweep, out, &format!("{k}/{count}")))
        .collect();
    children
        .into_iter()
        .map(|child| {
            let output = child.wait_with_output().unwrap();
            assert!(
                output.status.success(),
                "shard failed: {}",
                String::from_utf8_lossy(&output.stderr)
            );
            String::from_utf8(output.stdout).unwrap()
        })
        .collect()
}

/// `results.csv` without its last column, `wall_time_s` (a measurement, different in any two
/// runs); checks that the column is the one removed.
fn csv_without_wall_time(folder: &Path) -> String {
    let text = std::fs::read_to_string(folder.join("results.csv")).unwrap();
    assert!(text.lines().next().unwrap().ends_with(",wall_time_s"));
    text.lines()
        .map(|line| line.rsplit_once(',').unwrap().0)
        .collect::<Vec<_>>()
        .join("\n")
}

/// The rows printed by `--json`, without `wall_time_s`.
fn rows_without_wall_time(json: &str) -> Vec<serde_json::Value> {
    let mut rows: Vec<serde_json::Value> = serde_json::from_str(json).unwrap();
    for row in &mut rows {
        row.as_object_mut().unwrap().remove("wall_time_s").unwrap();
    }
    rows
}

/// Condensations reported in a shard's summary line ("…, 1 FEM condensations; …").
fn condensations(summary: &str) -> usize {
    let before = summary.split(" FEM condensations").next().unwrap();
    before.rsplit(' ').next().unwrap().parse().unwrap()
}

#[test]
fn three_shard_processes_merge_to_the_unsharded_results() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = eta_sweep(dir.path(), 4);
    let (whole, sharded) = (dir.path().join("whole"), dir.path().join("sharded"));
    let whole_json = sawdrive_ok(&["sweep", arg(&sweep), "--out", arg(&whole), "--json"]);

    let summaries = run_shards_together(&sweep, &sharded, 3);
    assert!(
        summaries.iter().any(|s| s.contains("results merged")),
        "the last shard merges: {summaries:?}"
    );
    let (a, b) = (whole.join("eta-grid"), sharded.join("eta-grid"));
    assert_eq!(
        csv_without_wall_time(&a),
        csv_without_wall_time(&b),
        "results.csv of 3 shards equals the unsharded one"
    );
    for chart in [
        "stall_thrust_n_vs_preload_n.svg",
        "stall_thrust_n_vs_preload_n.png",
    ] {
        assert_eq!(
            std::fs::read(a.join(chart)).unwrap(),
            std::fs::read(b.join(chart)).unwrap(),
            "stall-thrust chart {chart} of 3 shards equals the unsharded one"
        );
    }
    let merged_json = sawdrive_ok(&[
        "sweep",
        arg(&sweep),
        "--out",
        arg(&sharded),
        "--merge",
        "--json",
    ]);
    assert_eq!(
        rows_without_wall_time(&merged_json),
        rows_without_wall_time(&whole_json),
        "merged JSON rows (stall thrust, speed, efficiency, …) equal the unsharded ones"
    );
    assert_eq!(rows_without_wall_time(&merged_json).len(), 8);
}

#[test]
fn a_killed_shard_rerun_completes_the_set() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = write_sweep(dir.path(), "eta-grid", 4, SLOW, true);
    let out = dir.path().join("out");
    let points = out.join("eta-grid").join("points");
    let saved = || {
        std::fs::read_dir(&points).map_or(0, |d| {
            // Saved points only, not the hidden temporary file of a point being written.
            d.filter(|e| {
                let name = e.as_ref().unwrap().file_name();
                let name = name.to_str().unwrap();
                name.ends_with(".json") && !name.starts_with('.')
            })
            .count()
        })
    };
    let mut first = spawn_shard(&sweep, &out, "1/2");
    let start = Instant::now();
    while saved() == 0 {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "shard 1 saves a point"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    first.kill().unwrap();
    first.wait().unwrap();
    let after_kill = saved();
    assert!(
        (1..4).contains(&after_kill),
        "shard 1 killed after {after_kill} of its 4 points"
    );

    let second = sawdrive_ok(&[
        "sweep",
        arg(&sweep),
        "--out",
        arg(&out),
        "--jobs",
        "1",
        "--shard",
        "2/2",
    ]);
    assert!(
        second.contains("not saved yet"),
        "no merge with shard 1 incomplete: {second}"
    );
    let error = sawdrive_err(
        &["sweep", arg(&sweep), "--out", arg(&out), "--merge"],
        &format!("{} of 8 points not saved yet", 4 - after_kill),
    );
    for n in ["#2 [", "#4 [", "#6 [", "#8 ["] {
        assert!(
            !error.contains(n),
            "merge names only shard 1's points, not {n}: {error}"
        );
    }

    let rerun = sawdrive_ok(&[
        "sweep",
        arg(&sweep),
        "--out",
        arg(&out),
        "--jobs",
        "1",
        "--shard",
        "1/2",
    ]);
    assert!(
        rerun.contains(&format!("4 points ({after_kill} resumed)")),
        "the rerun resumes the killed shard's saved points: {rerun}"
    );
    assert!(rerun.contains("results merged"), "{rerun}");
    let csv = std::fs::read_to_string(out.join("eta-grid/results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 9, "header + 8 points:\n{csv}");
}

#[test]
fn merge_with_points_missing_names_them_and_keeps_earlier_results() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = eta_sweep(dir.path(), 2);
    let out = dir.path().join("out");
    let folder = out.join("eta-grid");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(folder.join("results.csv"), "earlier results\n").unwrap();
    sawdrive_ok(&["sweep", arg(&sweep), "--out", arg(&out), "--shard", "2/4"]);
    let error = sawdrive_err(
        &["sweep", arg(&sweep), "--out", arg(&out), "--merge"],
        "3 of 4 points not saved yet",
    );
    assert_eq!(error.trim().lines().count(), 1, "one line: {error}");
    for n in ["#1 [", "#3 [", "#4 ["] {
        assert!(error.contains(n), "names point {n}: {error}");
    }
    assert!(!error.contains("#2 ["), "point 2 is saved: {error}");
    assert_eq!(
        std::fs::read_to_string(folder.join("results.csv")).unwrap(),
        "earlier results\n",
        "a refused merge leaves earlier results"
    );
}

#[test]
fn shard_index_out_of_range_and_bad_shard_text_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = eta_sweep(dir.path(), 2);
    let out = dir.path().join("out");
    let error = sawdrive_err(
        &["sweep", arg(&sweep), "--out", arg(&out), "--shard", "5/4"],
        "--shard 5/4: shard index 5 is outside 1..=4",
    );
    assert!(error.contains("the 4 points"), "{error}");
    sawdrive_err(
        &["sweep", arg(&sweep), "--out", arg(&out), "--shard", "0/4"],
        "outside 1..=4",
    );
    sawdrive_err(
        &["sweep", arg(&sweep), "--out", arg(&out), "--shard", "1/9"],
        "use N ≤ 4",
    );
    sawdrive_err(
        &["sweep", arg(&sweep), "--out", arg(&out), "--shard", "two/4"],
        "is not K/N",
    );
    sawdrive_err(
        &[
            "sweep",
            arg(&sweep),
            "--out",
            arg(&out),
            "--shard",
            "1/2",
            "--merge",
        ],
        "--merge",
    );
    assert!(!out.exists(), "nothing written for a refused shard");
}

#[test]
fn fem_shards_sharing_one_cache_condense_each_geometry_once() {
    let dir = tempfile::tempdir().unwrap();
    // 2 preloads × 2 frictions, η from the FEM of one slider geometry (committed strip mesh).
    let sweep = write_sweep(dir.path(), "fem-grid", 2, FAST, false);
    let (whole, sharded) = (dir.path().join("whole"), dir.path().join("sharded"));
    sawdrive_ok(&["sweep", arg(&sweep), "--out", arg(&whole), "--jobs", "1"]);
    let summaries = run_shards_together(&sweep, &sharded, 2);
    let total: usize = summaries.iter().map(|s| condensations(s)).sum();
    assert_eq!(
        total, 1,
        "one FEM condensation of the one geometry for both shards: {summaries:?}"
    );
    assert_eq!(
        csv_without_wall_time(&whole.join("fem-grid")),
        csv_without_wall_time(&sharded.join("fem-grid")),
        "FEM sweep (η from the static stage) of 2 shards equals the unsharded one"
    );
    // The cache the shards shared is sound: the same sweep over it again condenses nothing.
    std::fs::remove_dir_all(sharded.join("fem-grid")).unwrap();
    let again = sawdrive_ok(&[
        "sweep",
        arg(&sweep),
        "--out",
        arg(&sharded),
        "--shard",
        "1/1",
    ]);
    assert_eq!(
        condensations(&again),
        0,
        "static cache entries verified and reused: {again}"
    );
    assert_eq!(
        csv_without_wall_time(&whole.join("fem-grid")),
        csv_without_wall_time(&sharded.join("fem-grid")),
        "results from the shared cache equal the unsharded ones"
    );
}

/// The Slurm job-array script under a throwaway single-node Slurm (`scripts/slurm-selftest.sh`).
/// Needs root and the Debian packages `slurmd slurmctld slurm-client munge`, so it is not in the
/// default run: `cargo test -p sawdrive-cli --test sweep_shards -- --ignored slurm`.
#[test]
#[ignore = "needs root and a Slurm installation (apt-get install slurmd slurmctld slurm-client munge)"]
fn slurm_job_array_merges_to_the_unsharded_results() {
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scripts/slurm-selftest.sh"
    );
    let output = Command::new(script)
        .arg(env!("CARGO_BIN_EXE_sawdrive"))
        .output()
        .expect("the self-test script runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success() && stdout.contains("slurm self-test passed"),
        "Slurm array of 3 shards merged to the unsharded results: {stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
}
