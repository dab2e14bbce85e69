//! One motor evaluation for Monte Carlo and design: a scene with one sample's perturbations →
//! whole-slider static contact (η, `slider_contact`, no FEM: the lattice operator with Johnson's
//! near field) → Johnson springs → period-average/transient speed–thrust curve (`stick_slip`)
//! → η, stall thrust, no-load speed, maximum output power, efficiency.
//!
//! Fidelities ([`Fidelity`]): `slider` resolves every post of the scene's array; `patch` solves
//! a band of [`PATCH_ROWS`] full-length rows (all posts along the wave, preload scaled by the
//! rows' share), whose η is within ≈ 1 % of the whole slider's for identical rows
//! (validation/whole-slider: 0.8265 at 10 rows vs 0.8160 at 100) at ≈ 1/10 of the cost; it does
//! not see a tilt across y. When the scene gives η as a number (`contact.effective_ratio`),
//! no static solve runs and height scatter, tilt and bow are refused (they could not act).

use contact_springs::PostSprings;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use slider_contact::{Imperfections, ImperfectionsExt, SliderModel, SliderParams};
use stick_slip::CurvePoint;

use crate::pipeline::{PipelineError, dynamic_scene, scene_springs};
use crate::scene::{Dynamics, Scene};

/// Rows of posts (along y) the `patch` fidelity solves.
pub const PATCH_ROWS: u32 = 8;

/// Which static model computed η.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Fidelity {
    /// η given by the scene (no static solve).
    Given,
    /// [`PATCH_ROWS`] rows of the lattice model.
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
    pub fn nominal(scene: &Scene) -> Self {
        Self {
            preload_n: scene.motor.load.preload_n,
            post_diameter_m: scene.motor.posts.diameter_m,
            mu_static: scene.motor.friction.mu_static,
            mu_kinetic: scene.motor.friction.mu_kinetic,
            tilt_x_m: 0.0,
            tilt_y_m: 0.0,
            bow_m: 0.0,
            height_scatter_m: 0.0,
            scatter_seed: 0,
        }
    }

    fn has_shape(&self) -> bool {
        self.tilt_x_m != 0.0
            || self.tilt_y_m != 0.0
            || self.bow_m != 0.0
            || self.height_scatter_m != 0.0
    }
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

/// The scene with a sample's preload, diameter and friction.
pub fn perturbed_scene(scene: &Scene, s: &MotorSample) -> Scene {
    let mut out = scene.clone();
    out.motor.load.preload_n = s.preload_n;
    out.motor.posts.diameter_m = s.post_diameter_m;
    out.motor.friction.mu_static = s.mu_static;
    out.motor.friction.mu_kinetic = s.mu_kinetic;
    out
}

/// The whole-slider parameters of `scene` (its lattice, materials, wave, preload and phases)
/// with imperfections `imperfections`; the solver and near field keep `SliderParams`' defaults.
pub fn slider_params(scene: &Scene, imperfections: Imperfections) -> SliderParams {
    SliderParams {
        phases: scene.static_fem.phases as usize,
        imperfections,
        ..SliderParams::for_motor(&scene.motor)
    }
}

/// The `patch` fidelity's parameters: [`PATCH_ROWS`] rows with the full slider's y margins,
/// the preload scaled by the rows' share.
fn patch_params(mut params: SliderParams) -> SliderParams {
    let rows = (PATCH_ROWS as usize).min(params.posts_y);
    let margin = params.slider_width_m - params.posts_y as f64 * params.post_pitch_m;
    params.preload_n *= rows as f64 / params.posts_y as f64;
    params.posts_y = rows;
    params.slider_width_m = rows as f64 * params.post_pitch_m + margin;
    params
}

/// The static model of one scene at one fidelity, built once and shared by every sample and
/// evaluation of that scene: the lattice operator C (the FFT spectrum of the kernel, docs/physics.md
/// §5) depends only on the lattice, the materials and the post diameter, so a sample that keeps
/// them (height scatter, tilt, bow, preload, μ) costs only its post offsets, the contact solves
/// of its phases and the η fit. A sample with another post diameter (the diameter tolerance)
/// changes C and builds its own operator (counted in [`EvaluationCost::operator_built`]).
#[derive(Debug)]
pub struct StaticModel {
    fidelity: Fidelity,
    /// The nominal scene's whole-slider model (`None`: η given by the scene).
    nominal: Option<SliderModel>,
}

impl StaticModel {
    /// Builds the operator of `scene` at `fidelity` (nothing when the scene gives η).
    pub fn build(scene: &Scene, fidelity: Fidelity) -> Result<Self, PipelineError> {
        if scene.contact.effective_ratio.is_some() {
            return Ok(Self {
                fidelity: Fidelity::Given,
                nominal: None,
            });
        }
        let params = fidelity_params(slider_params(scene, Imperfections::default()), fidelity);
        let nominal = SliderModel::build(&params).map_err(unsupported)?;
        Ok(Self {
            fidelity,
            nominal: Some(nominal),
        })
    }

    /// The fidelity its numbers carry.
    pub fn fidelity(&self) -> Fidelity {
        self.fidelity
    }

    /// The model of `params`: the shared operator when `params` has the nominal operator's
    /// inputs and a rigid back, else a fresh build. The checks are `SliderModel::build`'s.
    fn model_for(&self, params: SliderParams) -> Result<(SliderModel, bool), PipelineError> {
        let shared = self.nominal.as_ref().filter(|m| {
            !params.mechanism.is_free()
                && !m.params.mechanism.is_free()
                && m.params.operator_spec() == params.operator_spec()
        });
        let Some(shared) = shared else {
            return Ok((SliderModel::build(&params).map_err(unsupported)?, true));
        };
        params.validate().map_err(unsupported)?;
        let g = params.geometry();
        let post_offset_m = params
            .imperfections
            .post_offsets_m(&g)
            .map_err(unsupported)?;
        params
            .imperfections
            .check_body_clearance(&g, params.post_height_m, &post_offset_m)
            .map_err(unsupported)?;
        let model = SliderModel {
            params,
            operator: shared.operator.clone(),
            post_offset_m,
            free_back: None,
            build_s: 0.0,
            precondition_free_back: false,
        };
        Ok((model, false))
    }

    /// η, the contact fraction and the time spent building an operator (`None`: the shared one
    /// was used), for `scene` (already carrying the sample's preload, diameter and μ) with the
    /// sample's shape.
    fn eta(
        &self,
        scene: &Scene,
        s: &MotorSample,
    ) -> Result<(f64, Option<f64>, Option<f64>), PipelineError> {
        if let Some(eta) = scene.contact.effective_ratio {
            if s.has_shape() {
                return Err(PipelineError::Unsupported {
                    stage: "static",
                    message: format!(
                        "height scatter, tilt and bow act through the whole-slider static model, \
                         but contact.effective_ratio = {eta} is given: set effective_ratio = \
                         \"fem\" or drop the [scatter] height/tilt/bow keys"
                    ),
                });
            }
            return Ok((eta, None, None));
        }
        let imperfections = Imperfections {
            height_scatter_m: s.height_scatter_m,
            scatter_seed: s.scatter_seed,
            height_map: None,
            tilt_x_m: s.tilt_x_m,
            tilt_y_m: s.tilt_y_m,
            bow_m: s.bow_m,
        };
        let params = fidelity_params(slider_params(scene, imperfections), self.fidelity);
        let setup = Instant::now();
        let (model, built) = self.model_for(params)?;
        let operator_s = built.then(|| setup.elapsed().as_secs_f64());
        let report = model.analyse(model.params.preload_n).map_err(unsupported)?;
        let eta = report
            .effective_contact_ratio
            .ok_or_else(|| PipelineError::Unsupported {
                stage: "static (whole slider)",
                message: format!(
                    "η not identifiable ({})",
                    report
                        .eta_fit
                        .reason
                        .as_deref()
                        .unwrap_or("no reason given")
                ),
            })?;
        Ok((eta, Some(report.contact_fraction), operator_s))
    }
}

fn unsupported(e: slider_contact::SliderError) -> PipelineError {
    PipelineError::Unsupported {
        stage: "static (whole slider)",
        message: e.to_string(),
    }
}

/// `params` at `fidelity` (the patch's rows for [`Fidelity::Patch`]).
fn fidelity_params(params: SliderParams, fidelity: Fidelity) -> SliderParams {
    if fidelity == Fidelity::Patch {
        patch_params(params)
    } else {
        params
    }
}

/// Refuses the `[model]` settings that UQ and design could not honour, naming the key.
///
/// A sample or design evaluation is a whole-slider contact solve and a curve of the lumped
/// dynamic model (N_eff = η·N posts, `stick_slip`), never an FEM. The coupled model
/// (`coupled_dynamics`) runs on the strip FEM's tip compliances, which no sample has, so:
/// * `model.dynamics` = `periodic-average` or `transient`: used as given;
/// * `auto`: the lumped model (which picks the period average or the transient by their effect),
///   for the reason the pipeline's `auto` gives with a whole-slider static stage (its η carries
///   the imperfections, the coupled model the strip's ideal posts);
/// * `coupled`, and the keys only the coupled model or its choice use
///   (`model.lumped_tolerance`, `model.steps_per_period`): refused.
pub fn check_dynamics(scene: &Scene) -> Result<(), PipelineError> {
    let refuse = |message: String| {
        Err(PipelineError::Unsupported {
            stage: "uq/design",
            message,
        })
    };
    let m = &scene.model;
    if m.dynamics == Dynamics::Coupled {
        return refuse(
            "model.dynamics = \"coupled\" is not available to uq/design: a sample runs the \
             lumped model on the whole-slider η (the coupled model needs the strip FEM); set \
             \"auto\", \"periodic-average\" or \"transient\""
                .into(),
        );
    }
    if let Some(t) = m.lumped_tolerance {
        return refuse(format!(
            "model.lumped_tolerance = {t} is not used by uq/design: they always run the lumped \
             model (the coupled one needs the strip FEM); remove it (\"auto\")"
        ));
    }
    if let Some(n) = m.steps_per_period {
        return refuse(format!(
            "model.steps_per_period = {n} is not used by uq/design: it sets the coupled model, \
             and they run the lumped one; remove it (\"auto\")"
        ));
    }
    Ok(())
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
}

/// Evaluates `scene` perturbed by `sample`: η at `fidelity` (or the scene's given η), springs,
/// dynamic curve. Deterministic: the same inputs give bitwise the same outputs. Builds the
/// static model for this one call; many samples of one scene share it through
/// [`evaluate_with`].
pub fn evaluate(
    scene: &Scene,
    sample: &MotorSample,
    fidelity: Fidelity,
) -> Result<MotorOutputs, PipelineError> {
    evaluate_with(&StaticModel::build(scene, fidelity)?, scene, sample)
}

/// Evaluates `scene` perturbed by `sample` with the prepared static model of `scene`
/// (bitwise the same as [`evaluate`]).
pub fn evaluate_with(
    model: &StaticModel,
    scene: &Scene,
    sample: &MotorSample,
) -> Result<MotorOutputs, PipelineError> {
    let start = Instant::now();
    let scene = perturbed_scene(scene, sample);
    let (eta, contact_fraction, operator_s) = model.eta(&scene, sample)?;
    let static_s = start.elapsed().as_secs_f64();
    let springs: PostSprings = scene_springs(&scene)?;
    let dynamic = dynamic_scene(&scene, &springs, eta)?;
    let result = stick_slip::solve(&dynamic)?;
    let max_output_power_w = result
        .curve
        .iter()
        .map(|p| p.output_power_w)
        .fold(0.0, f64::max);
    Ok(MotorOutputs {
        effective_contact_ratio: eta,
        stall_thrust_n: result.stall_thrust_n,
        no_load_speed_m_per_s: result.no_load_speed_m_per_s,
        max_output_power_w,
        efficiency: result.efficiency,
        contact_fraction,
        curve: result.curve,
        cost: EvaluationCost {
            static_s,
            operator_s: operator_s.unwrap_or(0.0),
            dynamic_s: start.elapsed().as_secs_f64() - static_s,
            operator_built: operator_s.is_some(),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::scatter::{ScatterSpec, split_scatter};

    /// Samples 174, 373, 887 and 957 of `sawdrive uq validation/design/scatter.toml --seed 1`
    /// failed with a Zeno loop in stick-slip's event-driven post; 957 still did with
    /// the current springs and η, until the post's event hysteresis. The whole slider (10 000
    /// posts) takes ≈ 2 s a sample: `cargo test -p sawdrive --lib zeno -- --ignored`.
    #[test]
    #[ignore]
    fn the_case_study_samples_that_hit_a_zeno_loop_evaluate() {
        let scene = crate::scene::load_scene(None, &[]).unwrap();
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../validation/design/scatter.toml"
        );
        let text = std::fs::read_to_string(path).unwrap();
        let (_, _, table) = split_scatter(Some(&text), &[]).unwrap();
        let scatter = ScatterSpec::from_table(&table).unwrap();
        let inputs = scatter.inputs(&scene).unwrap();
        let model = StaticModel::build(&scene, Fidelity::Slider).unwrap();
        for k in [174u64, 373, 887, 957] {
            let (values, field_seed) = design::draw_inputs(&inputs, 1, k);
            let out = evaluate_with(&model, &scene, &scatter.sample(&values, field_seed))
                .unwrap_or_else(|e| panic!("sample {k}: {e}"));
            assert!(
                out.max_output_power_w > 0.0,
                "maximum output power of sample {k}: {} W",
                out.max_output_power_w
            );
        }
    }
}
