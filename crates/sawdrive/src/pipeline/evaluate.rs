//! The `sawdrive` library's [`design::Evaluator`]: one motor evaluation for Monte Carlo and
//! design, the glue between the studies of crate `design` (which never links the FEM or the
//! whole-slider model) and the pipeline's stages. A scene with one sample's perturbations →
//! whole-slider static contact (η, `slider_contact`, no FEM: the lattice operator with Johnson's
//! near field) → Johnson springs → period-average/transient speed–thrust curve (`stick_slip`)
//! (on the energy-conserving wave when `wave.attenuation` turns it on, as in the dynamic stage)
//! → η, stall thrust, no-load speed, maximum output power, efficiency.
//!
//! Fidelities ([`Fidelity`]): `slider` resolves every post of the scene's array; `patch` solves
//! a band of [`PATCH_ROWS`] full-length rows (all posts along the wave, preload scaled by the
//! rows' share), whose η is within ≈ 1 % of the whole slider's for identical rows
//! (validation/whole-slider: 0.8265 at 10 rows vs 0.8160 at 100) at ≈ 1/10 of the cost; it does
//! not see a tilt across y. When the scene gives η as a number (`contact.effective_ratio`),
//! no static solve runs and height scatter, tilt and bow are refused (they could not act): the
//! one "η given or from the static model" branch of the studies.
//!
//! Units: the studies' input files give human values by scene key ("20 um" for
//! `posts.diameter`); [`SceneEvaluator::quantity`] parses them with the scene's units
//! (`crate::units`, the one home of unit parsing), so `design` never parses a unit.
//! Validity: that of the whole-slider static model and the lumped dynamic model
//! (docs/physics.md); the coupled model is refused ([`check_dynamics`]).

use std::path::Path;
use std::time::Instant;

use contact_springs::PostSprings;
use design::evaluator::{
    CurvePoint, EvaluationCost, Evaluator, Fidelity, ModelError, MotorOutputs, MotorSample,
    SceneFacts, VariableKind,
};
use slider_contact::{Imperfections, ImperfectionsExt, SliderModel, SliderParams};

use super::dynamic_stage::attenuation::{AmplitudeProfile, attenuate_lumped, is_transient};
use super::local_amplitude::{attenuation_off, post_columns_m, settle_eta, stall_profile_at};
use crate::pipeline::{PipelineError, dynamic_scene, scene_springs};
use crate::scene::{Dynamics, Scene};
use crate::units::{Dimension, format_quantity, parse_quantity};

/// Rows of posts (along y) the `patch` fidelity solves.
pub const PATCH_ROWS: u32 = 8;

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

    /// The sample's whole-slider model (`scene` already carrying the sample's preload, diameter
    /// and μ; the sample's shape added) and the time spent building an operator (`None`: the
    /// shared one was used); `Ok(None)` when the scene gives η.
    fn sample_model(
        &self,
        scene: &Scene,
        s: &MotorSample,
    ) -> Result<Option<(SliderModel, Option<f64>)>, PipelineError> {
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
            return Ok(None);
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
        Ok(Some((model, built.then(|| setup.elapsed().as_secs_f64()))))
    }
}

/// η (`None`: not identifiable) and the contact fraction of a whole-slider model on its wave.
fn fit_eta(model: &SliderModel) -> Result<(Option<f64>, f64), PipelineError> {
    let report = model.analyse(model.params.preload_n).map_err(unsupported)?;
    Ok((report.effective_contact_ratio, report.contact_fraction))
}

/// η and the contact fraction on the constant wave, or the error naming why η is not
/// identifiable.
fn constant_wave_eta(model: &SliderModel) -> Result<(f64, f64), PipelineError> {
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
    Ok((eta, report.contact_fraction))
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
///   (`model.lumped_tolerance`, `model.coupled.steps_per_period`): refused.
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
            "model.coupled.steps_per_period = {n} is not used by uq/design: it sets the coupled model, \
             and they run the lumped one; remove it (\"auto\")"
        ));
    }
    Ok(())
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
/// (bitwise the same as [`evaluate`]). With the energy-conserving wave on and η from the
/// whole-slider model, η is the one at the local amplitude of the stall profile, settled with
/// the curve as in the dynamic stage (`pipeline::local_amplitude`, docs/physics.md §5.5); the
/// contact fraction stays the constant wave's.
pub fn evaluate_with(
    model: &StaticModel,
    scene: &Scene,
    sample: &MotorSample,
) -> Result<MotorOutputs, PipelineError> {
    let start = Instant::now();
    let scene = perturbed_scene(scene, sample);
    let slider = model.sample_model(&scene, sample)?;
    let (eta, contact_fraction, operator_s) = match &slider {
        Some((m, operator_s)) => {
            let (eta, fraction) = constant_wave_eta(m)?;
            (eta, Some(fraction), *operator_s)
        }
        None => (
            scene.contact.effective_ratio.unwrap_or_default(),
            None,
            None,
        ),
    };
    let static_s = start.elapsed().as_secs_f64();
    let springs: PostSprings = scene_springs(&scene)?;
    let dynamic = dynamic_scene(&scene, &springs, eta)?;
    let mut result = stick_slip::solve(&dynamic)?;
    // `wave.attenuation`, as in the dynamic stage: the energy-conserving wave when it is on.
    let attenuation = attenuate_lumped(&scene, &dynamic, &mut result)?;
    let eta = match (slider, attenuation.stall_profile) {
        (Some((mut slider, _)), Some(profile)) => {
            let columns = post_columns_m(&slider.params.geometry());
            let transient = is_transient(result.model);
            let eta_at = |scale: &[f64]| {
                slider.params.amplitude_scale_x = scale.to_vec();
                Ok(fit_eta(&slider)?.0)
            };
            let stall_profile = |eta: f64, warm: &AmplitudeProfile| {
                stall_profile_at(&scene, &springs, eta, transient, warm)
            };
            let settled = settle_eta(&columns, eta, profile, eta_at, stall_profile)?;
            let eta = settled.effective_contact_ratio;
            if settled.passes > 1 {
                let dynamic = dynamic_scene(&scene, &springs, eta)?;
                result = stick_slip::solve(&dynamic)?;
                let a = attenuate_lumped(&scene, &dynamic, &mut result)?;
                if a.stall_profile.is_none() {
                    return Err(attenuation_off(eta, &a.wave.reason));
                }
            }
            eta
        }
        _ => eta,
    };
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
        curve: result
            .curve
            .iter()
            .map(|p| CurvePoint {
                speed_m_per_s: p.speed_m_per_s,
                thrust_n: p.thrust_n,
            })
            .collect(),
        cost: EvaluationCost {
            static_s,
            operator_s: operator_s.unwrap_or(0.0),
            dynamic_s: start.elapsed().as_secs_f64() - static_s,
            operator_built: operator_s.is_some(),
        },
    })
}

/// The motor model of `sawdrive uq`, `sawdrive design` and the Python studies: the
/// [`design::Evaluator`] of a resolved [`Scene`], each evaluation through [`evaluate_with`].
#[derive(Debug, Clone, Copy, Default)]
pub struct SceneEvaluator;

/// The design variables a scene can express: (scene key, name in reports, whole values).
const VARIABLES: [(&str, &str, bool); 4] = [
    ("posts.diameter", "post_diameter_m", false),
    ("posts.count", "posts_per_side", true),
    ("posts.height", "post_height_m", false),
    ("load.preload", "preload_n", false),
];

/// The dimension of a scene key a study gives as a quantity (`None`: not one).
fn dimension(key: &str) -> Option<Dimension> {
    match key {
        "posts.diameter"
        | "posts.height"
        | "posts.height_scatter"
        | "slider.tilt_x"
        | "slider.tilt_y"
        | "slider.bow" => Some(Dimension::Length),
        "load.preload" => Some(Dimension::Force),
        _ => None,
    }
}

/// Why a scene key cannot be given as a quantity by a study.
#[derive(Debug, thiserror::Error)]
#[error("{key} is not a quantity a study can give (lengths of posts.* and slider.*, load.preload)")]
struct NotAQuantity {
    key: String,
}

impl Evaluator for SceneEvaluator {
    type Scene = Scene;
    type Prepared = StaticModel;

    fn load_scene(&self, path: Option<&Path>, set: &[String]) -> Result<Scene, ModelError> {
        Ok(crate::scene::load_scene(path, set)?)
    }

    fn load_scene_text(
        &self,
        file: Option<(&Path, &str)>,
        set: &[String],
    ) -> Result<Scene, ModelError> {
        Ok(crate::scene::load_scene_text(file, set)?)
    }

    fn read_scene_file(&self, path: &Path) -> Result<String, ModelError> {
        Ok(crate::scene::read_scene_file(path)?)
    }

    fn facts(&self, scene: &Scene) -> SceneFacts {
        let m = &scene.motor;
        let shape = &m.imperfections;
        SceneFacts {
            name: scene.name.clone(),
            preload_n: m.load.preload_n,
            post_diameter_m: m.posts.diameter_m,
            post_height_m: m.posts.height_m,
            posts: [m.posts.count_x, m.posts.count_y],
            pitch_m: [m.posts.pitch_x_m(), m.posts.pitch_y_m()],
            array_m: [m.posts.array_x_m, m.posts.array_y_m],
            mu_static: m.friction.mu_static,
            mu_kinetic: m.friction.mu_kinetic,
            max_friction: crate::scene::limits::MAX_FRICTION,
            tilt_x_m: shape.tilt_x_m,
            tilt_y_m: shape.tilt_y_m,
            bow_m: shape.bow_m,
            height_scatter_m: shape.height_scatter_m,
            has_height_map: shape.height_map.is_some(),
        }
    }

    fn scene_bytes(&self, scene: &Scene) -> Result<Vec<u8>, ModelError> {
        Ok(serde_json::to_vec(scene)?)
    }

    fn model_versions(&self) -> Vec<u8> {
        let mut v = crate::DYNAMIC_MODEL_VERSION.to_le_bytes().to_vec();
        v.extend(static_contact::params::MODEL_VERSION.to_le_bytes());
        v
    }

    fn check_study(&self, scene: &Scene) -> Result<(), ModelError> {
        Ok(check_dynamics(scene)?)
    }

    fn quantity(&self, key: &str, text: &str) -> Result<f64, ModelError> {
        let dimension = dimension(key).ok_or_else(|| NotAQuantity { key: key.into() })?;
        Ok(parse_quantity(text, dimension)?)
    }

    fn example(&self, key: &str) -> &'static str {
        dimension(key).map_or("\"20 um\"", Dimension::example)
    }

    fn describe(&self, key: &str, value: f64) -> String {
        match dimension(key) {
            Some(d) => format_quantity(value, d),
            None => value.to_string(),
        }
    }

    fn variable(&self, key: &str) -> Option<VariableKind> {
        VARIABLES
            .iter()
            .find(|v| v.0 == key)
            .map(|&(_, report_name, integer)| VariableKind {
                report_name,
                integer,
            })
    }

    fn set_variable(&self, key: &str, value: f64) -> String {
        match dimension(key) {
            Some(Dimension::Force) => format!("{key}={value:e} N"),
            Some(_) => format!("{key}={value:e} m"),
            None => format!("{key}={n}x{n}", n = value as u64),
        }
    }

    fn variable_value(&self, scene: &Scene, key: &str) -> f64 {
        let m = &scene.motor;
        match key {
            "posts.diameter" => m.posts.diameter_m,
            "posts.count" => f64::from(m.posts.count_x),
            "posts.height" => m.posts.height_m,
            _ => m.load.preload_n,
        }
    }

    fn prepare(&self, scene: &Scene, fidelity: Fidelity) -> Result<StaticModel, ModelError> {
        Ok(StaticModel::build(scene, fidelity)?)
    }

    fn fidelity(&self, prepared: &StaticModel) -> Fidelity {
        prepared.fidelity()
    }

    fn evaluate(
        &self,
        prepared: &StaticModel,
        scene: &Scene,
        sample: &MotorSample,
    ) -> Result<MotorOutputs, ModelError> {
        Ok(evaluate_with(prepared, scene, sample)?)
    }
}
