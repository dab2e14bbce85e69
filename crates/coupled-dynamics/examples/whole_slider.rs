//! The whole slider's coupled stick/slip (every post of the lattice) on the paper motor's static
//! state, with the cost per step and per curve point, the results as JSON and the per-post maps
//! as SVG.
//!
//! `cargo run -p coupled-dynamics --profile test --example whole_slider -- [--side N] [--steps M]
//! [--points K] [--scatter-nm S] [--preload-n P] [--tolerance T] [--point-only] [--cold] [--out DIR]`
//!
//! Defaults: the paper's 100 × 100 posts (`--side` makes an N × N corner-free sub-slider of the
//! same pitch, slider size N·pitch + the paper's margins), 64 steps per period, 8 curve points,
//! ideal posts, 40 N, rigid back, Johnson near fields, step tolerance 1e-10. `--point-only`: the normal grid, the
//! stall point and one point at half the crest speed (the timing of one curve point), no curve.
//! The curve's no-load search starts from the middle-row strip's no-load speed
//! (`SliderDynamics::solve_from_guess`); `--cold`: from the crest speed, the maps from rest
//! (`SliderDynamics::solve`, the earlier sequence). Under `--scatter-nm` there is no middle-row
//! strip (it stands for an ideal slider): the comparison is skipped, said so, and the search
//! starts from the crest speed. An ideal slider runs on its y-mirror's half (said so).
//! `--out DIR` writes DIR/results/whole_slider_<side>.json and DIR/figures/*.svg (maps of the
//! time-mean normal force, slip fraction and friction power per post at half the no-load speed,
//! and the friction power at stall).

use std::path::{Path, PathBuf};
use std::time::Instant;

use coupled_dynamics::{SliderDynamics, SliderScene};
use motor::Motor;
use slider_contact::{NearField, SliderModel, SliderParams};

struct Args {
    side: usize,
    steps: usize,
    points: usize,
    scatter_m: f64,
    preload_n: f64,
    point_only: bool,
    cold: bool,
    tolerance: f64,
    out: Option<PathBuf>,
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        side: 100,
        steps: 64,
        points: 8,
        scatter_m: 0.0,
        preload_n: 40.0,
        point_only: false,
        cold: false,
        tolerance: coupled_dynamics::slider::DEFAULT_SLIDER_TOLERANCE,
        out: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(key) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{key} needs a value"));
        let number = |s: String| s.parse::<f64>().map_err(|e| format!("{key}: {e}"));
        match key.as_str() {
            "--side" => a.side = number(value()?)? as usize,
            "--steps" => a.steps = number(value()?)? as usize,
            "--points" => a.points = number(value()?)? as usize,
            "--scatter-nm" => a.scatter_m = number(value()?)? * 1e-9,
            "--preload-n" => a.preload_n = number(value()?)?,
            "--point-only" => a.point_only = true,
            "--cold" => a.cold = true,
            "--tolerance" => a.tolerance = number(value()?)?,
            "--out" => a.out = Some(PathBuf::from(value()?)),
            other => return Err(format!("unknown argument {other}")),
        }
    }
    Ok(a)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = parse()?;
    let motor = Motor::paper();
    let mut params = SliderParams::for_motor(&motor);
    let margin_x = params.slider_length_m - params.posts_x as f64 * params.post_pitch_m;
    let margin_y = params.slider_width_m - params.posts_y as f64 * params.post_pitch_m;
    let share = (args.side * args.side) as f64 / (params.posts_x * params.posts_y) as f64;
    params.posts_x = args.side;
    params.posts_y = args.side;
    params.slider_length_m = args.side as f64 * params.post_pitch_m + margin_x;
    params.slider_width_m = args.side as f64 * params.post_pitch_m + margin_y;
    params.preload_n = args.preload_n * share;
    params.imperfections.height_scatter_m = args.scatter_m;
    let started = Instant::now();
    let static_model = SliderModel::build(&params)?;
    let build_s = started.elapsed().as_secs_f64();
    let mut scene = SliderScene::for_static(
        &static_model,
        motor.wave.clone(),
        motor.friction.mu_static,
        motor.friction.mu_kinetic,
    );
    scene.steps_per_period = args.steps;
    scene.curve_points = args.points;
    scene.tolerance = args.tolerance;
    let started = Instant::now();
    let slider = SliderDynamics::for_slider(&scene, &static_model, NearField::Johnson)?;
    let model_s = started.elapsed().as_secs_f64();
    let n = args.side * args.side;
    println!(
        "{} × {} posts, {} steps per period, P = {:.4} N: operators {build_s:.2} s, normal grid {:.2} s ({:.1} ms per phase)",
        args.side,
        args.side,
        args.steps,
        params.preload_n,
        model_s,
        1e3 * slider.normal_grid_wall_s() / args.steps as f64
    );
    let crest = slider.model().crest_speed_m_per_s();
    if args.point_only {
        for speed in [0.0, 0.5 * crest] {
            let (t, cpu) = (Instant::now(), cpu_s());
            let (p, _) = slider.model().at_speed_from(speed, None)?;
            let s = t.elapsed().as_secs_f64();
            let cpu = cpu_s() - cpu;
            let steps = p.periods * args.steps;
            println!(
                "v = {speed:.4} m/s: thrust {:.5} N (per post {:.4e}), {} periods, {:.2} s wall ({:.2} s CPU), {:.2} ms per step ({:.2} ms CPU), {:.1} solver iterations per step, balance {:.1e}, solver residual {:.1e}",
                p.thrust_n,
                p.thrust_n / n as f64,
                p.periods,
                s,
                cpu,
                1e3 * s / steps as f64,
                1e3 * cpu / steps as f64,
                p.solver_iterations as f64 / steps as f64,
                p.energy_balance_residual,
                p.max_solver_residual
            );
        }
        return Ok(());
    }
    if let Some(m) = slider.mirror() {
        println!(
            "y-mirror symmetric: the model runs on the {} posts of {} rows",
            m.len(),
            m.half_posts_y()
        );
    }
    let t = Instant::now();
    let strip = if args.scatter_m > 0.0 {
        println!(
            "height scatter: no middle-row strip to compare with (it stands for an ideal slider); the no-load search starts from the crest speed"
        );
        None
    } else {
        let strip = strip_reference(&static_model, &scene)?;
        println!(
            "strip of the middle row (same kernels, the {} rows loaded alike): stall thrust {:.4} N, no-load speed {:.4} m/s ({:.1} s)",
            args.side,
            strip.stall_thrust_n,
            strip.no_load_speed_m_per_s,
            t.elapsed().as_secs_f64()
        );
        Some(strip)
    };
    let t = Instant::now();
    let result = match &strip {
        Some(strip) if !args.cold => {
            slider.solve_from_guess(None, Some(strip.no_load_speed_m_per_s))?
        }
        _ => slider.solve(None)?,
    };
    let solve_s = t.elapsed().as_secs_f64();
    let c = &result.coupled;
    let periods: usize = c.curve.iter().map(|p| p.periods).sum();
    println!(
        "stall thrust {:.4} N, no-load speed {:.4} m/s, max energy balance residual {:.1e}, \
         curve + maps {solve_s:.1} s ({} points, {periods} periods, {:.2} ms per step)",
        c.stall_thrust_n,
        c.no_load_speed_m_per_s,
        c.energy_balance_residual,
        c.curve.len(),
        1e3 * solve_s / (periods * args.steps) as f64
    );
    for p in &c.curve {
        println!(
            "  v {:.4} m/s  F {:.4} N  stick {:.3}  stator {:.3} W  periods {}",
            p.speed_m_per_s, p.thrust_n, p.stick_fraction, p.stator_power_w, p.periods
        );
    }
    for m in &result.maps {
        let (i, j) = m.hottest_post();
        println!(
            "maps at {:.4} m/s: friction {:.4} W, hottest post ({i}, {j}) {:.3e} W, mean normal force {:.3e} … {:.3e} N",
            m.means.speed_m_per_s,
            m.total_friction_power_w(),
            m.means.friction_power_w[i * m.posts_y + j],
            min(&m.means.mean_normal_force_n),
            max(&m.means.mean_normal_force_n)
        );
    }
    if let Some(out) = &args.out {
        write_outputs(
            out,
            &args,
            &result,
            strip.as_ref(),
            build_s,
            model_s,
            solve_s,
        )?;
    }
    Ok(())
}

/// CPU seconds of this process so far (user + system, Linux's /proc/self/stat at 100 ticks per
/// second; NaN elsewhere): the figure to compare on a machine shared with other work.
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or(Vec::new(), |(_, rest)| rest.split_whitespace().collect());
    let tick = |k: usize| fields.get(k).and_then(|v| v.parse::<f64>().ok());
    match (tick(11), tick(12)) {
        (Some(user), Some(system)) => (user + system) / 100.0,
        _ => f64::NAN,
    }
}

/// The strip of the middle row on the slider's own compliances (`slider::middle_row_strip`).
fn strip_reference(
    model: &SliderModel,
    scene: &SliderScene,
) -> Result<coupled_dynamics::CoupledResult, Box<dyn std::error::Error>> {
    let tangential = slider_contact::LatticeOperator::tangential(
        &model.params.operator_spec(),
        NearField::Johnson,
    )?;
    let mut strip =
        coupled_dynamics::slider::middle_row_strip(scene, &model.operator, &tangential)?;
    strip.tolerance = 1e-12;
    Ok(coupled_dynamics::solve(
        &coupled_dynamics::CoupledModel::new(&strip)?,
        None,
    )?)
}

fn min(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

fn write_outputs(
    out: &Path,
    args: &Args,
    result: &coupled_dynamics::SliderDynamicsResult,
    strip: Option<&coupled_dynamics::CoupledResult>,
    build_s: f64,
    model_s: f64,
    solve_s: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all(out.join("results"))?;
    std::fs::create_dir_all(out.join("figures"))?;
    let json = serde_json::json!({
        "command": format!(
            "cargo run -p coupled-dynamics --profile test --example whole_slider -- --side {} --steps {} --points {} --scatter-nm {} --preload-n {} --tolerance {:e} --out DIR",
            args.side, args.steps, args.points, args.scatter_m * 1e9, args.preload_n, args.tolerance
        ),
        "operators_s": build_s,
        "normal_grid_s": model_s,
        "curve_and_maps_s": solve_s,
        "result": result,
        "strip_reference": strip,
    });
    let tag = format!(
        "side{}_{}n{}",
        args.side,
        args.preload_n,
        if args.scatter_m > 0.0 {
            format!("_scatter{}nm", args.scatter_m * 1e9)
        } else {
            String::new()
        }
    );
    atomic_files::write_atomically(
        &out.join("results").join(format!("whole_slider_{tag}.json")),
        serde_json::to_vec(&rounded(json))?,
    )?;
    let [stall, half] = [&result.maps[0], &result.maps[1]];
    let speed = format!("{:.3} m/s", half.means.speed_m_per_s);
    for (name, map, field, unit) in [
        (
            "mean_normal_force",
            half,
            &half.means.mean_normal_force_n,
            "N",
        ),
        ("slip_fraction", half, &half.means.slip_fraction, ""),
        ("friction_power", half, &half.means.friction_power_w, "W"),
        (
            "friction_power_stall",
            stall,
            &stall.means.friction_power_w,
            "W",
        ),
    ] {
        let title = format!(
            "{name} per post at {}",
            if name.ends_with("stall") {
                "stall".to_string()
            } else {
                speed.clone()
            }
        );
        atomic_files::write_atomically(
            &out.join("figures").join(format!("{name}_{tag}.svg")),
            map.svg(field, &title, unit),
        )?;
    }
    Ok(())
}

/// Every number to 7 significant digits (the per-post maps are 10⁵ numbers; the solver's own
/// tolerances are far coarser than 16 digits).
fn rounded(v: serde_json::Value) -> serde_json::Value {
    use serde_json::Value;
    match v {
        Value::Number(n) if n.is_f64() => {
            let x = n.as_f64().unwrap_or(0.0);
            let r = format!("{x:.6e}").parse::<f64>().unwrap_or(x);
            serde_json::Number::from_f64(r).map_or(Value::Null, Value::Number)
        }
        Value::Array(a) => Value::Array(a.into_iter().map(rounded).collect()),
        Value::Object(o) => Value::Object(o.into_iter().map(|(k, v)| (k, rounded(v))).collect()),
        other => other,
    }
}
