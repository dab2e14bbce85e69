//! Studies over many runs: sweeps (`sawdrive sweep`), Monte Carlo UQ (`sawdrive uq`) and the
//! texture optimiser (`sawdrive design`), each calling the library function its command calls.
//!
//! Cancellation: a sweep stops before its next point after an interrupt (the points saved so
//! far are kept for a rerun; `results.csv` and the charts are not written). UQ and design have
//! no cancellation point in the library yet: after an interrupt they run to their end in the
//! background. A UQ's results folder is committed here, on the calling thread, so an
//! interrupted UQ commits nothing (its saved samples let a rerun resume); `run_design` still
//! commits its own folder, which then appears complete (never half-written).

use std::path::{Path, PathBuf};

use ::design::ModelFidelity as Fidelity;
use ::design::scatter::{ScatterSpec, load_uq_inputs};
use ::design::study::{DesignSpec, run_design};
use ::design::uq::{UqOptions, run_uq_staged};
use pyo3::prelude::*;
use sawdrive::pipeline::evaluate::SceneEvaluator;
use sawdrive::scene::Scene;
use sawdrive::sweep::{SweepFile, run_sweep};
use serde_json::json;

use crate::errors::{Failure, Kind};
use crate::worker::{self, PointCount};
use crate::{convert, raise};

/// `sawdrive sweep FILE --out OUT [--jobs N]`: the sweep's outcome (rows, failures, folder,
/// resumed, files) as a dict. Progress counts the saved points. An interrupt stops the sweep
/// before its next point.
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
    let outcome = worker::run(py, progress, Some(count), move |cancel| {
        Ok(serde_json::to_value(run_sweep(
            &sweep,
            &out,
            jobs,
            &cancel.control(),
        )?)?)
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

/// The scene and scatter of `sawdrive uq [SCENE] --set …`, read as the command reads them.
fn uq_inputs(path: Option<&str>, overrides: &[String]) -> Result<(Scene, ScatterSpec), Failure> {
    load_uq_inputs(&SceneEvaluator, path.map(Path::new), overrides).map_err(Failure::from)
}

/// `sawdrive uq [SCENE] --samples N --seed S --out OUT [--patch] --json`: the report as a dict
/// with `folder` (the results folder written, `OUT/<scene>-uq/`).
#[pyfunction]
#[pyo3(signature = (path, overrides, samples, seed, out, patch=false, progress=None))]
#[allow(clippy::too_many_arguments)] // the command's flags, one argument each
fn uq<'py>(
    py: Python<'py>,
    path: Option<&str>,
    overrides: Vec<String>,
    samples: usize,
    seed: u64,
    out: String,
    patch: bool,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let (scene, scatter) = raise(py, uq_inputs(path, &overrides))?;
    if let Err(e) = ::design::uq::check_samples(samples) {
        return Err(Failure::new(Kind::Argument, &e).into_pyerr(py));
    }
    let options = UqOptions {
        samples,
        seed,
        out_dir: PathBuf::from(out),
        fidelity: if patch {
            Fidelity::Patch
        } else {
            Fidelity::Slider
        },
        write_files: true,
    };
    // The folder is committed here, on the calling thread: an interrupted call commits nothing.
    let (mut value, staged) = worker::run(py, progress, None, move |_| {
        let (report, staged) = run_uq_staged(&SceneEvaluator, &scene, &scatter, &options)?;
        Ok((serde_json::to_value(&report)?, staged))
    })?;
    let folder = staged
        .commit()
        .map_err(|e| Failure::from(e).into_pyerr(py))?;
    value["folder"] = json!(folder.display().to_string());
    convert::to_py(py, &value)
}

/// `sawdrive design FILE --out OUT --json`: the report as a dict with `folder` (`OUT/<name>/`).
#[pyfunction]
#[pyo3(signature = (file, out, progress=None))]
fn design<'py>(
    py: Python<'py>,
    file: &str,
    out: String,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let spec = raise(
        py,
        DesignSpec::read(&SceneEvaluator, Path::new(file)).map_err(Failure::from),
    )?;
    let out = PathBuf::from(out);
    let value = worker::run(py, progress, None, move |_| {
        let (report, folder) = run_design(&SceneEvaluator, &spec, &out, true)?;
        let mut value = serde_json::to_value(&report)?;
        value["folder"] = json!(folder.display().to_string());
        Ok(value)
    })?;
    convert::to_py(py, &value)
}

/// Add the study functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_points, m)?)?;
    m.add_function(wrap_pyfunction!(uq, m)?)?;
    m.add_function(wrap_pyfunction!(self::design, m)?)?;
    Ok(())
}
