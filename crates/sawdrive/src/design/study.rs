//! `sawdrive design DESIGN.toml`: a texture optimised for one output of the motor,
//! optionally robust to scatter (a quantile over Monte Carlo samples), searched with the cheap
//! `lattice-patch` model and confirmed with the whole-slider `lattice-slider` model
//! ([`design::multi_fidelity`]; method and tolerance in `design::optimise`).
//!
//! ```toml
//! name = "texture"                  # results folder OUT/<name>/
//! scene = "motor.toml"              # optional, relative to this file (default: embedded scene)
//! set = ["wave.normal_amplitude=20nm"]   # optional scene overrides
//! objective = "max_output_power_w"  # effective_contact_ratio | stall_thrust_n |
//!                                   # no_load_speed_m_per_s | max_output_power_w | efficiency
//! sense = "maximise"                # or "minimise"
//! quantile = 0.05                   # optional: robust objective, this quantile under [scatter]
//! samples = 16                      # Monte Carlo samples per design at full fidelity
//! cheap_samples = 4                 # … at the cheap fidelity
//! seed = 1
//!
//! [variables]                       # any subset; [lower, upper] with units
//! post_diameter = ["10 um", "60 um"]
//! posts_per_side = [20, 200]        # square array, pitch = posts.array / count
//! post_height = ["1 um", "4 um"]
//! preload = ["10 N", "100 N"]
//!
//! [constraints]                     # any subset
//! min_gap = "5 um"                  # pitch − diameter ≥ min_gap
//! contact_area_fraction = [0.05, 0.6]   # N π d²/4 over the array area
//! max_preload = "100 N"
//!
//! [scatter]                         # as in `sawdrive uq` (needed with `quantile`)
//! height_scatter = "5 nm"
//!
//! [optimiser]                       # design::OptimiserSettings; all optional
//! presearch_points = 24
//! starts = 2
//! max_evaluations_per_start = 30
//! x_tolerance = 0.01
//! finalists = 3
//! refine_evaluations = 20           # full-fidelity compass search from the best finalist (0: off)
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use design::{
    Evaluation, Objective, OptimiserSettings, Outcome, Sense, Variable, VariableSensitivity,
    draw_inputs, local_sensitivity, multi_fidelity, pareto_front, percentile,
};
use rayon::prelude::*;
use serde::Serialize;
use sha2::{Digest, Sha256};

use super::motor::{
    Fidelity, MotorSample, OUTPUT_NAMES, StaticModel, check_dynamics, evaluate_with,
};
use super::scatter::ScatterSpec;
use super::uq::design_error;
use crate::output::{ResultKind, StagedDir, write_atomically};
use crate::pipeline::PipelineError;
use crate::scene::{Scene, load_scene};
use crate::units::{Dimension, format_quantity, parse_quantity};

/// Version of the saved evaluations' layout (part of their key).
const EVALUATION_FORMAT: u32 = 1;

/// Relative step of the optimum's sensitivity (fraction of each variable's range).
const SENSITIVITY_STEP: f64 = 0.05;

/// A design variable the scene can express: (DESIGN.toml key, variable name with unit, scene
/// key it sets, dimension; `None`: a count).
const VARIABLES: [(&str, &str, &str, Option<Dimension>); 4] = [
    (
        "post_diameter",
        "post_diameter_m",
        "posts.diameter",
        Some(Dimension::Length),
    ),
    ("posts_per_side", "posts_per_side", "posts.count", None),
    (
        "post_height",
        "post_height_m",
        "posts.height",
        Some(Dimension::Length),
    ),
    (
        "preload",
        "preload_n",
        "load.preload",
        Some(Dimension::Force),
    ),
];

/// Fabrication constraints, SI.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Constraints {
    /// pitch − diameter ≥ this (m).
    pub min_gap_m: Option<f64>,
    /// N π d²/4 / array area within [lo, hi].
    pub contact_area_fraction: Option<[f64; 2]>,
    /// Preload ≤ this (N).
    pub max_preload_n: Option<f64>,
}

/// A parsed design file.
#[derive(Debug, Clone)]
pub struct DesignSpec {
    /// Results folder name.
    pub name: String,
    /// Scene file (absolute or relative to the current folder), if any.
    pub scene: Option<PathBuf>,
    /// Scene overrides.
    pub set: Vec<String>,
    /// Objective.
    pub objective: Objective,
    /// Robust quantile (`None`: nominal design).
    pub quantile: Option<f64>,
    /// Full-fidelity samples per design.
    pub samples: usize,
    /// Cheap-fidelity samples per design.
    pub cheap_samples: usize,
    /// Seed of the scatter.
    pub seed: u64,
    /// Variables (SI).
    pub variables: Vec<Variable>,
    /// Scene keys of the variables.
    pub scene_keys: Vec<&'static str>,
    /// Constraints.
    pub constraints: Constraints,
    /// Scatter.
    pub scatter: ScatterSpec,
    /// Optimiser settings.
    pub optimiser: OptimiserSettings,
}

type Table = toml::Table;

fn err(key: &str, message: impl std::fmt::Display) -> String {
    format!("{key}: {message}")
}

fn quantity(v: &toml::Value, key: &str, dim: Dimension) -> Result<f64, String> {
    let s = v.as_str().ok_or_else(|| {
        err(
            key,
            format!("expected a quantity with its unit, e.g. {}", dim.example()),
        )
    })?;
    parse_quantity(s, dim).map_err(|e| err(key, e))
}

fn number(v: &toml::Value, key: &str) -> Result<f64, String> {
    v.as_float()
        .or_else(|| v.as_integer().map(|i| i as f64))
        .ok_or_else(|| err(key, format!("expected a number, got {v}")))
}

fn count(v: &toml::Value, key: &str) -> Result<u64, String> {
    v.as_integer()
        .and_then(|i| u64::try_from(i).ok())
        .ok_or_else(|| err(key, format!("expected a whole number ≥ 0, got {v}")))
}

fn pair(v: &toml::Value, key: &str) -> Result<[toml::Value; 2], String> {
    match v.as_array().map(Vec::as_slice) {
        Some([a, b]) => Ok([a.clone(), b.clone()]),
        _ => Err(err(key, "expected [lower, upper]")),
    }
}

fn parse_variables(t: &Table) -> Result<(Vec<Variable>, Vec<&'static str>), String> {
    let mut vars = Vec::new();
    let mut keys = Vec::new();
    for (key, value) in t {
        let full = format!("variables.{key}");
        let Some(&(_, name, scene_key, dim)) = VARIABLES.iter().find(|v| v.0 == key) else {
            let known: Vec<&str> = VARIABLES.iter().map(|v| v.0).collect();
            return Err(err(
                &full,
                format!("unknown design variable (known: {})", known.join(", ")),
            ));
        };
        let [a, b] = pair(value, &full)?;
        let (lower, upper) = match dim {
            Some(d) => (quantity(&a, &full, d)?, quantity(&b, &full, d)?),
            None => (count(&a, &full)? as f64, count(&b, &full)? as f64),
        };
        let v = Variable {
            name: name.to_owned(),
            lower,
            upper,
            integer: dim.is_none(),
        };
        v.validate()
            .map_err(|e| e.to_string().replace(&format!("variables.{name}"), &full))?;
        vars.push(v);
        keys.push(scene_key);
    }
    if vars.is_empty() {
        return Err("variables: give at least one design variable".into());
    }
    Ok((vars, keys))
}

fn parse_constraints(t: &Table) -> Result<Constraints, String> {
    let mut c = Constraints::default();
    for (key, value) in t {
        let full = format!("constraints.{key}");
        match key.as_str() {
            "min_gap" => c.min_gap_m = Some(quantity(value, &full, Dimension::Length)?),
            "max_preload" => c.max_preload_n = Some(quantity(value, &full, Dimension::Force)?),
            "contact_area_fraction" => {
                let [a, b] = pair(value, &full)?;
                let (lo, hi) = (number(&a, &full)?, number(&b, &full)?);
                if !(0.0..=1.0).contains(&lo) || !(0.0..=1.0).contains(&hi) || lo > hi {
                    return Err(err(
                        &full,
                        format!("[{lo}, {hi}] must be an interval within [0, 1]"),
                    ));
                }
                c.contact_area_fraction = Some([lo, hi]);
            }
            _ => {
                return Err(err(
                    &full,
                    "unknown constraint (known: min_gap, contact_area_fraction, max_preload)",
                ));
            }
        }
    }
    Ok(c)
}

fn parse_optimiser(t: &Table) -> Result<OptimiserSettings, String> {
    let mut s = OptimiserSettings::default();
    for (key, value) in t {
        let full = format!("optimiser.{key}");
        match key.as_str() {
            "presearch_points" => s.presearch_points = count(value, &full)? as usize,
            "starts" => s.starts = count(value, &full)? as usize,
            "max_evaluations_per_start" => {
                s.max_evaluations_per_start = count(value, &full)? as usize
            }
            "finalists" => s.finalists = count(value, &full)? as usize,
            "refine_evaluations" => s.refine_evaluations = count(value, &full)? as usize,
            "seed" => s.seed = count(value, &full)?,
            "x_tolerance" => s.x_tolerance = number(value, &full)?,
            _ => return Err(err(&full, "unknown setting")),
        }
    }
    s.validate().map_err(|e| e.to_string())?;
    Ok(s)
}

impl DesignSpec {
    /// Reads and checks a design file; errors are one line naming the file and the key.
    pub fn read(path: &Path) -> Result<Self, String> {
        let text = atomic_files::read_input_text(path, atomic_files::MAX_SETTINGS_FILE_BYTES)
            .map_err(|e| e.to_string())?;
        Self::parse(&text, path.parent().unwrap_or(Path::new(".")))
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses a design file's text; a relative `scene` is taken relative to `base`.
    pub fn parse(text: &str, base: &Path) -> Result<Self, String> {
        let mut t: Table = text.parse().map_err(|e: toml::de::Error| {
            format!(
                "not valid TOML: {}",
                e.to_string().trim().replace('\n', " ")
            )
        })?;
        let mut take_table = |k: &str| -> Result<Table, String> {
            match t.remove(k) {
                None => Ok(Table::new()),
                Some(toml::Value::Table(x)) => Ok(x),
                Some(_) => Err(err(k, "must be a table")),
            }
        };
        let (variables, scene_keys) = parse_variables(&take_table("variables")?)?;
        let constraints = parse_constraints(&take_table("constraints")?)?;
        let scatter = ScatterSpec::from_table(&take_table("scatter")?)?;
        let optimiser = parse_optimiser(&take_table("optimiser")?)?;
        let mut spec = Self {
            name: "design".into(),
            scene: None,
            set: Vec::new(),
            objective: Objective {
                output: "max_output_power_w".into(),
                sense: Sense::Maximise,
            },
            quantile: None,
            samples: 16,
            cheap_samples: 4,
            seed: 1,
            variables,
            scene_keys,
            constraints,
            scatter,
            optimiser,
        };
        for (key, value) in &t {
            match key.as_str() {
                "name" => {
                    let name = value
                        .as_str()
                        .ok_or_else(|| err(key, "expected a string"))?;
                    atomic_files::check_name(name).map_err(|e| err(key, e.to_string()))?;
                    spec.name = name.to_owned()
                }
                "scene" => {
                    spec.scene =
                        Some(base.join(value.as_str().ok_or_else(|| err(key, "expected a path"))?))
                }
                "set" => {
                    spec.set = value
                        .as_array()
                        .ok_or_else(|| err(key, "expected a list of \"key=value\""))?
                        .iter()
                        .map(|v| {
                            v.as_str()
                                .map(str::to_owned)
                                .ok_or_else(|| err(key, "expected strings"))
                        })
                        .collect::<Result<_, _>>()?
                }
                "objective" => {
                    let o = value
                        .as_str()
                        .ok_or_else(|| err(key, "expected an output name"))?;
                    if !OUTPUT_NAMES.contains(&o) {
                        return Err(err(
                            key,
                            format!(
                                "unknown output \"{o}\" (known: {})",
                                OUTPUT_NAMES.join(", ")
                            ),
                        ));
                    }
                    spec.objective.output = o.to_owned();
                }
                "sense" => {
                    spec.objective.sense = match value.as_str() {
                        Some("maximise") => Sense::Maximise,
                        Some("minimise") => Sense::Minimise,
                        _ => {
                            return Err(err(
                                key,
                                format!("{value} is not \"maximise\" or \"minimise\""),
                            ));
                        }
                    }
                }
                "quantile" => {
                    let q = number(value, key)?;
                    if !(0.0..=1.0).contains(&q) {
                        return Err(err(key, format!("{q} outside [0, 1]")));
                    }
                    spec.quantile = Some(q);
                }
                "samples" | "cheap_samples" => {
                    let n = count(value, key)? as usize;
                    if n == 0 {
                        return Err(err(key, "must be ≥ 1"));
                    }
                    if n > crate::design::uq::MAX_SAMPLES {
                        return Err(err(
                            key,
                            format!(
                                "{n} is more than the {} accepted",
                                crate::design::uq::MAX_SAMPLES
                            ),
                        ));
                    }
                    if key == "samples" {
                        spec.samples = n
                    } else {
                        spec.cheap_samples = n
                    }
                }
                "seed" => spec.seed = count(value, key)?,
                other => {
                    return Err(err(
                        other,
                        "unknown key (known: name, scene, set, objective, sense, quantile, samples, cheap_samples, seed, [variables], [constraints], [scatter], [optimiser])",
                    ));
                }
            }
        }
        if spec.quantile.is_none() && spec.scatter != ScatterSpec::default() {
            return Err("scatter: a [scatter] section needs `quantile` (the robust objective), else it would be ignored".into());
        }
        if spec.quantile.is_some() && spec.scatter == ScatterSpec::default() {
            return Err("quantile: needs a [scatter] section (a quantile of identical samples is the nominal value), else it would be ignored".into());
        }
        if spec.cheap_samples > spec.samples {
            return Err(err(
                "cheap_samples",
                format!(
                    "{} is more than samples = {}: the cheap fidelity takes at most as many samples as the full one",
                    spec.cheap_samples, spec.samples
                ),
            ));
        }
        Ok(spec)
    }

    /// The scene of design `x`.
    pub fn scene_at(&self, x: &[f64]) -> Result<Scene, String> {
        let mut set = self.set.clone();
        for ((v, key), value) in self.variables.iter().zip(&self.scene_keys).zip(x) {
            let dim = VARIABLES.iter().find(|d| d.1 == v.name).and_then(|d| d.3);
            set.push(match dim {
                Some(_) if *key == "load.preload" => format!("{key}={value:e} N"),
                Some(_) => format!("{key}={value:e} m"),
                None => format!("{key}={n}x{n}", n = *value as u64),
            });
        }
        load_scene(self.scene.as_deref(), &set).map_err(|e| e.to_string())
    }

    /// Violations of the constraints by `scene` (relative amounts).
    fn violations(&self, scene: &Scene) -> Vec<(String, f64)> {
        let p = &scene.motor.posts;
        let c = &self.constraints;
        let mut v = Vec::new();
        if let Some(g) = c.min_gap_m {
            let gap = p.pitch_x_m().min(p.pitch_y_m()) - p.diameter_m;
            if gap < g {
                v.push((
                    "constraints.min_gap".to_owned(),
                    (g - gap) / g.max(p.diameter_m),
                ));
            }
        }
        if let Some([lo, hi]) = c.contact_area_fraction {
            let a = p.count() as f64 * std::f64::consts::PI * p.diameter_m.powi(2)
                / 4.0
                / (p.array_x_m * p.array_y_m);
            if a < lo {
                v.push((
                    "constraints.contact_area_fraction".to_owned(),
                    (lo - a) / lo.max(1e-12),
                ));
            } else if a > hi {
                v.push((
                    "constraints.contact_area_fraction".to_owned(),
                    (a - hi) / hi.max(1e-12),
                ));
            }
        }
        if let Some(m) = c.max_preload_n
            && scene.motor.load.preload_n > m
        {
            v.push((
                "constraints.max_preload".to_owned(),
                (scene.motor.load.preload_n - m) / m.max(1e-12),
            ));
        }
        v
    }

    /// The model at `fidelity`: constraints, then the nominal outputs or their quantile over
    /// `samples` scatter samples.
    fn model(&self, x: &[f64], fidelity: Fidelity, samples: usize) -> Result<Outcome, String> {
        let scene = self.scene_at(x)?;
        let violations = self.violations(&scene);
        if !violations.is_empty() {
            return Ok(Outcome {
                objective: f64::NAN,
                violations,
                outputs: BTreeMap::new(),
            });
        }
        let k = OUTPUT_NAMES
            .iter()
            .position(|n| *n == self.objective.output)
            .unwrap_or(3);
        // One operator per design and fidelity, shared by its scatter samples.
        let model = StaticModel::build(&scene, fidelity).map_err(|e| e.to_string())?;
        let runs: Vec<[f64; 5]> = match self.quantile {
            None => vec![
                evaluate_with(&model, &scene, &MotorSample::nominal(&scene))
                    .map_err(|e| e.to_string())?
                    .values(),
            ],
            Some(_) => {
                let inputs = self.scatter.inputs(&scene)?;
                (0..samples as u64)
                    .into_par_iter()
                    .map(|i| {
                        let (values, field_seed) = draw_inputs(&inputs, self.seed, i);
                        evaluate_with(&model, &scene, &self.scatter.sample(&values, field_seed))
                            .map(|o| o.values())
                            .map_err(|e| e.to_string())
                    })
                    .collect::<Result<_, _>>()?
            }
        };
        let q = self.quantile.unwrap_or(0.5);
        let mut outputs = BTreeMap::new();
        for (j, name) in OUTPUT_NAMES.iter().enumerate() {
            let col: Vec<f64> = runs.iter().map(|r| r[j]).collect();
            outputs.insert(
                name.to_string(),
                percentile(&col, q, name).map_err(|e| e.to_string())?,
            );
        }
        Ok(Outcome {
            objective: outputs[OUTPUT_NAMES[k]],
            violations: Vec::new(),
            outputs,
        })
    }
}

impl DesignSpec {
    /// The resume key of design `x` at `fidelity`: a hash of everything its outcome depends on
    /// (the resolved scene, the fidelity, the samples, quantile, scatter and seed, the objective,
    /// the constraints and the model versions), not of the optimiser's path.
    fn evaluation_key(
        &self,
        x: &[f64],
        fidelity: Fidelity,
        samples: usize,
    ) -> Result<String, String> {
        let scene = self.scene_at(x)?;
        let mut h = Sha256::new();
        h.update(serde_json::to_vec(&scene).map_err(|e| e.to_string())?);
        h.update(fidelity.label().as_bytes());
        h.update(samples.to_le_bytes());
        h.update(format!("{:?}", self.quantile).as_bytes());
        h.update(serde_json::to_vec(&self.scatter).map_err(|e| e.to_string())?);
        h.update(self.seed.to_le_bytes());
        h.update(serde_json::to_vec(&self.objective).map_err(|e| e.to_string())?);
        h.update(serde_json::to_vec(&self.constraints).map_err(|e| e.to_string())?);
        h.update(crate::DYNAMIC_MODEL_VERSION.to_le_bytes());
        h.update(static_contact::params::MODEL_VERSION.to_le_bytes());
        h.update(EVALUATION_FORMAT.to_le_bytes());
        Ok(h.finalize()
            .iter()
            .take(16)
            .map(|b| format!("{b:02x}"))
            .collect())
    }
}

/// The design model at one fidelity with resume: each finished evaluation is saved atomically to
/// `cache/<key>.json`, and one found there (from an interrupted run) is reused instead of
/// recomputed. The optimiser is deterministic, so a rerun retraces the interrupted run's path
/// through the saved evaluations and loses only those in flight. An infeasible outcome (NaN
/// objective) is not saved: it costs only the constraint check.
struct ResumableModel<'a> {
    spec: &'a DesignSpec,
    fidelity: Fidelity,
    samples: usize,
    cache: &'a Path,
    /// Evaluations (count, summed seconds) computed, by fidelity label; and reused.
    timing: &'a std::sync::Mutex<BTreeMap<String, (usize, f64)>>,
    resumed: &'a std::sync::atomic::AtomicUsize,
}

impl ResumableModel<'_> {
    fn call(&self, x: &[f64]) -> Result<Outcome, String> {
        let path = self.cache.join(format!(
            "{}.json",
            self.spec.evaluation_key(x, self.fidelity, self.samples)?
        ));
        let saved = std::fs::read(&path)
            .ok()
            .and_then(|b| serde_json::from_slice::<Outcome>(&b).ok());
        if let Some(o) = saved {
            self.resumed
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            return Ok(o);
        }
        let t = Instant::now();
        let outcome = self.spec.model(x, self.fidelity, self.samples)?;
        if let Ok(mut m) = self.timing.lock() {
            let e = m.entry(self.fidelity.label().to_owned()).or_default();
            e.0 += 1;
            e.1 += t.elapsed().as_secs_f64();
        }
        if outcome.objective.is_finite() {
            let bytes = serde_json::to_vec(&outcome).map_err(|e| e.to_string())?;
            write_atomically(&path, bytes).map_err(|e| e.to_string())?;
        }
        Ok(outcome)
    }
}

/// One evaluation as written to JSON/CSV.
#[derive(Debug, Clone, Serialize)]
pub struct EvaluationRow {
    /// Variables by name (with unit).
    pub variables: BTreeMap<String, f64>,
    /// Which model computed it.
    pub fidelity: String,
    /// Search stage.
    pub stage: &'static str,
    /// Objective value (NaN → null when infeasible).
    pub objective: Option<f64>,
    /// Whether every constraint holds.
    pub feasible: bool,
    /// Violated constraints.
    pub violations: Vec<String>,
    /// Outputs (the quantile of each, when robust).
    pub outputs: BTreeMap<String, f64>,
}

/// The optimum.
#[derive(Debug, Clone, Serialize)]
pub struct Optimum {
    /// Variables by name (with unit).
    pub variables: BTreeMap<String, f64>,
    /// Objective output name.
    pub objective: String,
    /// Its value at the optimum (the quantile when robust).
    pub objective_value: f64,
    /// Model that computed it.
    pub fidelity: String,
    /// Search stage that found it (`confirm`: a finalist; `refine`: the full-fidelity refinement).
    pub stage: &'static str,
    /// Every output at the optimum, same fidelity.
    pub outputs: BTreeMap<String, f64>,
}

/// `summary.json` of a design run.
#[derive(Debug, Clone, Serialize)]
pub struct DesignReport {
    /// Design name.
    pub name: String,
    /// The optimum, confirmed at full fidelity.
    pub optimum: Optimum,
    /// The scene's own design (nominal variables) at full fidelity, for comparison.
    pub baseline: Option<EvaluationRow>,
    /// Robust quantile, if any.
    pub quantile: Option<f64>,
    /// Sensitivity of the optimum's objective to each variable (full fidelity).
    pub sensitivity: Vec<VariableSensitivity>,
    /// Every evaluation.
    pub evaluations: Vec<EvaluationRow>,
    /// Evaluations computed in this run and their mean wall time (s, measured per evaluation;
    /// parallel evaluations overlap) by fidelity.
    pub cost: Vec<(String, usize, f64)>,
    /// Evaluations reused from the saved results (`OUT/.design-evaluations/`): an earlier,
    /// interrupted run's, or a design this run met twice (e.g. a sensitivity neighbour).
    pub resumed_evaluations: usize,
    /// Wall time (s).
    pub wall_time_s: f64,
    /// Files written.
    pub files: Vec<String>,
}

fn row(spec: &DesignSpec, e: &Evaluation) -> EvaluationRow {
    EvaluationRow {
        variables: spec
            .variables
            .iter()
            .map(|v| v.name.clone())
            .zip(e.x.iter().copied())
            .collect(),
        fidelity: e.fidelity.clone(),
        stage: e.stage,
        objective: e
            .outcome
            .objective
            .is_finite()
            .then_some(e.outcome.objective),
        feasible: e.outcome.feasible(),
        violations: e.outcome.violations.iter().map(|v| v.0.clone()).collect(),
        outputs: e.outcome.outputs.clone(),
    }
}

/// Runs the design study; writes `OUT/<name>/` when complete.
pub fn run_design(
    spec: &DesignSpec,
    out_dir: &Path,
    write_files: bool,
) -> Result<(DesignReport, PathBuf), PipelineError> {
    let start = Instant::now();
    let bad = |message: String| PipelineError::Unsupported {
        stage: "design",
        message,
    };
    let scene = spec
        .scene_at(&spec.variables.iter().map(|v| v.at(0.5)).collect::<Vec<_>>())
        .map_err(bad)?;
    check_dynamics(&scene)?;
    let staged = StagedDir::create(&out_dir.join(&spec.name), ResultKind::Design)?;
    let timing = std::sync::Mutex::new(BTreeMap::<String, (usize, f64)>::new());
    let resumed = std::sync::atomic::AtomicUsize::new(0);
    let cache = out_dir.join(".design-evaluations");
    let timed = |fidelity: Fidelity, samples: usize| {
        let m = ResumableModel {
            spec,
            fidelity,
            samples,
            cache: &cache,
            timing: &timing,
            resumed: &resumed,
        };
        move |x: &[f64]| m.call(x)
    };
    let cheap = timed(Fidelity::Patch, spec.cheap_samples);
    let full = timed(Fidelity::Slider, spec.samples);
    let result = multi_fidelity(
        &spec.variables,
        &spec.objective,
        &spec.optimiser,
        (Fidelity::Patch.label(), &cheap),
        (Fidelity::Slider.label(), &full),
    )
    .map_err(design_error)?;
    let best = &result.best;
    let sensitivity = local_sensitivity(
        &spec.variables,
        &best.x,
        best.outcome.objective,
        SENSITIVITY_STEP,
        &full,
    )
    .map_err(design_error)?;
    let baseline = baseline(spec, &full);
    let cost = timing
        .into_inner()
        .unwrap_or_default()
        .into_iter()
        .map(|(k, (n, s))| (k, n, if n > 0 { s / n as f64 } else { 0.0 }))
        .collect();
    let mut report = DesignReport {
        name: spec.name.clone(),
        optimum: Optimum {
            variables: spec
                .variables
                .iter()
                .map(|v| v.name.clone())
                .zip(best.x.iter().copied())
                .collect(),
            objective: spec.objective.output.clone(),
            objective_value: best.outcome.objective,
            fidelity: best.fidelity.clone(),
            stage: best.stage,
            outputs: best.outcome.outputs.clone(),
        },
        baseline,
        quantile: spec.quantile,
        sensitivity,
        evaluations: result.evaluations.iter().map(|e| row(spec, e)).collect(),
        cost,
        resumed_evaluations: resumed.into_inner(),
        wall_time_s: 0.0,
        files: Vec::new(),
    };
    if write_files {
        report.files = write_design_files(&report, staged.path())?;
    }
    report.files.push("summary.json".into());
    report.wall_time_s = start.elapsed().as_secs_f64();
    staged.write("summary.json", serde_json::to_vec_pretty(&report)?)?;
    Ok((report, staged.commit()?))
}

/// The scene's own values of the variables, evaluated at full fidelity (`None` if the scene's
/// design lies outside the bounds).
fn baseline<F>(spec: &DesignSpec, full: &F) -> Option<EvaluationRow>
where
    F: Fn(&[f64]) -> Result<Outcome, String>,
{
    let scene = load_scene(spec.scene.as_deref(), &spec.set).ok()?;
    let x: Vec<f64> = spec
        .variables
        .iter()
        .map(|v| match v.name.as_str() {
            "post_diameter_m" => scene.motor.posts.diameter_m,
            "posts_per_side" => f64::from(scene.motor.posts.count_x),
            "post_height_m" => scene.motor.posts.height_m,
            _ => scene.motor.load.preload_n,
        })
        .collect();
    let outcome = full(&x).ok()?;
    Some(row(
        spec,
        &Evaluation {
            x,
            fidelity: Fidelity::Slider.label().into(),
            stage: "baseline",
            outcome,
        },
    ))
}

fn evaluations_csv(report: &DesignReport) -> String {
    let vars: Vec<String> = report.optimum.variables.keys().cloned().collect();
    let mut s = format!(
        "{},fidelity,stage,feasible,objective,{},violations\n",
        vars.join(","),
        OUTPUT_NAMES.join(",")
    );
    for r in &report.evaluations {
        let cells: Vec<String> = vars
            .iter()
            .map(|v| format!("{:e}", r.variables[v]))
            .collect();
        let outs: Vec<String> = OUTPUT_NAMES
            .iter()
            .map(|n| {
                r.outputs
                    .get(*n)
                    .map_or(String::new(), |v| format!("{v:e}"))
            })
            .collect();
        s.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            cells.join(","),
            r.fidelity,
            r.stage,
            r.feasible,
            r.objective.map_or(String::new(), |v| format!("{v:e}")),
            outs.join(","),
            r.violations.join(";")
        ));
    }
    s
}

/// `evaluations.csv` and the Pareto chart (stall thrust against no-load speed of the feasible
/// evaluations, in three series by objective tercile, the front and the optimum).
fn write_design_files(report: &DesignReport, dir: &Path) -> Result<Vec<String>, PipelineError> {
    use charts::{Chart, Series, Style, write_chart};
    write_atomically(&dir.join("evaluations.csv"), evaluations_csv(report))?;
    let mut files = vec!["evaluations.csv".to_owned()];
    let feasible: Vec<&EvaluationRow> = report.evaluations.iter().filter(|r| r.feasible).collect();
    let point = |r: &EvaluationRow| {
        (
            r.outputs["no_load_speed_m_per_s"],
            r.outputs["stall_thrust_n"],
        )
    };
    let mut objectives: Vec<f64> = feasible.iter().filter_map(|r| r.objective).collect();
    objectives.sort_by(f64::total_cmp);
    let cut = |q: f64| {
        objectives
            .get(((objectives.len() as f64 - 1.0) * q) as usize)
            .copied()
            .unwrap_or(0.0)
    };
    let (t1, t2) = (cut(1.0 / 3.0), cut(2.0 / 3.0));
    let obj = &report.optimum.objective;
    let mut chart = Chart::new(
        format!("{}: evaluated designs (colour: {obj} tercile)", report.name),
        "no-load speed (m/s)",
        "stall thrust (N)",
    );
    for (label, lo, hi) in [
        ("lowest third", f64::NEG_INFINITY, t1),
        ("middle third", t1, t2),
        ("highest third", t2, f64::INFINITY),
    ] {
        let pts = feasible
            .iter()
            .filter(|r| {
                r.objective
                    .is_some_and(|o| (o > lo || lo == f64::NEG_INFINITY) && o <= hi)
            })
            .map(|r| point(r))
            .collect();
        chart
            .series
            .push(Series::new(format!("{obj}: {label}"), pts, Style::Markers));
    }
    let pts: Vec<(f64, f64)> = feasible.iter().map(|r| point(r)).collect();
    let front: Vec<(f64, f64)> = pareto_front(&pts).into_iter().map(|i| pts[i]).collect();
    chart
        .series
        .push(Series::new("Pareto front", front, Style::Line));
    let o = &report.optimum.outputs;
    chart.series.push(Series::new(
        "optimum (confirmed)",
        vec![(o["no_load_speed_m_per_s"], o["stall_thrust_n"])],
        Style::LineMarkers,
    ));
    for f in write_chart(&chart, &dir.join("pareto"))? {
        files.push(
            f.file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned(),
        );
    }
    Ok(files)
}

/// Human form of the optimum's variables.
pub fn describe_variables(variables: &BTreeMap<String, f64>) -> String {
    variables
        .iter()
        .map(|(k, v)| match k.as_str() {
            "post_diameter_m" | "post_height_m" => {
                format!("{k} = {}", format_quantity(*v, Dimension::Length))
            }
            "preload_n" => format!("{k} = {}", format_quantity(*v, Dimension::Force)),
            _ => format!("{k} = {v}"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = r#"
name = "small"
set = ["posts.count=10x10", "posts.array=0.4mm"]
objective = "max_output_power_w"
[variables]
preload = ["1 N", "4 N"]
[optimiser]
presearch_points = 3
starts = 1
max_evaluations_per_start = 3
finalists = 1
"#;

    fn parse(text: &str) -> Result<DesignSpec, String> {
        DesignSpec::parse(text, Path::new("."))
    }

    #[test]
    fn a_design_run_reports_a_confirmed_optimum_with_unit_named_variables() {
        let dir = tempfile::tempdir().unwrap();
        let (r, folder) = run_design(&parse(SMALL).unwrap(), dir.path(), false).unwrap();
        assert_eq!(
            r.optimum.fidelity, "lattice-slider",
            "fidelity of the optimum"
        );
        let p = r.optimum.variables["preload_n"];
        assert!(
            (1.0..=4.0).contains(&p),
            "optimal preload {p} N within its bounds"
        );
        assert!(
            r.evaluations.iter().any(|e| e.fidelity == "lattice-patch"),
            "cheap search ran"
        );
        assert!(r.optimum.objective_value > 0.0, "maximum output power");
        assert!(folder.join("summary.json").exists());
    }

    #[test]
    fn an_interrupted_design_run_resumes_from_its_saved_evaluations_and_loses_nothing() {
        let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        let spec = parse(SMALL).unwrap();
        run_design(&spec, a.path(), false).unwrap();
        let mut saved: Vec<PathBuf> = std::fs::read_dir(a.path().join(".design-evaluations"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        saved.sort();
        assert!(saved.len() >= 4, "evaluations saved: {}", saved.len());
        // Simulate an interruption: one saved evaluation lost, one damaged.
        std::fs::remove_file(&saved[0]).unwrap();
        std::fs::write(&saved[1], "{half").unwrap();
        let (resumed, _) = run_design(&spec, a.path(), false).unwrap();
        let recomputed: usize = resumed.cost.iter().map(|c| c.1).sum();
        assert_eq!(
            recomputed, 2,
            "evaluations recomputed after the interruption"
        );
        assert!(
            resumed.resumed_evaluations >= saved.len() - 2,
            "evaluations reused"
        );
        let (fresh, _) = run_design(&spec, b.path(), false).unwrap();
        assert_eq!(
            resumed.optimum.objective_value.to_bits(),
            fresh.optimum.objective_value.to_bits(),
            "resumed and fresh optimal output power"
        );
        assert_eq!(
            resumed.optimum.variables, fresh.optimum.variables,
            "resumed and fresh optimal design"
        );
        assert_eq!(
            resumed.evaluations.len(),
            fresh.evaluations.len(),
            "resumed and fresh evaluation logs"
        );
    }

    #[test]
    fn bad_design_files_are_refused_naming_the_key() {
        let e = parse(&SMALL.replace("[\"1 N\", \"4 N\"]", "[\"4 N\", \"1 N\"]")).unwrap_err();
        assert!(e.starts_with("variables.preload: bounds reversed"), "{e}");
        let e = parse(&SMALL.replace("\"max_output_power_w\"", "\"max_power\"")).unwrap_err();
        assert!(
            e.starts_with("objective: unknown output \"max_power\""),
            "{e}"
        );
        let e = parse(&format!("{SMALL}\n[scatter]\nheight_scatter = \"5 nm\"\n")).unwrap_err();
        assert!(e.starts_with("scatter:"), "{e}");
        let e = parse(&SMALL.replace("[variables]", "samples = 0\n[variables]")).unwrap_err();
        assert!(e.starts_with("samples: must be ≥ 1"), "{e}");
    }

    #[test]
    fn a_coupled_dynamics_setting_is_refused_naming_the_key() {
        let text = SMALL.replace(
            "\"posts.array=0.4mm\"]",
            "\"posts.array=0.4mm\", \"model.dynamics=coupled\"]",
        );
        let dir = tempfile::tempdir().unwrap();
        let e = run_design(&parse(&text).unwrap(), dir.path(), false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("model.dynamics"), "{e}");
        assert!(
            !dir.path().join("small").exists(),
            "a refused design run wrote no results"
        );
    }

    #[test]
    fn an_infeasible_constraint_set_is_reported_naming_the_constraints() {
        // 40 µm pitch and diameters of 30–35 µm leave gaps of at most 10 µm < 20 µm; preload
        // ≥ 10 N above the 5 N limit.
        let text = SMALL.replace(
            "preload = [\"1 N\", \"4 N\"]",
            "preload = [\"10 N\", \"20 N\"]\npost_diameter = [\"30 um\", \"35 um\"]",
        ) + "[constraints]\nmin_gap = \"20 um\"\nmax_preload = \"5 N\"\n";
        let dir = tempfile::tempdir().unwrap();
        let e = run_design(&parse(&text).unwrap(), dir.path(), false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("infeasible"), "{e}");
        assert!(
            e.contains("constraints.min_gap") && e.contains("constraints.max_preload"),
            "{e}"
        );
    }
}
