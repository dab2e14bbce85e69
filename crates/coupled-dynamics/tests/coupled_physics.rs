//! Physics of the coupled model on a dense (interacting) compliance: reversing the wave reverses
//! the motion, the energy bookkeeping closes at every curve point, the preload is balanced at
//! every instant, and bad input is refused naming the field.

use coupled_dynamics::{
    CoupledError, CoupledModel, CoupledScene, PreloadBalance, WaveDirection, solve,
};
use nalgebra::DMatrix;
use stick_slip::{DynamicScene, PostLayout, Wave};

const K_N: f64 = 1.8e6;
const K_T: f64 = 1.5e6;
const PITCH_M: f64 = 40e-6;

/// `n` posts symmetric about x = 0 at the paper's pitch; compliances decaying with distance
/// (self 1/k plus a 1/(1 + r/pitch) interaction of 20 %): mirror-symmetric and SPD.
fn interacting_scene(n: usize, preload_n: f64) -> CoupledScene {
    let wave = Wave::paper_default();
    let x: Vec<f64> = (0..n)
        .map(|i| (i as f64 - 0.5 * (n - 1) as f64) * PITCH_M)
        .collect();
    let interaction = |k: f64| {
        DMatrix::from_fn(n, n, |i, j| {
            let r = (x[i] - x[j]).abs() / PITCH_M;
            (if i == j { 1.0 } else { 0.0 } + 0.2 / (1.0 + r)) / k
        })
    };
    let mut scene =
        CoupledScene::independent_posts(wave, x.clone(), K_N, K_T, 0.35, 0.3, preload_n);
    scene.normal_compliance_m_per_n = interaction(K_N);
    scene.tangential_compliance_m_per_n = interaction(K_T);
    scene.steps_per_period = 64;
    scene.curve_points = 6;
    scene
}

fn preload_for(n: usize) -> f64 {
    n as f64 * 0.3 * K_N * Wave::paper_default().normal_amplitude_m
}

#[test]
fn reversing_the_wave_reverses_the_motion() {
    let scene = interacting_scene(9, preload_for(9));
    let forward = solve(&CoupledModel::new(&scene).unwrap(), None).unwrap();
    let reversed_scene = CoupledScene {
        wave_direction: WaveDirection::MinusX,
        ..scene
    };
    let reversed = solve(&CoupledModel::new(&reversed_scene).unwrap(), None).unwrap();
    assert!(forward.no_load_speed_m_per_s > 0.0, "the motor runs");
    assert_eq!(
        forward.drive_direction_x, -1.0,
        "a +x wave drives the slider along −x"
    );
    assert_eq!(
        reversed.drive_direction_x, 1.0,
        "the reversed wave drives it along +x"
    );
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(
        rel(
            reversed.no_load_speed_m_per_s,
            forward.no_load_speed_m_per_s
        ) < 1e-9,
        "no-load speed of the mirrored scene: {} vs {} m/s",
        reversed.no_load_speed_m_per_s,
        forward.no_load_speed_m_per_s
    );
    assert!(
        rel(reversed.stall_thrust_n, forward.stall_thrust_n) < 1e-9,
        "stall thrust of the mirrored scene: {} vs {} N",
        reversed.stall_thrust_n,
        forward.stall_thrust_n
    );
}

#[test]
fn energy_closes_and_the_preload_is_balanced_at_every_instant() {
    let n = 9;
    let preload = preload_for(n);
    let model = CoupledModel::new(&interacting_scene(n, preload)).unwrap();
    for j in 0..64 {
        let total = model.strip_normal_force_n(j);
        assert!(
            (total / preload - 1.0).abs() < 1e-9,
            "Σ N at grid phase {j}: {total} N vs preload {preload} N"
        );
    }
    let result = solve(&model, None).unwrap();
    for p in &result.curve {
        assert!(
            p.energy_identity_residual.abs() < 1e-10,
            "energy identity at {} m/s: {}",
            p.speed_m_per_s,
            p.energy_identity_residual
        );
        // Without the numerical term the balance misses by the step's O(h) dissipation
        // (≈ 4 % at T/32, 1 % at T/128 for independent posts; see lumped_agreement).
        assert!(
            p.energy_balance_residual.abs() < 0.1,
            "energy balance residual at {} m/s and 64 steps per period: {}",
            p.speed_m_per_s,
            p.energy_balance_residual
        );
        assert!(
            p.converged,
            "periodic steady state at {} m/s",
            p.speed_m_per_s
        );
        assert!(p.max_solver_residual < 1e-9, "contact solves converge");
    }
    assert!(
        result.stall_thrust_n > 0.0 && result.stall_thrust_n <= 0.35 * preload,
        "stall thrust {} N within the friction limit {} N",
        result.stall_thrust_n,
        0.35 * preload
    );
    assert!(
        result.no_load_speed_m_per_s < Wave::paper_default().crest_speed_m_per_s(),
        "no-load speed below the crest speed"
    );
    let json = serde_json::to_value(&result).unwrap();
    for key in [
        "model",
        "stall_thrust_n",
        "no_load_speed_m_per_s",
        "curve",
        "energy_balance_residual",
        "eta_dyn",
        "wall_time_s",
    ] {
        assert!(json.get(key).is_some(), "JSON key {key}");
    }
    assert_eq!(json["model"], "coupled", "model name");
}

#[test]
fn eta_dyn_of_independent_posts_is_one() {
    let n = 4;
    let wave = Wave::paper_default();
    let preload = preload_for(n);
    let x = (0..n)
        .map(|i| wave.wavelength_m() * i as f64 / n as f64)
        .collect();
    let mut scene = CoupledScene::independent_posts(wave, x, K_N, K_T, 0.3, 0.3, preload);
    scene.preload_balance = PreloadBalance::PeriodMean;
    scene.steps_per_period = 256;
    scene.curve_points = 8;
    let model = CoupledModel::new(&scene).unwrap();
    let mut lumped = DynamicScene::paper_default(K_N, K_T);
    lumped.slider.layout = PostLayout::UniformPhase { post_count: n };
    lumped.slider.preload_n = preload;
    let result = solve(&model, Some(&lumped)).unwrap();
    let eta = result.eta_dyn.unwrap();
    assert!(
        (eta - 1.0).abs() < 0.01,
        "η_dyn of independent posts (step error only): {eta}, misfit {:?}",
        result.eta_dyn_misfit
    );
}

#[test]
fn bad_input_is_refused_naming_the_field() {
    let mut scene = interacting_scene(3, preload_for(3));
    scene.mu_static = 0.2;
    let err = CoupledModel::new(&scene).unwrap_err();
    assert!(
        err.to_string().contains("mu_static"),
        "μ_k > μ_s named: {err}"
    );
    let mut scene = interacting_scene(3, preload_for(3));
    scene.steps_per_period = 8;
    let err = CoupledModel::new(&scene).unwrap_err();
    assert!(
        err.to_string().contains("steps_per_period"),
        "too coarse a step named: {err}"
    );
    let mut scene = interacting_scene(3, preload_for(3));
    scene.tangential_compliance_m_per_n[(0, 1)] = -1.0;
    let err = CoupledModel::new(&scene).unwrap_err();
    assert!(
        matches!(
            err,
            CoupledError::NotPositiveDefinite {
                what: "tangential_compliance_m_per_n"
            }
        ),
        "asymmetric compliance named: {err}"
    );
    let mut scene = interacting_scene(3, preload_for(3));
    scene.post_x_m.pop();
    let err = CoupledModel::new(&scene).unwrap_err();
    assert!(
        err.to_string().contains("normal_compliance_m_per_n"),
        "size mismatch named: {err}"
    );
}

#[test]
fn post_histories_respect_contact_and_the_friction_cone() {
    let n = 9;
    let preload = preload_for(n);
    let model = CoupledModel::new(&interacting_scene(n, preload)).unwrap();
    let v0 = solve(&model, None).unwrap().no_load_speed_m_per_s;
    let (_, h) = model.post_histories(0.5 * v0).unwrap();
    assert_eq!(h.time_s.len(), 64, "one sample per step of the period");
    let mut mean_thrust = 0.0;
    for k in 0..h.time_s.len() {
        let total: f64 = h.normal_force_n[k].iter().sum();
        assert!(
            (total / preload - 1.0).abs() < 1e-9,
            "Σ N = P at sample {k}"
        );
        for i in 0..n {
            let (normal, tangential) = (h.normal_force_n[k][i], h.tangential_force_n[k][i]);
            assert!(normal >= 0.0, "unilateral normal force of post {i}");
            assert!(
                tangential.abs() <= 0.35 * normal * (1.0 + 1e-9) + 1e-15,
                "friction cone of post {i} at sample {k}: |T| = {tangential}, μ_s N = {}",
                0.35 * normal
            );
            if normal == 0.0 {
                assert_eq!(
                    h.mode[k][i],
                    coupled_dynamics::PostMode::Separated,
                    "separated post {i}"
                );
            }
        }
        mean_thrust += h.tangential_force_n[k].iter().sum::<f64>() / h.time_s.len() as f64;
    }
    let point = model.at_speed(0.5 * v0).unwrap();
    assert!(
        (mean_thrust / point.thrust_n - 1.0).abs() < 1e-9,
        "the histories' mean tangential force {mean_thrust} N is the thrust {} N",
        point.thrust_n
    );
}

#[test]
fn a_step_too_coarse_for_the_contact_arcs_is_warned_with_the_limit() {
    // Light preload: short contact arcs (≈ 10 % of the period), 16 steps resolve them by ≈ 2.
    let n = 3;
    let mut scene = interacting_scene(n, 0.02 * preload_for(n));
    scene.steps_per_period = 16;
    scene.curve_points = 3;
    let result = solve(&CoupledModel::new(&scene).unwrap(), None).unwrap();
    assert!(
        result
            .warnings
            .iter()
            .any(|w| w.contains("steps_per_period = 16") && w.contains("use steps_per_period ≥")),
        "coarse-step warning with the limit: {:?}",
        result.warnings
    );
    scene.steps_per_period = 512;
    let fine = solve(&CoupledModel::new(&scene).unwrap(), None).unwrap();
    assert!(
        fine.warnings
            .iter()
            .all(|w| !w.contains("steps_per_period")),
        "no warning once the arcs are resolved: {:?}",
        fine.warnings
    );
}

#[test]
fn stator_work_equals_output_plus_friction_within_1e_6_at_every_curve_point() {
    // Interacting posts with μ_s > μ_k (force drops at slip onset) and separations: the
    // midpoint (discrete-gradient) bookkeeping closes the balance to round-off at every point.
    let n = 9;
    let mut scene = interacting_scene(n, preload_for(n));
    scene.curve_points = 12;
    let result = solve(&CoupledModel::new(&scene).unwrap(), None).unwrap();
    for p in &result.curve {
        assert!(
            p.energy_balance_residual.abs() < 1e-6,
            "stator − output − friction work per period at {} m/s: {:.3e} of the power flow",
            p.speed_m_per_s,
            p.energy_balance_residual
        );
        assert!(
            p.friction_dissipation_w >= 0.0,
            "friction dissipation at {} m/s is {} W",
            p.speed_m_per_s,
            p.friction_dissipation_w
        );
    }
    eprintln!(
        "largest balance residual over the curve: midpoint {:.2e}, right-endpoint {:.2e}",
        result.energy_balance_residual,
        result
            .curve
            .iter()
            .map(|p| p.right_endpoint_balance_residual.abs())
            .fold(0.0, f64::max)
    );
    assert!(
        result.energy_balance_residual < 1e-6,
        "largest balance residual over the curve: {:.3e}",
        result.energy_balance_residual
    );
    // The right-endpoint bookkeeping misses by the step's numerical dissipation (O(h)).
    let worst = result
        .curve
        .iter()
        .map(|p| p.right_endpoint_balance_residual.abs())
        .fold(0.0, f64::max);
    assert!(
        worst > 1e-4,
        "the right-endpoint balance shows the O(h) numerical dissipation: {worst:.3e}"
    );
}

#[test]
fn stator_power_and_efficiency_converge_with_the_step() {
    // The work terms are trapezoid quadratures of the backward-Euler trajectory: their error
    // against a fine step falls at least linearly (observed order printed).
    let n = 5;
    let preload = preload_for(n);
    let run = |m: usize| {
        let mut scene = interacting_scene(n, preload);
        scene.steps_per_period = m;
        let model = CoupledModel::new(&scene).unwrap();
        let v = 0.3 * model.crest_speed_m_per_s();
        model.at_speed(v).unwrap()
    };
    let reference = run(4096);
    let steps = [64, 128, 256, 512];
    let errors: Vec<f64> = steps
        .iter()
        .map(|&m| (run(m).stator_power_w / reference.stator_power_w - 1.0).abs())
        .collect();
    // Least-squares slope of ln e against ln M.
    let xs: Vec<f64> = steps.iter().map(|&m| (m as f64).ln()).collect();
    let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / 4.0, ys.iter().sum::<f64>() / 4.0);
    let order = -xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    eprintln!("stator power errors {errors:?} at {steps:?} steps: order {order:.2}");
    assert!(
        order > 0.9,
        "observed order of the stator power: {order:.2} (errors {errors:?})"
    );
    assert!(
        errors[3] < 1e-2,
        "stator power at 512 steps within 1 % of 4096: {:.3e}",
        errors[3]
    );
}

#[test]
fn a_warm_started_point_is_the_cold_started_steady_state() {
    // The curve's chains and the no-load search start each speed from a neighbour's periodic
    // state; the steady cycle they reach must be the one reached from rest.
    let scene = interacting_scene(9, preload_for(9));
    let model = CoupledModel::new(&scene).unwrap();
    let result = solve(&model, None).unwrap();
    let (v0, stall) = (result.no_load_speed_m_per_s, result.stall_thrust_n);
    for fraction in [0.3, 0.7, 0.95] {
        let (_, above) = model.at_speed_from((fraction + 0.05) * v0, None).unwrap();
        let (warm, _) = model.at_speed_from(fraction * v0, Some(&above)).unwrap();
        let cold = model.at_speed(fraction * v0).unwrap();
        assert!(
            warm.converged && cold.converged,
            "both starts reach a periodic cycle at {fraction} v₀"
        );
        assert!(
            (warm.thrust_n - cold.thrust_n).abs() <= 1e-9 * stall,
            "thrust at {fraction} v₀: warm start {} N, from rest {} N",
            warm.thrust_n,
            cold.thrust_n
        );
        assert!(
            (warm.stator_power_w - cold.stator_power_w).abs()
                <= 1e-9 * cold.stator_power_w.abs().max(1e-300),
            "stator power at {fraction} v₀: warm start {} W, from rest {} W",
            warm.stator_power_w,
            cold.stator_power_w
        );
    }
    let curve_no_load = result.curve.last().unwrap();
    assert!(
        curve_no_load.thrust_n.abs() <= 1e-6 * stall,
        "the warm-started curve's last point is at no load: {} N",
        curve_no_load.thrust_n
    );
}
