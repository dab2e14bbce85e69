//! Static stage: the slider pressed on the frozen wave → post forces and η, by the model
//! `static.model` chooses ([`StaticModel::choose`]): the strip (one post row, FEM) here, the
//! whole slider in [`super::slider`]. The strip's verified cache ([`super::cache`]):
//! `static-<content hash>.json` holds the typed report with the SHA-256 of its JSON and of the
//! cached field files; an entry that fails the check is rebuilt and reported on stderr, and
//! results folders get copies of cached files (never hard links).

use std::path::{Path, PathBuf};

use contact_springs::PostSprings;
use serde::Serialize;
use static_contact::{ContactError, StaticAnalysis, StaticParams, StaticReport};

use super::cache::{self, Entry, Layout, Lookup};
use super::keys::static_params;
use super::slider::{SliderStage, announce, run_slider_static, write_slider_maps};
use crate::output::{ResultKind, StagedDir, io};
use crate::pipeline::{PipelineError, RunControl};
use crate::scene::{Scene, StaticModel};

/// The static stage's report, whichever model ran: the contract's numbers as fields (the same
/// for both models) and the model's own report. Its JSON is the model's report with `model`,
/// `model_reason` and `wall_time_s` added at the top level.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticStageReport {
    /// The model that ran: `Strip` or `Slider`.
    pub model: StaticModel,
    /// Why that model (one line).
    pub model_reason: String,
    /// η (`None`: not identifiable).
    pub effective_contact_ratio: Option<f64>,
    /// Why η is `None` or what limits it.
    pub effective_contact_ratio_note: Option<String>,
    /// Load sharing (Σf)²/(N Σf²).
    pub load_sharing: f64,
    /// Fraction of posts in contact.
    pub contact_fraction: f64,
    /// Largest scaled complementarity residual.
    pub complementarity_residual: f64,
    /// Solver iterations (active-set for the strip, CG for the slider).
    pub iterations: usize,
    /// The stage's own wall time (s); for the slider without the one-off cell FEM.
    pub wall_time_s: f64,
    /// The model's report.
    pub details: StaticDetails,
}

/// The report of the model that ran.
#[derive(Debug, Clone, PartialEq)]
pub enum StaticDetails {
    /// The strip FEM's report.
    Strip(Box<StaticReport>),
    /// The whole slider's.
    Slider(Box<SliderStage>),
}

impl StaticStageReport {
    fn strip(report: StaticReport, model_reason: String) -> Self {
        Self {
            model: StaticModel::Strip,
            model_reason,
            effective_contact_ratio: report.effective_contact_ratio,
            effective_contact_ratio_note: report.effective_contact_ratio_note.clone(),
            load_sharing: report.load_sharing,
            contact_fraction: report.contact_fraction,
            complementarity_residual: report.complementarity_residual,
            iterations: report.iterations,
            wall_time_s: report.timings.wall_time_s,
            details: StaticDetails::Strip(Box::new(report)),
        }
    }

    fn slider(stage: SliderStage, model_reason: String) -> Self {
        let r = &stage.report;
        Self {
            model: StaticModel::Slider,
            model_reason,
            effective_contact_ratio: r.effective_contact_ratio,
            effective_contact_ratio_note: r.eta_fit.reason.clone(),
            load_sharing: r.load_sharing,
            contact_fraction: r.contact_fraction,
            complementarity_residual: r.complementarity_residual,
            iterations: r.iterations,
            wall_time_s: r.wall_time_s,
            details: StaticDetails::Slider(Box::new(stage)),
        }
    }
}

impl Serialize for StaticStageReport {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::Error;
        let value = match &self.details {
            StaticDetails::Strip(r) => serde_json::to_value(r),
            StaticDetails::Slider(stage) => serde_json::to_value(stage),
        }
        .map_err(S::Error::custom)?;
        let serde_json::Value::Object(mut map) = value else {
            return Err(S::Error::custom("a static report is a JSON object"));
        };
        // The slider's report comes up to the top level, next to its near field and hash.
        if let Some(serde_json::Value::Object(inner)) = map.remove("report") {
            map.extend(inner);
        }
        map.insert("model".into(), self.model.name().into());
        map.insert("model_reason".into(), self.model_reason.clone().into());
        map.insert("wall_time_s".into(), self.wall_time_s.into());
        map.serialize(serializer)
    }
}

/// Result of the static stage: the analysis (fresh runs) or the cached report.
#[derive(Debug)]
pub struct StaticOutcome {
    /// The typed report (fresh or from the verified cache).
    pub report: StaticStageReport,
    /// η at the scene's preload (`None`: not identifiable, e.g. flat stator).
    pub effective_ratio: Option<f64>,
    /// Content hash of the inputs.
    pub content_hash: String,
    /// Whether the report came from the cache.
    pub cached: bool,
    /// Seconds of the one-off cell FEM that calibrated the slider's near field in this run
    /// (0: strip model, or the near field came from the cache).
    pub cell_fem_s: f64,
    /// The analysis, for field and chart output (fresh strip runs only).
    pub analysis: Option<StaticAnalysis>,
    /// Cached field files (force chart, VTU) of these inputs, if they were asked for and exist.
    pub cached_fields: Option<PathBuf>,
    /// What the cache checks found and did (a damaged entry or mesh rebuilt), one line each;
    /// also printed on stderr.
    pub notes: Vec<String>,
}

/// The strip report's cache entries, `static-<content hash>.json`: the typed report (which
/// carries its content hash) with the SHA-256 of its JSON and of the cached field files. Format
/// 2: the report gained the FEM ordering flag and the whole-slider stage report.
const REPORT_ENTRY: Layout = Layout {
    format: 2,
    key_field: None,
    hash_field: "report_sha256",
    sidecar_field: Some("field_files"),
    value_field: "report",
};

/// Read and verify the entry `file` for the inputs `content_hash`; with `fields`, also the
/// field files in that folder against the hashes the entry recorded.
pub(super) fn lookup(
    file: &Path,
    content_hash: &str,
    fields: Option<&Path>,
) -> Lookup<StaticReport> {
    let entry = Entry {
        file,
        layout: &REPORT_ENTRY,
        key: content_hash,
        sidecars: fields,
    };
    cache::get(&entry, |report: &StaticReport| {
        match report.content_hash == content_hash {
            true => Ok(()),
            false => Err("it holds the report of other inputs".into()),
        }
    })
}

/// Write the entry for `report` (with the hashes of the field files in `fields`, if any).
pub(super) fn store(
    file: &Path,
    report: &StaticReport,
    fields: Option<&Path>,
) -> Result<(), PipelineError> {
    let entry = Entry {
        file,
        layout: &REPORT_ENTRY,
        key: &report.content_hash,
        sidecars: fields,
    };
    cache::put(&entry, report)
}

/// A solver that stopped names the scene keys that limit it; other errors pass through.
pub(super) fn static_error(error: ContactError, params: &StaticParams) -> PipelineError {
    match error {
        e @ ContactError::NotConverged { .. } => PipelineError::StaticNotConverged {
            source: e,
            max_iterations: params.max_iterations,
            tolerance: params.contact_tolerance,
        },
        e => e.into(),
    }
}

/// Run the static stage by the model `static.model` chooses (`auto`: the strip for the ideal
/// motor, else the whole slider, said so on stderr). The whole slider: [`run_slider_static`].
/// The strip: with the post springs `springs` (computed once per run), or its report from
/// `cache_dir/static-<hash>.json` when the same inputs ran before and the entry verifies (a
/// damaged entry is rebuilt, and said so on stderr). With `with_fields`, the cache also keeps
/// the force chart and the VTU in `cache_dir/static-<hash>/`, and a cached report without them
/// (e.g. one a sweep filled in) counts as a miss, so that a results folder never lacks them.
/// `control` is asked before the stage and, for the strip, before its condensation and each
/// contact solve; a stopped run writes nothing to the cache. The whole slider's solve and the
/// FEM factorisation are not interrupted.
pub fn run_static(
    scene: &Scene,
    springs: &PostSprings,
    cache_dir: Option<&Path>,
    with_fields: bool,
    control: &RunControl,
) -> Result<StaticOutcome, PipelineError> {
    PipelineError::check(control, "static")?;
    let (model, reason) = scene.static_fem.model.choose(&scene.motor);
    if model == StaticModel::Slider {
        let (stage, cell_fem_s, cached, mut notes) = run_slider_static(scene, cache_dir)?;
        // Said after the run, so that an error stays one line (it names the slider model).
        if scene.static_fem.model == StaticModel::Auto {
            notes.push(reason.clone());
        }
        announce(&notes);
        return Ok(StaticOutcome {
            effective_ratio: stage.report.effective_contact_ratio,
            content_hash: stage.content_hash.clone(),
            report: StaticStageReport::slider(stage, reason),
            cached,
            cell_fem_s,
            analysis: None,
            cached_fields: None,
            notes,
        });
    }
    let params = static_params(scene, cache_dir.map(|d| d.join("meshes")).as_deref())?;
    let content_hash = params.content_hash()?;
    let cache_file = cache_dir.map(|d| d.join(format!("static-{content_hash}.json")));
    let fields_dir = cache_dir
        .filter(|_| with_fields)
        .map(|d| d.join(format!("static-{content_hash}")));
    let mut notes = Vec::new();
    if let Some(file) = &cache_file {
        match lookup(file, &content_hash, fields_dir.as_deref()) {
            Lookup::Hit(report) => {
                return Ok(StaticOutcome {
                    effective_ratio: report.effective_contact_ratio,
                    report: StaticStageReport::strip(report, reason),
                    content_hash,
                    cached: true,
                    cell_fem_s: 0.0,
                    analysis: None,
                    cached_fields: fields_dir,
                    notes,
                });
            }
            Lookup::Damaged(why) => notes.push(format!(
                "static cache entry {} not used: {why}; recomputing it",
                file.display()
            )),
            Lookup::Miss => {}
        }
    }
    announce(&notes);
    let analysis =
        analyse_strip(&params, springs, control).map_err(|e| static_error(e, &params))?;
    announce(&analysis.notes);
    notes.extend(analysis.notes.iter().cloned());
    if let Some(dir) = &fields_dir {
        let staged = StagedDir::create(dir, ResultKind::Fields)?;
        write_field_files(&analysis, staged.path())?;
        staged.commit()?;
    }
    if let Some(file) = &cache_file {
        store(file, &analysis.report, fields_dir.as_deref())?;
    }
    Ok(StaticOutcome {
        effective_ratio: analysis.report.effective_contact_ratio,
        report: StaticStageReport::strip(analysis.report.clone(), reason),
        content_hash,
        cached: false,
        cell_fem_s: 0.0,
        analysis: Some(analysis),
        cached_fields: fields_dir,
        notes,
    })
}

/// The strip of `params` prepared (mesh, condensation) and analysed; `control` is asked before
/// the mesh and condensation (which cannot be interrupted) and before each contact solve.
fn analyse_strip(
    params: &StaticParams,
    springs: &PostSprings,
    control: &RunControl,
) -> Result<StaticAnalysis, ContactError> {
    if control.should_stop() {
        return Err(ContactError::Cancelled {
            before: "the strip's mesh and condensation".into(),
        });
    }
    let strip = static_contact::prepare_strip(params)?;
    let report = strip.analyse(params, springs, control)?;
    Ok(strip.into_analysis(params, report))
}

/// Write the post-force chart and the VTU of the first snapshot of `analysis` into `dir`.
fn write_field_files(analysis: &StaticAnalysis, dir: &Path) -> Result<Vec<PathBuf>, PipelineError> {
    let mut files =
        static_contact::output::write_force_chart(analysis, 0, 0, &dir.join("post_forces"))?;
    if let Some(snapshot) = analysis
        .report
        .preloads
        .first()
        .and_then(|p| p.snapshots.first())
    {
        let vtu = dir.join("static_snapshot0.vtu");
        static_contact::output::write_snapshot_vtu(analysis, snapshot, &vtu)?;
        files.push(vtu);
    }
    Ok(files)
}

/// Copy every file of `from` into `dir`: copies, never hard links, so that editing a result
/// cannot change the cache (and the reverse).
fn copy_files(from: &Path, dir: &Path) -> Result<Vec<PathBuf>, PipelineError> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(from).map_err(io("read the cached fields", from))? {
        let source = entry.map_err(io("read the cached fields", from))?.path();
        let Some(name) = source.file_name() else {
            continue;
        };
        // The cache folder's own marker (atomic_files::RESULT_MARKER) is not a field file.
        if name.to_string_lossy().starts_with('.') {
            continue;
        }
        let target = dir.join(name);
        std::fs::copy(&source, &target).map_err(io("copy a cached field file", &source))?;
        files.push(target);
    }
    files.sort();
    Ok(files)
}

/// Write `static.json` and the field files into `dir`: for the strip, the post-force chart and
/// the VTU of the first snapshot (from the analysis, or copied from the cache); for the whole
/// slider, its 2D post-force map ([`write_slider_maps`]).
pub fn write_static_files(
    outcome: &StaticOutcome,
    dir: &Path,
) -> Result<Vec<PathBuf>, PipelineError> {
    let mut files = vec![dir.join("static.json")];
    std::fs::write(&files[0], serde_json::to_vec_pretty(&outcome.report)?)
        .map_err(io("write", &files[0]))?;
    if let StaticDetails::Slider(stage) = &outcome.report.details {
        files.extend(write_slider_maps(stage, dir)?);
        return Ok(files);
    }
    match (&outcome.cached_fields, &outcome.analysis) {
        (Some(cached), _) if cached.is_dir() => files.extend(copy_files(cached, dir)?),
        (_, Some(analysis)) => files.extend(write_field_files(analysis, dir)?),
        _ => {}
    }
    Ok(files)
}
