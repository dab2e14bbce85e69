//! The short-strip study of validation/coupled-dynamics/README.md ("Paper sliders: lumped vs
//! coupled", `results/sliders.csv`), part of the `coupled-dynamics` case: for the paper's
//! sliders at 10, 40 and 100 N, stall thrust and no-load speed of the coupled model on the FEM
//! strip's condensed tip compliance (Si body Tet10 + LiNbO3 half-space, strips of
//! [`STRIP_WAVELENGTHS`] wavelengths, T/128, the preload balanced at every instant) against the
//! lumped period average at the static η (the static stage's fit to 8 frozen-wave phases on the
//! same normal compliance) and at η_dyn.
//!
//! Checks per scene: the coupled stall thrust and no-load speed reproduce the committed
//! `results/sliders.csv` (compiled in) within [`STRIP_REPRODUCTION`]; the lumped model's error
//! at the static η is never above `coupled_dynamics::lumped_error_estimate` (the README's
//! criterion, "≥ the measured error in every scene"); the energy balance closes to
//! [`super::coupled_dynamics::ENERGY_BALANCE`]. The tip compliances are cached (JSON) in
//! `coupled-strips/` of the mesh cache (`static_contact::mesh_source::cache_dir`); a strip costs
//! ≈ 45 s of meshing and FEM the first time.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use contact_springs::{Material, post_springs};
use coupled_dynamics::{
    CoupledModel, CoupledScene, LumpedEvidence, PreloadBalance, lumped_error_estimate, solve,
};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use static_contact::mesh_source::cache_dir;
use static_contact::{
    ActiveSetSolver, ContactProblem, FitSample, StaticParams, fit_eta, prepare_strip,
};
use stick_slip::{DynamicScene, ModelChoice, PeriodicAverageModel, Wave};

use super::Check;
use super::coupled_dynamics::ENERGY_BALANCE;
use crate::error::ValidationError;

const CASE: &str = "coupled-dynamics";

/// Wavelengths a study strip spans. 3.
pub const STRIP_WAVELENGTHS: f64 = 3.0;
/// Frozen-wave phases of the static η fit. 8.
pub const FIT_PHASES: usize = 8;
/// Relative tolerance of the coupled figures against the committed `results/sliders.csv`
/// (same strips and code path; the contact solvers have changed since: measured 2.6e-4 at 10 N
/// to 7.9e-3 at 100 N on the 50 µm slider), an order below the lumped errors the study
/// reports. 0.01.
pub const STRIP_REPRODUCTION: f64 = 0.01;

const SLIDERS_CSV: &str =
    include_str!("../../../../validation/coupled-dynamics/results/sliders.csv");

fn failed(context: &str, e: impl std::fmt::Display) -> ValidationError {
    ValidationError::InvalidOption {
        option: "coupled-dynamics short strips",
        value: format!("{context}: {e}"),
        reason: "the strip FEM or the coupled model failed",
    }
}

/// Posts of the study's strip: enough to span [`STRIP_WAVELENGTHS`], at most a whole row.
pub fn strip_posts(pitch_m: f64, per_side: usize) -> usize {
    let n =
        (STRIP_WAVELENGTHS * Wave::paper_default().wavelength_m() / pitch_m).ceil() as usize + 1;
    n.min(per_side)
}

#[derive(Serialize, Deserialize)]
struct CachedStrip {
    x_m: Vec<f64>,
    share: f64,
    normal: Vec<f64>,
    tangential: Vec<f64>,
}

/// A strip's post positions, share, and normal and tangential tip compliance (m/N).
struct Strip {
    x_m: Vec<f64>,
    share: f64,
    normal: DMatrix<f64>,
    tangential: DMatrix<f64>,
}

fn cache_file(d: f64, per_side: usize) -> PathBuf {
    cache_dir(&StaticParams::default())
        .join("coupled-strips")
        .join(format!("strip-{:.0}um-{per_side}.json", d * 1e6))
}

fn strip(d: f64, per_side: usize) -> Result<Strip, ValidationError> {
    let file = cache_file(d, per_side);
    let cached: CachedStrip = match std::fs::read(&file)
        .ok()
        .and_then(|b| serde_json::from_slice(&b).ok())
    {
        Some(c) => c,
        None => {
            let mut params = StaticParams::square_array(d, per_side);
            params.strip_posts = Some(strip_posts(params.post_pitch_m, per_side));
            let prepared = prepare_strip(&params).map_err(|e| failed("strip FEM", e))?;
            let tips = prepared
                .model
                .tip_compliance()
                .map_err(|e| failed("tip compliance", e))?;
            let c = CachedStrip {
                x_m: prepared.model.posts.iter().map(|p| p.x_m).collect(),
                share: params.strip_share(),
                normal: tips.normal_m_per_n.as_slice().to_vec(),
                tangential: tips.tangential_m_per_n.as_slice().to_vec(),
            };
            write_cache(&file, &c)?;
            c
        }
    };
    let n = cached.x_m.len();
    Ok(Strip {
        normal: DMatrix::from_column_slice(n, n, &cached.normal),
        tangential: DMatrix::from_column_slice(n, n, &cached.tangential),
        x_m: cached.x_m,
        share: cached.share,
    })
}

fn write_cache(file: &Path, c: &CachedStrip) -> Result<(), ValidationError> {
    let io = |e| ValidationError::Io {
        path: file.to_path_buf(),
        source: e,
    };
    if let Some(dir) = file.parent() {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    std::fs::write(file, serde_json::to_vec(c).unwrap_or_default()).map_err(io)
}

/// Static η and its relative rms misfit: the fit of the lumped model to the frozen-wave post
/// forces on the same normal compliance.
fn static_eta(s: &Strip, k_n: f64, preload: f64) -> Result<(f64, f64), ValidationError> {
    let wave = Wave::paper_default();
    let k = wave.wavenumber_rad_per_m();
    let solver = ActiveSetSolver::default();
    let samples: Vec<FitSample> = (0..FIT_PHASES)
        .map(|j| {
            let phase = 2.0 * PI * j as f64 / FIT_PHASES as f64;
            let h: Vec<f64> = s
                .x_m
                .iter()
                .map(|xi| wave.normal_amplitude_m * (phase - k * xi).sin())
                .collect();
            let solution = solver
                .solve(&ContactProblem {
                    compliance_m_per_n: s.normal.clone(),
                    obstacle_height_m: h.clone(),
                    preload_n: preload * s.share,
                    length_scale_m: Some(wave.normal_amplitude_m),
                })
                .map_err(|e| failed("static snapshot", e))?;
            Ok(FitSample {
                height_m: h,
                force_n: solution.force_n,
                preload_n: preload * s.share,
            })
        })
        .collect::<Result<_, ValidationError>>()?;
    let fit = fit_eta(&samples, k_n);
    Ok((fit.eta.unwrap_or(f64::NAN), fit.relative_rms_residual))
}

fn coupled_scene(s: &Strip, preload: f64) -> CoupledScene {
    let mut scene = CoupledScene::independent_posts(
        Wave::paper_default(),
        s.x_m.clone(),
        1.0,
        1.0,
        stick_slip::PAPER_FRICTION_COEFFICIENT,
        stick_slip::PAPER_FRICTION_COEFFICIENT,
        preload,
    );
    scene.normal_compliance_m_per_n = s.normal.clone();
    scene.tangential_compliance_m_per_n = s.tangential.clone();
    scene.strip_share = s.share;
    scene.preload_balance = PreloadBalance::Instant;
    scene.steps_per_period = 128;
    scene
}

fn lumped_scene(d: f64, per_side: usize, preload: f64) -> Result<DynamicScene, ValidationError> {
    let springs = post_springs(&Material::silicon(), &Material::lithium_niobate(), 0.5 * d)
        .map_err(|e| failed("post springs", e))?;
    let mut scene = DynamicScene::paper_default(springs.k_n_n_per_m, springs.k_t_n_per_m);
    scene.slider.layout = stick_slip::PostLayout::SquareArray {
        posts_per_side: per_side,
        pitch_m: 4e-3 / per_side as f64,
    };
    scene.slider.preload_n = preload;
    scene.model = ModelChoice::PeriodicAverage;
    Ok(scene)
}

/// (stall N, no-load m/s) of the lumped period average at η.
fn lumped(base: &DynamicScene, eta: f64) -> Result<(f64, f64), ValidationError> {
    let mut scene = base.clone();
    scene.slider.effective_ratio = eta;
    let m = PeriodicAverageModel::new(&scene).map_err(|e| failed("lumped model", e))?;
    let stall = m.stall_thrust_n().map_err(|e| failed("lumped stall", e))?;
    let v0 = m
        .no_load_speed_m_per_s()
        .map_err(|e| failed("lumped no-load speed", e))?;
    Ok((stall, v0))
}

fn error(a: (f64, f64), reference: (f64, f64)) -> f64 {
    ((a.0 / reference.0) - 1.0)
        .abs()
        .max(((a.1 / reference.1) - 1.0).abs())
}

/// The committed (stall N, no-load m/s) of a scene in `results/sliders.csv`.
fn committed(d: f64, per_side: usize, preload: f64) -> Option<(f64, f64)> {
    let mut lines = SLIDERS_CSV.lines();
    let header: Vec<&str> = lines.next()?.split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name);
    let (cd, cn, cp) = (
        col("post_diameter_m")?,
        col("posts_per_side")?,
        col("preload_n")?,
    );
    let (cs, cv) = (
        col("coupled_stall_thrust_n")?,
        col("coupled_no_load_speed_m_per_s")?,
    );
    lines.find_map(|line| {
        let f: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().unwrap_or(f64::NAN))
            .collect();
        ((f[cd] - d).abs() < 1e-12 && f[cn] as usize == per_side && f[cp] == preload)
            .then(|| (f[cs], f[cv]))
    })
}

/// Runs the scenes (post diameter m, posts per side, preload N); returns the checks and the
/// CSV rows (`results/sliders.csv`'s columns).
pub fn run(scenes: &[(f64, usize, f64)]) -> Result<(Vec<Check>, String), ValidationError> {
    let mut csv = String::from(
        "post_diameter_m,posts_per_side,preload_n,strip_posts,eta_static,eta_fit_misfit,eta_dyn,coupled_stall_thrust_n,coupled_no_load_speed_m_per_s,lumped_static_stall_thrust_n,lumped_static_no_load_speed_m_per_s,lumped_static_error,lumped_error_estimate,energy_balance_residual\n",
    );
    let mut checks = Vec::new();
    for &(d, per_side, preload) in scenes {
        let s = strip(d, per_side)?;
        let k_n = post_springs(&Material::silicon(), &Material::lithium_niobate(), 0.5 * d)
            .map_err(|e| failed("post springs", e))?
            .k_n_n_per_m;
        let base = lumped_scene(d, per_side, preload)?;
        let (eta_static, misfit) = static_eta(&s, k_n, preload)?;
        let model = CoupledModel::new(&coupled_scene(&s, preload))
            .map_err(|e| failed("coupled model", e))?;
        let r = solve(&model, Some(&base)).map_err(|e| failed("coupled run", e))?;
        let ls = lumped(&base, eta_static.min(1.5))?;
        let coupled = (r.stall_thrust_n, r.no_load_speed_m_per_s);
        let lumped_error = error(ls, coupled);
        let estimate = lumped_error_estimate(&LumpedEvidence {
            eta_fit_misfit: misfit,
            lumped_no_load_speed_m_per_s: ls.1,
            crest_speed_m_per_s: Wave::paper_default().crest_speed_m_per_s(),
        });
        csv += &format!(
            "{d},{per_side},{preload},{},{eta_static},{misfit},{},{},{},{},{},{lumped_error},{estimate},{}\n",
            s.x_m.len(),
            r.eta_dyn.unwrap_or(f64::NAN),
            coupled.0,
            coupled.1,
            ls.0,
            ls.1,
            r.energy_balance_residual
        );
        let slider = format!(
            "{:.0} µm × {}, {preload} N, {}-post strip",
            d * 1e6,
            per_side * per_side,
            s.x_m.len()
        );
        let reference = committed(d, per_side, preload)
            .ok_or_else(|| failed("sliders.csv", format!("no row for {slider}")))?;
        let source =
            "committed validation/coupled-dynamics/results/sliders.csv (short-strip study)";
        for (what, value, committed) in [
            ("coupled stall thrust (N)", coupled.0, reference.0),
            ("coupled no-load speed (m/s)", coupled.1, reference.1),
        ] {
            checks.push(Check::relative(
                CASE,
                format!("{slider}: {what}"),
                value,
                committed,
                STRIP_REPRODUCTION,
                source,
            ));
        }
        checks.push(Check::at_most(
            CASE,
            format!("{slider}: lumped error at the static η, must not exceed its estimate"),
            lumped_error,
            estimate,
            "validation/coupled-dynamics/README.md, criterion (the estimate ≥ the measured error in every scene)",
        ));
        checks.push(Check::at_most(
            CASE,
            format!("{slider}: energy balance residual of the coupled curve"),
            r.energy_balance_residual,
            ENERGY_BALANCE,
            "validation/coupled-dynamics/README.md, energy",
        ));
    }
    Ok((checks, csv))
}
