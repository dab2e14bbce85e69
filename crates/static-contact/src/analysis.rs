//! The static stage of the pipeline: parameters → mesh → condensed strip → snapshots → η.
//!
//! Two entry points: [`prepare_strip`] (validate the parameters, find or make the mesh, condense
//! the strip onto its posts: everything that does not depend on the preload) and
//! [`PreparedStrip::analyse`] (every preload × wave phase and the flat stator solved on that strip,
//! η fitted by least squares, docs/physics.md §6). A hand-built [`StripModel`] is analysed by
//! wrapping it in a [`PreparedStrip`].

use std::f64::consts::PI;
use std::time::Instant;

use contact_springs::PostSprings;
use run_control::RunControl;
use serde::{Deserialize, Serialize};

use crate::FemStats;
use crate::error::{ContactError, Result};
use crate::eta::{EtaFit, FitSample, fit_eta};
use crate::eta_full_contact::full_contact_eta;
use crate::lcp::{ActiveSetOptions, ContactSolution, IterationLog};
use crate::params::{MODEL_VERSION, StaticParams};
use crate::scene::{StatorModel, StripConfig, StripModel};

/// One post of one snapshot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PostResult {
    /// Post index in the strip (x order).
    pub index: usize,
    /// Centre x (m).
    pub x_m: f64,
    /// Stator surface height under the post (m).
    pub surface_height_m: f64,
    /// Contact force (N), ≥ 0.
    pub force_n: f64,
    /// Whether the post is in the active (contact) set.
    pub in_contact: bool,
    /// Gap (m), ≥ 0.
    pub gap_m: f64,
}

/// One snapshot (one phase θ₀ of the frozen wave, or the flat stator).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SnapshotResult {
    /// Phase θ₀ (rad) of w(x) = A_n sin(θ₀ − kx); `None` for the flat stator.
    pub phase_rad: Option<f64>,
    /// Posts.
    pub posts: Vec<PostResult>,
    /// (Σf)² / (N Σf²): 1 when all posts carry the same force.
    pub load_sharing: f64,
    /// Fraction of the strip's posts in contact.
    pub contact_fraction: f64,
    /// Scaled complementarity residual (see [`ContactSolution`]).
    pub complementarity_residual: f64,
    /// Active-set iterations.
    pub iterations: usize,
    /// Slider reference height z_s (m).
    pub reference_height_m: f64,
    /// Per-iteration log.
    pub log: Vec<IterationLog>,
}

/// Results for one preload.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PreloadResult {
    /// Preload on the whole slider (N).
    pub preload_n: f64,
    /// The strip's share (N).
    pub preload_strip_n: f64,
    /// η fitted over the wave snapshots (`None`: not identifiable, see `eta_fit.reason`).
    pub effective_contact_ratio: Option<f64>,
    /// The fit's details.
    pub eta_fit: EtaFit,
    /// Mean load-sharing ratio over the wave snapshots.
    pub load_sharing: f64,
    /// Mean fraction of posts in contact over the wave snapshots.
    pub contact_fraction: f64,
    /// Largest residual over the snapshots.
    pub complementarity_residual: f64,
    /// Total active-set iterations over the snapshots.
    pub iterations: usize,
    /// Wave snapshots, one per phase.
    pub snapshots: Vec<SnapshotResult>,
    /// The same preload on a flat stator: load sharing from the slider's and stator's own
    /// compliance alone (edge posts of a rigid-backed slider carry more).
    pub flat_stator: SnapshotResult,
}

/// Which stator model and FEM sizes produced the numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FemSummary {
    /// Stator model.
    pub stator_model: StatorModel,
    /// Slider strip FEM.
    pub slider: FemStats,
    /// Why the slider's FEM solver (`slider.solver`): the cost model's figures, or "requested".
    #[serde(default)]
    pub slider_solver_reason: String,
    /// Meshed stator FEM, if any.
    pub stator: Option<FemStats>,
}

/// Wall times (s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Timings {
    /// Mesh choice / generation and reading.
    pub mesh_s: f64,
    /// FEM assembly, factorisation and condensation onto the posts.
    pub condensation_s: f64,
    /// All contact solves and η fits.
    pub contact_s: f64,
    /// Everything.
    pub wall_time_s: f64,
}

/// The static stage's result (serialisable; the top-level keys refer to the main preload).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StaticReport {
    /// Content hash of the inputs ([`StaticParams::content_hash`]).
    pub content_hash: String,
    /// [`MODEL_VERSION`].
    pub model_version: u32,
    /// Mesh file used.
    pub mesh_file: String,
    /// Main preload (N).
    pub preload_n: f64,
    /// η at the main preload.
    pub effective_contact_ratio: Option<f64>,
    /// Why η is missing, or a caveat.
    pub effective_contact_ratio_note: Option<String>,
    /// Load-sharing ratio at the main preload (mean over the wave snapshots).
    pub load_sharing: f64,
    /// Fraction of posts in contact at the main preload (mean over the wave snapshots).
    pub contact_fraction: f64,
    /// Largest scaled complementarity residual of all solves.
    pub complementarity_residual: f64,
    /// Active-set iterations of all solves.
    pub iterations: usize,
    /// Post forces (N) of the first snapshot (θ₀ = 0) at the main preload.
    pub post_forces_n: Vec<f64>,
    /// Posts of that snapshot.
    pub posts: Vec<PostResult>,
    /// Johnson series stiffness k_n = k_pn ⊕ k_sn of one post (N/m).
    pub k_n_n_per_m: f64,
    /// η at full contact, the high-preload asymptote of the fitted η
    /// ([`crate::eta_full_contact`]); `None` if the compliance is singular.
    pub eta_full_contact: Option<f64>,
    /// Posts in the strip.
    pub posts_in_strip: usize,
    /// Posts of the whole slider.
    pub posts_total: usize,
    /// Effective post count η N for the dynamic model at the main preload.
    pub effective_post_count: Option<f64>,
    /// Every preload (main first).
    pub preloads: Vec<PreloadResult>,
    /// FEM sizes and stator model.
    pub fem: FemSummary,
    /// Wall times.
    pub timings: Timings,
}

/// A finished run: the condensed model (for field output) and the report.
#[derive(Debug)]
pub struct StaticAnalysis {
    /// Parameters.
    pub params: StaticParams,
    /// Condensed strip.
    pub model: StripModel,
    /// Results.
    pub report: StaticReport,
    /// What the mesh cache check found (e.g. a damaged cached mesh regenerated), for the user.
    pub notes: Vec<String>,
}

/// Stator surface height under each post: w(x) = A_n sin(θ₀ − k x) (m).
fn wave_heights(
    model: &StripModel,
    amplitude_m: f64,
    wavelength_m: f64,
    phase_rad: f64,
) -> Vec<f64> {
    let k = 2.0 * PI / wavelength_m;
    model
        .posts
        .iter()
        .map(|p| amplitude_m * (phase_rad - k * p.x_m).sin())
        .collect()
}

fn snapshot(
    model: &StripModel,
    heights: Vec<f64>,
    phase_rad: Option<f64>,
    solution: ContactSolution,
) -> SnapshotResult {
    let f = &solution.force_n;
    let n = f.len() as f64;
    let sum: f64 = f.iter().sum();
    let sum_sq: f64 = f.iter().map(|x| x * x).sum();
    let posts = model
        .posts
        .iter()
        .enumerate()
        .map(|(i, p)| PostResult {
            index: i,
            x_m: p.x_m,
            surface_height_m: heights[i],
            force_n: f[i],
            in_contact: solution.in_contact[i],
            gap_m: solution.gap_m[i],
        })
        .collect();
    SnapshotResult {
        phase_rad,
        posts,
        load_sharing: if sum_sq > 0.0 {
            sum * sum / (n * sum_sq)
        } else {
            0.0
        },
        contact_fraction: solution.in_contact.iter().filter(|&&c| c).count() as f64 / n,
        complementarity_residual: solution.complementarity_residual,
        iterations: solution.iterations,
        reference_height_m: solution.reference_height_m,
        log: solution.log,
    }
}

fn with_context(e: ContactError, preload_n: f64, phase: Option<f64>) -> ContactError {
    match e {
        ContactError::NotConverged {
            iterations,
            active,
            posts,
            residual,
            tolerance,
            context,
        } => ContactError::NotConverged {
            iterations,
            active,
            posts,
            residual,
            tolerance,
            context: format!(
                "{context} at preload {preload_n} N, phase {}",
                phase.map_or("flat".to_string(), |p| format!("{p:.4} rad"))
            ),
        },
        other => other,
    }
}

/// `Err(Cancelled)` naming the step `before` if the caller asked to stop. The static stage asks
/// before each contact solve (each phase of each preload, and the flat stator) and before the
/// strip's condensation; the FEM factorisation inside the condensation is not interrupted.
fn stop_check(control: &RunControl, before: impl FnOnce() -> String) -> Result<()> {
    match control.should_stop() {
        true => Err(ContactError::Cancelled { before: before() }),
        false => Ok(()),
    }
}

/// Solves every snapshot of one preload on a built model and fits η; `control` is asked before
/// each contact solve.
fn analyse_preload(
    model: &StripModel,
    params: &StaticParams,
    preload_n: f64,
    k_n_n_per_m: f64,
    options: ActiveSetOptions,
    control: &RunControl,
) -> Result<PreloadResult> {
    let preload_strip_n = preload_n * params.strip_share();
    let scale = (params.wave_amplitude_m > 0.0).then_some(params.wave_amplitude_m);
    let mut snapshots = Vec::with_capacity(params.phases);
    let mut samples = Vec::with_capacity(params.phases);
    for k in 0..params.phases {
        let phase = 2.0 * PI * k as f64 / params.phases as f64;
        stop_check(control, || {
            format!(
                "the contact solve at preload {preload_n} N, phase {} of {}",
                k + 1,
                params.phases
            )
        })?;
        let heights = wave_heights(model, params.wave_amplitude_m, params.wavelength_m, phase);
        let solution = model
            .solve(preload_strip_n, heights.clone(), scale, options)
            .map_err(|e| with_context(e, preload_n, Some(phase)))?;
        samples.push(FitSample {
            height_m: heights.clone(),
            force_n: solution.force_n.clone(),
            preload_n: preload_strip_n,
        });
        snapshots.push(snapshot(model, heights, Some(phase), solution));
    }
    stop_check(control, || {
        format!("the flat-stator solve at preload {preload_n} N")
    })?;
    let flat_heights = vec![0.0; model.post_count()];
    let flat = model
        .solve(preload_strip_n, flat_heights.clone(), None, options)
        .map_err(|e| with_context(e, preload_n, None))?;
    let flat_stator = snapshot(model, flat_heights, None, flat);
    let eta_fit = fit_eta(&samples, k_n_n_per_m);
    let m = snapshots.len() as f64;
    Ok(PreloadResult {
        preload_n,
        preload_strip_n,
        effective_contact_ratio: eta_fit.eta,
        load_sharing: snapshots.iter().map(|s| s.load_sharing).sum::<f64>() / m,
        contact_fraction: snapshots.iter().map(|s| s.contact_fraction).sum::<f64>() / m,
        complementarity_residual: snapshots
            .iter()
            .chain(std::iter::once(&flat_stator))
            .map(|s| s.complementarity_residual)
            .fold(0.0, f64::max),
        iterations: snapshots.iter().map(|s| s.iterations).sum(),
        eta_fit,
        snapshots,
        flat_stator,
    })
}

/// A condensed strip model and where it came from: everything of a static run that does not
/// depend on the preload (a sweep over preloads builds it once).
#[derive(Debug)]
pub struct PreparedStrip {
    /// The condensed strip.
    pub model: StripModel,
    /// Mesh file used.
    pub mesh_file: String,
    /// What the mesh cache check found (e.g. a damaged cached mesh regenerated), for the user.
    pub notes: Vec<String>,
    /// Wall time of mesh choice, generation and reading (s).
    pub mesh_s: f64,
    /// Wall time of FEM assembly, factorisation and condensation (s).
    pub condensation_s: f64,
}

/// Validates `params`, finds or makes the mesh, reads it and condenses the strip onto the posts.
pub fn prepare_strip(params: &StaticParams) -> Result<PreparedStrip> {
    let start = Instant::now();
    params.validate()?;
    let resolved = crate::mesh_source::resolve_mesh_verified(params)?;
    let path = resolved.path.clone();
    let mesh = resolved
        .read()
        .map_err(|source| match &resolved.cache_dir {
            Some(cache_dir) => ContactError::CachedMesh {
                file: path.clone(),
                cache_dir: cache_dir.clone(),
                source: Box::new(source),
            },
            None => ContactError::Mesh {
                file: path.display().to_string(),
                source: Box::new(source),
            },
        })?;
    if mesh.tets.order() != params.element_order {
        return Err(ContactError::MeshMismatch {
            file: path.display().to_string(),
            detail: format!(
                "mesh has {} elements, element_order = {} was asked",
                mesh.tets.kind(),
                params.element_order
            ),
        });
    }
    let mesh_s = start.elapsed().as_secs_f64();
    let t = Instant::now();
    let model = StripModel::build_with_order_cache(
        mesh,
        params.strip_config(),
        resolved.cache_dir.as_deref(),
    )?;
    // The FEM solver and its reason are in the report (`fem.slider.solver`, `solver_reason`)
    // and in `sawdrive static`'s summary, not in the notes: a later error stays one line.
    Ok(PreparedStrip {
        model,
        notes: resolved.notes,
        mesh_file: path.display().to_string(),
        mesh_s,
        condensation_s: t.elapsed().as_secs_f64(),
    })
}

impl PreparedStrip {
    /// Solves every preload × phase and the flat stator on this strip with the parameters'
    /// solver settings ([`StaticParams::solver_options`]) and fits η; `springs` are the post's
    /// Johnson springs (a pipeline computes them once per run). `params` may differ from the
    /// strip's own in anything that does not change the mesh or the condensation (preloads,
    /// wave, phases, solver settings): a sweep over preloads prepares the strip once.
    /// `control` is asked before each contact solve.
    pub fn analyse(
        &self,
        params: &StaticParams,
        springs: &PostSprings,
        control: &RunControl,
    ) -> Result<StaticReport> {
        let start = Instant::now();
        params.validate()?;
        let content_hash = params.content_hash()?;
        let k_n = springs.k_n_n_per_m;
        let options = params.solver_options();
        let preloads = params
            .all_preloads_n()
            .into_iter()
            .map(|p| analyse_preload(&self.model, params, p, k_n, options, control))
            .collect::<Result<Vec<_>>>()?;
        let contact_s = start.elapsed().as_secs_f64();
        let timings = Timings {
            mesh_s: self.mesh_s,
            condensation_s: self.condensation_s,
            contact_s,
            wall_time_s: self.mesh_s + self.condensation_s + contact_s,
        };
        Ok(report(
            &self.model,
            params,
            k_n,
            content_hash,
            self.mesh_file.clone(),
            timings,
            preloads,
        ))
    }

    /// The run of this strip with `params` and its `report`, for field output
    /// ([`crate::output`]).
    pub fn into_analysis(self, params: &StaticParams, report: StaticReport) -> StaticAnalysis {
        StaticAnalysis {
            params: params.clone(),
            model: self.model,
            report,
            notes: self.notes,
        }
    }
}

/// The report of every preload's result on `model`: the first preload's η, load sharing and
/// post forces; the worst residual and the iterations of all.
fn report(
    model: &StripModel,
    params: &StaticParams,
    k_n: f64,
    content_hash: String,
    mesh_file: String,
    timings: Timings,
    preloads: Vec<PreloadResult>,
) -> StaticReport {
    let main = &preloads[0];
    let posts_total = params.posts_x * params.posts_y;
    StaticReport {
        content_hash,
        model_version: MODEL_VERSION,
        mesh_file,
        preload_n: params.preload_n,
        effective_contact_ratio: main.effective_contact_ratio,
        effective_contact_ratio_note: main.eta_fit.reason.clone(),
        load_sharing: main.load_sharing,
        contact_fraction: main.contact_fraction,
        complementarity_residual: preloads
            .iter()
            .map(|p| p.complementarity_residual)
            .fold(0.0, f64::max),
        iterations: preloads
            .iter()
            .map(|p| p.iterations + p.flat_stator.iterations)
            .sum(),
        post_forces_n: main.snapshots[0].posts.iter().map(|p| p.force_n).collect(),
        posts: main.snapshots[0].posts.clone(),
        k_n_n_per_m: k_n,
        eta_full_contact: full_contact_eta(model, k_n, params.wavelength_m),
        posts_in_strip: model.post_count(),
        posts_total,
        effective_post_count: main
            .effective_contact_ratio
            .map(|eta| eta * posts_total as f64),
        fem: FemSummary {
            stator_model: model.config.stator,
            slider: model.slider.stats,
            slider_solver_reason: model.slider.solver_reason.clone(),
            stator: match &model.stator {
                crate::scene::StatorCompliance::Meshed(b) => Some(b.stats),
                crate::scene::StatorCompliance::HalfSpace(_) => None,
            },
        },
        timings,
        preloads,
    }
}
impl StaticParams {
    /// The strip configuration of the parameters: materials, post geometry, rows, stator model
    /// and FEM solver ([`StripModel::build`]'s input).
    pub fn strip_config(&self) -> StripConfig {
        StripConfig {
            slider_material: self.slider_material.clone(),
            stator_material: self.stator_material.clone(),
            post_radius_m: 0.5 * self.post_diameter_m,
            post_height_m: self.post_height_m,
            pitch_m: self.post_pitch_m,
            slider_rows: self.posts_y,
            expected_strip_posts: Some(self.strip_post_count()),
            stator: self.stator,
            fem_solver: self.fem_solver,
        }
    }
}
