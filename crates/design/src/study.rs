//! `sawdrive design DESIGN.toml`: a texture optimised for one output of the motor,
//! optionally robust to scatter (a quantile over Monte Carlo samples), searched with the cheap
//! `lattice-patch` model and confirmed with the whole-slider `lattice-slider` model
//! ([`crate::multi_fidelity`]; method and tolerance in [`optimise`](mod@crate::optimise)). The motor model is
//! the [`crate::Evaluator`] (the `sawdrive` library's, `SceneEvaluator`).
//!
//! ```toml
//! name = "texture"                  # results folder OUT/<name>/
//! scene = "motor.toml"              # optional, relative to this file (default: embedded scene)
//! objective = "max_output_power_w"  # effective_contact_ratio | stall_thrust_n |
//!                                   # no_load_speed_m_per_s | max_output_power_w | efficiency
//! sense = "maximise"                # or "minimise"
//! quantile = 0.05                   # optional: robust objective, this quantile under [scatter]
//! samples = 16                      # Monte Carlo samples per design at full fidelity
//! cheap_samples = 4                 # … at the cheap fidelity
//! seed = 1
//!
//! [set]                             # optional scene overrides, by scene key (a table)
//! "wave.normal_amplitude" = "20 nm"
//!
//! [variables]                       # any subset, by scene key; [lower, upper] with units
//! "posts.diameter" = ["10 um", "60 um"]
//! "posts.count" = [20, 200]         # posts per side of a square array, pitch = posts.array / count
//! "posts.height" = ["1 um", "4 um"]
//! "load.preload" = ["10 N", "100 N"]
//!
//! [constraints]                     # any subset
//! min_gap = "5 um"                  # pitch − diameter ≥ min_gap
//! contact_area_fraction = [0.05, 0.6]   # N π d²/4 over the array area
//! max_preload = "100 N"
//!
//! [scatter]                         # as in `sawdrive uq` (needed with `quantile`)
//! posts.height_scatter = "5 nm"
//!
//! [optimiser]                       # design::OptimiserSettings; all optional
//! presearch_points = 24
//! starts = 2
//! max_evaluations_per_start = 30
//! x_tolerance = 0.01
//! finalists = 3
//! refine_evaluations = 20           # full-fidelity compass search from the best finalist (0: off)
//! ```
//!
//! The former spellings are refused, each naming its scene key: the variables `post_diameter`,
//! `posts_per_side`, `post_height`, `preload` ([`RENAMED_VARIABLES`]), a `set` list of
//! `"key=value"` strings, and the `[scatter]` keys of [`crate::scatter::RENAMED_SCATTER_KEYS`].
//! Report names stay SI with their unit (`post_diameter_m`, `posts_per_side`, `post_height_m`,
//! `preload_n`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::StudyError;
use crate::evaluator::{Evaluator, Fidelity, MotorSample, OUTPUT_NAMES, SceneFacts};
use crate::files::{staged_results, write_atomically};
use crate::scatter::{Quantity, ScatterSpec, dotted_keys};
use crate::uq::MAX_SAMPLES;
use crate::{
    Evaluation, Objective, OptimiserSettings, Outcome, Sense, Variable, VariableSensitivity,
    draw_inputs, local_sensitivity, multi_fidelity, pareto_front, percentile,
};

/// Version of the saved evaluations' layout (part of their key).
const EVALUATION_FORMAT: u32 = 1;

/// Relative step of the optimum's sensitivity (fraction of each variable's range).
const SENSITIVITY_STEP: f64 = 0.05;

/// The design variables, by the scene key each sets, in the order the optimiser's unit box
/// takes them whatever the file's order (the search path, and so the optimum found within the
/// tolerance, depends on it): diameter, height, count per side, preload. The evaluator says
/// what each is (its unit, whether it is a count, its name in reports: `posts.diameter` →
/// `post_diameter_m`).
const VARIABLES: [&str; 4] = [
    "posts.diameter",
    "posts.height",
    "posts.count",
    "load.preload",
];

/// The former names of the design variables and their scene keys (refused, naming the new one).
pub const RENAMED_VARIABLES: [(&str, &str); 4] = [
    ("post_diameter", "posts.diameter"),
    ("posts_per_side", "posts.count"),
    ("post_height", "posts.height"),
    ("preload", "load.preload"),
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
    pub scene_keys: Vec<String>,
    /// Constraints.
    pub constraints: Constraints,
    /// Scatter.
    pub scatter: ScatterSpec,
    /// Optimiser settings.
    pub optimiser: OptimiserSettings,
}

/// A design file as written (module doc): every table refuses unknown keys, each entry under
/// its scene key. Quantities keep their text ([`Quantity`]) until the evaluator parses them as
/// their scene key; counts are whole numbers.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignFile {
    /// Results folder name (default `design`).
    pub name: Option<String>,
    /// Scene file, relative to the design file.
    pub scene: Option<PathBuf>,
    /// Scene overrides: a table of scene keys (checked by `scene_overrides`).
    pub set: Option<toml::Value>,
    /// Output optimised (default `max_output_power_w`).
    pub objective: Option<String>,
    /// `maximise` (default) or `minimise`.
    pub sense: Option<Sense>,
    /// Robust quantile under `[scatter]`.
    pub quantile: Option<f64>,
    /// Full-fidelity samples per design (default 16).
    pub samples: Option<u64>,
    /// Cheap-fidelity samples per design (default 4).
    pub cheap_samples: Option<u64>,
    /// Seed of the scatter (default 1).
    pub seed: Option<u64>,
    /// The design variables.
    #[serde(default)]
    pub variables: VariablesFile,
    /// Fabrication constraints.
    #[serde(default)]
    pub constraints: ConstraintsFile,
    /// The scatter, as in `sawdrive uq` ([`ScatterSpec::from_table`]).
    #[serde(default)]
    pub scatter: toml::Table,
    /// Optimiser settings.
    #[serde(default)]
    pub optimiser: OptimiserFile,
}

/// `[variables]`: `[lower, upper]` of each scene key that varies.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariablesFile {
    /// `posts.diameter`, `posts.height`, `posts.count`.
    #[serde(default)]
    pub posts: PostVariables,
    /// `load.preload`.
    #[serde(default)]
    pub load: LoadVariables,
}

/// `[variables]` under `posts`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PostVariables {
    /// Post diameter bounds.
    pub diameter: Option<[Quantity; 2]>,
    /// Post height bounds.
    pub height: Option<[Quantity; 2]>,
    /// Posts per side of a square array.
    pub count: Option<[u64; 2]>,
}

/// `[variables]` under `load`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadVariables {
    /// Preload bounds.
    pub preload: Option<[Quantity; 2]>,
}

/// `[constraints]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintsFile {
    /// pitch − diameter ≥ this.
    pub min_gap: Option<Quantity>,
    /// N π d²/4 over the array area within [lo, hi].
    pub contact_area_fraction: Option<[f64; 2]>,
    /// Preload ≤ this.
    pub max_preload: Option<Quantity>,
}

/// `[optimiser]`: [`OptimiserSettings`], each absent one its default.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptimiserFile {
    pub presearch_points: Option<u64>,
    pub starts: Option<u64>,
    pub max_evaluations_per_start: Option<u64>,
    pub finalists: Option<u64>,
    pub refine_evaluations: Option<u64>,
    pub seed: Option<u64>,
    pub x_tolerance: Option<f64>,
}

fn err(key: &str, message: impl std::fmt::Display) -> StudyError {
    StudyError::input(key, message)
}

/// The quantity `q` of design-file key `key`, parsed by the evaluator as scene key `scene_key`.
fn quantity<E: Evaluator>(
    ev: &E,
    q: &Quantity,
    key: &str,
    scene_key: &str,
) -> Result<f64, StudyError> {
    ev.quantity(scene_key, &q.0).map_err(|e| err(key, e))
}

/// The variables given, in the order of [`VARIABLES`], with their SI bounds.
fn parse_variables<E: Evaluator>(
    ev: &E,
    v: &VariablesFile,
) -> Result<(Vec<Variable>, Vec<String>), StudyError> {
    let mut vars = Vec::new();
    let mut keys = Vec::new();
    let count = |[a, b]: [u64; 2]| (a as f64, b as f64);
    let given: [(&str, Option<(f64, f64)>); 4] = {
        let bounds = |q: &Option<[Quantity; 2]>, key: &str| -> Result<_, StudyError> {
            let full = format!("variables.{key}");
            q.as_ref()
                .map(|[a, b]| Ok((quantity(ev, a, &full, key)?, quantity(ev, b, &full, key)?)))
                .transpose()
        };
        let [d, h, n, p] = VARIABLES;
        [
            (d, bounds(&v.posts.diameter, d)?),
            (h, bounds(&v.posts.height, h)?),
            (n, v.posts.count.map(count)),
            (p, bounds(&v.load.preload, p)?),
        ]
    };
    for (scene_key, bounds) in given {
        let Some((lower, upper)) = bounds else {
            continue;
        };
        let full = format!("variables.{scene_key}");
        let kind = ev
            .variable(scene_key)
            .ok_or_else(|| err(&full, "not a design variable of this motor model"))?;
        let v = Variable {
            name: kind.report_name.to_owned(),
            lower,
            upper,
            integer: kind.integer,
        };
        v.validate().map_err(|e| {
            StudyError::Conflict(
                e.to_string()
                    .replace(&format!("variables.{}", kind.report_name), &full),
            )
        })?;
        vars.push(v);
        keys.push(scene_key.to_owned());
    }
    if vars.is_empty() {
        return Err(err("variables", "give at least one design variable"));
    }
    Ok((vars, keys))
}

fn parse_constraints<E: Evaluator>(ev: &E, c: &ConstraintsFile) -> Result<Constraints, StudyError> {
    let contact_area_fraction = match c.contact_area_fraction {
        Some([lo, hi]) if !(0.0..=1.0).contains(&lo) || !(0.0..=1.0).contains(&hi) || lo > hi => {
            return Err(err(
                "constraints.contact_area_fraction",
                format!("[{lo}, {hi}] must be an interval within [0, 1]"),
            ));
        }
        other => other,
    };
    Ok(Constraints {
        min_gap_m: c
            .min_gap
            .as_ref()
            .map(|q| quantity(ev, q, "constraints.min_gap", "posts.diameter"))
            .transpose()?,
        contact_area_fraction,
        max_preload_n: c
            .max_preload
            .as_ref()
            .map(|q| quantity(ev, q, "constraints.max_preload", "load.preload"))
            .transpose()?,
    })
}

fn parse_optimiser(o: &OptimiserFile) -> Result<OptimiserSettings, StudyError> {
    let mut s = OptimiserSettings::default();
    let size = |v: Option<u64>, default: usize| v.map_or(default, |n| n as usize);
    s.presearch_points = size(o.presearch_points, s.presearch_points);
    s.starts = size(o.starts, s.starts);
    s.max_evaluations_per_start = size(o.max_evaluations_per_start, s.max_evaluations_per_start);
    s.finalists = size(o.finalists, s.finalists);
    s.refine_evaluations = size(o.refine_evaluations, s.refine_evaluations);
    s.seed = o.seed.unwrap_or(s.seed);
    s.x_tolerance = o.x_tolerance.unwrap_or(s.x_tolerance);
    s.validate()
        .map_err(|e| StudyError::Conflict(e.to_string()))?;
    Ok(s)
}

/// The `set` table of scene overrides (`[set]` with `"posts.count" = "10x10"`, dotted or
/// quoted scene keys, values as in a scene file) as `--set` lines. The former list of
/// `"key=value"` strings is refused, naming the table form.
fn scene_overrides(value: &toml::Value) -> Result<Vec<String>, StudyError> {
    let table = match value {
        toml::Value::Table(t) => t,
        toml::Value::Array(_) => {
            return Err(err(
                "set",
                "a list of \"key=value\" is the former spelling; write a table of scene keys: \
                 [set] with \"posts.count\" = \"10x10\" (or set = { \"posts.count\" = \"10x10\" })",
            ));
        }
        other => {
            return Err(err(
                "set",
                format!("expected a table of scene keys, got {other}"),
            ));
        }
    };
    dotted_keys(table)
        .into_iter()
        .map(|(key, v)| match v {
            toml::Value::String(text) => Ok(format!("{key}={text}")),
            toml::Value::Integer(_) | toml::Value::Float(_) | toml::Value::Boolean(_) => {
                Ok(format!("{key}={v}"))
            }
            other => Err(err(
                &format!("set.{key}"),
                format!("expected a text, number or true/false, got {other}"),
            )),
        })
        .collect()
}

/// A sample count (`samples`, `cheap_samples`) in 1..=[`MAX_SAMPLES`].
fn sample_count(n: Option<u64>, default: usize, key: &str) -> Result<usize, StudyError> {
    let Some(n) = n else {
        return Ok(default);
    };
    if n == 0 {
        return Err(err(key, "must be ≥ 1"));
    }
    if n > MAX_SAMPLES as u64 {
        return Err(err(
            key,
            format!("{n} is more than the {MAX_SAMPLES} accepted"),
        ));
    }
    Ok(n as usize)
}

/// The old spellings of design-file keys, refused naming the new one.
fn renamed_design_keys() -> Vec<(String, String)> {
    RENAMED_VARIABLES
        .iter()
        .map(|(old, new)| {
            (
                format!("variables.{old}"),
                format!("\"{new}\" = [lower, upper]: design variables are named by the scene key they set"),
            )
        })
        .chain(crate::scatter::RENAMED_SCATTER_KEYS.iter().map(|(old, new)| {
            (
                format!("scatter.{old}"),
                format!("scatter.{new} (`{new} = …` in [scatter]): scatter entries are named by the scene key they spread"),
            )
        }))
        .collect()
}

impl DesignSpec {
    /// Reads and checks a design file; errors are one line naming the file and the key.
    pub fn read<E: Evaluator>(ev: &E, path: &Path) -> Result<Self, StudyError> {
        let text = atomic_files::read_input_text(path, atomic_files::MAX_SETTINGS_FILE_BYTES)?;
        Self::parse(ev, &text, path.parent().unwrap_or(Path::new("."))).map_err(|e| {
            StudyError::File {
                path: path.to_owned(),
                source: Box::new(e),
            }
        })
    }

    /// Parses a design file's text into [`DesignFile`] ([`motor::input`]: the scene's reader);
    /// a relative `scene` is taken relative to `base`. Quantities are parsed by `ev`, as the
    /// scene key they set.
    pub fn parse<E: Evaluator>(ev: &E, text: &str, base: &Path) -> Result<Self, StudyError> {
        let table = motor::input::parse_table(text).map_err(|e| StudyError::Conflict(e.message))?;
        let renamed = renamed_design_keys();
        let renamed: Vec<(&str, &str)> = renamed
            .iter()
            .map(|(o, n)| (o.as_str(), n.as_str()))
            .collect();
        if let Some(e) = motor::input::first_moved(&table, &renamed) {
            return Err(err(&e.field, format!("renamed: {}", e.message)));
        }
        if let Some(set) = table.get("set") {
            scene_overrides(set)?;
        }
        let mut table = table;
        for section in ["variables", "constraints", "optimiser"] {
            if let Some(toml::Value::Table(t)) = table.get_mut(section) {
                *t = motor::input::nest_dotted_keys(t);
            }
        }
        let file: DesignFile =
            motor::input::from_table(table).map_err(|e| err(&e.field, e.message))?;
        Self::from_file(ev, file, base)
    }

    /// Checks a [`DesignFile`] and converts it to SI.
    fn from_file<E: Evaluator>(ev: &E, file: DesignFile, base: &Path) -> Result<Self, StudyError> {
        let name = file.name.unwrap_or_else(|| "design".into());
        atomic_files::check_name(&name).map_err(|e| err("name", e))?;
        let output = file
            .objective
            .unwrap_or_else(|| "max_output_power_w".into());
        if !OUTPUT_NAMES.contains(&output.as_str()) {
            return Err(err(
                "objective",
                format!(
                    "unknown output \"{output}\" (known: {})",
                    OUTPUT_NAMES.join(", ")
                ),
            ));
        }
        if let Some(q) = file.quantile.filter(|q| !(0.0..=1.0).contains(q)) {
            return Err(err("quantile", format!("{q} outside [0, 1]")));
        }
        let mut spec = Self {
            name,
            scene: file.scene.map(|s| base.join(s)),
            set: file
                .set
                .as_ref()
                .map(scene_overrides)
                .transpose()?
                .unwrap_or_default(),
            objective: Objective {
                output,
                sense: file.sense.unwrap_or(Sense::Maximise),
            },
            quantile: file.quantile,
            samples: sample_count(file.samples, 16, "samples")?,
            cheap_samples: sample_count(file.cheap_samples, 4, "cheap_samples")?,
            seed: file.seed.unwrap_or(1),
            variables: Vec::new(),
            scene_keys: Vec::new(),
            // The settings first, the design space last: a refused setting is named even in a
            // file whose variables are refused too.
            optimiser: parse_optimiser(&file.optimiser)?,
            constraints: parse_constraints(ev, &file.constraints)?,
            scatter: ScatterSpec::from_table(ev, &file.scatter)?,
        };
        if spec.quantile.is_none() && spec.scatter != ScatterSpec::default() {
            return Err(err(
                "scatter",
                "a [scatter] section needs `quantile` (the robust objective), else it would be ignored",
            ));
        }
        if spec.quantile.is_some() && spec.scatter == ScatterSpec::default() {
            return Err(err(
                "quantile",
                "needs a [scatter] section (a quantile of identical samples is the nominal value), else it would be ignored",
            ));
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
        (spec.variables, spec.scene_keys) = parse_variables(ev, &file.variables)?;
        Ok(spec)
    }

    /// The scene of design `x`.
    pub fn scene_at<E: Evaluator>(&self, ev: &E, x: &[f64]) -> Result<E::Scene, StudyError> {
        let mut set = self.set.clone();
        for (key, value) in self.scene_keys.iter().zip(x) {
            set.push(ev.set_variable(key, *value));
        }
        ev.load_scene(self.scene.as_deref(), &set)
            .map_err(StudyError::Model)
    }

    /// Violations of the constraints by the scene of `facts` (relative amounts).
    fn violations(&self, facts: &SceneFacts) -> Vec<(String, f64)> {
        let c = &self.constraints;
        let diameter_m = facts.post_diameter_m;
        let mut v = Vec::new();
        if let Some(g) = c.min_gap_m {
            let gap = facts.pitch_m[0].min(facts.pitch_m[1]) - diameter_m;
            if gap < g {
                v.push((
                    "constraints.min_gap".to_owned(),
                    (g - gap) / g.max(diameter_m),
                ));
            }
        }
        if let Some([lo, hi]) = c.contact_area_fraction {
            let count = u64::from(facts.posts[0]) * u64::from(facts.posts[1]);
            let a = count as f64 * std::f64::consts::PI * diameter_m.powi(2)
                / 4.0
                / (facts.array_m[0] * facts.array_m[1]);
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
            && facts.preload_n > m
        {
            v.push((
                "constraints.max_preload".to_owned(),
                (facts.preload_n - m) / m.max(1e-12),
            ));
        }
        v
    }

    /// The model at `fidelity`: constraints, then the nominal outputs or their quantile over
    /// `samples` scatter samples.
    fn model<E: Evaluator>(
        &self,
        ev: &E,
        x: &[f64],
        fidelity: Fidelity,
        samples: usize,
    ) -> Result<Outcome, StudyError> {
        let scene = self.scene_at(ev, x)?;
        let facts = ev.facts(&scene);
        let violations = self.violations(&facts);
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
        let model = ev.prepare(&scene, fidelity).map_err(StudyError::Model)?;
        let runs: Vec<[f64; 5]> = match self.quantile {
            None => vec![
                ev.evaluate(&model, &scene, &MotorSample::nominal(&facts))
                    .map_err(StudyError::Model)?
                    .values(),
            ],
            Some(_) => {
                let inputs = self.scatter.inputs(&facts)?;
                (0..samples as u64)
                    .into_par_iter()
                    .map(|i| {
                        let (values, field_seed) = draw_inputs(&inputs, self.seed, i);
                        ev.evaluate(&model, &scene, &self.scatter.sample(&values, field_seed))
                            .map(|o| o.values())
                            .map_err(StudyError::Model)
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
                percentile(&col, q, name).map_err(|e| StudyError::Conflict(e.to_string()))?,
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
    fn evaluation_key<E: Evaluator>(
        &self,
        ev: &E,
        x: &[f64],
        fidelity: Fidelity,
        samples: usize,
    ) -> Result<String, StudyError> {
        let scene = self.scene_at(ev, x)?;
        let mut h = Sha256::new();
        h.update(ev.scene_bytes(&scene).map_err(StudyError::Model)?);
        h.update(fidelity.label().as_bytes());
        h.update(samples.to_le_bytes());
        h.update(format!("{:?}", self.quantile).as_bytes());
        h.update(serde_json::to_vec(&self.scatter)?);
        h.update(self.seed.to_le_bytes());
        h.update(serde_json::to_vec(&self.objective)?);
        h.update(serde_json::to_vec(&self.constraints)?);
        h.update(ev.model_versions());
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
struct ResumableModel<'a, E> {
    ev: &'a E,
    spec: &'a DesignSpec,
    fidelity: Fidelity,
    samples: usize,
    cache: &'a Path,
    /// Evaluations (count, summed seconds) computed, by fidelity label; and reused.
    timing: &'a std::sync::Mutex<BTreeMap<String, (usize, f64)>>,
    resumed: &'a std::sync::atomic::AtomicUsize,
}

impl<E: Evaluator> ResumableModel<'_, E> {
    /// The outcome of design `x`, saved or computed.
    fn call(&self, x: &[f64]) -> Result<Outcome, StudyError> {
        let path = self.cache.join(format!(
            "{}.json",
            self.spec
                .evaluation_key(self.ev, x, self.fidelity, self.samples)?
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
        let outcome = self.spec.model(self.ev, x, self.fidelity, self.samples)?;
        if let Ok(mut m) = self.timing.lock() {
            let e = m.entry(self.fidelity.label().to_owned()).or_default();
            e.0 += 1;
            e.1 += t.elapsed().as_secs_f64();
        }
        if outcome.objective.is_finite() {
            write_atomically(&path, serde_json::to_vec(&outcome)?)?;
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
    /// The dynamic model of the evaluations and how it is chosen (`model.dynamics`).
    pub dynamics: String,
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

/// The optimum found: its variables by report name, the objective and the outputs.
fn optimum(spec: &DesignSpec, best: &Evaluation) -> Optimum {
    Optimum {
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
    }
}

/// Per fidelity: the evaluations computed and their mean cost (s).
fn mean_costs(timing: BTreeMap<String, (usize, f64)>) -> Vec<(String, usize, f64)> {
    timing
        .into_iter()
        .map(|(k, (n, s))| (k, n, if n > 0 { s / n as f64 } else { 0.0 }))
        .collect()
}

/// Runs the design study; writes `OUT/<name>/` when complete.
pub fn run_design<E: Evaluator>(
    ev: &E,
    spec: &DesignSpec,
    out_dir: &Path,
    write_files: bool,
) -> Result<(DesignReport, PathBuf), StudyError> {
    let start = Instant::now();
    let centre: Vec<f64> = spec.variables.iter().map(|v| v.at(0.5)).collect();
    let scene = spec.scene_at(ev, &centre).map_err(|e| StudyError::Study {
        stage: "design",
        message: e.to_string(),
    })?;
    ev.check_study(&scene).map_err(StudyError::Model)?;
    let staged = staged_results(&out_dir.join(&spec.name), "design")?;
    let timing = std::sync::Mutex::new(BTreeMap::<String, (usize, f64)>::new());
    let resumed = std::sync::atomic::AtomicUsize::new(0);
    let cache = out_dir.join(".design-evaluations");
    let timed = |fidelity: Fidelity, samples: usize| {
        let m = ResumableModel {
            ev,
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
    )?;
    let best = &result.best;
    let sensitivity = local_sensitivity(
        &spec.variables,
        &best.x,
        best.outcome.objective,
        SENSITIVITY_STEP,
        &full,
    )?;
    let baseline = baseline(ev, spec, &full);
    let cost = mean_costs(timing.into_inner().unwrap_or_default());
    let mut report = DesignReport {
        name: spec.name.clone(),
        optimum: optimum(spec, best),
        baseline,
        quantile: spec.quantile,
        dynamics: ev.dynamics_policy(&scene),
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
fn baseline<E, F>(ev: &E, spec: &DesignSpec, full: &F) -> Option<EvaluationRow>
where
    E: Evaluator,
    F: Fn(&[f64]) -> Result<Outcome, StudyError>,
{
    let scene = ev.load_scene(spec.scene.as_deref(), &spec.set).ok()?;
    let x: Vec<f64> = spec
        .scene_keys
        .iter()
        .map(|key| ev.variable_value(&scene, key))
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
fn write_design_files(report: &DesignReport, dir: &Path) -> Result<Vec<String>, StudyError> {
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

/// Human form of the optimum's variables (named as in the report, in its order), each
/// quantity with its unit as the evaluator writes the scene key it sets.
pub fn describe_variables<E: Evaluator>(
    ev: &E,
    spec: &DesignSpec,
    variables: &BTreeMap<String, f64>,
) -> String {
    variables
        .iter()
        .map(|(k, v)| {
            let found = spec
                .variables
                .iter()
                .zip(&spec.scene_keys)
                .find(|(var, _)| &var.name == k);
            match found {
                Some((var, key)) if !var.integer => format!("{k} = {}", ev.describe(key, *v)),
                _ => format!("{k} = {v}"),
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}
