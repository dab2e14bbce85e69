//! Running a sweep: every point through the pipeline in parallel, each result saved atomically
//! as `points/<hash>.json` so an interrupted sweep resumes where it stopped; then one CSV of all
//! points and the charts the sweep file asks for.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::error::{MAX_JOBS, NUMERIC_COLUMNS, SweepRunError};
use super::{SweepFile, SweepPoint};
use crate::output::{Saved, read_verified_json, to_verified_json, write_atomically};
use crate::pipeline::{Progress, RunControl, RunOptions, run_pipeline};
use crate::scene::load_scene;

/// Versions of the models whose numbers a saved sweep point holds. They are part of the point
/// hash, so a resumed sweep recomputes points saved before a physics change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ModelVersions {
    /// [`static_contact::params::MODEL_VERSION`] (η, post forces).
    static_contact: u32,
    /// [`crate::DYNAMIC_MODEL_VERSION`] (speed–thrust curve, stall thrust, efficiency).
    dynamic: u32,
}

/// The models this build computes with.
const CURRENT_MODELS: ModelVersions = ModelVersions {
    static_contact: static_contact::params::MODEL_VERSION,
    dynamic: crate::DYNAMIC_MODEL_VERSION,
};

/// One row of the results table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointRow {
    /// Content hash of the point (scene file + overrides).
    pub hash: String,
    /// Variant label.
    pub variant: String,
    /// Grid values as written.
    pub grid: BTreeMap<String, String>,
    /// Numeric results by column name ([`NUMERIC_COLUMNS`]).
    pub values: BTreeMap<String, f64>,
    /// Wall time of the point (s).
    pub wall_time_s: f64,
}

/// Outcome of a sweep.
#[derive(Debug, Clone, Serialize)]
pub struct SweepOutcome {
    /// Results folder.
    pub folder: PathBuf,
    /// All rows, in point order.
    pub rows: Vec<PointRow>,
    /// Points that were already done (resumed).
    pub resumed: usize,
    /// Points that failed: (overrides, error).
    pub failures: Vec<(String, String)>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// Content hash of a point: model versions, scene file text and overrides.
fn point_hash(scene_text: &str, point: &SweepPoint, models: ModelVersions) -> String {
    let mut hasher = Sha256::new();
    hasher.update(format!(
        "static-contact model {}, dynamic model {}\n",
        models.static_contact, models.dynamic
    ));
    hasher.update(scene_text.as_bytes());
    for o in &point.overrides {
        hasher.update(b"\n");
        hasher.update(o.as_bytes());
    }
    hasher
        .finalize()
        .iter()
        .take(12)
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Why a point gave no row.
enum PointFailure {
    /// The sweep was cancelled while the point ran (its stages stopped; nothing was saved).
    Cancelled,
    /// The point failed: the one-line error.
    Failed(String),
}

/// Run `point` through the pipeline, which stops inside its stages once `control` asks to.
fn run_point(
    sweep: &SweepFile,
    point: &SweepPoint,
    hash: &str,
    folder: &Path,
    cache: &Path,
    control: &RunControl,
) -> Result<PointRow, PointFailure> {
    let failed = |e: &dyn std::fmt::Display| PointFailure::Failed(e.to_string());
    let scene = load_scene(sweep.scene.as_deref(), &point.overrides).map_err(|e| failed(&e))?;
    let options = RunOptions {
        out_dir: folder.join("runs").join(hash),
        cache_dir: Some(cache.to_owned()),
        write_files: false,
    };
    let (summary, _) =
        run_pipeline(&scene, &options, control).map_err(|e| match e.is_cancelled() {
            true => PointFailure::Cancelled,
            false => failed(&e),
        })?;
    let values = BTreeMap::from([
        ("preload_n".to_owned(), scene.motor.load.preload_n),
        ("post_count".to_owned(), scene.motor.posts.count() as f64),
        ("post_diameter_m".to_owned(), scene.motor.posts.diameter_m),
        ("mu_kinetic".to_owned(), scene.motor.friction.mu_kinetic),
        (
            "normal_amplitude_m".to_owned(),
            scene.motor.wave.normal_amplitude_m,
        ),
        (
            "effective_contact_ratio".to_owned(),
            summary.effective_contact_ratio,
        ),
        (
            "effective_post_count".to_owned(),
            summary.effective_post_count,
        ),
        ("stall_thrust_n".to_owned(), summary.stall_thrust_n),
        (
            "no_load_speed_m_per_s".to_owned(),
            summary.no_load_speed_m_per_s,
        ),
        ("efficiency".to_owned(), summary.efficiency),
        ("stick_fraction".to_owned(), summary.stick_fraction),
    ]);
    Ok(PointRow {
        hash: hash.to_owned(),
        variant: point.variant.clone(),
        grid: point.grid_values.clone(),
        values,
        wall_time_s: summary.timings.total_s,
    })
}

/// A sweep ready to run or merge: its points, their content hashes and where results go.
pub(super) struct Prepared<'a> {
    /// The sweep file.
    pub(super) sweep: &'a SweepFile,
    /// Every point, in sweep order.
    pub(super) points: Vec<SweepPoint>,
    /// Content hash of each point (same order).
    pub(super) hashes: Vec<String>,
    /// `OUT/<sweep name>/`.
    pub(super) folder: PathBuf,
    /// `OUT/<sweep name>/points/`.
    pub(super) points_dir: PathBuf,
    /// The FEM cache, `OUT/.cache` (shared by every sweep and shard writing to OUT).
    pub(super) cache: PathBuf,
}

/// Check the sweep's charts, `--jobs` and first scene, and compute every point's hash. Writes
/// nothing.
pub(super) fn prepare<'a>(
    sweep: &'a SweepFile,
    out_dir: &Path,
    jobs: Option<usize>,
) -> Result<Prepared<'a>, SweepRunError> {
    for (i, chart) in sweep.charts.iter().enumerate() {
        for column in [&chart.x, &chart.y] {
            if !NUMERIC_COLUMNS.contains(&column.as_str()) {
                return Err(SweepRunError::UnknownColumn {
                    which: i + 1,
                    column: column.clone(),
                });
            }
        }
    }
    if let Some(jobs) = jobs.filter(|&j| j == 0 || j > MAX_JOBS) {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        return Err(SweepRunError::Jobs { jobs, cores });
    }
    let points = sweep.points();
    if let Some(first) = points.first() {
        load_scene(sweep.scene.as_deref(), &first.overrides).map_err(|source| {
            SweepRunError::Scene {
                overrides: first.overrides.join(" "),
                source,
            }
        })?;
    }
    let scene_text = match &sweep.scene {
        Some(path) => {
            crate::scene::read_scene_file(path).map_err(|source| SweepRunError::Scene {
                overrides: "(the scene file)".into(),
                source,
            })?
        }
        None => crate::scene::DEFAULT_SCENE_TOML.to_owned(),
    };
    let hashes = points
        .iter()
        .map(|p| point_hash(&scene_text, p, CURRENT_MODELS))
        .collect();
    let folder = out_dir.join(&sweep.name);
    Ok(Prepared {
        sweep,
        points,
        hashes,
        points_dir: folder.join("points"),
        folder,
        cache: out_dir.join(".cache"),
    })
}

impl Prepared<'_> {
    /// The file of point `i`'s saved result.
    fn point_file(&self, i: usize) -> PathBuf {
        self.points_dir.join(format!("{}.json", self.hashes[i]))
    }

    /// The saved result of point `i` (0-based), if its file exists, is intact (its checksum
    /// matches) and holds this point.
    pub(super) fn saved(&self, i: usize) -> Option<PointRow> {
        match read_verified_json::<PointRow>(&self.point_file(i)) {
            Saved::Valid(row) => (row.hash == self.hashes[i]).then_some(row),
            Saved::Missing | Saved::Altered(_) => None,
        }
    }

    /// A note for each selected point whose saved file exists but was altered: it is recomputed.
    fn note_altered(&self, selected: &[usize]) {
        for &i in selected {
            if let Saved::Altered(why) = read_verified_json::<PointRow>(&self.point_file(i)) {
                eprintln!(
                    "note: {} {why}: the point is recomputed",
                    self.point_file(i).display()
                );
            }
        }
    }

    /// Run the points `selected` (0-based, ascending) that are not saved yet with `jobs`
    /// threads, saving each as it finishes. The static cache is filled first, one FEM
    /// condensation per geometry across every process sharing the cache ([`super::locks`]);
    /// `rotation` staggers the order in which concurrent shards visit the geometries. A stop
    /// request of `control` starts no further geometry or point and returns
    /// [`SweepRunError::Cancelled`]; each finished point is reported as a count of `selected`.
    pub(super) fn run_points(
        &self,
        selected: &[usize],
        jobs: Option<usize>,
        rotation: usize,
        control: &RunControl,
    ) -> Result<PointsRun, SweepRunError> {
        std::fs::create_dir_all(&self.points_dir)
            .map_err(crate::output::io("create", &self.points_dir))?;
        self.note_altered(selected);
        let saved: Vec<Option<PointRow>> = selected.iter().map(|&i| self.saved(i)).collect();
        let resumed = saved.iter().filter(|s| s.is_some()).count();
        let condensations = self.fill_static_cache(selected, &saved, rotation, control)?;
        self.check_cancel(control)?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(jobs.unwrap_or(0))
            .build()
            .map_err(|e| SweepRunError::Pool {
                jobs: jobs.unwrap_or(0),
                message: e.to_string(),
            })?;
        // The points run side by side: their stage messages are not reported, their count is.
        let point_control = control.without_progress();
        let done = AtomicUsize::new(resumed);
        let total = selected.len();
        // `None`: skipped after a cancel.
        let results: Vec<Option<Result<PointRow, (String, String)>>> = pool.install(|| {
            selected
                .par_iter()
                .zip(saved)
                .map(|(&i, saved)| match saved {
                    Some(row) => Some(Ok(row)),
                    None if control.should_stop() => None,
                    None => {
                        let outcome = self.compute_and_save(i, &point_control);
                        if outcome.is_some() {
                            let done = done.fetch_add(1, Ordering::Relaxed) + 1;
                            control.report(Progress::Count { done, total });
                        }
                        outcome
                    }
                })
                .collect()
        });
        if results.iter().any(Option::is_none) {
            return Err(self.cancelled());
        }
        let mut run = PointsRun {
            rows: Vec::new(),
            resumed,
            failures: Vec::new(),
            condensations,
        };
        for r in results.into_iter().flatten() {
            match r {
                Ok(row) => run.rows.push(row),
                Err(f) => run.failures.push(f),
            }
        }
        Ok(run)
    }

    /// One FEM condensation per distinct slider geometry among the pending `selected` points,
    /// before the parallel points (which then read their static reports from the cache). The
    /// reports of every pending point of the sweep with such a geometry are filled, whichever
    /// shard owns the point, so that no other shard condenses that geometry again.
    fn fill_static_cache(
        &self,
        selected: &[usize],
        saved: &[Option<PointRow>],
        rotation: usize,
        control: &RunControl,
    ) -> Result<usize, SweepRunError> {
        let mine: Vec<usize> = selected
            .iter()
            .zip(saved)
            .filter(|(_, s)| s.is_none())
            .map(|(&i, _)| i)
            .collect();
        if mine.is_empty() {
            return Ok(0);
        }
        let scene = |i: usize| load_scene(self.sweep.scene.as_deref(), &self.points[i].overrides);
        let pending: Vec<(crate::scene::Scene, bool)> = (0..self.points.len())
            .filter(|i| mine.binary_search(i).is_ok() || self.saved(*i).is_none())
            .filter_map(|i| scene(i).ok().map(|s| (s, mine.binary_search(&i).is_ok())))
            .collect();
        super::locks::fill_static_cache_shared(&pending, &self.cache, rotation, control)
    }

    /// [`SweepRunError::Cancelled`] if `control` asks to stop.
    fn check_cancel(&self, control: &RunControl) -> Result<(), SweepRunError> {
        match control.should_stop() {
            true => Err(self.cancelled()),
            false => Ok(()),
        }
    }

    /// The cancellation error, counting the points saved now.
    fn cancelled(&self) -> SweepRunError {
        SweepRunError::Cancelled {
            sweep: self.sweep.name.clone(),
            folder: self.points_dir.clone(),
            saved: (0..self.points.len())
                .filter(|&i| self.saved(i).is_some())
                .count(),
            total: self.points.len(),
        }
    }

    /// Run point `i` through the pipeline and save its row atomically; `None` if `control`
    /// stopped it (nothing saved), else its row or (overrides, error).
    fn compute_and_save(
        &self,
        i: usize,
        control: &RunControl,
    ) -> Option<Result<PointRow, (String, String)>> {
        let (point, hash) = (&self.points[i], &self.hashes[i]);
        let failed = |e: String| (point.overrides.join(" "), e);
        let row = match run_point(self.sweep, point, hash, &self.folder, &self.cache, control) {
            Ok(row) => row,
            Err(PointFailure::Cancelled) => return None,
            Err(PointFailure::Failed(e)) => return Some(Err(failed(e))),
        };
        let saved = to_verified_json(&row)
            .map_err(|e| failed(e.to_string()))
            .and_then(|bytes| {
                write_atomically(&self.point_file(i), bytes).map_err(|e| failed(e.to_string()))
            });
        Some(saved.map(|()| row))
    }

    /// Write `results.csv` and the charts of `rows` (in point order); returns the files.
    pub(super) fn write_results(&self, rows: &[PointRow]) -> Result<Vec<PathBuf>, SweepRunError> {
        let mut files = vec![self.folder.join("results.csv")];
        write_atomically(&files[0], results_csv(self.sweep, rows))?;
        files.extend(write_charts(self.sweep, rows, &self.folder)?);
        Ok(files)
    }
}

/// What running some points of a sweep gave.
pub(super) struct PointsRun {
    /// Rows of the points that succeeded, in point order.
    pub(super) rows: Vec<PointRow>,
    /// Points that were already saved.
    pub(super) resumed: usize,
    /// Points that failed: (overrides, error).
    pub(super) failures: Vec<(String, String)>,
    /// FEM condensations this process ran.
    pub(super) condensations: usize,
}

/// Run `sweep` into `out_dir/<sweep name>/` with `jobs` threads (None: all cores). Stops when
/// `control` asks to: no point or FEM condensation starts after it, the running points stop
/// inside their stages and save nothing, and the sweep returns [`SweepRunError::Cancelled`]
/// without writing `results.csv` or the charts (`sweep::cancel`). Progress: the count of
/// points finished ([`crate::pipeline::Progress::Count`]).
pub fn run_sweep(
    sweep: &SweepFile,
    out_dir: &Path,
    jobs: Option<usize>,
    control: &RunControl,
) -> Result<SweepOutcome, SweepRunError> {
    let prepared = prepare(sweep, out_dir, jobs)?;
    let all: Vec<usize> = (0..prepared.points.len()).collect();
    let run = prepared.run_points(&all, jobs, 0, control)?;
    let files = prepared.write_results(&run.rows)?;
    Ok(SweepOutcome {
        folder: prepared.folder,
        rows: run.rows,
        resumed: run.resumed,
        failures: run.failures,
        files,
    })
}

/// All rows as CSV: variant, grid keys, numeric columns, wall time (RFC 4180, text cells
/// neutralised against spreadsheet formulas: [`crate::output::csv_table`]).
pub fn results_csv(sweep: &SweepFile, rows: &[PointRow]) -> String {
    use crate::output::{Cell, csv_table};
    let grid_keys: Vec<&String> = sweep.grid.keys().collect();
    let mut header = vec!["variant"];
    header.extend(grid_keys.iter().map(|k| k.as_str()));
    header.extend(NUMERIC_COLUMNS);
    header.push("wall_time_s");
    let cells = rows.iter().map(|row| {
        let mut cells = vec![Cell::Text(row.variant.clone())];
        cells.extend(
            grid_keys
                .iter()
                .map(|k| Cell::Text(row.grid.get(*k).cloned().unwrap_or_default())),
        );
        cells.extend(
            NUMERIC_COLUMNS
                .iter()
                .map(|c| Cell::Number(row.values.get(*c).copied().unwrap_or(f64::NAN))),
        );
        cells.push(Cell::Number(row.wall_time_s));
        cells
    });
    csv_table(&header, cells)
}

fn write_charts(
    sweep: &SweepFile,
    rows: &[PointRow],
    folder: &Path,
) -> Result<Vec<PathBuf>, SweepRunError> {
    let mut files = Vec::new();
    for spec in &sweep.charts {
        let mut series: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
        for row in rows {
            let key = match &spec.series {
                Some(k) => format!("{k} = {}", row.grid.get(k).cloned().unwrap_or_default()),
                None => row.variant.clone(),
            };
            if let (Some(x), Some(y)) = (row.values.get(&spec.x), row.values.get(&spec.y)) {
                series.entry(key).or_default().push((*x, *y));
            }
        }
        let title = spec
            .title
            .clone()
            .unwrap_or_else(|| format!("{} vs {}", spec.y, spec.x));
        let mut chart = charts::Chart::new(title, spec.x.as_str(), spec.y.as_str());
        // Keep the sweep's point order within a series (sorted by x for lines).
        for (name, mut points) in series {
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart.series.push(charts::Series::new(
                name,
                points,
                charts::Style::LineMarkers,
            ));
        }
        if chart.series.iter().all(|s| s.points.is_empty()) {
            continue;
        }
        let stem = spec
            .file
            .clone()
            .unwrap_or_else(|| format!("{}_vs_{}", spec.y, spec.x));
        files.extend(charts::write_chart(&chart, &folder.join(stem))?);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-point sweep of the small scene with η given (dynamic stage only: fast).
    fn one_point_sweep(dir: &Path) -> SweepFile {
        let scene = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/scenes/small-strip.toml"
        );
        let path = dir.join("sweep.toml");
        let text = format!(
            "name = \"versions\"\nscene = \"{scene}\"\n[set]\neffective_ratio = 0.36\n[grid]\npreload = [\"0.4 N\"]\n"
        );
        std::fs::write(&path, text).unwrap();
        SweepFile::load(&path).unwrap()
    }

    /// Save `row` as the point of `sweep` under the hash computed with `models`.
    fn save_point(sweep: &SweepFile, out: &Path, models: ModelVersions, mut row: PointRow) {
        let scene_text = std::fs::read_to_string(sweep.scene.as_ref().unwrap()).unwrap();
        row.hash = point_hash(&scene_text, &sweep.points()[0], models);
        let dir = out.join(&sweep.name).join("points");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join(format!("{}.json", row.hash)),
            crate::output::to_verified_json(&row).unwrap(),
        )
        .unwrap();
    }

    fn stale_row(computed: &PointRow) -> PointRow {
        let mut row = computed.clone();
        row.values.insert("stall_thrust_n".into(), 123.0);
        row
    }

    #[test]
    fn point_hash_changes_with_either_model_version() {
        let point = SweepPoint {
            variant: String::new(),
            grid_values: BTreeMap::new(),
            overrides: vec!["preload=1N".into()],
        };
        let hash = |static_contact, dynamic| {
            point_hash(
                "scene",
                &point,
                ModelVersions {
                    static_contact,
                    dynamic,
                },
            )
        };
        assert_ne!(hash(1, 1), hash(2, 1), "static model version in the hash");
        assert_ne!(hash(1, 1), hash(1, 2), "dynamic model version in the hash");
    }

    #[test]
    fn point_saved_with_another_model_version_is_recomputed() {
        let root = tempfile::tempdir().unwrap();
        let sweep = one_point_sweep(root.path());
        let out = root.path().join("out");
        let computed = run_sweep(&sweep, &out, Some(1), &RunControl::none())
            .unwrap()
            .rows[0]
            .clone();
        std::fs::remove_dir_all(out.join(&sweep.name)).unwrap();

        // A stale result (stall thrust 123 N) saved by a build with an older dynamic model.
        let older = ModelVersions {
            dynamic: CURRENT_MODELS.dynamic + 1,
            ..CURRENT_MODELS
        };
        save_point(&sweep, &out, older, stale_row(&computed));
        let outcome = run_sweep(&sweep, &out, Some(1), &RunControl::none()).unwrap();
        assert_eq!(outcome.resumed, 0, "stale point not resumed");
        assert_eq!(
            outcome.rows[0].values["stall_thrust_n"], computed.values["stall_thrust_n"],
            "stall thrust recomputed"
        );

        // The same file saved with the current versions is resumed (the check above can fail).
        std::fs::remove_dir_all(out.join(&sweep.name)).unwrap();
        save_point(&sweep, &out, CURRENT_MODELS, stale_row(&computed));
        let outcome = run_sweep(&sweep, &out, Some(1), &RunControl::none()).unwrap();
        assert_eq!(outcome.resumed, 1);
        assert_eq!(
            outcome.rows[0].values["stall_thrust_n"], 123.0,
            "saved stall thrust reused"
        );
    }

    #[test]
    fn an_edited_or_emptied_point_file_is_recomputed_not_merged() {
        let root = tempfile::tempdir().unwrap();
        let sweep = one_point_sweep(root.path());
        let out = root.path().join("out");
        let computed = run_sweep(&sweep, &out, Some(1), &RunControl::none())
            .unwrap()
            .rows[0]
            .clone();
        let file = out
            .join(&sweep.name)
            .join("points")
            .join(format!("{}.json", computed.hash));
        let text = std::fs::read_to_string(&file).unwrap();
        let stall = computed.values["stall_thrust_n"].to_string();
        assert!(
            text.contains(&stall),
            "the saved file holds the stall thrust"
        );
        for edited in [
            text.replace(&stall, "123.0"),
            text.replace("\"values\"", "\"valeus\""),
            String::new(),
        ] {
            std::fs::write(&file, edited).unwrap();
            let outcome = run_sweep(&sweep, &out, Some(1), &RunControl::none()).unwrap();
            assert_eq!(outcome.resumed, 0, "an altered point is not resumed");
            assert_eq!(outcome.rows[0].values, computed.values, "it is recomputed");
        }
        let outcome = run_sweep(&sweep, &out, Some(1), &RunControl::none()).unwrap();
        assert_eq!(
            outcome.resumed, 1,
            "the recomputed point is saved intact again"
        );
    }

    #[test]
    fn a_cancelled_sweep_runs_no_point_writes_no_results_and_a_rerun_completes() {
        let root = tempfile::tempdir().unwrap();
        let sweep = one_point_sweep(root.path());
        let out = root.path().join("out");
        let stopped = RunControl::none().with_stop(|| true);
        let error = run_sweep(&sweep, &out, Some(1), &stopped).unwrap_err();
        assert!(
            matches!(
                error,
                SweepRunError::Cancelled {
                    saved: 0,
                    total: 1,
                    ..
                }
            ),
            "cancelled before any point: {error}"
        );
        assert!(error.to_string().contains("rerun to resume"), "{error}");
        let folder = out.join(&sweep.name);
        assert!(
            !folder.join("results.csv").exists(),
            "no results table after a cancel"
        );
        let points = std::fs::read_dir(folder.join("points")).unwrap().count();
        assert_eq!(points, 0, "no point saved after a cancel before the start");
        let outcome = run_sweep(&sweep, &out, Some(1), &RunControl::none()).unwrap();
        assert_eq!(
            (outcome.rows.len(), outcome.resumed),
            (1, 0),
            "the rerun runs the point"
        );
        assert!(folder.join("results.csv").exists(), "and writes the table");
    }

    #[test]
    fn jobs_beyond_the_bound_are_a_named_error_before_any_thread_starts() {
        let root = tempfile::tempdir().unwrap();
        let sweep = one_point_sweep(root.path());
        let out = root.path().join("out");
        for jobs in [0, MAX_JOBS + 1, 100_000] {
            let error = run_sweep(&sweep, &out, Some(jobs), &RunControl::none()).unwrap_err();
            assert!(
                matches!(error, SweepRunError::Jobs { jobs: j, .. } if j == jobs),
                "--jobs {jobs} refused: {error}"
            );
            assert!(error.to_string().contains(&format!("--jobs {jobs}")));
        }
        assert!(!out.exists(), "nothing written for refused --jobs");
    }

    #[test]
    fn messages_count_cores_in_english_and_blame_the_file_system_only_when_it_cannot_lock() {
        let one = SweepRunError::Jobs { jobs: 0, cores: 1 }.to_string();
        assert!(one.ends_with("has 1 core)"), "{one}");
        let two = SweepRunError::Jobs { jobs: 0, cores: 2 }.to_string();
        assert!(two.ends_with("has 2 cores)"), "{two}");
        let lock = |source: std::io::Error| {
            SweepRunError::Lock {
                path: "OUT/.cache/locks/x".into(),
                source,
            }
            .to_string()
        };
        let folder = lock(std::io::Error::from(std::io::ErrorKind::IsADirectory));
        assert!(
            !folder.contains("file system"),
            "a folder is not the file system's fault: {folder}"
        );
        let unsupported = lock(std::io::Error::from_raw_os_error(37));
        assert!(
            unsupported.contains("file system with file locks"),
            "{unsupported}"
        );
    }
}
