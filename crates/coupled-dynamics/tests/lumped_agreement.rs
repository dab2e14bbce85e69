//! The coupled model's key check: with a diagonal compliance (no interaction: C_nn = 1/k_n,
//! C_tt = 1/k_t) and the lumped model's period-mean preload, the coupled model reproduces
//! stick_slip's period-average model at η = 1 (same k_n, k_t, μ, wave, step) within 1e-6 in
//! stall thrust and no-load speed; and its time-step error against the lumped closed form
//! falls with the observed order.

use std::f64::consts::PI;

use coupled_dynamics::{CoupledModel, CoupledScene, PreloadBalance};
use stick_slip::{DynamicScene, Integrator, ModelChoice, PeriodicAverageModel, PostLayout, Wave};

const K_N: f64 = 1.8e6;
const K_T: f64 = 1.5e6;
const POSTS: usize = 4;

fn lumped_scene(preload_n: f64, integrator: Integrator, mu_s: f64, mu_k: f64) -> DynamicScene {
    let mut scene = DynamicScene::paper_default(K_N, K_T);
    scene.slider.layout = PostLayout::UniformPhase { post_count: POSTS };
    scene.slider.effective_ratio = 1.0;
    scene.slider.preload_n = preload_n;
    scene.contact.mu_static = mu_s;
    scene.contact.mu_kinetic = mu_k;
    scene.model = ModelChoice::PeriodicAverage;
    scene.integrator = integrator;
    scene
}

/// Posts a quarter wavelength apart: every post's phase lies on the same step grid.
fn coupled_scene(
    wave: &Wave,
    preload_n: f64,
    steps: usize,
    start: f64,
    mu_s: f64,
    mu_k: f64,
) -> CoupledScene {
    let x = (0..POSTS)
        .map(|i| wave.wavelength_m() * i as f64 / POSTS as f64)
        .collect();
    let mut scene =
        CoupledScene::independent_posts(wave.clone(), x, K_N, K_T, mu_s, mu_k, preload_n);
    scene.preload_balance = PreloadBalance::PeriodMean;
    scene.steps_per_period = steps;
    scene.start_phase_rad = start;
    scene
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn check(mu_s: f64, mu_k: f64) {
    let wave = Wave::paper_default();
    // Mean normal force 0.3 k_n A_n per post: the posts separate every period.
    let preload = POSTS as f64 * 0.3 * K_N * wave.normal_amplitude_m;
    let steps = 128;
    let dt = wave.period_s() / steps as f64 * (1.0 + 1e-9);
    let lumped = PeriodicAverageModel::new(&lumped_scene(
        preload,
        Integrator::ReturnMapping { dt_s: dt },
        mu_s,
        mu_k,
    ))
    .expect("lumped model");
    // The lumped return mapping starts at touchdown, θ = π/2 − arccos c.
    let c = lumped.tip_height_m() / wave.normal_amplitude_m;
    let start = 0.5 * PI - c.acos();
    let model = CoupledModel::new(&coupled_scene(&wave, preload, steps, start, mu_s, mu_k))
        .expect("coupled model");
    let stall_lumped = lumped.stall_thrust_n().unwrap();
    let stall = model.stall_thrust_n().unwrap();
    assert!(
        relative(stall, stall_lumped) < 1e-6,
        "stall thrust (μ_s {mu_s}, μ_k {mu_k}): coupled {stall:.12e} N vs lumped {stall_lumped:.12e} N"
    );
    let v0_lumped = lumped.no_load_speed_m_per_s().unwrap();
    let v0 = model.no_load_speed_m_per_s(stall).unwrap();
    assert!(
        relative(v0, v0_lumped) < 1e-6,
        "no-load speed (μ_s {mu_s}, μ_k {mu_k}): coupled {v0:.12e} vs lumped {v0_lumped:.12e} m/s"
    );
    let mid = model.at_speed(0.5 * v0).unwrap();
    let mid_lumped = lumped.at_speed(0.5 * v0).unwrap();
    assert!(
        relative(mid.thrust_n, mid_lumped.thrust_n) < 1e-6,
        "thrust at v₀/2: coupled {} vs lumped {} N",
        mid.thrust_n,
        mid_lumped.thrust_n
    );
}

#[test]
fn independent_posts_reproduce_the_lumped_period_average_at_eta_one() {
    check(0.3, 0.3);
}

#[test]
fn independent_posts_reproduce_the_lumped_model_with_static_above_kinetic_friction() {
    check(0.35, 0.3);
}

/// Least-squares slope of ln e against ln(1/M).
fn observed_order(steps: &[usize], errors: &[f64]) -> f64 {
    let x: Vec<f64> = steps.iter().map(|&m| (m as f64).ln()).collect();
    let y: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let (mx, my) = (
        x.iter().sum::<f64>() / x.len() as f64,
        y.iter().sum::<f64>() / y.len() as f64,
    );
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    -sxy / sxx
}

#[test]
fn the_step_error_against_the_lumped_closed_form_falls_with_the_observed_order() {
    let wave = Wave::paper_default();
    let preload = POSTS as f64 * 0.3 * K_N * wave.normal_amplitude_m;
    let exact =
        PeriodicAverageModel::new(&lumped_scene(preload, Integrator::Auto, 0.3, 0.3)).unwrap();
    let stall_exact = exact.stall_thrust_n().unwrap();
    let v0_exact = exact.no_load_speed_m_per_s().unwrap();
    // Touchdown on the grid (as the lumped return mapping starts).
    let start = 0.5 * PI - (exact.tip_height_m() / wave.normal_amplitude_m).acos();
    let steps = [32, 64, 128, 256, 512];
    let mut stall_errors = Vec::new();
    let mut speed_errors = Vec::new();
    let mut balance = Vec::new();
    for m in steps {
        let model = CoupledModel::new(&coupled_scene(&wave, preload, m, start, 0.3, 0.3)).unwrap();
        let p = model.at_speed(0.0).unwrap();
        stall_errors.push(relative(p.thrust_n, stall_exact));
        speed_errors.push(relative(
            model.no_load_speed_m_per_s(p.thrust_n).unwrap(),
            v0_exact,
        ));
        balance.push(p.right_endpoint_balance_residual.abs());
        assert!(
            p.energy_identity_residual.abs() < 1e-10,
            "energy identity with the numerical dissipation at {m} steps: {}",
            p.energy_identity_residual
        );
    }
    let (stall_order, speed_order, balance_order) = (
        observed_order(&steps, &stall_errors),
        observed_order(&steps, &speed_errors),
        observed_order(&steps, &balance),
    );
    eprintln!(
        "steps {steps:?}: stall errors {stall_errors:?} (order {stall_order:.2}), no-load speed errors {speed_errors:?} (order {speed_order:.2}), energy residuals {balance:?} (order {balance_order:.2})"
    );
    assert!(
        stall_order > 0.8 && speed_order > 0.8,
        "observed orders: stall thrust {stall_order}, no-load speed {speed_order}"
    );
    assert!(
        (balance_order - 1.0).abs() < 0.2,
        "the energy residual (numerical dissipation) is first order: {balance_order}"
    );
}
