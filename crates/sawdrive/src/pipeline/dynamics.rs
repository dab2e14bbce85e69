//! Dynamic stage: the scene's wave, posts (k_n, k_t from Johnson) and slider → stick-slip.

use std::path::{Path, PathBuf};

use contact_springs::PostSprings;
use stick_slip::{
    DynamicResult, DynamicScene, HistoryOptions, Integrator, ModelChoice, ModelKind, PostContact,
    PostLayout, RunHistories, Slider, SolveOptions, StabilityPolicy, StickSlipError,
    TransientOptions, VerticalModel, Wave,
};

use super::PipelineError;
use crate::output::io;
use crate::scene::{
    DEFAULT_CURVE_POINTS, DEFAULT_TRANSIENT_PERIODS, DEFAULT_VERTICAL_DAMPING_RATIO,
    DynamicsChoice, IntegratorChoice, Model, Scene, VerticalChoice,
};

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

/// Post layout along x: a centred square array, or explicit positions for rectangular arrays
/// (one x per post: refused before allocating when above the run's memory limit).
fn layout(scene: &Scene) -> Result<PostLayout, PipelineError> {
    let p = &scene.posts;
    if p.count_x == p.count_y && (p.pitch_x_m - p.pitch_y_m).abs() <= 1e-12 * p.pitch_x_m {
        return Ok(PostLayout::SquareArray {
            posts_per_side: p.count_x as usize,
            pitch_m: p.pitch_x_m,
        });
    }
    let bytes = p.count as f64 * 4.0 * std::mem::size_of::<f64>() as f64;
    if bytes > stick_slip::MAX_RUN_MEMORY_BYTES {
        return Err(PipelineError::Unsupported {
            stage: "dynamic",
            message: format!(
                "posts.count: a rectangular array of {} posts needs ≈ {bytes:.3e} bytes of post positions, above the limit of {:.3e} bytes",
                p.count,
                stick_slip::MAX_RUN_MEMORY_BYTES
            ),
        });
    }
    let centre = 0.5 * (f64::from(p.count_x) - 1.0);
    let x_m = (0..p.count_x)
        .flat_map(|j| {
            std::iter::repeat_n((f64::from(j) - centre) * p.pitch_x_m, p.count_y as usize)
        })
        .collect();
    Ok(PostLayout::Positions { x_m, gap_m: None })
}

/// The dynamic model's input for `scene` with the post springs `springs` (from
/// [`scene_springs`](super::scene_springs), computed once per run) and effective contact ratio
/// `effective_ratio`.
pub fn dynamic_scene(
    scene: &Scene,
    springs: &PostSprings,
    effective_ratio: f64,
) -> Result<DynamicScene, PipelineError> {
    let wave = Wave {
        frequency_hz: scene.wave.frequency_hz,
        normal_amplitude_m: scene.wave.normal_amplitude_m,
        tangential_amplitude_m: scene.wave.tangential_amplitude_m,
        phase_velocity_m_per_s: scene.wave.phase_velocity_m_per_s,
        decay_length_m: scene.wave.decay_length_m,
        burst_periods: scene.wave.burst_periods,
    };
    let m = &scene.model;
    let needs_mass = matches!(
        m.integrator,
        IntegratorChoice::Regularized | IntegratorChoice::PostMass
    );
    let post_mass = PostContact::cylinder_mass_kg(
        scene.slider.material.density_kg_per_m3,
        scene.posts.radius_m(),
        scene.posts.height_m,
    );
    let contact = PostContact {
        k_n_n_per_m: springs.k_n_n_per_m,
        k_t_n_per_m: springs.k_t_n_per_m,
        mu_static: scene.friction.mu_static,
        mu_kinetic: scene.friction.mu_kinetic,
        post_mass_kg: needs_mass.then_some(post_mass),
    };
    let slider = Slider {
        mass_kg: scene.slider.mass_kg,
        preload_n: scene.load.preload_n,
        external_load_n: scene.load.external_load_n,
        layout: layout(scene)?,
        effective_ratio,
        vertical: match m.vertical {
            VerticalChoice::QuasiStatic => VerticalModel::PeriodMean,
            VerticalChoice::Dynamic => VerticalModel::Dynamic {
                damping_ratio: m
                    .vertical_damping_ratio
                    .unwrap_or(DEFAULT_VERTICAL_DAMPING_RATIO),
            },
        },
    };
    let model = match m.dynamics {
        DynamicsChoice::Auto => ModelChoice::Auto,
        DynamicsChoice::PeriodicAverage => ModelChoice::PeriodicAverage,
        DynamicsChoice::Transient => ModelChoice::Transient,
    };
    let mut dynamic = DynamicScene {
        wave,
        contact,
        slider,
        model,
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
                    "model.periods",
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
            IntegratorChoice::Auto | IntegratorChoice::EventDriven
        );
    if let (Some(dt), true) = (m.time_step_s, closed_form) {
        return Err(unused(
            "model.time_step",
            format!("{dt:e} s"),
            "the period average runs the closed-form event-driven post, which has no time step; set model.integrator to return-mapping, post-mass or regularized, or model.dynamics = \"transient\"",
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
        IntegratorChoice::Auto => match m.time_step_s {
            Some(dt_s) => Integrator::ReturnMapping { dt_s },
            None => Integrator::Auto,
        },
        IntegratorChoice::EventDriven => Integrator::EventDriven {
            max_step_s: m.time_step_s,
        },
        IntegratorChoice::ReturnMapping => Integrator::ReturnMapping {
            dt_s: m.time_step_s.unwrap_or(period / AUTO_STEPS_PER_PERIOD),
        },
        IntegratorChoice::Regularized => {
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
        IntegratorChoice::PostMass => Integrator::PostMass {
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
/// `effective_ratio`.
pub fn run_dynamic(
    scene: &Scene,
    springs: &PostSprings,
    effective_ratio: f64,
) -> Result<DynamicRun, PipelineError> {
    let dynamic = dynamic_scene(scene, springs, effective_ratio)?;
    let (result, histories) =
        stick_slip::solve_with_histories(&dynamic).map_err(name_scene_keys)?;
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
            "options.transient.periods" => "model.periods",
            "options.curve_points" => "model.curve_points",
            "slider.layout" => "posts.count",
            _ => return error.into(),
        },
        StickSlipError::CostLimit { .. } => {
            "model.time_step, model.periods, model.integrator, posts.count"
        }
        _ => return error.into(),
    };
    PipelineError::Unsupported {
        stage: "dynamic",
        message: format!("{error} [scene: {keys}]"),
    }
}

/// Write `dynamic.json`, `curve.csv`, the speed–thrust chart, a Fig. 6-style time history of
/// one post (at the operating point, or at half the no-load speed when the load stalls the
/// slider) and, for the transient, the slider's history into `dir`. `title` heads the charts.
pub fn write_dynamic_files(
    title: &str,
    run: &DynamicRun,
    dir: &Path,
) -> Result<Vec<PathBuf>, PipelineError> {
    let result = &run.result;
    let mut files = vec![dir.join("dynamic.json"), dir.join("curve.csv")];
    std::fs::write(&files[0], serde_json::to_vec_pretty(result)?)
        .map_err(io("write", &files[0]))?;
    std::fs::write(&files[1], stick_slip::curve_csv(&result.curve))
        .map_err(io("write", &files[1]))?;
    files.extend(stick_slip::plots::write_speed_thrust_chart(
        result,
        &dir.join("speed_thrust"),
    )?);
    files.extend(stick_slip::plots::write_post_history_chart(
        title,
        &run.histories.post,
        &dir.join("post_history"),
    )?);
    if let Some(slider) = &run.histories.slider {
        files.extend(stick_slip::plots::write_slider_history_chart(
            title,
            slider,
            &dir.join("slider_history"),
        )?);
    }
    Ok(files)
}
