//! Running a sweep: every point through the pipeline in parallel, each result saved atomically
//! as `points/<hash>.json` so an interrupted sweep resumes where it stopped; then one CSV of all
//! points and the charts the sweep file asks for.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::{SweepFile, SweepPoint};
use crate::output::write_atomically;
use crate::pipeline::{RunOptions, fill_static_cache, run_pipeline};
use crate::scene::load_scene;

/// Numeric result columns a chart may use.
pub const NUMERIC_COLUMNS: [&str; 11] = [
    "preload_n",
    "post_count",
    "post_diameter_m",
    "mu_kinetic",
    "normal_amplitude_m",
    "effective_contact_ratio",
    "effective_post_count",
    "stall_thrust_n",
    "no_load_speed_m_per_s",
    "efficiency",
    "stick_fraction",
];

/// Most worker threads a sweep starts (`--jobs`). Every point is CPU-bound, so threads beyond the
/// cores only cost memory (a stack and a solver workspace each); the bound turns a typo such as
/// `--jobs 100000` into an error instead of a hundred thousand threads. Unit: threads.
pub const MAX_JOBS: usize = 256;

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

/// Why a sweep could not run (individual point failures are reported in [`SweepOutcome`]).
#[derive(Debug, thiserror::Error)]
pub enum SweepRunError {
    /// The sweep file.
    #[error(transparent)]
    File(#[from] super::SweepError),
    /// A chart names a column that does not exist.
    #[error("chart {which}: unknown column \"{column}\"; columns: {}", NUMERIC_COLUMNS.join(", "))]
    UnknownColumn {
        /// Which chart (1-based).
        which: usize,
        /// The name given.
        column: String,
    },
    /// The first point's scene does not load: every point would fail.
    #[error("sweep point {overrides}: {source}")]
    Scene {
        /// The overrides of the point.
        overrides: String,
        /// The scene error.
        source: crate::scene::SceneError,
    },
    /// Writing results.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// Charts.
    #[error(transparent)]
    Chart(#[from] charts::ChartError),
    /// More worker threads asked for than [`MAX_JOBS`], or none.
    #[error(
        "--jobs {jobs}: must be between 1 and {MAX_JOBS} worker threads (this machine has {cores} cores)"
    )]
    Jobs {
        /// Jobs asked for.
        jobs: usize,
        /// Cores available.
        cores: usize,
    },
    /// Thread pool.
    #[error("cannot start {jobs} worker threads: {message}")]
    Pool {
        /// Jobs asked for.
        jobs: usize,
        /// The error.
        message: String,
    },
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

fn run_point(
    sweep: &SweepFile,
    point: &SweepPoint,
    hash: &str,
    folder: &Path,
    cache: &Path,
) -> Result<PointRow, String> {
    let scene = load_scene(sweep.scene.as_deref(), &point.overrides).map_err(|e| e.to_string())?;
    let options = RunOptions {
        out_dir: folder.join("runs").join(hash),
        cache_dir: Some(cache.to_owned()),
        progress: false,
        write_files: false,
    };
    let (summary, _) = run_pipeline(&scene, &options).map_err(|e| e.to_string())?;
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

/// Run `sweep` into `out_dir/<sweep name>/` with `jobs` threads (None: all cores).
pub fn run_sweep(
    sweep: &SweepFile,
    out_dir: &Path,
    jobs: Option<usize>,
) -> Result<SweepOutcome, SweepRunError> {
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
        Some(path) => std::fs::read_to_string(path).unwrap_or_default(),
        None => crate::scene::DEFAULT_SCENE_TOML.to_owned(),
    };
    let folder = out_dir.join(&sweep.name);
    let points_dir = folder.join("points");
    std::fs::create_dir_all(&points_dir).map_err(crate::output::io("create", &points_dir))?;
    let cache = out_dir.join(".cache");

    let hashes: Vec<String> = points
        .iter()
        .map(|p| point_hash(&scene_text, p, CURRENT_MODELS))
        .collect();
    let done = |hash: &str| -> Option<PointRow> {
        let bytes = std::fs::read(points_dir.join(format!("{hash}.json"))).ok()?;
        let row: PointRow = serde_json::from_slice(&bytes).ok()?;
        (row.hash == hash).then_some(row)
    };
    let resumed = hashes.iter().filter(|h| done(h).is_some()).count();
    // One FEM condensation per distinct slider geometry, before the parallel points (which then
    // read their static reports from the cache).
    let pending_scenes: Vec<_> = points
        .iter()
        .zip(&hashes)
        .filter(|(_, h)| done(h).is_none())
        .filter_map(|(p, _)| load_scene(sweep.scene.as_deref(), &p.overrides).ok())
        .collect();
    let (_, _static_failures) = fill_static_cache(&pending_scenes, &cache);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .build()
        .map_err(|e| SweepRunError::Pool {
            jobs: jobs.unwrap_or(0),
            message: e.to_string(),
        })?;
    let results: Vec<Result<PointRow, (String, String)>> = pool.install(|| {
        points
            .par_iter()
            .zip(&hashes)
            .map(|(point, hash)| {
                if let Some(row) = done(hash) {
                    return Ok(row);
                }
                let row = run_point(sweep, point, hash, &folder, &cache)
                    .map_err(|e| (point.overrides.join(" "), e))?;
                let bytes = serde_json::to_vec_pretty(&row)
                    .map_err(|e| (point.overrides.join(" "), e.to_string()))?;
                write_atomically(&points_dir.join(format!("{hash}.json")), bytes)
                    .map_err(|e| (point.overrides.join(" "), e.to_string()))?;
                Ok(row)
            })
            .collect()
    });
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for r in results {
        match r {
            Ok(row) => rows.push(row),
            Err(f) => failures.push(f),
        }
    }
    let mut files = vec![folder.join("results.csv")];
    write_atomically(&files[0], results_csv(sweep, &rows))?;
    files.extend(write_charts(sweep, &rows, &folder)?);
    Ok(SweepOutcome {
        folder,
        rows,
        resumed,
        failures,
        files,
    })
}

/// All rows as CSV: variant, grid keys, numeric columns, wall time.
pub fn results_csv(sweep: &SweepFile, rows: &[PointRow]) -> String {
    let grid_keys: Vec<&String> = sweep.grid.keys().collect();
    let mut text = String::from("variant");
    for k in &grid_keys {
        text.push(',');
        text.push_str(k);
    }
    for c in NUMERIC_COLUMNS {
        text.push(',');
        text.push_str(c);
    }
    text.push_str(",wall_time_s\n");
    for row in rows {
        text.push_str(&row.variant.replace(',', ";"));
        for k in &grid_keys {
            text.push(',');
            text.push_str(
                &row.grid
                    .get(*k)
                    .cloned()
                    .unwrap_or_default()
                    .replace(',', ";"),
            );
        }
        for c in NUMERIC_COLUMNS {
            text.push_str(&format!(
                ",{}",
                row.values.get(c).copied().unwrap_or(f64::NAN)
            ));
        }
        text.push_str(&format!(",{}\n", row.wall_time_s));
    }
    text
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
            serde_json::to_vec(&row).unwrap(),
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
        let computed = run_sweep(&sweep, &out, Some(1)).unwrap().rows[0].clone();
        std::fs::remove_dir_all(out.join(&sweep.name)).unwrap();

        // A stale result (stall thrust 123 N) saved by a build with an older dynamic model.
        let older = ModelVersions {
            dynamic: CURRENT_MODELS.dynamic + 1,
            ..CURRENT_MODELS
        };
        save_point(&sweep, &out, older, stale_row(&computed));
        let outcome = run_sweep(&sweep, &out, Some(1)).unwrap();
        assert_eq!(outcome.resumed, 0, "stale point not resumed");
        assert_eq!(
            outcome.rows[0].values["stall_thrust_n"], computed.values["stall_thrust_n"],
            "stall thrust recomputed"
        );

        // The same file saved with the current versions is resumed (the check above can fail).
        std::fs::remove_dir_all(out.join(&sweep.name)).unwrap();
        save_point(&sweep, &out, CURRENT_MODELS, stale_row(&computed));
        let outcome = run_sweep(&sweep, &out, Some(1)).unwrap();
        assert_eq!(outcome.resumed, 1);
        assert_eq!(
            outcome.rows[0].values["stall_thrust_n"], 123.0,
            "saved stall thrust reused"
        );
    }

    #[test]
    fn jobs_beyond_the_bound_are_a_named_error_before_any_thread_starts() {
        let root = tempfile::tempdir().unwrap();
        let sweep = one_point_sweep(root.path());
        let out = root.path().join("out");
        for jobs in [0, MAX_JOBS + 1, 100_000] {
            let error = run_sweep(&sweep, &out, Some(jobs)).unwrap_err();
            assert!(
                matches!(error, SweepRunError::Jobs { jobs: j, .. } if j == jobs),
                "--jobs {jobs} refused: {error}"
            );
            assert!(error.to_string().contains(&format!("--jobs {jobs}")));
        }
        assert!(!out.exists(), "nothing written for refused --jobs");
    }
}
