//! `sawdrive run`: scene → springs → static (η) → dynamic → `OUT/<scene>/`, written atomically.

use std::path::{Path, PathBuf};
use std::time::Instant;

use contact_springs::PostSprings;
use serde::Serialize;

use super::{
    DynamicStage, PipelineError, RunControl, StaticOutcome, effective_ratio, run_dynamic_stage,
    scene_springs, write_dynamic_stage_files, write_static_files,
};
use crate::output::{ResultKind, StagedDir};
use crate::scene::Scene;

/// Where and how a run writes.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Results go to `out_dir/<scene name>/`.
    pub out_dir: PathBuf,
    /// Cache of FEM results and meshes (keyed by a hash of their inputs); `None`: no cache.
    pub cache_dir: Option<PathBuf>,
    /// Write charts, CSV and VTU files besides `summary.json` (off for sweep points).
    pub write_files: bool,
}

/// Wall time of each stage (s).
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct StageTimings {
    pub springs_s: f64,
    pub static_s: f64,
    pub dynamic_s: f64,
    pub output_s: f64,
    pub total_s: f64,
}

/// Static-stage figures carried into the summary.
#[derive(Debug, Clone, Serialize)]
pub struct StaticFigures {
    /// Whether the report came from the FEM cache.
    pub cached: bool,
    /// Content hash of the static inputs.
    pub content_hash: String,
    pub load_sharing: Option<f64>,
    pub contact_fraction: Option<f64>,
    pub complementarity_residual: Option<f64>,
    pub iterations: Option<u64>,
}

/// `summary.json` of a run.
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// The resolved scene (SI).
    pub scene: Scene,
    /// Johnson springs of one post (`None`: a ball slider).
    pub springs: Option<PostSprings>,
    /// η used by the dynamic model.
    pub effective_contact_ratio: f64,
    /// `given` (scene), `fem` (static stage) or `fem at the local amplitude` (the whole slider's
    /// static stage on the energy-conserving wave's profile at stall, docs/physics.md §5.5).
    pub effective_contact_ratio_source: String,
    /// N_eff = η·N.
    pub effective_post_count: f64,
    /// Static stage figures (when it ran).
    #[serde(rename = "static")]
    pub static_figures: Option<StaticFigures>,
    pub stall_thrust_n: f64,
    pub no_load_speed_m_per_s: f64,
    pub efficiency: f64,
    pub stick_fraction: f64,
    /// Which dynamic model ran (`coupled`, `periodic-average` or `transient`), and why.
    pub model: String,
    pub model_reason: String,
    /// Estimated relative error of the lumped model at the static η against the coupled model
    /// (`coupled_dynamics::lumped_error_estimate`); `None` when η was given.
    pub lumped_error_estimate: Option<f64>,
    /// Estimated relative error of the model that ran: `lumped_error_estimate` for a lumped
    /// model, the time-step error (Richardson, step halved) for the coupled one.
    pub model_error_estimate: Option<f64>,
    /// The coupled model's own figures, when it ran.
    pub coupled: Option<CoupledFigures>,
    pub curve: Vec<stick_slip::CurvePoint>,
    /// The scene's warnings (a given wave value more than 2 % off the stator's cut, a beam
    /// narrower than the post array, …; also in `scene.warnings`), then the lumped model's.
    pub warnings: Vec<stick_slip::Warning>,
    pub timings: StageTimings,
    /// Files written, relative to the results folder.
    pub files: Vec<String>,
    /// `normal_amplitude_m`, `electrical_power_w`, `overall_efficiency` with a drive voltage.
    #[serde(flatten)]
    pub drive: Option<super::DriveFigures>,
}

impl RunSummary {
    /// The headline figures are finite: a NaN or an infinity would be written as `null` and
    /// read as a result. Refused naming the figure; nothing is committed.
    pub(super) fn check_finite(&self) -> Result<(), PipelineError> {
        check_finite_figures(&[
            ("effective_contact_ratio", self.effective_contact_ratio),
            ("effective_post_count", self.effective_post_count),
            ("stall_thrust_n", self.stall_thrust_n),
            ("no_load_speed_m_per_s", self.no_load_speed_m_per_s),
            ("efficiency", self.efficiency),
            ("stick_fraction", self.stick_fraction),
        ])
    }
}

/// The dynamic stage's headline figures (stall thrust, no-load speed, efficiency, stick
/// fraction) are finite; see `check_finite_figures`.
pub fn check_dynamic_figures(stage: &super::DynamicStage) -> Result<(), PipelineError> {
    check_finite_figures(&[
        ("stall_thrust_n", stage.stall_thrust_n()),
        ("no_load_speed_m_per_s", stage.no_load_speed_m_per_s()),
        ("efficiency", stage.efficiency()),
        ("stick_fraction", stage.stick_fraction()),
    ])
}

/// Every named figure is a finite number, else an error naming the first that is not (JSON
/// would write it as `null`, read as a result).
fn check_finite_figures(figures: &[(&str, f64)]) -> Result<(), PipelineError> {
    match figures.iter().find(|(_, v)| !v.is_finite()) {
        None => Ok(()),
        Some((name, value)) => Err(PipelineError::Unsupported {
            stage: "dynamic",
            message: format!(
                "{name} came out as {value}: the scene's inputs lie outside the models' range (nothing was written)"
            ),
        }),
    }
}

/// The coupled model's figures carried into the summary (the whole result is `coupled.json`).
#[derive(Debug, Clone, Serialize)]
pub struct CoupledFigures {
    /// Largest energy-balance residual over the curve, relative to the power flow.
    pub energy_balance_residual: f64,
    /// η at which the lumped model reproduces the coupled curve best.
    pub eta_dyn: Option<f64>,
    /// Posts of the strip.
    pub posts: usize,
    pub steps_per_period: usize,
    /// The lumped model's figures at the static η, for comparison.
    pub lumped: super::LumpedFigures,
    pub warnings: Vec<String>,
}

impl CoupledFigures {
    fn of(stage: &DynamicStage) -> Option<Self> {
        let c = stage.coupled.as_ref()?;
        Some(Self {
            energy_balance_residual: c.energy_balance_residual,
            eta_dyn: c.eta_dyn,
            posts: c.posts,
            steps_per_period: c.steps_per_period,
            lumped: super::LumpedFigures::of(&stage.lumped.result),
            warnings: c.warnings.clone(),
        })
    }
}

/// Run every stage of `scene` and write `OUT/<name>/` (replacing earlier results only when all
/// succeeded). Returns the summary and the folder written. `control` is asked between the
/// stages and inside them (each static contact solve, each dynamic curve point; a stopped run
/// leaves `OUT/<name>/` as it was) and told each stage as it starts.
pub fn run_pipeline(
    scene: &Scene,
    options: &RunOptions,
    control: &RunControl,
) -> Result<(RunSummary, PathBuf), PipelineError> {
    if scene.ball.is_some() {
        return run_ball_pipeline(scene, options, control);
    }
    let start = Instant::now();
    let destination = options.out_dir.join(&scene.name);
    let staged = StagedDir::create(&destination, ResultKind::Run)?;
    let mut timings = StageTimings::default();

    control.stage("contact springs");
    let t = Instant::now();
    let springs = scene_springs(scene)?;
    timings.springs_s = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let eta = effective_ratio(
        scene,
        &springs,
        options.cache_dir.as_deref(),
        options.write_files,
        control,
    )?;
    let (effective_ratio, source, static_outcome) = (eta.value, eta.source, eta.statics);
    let static_figures = static_outcome.as_ref().map(static_figures);
    timings.static_s = t.elapsed().as_secs_f64();

    control.stage("stick/slip dynamics");
    let t = Instant::now();
    let (stage, static_files) = dynamic_beside_static_files(
        scene,
        options,
        control,
        &springs,
        effective_ratio,
        static_outcome.as_ref(),
        staged.path(),
    );
    let stage = stage?;
    PipelineError::check(control, "output")?;
    timings.dynamic_s = t.elapsed().as_secs_f64();

    control.stage("writing results");
    let t = Instant::now();
    let mut files = Vec::new();
    if let Some(written) = static_files {
        files.extend(written?);
    }
    if options.write_files {
        files.extend(write_dynamic_stage_files(
            &scene.name,
            &stage,
            staged.path(),
        )?);
    }
    timings.output_s = t.elapsed().as_secs_f64();
    timings.total_s = start.elapsed().as_secs_f64();

    let mut names: Vec<String> = files
        .iter()
        .filter_map(|f| f.file_name().and_then(|n| n.to_str()).map(str::to_owned))
        .collect();
    names.push("summary.json".into());
    let summary = run_summary(
        scene,
        springs,
        (effective_ratio, source),
        static_figures,
        &stage,
        timings,
        names,
    );
    summary.check_finite()?;
    staged.write("summary.json", serde_json::to_vec_pretty(&summary)?)?;
    let folder = staged.commit()?;
    Ok((summary, folder))
}

/// The static stage's figures of `summary.json`.
fn static_figures(outcome: &StaticOutcome) -> StaticFigures {
    let r = &outcome.report;
    StaticFigures {
        cached: outcome.cached,
        content_hash: outcome.content_hash.clone(),
        load_sharing: Some(r.load_sharing),
        contact_fraction: Some(r.contact_fraction),
        complementarity_residual: Some(r.complementarity_residual),
        iterations: Some(r.iterations as u64),
    }
}

/// The dynamic stage's outcome and, when written, the static files' outcome.
type StageAndStaticFiles = (
    Result<DynamicStage, PipelineError>,
    Option<Result<Vec<PathBuf>, PipelineError>>,
);

/// The dynamic stage, with the static fields written beside it. The static fields (VTU
/// snapshot: a displacement solve, stress recovery and ≈ 20 MB of text on the default scene)
/// depend on the static stage only: they are written on a thread of their own while the
/// dynamic stage runs, whose curve keeps about one of two cores busy (`dynamic_s` is the wall
/// time of both; `output_s` the rest of the files).
fn dynamic_beside_static_files(
    scene: &Scene,
    options: &RunOptions,
    control: &RunControl,
    springs: &PostSprings,
    effective_ratio: f64,
    static_outcome: Option<&StaticOutcome>,
    staged: &Path,
) -> StageAndStaticFiles {
    std::thread::scope(|scope| {
        let static_writer = (options.write_files && static_outcome.is_some()).then(|| {
            scope.spawn(|| {
                let outcome = static_outcome.expect("static outcome present");
                write_static_files(outcome, staged)
            })
        });
        let stage = run_dynamic_stage(
            scene,
            springs,
            effective_ratio,
            static_outcome,
            options.cache_dir.as_deref(),
            control,
        );
        let written = static_writer.map(|h| h.join().expect("static file writer panicked"));
        (stage, written)
    })
}

/// `summary.json` of a post-array run: the static stage's η (`eta`: value and source; the
/// local amplitude's when the dynamic stage settled one) and figures, the dynamic stage's
/// results, the timings and the files written.
fn run_summary(
    scene: &Scene,
    springs: PostSprings,
    (effective_ratio, source): (f64, &str),
    static_figures: Option<StaticFigures>,
    stage: &DynamicStage,
    timings: StageTimings,
    names: Vec<String>,
) -> RunSummary {
    RunSummary {
        scene: scene.clone(),
        springs: Some(springs),
        effective_contact_ratio: stage
            .local_amplitude
            .as_ref()
            .map_or(effective_ratio, |l| l.effective_contact_ratio),
        effective_contact_ratio_source: match stage.local_amplitude {
            Some(_) => "fem at the local amplitude".into(),
            None => source.into(),
        },
        effective_post_count: stage.lumped.result.effective_post_count,
        static_figures,
        stall_thrust_n: stage.stall_thrust_n(),
        no_load_speed_m_per_s: stage.no_load_speed_m_per_s(),
        efficiency: stage.efficiency(),
        stick_fraction: stage.stick_fraction(),
        model: stage.model_name().to_owned(),
        model_reason: stage.model_reason(),
        lumped_error_estimate: stage.lumped_error_estimate,
        model_error_estimate: stage.model_error_estimate(),
        coupled: CoupledFigures::of(&stage),
        curve: stage.curve(),
        warnings: stage.lumped.result.warnings.clone(),
        timings,
        files: names,
        drive: stage.drive,
    }
}

/// `sawdrive run` of a ball scene: the ball's dynamic stage and `OUT/<name>/` with its files
/// and `summary.json` (η and N_eff are 1: the one contact carries the whole preload; no
/// springs, static figures or lumped estimates).
fn run_ball_pipeline(
    scene: &Scene,
    options: &RunOptions,
    control: &RunControl,
) -> Result<(RunSummary, PathBuf), PipelineError> {
    let start = Instant::now();
    let staged = StagedDir::create(&options.out_dir.join(&scene.name), ResultKind::Run)?;
    PipelineError::check(control, "dynamic (ball)")?;
    let stage = super::run_ball_stage(scene)?;
    PipelineError::check(control, "output")?;
    let mut timings = StageTimings {
        dynamic_s: stage.wall_time_s,
        ..StageTimings::default()
    };
    let t = Instant::now();
    let mut names = Vec::new();
    if options.write_files {
        for file in super::write_ball_stage_files(&scene.name, &stage, staged.path())? {
            names.extend(file.file_name().and_then(|n| n.to_str()).map(str::to_owned));
        }
    }
    names.push("summary.json".into());
    timings.output_s = t.elapsed().as_secs_f64();
    timings.total_s = start.elapsed().as_secs_f64();
    let r = &stage.result;
    let summary = RunSummary {
        scene: scene.clone(),
        springs: None,
        effective_contact_ratio: 1.0,
        effective_contact_ratio_source: "ball".into(),
        effective_post_count: 1.0,
        static_figures: None,
        stall_thrust_n: r.stall_thrust_n,
        no_load_speed_m_per_s: r.no_load_speed_m_per_s,
        efficiency: r.max_efficiency,
        stick_fraction: stage.stick_fraction(),
        model: "ball".into(),
        model_reason: super::dynamic_stage::ball::BALL_REASON.into(),
        lumped_error_estimate: None,
        model_error_estimate: None,
        coupled: None,
        curve: stage.curve(),
        warnings: stage.warnings.clone(),
        timings,
        files: names,
        drive: stage.drive,
    };
    summary.check_finite()?;
    staged.write("summary.json", serde_json::to_vec_pretty(&summary)?)?;
    let folder = staged.commit()?;
    Ok((summary, folder))
}
