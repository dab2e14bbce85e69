//! The ball-slider validation study: writes `results/ball_study.json` and the SVG figures of
//! `validation/ball-slider/` (or of the folder given as the first argument).
//!
//! `cargo run --release -p ball-slider --example ball_study` (≈ 10 s).

use std::path::{Path, PathBuf};

use ball_slider::BallResult;
use ball_slider::study::{self, Study, StudySize};
use charts::{Chart, Scale, Series, Style};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation/ball-slider")
        });
    let study = study::run(StudySize::Full)?;
    std::fs::create_dir_all(out.join("results"))?;
    std::fs::create_dir_all(out.join("figures"))?;
    let json = serde_json::to_string_pretty(&study)?;
    std::fs::write(out.join("results/ball_study.json"), json + "\n")?;
    draw(&study, &out.join("figures"))?;
    print_summary(&study);
    Ok(())
}

fn curve_series(name: String, r: &BallResult) -> Series {
    let points = r
        .curve
        .iter()
        .map(|p| (p.thrust_n * 1e3, p.speed_m_per_s))
        .collect();
    Series::new(name, points, Style::LineMarkers)
}

/// Write an SVG chart only (the PNG twin is removed: the folder keeps SVG).
fn svg(chart: &Chart, stem: &Path) -> Result<(), Box<dyn std::error::Error>> {
    for file in charts::write_chart(chart, stem)? {
        if file.extension().is_some_and(|e| e == "png") {
            std::fs::remove_file(file)?;
        }
    }
    Ok(())
}

fn draw(s: &Study, dir: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let mut curves = Chart::new(
        "2 mm steel ball, 20 mN: speed–thrust at wave amplitudes A_n (A_t/A_n = 0.91)",
        "thrust (mN)",
        "speed (m/s)",
    );
    for row in s.amplitude_sweep.iter().filter(|r| r.result.drives) {
        curves.series.push(curve_series(
            format!("{:.0} nm", row.value * 1e9),
            &row.result,
        ));
    }
    svg(&curves, &dir.join("speed_thrust_amplitudes"))?;
    let amp = |f: &dyn Fn(&BallResult) -> f64| -> Vec<(f64, f64)> {
        s.amplitude_sweep
            .iter()
            .map(|r| (r.value * 1e9, f(&r.result)))
            .collect()
    };
    let mut stall = Chart::new(
        "Stall thrust against wave amplitude (2 mm ball, 20 mN)",
        "A_n (nm)",
        "thrust (mN)",
    );
    stall.series.push(Series::new(
        "stall thrust",
        amp(&|r| r.stall_thrust_n * 1e3),
        Style::LineMarkers,
    ));
    stall.series.push(Series::new(
        "μP",
        amp(&|r| r.friction_limit_n * 1e3),
        Style::Dashed,
    ));
    svg(&stall, &dir.join("stall_thrust_vs_amplitude"))?;
    let mut speed = Chart::new(
        "No-load speed against wave amplitude (2 mm ball, 20 mN)",
        "A_n (nm)",
        "speed (m/s)",
    );
    speed.series.push(Series::new(
        "no-load speed",
        amp(&|r| r.no_load_speed_m_per_s),
        Style::LineMarkers,
    ));
    speed.series.push(Series::new(
        "crest speed A_tω",
        amp(&|r| r.crest_speed_m_per_s),
        Style::Dashed,
    ));
    svg(&speed, &dir.join("no_load_speed_vs_amplitude"))?;
    let pre = |f: &dyn Fn(&BallResult) -> f64| -> Vec<(f64, f64)> {
        s.preload_sweep
            .iter()
            .map(|r| (r.value * 1e3, f(&r.result)))
            .collect()
    };
    let mut preload = Chart::new(
        "Preload sweep at 20 nm (2 mm ball)",
        "preload (mN)",
        "stall thrust / μP, no-load speed / A_tω",
    );
    preload.x_scale = Scale::Log;
    preload.series.push(Series::new(
        "stall thrust / μP",
        pre(&|r| r.stall_thrust_n / r.friction_limit_n),
        Style::LineMarkers,
    ));
    preload.series.push(Series::new(
        "no-load speed / A_tω",
        pre(&|r| r.no_load_speed_m_per_s / r.crest_speed_m_per_s),
        Style::LineMarkers,
    ));
    svg(&preload, &dir.join("preload_sweep"))?;
    let d = &s.default;
    let pw = |f: &dyn Fn(&ball_slider::CurvePoint) -> f64| -> Vec<(f64, f64)> {
        d.curve
            .iter()
            .map(|p| (p.speed_m_per_s, f(p) * 1e3))
            .collect()
    };
    let mut power = Chart::new(
        "Power books along the default curve (2 mm, 20 mN, 20 nm)",
        "speed (m/s)",
        "power (mW)",
    );
    power.series.push(Series::new(
        "from the wave",
        pw(&|p| p.stator_power_w),
        Style::LineMarkers,
    ));
    power.series.push(Series::new(
        "friction",
        pw(&|p| p.friction_power_w),
        Style::LineMarkers,
    ));
    power.series.push(Series::new(
        "mechanical output",
        pw(&|p| p.mechanical_power_w),
        Style::LineMarkers,
    ));
    svg(&power, &dir.join("power_books_default"))?;
    Ok(())
}

fn print_summary(s: &Study) {
    let d = &s.default;
    println!(
        "default: stall {:.4e} N, no-load {:.4} m/s, P_max {:.4e} W, efficiency {:.4}, residual {:.1e}, steady {}",
        d.stall_thrust_n,
        d.no_load_speed_m_per_s,
        d.max_mechanical_power_w,
        d.max_efficiency,
        d.max_energy_residual,
        d.all_steady
    );
    for (name, rows, unit) in [
        ("amplitude", &s.amplitude_sweep, 1e9),
        ("preload", &s.preload_sweep, 1e3),
        ("diameter", &s.diameter_sweep, 1e3),
    ] {
        for r in rows {
            let x = &r.result;
            let stall_point = x.curve.first();
            println!(
                "{name} {:>7.2}: drives {} stall {:.4e} N ({:.3} μP) v0 {:.4} m/s P_max {:.3e} W eff {:.3} δ0/A_n {:.3} C/A_t {:.3} ka {:.3} contact {:.3} thrust(0+) {:.4e} N",
                r.value * unit,
                x.drives,
                x.stall_thrust_n,
                x.stall_thrust_n / x.friction_limit_n,
                x.no_load_speed_m_per_s,
                x.max_mechanical_power_w,
                x.max_efficiency,
                x.static_contact.approach_over_amplitude,
                x.static_contact.full_slip_over_tangential_amplitude,
                x.static_contact.contact_wavenumber,
                stall_point.map_or(f64::NAN, |p| p.contact_fraction),
                x.zero_speed_thrust_n,
            );
        }
    }
    for (name, rows) in [
        ("steps", &s.step_refinement),
        ("springs", &s.spring_refinement),
    ] {
        for r in rows {
            println!(
                "{name} {:>5}: v0 {:.8} m/s stall {:.8e} N",
                r.level, r.no_load_speed_m_per_s, r.stall_thrust_n
            );
        }
    }
}
