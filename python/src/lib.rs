//! `sawdrive._native`: the Python extension module behind the `sawdrive` package.
//!
//! Each function wraps one high-level call of the `sawdrive` library (the same calls the
//! command line makes, in the same order) and returns its serde-serialised result as Python
//! dicts and lists ([`convert::to_py`]: every f64 crosses as itself, bit for bit). The typed
//! Python API (`sawdrive/__init__.py`) is built on these dictionaries, so a field added or
//! renamed inside the library reaches Python without a change here.
//!
//! A scene crosses as a [`NativeScene`]: the optional scene file and the `key=value` overrides
//! of `--set`, resolved by [`sawdrive::scene::load_scene`] once, when the Python scene is built
//! or changed (so a stage call does not parse TOML again).
//!
//! Results with a curve come back as native objects ([`outcome::DynamicResult`],
//! [`outcome::RunResult`]), converted to Python objects only when their fields are read.

mod convert;
mod errors;
mod outcome;
mod studies;
mod worker;

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};
use std::time::Instant;

use pyo3::prelude::*;
use sawdrive::output::{ResultKind, StagedDir};
use sawdrive::pipeline::{
    RunControl, RunOptions, StaticOutcome, effective_ratio, run_dynamic_stage, run_pipeline,
    run_static, scene_springs, write_dynamic_stage_files, write_static_files,
};
use sawdrive::scene::{DEFAULT_SCENE_TOML, Scene, load_scene};
use sawdrive::sweep::Cancel;
use serde_json::json;

use errors::{Failure, Kind};
use outcome::{DynamicResult, Fields, Outcome, RunResult};

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

/// A scene resolved to SI: the default scene or a scene file, with `--set` overrides. Built
/// once; stages take it without reading or parsing anything again.
#[pyclass(frozen, module = "sawdrive._native")]
#[derive(Debug)]
struct NativeScene {
    scene: Arc<Scene>,
    /// [`quick_dynamic`] of the scene, computed on the first dynamic call.
    quick_dynamic: OnceLock<bool>,
}

#[pymethods]
impl NativeScene {
    /// Load `path` (default scene if `None`) with `overrides` (`key=value`); raises the
    /// command line's error naming the key or file.
    #[new]
    fn new(py: Python<'_>, path: Option<&str>, overrides: Vec<String>) -> PyResult<Self> {
        let scene = raise(py, scene(path, &overrides))?;
        Ok(Self {
            scene: Arc::new(scene),
            quick_dynamic: OnceLock::new(),
        })
    }

    /// The scene's name (`OUT/<name>/`).
    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }

    /// The resolved scene as a dict (`sawdrive scene --resolve --json`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py_value(py, self.scene.as_ref())
    }

    /// The resolved scene as TOML (`sawdrive scene --resolve`).
    fn to_toml(&self, py: Python<'_>) -> PyResult<String> {
        let text = toml::to_string_pretty(self.scene.as_ref()).map_err(|e| {
            Failure::text(
                Kind::Pipeline,
                format!("formatting the resolved scene: {e}"),
            )
        });
        raise(py, text)
    }

    /// The four Johnson springs of one post of the scene (SI), as a dict.
    fn post_springs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let springs = raise(py, springs_of(&self.scene))?;
        py_value(py, &springs)
    }
}

/// The post springs of `scene`, failing as the pipeline does.
fn springs_of(scene: &Scene) -> Result<contact_springs::PostSprings, Failure> {
    scene_springs(scene)
        .map_err(|e| Failure::new(Kind::Pipeline, &sawdrive::pipeline::PipelineError::from(e)))
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
/// cached, notes, folder}`; with `out`, writes `out/<scene>/static/` like the command. After an
/// interrupt the strip stops before its next contact solve (an FEM factorisation or the whole
/// slider's solve already running finishes first) and writes nothing.
#[pyfunction]
#[pyo3(signature = (scene, out=None, cache=None, progress=None))]
fn static_stage<'py>(
    py: Python<'py>,
    scene: &Bound<'py, NativeScene>,
    out: Option<String>,
    cache: Option<String>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = Arc::clone(&scene.get().scene);
    let (out, cache) = folders(out, cache);
    let (mut value, staged) = worker::run(py, progress, None, move |cancel| {
        let springs = springs_of(&scene)?;
        let control = cancel.control();
        let outcome = run_static(&scene, &springs, cache.as_deref(), out.is_some(), &control)?;
        worker::check(cancel)?;
        let staged = match &out {
            Some(out) => {
                let staged =
                    StagedDir::create(&out.join(&scene.name).join("static"), ResultKind::Static)?;
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

/// η of `scene` with where it came from, and the static stage's outcome when it ran: the
/// library's one branch ([`effective_ratio`], as `sawdrive run` and `sawdrive dynamic` take it).
fn scene_eta(
    scene: &Scene,
    springs: &contact_springs::PostSprings,
    cache: Option<&Path>,
    control: &RunControl,
) -> Result<(f64, &'static str, Option<StaticOutcome>), Failure> {
    let eta = effective_ratio(scene, springs, cache, false, control)?;
    Ok((eta.value, eta.source, eta.statics))
}

/// Whether the dynamic stage of `scene` is the period average with η given: milliseconds, run
/// on the calling thread (a transient, or a stage that needs the FEM, goes to a worker thread
/// so that Ctrl-C interrupts it at once). A scene the model refuses goes to the worker, which
/// reports the error.
fn quick_dynamic(scene: &Scene) -> bool {
    let Some(eta) = scene.contact.effective_ratio else {
        return false;
    };
    springs_of(scene)
        .ok()
        .and_then(|springs| sawdrive::pipeline::dynamic_scene(scene, &springs, eta).ok())
        .and_then(|dynamic| dynamic.resolve_model().ok())
        .is_some_and(|(kind, _)| kind == stick_slip::ModelKind::PeriodicAverage)
}

/// `sawdrive dynamic`: a [`DynamicResult`] whose fields are what `sawdrive dynamic --json` prints
/// (without its curve) plus `effective_ratio`, `effective_ratio_source` and `folder`; with
/// `out`, writes `out/<scene>/dynamic/`. An interrupt stops the static stage before its next
/// contact solve and the dynamic stage before its next curve point (transient run), and writes
/// nothing.
#[pyfunction]
#[pyo3(signature = (scene, out=None, cache=None, progress=None))]
fn dynamic_stage<'py>(
    py: Python<'py>,
    scene: &Bound<'py, NativeScene>,
    out: Option<String>,
    cache: Option<String>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<DynamicResult> {
    let native = scene.get();
    let scene = Arc::clone(&native.scene);
    // Nothing to write and a period average with η given: the stage runs on this thread.
    let inline = out.is_none() && *native.quick_dynamic.get_or_init(|| quick_dynamic(&scene));
    let (out, cache) = folders(out, cache);
    let job = move |cancel: &Cancel| {
        let control = cancel.control();
        let springs = springs_of(&scene)?;
        let (eta, source, statics) = scene_eta(&scene, &springs, cache.as_deref(), &control)?;
        let stage = run_dynamic_stage(
            &scene,
            &springs,
            eta,
            statics.as_ref(),
            cache.as_deref(),
            &control,
        )?;
        worker::check(cancel)?;
        let staged = match &out {
            Some(out) => {
                let staged =
                    StagedDir::create(&out.join(&scene.name).join("dynamic"), ResultKind::Dynamic)?;
                write_dynamic_stage_files(&scene.name, &stage, staged.path())?;
                Some(staged)
            }
            None => None,
        };
        let (fields, curve) = Fields::of_stage(stage, eta, source);
        Ok((fields, curve, staged))
    };
    let (fields, curve, staged) = if inline {
        worker::run_inline(py, || job(&Cancel::new()))?
    } else {
        worker::run(py, progress, None, job)?
    };
    let folder = raise(py, commit(staged))?;
    Ok(DynamicResult(Outcome::new(fields, folder, curve)))
}

/// `sawdrive run`: a [`RunResult`] whose fields are `summary.json` without its curve, plus
/// `folder`. With `out`, the results replace `out/<scene>/` only when every stage succeeded and
/// the call was not interrupted; without, they are computed in a temporary folder and
/// discarded. After an interrupt the pipeline stops before its next contact solve or curve
/// point (an FEM factorisation already running finishes first) and its results are removed.
#[pyfunction]
#[pyo3(signature = (scene, out=None, cache=None, progress=None))]
fn run<'py>(
    py: Python<'py>,
    scene: &Bound<'py, NativeScene>,
    out: Option<String>,
    cache: Option<String>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<RunResult> {
    let scene = Arc::clone(&scene.get().scene);
    let (out, cache) = folders(out, cache);
    let scratch = raise(py, scratch_folder(out.as_deref()))?;
    let name = scene.name.clone();
    let options = RunOptions {
        out_dir: scratch.path().to_owned(),
        cache_dir: cache,
        write_files: true,
    };
    let (summary, curve, scratch) = worker::run(py, progress, None, move |cancel| {
        let (mut summary, _) = run_pipeline(&scene, &options, &cancel.control())?;
        let curve = std::mem::take(&mut summary.curve);
        let fields = match serde_json::to_value(&summary)? {
            serde_json::Value::Object(mut map) => {
                map.remove("curve");
                map
            }
            _ => serde_json::Map::new(),
        };
        Ok((fields, curve, scratch))
    })?;
    let folder = match &out {
        Some(out) => Some(raise(
            py,
            publish(&scratch.path().join(&name), &out.join(&name)),
        )?),
        None => None,
    };
    Ok(RunResult(Outcome::new(
        Fields::Json(summary),
        folder,
        curve,
    )))
}

/// Scratch folders of calls still running (their work may go on in the background after an
/// interrupt). [`remove_scratch_folders`] removes them when the interpreter exits, which would
/// otherwise end the background work before it drops them.
static LIVE_SCRATCH: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// A scratch folder, removed when dropped and, if the interpreter exits first, at exit.
struct Scratch(tempfile::TempDir);

impl Scratch {
    fn new(dir: tempfile::TempDir) -> Self {
        if let Ok(mut live) = LIVE_SCRATCH.lock() {
            live.push(dir.path().to_owned());
        }
        Self(dir)
    }

    fn path(&self) -> &Path {
        self.0.path()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if let Ok(mut live) = LIVE_SCRATCH.lock() {
            live.retain(|p| p != self.0.path());
        }
    }
}

/// Remove the scratch folders of calls still running (registered with `atexit` by the Python
/// package, so that an interrupted call leaves no folder behind when the interpreter exits).
#[pyfunction]
fn remove_scratch_folders() {
    let live = LIVE_SCRATCH
        .lock()
        .map(|mut l| std::mem::take(&mut *l))
        .unwrap_or_default();
    for path in live {
        let _ = std::fs::remove_dir_all(path);
    }
}

/// A hidden temporary folder inside `out` (same file system, so the results move by rename),
/// or in the system's temporary folder without `out`. Removed when dropped.
fn scratch_folder(out: Option<&Path>) -> Result<Scratch, Failure> {
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
                .map(Scratch::new)
                .map_err(|e| io(e, out))
        }
        None => tempfile::Builder::new()
            .prefix("sawdrive-python-")
            .tempdir()
            .map(Scratch::new)
            .map_err(|e| io(e, &std::env::temp_dir())),
    }
}

/// Move the finished results folder `from` over `destination` with the library's staged swap.
fn publish(from: &Path, destination: &Path) -> Result<String, Failure> {
    let staged = StagedDir::create(destination, ResultKind::Run)?;
    // The fresh staging folder holds only its marker; `from`, a committed run result, has its own.
    let move_in =
        std::fs::remove_dir_all(staged.path()).and_then(|()| std::fs::rename(from, staged.path()));
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

/// Benchmark baseline: the wall time (s) of each of `repeats` calls of the dynamic stage made
/// from Rust on the resolved `scene` (post springs, then `run_dynamic_stage`: the work
/// `sawdrive.dynamic(scene)` asks for, without the Python layer). The scene must give η (the
/// benchmark is about the call, not the FEM).
#[pyfunction]
fn time_rust_dynamic(
    py: Python<'_>,
    scene: &Bound<'_, NativeScene>,
    repeats: usize,
) -> PyResult<Vec<f64>> {
    let scene = Arc::clone(&scene.get().scene);
    let timed = py.detach(move || -> Result<Vec<f64>, Failure> {
        let eta = scene.contact.effective_ratio.ok_or_else(|| {
            Failure::text(
                Kind::Argument,
                "the benchmark needs a given η: set effective_ratio",
            )
        })?;
        let mut times = Vec::with_capacity(repeats);
        for _ in 0..repeats {
            let start = Instant::now();
            let springs = springs_of(&scene)?;
            let stage = run_dynamic_stage(&scene, &springs, eta, None, None, &RunControl::none())?;
            std::hint::black_box(&stage.lumped.result);
            drop(stage);
            times.push(start.elapsed().as_secs_f64());
        }
        Ok(times)
    });
    raise(py, timed)
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(default_scene_toml, m)?)?;
    m.add_class::<NativeScene>()?;
    m.add_class::<DynamicResult>()?;
    m.add_class::<RunResult>()?;
    m.add_function(wrap_pyfunction!(post_springs, m)?)?;
    m.add_function(wrap_pyfunction!(static_stage, m)?)?;
    m.add_function(wrap_pyfunction!(dynamic_stage, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    studies::register(m)?;
    m.add_function(wrap_pyfunction!(time_rust_dynamic, m)?)?;
    m.add_function(wrap_pyfunction!(remove_scratch_folders, m)?)?;
    m.add("DYNAMIC_MODEL_VERSION", sawdrive::DYNAMIC_MODEL_VERSION)?;
    Ok(())
}
