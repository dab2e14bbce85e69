//! The default slider's row (100 posts at 40 µm, analytic compliance as in the `curve` bench:
//! Johnson post springs plus the half-space terms of all 100 rows) with and without the
//! energy-conserving wave: stall thrust, no-load speed, max output power, stator power at
//! stall, wave power in/out, fixed-point iterations and balance residual.
//!
//! `cargo run -p coupled-dynamics --example attenuated_row -- PRELOAD_N POWER_IN_W [POINTS]`
//! (POWER_IN_W: `sawdrive wave --json`'s `power_under_array_w`, 9.786 W for the paper wave);
//! with `ATTENUATED_ROW_CHART=STEM` also STEM-amplitude.svg/.png (the amplitude along the slider
//! at stall, at maximum output power and near no load) and STEM-speed-thrust.svg/.png (the
//! curves with and without the energy-conserving wave).

use coupled_dynamics::{AttenuationOptions, CoupledModel, solve, solve_attenuated};

mod common;

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("a number"))
        .collect();
    let (preload, power_in) = (args[0], args[1]);
    let mut scene = common::analytic_row(100, preload);
    scene.curve_points = args.get(2).map_or(21, |p| *p as usize);
    let started = std::time::Instant::now();
    let constant = solve(&CoupledModel::new(&scene).unwrap(), None).unwrap();
    let max_power = |p: &mut dyn Iterator<Item = f64>| p.fold(0.0, f64::max);
    println!(
        "constant amplitude, {preload} N: stall {:.4} N, no-load {:.4} m/s, max power {:.4} W, stator at stall {:.4} W ({:.1} s)",
        constant.stall_thrust_n,
        constant.no_load_speed_m_per_s,
        max_power(&mut constant.curve.iter().map(|p| p.output_power_w)),
        constant.curve[0].stator_power_w,
        started.elapsed().as_secs_f64()
    );
    let started = std::time::Instant::now();
    let a = solve_attenuated(&scene, &AttenuationOptions::new(power_in)).unwrap();
    let stall = &a.curve[0];
    println!(
        "attenuated, {preload} N, P_in {power_in} W: stall {:.4} N, no-load {:.4} m/s, max power {:.4} W, stator at stall {:.4} W, wave in {:.4} W out {:.4} W, iterations ≤ {}, balance ≤ {:.2e} ({:.1} s)",
        a.stall_thrust_n,
        a.no_load_speed_m_per_s,
        max_power(&mut a.curve.iter().map(|p| p.point.output_power_w)),
        stall.point.stator_power_w,
        stall.wave_power_in_w,
        stall.wave_power_out_w,
        a.max_iterations,
        a.max_balance_residual,
        started.elapsed().as_secs_f64()
    );
    for (c, p) in constant.curve.iter().zip(&a.curve) {
        println!(
            "  v {:.4} F {:.4} P {:.4} | v {:.4} F {:.4} P {:.4} drawn {:.4} out {:.4} iterations {}",
            c.speed_m_per_s,
            c.thrust_n,
            c.output_power_w,
            p.point.speed_m_per_s,
            p.point.thrust_n,
            p.point.output_power_w,
            p.point.stator_power_w,
            p.wave_power_out_w,
            p.iterations
        );
    }
    if let Ok(stem) = std::env::var("ATTENUATED_ROW_CHART") {
        use charts::{Chart, Series, Style, write_chart};
        let x0 = scene.post_x_m[0];
        let profile = |p: &coupled_dynamics::AttenuatedPoint| -> Vec<(f64, f64)> {
            scene
                .post_x_m
                .iter()
                .zip(&p.amplitude_scale)
                .map(|(x, a)| ((x - x0) * 1e3, a * scene.wave.normal_amplitude_m * 1e9))
                .collect()
        };
        let best = a
            .curve
            .iter()
            .max_by(|p, q| p.point.output_power_w.total_cmp(&q.point.output_power_w))
            .unwrap();
        let near_no_load = &a.curve[a.curve.len() - 2];
        let mut amplitude = Chart::new(
            format!("Normal amplitude along the slider, {preload} N, P_in = {power_in:.2} W"),
            "distance from the leading edge (mm)",
            "normal amplitude (nm)",
        );
        for (name, p) in [
            ("stall".to_string(), stall),
            (
                format!("max power, {:.3} m/s", best.point.speed_m_per_s),
                best,
            ),
            (
                format!("near no load, {:.3} m/s", near_no_load.point.speed_m_per_s),
                near_no_load,
            ),
        ] {
            amplitude
                .series
                .push(Series::new(name, profile(p), Style::Line));
        }
        let mut curves = Chart::new("Speed–thrust", "speed (m/s)", "thrust (N)");
        curves.series.push(Series::new(
            "constant amplitude",
            constant
                .curve
                .iter()
                .map(|p| (p.speed_m_per_s, p.thrust_n))
                .collect(),
            Style::LineMarkers,
        ));
        curves.series.push(Series::new(
            "energy-conserving wave",
            a.curve
                .iter()
                .map(|p| (p.point.speed_m_per_s, p.point.thrust_n))
                .collect(),
            Style::LineMarkers,
        ));
        for (chart, suffix) in [(amplitude, "amplitude"), (curves, "speed-thrust")] {
            let written =
                write_chart(&chart, std::path::Path::new(&format!("{stem}-{suffix}"))).unwrap();
            println!("wrote {written:?}");
        }
    }
    let alpha = &stall.amplitude_scale;
    println!(
        "amplitude at stall, A/A₀ every 10th post along the wave: {:?}",
        alpha
            .iter()
            .step_by(10)
            .map(|a| (a * 1e4).round() / 1e4)
            .collect::<Vec<_>>()
    );
}
