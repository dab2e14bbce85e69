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

mod common;
use common::cpu_s;

use coupled_dynamics::model::periods_stepped;
use coupled_dynamics::{AttenuationOptions, CoupledModel, solve, solve_attenuated_with_histories};

/// `sawdrive wave --json`'s `power_under_array_w` for the paper wave.
const POWER_UNDER_ARRAY_W: f64 = 9.78634644379686;

/// Periods and CPU seconds of `f`, with its value.
fn cost<T>(f: impl FnOnce() -> T) -> (T, usize, f64) {
    let (p0, c0) = (periods_stepped(), cpu_s());
    let value = f();
    (value, periods_stepped() - p0, cpu_s() - c0)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut scene = match args.first().map(String::as_str) {
        Some("--row") => common::analytic_row(100, args[1].parse().expect("PRELOAD_N")),
        Some(path) => common::cached_strip(path, 64).unwrap_or_else(|e| {
            eprintln!("error: {e}");
            std::process::exit(1);
        }),
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
