//! The energy-conserving wave in the lumped models on the default motor (`Motor::paper()`
//! springs, 100 × 100 posts, η = 0.36) at 40 and 100 N: constant vs attenuated period average
//! (every column its own bin), the amplitude along the slider at stall, at maximum output power
//! and at no load, the bin-count convergence, and the attenuated transient against the
//! attenuated period average (two loads, and the whole transient curve: stall thrust, no-load
//! speed, books of every point, cost against the constant transient curve). Writes
//! `results.json` and SVG charts into the folder given (default
//! `validation/stick-slip/attenuation`).
//!
//! `cargo run --release -p stick-slip --example attenuation_study -- validation/stick-slip/attenuation`

#[path = "../tests/support/johnson.rs"]
mod johnson;

use std::path::{Path, PathBuf};
use std::time::Instant;

use charts::{Chart, Series, Style, write_chart};
use serde_json::json;
use stick_slip::{
    AttenuatedPeriodicModel, AttenuatedRun, AttenuatedSample, AttenuatedTransientResult,
    AttenuationOptions, DynamicResult, DynamicScene, ModelChoice, PeriodicAverageModel,
    TransientModel, TransientStart,
};

/// `sawdrive wave --json`'s `power_under_array_w` for the paper wave (128° Y-X LiNbO3, 20 nm,
/// 9.61 MHz, 2.4466 kW/m × the 4 mm array).
const POWER_UNDER_ARRAY_W: f64 = 9.78634644379686;

fn scene(preload_n: f64) -> DynamicScene {
    let (k_n, k_t) = johnson::springs(10e-6);
    let mut scene = DynamicScene::paper_default(k_n, k_t);
    scene.slider.preload_n = preload_n;
    scene
}

fn profile(s: &AttenuatedSample) -> Vec<(f64, f64)> {
    s.x_m
        .iter()
        .zip(&s.amplitude_scale)
        .map(|(x, a)| (x * 1e3, *a))
        .collect()
}

fn point_json(s: &AttenuatedSample) -> serde_json::Value {
    json!({
        "speed_m_per_s": s.sample.speed_m_per_s,
        "thrust_n": s.sample.thrust_n,
        "output_power_w": s.sample.output_power_w,
        "stator_power_w": s.sample.stator_power_w,
        "wave_power_in_w": s.wave_power_in_w,
        "wave_power_out_w": s.wave_power_out_w,
        "balance_residual": s.balance_residual,
        "iterations": s.iterations,
        "x_m": s.x_m,
        "amplitude_scale": s.amplitude_scale,
    })
}

fn study(preload_n: f64, out: &Path) -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    let scene = scene(preload_n);
    let t0 = Instant::now();
    let constant_model = PeriodicAverageModel::new(&scene)?;
    let constant = constant_model.solve(&stick_slip::RunControl::none())?;
    let constant_time = t0.elapsed().as_secs_f64();
    let constant_stall_draw = constant_model.at_speed(0.0)?.stator_power_w;
    let options = AttenuationOptions::new(POWER_UNDER_ARRAY_W);
    let t1 = Instant::now();
    let attenuated = AttenuatedPeriodicModel::new(&scene, &options)?.solve()?;
    let attenuated_time = t1.elapsed().as_secs_f64();
    let r = &attenuated.result;
    let points = &attenuated.points;
    let max_power = points
        .iter()
        .max_by(|a, b| a.sample.output_power_w.total_cmp(&b.sample.output_power_w))
        .expect("a curve");
    let (stall, no_load) = (&points[0], points.last().expect("a curve"));
    let name = format!("{preload_n:.0}N");
    let mut chart = Chart::new(
        format!("Amplitude along the slider, {preload_n:.0} N, P_in = {POWER_UNDER_ARRAY_W:.2} W"),
        "x under the slider (mm; the wave enters at the left)",
        "A / A0",
    );
    for (label, s) in [
        ("stall", stall),
        ("maximum output power", max_power),
        ("no load", no_load),
    ] {
        chart.series.push(Series::new(
            format!("{label} ({:.3} m/s)", s.sample.speed_m_per_s),
            profile(s),
            Style::Line,
        ));
    }
    write_chart(&chart, &out.join(format!("profile_{name}")))?;
    let mut curve = Chart::new(
        format!("Speed–thrust, {preload_n:.0} N, period average"),
        "speed (m/s)",
        "thrust (N)",
    );
    curve.series.push(Series::new(
        "constant amplitude",
        constant
            .curve
            .iter()
            .map(|p| (p.speed_m_per_s, p.thrust_n))
            .collect(),
        Style::Dashed,
    ));
    curve.series.push(Series::new(
        "energy-conserving wave",
        r.curve
            .iter()
            .map(|p| (p.speed_m_per_s, p.thrust_n))
            .collect(),
        Style::Line,
    ));
    let (transient, transient_json) = transient_curve(preload_n)?;
    curve.series.push(Series::new(
        "energy-conserving wave, transient",
        transient
            .result
            .curve
            .iter()
            .map(|p| (p.speed_m_per_s, p.thrust_n))
            .collect(),
        Style::Markers,
    ));
    write_chart(&curve, &out.join(format!("curve_{name}")))?;
    // Bin-count convergence of the stall point.
    let mut bins = Vec::new();
    for n in [5usize, 10, 20, 50] {
        let mut o = options;
        o.bins = Some(n);
        let s = AttenuatedPeriodicModel::new(&scene, &o)?.at_speed(0.0, None)?;
        bins.push(json!({
            "bins": n,
            "stall_thrust_n": s.sample.thrust_n,
            "relative_to_every_column": (s.sample.thrust_n - stall.sample.thrust_n) / stall.sample.thrust_n,
        }));
    }
    let row = |label: &str, stall_n: f64, v0: f64, power: f64, eff: f64| {
        json!({"wave": label, "stall_thrust_n": stall_n, "no_load_speed_m_per_s": v0,
               "max_output_power_w": power, "max_efficiency": eff})
    };
    Ok(json!({
        "preload_n": preload_n,
        "power_in_w": POWER_UNDER_ARRAY_W,
        "table": [
            row("constant", constant.stall_thrust_n, constant.no_load_speed_m_per_s,
                constant.max_output_power_w, constant.efficiency),
            row("energy-conserving", r.stall_thrust_n, r.no_load_speed_m_per_s,
                r.max_output_power_w, r.efficiency),
        ],
        "constant_stall_stator_power_w": constant_stall_draw,
        "attenuated_stall_stator_power_w": stall.sample.stator_power_w,
        "attenuated_stall_wave_power_out_w": stall.wave_power_out_w,
        "trailing_amplitude_at_stall": stall.amplitude_scale.last(),
        "max_balance_residual": attenuated.max_balance_residual,
        "max_iterations": attenuated.max_iterations,
        "post_solves": attenuated.post_solves,
        "wall_time_constant_s": constant_time,
        "wall_time_attenuated_s": attenuated_time,
        "bins": bins,
        "stall": point_json(stall),
        "max_power": point_json(max_power),
        "no_load": point_json(no_load),
        "curve": points.iter().map(point_json).collect::<Vec<_>>(),
        "transient": transient_json,
    }))
}

fn run_json(p: &AttenuatedRun) -> serde_json::Value {
    json!({
        "load_n": p.run.load_n,
        "speed_m_per_s": p.run.speed_m_per_s,
        "thrust_n": p.run.thrust_n,
        "output_power_w": p.run.output_power_w,
        "stator_power_w": p.run.stator_power_w,
        "wave_power_in_w": p.wave_power_in_w,
        "wave_power_out_w": p.wave_power_out_w,
        "balance_residual": p.balance_residual,
        "steady": p.run.steady,
        "iterations": p.iterations,
        "periods_simulated": p.periods_simulated,
        "last_change": p.last_change,
        "trailing_amplitude": p.amplitude_scale.last(),
    })
}

fn summary_json(label: &str, r: &DynamicResult) -> serde_json::Value {
    json!({"wave": label, "stall_thrust_n": r.stall_thrust_n,
           "no_load_speed_m_per_s": r.no_load_speed_m_per_s,
           "max_output_power_w": r.max_output_power_w, "max_efficiency": r.efficiency})
}

/// The whole transient curve (200 periods, the last 80 averaged, the default 6 curve loads and
/// stall search), constant and attenuated (profile adjusted inside each run, to 1e-6).
fn transient_curve(
    preload_n: f64,
) -> Result<(AttenuatedTransientResult, serde_json::Value), Box<dyn std::error::Error>> {
    let mut scene = scene(preload_n);
    scene.model = ModelChoice::Transient;
    scene.options.transient.periods = 200.0;
    scene.options.transient.average_periods = 80.0;
    let model = TransientModel::new(&scene)?;
    let t = Instant::now();
    let constant = model.solve()?;
    let constant_s = t.elapsed().as_secs_f64();
    let mut options = AttenuationOptions::new(POWER_UNDER_ARRAY_W);
    options.tolerance = 1e-6;
    let t = Instant::now();
    let attenuated = model.solve_attenuated(&options)?;
    let attenuated_s = t.elapsed().as_secs_f64();
    let constant_runs = constant.transient.as_ref().map_or(0, |s| s.runs);
    let json = json!({
        "settings": "200 periods, the last 80 averaged, 6 curve loads, stall search to 2e-3, profile to 1e-6 inside each run",
        "table": [
            summary_json("constant", &constant),
            summary_json("energy-conserving", &attenuated.result),
        ],
        "max_balance_residual": attenuated.max_balance_residual,
        "min_wave_power_out_w": attenuated.points.iter().map(|p| p.wave_power_out_w).fold(f64::INFINITY, f64::min),
        "max_iterations": attenuated.max_iterations,
        "loads_run": attenuated.runs,
        "periods_constant": constant_runs * 200,
        "periods_attenuated": attenuated.periods_simulated,
        "wall_time_constant_s": constant_s,
        "wall_time_attenuated_s": attenuated_s,
        "warnings": attenuated.result.warnings.iter().map(ToString::to_string).collect::<Vec<_>>(),
        "curve": attenuated.points.iter().map(run_json).collect::<Vec<_>>(),
    });
    Ok((attenuated, json))
}

/// The attenuated transient against the attenuated period average at two loads (40 N).
fn transient_check() -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    let mut scene = scene(40.0);
    scene.model = ModelChoice::Transient;
    scene.options.transient.periods = 200.0;
    scene.options.transient.average_periods = 80.0;
    let mut options = AttenuationOptions::new(POWER_UNDER_ARRAY_W);
    options.tolerance = 1e-6;
    let periodic = AttenuatedPeriodicModel::new(&scene, &options)?;
    let stall = periodic.at_speed(0.0, None)?.sample.thrust_n;
    let transient = TransientModel::new(&scene)?;
    let constant_pa = PeriodicAverageModel::new(&scene)?;
    let mut rows = Vec::new();
    for load in [0.0, 0.5 * stall] {
        let mut at = scene.clone();
        at.slider.external_load_n = load;
        let pa = AttenuatedPeriodicModel::new(&at, &options)?
            .solve()?
            .operating
            .ok_or("load above the attenuated stall thrust")?;
        let t = Instant::now();
        let run = transient.run_attenuated(
            load,
            TransientStart::Estimate,
            &options,
            Some(&pa.amplitude_scale),
        )?;
        let attenuated_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let constant_run = transient.run(load, TransientStart::Estimate, false)?;
        let constant_s = t.elapsed().as_secs_f64();
        let constant_speed = constant_pa.at_load(load)?.map_or(0.0, |s| s.speed_m_per_s);
        rows.push(json!({
            "load_n": load,
            "attenuated_transient_speed_m_per_s": run.run.speed_m_per_s,
            "attenuated_period_average_speed_m_per_s": pa.sample.speed_m_per_s,
            "constant_transient_speed_m_per_s": constant_run.speed_m_per_s,
            "constant_period_average_speed_m_per_s": constant_speed,
            "transient_runs": run.iterations,
            "transient_last_change": run.last_change,
            "transient_balance_residual": run.balance_residual,
            "max_profile_difference": run.amplitude_scale.iter().zip(&pa.amplitude_scale)
                .map(|(a, b)| (a - b).abs()).fold(0.0, f64::max),
            "wall_time_attenuated_run_s": attenuated_s,
            "wall_time_constant_run_s": constant_s,
        }));
    }
    Ok(json!(rows))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).map_or_else(
        || PathBuf::from("validation/stick-slip/attenuation"),
        PathBuf::from,
    );
    std::fs::create_dir_all(&out)?;
    let results = json!({
        "command": "cargo run --release -p stick-slip --example attenuation_study -- validation/stick-slip/attenuation",
        "motor": "Motor::paper() springs (20 µm posts), 100 × 100 at 40 µm, η = 0.36, μ = 0.3, 50-point curves",
        "period_average": [study(40.0, &out)?, study(100.0, &out)?],
        "transient_vs_period_average_40N": transient_check()?,
    });
    let text = serde_json::to_string_pretty(&results)?;
    std::fs::write(out.join("results.json"), text + "\n")?;
    println!(
        "{}",
        serde_json::to_string_pretty(&results["period_average"][0]["table"])?
    );
    println!(
        "{}",
        serde_json::to_string_pretty(&results["period_average"][1]["table"])?
    );
    Ok(())
}
