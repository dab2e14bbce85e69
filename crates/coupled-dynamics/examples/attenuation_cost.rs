//! The cost of the energy-conserving wave against the constant wave on one coupled row: periods
//! stepped (`coupled_dynamics::model::periods_stepped`, independent of the machine's load) and
//! process CPU time of the constant curve, the attenuated curve and the attenuated history point
//! (half the no-load speed, with every post's histories), with the headline figures and every
//! curve point's thrust and output power for comparing two builds.
//!
//! `cargo run --release -p coupled-dynamics --example attenuation_cost -- (COMPLIANCE.json | --row PRELOAD_N) [--out FILE] [--tolerance T]`
//!
//! COMPLIANCE.json: the compliance cache entry of `sawdrive run` (`out/.cache/compliance-*.json`,
//! the default strip, 64 steps per period: the default run's coupled model). `--row`: the analytic
//! 100-post row of the default slider (Johnson post springs plus the half-space terms of all 100
//! rows, 128 steps per period). Both with 50 curve points and P_in = 9.786 W (the paper wave under
//! the 4 mm array). `--out` writes the figures (17 significant digits) for a later comparison;
//! `--tolerance` sets the profile's tolerance (default 1e-6; e.g. 1e-10 for a reference).

use std::fmt::Write as _;

use contact_springs::{Material, post_springs};
use coupled_dynamics::model::periods_stepped;
use coupled_dynamics::{
    AttenuationOptions, CoupledModel, CoupledScene, PreloadBalance, solve,
    solve_attenuated_with_histories,
};
use motor::Motor;
use nalgebra::DMatrix;
use static_contact::halfspace::{
    RowLayout, StripPost, strip_compliance, strip_tangential_compliance,
};

/// `sawdrive wave --json`'s `power_under_array_w` for the paper wave.
const POWER_UNDER_ARRAY_W: f64 = 9.78634644379686;

fn row_scene(preload_n: f64) -> CoupledScene {
    let (pitch, radius, n) = (40e-6, 10e-6, 100);
    let (si, ln) = (Material::silicon(), Material::lithium_niobate());
    let springs = post_springs(&si, &ln, radius).unwrap();
    let posts: Vec<StripPost> = (0..n)
        .map(|i| StripPost {
            x_m: (i as f64 - 0.5 * (n - 1) as f64) * pitch,
            row: 0,
        })
        .collect();
    let layout = RowLayout {
        pitch_m: pitch,
        strip_rows: 1,
        slider_rows: 100,
    };
    let (g, nu) = (ln.shear_modulus_pa, ln.poisson_ratio);
    let mut scene = CoupledScene::independent_posts(
        stick_slip::Wave::paper_default(),
        posts.iter().map(|p| p.x_m).collect(),
        1.0,
        1.0,
        0.3,
        0.3,
        preload_n,
    );
    scene.normal_compliance_m_per_n = strip_compliance(g, nu, radius, &posts, &layout)
        + DMatrix::identity(n, n) / springs.k_pn_n_per_m;
    scene.tangential_compliance_m_per_n =
        strip_tangential_compliance(g, nu, radius, &posts, &layout)
            + DMatrix::identity(n, n) / springs.k_pt_n_per_m;
    scene.strip_share = 0.01;
    scene.preload_balance = PreloadBalance::Instant;
    scene.steps_per_period = 128;
    scene
}

fn cached_scene(path: &str) -> CoupledScene {
    let text = std::fs::read_to_string(path).expect("the compliance cache entry");
    let entry: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let tips = &entry["tips"];
    let numbers = |key: &str| -> Vec<f64> {
        tips[key]
            .as_array()
            .expect(key)
            .iter()
            .map(|v| v.as_f64().expect("a number"))
            .collect()
    };
    let x = numbers("post_x_m");
    let n = x.len();
    let motor = Motor::paper();
    let mut scene = CoupledScene::independent_posts(
        motor.wave.clone(),
        x,
        1.0,
        1.0,
        motor.friction.mu_static,
        motor.friction.mu_kinetic,
        motor.load.preload_n,
    );
    scene.normal_compliance_m_per_n = DMatrix::from_vec(n, n, numbers("normal_m_per_n"));
    scene.tangential_compliance_m_per_n = DMatrix::from_vec(n, n, numbers("tangential_m_per_n"));
    scene.strip_share = tips["strip_share"].as_f64().expect("strip_share");
    scene.preload_balance = PreloadBalance::Instant;
    scene.steps_per_period = 64;
    scene
}

/// Process CPU time (user + system, s) from /proc/self/stat (clock ticks of 1/100 s).
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or(vec![], |(_, rest)| rest.split_whitespace().collect());
    let tick = |k: usize| {
        fields
            .get(k)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (tick(11) + tick(12)) / 100.0
}

/// Periods and CPU seconds of `f`, with its value.
fn cost<T>(f: impl FnOnce() -> T) -> (T, usize, f64) {
    let (p0, c0) = (periods_stepped(), cpu_s());
    let value = f();
    (value, periods_stepped() - p0, cpu_s() - c0)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut scene = match args.first().map(String::as_str) {
        Some("--row") => row_scene(args[1].parse().expect("PRELOAD_N")),
        Some(path) => cached_scene(path),
        None => {
            eprintln!(
                "error: usage: attenuation_cost (COMPLIANCE.json | --row PRELOAD_N) [--out FILE]"
            );
            std::process::exit(2);
        }
    };
    scene.curve_points = 50;
    let out = args
        .iter()
        .position(|a| a == "--out")
        .map(|k| args[k + 1].clone());
    let (constant, periods, cpu) =
        cost(|| solve(&CoupledModel::new(&scene).unwrap(), None).unwrap());
    println!(
        "constant curve: {periods} periods, {cpu:.2} s CPU; stall {:.6} N, no-load {:.6} m/s",
        constant.stall_thrust_n, constant.no_load_speed_m_per_s
    );
    println!(
        "  constant points' periods: {:?}",
        constant.curve.iter().map(|p| p.periods).collect::<Vec<_>>()
    );
    let mut options = AttenuationOptions::new(POWER_UNDER_ARRAY_W);
    if let Some(k) = args.iter().position(|a| a == "--tolerance") {
        options.tolerance = args[k + 1].parse().expect("--tolerance: a number");
    }
    options.no_load_guess_m_per_s = Some(constant.no_load_speed_m_per_s);
    let ((curve, at_half, histories), periods, cpu) =
        cost(|| solve_attenuated_with_histories(&scene, &options, 0.5).unwrap());
    println!(
        "attenuated curve and history point: {periods} periods, {cpu:.2} s CPU; stall {:.6} N, no-load {:.6} m/s, iterations ≤ {}, balance ≤ {:.1e}",
        curve.stall_thrust_n,
        curve.no_load_speed_m_per_s,
        curve.max_iterations,
        curve.max_balance_residual
    );
    println!(
        "  curve points' periods: {:?}",
        curve
            .curve
            .iter()
            .map(|p| p.point.periods)
            .collect::<Vec<_>>()
    );
    println!(
        "  history point at {:.6} m/s: thrust {:.6} N, {} samples",
        at_half.point.speed_m_per_s,
        at_half.point.thrust_n,
        histories.time_s.len()
    );
    let mut text = String::new();
    let _ = writeln!(
        text,
        "stall_thrust_n {:.17e}\nno_load_speed_m_per_s {:.17e}\nhistory_thrust_n {:.17e}\nhistory_tangential_sum_n {:.17e}",
        curve.stall_thrust_n,
        curve.no_load_speed_m_per_s,
        at_half.point.thrust_n,
        histories.tangential_force_n.iter().flatten().sum::<f64>()
    );
    for p in &curve.curve {
        let _ = writeln!(
            text,
            "point {:.17e} {:.17e} {:.17e} {:.17e} {:.17e} {:.3e}",
            p.point.speed_m_per_s,
            p.point.thrust_n,
            p.point.output_power_w,
            p.point.stator_power_w,
            p.wave_power_out_w,
            p.balance_residual
        );
    }
    if let Some(file) = out {
        std::fs::write(&file, text).expect("--out");
    }
}
