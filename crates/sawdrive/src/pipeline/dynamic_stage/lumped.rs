//! Dynamic stage: the scene's wave, posts (k_n, k_t from Johnson) and slider → stick-slip.

use std::path::{Path, PathBuf};

use contact_springs::PostSprings;
use stick_slip::{
    DynamicResult, DynamicScene, HistoryOptions, Integrator, IntegratorKind, ModelKind,
    PostContact, RunHistories, Slider, SolveOptions, StabilityPolicy, StickSlipError,
    TransientOptions,
};

use crate::pipeline::{PipelineError, RunControl};
use crate::scene::{DEFAULT_CURVE_POINTS, DEFAULT_TRANSIENT_PERIODS, Model, Scene};

/// Steps per wave period of a fixed-step integrator when the scene says `time_step = "auto"`.
const AUTO_STEPS_PER_PERIOD: f64 = stick_slip::TRANSIENT_DEFAULT_STEPS_PER_PERIOD;
/// Fraction of an explicit scheme's stability limit used for an automatic step.
const AUTO_STEP_FRACTION_OF_LIMIT: f64 = 0.5;
/// Regularisation speed of tanh friction as a fraction of the crest speed A_t ω, when "auto".
const AUTO_REGULARIZATION_FRACTION_OF_CREST: f64 = 1e-3;
/// Wave periods of the Fig. 6-style time history.
const HISTORY_PERIODS: f64 = 3.0;
/// Samples per wave period of the time history.
const HISTORY_SAMPLES_PER_PERIOD: usize = 256;

/// The dynamic model's input for `scene` with the post springs `springs` (from
/// [`scene_springs`](crate::pipeline::scene_springs), computed once per run) and effective contact ratio
/// `effective_ratio`: the motor's wave, post contact and slider, with the scene's model settings.
pub fn dynamic_scene(
    scene: &Scene,
    springs: &PostSprings,
    effective_ratio: f64,
) -> Result<DynamicScene, PipelineError> {
    let motor = &scene.motor;
    let m = &scene.model;
    let needs_mass = matches!(
        m.integrator,
        IntegratorKind::Regularized | IntegratorKind::PostMass
    );
    let contact = PostContact {
        k_n_n_per_m: springs.k_n_n_per_m,
        k_t_n_per_m: springs.k_t_n_per_m,
        mu_static: motor.friction.mu_static,
        mu_kinetic: motor.friction.mu_kinetic,
        post_mass_kg: needs_mass.then_some(motor.post_mass_kg()),
    };
    let slider = Slider::for_motor(motor, effective_ratio, m.vertical).map_err(name_scene_keys)?;
    let mut dynamic = DynamicScene {
        wave: motor.wave.clone(),
        contact,
        slider,
        model: m.dynamics.lumped_choice(),
        integrator: Integrator::Auto,
        options: SolveOptions::default(),
    };
    let kind = dynamic.resolve_model()?.0;
    dynamic.options = options(&scene.model, kind)?;
    dynamic.integrator = integrator(scene, &dynamic, kind)?;
    Ok(dynamic)
}

/// A setting given for a model that does not use it: refused, naming the key.
fn unused(key: &str, value: impl std::fmt::Display, why: &str) -> PipelineError {
    PipelineError::Unsupported {
        stage: "dynamic",
        message: format!(
            "{key} = {value} is not used: {why}; remove it (\"auto\") or choose a model that uses it"
        ),
    }
}

/// Solver options of the model `kind` that runs. The rule: a model setting the running model
/// does not use is refused (`periods` with the period average); `"auto"` takes the model's
/// default; `curve_points` sets the period average's speeds or the transient's loads.
fn options(m: &Model, kind: ModelKind) -> Result<SolveOptions, PipelineError> {
    let mut options = SolveOptions {
        stability: StabilityPolicy::Refuse,
        history: HistoryOptions {
            periods: HISTORY_PERIODS,
            samples_per_period: HISTORY_SAMPLES_PER_PERIOD,
        },
        ..SolveOptions::default()
    };
    match kind {
        ModelKind::PeriodicAverage => {
            if let Some(periods) = m.periods {
                return Err(unused(
                    "model.transient.periods",
                    periods,
                    "this scene runs the period average, which simulates no wave periods (periodic by construction)",
                ));
            }
            options.curve_points = m.curve_points.unwrap_or(DEFAULT_CURVE_POINTS) as usize;
        }
        ModelKind::Transient => {
            let periods = f64::from(m.periods.unwrap_or(DEFAULT_TRANSIENT_PERIODS));
            options.transient = TransientOptions {
                periods,
                average_periods: (0.25 * periods).max(1.0),
                ..TransientOptions::default()
            };
            if let Some(loads) = m.curve_points {
                options.transient.curve_loads = loads as usize;
            }
        }
    }
    Ok(options)
}

/// The scene's integrator for the model `kind` that runs, with automatic steps chosen inside the
/// stability limit. A `time_step` is honoured by every fixed-step scheme and by `auto` on the
/// transient (its return mapping); it is refused where no scheme takes it (`auto` or
/// `event-driven` on the closed-form period average).
fn integrator(
    scene: &Scene,
    dynamic: &DynamicScene,
    kind: ModelKind,
) -> Result<Integrator, PipelineError> {
    let m = &scene.model;
    let period = dynamic.wave.period_s();
    let closed_form = kind == ModelKind::PeriodicAverage
        && matches!(
            m.integrator,
            IntegratorKind::Auto | IntegratorKind::EventDriven
        );
    if let (Some(dt), true) = (m.time_step_s, closed_form) {
        return Err(unused(
            "model.lumped.time_step",
            format!("{dt:e} s"),
            "the period average runs the closed-form event-driven post, which has no time step; set model.lumped.integrator to return-mapping, post-mass or regularized, or model.dynamics = \"transient\"",
        ));
    }
    let explicit_step = |candidate: Integrator| -> Result<f64, PipelineError> {
        if let Some(dt) = m.time_step_s {
            return Ok(dt);
        }
        let model = stick_slip::ModelKind::Transient;
        let limit = candidate
            .stability_limit(&dynamic.stability_setting(model))
            .map_or(period / AUTO_STEPS_PER_PERIOD, |l| l.limit_s);
        Ok((AUTO_STEP_FRACTION_OF_LIMIT * limit).min(period / AUTO_STEPS_PER_PERIOD))
    };
    Ok(match m.integrator {
        IntegratorKind::Auto => match m.time_step_s {
            Some(dt_s) => Integrator::ReturnMapping { dt_s },
            None => Integrator::Auto,
        },
        IntegratorKind::EventDriven => Integrator::EventDriven {
            max_step_s: m.time_step_s,
        },
        IntegratorKind::ReturnMapping => Integrator::ReturnMapping {
            dt_s: m.time_step_s.unwrap_or(period / AUTO_STEPS_PER_PERIOD),
        },
        IntegratorKind::Regularized => {
            let v_reg = m.regularization_velocity_m_per_s.unwrap_or(
                AUTO_REGULARIZATION_FRACTION_OF_CREST * dynamic.wave.crest_speed_m_per_s(),
            );
            let probe = Integrator::RegularizedExplicit {
                dt_s: period,
                regularization_speed_m_per_s: v_reg,
            };
            Integrator::RegularizedExplicit {
                dt_s: explicit_step(probe)?,
                regularization_speed_m_per_s: v_reg,
            }
        }
        IntegratorKind::PostMass => Integrator::PostMass {
            dt_s: explicit_step(Integrator::PostMass { dt_s: period })?,
        },
    })
}

/// What the dynamic stage produced: the model input that ran, its result and the histories of
/// the run itself (taken from the model that ran, so bursts, decaying waves and gapped posts,
/// which only the transient represents, chart like any other scene).
#[derive(Debug, Clone)]
pub struct DynamicRun {
    /// The dynamic model's input (built once from the scene).
    pub scene: DynamicScene,
    /// Speed–thrust curve, stall thrust, no-load speed, …
    pub result: DynamicResult,
    /// One post at the operating point, and the slider (transient only).
    pub histories: RunHistories,
}

/// Run the dynamic stage with the post springs `springs` and effective contact ratio
/// `effective_ratio`; `control` is asked before each point of the curve (each transient run).
pub fn run_dynamic(
    scene: &Scene,
    springs: &PostSprings,
    effective_ratio: f64,
    control: &RunControl,
) -> Result<DynamicRun, PipelineError> {
    let dynamic = dynamic_scene(scene, springs, effective_ratio)?;
    let (mut result, histories) =
        stick_slip::solve_with_histories(&dynamic, control).map_err(name_scene_keys)?;
    // The scene's own warnings (a wave value off the stator's cut, …) lead the model's.
    result.warnings.splice(0..0, scene.warnings.iter().cloned());
    Ok(DynamicRun {
        scene: dynamic,
        result,
        histories,
    })
}

/// Name the scene keys behind a size or cost refusal of the dynamic model (whose errors name its
/// own options).
fn name_scene_keys(error: StickSlipError) -> PipelineError {
    let keys = match &error {
        StickSlipError::MemoryLimit { parameter, .. } => match *parameter {
            "options.transient.periods" => "model.transient.periods",
            "options.curve_points" => "model.curve_points",
            "slider.layout" => "posts.count",
            _ => return error.into(),
        },
        StickSlipError::CostLimit { .. } => {
            "model.lumped.time_step, model.transient.periods, model.lumped.integrator, posts.count"
        }
        _ => return error.into(),
    };
    PipelineError::Unsupported {
        stage: "dynamic",
        message: format!("{error} [scene: {keys}]"),
    }
}

/// Write the lumped run's time-history charts into `dir`: a Fig. 6-style history of one post
/// (at the operating point, or at half the no-load speed when the load stalls the slider) and,
/// for the transient, the slider's history. `title` heads the charts. The result files
/// (`dynamic.json`, `curve.csv`, `speed_thrust`) are the dynamic stage's
/// ([`crate::pipeline::write_dynamic_stage_files`]).
pub fn write_history_charts(
    title: &str,
    run: &DynamicRun,
    dir: &Path,
) -> Result<Vec<PathBuf>, PipelineError> {
    let mut files = stick_slip::plots::write_post_history_chart(
        title,
        &run.histories.post,
        &dir.join("post_history"),
    )?;
    if let Some(slider) = &run.histories.slider {
        files.extend(stick_slip::plots::write_slider_history_chart(
            title,
            slider,
            &dir.join("slider_history"),
        )?);
    }
    Ok(files)
}
