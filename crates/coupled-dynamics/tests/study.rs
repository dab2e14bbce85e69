//! The study of validation/coupled-dynamics/README.md: for the paper's sliders (five
//! counts of 20 µm posts, four diameters at equal area) at 10, 40, 100 N, stall thrust and
//! no-load speed from the lumped model at the static η, at η_dyn, and from the coupled model on
//! the FEM strip's row compliance; and the work-precision chart of the default slider at 40 N.
//!
//! Strips of [`STRIP_WAVELENGTHS`] wavelengths (11–31 posts), not whole rows, to keep the FEM
//! affordable. Heavy (meshes and factors eight strips; their tip compliances are cached in
//! `target/coupled-study-cache/`, so a rerun skips the FEM):
//! `cargo test -p coupled-dynamics --test study -- --ignored --nocapture --test-threads 1`
//! Writes validation/coupled-dynamics/results/{sliders,work_precision}.csv and
//! figures/work_precision.svg.

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use charts::{Chart, Series, Style, write_chart};
use contact_springs::{Material, post_springs};
use coupled_dynamics::{
    CoupledModel, CoupledScene, LumpedEvidence, PreloadBalance, lumped_error_estimate, solve,
};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use static_contact::{
    ActiveSetSolver, ContactProblem, FitSample, StaticParams, fit_eta, prepare_strip,
};
use stick_slip::{DynamicScene, ModelChoice, PeriodicAverageModel, Wave};

/// The paper's sliders: (post diameter m, posts per side) — Figs 7–8 (20 µm, five counts) and
/// Figs 9–10 (four diameters at equal tip area).
const SLIDERS: [(f64, usize); 8] = [
    (20e-6, 100),
    (20e-6, 80),
    (20e-6, 66),
    (20e-6, 50),
    (20e-6, 33),
    (30e-6, 67),
    (40e-6, 50),
    (50e-6, 40),
];
const PRELOADS_N: [f64; 3] = [10.0, 40.0, 100.0];
/// Steps per period of the study's coupled runs.
const STUDY_STEPS: usize = 128;
/// Frozen-wave phases of the static η fit (the static stage's default is 4; 8 here).
const FIT_PHASES: usize = 8;

/// Wavelengths a study strip spans (short strips keep the FEM affordable; see the README).
const STRIP_WAVELENGTHS: f64 = 3.0;

/// Posts of the study's strip: enough to span [`STRIP_WAVELENGTHS`], at most a whole row.
fn strip_posts(pitch_m: f64, per_side: usize) -> usize {
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
    prep_s: f64,
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn strip(d: f64, per_side: usize) -> (Vec<f64>, f64, DMatrix<f64>, DMatrix<f64>, f64) {
    let dir = root().join("target/coupled-study-cache");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(format!("strip-{:.0}um-{per_side}.json", d * 1e6));
    let cached: CachedStrip = match std::fs::read(&file) {
        Ok(bytes) => serde_json::from_slice(&bytes).unwrap(),
        Err(_) => {
            let mut params = StaticParams::square_array(d, per_side);
            params.strip_posts = Some(strip_posts(params.post_pitch_m, per_side));
            let t = Instant::now();
            let prepared = prepare_strip(&params).expect("strip");
            let tips = prepared.model.tip_compliance().expect("tip compliance");
            let c = CachedStrip {
                x_m: prepared.model.posts.iter().map(|p| p.x_m).collect(),
                share: params.strip_share(),
                normal: tips.normal_m_per_n.as_slice().to_vec(),
                tangential: tips.tangential_m_per_n.as_slice().to_vec(),
                prep_s: t.elapsed().as_secs_f64(),
            };
            std::fs::write(&file, serde_json::to_vec(&c).unwrap()).unwrap();
            c
        }
    };
    let n = cached.x_m.len();
    let cn = DMatrix::from_column_slice(n, n, &cached.normal);
    let ct = DMatrix::from_column_slice(n, n, &cached.tangential);
    (cached.x_m, cached.share, cn, ct, cached.prep_s)
}

/// Static η: the static stage's fit of the lumped model to the frozen-wave post forces on the
/// same normal compliance, and its relative rms misfit.
fn static_eta(x: &[f64], share: f64, cn: &DMatrix<f64>, k_n: f64, preload: f64) -> (f64, f64) {
    let wave = Wave::paper_default();
    let k = wave.wavenumber_rad_per_m();
    let solver = ActiveSetSolver::default();
    let samples: Vec<FitSample> = (0..FIT_PHASES)
        .map(|j| {
            let phase = 2.0 * PI * j as f64 / FIT_PHASES as f64;
            let h: Vec<f64> = x
                .iter()
                .map(|xi| wave.normal_amplitude_m * (phase - k * xi).sin())
                .collect();
            let s = solver
                .solve(&ContactProblem {
                    compliance_m_per_n: cn.clone(),
                    obstacle_height_m: h.clone(),
                    preload_n: preload * share,
                    length_scale_m: Some(wave.normal_amplitude_m),
                })
                .expect("static snapshot");
            FitSample {
                height_m: h,
                force_n: s.force_n,
                preload_n: preload * share,
            }
        })
        .collect();
    let fit = fit_eta(&samples, k_n);
    (fit.eta.unwrap_or(f64::NAN), fit.relative_rms_residual)
}

fn coupled_scene(
    x: &[f64],
    share: f64,
    cn: &DMatrix<f64>,
    ct: &DMatrix<f64>,
    preload: f64,
    steps: usize,
) -> CoupledScene {
    let mut scene = CoupledScene::independent_posts(
        Wave::paper_default(),
        x.to_vec(),
        1.0,
        1.0,
        stick_slip::PAPER_FRICTION_COEFFICIENT,
        stick_slip::PAPER_FRICTION_COEFFICIENT,
        preload,
    );
    scene.normal_compliance_m_per_n = cn.clone();
    scene.tangential_compliance_m_per_n = ct.clone();
    scene.strip_share = share;
    scene.preload_balance = PreloadBalance::Instant;
    scene.steps_per_period = steps;
    scene
}

fn lumped_scene(d: f64, per_side: usize, preload: f64) -> DynamicScene {
    let springs =
        post_springs(&Material::silicon(), &Material::lithium_niobate(), 0.5 * d).unwrap();
    let mut scene = DynamicScene::paper_default(springs.k_n_n_per_m, springs.k_t_n_per_m);
    scene.slider.layout = stick_slip::PostLayout::SquareArray {
        posts_per_side: per_side,
        pitch_m: 4e-3 / per_side as f64,
    };
    scene.slider.preload_n = preload;
    scene.model = ModelChoice::PeriodicAverage;
    scene
}

/// (stall N, no-load m/s, wall s) of the lumped model at η.
fn lumped(base: &DynamicScene, eta: f64) -> (f64, f64, f64) {
    let mut scene = base.clone();
    scene.slider.effective_ratio = eta;
    let t = Instant::now();
    let m = PeriodicAverageModel::new(&scene).unwrap();
    let stall = m.stall_thrust_n().unwrap();
    let v0 = m.no_load_speed_m_per_s().unwrap();
    (stall, v0, t.elapsed().as_secs_f64())
}

fn error(stall: f64, v0: f64, stall_ref: f64, v0_ref: f64) -> f64 {
    ((stall - stall_ref) / stall_ref)
        .abs()
        .max(((v0 - v0_ref) / v0_ref).abs())
}

#[test]
#[ignore = "meshes and factors eight FEM strips; see the module docs for the command"]
fn paper_sliders_lumped_against_coupled() {
    let out = root().join("validation/coupled-dynamics/results");
    std::fs::create_dir_all(&out).unwrap();
    let mut csv = String::from(
        "post_diameter_m,posts_per_side,preload_n,strip_posts,eta_static,eta_fit_misfit,eta_dyn,eta_dyn_misfit,coupled_stall_thrust_n,coupled_no_load_speed_m_per_s,lumped_static_stall_thrust_n,lumped_static_no_load_speed_m_per_s,lumped_dyn_stall_thrust_n,lumped_dyn_no_load_speed_m_per_s,lumped_static_error,lumped_dyn_error,lumped_error_estimate,coupled_wall_time_s,energy_balance_residual,strip_prep_s\n",
    );
    for (d, per_side) in SLIDERS {
        let (x, share, cn, ct, prep_s) = strip(d, per_side);
        let k_n = post_springs(&Material::silicon(), &Material::lithium_niobate(), 0.5 * d)
            .unwrap()
            .k_n_n_per_m;
        for preload in PRELOADS_N {
            let base = lumped_scene(d, per_side, preload);
            let (eta_static, fit_misfit) = static_eta(&x, share, &cn, k_n, preload);
            let t = Instant::now();
            let model =
                CoupledModel::new(&coupled_scene(&x, share, &cn, &ct, preload, STUDY_STEPS))
                    .expect("coupled model");
            let r = solve(&model, Some(&base)).expect("coupled run");
            let wall = t.elapsed().as_secs_f64();
            let eta_dyn = r.eta_dyn.unwrap_or(f64::NAN);
            let ls = lumped(&base, eta_static.min(1.5));
            let ld = lumped(&base, eta_dyn);
            let (cs, cv) = (r.stall_thrust_n, r.no_load_speed_m_per_s);
            let estimate = lumped_error_estimate(&LumpedEvidence {
                eta_fit_misfit: fit_misfit,
                lumped_no_load_speed_m_per_s: ls.1,
                crest_speed_m_per_s: Wave::paper_default().crest_speed_m_per_s(),
            });
            let row = format!(
                "{d},{per_side},{preload},{},{eta_static},{fit_misfit},{eta_dyn},{},{cs},{cv},{},{},{},{},{},{},{estimate},{wall},{},{prep_s}\n",
                x.len(),
                r.eta_dyn_misfit.unwrap_or(f64::NAN),
                ls.0,
                ls.1,
                ld.0,
                ld.1,
                error(ls.0, ls.1, cs, cv),
                error(ld.0, ld.1, cs, cv),
                r.energy_balance_residual,
            );
            eprint!("{row}");
            csv.push_str(&row);
        }
    }
    std::fs::write(out.join("sliders.csv"), csv).unwrap();
}

#[test]
#[ignore = "meshes and factors the default strip; see the module docs for the command"]
fn work_precision_of_the_default_slider_at_40_n() {
    let (d, per_side, preload) = (20e-6, 100, 40.0);
    let (x, share, cn, ct, _) = strip(d, per_side);
    let run = |steps: usize| {
        let t = Instant::now();
        let model = CoupledModel::new(&coupled_scene(&x, share, &cn, &ct, preload, steps)).unwrap();
        let stall = model.stall_thrust_n().unwrap();
        let v0 = model.no_load_speed_m_per_s(stall).unwrap();
        (stall, v0, t.elapsed().as_secs_f64())
    };
    let (sr, vr, wr) = run(1024);
    let mut csv = String::from(
        "model,steps_per_period,stall_thrust_n,no_load_speed_m_per_s,error,wall_time_s\n",
    );
    let _ = writeln!(csv, "coupled,1024,{sr},{vr},0,{wr}");
    let mut coupled = Vec::new();
    for steps in [32, 64, 128, 256, 512] {
        let (s, v, w) = run(steps);
        let e = error(s, v, sr, vr);
        let _ = writeln!(csv, "coupled,{steps},{s},{v},{e},{w}");
        coupled.push((w, e));
    }
    let base = lumped_scene(d, per_side, preload);
    let k_n = post_springs(&Material::silicon(), &Material::lithium_niobate(), 0.5 * d)
        .unwrap()
        .k_n_n_per_m;
    let (eta_static, _) = static_eta(&x, share, &cn, k_n, preload);
    let model = CoupledModel::new(&coupled_scene(&x, share, &cn, &ct, preload, 256)).unwrap();
    let r = solve(&model, Some(&base)).unwrap();
    let eta_dyn = r.eta_dyn.unwrap();
    let mut lumped_points = Vec::new();
    for (label, eta) in [
        ("lumped-static-eta", eta_static),
        ("lumped-eta-dyn", eta_dyn),
    ] {
        let (s, v, w) = lumped(&base, eta);
        let e = error(s, v, sr, vr);
        let _ = writeln!(csv, "{label},closed-form,{s},{v},{e},{w}");
        lumped_points.push((label, (w, e)));
    }
    // Transient (lumped, phase groups and the slider integrated in time) at η_dyn.
    let mut transient = Vec::new();
    for steps in [64usize, 256] {
        let mut scene = base.clone();
        scene.slider.effective_ratio = eta_dyn;
        scene.model = ModelChoice::Transient;
        scene.integrator = stick_slip::Integrator::ReturnMapping {
            dt_s: scene.wave.period_s() / steps as f64,
        };
        let t = Instant::now();
        match stick_slip::solve(&scene) {
            Ok(res) => {
                let w = t.elapsed().as_secs_f64();
                let e = error(res.stall_thrust_n, res.no_load_speed_m_per_s, sr, vr);
                let _ = writeln!(
                    csv,
                    "transient-eta-dyn,{steps},{},{},{e},{w}",
                    res.stall_thrust_n, res.no_load_speed_m_per_s
                );
                transient.push((w, e));
            }
            Err(err) => eprintln!("transient at {steps} steps: {err}"),
        }
    }
    eprint!("{csv}");
    let out = root().join("validation/coupled-dynamics");
    std::fs::create_dir_all(out.join("results")).unwrap();
    std::fs::create_dir_all(out.join("figures")).unwrap();
    std::fs::write(out.join("results/work_precision.csv"), &csv).unwrap();
    let mut chart = Chart::new(
        "Work-precision, default slider, 40 N (reference: coupled, T/1024)",
        "wall time (s)",
        "max relative error of stall thrust and no-load speed",
    )
    .log_log();
    chart.series.push(Series::new(
        "coupled, T/32 … T/512",
        coupled,
        Style::LineMarkers,
    ));
    for (label, p) in lumped_points {
        chart
            .series
            .push(Series::new(label, vec![p], Style::Markers));
    }
    if !transient.is_empty() {
        chart.series.push(Series::new(
            "transient at η_dyn, T/64, T/256",
            transient,
            Style::LineMarkers,
        ));
    }
    write_chart(&chart, &out.join("figures/work_precision")).unwrap();
}
