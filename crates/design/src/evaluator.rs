//! The seam between the studies (this crate) and the motor model (the `sawdrive` library):
//! the [`Evaluator`] trait, and the values that cross it — one sample's inputs
//! ([`MotorSample`]), one evaluation's outputs ([`MotorOutputs`]), the static model's
//! [`Fidelity`] and what a study reads of a scene ([`SceneFacts`]).
//!
//! Model: an evaluation maps a scene perturbed by one sample (preload P, post diameter d,
//! μ_s, μ_k, tilt τ_x, τ_y, bow b, σ of the post heights and their seed) to η, the stall thrust,
//! the no-load speed, the largest output power along the speed–thrust curve and the largest
//! efficiency. It must be deterministic: the same scene and sample give bitwise the same
//! outputs, on any thread — the studies' reproducibility and resume rest on it.
//!
//! Units: SI in every value that crosses the seam. Human values of the input files ("20 um",
//! "2 N") are parsed by the evaluator, by scene key ([`Evaluator::quantity`]): the units have
//! one home, the library's scene reader (`sawdrive::units`), which knows the dimension of every
//! scene key; this crate never parses a unit. (Moving the units into a crate below both would
//! split the scene's own quantity types from the scene reader that owns them.)

use std::path::Path;

use serde::{Deserialize, Serialize};

/// A boxed error of the evaluator (the library's scene or pipeline error), kept as the source.
pub type ModelError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// Which static model computed η.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Fidelity {
    /// η given by the scene (no static solve).
    Given,
    /// A band of rows of the lattice model (cheap).
    Patch,
    /// Every post of the lattice model.
    Slider,
}

impl Fidelity {
    /// Label written next to every number.
    pub fn label(self) -> &'static str {
        match self {
            Self::Given => "given-eta",
            Self::Patch => "lattice-patch",
            Self::Slider => "lattice-slider",
        }
    }
}

/// One sample's (or design's) values of the scattered inputs, SI.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MotorSample {
    /// Preload P (N).
    pub preload_n: f64,
    /// Post diameter (m).
    pub post_diameter_m: f64,
    /// μ_s.
    pub mu_static: f64,
    /// μ_k (≤ μ_s).
    pub mu_kinetic: f64,
    /// Tilt τ_x (m).
    pub tilt_x_m: f64,
    /// Tilt τ_y (m).
    pub tilt_y_m: f64,
    /// Bow b (m).
    pub bow_m: f64,
    /// σ of the per-post height scatter (m).
    pub height_scatter_m: f64,
    /// Seed of this sample's post heights.
    pub scatter_seed: u64,
}

impl MotorSample {
    /// The scene's own values, ideal posts.
    pub fn nominal(facts: &SceneFacts) -> Self {
        Self {
            preload_n: facts.preload_n,
            post_diameter_m: facts.post_diameter_m,
            mu_static: facts.mu_static,
            mu_kinetic: facts.mu_kinetic,
            tilt_x_m: 0.0,
            tilt_y_m: 0.0,
            bow_m: 0.0,
            height_scatter_m: 0.0,
            scatter_seed: 0,
        }
    }

    /// Whether the sample changes the slider's shape (tilt, bow or post heights).
    pub fn has_shape(&self) -> bool {
        self.tilt_x_m != 0.0
            || self.tilt_y_m != 0.0
            || self.bow_m != 0.0
            || self.height_scatter_m != 0.0
    }
}

/// Where one evaluation's time went (s), measured on its own thread.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct EvaluationCost {
    /// Post offsets, operator (when built), contact solves of every phase and the η fit.
    pub static_s: f64,
    /// The part of `static_s` that built this evaluation's own operator (0: shared).
    #[serde(default)]
    pub operator_s: f64,
    /// Springs and the dynamic speed–thrust curve.
    pub dynamic_s: f64,
    /// Whether this evaluation built its own lattice operator (another post diameter).
    pub operator_built: bool,
    /// The coupled model's share of `dynamic_s` (all 0 when the lumped model ran).
    #[serde(default)]
    pub coupled: CoupledCost,
}

/// Where a coupled evaluation's dynamic time went (s, wall on its thread).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct CoupledCost {
    /// The normal contact of every post at every time step's phase.
    pub normal_grid_s: f64,
    /// The stall point.
    pub stall_s: f64,
    /// The no-load speed's search.
    pub no_load_s: f64,
    /// The remaining curve points.
    pub points_s: f64,
    /// Wave periods stepped at the solved points (the no-load search's not counted).
    pub periods: usize,
}

/// One point of a speed–thrust curve (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CurvePoint {
    /// Slider speed (m/s).
    pub speed_m_per_s: f64,
    /// Thrust (N).
    pub thrust_n: f64,
    /// Output power over the power the stator delivers through the contacts at this speed
    /// (0 where there is no output): at most 1 on every model's curve.
    pub efficiency: f64,
}

/// The outputs of one evaluation (SI, unit in the name).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MotorOutputs {
    /// η.
    pub effective_contact_ratio: f64,
    /// Stall thrust (N).
    pub stall_thrust_n: f64,
    /// No-load speed (m/s).
    pub no_load_speed_m_per_s: f64,
    /// Largest thrust × speed along the curve (W).
    pub max_output_power_w: f64,
    /// Largest efficiency along the curve.
    pub efficiency: f64,
    /// Fraction of posts in contact (mean over phases; `None` when η was given).
    pub contact_fraction: Option<f64>,
    /// The speed–thrust curve.
    pub curve: Vec<CurvePoint>,
    /// The dynamic model that ran: `"lumped"` (period average or transient on N_eff = η·N) or
    /// `"coupled"` (every post of the whole slider).
    pub dynamics_model: &'static str,
    /// Why that model ran (`model.dynamics`, or the criterion's estimate under `auto`).
    pub dynamics_reason: String,
    /// Where the evaluation's time went.
    pub cost: EvaluationCost,
}

/// Output names (with units) in the order of [`MotorOutputs::values`].
pub const OUTPUT_NAMES: [&str; 5] = [
    "effective_contact_ratio",
    "stall_thrust_n",
    "no_load_speed_m_per_s",
    "max_output_power_w",
    "efficiency",
];

impl MotorOutputs {
    /// The scalar outputs in the order of [`OUTPUT_NAMES`].
    pub fn values(&self) -> [f64; 5] {
        [
            self.effective_contact_ratio,
            self.stall_thrust_n,
            self.no_load_speed_m_per_s,
            self.max_output_power_w,
            self.efficiency,
        ]
    }
}

/// What the studies read of a resolved scene (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneFacts {
    /// The scene's name (results folder `OUT/<name>-uq/`).
    pub name: String,
    /// Preload (N).
    pub preload_n: f64,
    /// Post diameter (m).
    pub post_diameter_m: f64,
    /// Post height h (m).
    pub post_height_m: f64,
    /// Posts along x and y.
    pub posts: [u32; 2],
    /// Post pitch along x and y (m).
    pub pitch_m: [f64; 2],
    /// Extent of the post array along x and y (m).
    pub array_m: [f64; 2],
    /// μ_s and μ_k.
    pub mu_static: f64,
    /// μ_k.
    pub mu_kinetic: f64,
    /// The largest friction coefficient the scene accepts.
    pub max_friction: f64,
    /// The scene's fixed tilt τ_x, τ_y and bow b (m).
    pub tilt_x_m: f64,
    /// Tilt τ_y (m).
    pub tilt_y_m: f64,
    /// Bow (m).
    pub bow_m: f64,
    /// The scene's σ of the post heights (`posts.height_scatter`, m).
    pub height_scatter_m: f64,
    /// Whether the scene gives a measured height map (`posts.height_map`).
    pub has_height_map: bool,
}

/// A design variable the scene can express, as the evaluator describes it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VariableKind {
    /// Its name in reports and result tables, SI with the unit (`post_diameter_m`).
    pub report_name: &'static str,
    /// Whether it takes whole values (a post count per side).
    pub integer: bool,
}

/// The motor model a study runs on: implemented once by the `sawdrive` library
/// (`sawdrive::pipeline::evaluate`), used by [`crate::uq`] and [`crate::study`].
pub trait Evaluator: Sync {
    /// A resolved scene (SI).
    type Scene: Clone + Send + Sync;
    /// The static model of one scene at one fidelity, built once and shared by its samples.
    type Prepared: Send + Sync;

    /// Reads the scene `path` (the embedded default scene for `None`) with `--set` overrides.
    fn load_scene(&self, path: Option<&Path>, set: &[String]) -> Result<Self::Scene, ModelError>;
    /// Reads a scene file's text (already without its `[scatter]` section) as if from `path`
    /// (relative paths in it resolve against the file's folder).
    fn load_scene_text(
        &self,
        file: Option<(&Path, &str)>,
        set: &[String],
    ) -> Result<Self::Scene, ModelError>;
    /// Reads a scene file's text (bounded, regular files only).
    fn read_scene_file(&self, path: &Path) -> Result<String, ModelError>;
    /// What a study reads of `scene`.
    fn facts(&self, scene: &Self::Scene) -> SceneFacts;
    /// The resolved scene as bytes (its JSON), part of the resume keys of saved samples and
    /// evaluations.
    fn scene_bytes(&self, scene: &Self::Scene) -> Result<Vec<u8>, ModelError>;
    /// The versions of the models behind an evaluation as bytes (a new version makes saved
    /// samples and evaluations stale).
    fn model_versions(&self) -> Vec<u8>;
    /// Refuses the scene's settings a study could not honour, naming the key.
    fn check_study(&self, scene: &Self::Scene) -> Result<(), ModelError>;
    /// One sentence: which dynamic model a study's evaluations of `scene` run and how it is
    /// chosen (once for the scene, or per sample).
    fn dynamics_policy(&self, scene: &Self::Scene) -> String;

    /// The human value `text` of scene key `key` ("20 um" for `posts.diameter`) in SI.
    fn quantity(&self, key: &str, text: &str) -> Result<f64, ModelError>;
    /// An example of a value of scene key `key` with its unit, for messages (`"20 um"`).
    fn example(&self, key: &str) -> &'static str;
    /// `value` (SI) of a quantity of scene key `key`, written with its unit for people.
    fn describe(&self, key: &str, value: f64) -> String;
    /// The design variable of scene key `key` (`None`: not a variable a design can set).
    fn variable(&self, key: &str) -> Option<VariableKind>;
    /// The `--set` override giving scene key `key` the value `value` (SI).
    fn set_variable(&self, key: &str, value: f64) -> String;
    /// The scene's own value of design variable `key` (SI).
    fn variable_value(&self, scene: &Self::Scene, key: &str) -> f64;

    /// Builds the static model of `scene` at `fidelity` (the fidelity of the result may be
    /// [`Fidelity::Given`] when the scene gives η).
    fn prepare(
        &self,
        scene: &Self::Scene,
        fidelity: Fidelity,
    ) -> Result<Self::Prepared, ModelError>;
    /// The fidelity the numbers of `prepared` carry.
    fn fidelity(&self, prepared: &Self::Prepared) -> Fidelity;
    /// Evaluates `scene` perturbed by `sample` with its prepared static model.
    fn evaluate(
        &self,
        prepared: &Self::Prepared,
        scene: &Self::Scene,
        sample: &MotorSample,
    ) -> Result<MotorOutputs, ModelError>;
}
