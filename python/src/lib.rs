//! `sawdrive._native`: the Python extension module behind the `sawdrive` package.
//!
//! Each function wraps one high-level call of the `sawdrive` library (the same calls the
//! command line makes, in the same order) and returns its serde-serialised result as Python
//! dicts and lists ([`convert::to_py`]: every f64 crosses as itself, bit for bit). The typed
//! Python API (`sawdrive/__init__.py`) is built on these dictionaries, so a field added or
//! renamed inside the library reaches Python without a change here.
//!
//! A scene crosses as `(path, overrides)`: the optional scene file and the `key=value`
//! overrides of `--set`, resolved by [`sawdrive::scene::load_scene`] on every call.

mod convert;
mod errors;
mod worker;

use std::path::{Path, PathBuf};
use std::time::Instant;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use sawdrive::output::StagedDir;
use sawdrive::pipeline::{
    RunOptions, run_dynamic, run_pipeline, run_static, scene_springs, write_dynamic_files,
    write_static_files,
};
use sawdrive::scene::{DEFAULT_SCENE_TOML, Scene, load_scene};
use sawdrive::sweep::{SweepFile, run_sweep};
use serde_json::json;

use errors::{Failure, Kind};
use worker::PointCount;

/// The scene of `path` (default scene if `None`) with `overrides`.
fn scene(path: Option<&str>, overrides: &[String]) -> Result<Scene, Failure> {
    Ok(load_scene(path.map(Path::new), overrides)?)
}

/// Raise `failure` as its Python exception.
fn raise<T>(py: Python<'_>, result: Result<T, Failure>) -> PyResult<T> {
    result.map_err(|f| f.into_pyerr(py))
}

/// The embedded default scene as TOML (what `sawdrive scene` prints).
#[pyfunction]
fn default_scene_toml() -> &'static str {
    DEFAULT_SCENE_TOML
}

/// `value` serialised and converted to Python objects.
fn py_value<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let value = raise(py, serde_json::to_value(value).map_err(Failure::from))?;
    convert::to_py(py, &value)
}

/// The scene resolved to SI as a dict (`sawdrive scene --resolve --json`).
#[pyfunction]
fn resolve_scene<'py>(
    py: Python<'py>,
    path: Option<&str>,
    overrides: Vec<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = raise(py, scene(path, &overrides))?;
    py_value(py, &scene)
}

/// The scene resolved to SI as TOML (`sawdrive scene --resolve`).
#[pyfunction]
fn scene_toml(py: Python<'_>, path: Option<&str>, overrides: Vec<String>) -> PyResult<String> {
    let text = scene(path, &overrides).and_then(|s| {
        toml::to_string_pretty(&s).map_err(|e| {
            Failure::text(
                Kind::Pipeline,
                format!("formatting the resolved scene: {e}"),
            )
        })
    });
    raise(py, text)
}

/// The four Johnson springs of one post of the scene (SI), as a dict.
#[pyfunction]
fn scene_post_springs<'py>(
    py: Python<'py>,
    path: Option<&str>,
    overrides: Vec<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let springs = scene(path, &overrides).and_then(|s| {
        scene_springs(&s)
            .map_err(|e| Failure::new(Kind::Pipeline, &sawdrive::pipeline::PipelineError::from(e)))
    });
    py_value(py, &raise(py, springs)?)
}

/// `sawdrive springs --diameter D --slider S --stator T --json`, as a dict.
#[pyfunction]
fn post_springs<'py>(
    py: Python<'py>,
    diameter: &str,
    slider: &str,
    stator: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let springs = raise(py, springs_of_diameter(diameter, slider, stator))?;
    py_value(py, &springs)
}

fn springs_of_diameter(
    diameter: &str,
    slider: &str,
    stator: &str,
) -> Result<contact_springs::PostSprings, Failure> {
    use contact_springs::Material;
    use sawdrive::units::{Dimension, parse_quantity};
    let argument = |message: String| Failure::text(Kind::Argument, message);
    let diameter_m = parse_quantity(diameter, Dimension::Length)
        .map_err(|e| argument(format!("--diameter: {}", errors::one_line(&e))))?;
    if diameter_m <= 0.0 {
        return Err(argument(format!("--diameter {diameter}: must be > 0")));
    }
    let material = |flag: &str, name: &str| {
        Material::named(name).ok_or_else(|| {
            argument(format!(
                "--{flag} {name}: unknown material, use si or linbo3"
            ))
        })
    };
    let (slider, stator) = (material("slider", slider)?, material("stator", stator)?);
    contact_springs::post_springs(&slider, &stator, 0.5 * diameter_m)
        .map_err(|e| argument(format!("--diameter: {}", errors::one_line(&e))))
}

/// Where results and the FEM cache go: `out` (None: no results folder) and `cache` (None: none).
fn folders(out: Option<String>, cache: Option<String>) -> (Option<PathBuf>, Option<PathBuf>) {
    (out.map(PathBuf::from), cache.map(PathBuf::from))
}

/// Commit a staged results folder (on the calling thread: an interrupted call never commits).
fn commit(staged: Option<StagedDir>) -> Result<Option<String>, Failure> {
    Ok(match staged {
        Some(s) => Some(s.commit()?.display().to_string()),
        None => None,
    })
}

/// `sawdrive static`: post forces and η, as a dict `{report, effective_ratio, content_hash,
/// cached, notes, folder}`; with `out`, writes `out/<scene>/static/` like the command.
#[pyfunction]
#[pyo3(signature = (path, overrides, out=None, cache=None, progress=None))]
fn static_stage<'py>(
    py: Python<'py>,
    path: Option<&str>,
    overrides: Vec<String>,
    out: Option<String>,
    cache: Option<String>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = raise(py, scene(path, &overrides))?;
    let (out, cache) = folders(out, cache);
    let (mut value, staged) = worker::run(py, progress, None, move || {
        let springs = scene_springs(&scene)?;
        let outcome = run_static(&scene, &springs, cache.as_deref(), out.is_some())?;
        let staged = match &out {
            Some(out) => {
                let staged = StagedDir::create(&out.join(&scene.name).join("static"))?;
                write_static_files(&outcome, staged.path())?;
                Some(staged)
            }
            None => None,
        };
        let value = json!({
            "report": outcome.report,
            "effective_ratio": outcome.effective_ratio,
            "content_hash": outcome.content_hash,
            "cached": outcome.cached,
            "notes": outcome.notes,
        });
        Ok((value, staged))
    })?;
    value["folder"] = json!(raise(py, commit(staged))?);
    convert::to_py(py, &value)
}

/// η of `scene`: given, or from the static stage (as `sawdrive dynamic` does).
fn scene_eta(scene: &Scene, cache: Option<&Path>) -> Result<(f64, &'static str), Failure> {
    if let Some(eta) = scene.contact.effective_ratio {
        return Ok((eta, "given"));
    }
    let outcome = run_static(scene, &scene_springs(scene)?, cache, false)?;
    let eta = outcome.effective_ratio.ok_or_else(|| {
        Failure::text(
            Kind::Pipeline,
            "the static stage could not identify η: give --set effective_ratio=0.36",
        )
    })?;
    Ok((eta, "fem"))
}

/// `sawdrive dynamic`, as a dict `{result, effective_ratio, effective_ratio_source, folder,
/// curve}`: `result` is what `sawdrive dynamic --json` prints without its `curve`, which comes
/// as f64 bytes ([`convert::curve_columns`]); with `out`, writes `out/<scene>/dynamic/`.
#[pyfunction]
#[pyo3(signature = (path, overrides, out=None, cache=None, progress=None))]
fn dynamic_stage<'py>(
    py: Python<'py>,
    path: Option<&str>,
    overrides: Vec<String>,
    out: Option<String>,
    cache: Option<String>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = raise(py, scene(path, &overrides))?;
    // η given and nothing to write: no FEM, no charts; the stage runs on this thread.
    let inline = out.is_none() && scene.contact.effective_ratio.is_some();
    let (out, cache) = folders(out, cache);
    let job = move || {
        let (eta, source) = scene_eta(&scene, cache.as_deref())?;
        let springs = scene_springs(&scene).map_err(|e| {
            Failure::new(Kind::Pipeline, &sawdrive::pipeline::PipelineError::from(e))
        })?;
        let mut run = run_dynamic(&scene, &springs, eta)?;
        let staged = match &out {
            Some(out) => {
                let staged = StagedDir::create(&out.join(&scene.name).join("dynamic"))?;
                write_dynamic_files(&scene.name, &run, staged.path())?;
                Some(staged)
            }
            None => None,
        };
        let curve = std::mem::take(&mut run.result.curve);
        let value = json!({
            "result": run.result,
            "effective_ratio": eta,
            "effective_ratio_source": source,
        });
        Ok((value, curve, staged))
    };
    let (value, curve, staged) = if inline {
        worker::run_inline(py, job)?
    } else {
        worker::run(py, progress, None, job)?
    };
    let folder = raise(py, commit(staged))?;
    let dict = convert::to_py(py, &value)?;
    dict.set_item("folder", folder)?;
    dict.set_item("curve", convert::curve_columns(py, &curve))?;
    dict.set_item("curve_columns", convert::CURVE_COLUMNS.to_vec())?;
    Ok(dict)
}

/// `sawdrive run`, as a dict `{summary, folder, curve}` (`summary` is `summary.json` without
/// its curve, `curve` as for [`dynamic_stage`]). With `out`, the results replace `out/<scene>/` only when every
/// stage succeeded and the call was not interrupted; without, they are computed in a temporary
/// folder and discarded.
#[pyfunction]
#[pyo3(signature = (path, overrides, out=None, cache=None, progress=None))]
fn run<'py>(
    py: Python<'py>,
    path: Option<&str>,
    overrides: Vec<String>,
    out: Option<String>,
    cache: Option<String>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = raise(py, scene(path, &overrides))?;
    let (out, cache) = folders(out, cache);
    let scratch = raise(py, scratch_folder(out.as_deref()))?;
    let name = scene.name.clone();
    let options = RunOptions {
        out_dir: scratch.path().to_owned(),
        cache_dir: cache,
        progress: false,
        write_files: true,
    };
    let (summary, curve, scratch) = worker::run(py, progress, None, move || {
        let (mut summary, _) = run_pipeline(&scene, &options)?;
        let curve = std::mem::take(&mut summary.curve);
        Ok((serde_json::to_value(&summary)?, curve, scratch))
    })?;
    let folder = match &out {
        Some(out) => Some(raise(
            py,
            publish(&scratch.path().join(&name), &out.join(&name)),
        )?),
        None => None,
    };
    let dict = PyDict::new(py);
    dict.set_item("summary", convert::to_py(py, &summary)?)?;
    dict.set_item("folder", folder)?;
    dict.set_item("curve", convert::curve_columns(py, &curve))?;
    dict.set_item("curve_columns", convert::CURVE_COLUMNS.to_vec())?;
    Ok(dict.into_any())
}

/// A hidden temporary folder inside `out` (same file system, so the results move by rename),
/// or in the system's temporary folder without `out`. Removed when dropped.
fn scratch_folder(out: Option<&Path>) -> Result<tempfile::TempDir, Failure> {
    let io = |e: std::io::Error, what: &Path| {
        Failure::text(
            Kind::Pipeline,
            format!("cannot create a scratch folder in {}: {e}", what.display()),
        )
    };
    match out {
        Some(out) => {
            std::fs::create_dir_all(out).map_err(|e| io(e, out))?;
            tempfile::Builder::new()
                .prefix(".sawdrive-python-")
                .tempdir_in(out)
                .map_err(|e| io(e, out))
        }
        None => tempfile::Builder::new()
            .prefix("sawdrive-python-")
            .tempdir()
            .map_err(|e| io(e, &std::env::temp_dir())),
    }
}

/// Move the finished results folder `from` over `destination` with the library's staged swap.
fn publish(from: &Path, destination: &Path) -> Result<String, Failure> {
    let staged = StagedDir::create(destination)?;
    let move_in =
        std::fs::remove_dir(staged.path()).and_then(|()| std::fs::rename(from, staged.path()));
    move_in.map_err(|e| {
        Failure::text(
            Kind::Pipeline,
            format!(
                "cannot move the results into {}: {e}",
                destination.display()
            ),
        )
    })?;
    Ok(staged.commit()?.display().to_string())
}

/// `sawdrive sweep FILE --out OUT [--jobs N]`: the sweep's outcome (rows, failures, folder,
/// resumed, files) as a dict. Progress counts the saved points.
#[pyfunction]
#[pyo3(signature = (file, out, jobs=None, progress=None))]
fn sweep<'py>(
    py: Python<'py>,
    file: &str,
    out: String,
    jobs: Option<usize>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let sweep = raise(py, SweepFile::load(Path::new(file)).map_err(Failure::from))?;
    let out = PathBuf::from(out);
    let count = PointCount {
        folder: out.join(&sweep.name).join("points"),
        total: sweep.points().len(),
    };
    let outcome = worker::run(py, progress, Some(count), move || {
        Ok(serde_json::to_value(run_sweep(&sweep, &out, jobs)?)?)
    })?;
    convert::to_py(py, &outcome)
}

/// The points of a sweep file: `[{variant, grid, overrides}]`.
#[pyfunction]
fn sweep_points<'py>(py: Python<'py>, file: &str) -> PyResult<Bound<'py, PyAny>> {
    let sweep = raise(py, SweepFile::load(Path::new(file)).map_err(Failure::from))?;
    let points: Vec<_> = sweep
        .points()
        .into_iter()
        .map(|p| json!({"variant": p.variant, "grid": p.grid_values, "overrides": p.overrides}))
        .collect();
    convert::to_py(py, &serde_json::Value::from(points))
}

/// Benchmark baseline: the wall time (s) of `repeats` calls of the dynamic stage made from Rust
/// (load the scene, springs, dynamic model: the work `sawdrive.dynamic` asks for, without the
/// Python layer). The scene must give η (the benchmark is about the call, not the FEM).
#[pyfunction]
fn time_rust_dynamic(
    py: Python<'_>,
    path: Option<&str>,
    overrides: Vec<String>,
    repeats: usize,
) -> PyResult<Vec<f64>> {
    let timed = py.detach(|| -> Result<Vec<f64>, Failure> {
        let mut times = Vec::with_capacity(repeats);
        for _ in 0..repeats {
            let start = Instant::now();
            let scene = scene(path, &overrides)?;
            let eta = scene.contact.effective_ratio.ok_or_else(|| {
                Failure::text(
                    Kind::Argument,
                    "the benchmark needs a given η: set effective_ratio",
                )
            })?;
            let springs = scene_springs(&scene).map_err(|e| {
                Failure::new(Kind::Pipeline, &sawdrive::pipeline::PipelineError::from(e))
            })?;
            let run = run_dynamic(&scene, &springs, eta)?;
            std::hint::black_box(&run.result);
            times.push(start.elapsed().as_secs_f64());
        }
        Ok(times)
    });
    raise(py, timed)
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(default_scene_toml, m)?)?;
    m.add_function(wrap_pyfunction!(resolve_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene_toml, m)?)?;
    m.add_function(wrap_pyfunction!(scene_post_springs, m)?)?;
    m.add_function(wrap_pyfunction!(post_springs, m)?)?;
    m.add_function(wrap_pyfunction!(static_stage, m)?)?;
    m.add_function(wrap_pyfunction!(dynamic_stage, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_points, m)?)?;
    m.add_function(wrap_pyfunction!(time_rust_dynamic, m)?)?;
    m.add("DYNAMIC_MODEL_VERSION", sawdrive::DYNAMIC_MODEL_VERSION)?;
    Ok(())
}
