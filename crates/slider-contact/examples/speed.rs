//! The whole-slider stage's speed, one command: for each preload mechanism
//! (rigid back, ball at the centre, pressure), the default slider (100 × 100 posts, 4 phases,
//! one preload of 40 N): operator build, the 4 phases + η, wall and CPU time (user + sys of the
//! process, all threads), CG iterations; the cost of an extra phase (1 → 8 phases); and one phase
//! against the number of posts (1 024 → 40 000 at the default pitch and per-post load, 4 mN;
//! margins 0.5 mm) with the fitted exponent of the growth. Prints the load average first: on a
//! shared machine the wall times are upper bounds, the CPU times are what the code costs.
//!
//! `cargo run -p slider-contact --profile test --example speed [max_posts_per_side]`
//! (default 200: the 40 000-post pressure phase takes tens of seconds of CPU).

use std::time::Instant;

use slider_contact::{Mechanism, SliderModel, SliderParams};

/// CPU seconds (user + sys) of this process so far, from /proc/self/stat (clock ticks of 10 ms).
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name (which may hold spaces) start at ") ".
    let rest = stat.rsplit_once(") ").map_or("", |(_, r)| r);
    let f: Vec<f64> = rest
        .split_whitespace()
        .map(|x| x.parse().unwrap_or(0.0))
        .collect();
    // utime and stime are fields 14 and 15 of stat, i.e. 11 and 12 after the state field.
    f.get(11)
        .zip(f.get(12))
        .map_or(f64::NAN, |(u, s)| (u + s) / 100.0)
}

/// Wall and CPU seconds of `f`.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64, f64) {
    let (w, c) = (Instant::now(), cpu_s());
    let out = f();
    (out, w.elapsed().as_secs_f64(), cpu_s() - c)
}

fn mechanisms() -> [(&'static str, Mechanism); 3] {
    [
        ("rigid", Mechanism::Rigid),
        (
            "ball",
            Mechanism::Point {
                x_m: 2.5e-3,
                y_m: 2.5e-3,
            },
        ),
        ("pressure", Mechanism::Pressure),
    ]
}

/// A square slider of side² posts at the default pitch and per-post load, 0.5 mm margins.
fn lattice(side: usize, mechanism: Mechanism) -> SliderParams {
    let l = side as f64 * 40e-6 + 1e-3;
    let w = l;
    let mechanism = match mechanism {
        Mechanism::Point { .. } => Mechanism::Point {
            x_m: 0.5 * l,
            y_m: 0.5 * w,
        },
        other => other,
    };
    SliderParams {
        posts_x: side,
        posts_y: side,
        slider_length_m: l,
        slider_width_m: w,
        preload_n: 4e-3 * (side * side) as f64,
        mechanism,
        ..SliderParams::default()
    }
}

fn main() -> anyhow::Result<()> {
    let max_side: usize = std::env::args().nth(1).map_or(Ok(200), |s| s.parse())?;
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("load average: {}", load.trim());
    println!(
        "\n## Default slider, 40 N, tolerance {:e}",
        slider_contact::DEFAULT_TOLERANCE
    );
    println!(
        "| mechanism | build wall / CPU | 4 phases + η wall / CPU | iterations per phase | η | 1 phase wall / CPU | 8 phases wall / CPU | per extra phase (CPU) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (name, mechanism) in mechanisms() {
        let mut params = SliderParams {
            mechanism,
            ..SliderParams::default()
        };
        let (model, bw, bc) = timed(|| SliderModel::build(&params));
        let model = model?;
        let (r, sw, sc) = timed(|| model.analyse(40.0));
        let r = r?;
        let its: Vec<usize> = r.snapshots.iter().map(|s| s.iterations).collect();
        let mut per_phases = Vec::new();
        for phases in [1, 8] {
            params.phases = phases;
            let m = SliderModel::build(&params)?;
            let (r, w, c) = timed(|| m.analyse(40.0));
            r?;
            per_phases.push((w, c));
        }
        let extra = (per_phases[1].1 - per_phases[0].1) / 7.0;
        println!(
            "| {name} | {bw:.2} / {bc:.2} s | **{sw:.2}** / {sc:.2} s | {its:?} | {:.5} | {:.2} / {:.2} s | {:.2} / {:.2} s | {extra:.3} s |",
            r.effective_contact_ratio.unwrap_or(f64::NAN),
            per_phases[0].0,
            per_phases[0].1,
            per_phases[1].0,
            per_phases[1].1,
        );
    }
    println!("\n## One phase against the number of posts (θ₀ = 0, 4 mN per post)");
    println!("| mechanism | posts | wall / CPU | iterations |");
    println!("|---|---|---|---|");
    for (name, mechanism) in mechanisms() {
        let mut points = Vec::new();
        for side in [32, 71, 100, 141, 200]
            .into_iter()
            .filter(|&s| s <= max_side)
        {
            let params = lattice(side, mechanism);
            let model = SliderModel::build(&params)?;
            // The fastest of a few repeats (the least disturbed by other processes).
            let repeats = if side * side <= 10_000 { 3 } else { 1 };
            let (mut best, mut cpu, mut iterations) = (f64::INFINITY, 0.0, 0);
            for _ in 0..repeats {
                let (s, w, c) = timed(|| model.solve_phase(params.preload_n, Some(0.0)));
                iterations = s?.iterations;
                best = best.min(w);
                cpu += c / repeats as f64;
            }
            println!(
                "| {name} | {} | {best:.3} / {cpu:.2} s | {iterations} |",
                side * side
            );
            points.push(((side * side) as f64, best));
        }
        if points.len() >= 2 {
            // Least-squares slope of log(wall) against log(N).
            let m = points.len() as f64;
            let (sx, sy) = points
                .iter()
                .fold((0.0, 0.0), |(a, b), p| (a + p.0.ln(), b + p.1.ln()));
            let (mx, my) = (sx / m, sy / m);
            let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), p| {
                (
                    a + (p.0.ln() - mx) * (p.1.ln() - my),
                    b + (p.0.ln() - mx).powi(2),
                )
            });
            println!(
                "| {name} | exponent (wall, least squares, {:.0} → {:.0} posts) | N^{:.2} | |",
                points[0].0,
                points[points.len() - 1].0,
                num / den
            );
        }
    }
    Ok(())
}
