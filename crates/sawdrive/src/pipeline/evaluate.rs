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
use coupled_dynamics::{DEFAULT_AUTO_TOLERANCE, DynamicsChoice, LumpedEvidence, choose_model};
use design::evaluator::{
    CoupledCost, CurvePoint, EvaluationCost, Evaluator, Fidelity, ModelError, MotorOutputs,
    MotorSample, SceneFacts, VariableKind,
};
use slider_contact::{Imperfections, ImperfectionsExt, SliderModel, SliderParams};

use super::dynamic_stage::attenuation::{AmplitudeProfile, attenuate_lumped, is_transient};
use super::dynamic_stage::whole_slider::{self, StudyCurve, StudyTangential, StudyWarmStart};
use super::local_amplitude::{attenuation_off, post_columns_m, settle_eta, stall_profile_at};
use crate::pipeline::{PipelineError, dynamic_scene, scene_springs};
use crate::scene::{Dynamics, Scene, StaticModel as StaticChoice};
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
    /// The coupled model's warm start: the periodic states of the nominal sample's coupled
    /// curve, solved from rest once when the operator is built ([`Self::build`]) and shared by
    /// every evaluation, so that a sample's result depends only on the scene and the sample.
    warm: Option<StudyWarmStart>,
    /// The nominal operator's tangential lattice operator, when the coupled model may run.
    tangential: Option<StudyTangential>,
}

impl StaticModel {
    /// Builds the operator of `scene` at `fidelity` (nothing when the scene gives η).
    pub fn build(scene: &Scene, fidelity: Fidelity) -> Result<Self, PipelineError> {
        if scene.contact.effective_ratio.is_some() {
            return Ok(Self {
                fidelity: Fidelity::Given,
                nominal: None,
                warm: None,
                tangential: None,
            });
        }
        let params = fidelity_params(slider_params(scene, Imperfections::default()), fidelity);
        let nominal = SliderModel::build(&params).map_err(unsupported)?;
        let mut out = Self {
            fidelity,
            nominal: Some(nominal),
            warm: None,
            tangential: None,
        };
        out.warm = out.nominal_warm(scene)?;
        Ok(out)
    }

    /// The periodic states of the nominal sample's coupled curve (the scene's own preload,
    /// diameter and μ, ideal posts), from rest, when `model.dynamics = "coupled"`; with them
    /// (and under `auto`) the tangential operator. Solved here, once and before any sample, so
    /// that every sample starts from the same states whatever the threads. Under `auto` no
    /// nominal curve is solved (its lumped curve alone may cost as much as a sample, and the
    /// nominal's ideal posts rarely pick the coupled model): an `auto` sample that goes coupled
    /// starts from rest.
    fn nominal_warm(&mut self, scene: &Scene) -> Result<Option<StudyWarmStart>, PipelineError> {
        let may_couple = match scene.model.dynamics {
            Dynamics::Lumped(_) => false,
            Dynamics::Auto => {
                scene.static_fem.model != StaticChoice::Strip
                    && whole_slider::check_scene(scene).is_ok()
            }
            Dynamics::Coupled => check_dynamics(scene).is_ok(),
        };
        if !may_couple {
            return Ok(None);
        }
        let m = &scene.motor;
        let nominal = MotorSample {
            preload_n: m.load.preload_n,
            post_diameter_m: m.posts.diameter_m,
            mu_static: m.friction.mu_static,
            mu_kinetic: m.friction.mu_kinetic,
            tilt_x_m: 0.0,
            tilt_y_m: 0.0,
            bow_m: 0.0,
            height_scatter_m: 0.0,
            scatter_seed: 0,
        };
        let Some((slider, _)) = self.sample_model(scene, &nominal)? else {
            return Ok(None);
        };
        let tangential = StudyTangential::build(&slider)?;
        if scene.model.dynamics != Dynamics::Coupled {
            self.tangential = Some(tangential);
            return Ok(None);
        }
        let fit = constant_wave_fit(&slider)?;
        let springs = scene_springs(scene)?;
        let dynamic = dynamic_scene(scene, &springs, fit.eta)?;
        let lumped_v0 = stick_slip::solve(&dynamic)?.no_load_speed_m_per_s;
        let curve = whole_slider::study_curve(scene, &slider, &tangential, lumped_v0, None)?;
        self.tangential = Some(tangential);
        // An unresolved nominal curve leaves no warm start: each sample starts from rest and
        // is accepted or refused on its own.
        Ok(curve.ok().map(|c| c.warm))
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

/// The η fit on the constant wave, or the error naming why η is not identifiable.
fn constant_wave_fit(model: &SliderModel) -> Result<StaticFit, PipelineError> {
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
    Ok(StaticFit {
        eta,
        contact_fraction: report.contact_fraction,
        misfit: report.eta_fit.relative_rms_residual,
    })
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
/// A sample or design evaluation is a whole-slider contact solve (the study's static model:
/// the lattice operator with Johnson's near field, no FEM) followed by
/// * the lumped model (N_eff = η·N posts, `stick_slip`) for `periodic-average` and `transient`;
/// * the whole slider's coupled model (every post of the sample's own slider, its scatter,
///   tilt, bow, preload, diameter and μ; `whole_slider::study_curve`) for `coupled`;
/// * per sample, the one the criterion picks for `auto` ([`dynamics_policy`]).
///
/// Refused, naming the key: `coupled` with η given (`contact.effective_ratio`: no static state
/// to run it on) or with `static.model = "strip"` (the strip's coupled model needs a strip FEM
/// per sample and cannot carry a sample's scatter, tilt or bow), and what the whole slider's
/// coupled model refuses in the dynamic stage (`model.lumped.vertical = "dynamic"`).
/// `wave.attenuation` is honoured as in the dynamic stage: on the energy-conserving wave each
/// sample's coupled curve is self-consistent in its amplitude profile. The coupled model's own keys
/// (`model.coupled.steps_per_period`, `model.curve_points`, `model.lumped_tolerance` under
/// `auto`) are honoured; the scene reader refuses them under a lumped `model.dynamics`.
pub fn check_dynamics(scene: &Scene) -> Result<(), PipelineError> {
    let refuse = |message: String| {
        Err(PipelineError::Unsupported {
            stage: "uq/design",
            message,
        })
    };
    if scene.model.dynamics != Dynamics::Coupled {
        return Ok(());
    }
    if let Some(eta) = scene.contact.effective_ratio {
        return refuse(format!(
            "model.dynamics = \"coupled\" runs every sample's whole slider on its own static \
             state, but contact.effective_ratio = {eta} is given: set it to \"fem\""
        ));
    }
    if scene.static_fem.model == StaticChoice::Strip {
        return refuse(
            "static.model = \"strip\" with model.dynamics = \"coupled\": uq/design run the \
             coupled model on every sample's whole slider (its own scatter, tilt and bow); the \
             strip's coupled model would need a strip FEM per sample and cannot carry them: set \
             static.model = \"slider\" or \"auto\""
                .into(),
        );
    }
    whole_slider::check_scene(scene).map_err(|e| PipelineError::Unsupported {
        stage: "uq/design",
        message: e.to_string(),
    })
}

/// Which dynamic model the evaluations of `scene` run and how it is chosen, in one sentence.
///
/// `auto` decides **per sample**, by the dynamic stage's criterion on that sample's
/// whole-slider η fit (estimated lumped error = the fit's relative rms misfit × the strips'
/// envelope factor, against `model.lumped_tolerance`), not once on the nominal: the nominal
/// sample has ideal posts, whose fit misfit is the smallest, so a decision on it would keep
/// the lumped model for exactly the scattered samples whose error the criterion is meant to
/// bound; per sample, every sample's output carries the criterion's bound.
pub fn dynamics_policy(scene: &Scene) -> String {
    let tolerance = scene
        .model
        .lumped_tolerance
        .unwrap_or(DEFAULT_AUTO_TOLERANCE);
    match scene.model.dynamics {
        Dynamics::Lumped(_) => "lumped (model.dynamics names it): every sample's whole-slider η \
                                on N_eff = η·N posts"
            .into(),
        Dynamics::Coupled => format!(
            "coupled (model.dynamics = \"coupled\"): every sample's whole slider (its own \
             scatter, tilt, bow, preload, diameter, μ) through the whole-slider coupled model \
             (every post, Coulomb stick/slip; Johnson's near fields, as the study's static \
             model) at stall, v₀ and {}, warm-started from the nominal sample's periodic states{}",
            curve_layout(scene),
            study_wave(scene)
        ),
        Dynamics::Auto if scene.contact.effective_ratio.is_some() => {
            "lumped (model.dynamics = \"auto\"): η is given, so no static fit estimates the \
             lumped model's error"
                .into()
        }
        Dynamics::Auto if scene.static_fem.model == StaticChoice::Strip => {
            "lumped (model.dynamics = \"auto\" with static.model = \"strip\"): the strip's \
             coupled model cannot carry a sample's scatter; set static.model = \"slider\" to let \
             the criterion choose the whole slider's coupled model"
                .into()
        }
        Dynamics::Auto => format!(
            "auto, per sample: the coupled model (at stall, v₀ and {}, from rest) when \
             the lumped model's error estimated from the sample's whole-slider η fit misfit \
             exceeds {tolerance} (model.lumped_tolerance), else the lumped one; per sample, not \
             once on the nominal, because the nominal sample's ideal posts have the smallest \
             misfit and would hide the scattered samples' error{}",
            curve_layout(scene),
            study_wave(scene)
        ),
    }
}

/// What wave a study's coupled curves run on, in words.
fn study_wave(scene: &Scene) -> String {
    match scene.wave_attenuation {
        stick_slip::AttenuationSetting::Off => {
            "; on the constant-amplitude wave (wave.attenuation)".into()
        }
        stick_slip::AttenuationSetting::On => concat!(
            "; on the energy-conserving wave (wave.attenuation): every post at its local ",
            "amplitude, each speed's profile self-consistent"
        )
        .into(),
        stick_slip::AttenuationSetting::Auto => format!(
            "; on the energy-conserving wave (every post at its local amplitude) when the \
             sample's constant-wave posts draw more than {} % of the wave's power at stall, as \
             in the dynamic stage (wave.attenuation = \"auto\")",
            100.0 * stick_slip::attenuation::AUTO_DRAW_FRACTION
        ),
    }
}

/// The speeds of a study's coupled curve besides stall and v₀, in words.
fn curve_layout(scene: &Scene) -> String {
    match scene.model.curve_points {
        Some(n) => format!("{n} evenly spaced points (model.curve_points)"),
        None => format!(
            "{:?} v₀ (maximum power and efficiency from the interpolants through them)",
            whole_slider::STUDY_SPEED_FRACTIONS
        ),
    }
}

/// Whether the coupled model runs for one sample, and why: `model.dynamics` when it names a
/// model; under `auto` the criterion on the sample's η fit `fit` (none: η given) and the lumped
/// no-load speed, kept lumped when the static model is the strip. The wave is the coupled
/// curve's own decision ([`whole_slider::study_curve`]).
fn choose_dynamics(
    scene: &Scene,
    fit: Option<&StaticFit>,
    lumped_no_load_m_per_s: f64,
) -> Result<(bool, String), PipelineError> {
    match scene.model.dynamics {
        Dynamics::Lumped(_) => return Ok((false, "model.dynamics names a lumped model".into())),
        Dynamics::Coupled => return Ok((true, "model.dynamics = \"coupled\"".into())),
        Dynamics::Auto => {}
    }
    let (Some(fit), false) = (fit, scene.static_fem.model == StaticChoice::Strip) else {
        return Ok((false, dynamics_policy(scene)));
    };
    let evidence = LumpedEvidence {
        eta_fit_misfit: fit.misfit,
        lumped_no_load_speed_m_per_s: lumped_no_load_m_per_s,
        crest_speed_m_per_s: scene.motor.wave.crest_speed_m_per_s(),
    };
    let tolerance = scene
        .model
        .lumped_tolerance
        .unwrap_or(DEFAULT_AUTO_TOLERANCE);
    let decision = choose_model(&evidence, tolerance)?;
    let coupled = decision.model == DynamicsChoice::Coupled;
    if coupled {
        whole_slider::check_scene(scene)?;
    }
    Ok((coupled, decision.reason))
}

/// A sample's whole-slider η fit on the constant wave.
#[derive(Debug, Clone, Copy)]
struct StaticFit {
    eta: f64,
    contact_fraction: f64,
    /// Relative rms misfit of the η fit (the auto criterion's evidence).
    misfit: f64,
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

/// When one evaluation started and its static part's times.
#[derive(Debug, Clone, Copy)]
struct Clock {
    start: Instant,
    static_s: f64,
    operator_s: Option<f64>,
}

impl Clock {
    fn cost(&self, coupled: CoupledCost) -> EvaluationCost {
        EvaluationCost {
            static_s: self.static_s,
            operator_s: self.operator_s.unwrap_or(0.0),
            dynamic_s: self.start.elapsed().as_secs_f64() - self.static_s,
            operator_built: self.operator_s.is_some(),
            coupled,
        }
    }
}

/// Evaluates `scene` perturbed by `sample` with the prepared static model of `scene`
/// (bitwise the same as [`evaluate`]): the sample's whole-slider η, the lumped curve at it,
/// then the dynamic model `choose_dynamics` picks — the lumped curve as it is (with the
/// energy-conserving wave on, η at the local amplitude of the stall profile, settled with the
/// curve as in the dynamic stage: `pipeline::local_amplitude`, docs/physics.md §5.5; the contact
/// fraction stays the constant wave's), or the whole slider's coupled curve of the sample
/// (`coupled_outputs`).
pub fn evaluate_with(
    model: &StaticModel,
    scene: &Scene,
    sample: &MotorSample,
) -> Result<MotorOutputs, PipelineError> {
    let start = Instant::now();
    let scene = perturbed_scene(scene, sample);
    let slider = model.sample_model(&scene, sample)?;
    let fit = match &slider {
        Some((m, _)) => Some(constant_wave_fit(m)?),
        None => None,
    };
    let clock = Clock {
        start,
        static_s: start.elapsed().as_secs_f64(),
        operator_s: slider.as_ref().and_then(|s| s.1),
    };
    let eta = fit.map_or(scene.contact.effective_ratio.unwrap_or_default(), |f| f.eta);
    let springs: PostSprings = scene_springs(&scene)?;
    let dynamic = dynamic_scene(&scene, &springs, eta)?;
    let result = stick_slip::solve(&dynamic)?;
    let lumped_v0 = result.no_load_speed_m_per_s;
    let (coupled, reason) = choose_dynamics(&scene, fit.as_ref(), lumped_v0)?;
    let run = LumpedRun {
        springs: &springs,
        dynamic: &dynamic,
        result,
    };
    match (coupled, slider, fit) {
        (true, Some((slider, _)), Some(fit)) => {
            let tangential = match &model.tangential {
                Some(t) => t.clone(),
                None => StudyTangential::build(&slider)?,
            };
            let warm = model.warm.as_ref();
            match whole_slider::study_curve(&scene, &slider, &tangential, lumped_v0, warm)? {
                Ok(curve) => Ok(coupled_outputs(model, &scene, fit, curve, reason, clock)),
                Err(unresolved) => {
                    let reason = unresolved_reason(&scene, reason, &unresolved)?;
                    let slider = Some((slider, None));
                    lumped_outputs(&scene, run, slider, Some(fit), reason, clock)
                }
            }
        }
        (_, slider, fit) => lumped_outputs(&scene, run, slider, fit, reason, clock),
    }
}

/// The reason an `auto` evaluation keeps the lumped model after the criterion picked the
/// coupled one whose curve is [`Unresolved`](whole_slider::Unresolved) (a nearly locked
/// sample); with `model.dynamics = "coupled"` the refusal, naming the key.
fn unresolved_reason(
    scene: &Scene,
    reason: String,
    unresolved: &whole_slider::Unresolved,
) -> Result<String, PipelineError> {
    match scene.model.dynamics {
        Dynamics::Coupled => Err(PipelineError::Unsupported {
            stage: "dynamic",
            message: format!(
                "model.dynamics = \"coupled\": {unresolved}; its figures would not be the coupled \
                 model's steady ones (\"auto\" keeps the lumped model for such a sample)"
            ),
        }),
        _ => Ok(format!(
            "{reason}; but {unresolved}, so the lumped model runs"
        )),
    }
}

/// A sample's lumped run: its springs, the lumped scene at its η and the curve solved on it.
struct LumpedRun<'a> {
    springs: &'a PostSprings,
    dynamic: &'a stick_slip::DynamicScene,
    result: stick_slip::DynamicResult,
}

/// The outputs of the lumped curve at the sample's η ([`lumped_curve`] of `run`): thrust,
/// powers and efficiency as the lumped model gives them.
fn lumped_outputs(
    scene: &Scene,
    run: LumpedRun<'_>,
    slider: Option<(SliderModel, Option<f64>)>,
    fit: Option<StaticFit>,
    reason: String,
    clock: Clock,
) -> Result<MotorOutputs, PipelineError> {
    let eta = fit.map_or(scene.contact.effective_ratio.unwrap_or_default(), |f| f.eta);
    let (eta, result) = lumped_curve(scene, run.springs, run.dynamic, run.result, slider, eta)?;
    let max_output_power_w = lumped_max_output_power_w(&result.curve);
    Ok(MotorOutputs {
        effective_contact_ratio: eta,
        stall_thrust_n: result.stall_thrust_n,
        no_load_speed_m_per_s: result.no_load_speed_m_per_s,
        max_output_power_w,
        efficiency: result.efficiency,
        contact_fraction: fit.map(|f| f.contact_fraction),
        curve: result
            .curve
            .iter()
            .map(|p| CurvePoint {
                speed_m_per_s: p.speed_m_per_s,
                thrust_n: p.thrust_n,
                efficiency: p.efficiency,
            })
            .collect(),
        dynamics_model: "lumped",
        dynamics_reason: reason,
        cost: clock.cost(CoupledCost::default()),
    })
}

/// Largest relative difference between a lumped point's output power (its period's output
/// work) and thrust × speed for the work to count: the two agree to round-off over a closed
/// steady period on the constant wave and to ≈ 1e-4 on the energy-conserving wave (the
/// golden uq case), while a nearly locked slider's differ by a factor 20–1000. Default 1e-2.
const OUTPUT_WORK_TOLERANCE: f64 = 1e-2;

/// The largest output power along a lumped curve: each point's output work over its period,
/// or thrust × speed where the two disagree by more than [`OUTPUT_WORK_TOLERANCE`] — the
/// period average of a nearly locked slider (µm/s and below) leaves the small output work
/// unbalanced, up to 1000 × thrust × speed (the design golden's 40 N baseline), while the mean thrust stays exact; the output
/// power is thrust × speed by definition, so no point can put out more than its stator
/// delivers.
fn lumped_max_output_power_w(curve: &[stick_slip::CurvePoint]) -> f64 {
    curve
        .iter()
        .map(|p| {
            let thrust_power = p.thrust_n * p.speed_m_per_s;
            let scale = p.output_power_w.abs().max(thrust_power.abs());
            match (p.output_power_w - thrust_power).abs() <= OUTPUT_WORK_TOLERANCE * scale {
                true => p.output_power_w,
                false => thrust_power,
            }
        })
        .fold(0.0, f64::max)
}

/// The lumped curve at η (`result`, solved on `dynamic`), on the energy-conserving wave when
/// `wave.attenuation` turns it on (as in the dynamic stage), with η settled at the local
/// amplitude when the whole slider's model `slider` is there; returns that η and the curve.
fn lumped_curve(
    scene: &Scene,
    springs: &PostSprings,
    dynamic: &stick_slip::DynamicScene,
    mut result: stick_slip::DynamicResult,
    slider: Option<(SliderModel, Option<f64>)>,
    eta: f64,
) -> Result<(f64, stick_slip::DynamicResult), PipelineError> {
    let attenuation = attenuate_lumped(scene, dynamic, &mut result)?;
    let (Some((mut slider, _)), Some(profile)) = (slider, attenuation.stall_profile) else {
        return Ok((eta, result));
    };
    let columns = post_columns_m(&slider.params.geometry());
    let transient = is_transient(result.model);
    let eta_at = |scale: &[f64]| {
        slider.params.amplitude_scale_x = scale.to_vec();
        Ok(fit_eta(&slider)?.0)
    };
    let stall_profile =
        |eta: f64, warm: &AmplitudeProfile| stall_profile_at(scene, springs, eta, transient, warm);
    let settled = settle_eta(&columns, eta, profile, eta_at, stall_profile)?;
    let eta = settled.effective_contact_ratio;
    if settled.passes > 1 {
        let dynamic = dynamic_scene(scene, springs, eta)?;
        result = stick_slip::solve(&dynamic)?;
        let a = attenuate_lumped(scene, &dynamic, &mut result)?;
        if a.stall_profile.is_none() {
            return Err(attenuation_off(eta, &a.wave.reason));
        }
    }
    Ok((eta, result))
}

/// The outputs of a sample's coupled curve: η and the contact fraction of its static fit; a
/// `patch` evaluation's thrust and powers scaled from its rows to the whole slider's
/// (`posts_y / rows`: the patch carries that share of the preload; speed and efficiency stay).
fn coupled_outputs(
    model: &StaticModel,
    scene: &Scene,
    fit: StaticFit,
    curve: StudyCurve,
    reason: String,
    clock: Clock,
) -> MotorOutputs {
    let rows = match model.fidelity {
        Fidelity::Patch => PATCH_ROWS.min(scene.motor.posts.count_y),
        _ => scene.motor.posts.count_y,
    };
    let share = f64::from(scene.motor.posts.count_y) / f64::from(rows);
    let wave = match curve.wave.on() {
        true => "the energy-conserving wave",
        false => "the constant-amplitude wave",
    };
    let reason = format!("{reason}; on {wave} ({})", curve.wave.reason);
    let t = curve.times_s;
    let cost = CoupledCost {
        normal_grid_s: t.normal_grid_s,
        stall_s: t.stall_s,
        no_load_s: t.no_load_s,
        points_s: t.points_s,
        periods: curve.periods,
    };
    MotorOutputs {
        effective_contact_ratio: fit.eta,
        stall_thrust_n: curve.stall_thrust_n * share,
        no_load_speed_m_per_s: curve.no_load_speed_m_per_s,
        max_output_power_w: curve.max_output_power_w * share,
        efficiency: curve.efficiency,
        contact_fraction: Some(fit.contact_fraction),
        curve: curve
            .curve
            .iter()
            .map(|p| CurvePoint {
                speed_m_per_s: p.speed_m_per_s,
                thrust_n: p.thrust_n * share,
                efficiency: p.efficiency,
            })
            .collect(),
        dynamics_model: "coupled",
        dynamics_reason: reason,
        cost: clock.cost(cost),
    }
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

    fn dynamics_policy(&self, scene: &Scene) -> String {
        dynamics_policy(scene)
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
