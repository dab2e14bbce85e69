//! `sawdrive run`: scene → springs → static (η) → dynamic → `OUT/<scene>/`, written atomically.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use contact_springs::PostSprings;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use stick_slip::DynamicResult;

use super::{
    PipelineError, run_dynamic, run_static, scene_springs, write_dynamic_files, write_static_files,
};
use crate::output::StagedDir;
use crate::scene::Scene;

/// Where and how a run writes.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Results go to `out_dir/<scene name>/`.
    pub out_dir: PathBuf,
    /// Cache of FEM results and meshes (keyed by a hash of their inputs); `None`: no cache.
    pub cache_dir: Option<PathBuf>,
    /// Show a progress spinner on a terminal.
    pub progress: bool,
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
    /// Johnson springs of one post.
    pub springs: PostSprings,
    /// η used by the dynamic model.
    pub effective_contact_ratio: f64,
    /// `given` (scene) or `fem` (static stage).
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
    /// Which dynamic model ran, and why.
    pub model: String,
    pub model_reason: String,
    pub curve: Vec<stick_slip::CurvePoint>,
    pub timings: StageTimings,
    /// Files written, relative to the results folder.
    pub files: Vec<String>,
}

fn spinner(enabled: bool) -> ProgressBar {
    if !enabled || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new_spinner();
    if let Ok(style) = ProgressStyle::with_template("{spinner} [{elapsed}] {msg}") {
        bar.set_style(style);
    }
    bar.enable_steady_tick(Duration::from_millis(120));
    bar
}

/// Run every stage of `scene` and write `OUT/<name>/` (replacing earlier results only when all
/// succeeded). Returns the summary and the folder written.
pub fn run_pipeline(
    scene: &Scene,
    options: &RunOptions,
) -> Result<(RunSummary, PathBuf), PipelineError> {
    let start = Instant::now();
    let destination = options.out_dir.join(&scene.name);
    let staged = StagedDir::create(&destination)?;
    let bar = spinner(options.progress);
    let mut timings = StageTimings::default();

    bar.set_message("contact springs");
    let t = Instant::now();
    let springs = scene_springs(scene)?;
    timings.springs_s = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let (effective_ratio, source, static_figures, static_outcome) =
        match scene.contact.effective_ratio {
            Some(eta) => (eta, "given", None, None),
            None => {
                bar.set_message("static FEM contact (η)");
                let outcome = run_static(
                    scene,
                    &springs,
                    options.cache_dir.as_deref(),
                    options.write_files,
                )?;
                let eta = outcome.effective_ratio.ok_or_else(|| PipelineError::Unsupported {
                stage: "static",
                message: format!(
                    "η is not identifiable for this scene ({}); give effective_ratio as a number",
                    outcome
                        .report
                        .effective_contact_ratio_note
                        .as_deref()
                        .unwrap_or("no reason given")
                ),
            })?;
                let r = &outcome.report;
                let figures = StaticFigures {
                    cached: outcome.cached,
                    content_hash: outcome.content_hash.clone(),
                    load_sharing: Some(r.load_sharing),
                    contact_fraction: Some(r.contact_fraction),
                    complementarity_residual: Some(r.complementarity_residual),
                    iterations: Some(r.iterations as u64),
                };
                (eta, "fem", Some(figures), Some(outcome))
            }
        };
    timings.static_s = t.elapsed().as_secs_f64();

    bar.set_message("stick/slip dynamics");
    let t = Instant::now();
    let run = run_dynamic(scene, &springs, effective_ratio)?;
    let dynamic: &DynamicResult = &run.result;
    timings.dynamic_s = t.elapsed().as_secs_f64();

    bar.set_message("writing results");
    let t = Instant::now();
    let mut files = Vec::new();
    if options.write_files {
        if let Some(outcome) = &static_outcome {
            files.extend(write_static_files(outcome, staged.path())?);
        }
        files.extend(write_dynamic_files(&scene.name, &run, staged.path())?);
    }
    timings.output_s = t.elapsed().as_secs_f64();
    timings.total_s = start.elapsed().as_secs_f64();

    let mut names: Vec<String> = files
        .iter()
        .filter_map(|f| f.file_name().and_then(|n| n.to_str()).map(str::to_owned))
        .collect();
    names.push("summary.json".into());
    let summary = RunSummary {
        scene: scene.clone(),
        springs,
        effective_contact_ratio: effective_ratio,
        effective_contact_ratio_source: source.into(),
        effective_post_count: dynamic.effective_post_count,
        static_figures,
        stall_thrust_n: dynamic.stall_thrust_n,
        no_load_speed_m_per_s: dynamic.no_load_speed_m_per_s,
        efficiency: dynamic.efficiency,
        stick_fraction: dynamic.stick_fraction,
        model: serde_json::to_value(dynamic.model)?
            .as_str()
            .unwrap_or_default()
            .to_owned(),
        model_reason: dynamic.model_reason.clone(),
        curve: dynamic.curve.clone(),
        timings,
        files: names,
    };
    staged.write("summary.json", serde_json::to_vec_pretty(&summary)?)?;
    let folder = staged.commit()?;
    bar.finish_and_clear();
    Ok((summary, folder))
}
