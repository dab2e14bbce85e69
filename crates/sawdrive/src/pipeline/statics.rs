//! Static stage: the slider strip pressed on the frozen wave → post forces and η.

use std::path::{Path, PathBuf};

use static_contact::{MeshChoice, StaticAnalysis, StaticParams, StatorModel};

use super::PipelineError;
use crate::output::{StagedDir, io};
use crate::scene::{Scene, StatorChoice};

/// Relative tolerance on equal x and y pitch (the strip model needs a square post lattice).
const PITCH_MISMATCH_TOLERANCE: f64 = 1e-9;

/// The static stage's parameters for `scene`.
pub fn static_params(
    scene: &Scene,
    mesh_cache_dir: Option<&Path>,
) -> Result<StaticParams, PipelineError> {
    let posts = &scene.posts;
    if (posts.pitch_x_m - posts.pitch_y_m).abs() > PITCH_MISMATCH_TOLERANCE * posts.pitch_x_m {
        return Err(PipelineError::Unsupported {
            stage: "static",
            message: format!(
                "the strip model needs equal pitch in x and y, got {} m and {} m (posts.array / count): \
                 give effective_ratio as a number to skip the static stage",
                posts.pitch_x_m, posts.pitch_y_m
            ),
        });
    }
    let mesh = match scene.static_fem.mesh.as_str() {
        "auto" => MeshChoice::Auto,
        path => MeshChoice::File(PathBuf::from(path)),
    };
    Ok(StaticParams {
        slider_material: scene.slider.material.clone(),
        stator_material: scene.stator.clone(),
        post_diameter_m: posts.diameter_m,
        post_height_m: posts.height_m,
        posts_x: posts.count_x as usize,
        posts_y: posts.count_y as usize,
        post_pitch_m: posts.pitch_x_m,
        slider_length_m: scene.slider.length_m,
        slider_width_m: scene.slider.width_m,
        slider_thickness_m: scene.slider.thickness_m,
        wave_amplitude_m: scene.wave.normal_amplitude_m,
        wavelength_m: scene.wave.wavelength_m,
        preload_n: scene.load.preload_n,
        phases: scene.static_fem.phases as usize,
        element_order: scene.static_fem.element_order as u8,
        strip_rows: scene.static_fem.strip_rows as usize,
        stator: match scene.static_fem.stator {
            StatorChoice::HalfSpace => StatorModel::HalfSpace,
            StatorChoice::MeshedBlock => StatorModel::MeshedBlock,
        },
        mesh,
        mesh_cache_dir: mesh_cache_dir.map(Path::to_owned),
        ..StaticParams::default()
    })
}

/// Result of the static stage: the analysis (fresh runs) or the cached report.
#[derive(Debug)]
pub struct StaticOutcome {
    /// The report as JSON (fresh or from the cache).
    pub report_json: serde_json::Value,
    /// η at the scene's preload (`None`: not identifiable, e.g. flat stator).
    pub effective_ratio: Option<f64>,
    /// Content hash of the inputs.
    pub content_hash: String,
    /// Whether the report came from the cache.
    pub cached: bool,
    /// The analysis, for field and chart output (fresh runs only).
    pub analysis: Option<StaticAnalysis>,
    /// Cached field files (force chart, VTU) of these inputs, if they were asked for and exist.
    pub cached_fields: Option<PathBuf>,
}

/// Run the static stage, or take its report from `cache_dir/static-<hash>.json` when the same
/// inputs ran before. With `with_fields`, the cache also keeps the force chart and the VTU in
/// `cache_dir/static-<hash>/`, and a cached report without them (e.g. one a sweep filled in)
/// counts as a miss, so that a results folder never lacks them.
pub fn run_static(
    scene: &Scene,
    cache_dir: Option<&Path>,
    with_fields: bool,
) -> Result<StaticOutcome, PipelineError> {
    let params = static_params(scene, cache_dir.map(|d| d.join("meshes")).as_deref())?;
    let content_hash = params.content_hash()?;
    let cache_file = cache_dir.map(|d| d.join(format!("static-{content_hash}.json")));
    let fields_dir = cache_dir
        .filter(|_| with_fields)
        .map(|d| d.join(format!("static-{content_hash}")));
    let fields_cached = fields_dir.as_ref().is_none_or(|d| d.is_dir());
    if let (Some(file), true) = (&cache_file, fields_cached) {
        if let Some(report_json) = std::fs::read(file)
            .ok()
            .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
        {
            let effective_ratio = report_json["effective_contact_ratio"].as_f64();
            return Ok(StaticOutcome {
                report_json,
                effective_ratio,
                content_hash,
                cached: true,
                analysis: None,
                cached_fields: fields_dir,
            });
        }
    }
    let analysis = static_contact::run(&params)?;
    let report_json = serde_json::to_value(&analysis.report)?;
    if let Some(dir) = &fields_dir {
        let staged = StagedDir::create(dir)?;
        write_field_files(&analysis, staged.path())?;
        staged.commit()?;
    }
    if let Some(file) = &cache_file {
        crate::output::write_atomically(file, serde_json::to_vec(&report_json)?)?;
    }
    Ok(StaticOutcome {
        effective_ratio: analysis.report.effective_contact_ratio,
        report_json,
        content_hash,
        cached: false,
        analysis: Some(analysis),
        cached_fields: fields_dir,
    })
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

/// Put every file of `from` into `dir`: a hard link where the file system allows (the VTU of
/// the default scene is ≈ 33 MB), a copy otherwise.
fn link_or_copy_files(from: &Path, dir: &Path) -> Result<Vec<PathBuf>, PipelineError> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(from).map_err(io("read the cached fields", from))? {
        let source = entry.map_err(io("read the cached fields", from))?.path();
        let Some(name) = source.file_name() else {
            continue;
        };
        let target = dir.join(name);
        if std::fs::hard_link(&source, &target).is_err() {
            std::fs::copy(&source, &target).map_err(io("copy a cached field file", &source))?;
        }
        files.push(target);
    }
    files.sort();
    Ok(files)
}

/// Write `static.json`, the post-force chart and the VTU of the first snapshot into `dir` (the
/// last two from the analysis, or from the cache).
pub fn write_static_files(
    outcome: &StaticOutcome,
    dir: &Path,
) -> Result<Vec<PathBuf>, PipelineError> {
    let mut files = vec![dir.join("static.json")];
    std::fs::write(&files[0], serde_json::to_vec_pretty(&outcome.report_json)?)
        .map_err(io("write", &files[0]))?;
    match (&outcome.cached_fields, &outcome.analysis) {
        (Some(cached), _) if cached.is_dir() => files.extend(link_or_copy_files(cached, dir)?),
        (_, Some(analysis)) => files.extend(write_field_files(analysis, dir)?),
        _ => {}
    }
    Ok(files)
}

/// Hash of what the condensed strip model depends on: the static inputs without the preloads
/// and snapshot phases (which only enter the cheap contact solves).
pub fn geometry_key(params: &StaticParams) -> Result<String, PipelineError> {
    let mut geometry = params.clone();
    geometry.preload_n = 1.0;
    geometry.preload_sweep_n.clear();
    geometry.phases = 1;
    Ok(geometry.content_hash()?)
}

/// Fill the static cache for many scenes (a sweep) with one FEM condensation per distinct
/// geometry: scenes that differ only in preload share the factorised strip, and each gets its
/// own cached report. Scenes with a given η or an existing cache entry are skipped. Returns the
/// number of condensations run and the groups that failed (their points fail on their own later).
pub fn fill_static_cache(scenes: &[Scene], cache_dir: &Path) -> (usize, Vec<(String, String)>) {
    let mut groups: Vec<(String, Vec<(StaticParams, String)>)> = Vec::new();
    for scene in scenes
        .iter()
        .filter(|s| s.contact.effective_ratio.is_none())
    {
        let Ok(params) = static_params(scene, Some(&cache_dir.join("meshes"))) else {
            continue;
        };
        let (Ok(key), Ok(hash)) = (geometry_key(&params), params.content_hash()) else {
            continue;
        };
        if cache_dir.join(format!("static-{hash}.json")).exists() {
            continue;
        }
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, members)) if !members.iter().any(|(_, h)| *h == hash) => {
                members.push((params, hash))
            }
            Some(_) => {}
            None => groups.push((key, vec![(params, hash)])),
        }
    }
    let mut built = 0;
    let mut failures = Vec::new();
    for (key, members) in groups {
        if let Err(e) = condense_and_cache(&members, cache_dir) {
            failures.push((key, e.to_string()));
        } else {
            built += 1;
        }
    }
    (built, failures)
}

/// Build the strip model of the first member once and cache a report for every member.
fn condense_and_cache(
    members: &[(StaticParams, String)],
    cache_dir: &Path,
) -> Result<(), PipelineError> {
    let prepared = static_contact::prepare_strip(&members[0].0)?;
    for (params, hash) in members {
        let report = static_contact::analysis::report_for_model(
            &prepared.model,
            params,
            hash.clone(),
            prepared.mesh_file.clone(),
            static_contact::ActiveSetOptions::default(),
            prepared.mesh_s,
            prepared.condensation_s,
            std::time::Instant::now(),
        )?;
        let file = cache_dir.join(format!("static-{hash}.json"));
        crate::output::write_atomically(&file, serde_json::to_vec(&report)?)?;
    }
    Ok(())
}
