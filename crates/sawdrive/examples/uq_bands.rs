//! The band study of validation/whole-slider/bands: `sawdrive uq`'s bands of the lumped model
//! (the period average on each sample's whole-slider η) and of the whole slider's coupled model
//! (every post of each sample's slider) on the SAME samples (same seed, same draws), for
//! post-height scatter σ = 0, 2, 5, 10 nm. Writes `bands.csv` (one row per σ and model: P5,
//! P50, P95 and mean of the stall thrust and the no-load speed, the samples, the wall time)
//! and `bands.svg` (P5–P95 of the stall thrust and the no-load speed against σ, both models).
//!
//! ```sh
//! cargo run --release -p sawdrive --example uq_bands -- --side 20 --samples 20 --out validation/whole-slider/bands
//! ```
//!
//! `--side n`: n × n posts of the default post cell (20 µm at 40 µm) on a body 20 µm wider than
//! the array, preload 40 N · n²/10 000 (the default slider's 4 mN a post); `--sigmas 0,2,5,10`;
//! `--seed`. Model settings: the scene's defaults (64 steps per period; the coupled study's
//! points at stall, 0.55, 0.75, 0.92 v₀ and v₀) on the constant-amplitude wave
//! (`wave.attenuation = "off"`) for both models: the comparison isolates the lumped model's
//! error from the wave model's.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use charts::{Chart, Series, Style, write_chart};
use design::ModelFidelity as Fidelity;
use design::scatter::ScatterSpec;
use design::uq::{UqOptions, UqReport, run_uq};
use sawdrive::pipeline::evaluate::SceneEvaluator;
use sawdrive::scene::load_scene;

struct Args {
    side: u32,
    samples: usize,
    seed: u64,
    sigmas_nm: Vec<f64>,
    out: PathBuf,
}

fn args() -> Args {
    let mut a = Args {
        side: 20,
        samples: 20,
        seed: 1,
        sigmas_nm: vec![0.0, 2.0, 5.0, 10.0],
        out: PathBuf::from("validation/whole-slider/bands"),
    };
    let list: Vec<String> = std::env::args().skip(1).collect();
    for pair in list.chunks(2) {
        let value = pair.get(1).cloned().unwrap_or_default();
        match pair[0].as_str() {
            "--side" => a.side = value.parse().expect("--side: posts per side"),
            "--samples" => a.samples = value.parse().expect("--samples: a count"),
            "--seed" => a.seed = value.parse().expect("--seed: an integer"),
            "--sigmas" => {
                a.sigmas_nm = value
                    .split(',')
                    .map(|s| s.parse().expect("--sigmas: nm, comma separated"))
                    .collect()
            }
            "--out" => a.out = PathBuf::from(value),
            other => panic!("unknown option {other}"),
        }
    }
    a
}

/// One uq run of the study: its report and wall time (s).
fn run(a: &Args, dynamics: &str, sigma_nm: f64, dir: &std::path::Path) -> (UqReport, f64) {
    let n = a.side;
    let pitch_um = 40.0;
    let sets = vec![
        format!("posts.count={n}x{n}"),
        format!("posts.array={}um", f64::from(n) * pitch_um),
        format!("slider.length={}um", f64::from(n) * pitch_um + 20.0),
        format!("slider.width={}um", f64::from(n) * pitch_um + 20.0),
        format!("load.preload={}N", 40.0 * f64::from(n * n) / 10_000.0),
        "static.model=slider".into(),
        // Both models on the same, constant-amplitude wave: the lumped model's error alone.
        "wave.attenuation=off".into(),
        format!("model.dynamics={dynamics}"),
    ];
    let scene = load_scene(None, &sets).expect("the study's scene");
    let scatter = ScatterSpec {
        height_scatter_m: sigma_nm * 1e-9,
        ..ScatterSpec::default()
    };
    let options = UqOptions {
        samples: if sigma_nm == 0.0 { 1 } else { a.samples },
        seed: a.seed,
        out_dir: dir.to_owned(),
        fidelity: Fidelity::Slider,
        write_files: false,
    };
    let started = Instant::now();
    let (report, _) = run_uq(&SceneEvaluator, &scene, &scatter, &options).expect("uq runs");
    (report, started.elapsed().as_secs_f64())
}

fn main() {
    let a = args();
    std::fs::create_dir_all(&a.out).expect("output folder");
    let work = tempfile::tempdir().expect("a scratch folder");
    let mut csv = String::from(
        "posts_per_side,sigma_nm,model,samples,coupled_samples,stall_p5_n,stall_p50_n,stall_p95_n,\
         stall_mean_n,no_load_p5_m_per_s,no_load_p50_m_per_s,no_load_p95_m_per_s,\
         no_load_mean_m_per_s,wall_s\n",
    );
    let mut chart_points: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for &sigma in &a.sigmas_nm {
        for (model, dynamics) in [("lumped", "periodic-average"), ("coupled", "coupled")] {
            let (r, wall) = run(&a, dynamics, sigma, work.path());
            let (s, v) = (r.stall_thrust_n, r.no_load_speed_m_per_s);
            writeln!(
                csv,
                "{},{sigma},{model},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{wall:.1}",
                a.side,
                r.samples,
                r.coupled_samples,
                s.p5,
                s.p50,
                s.p95,
                s.mean,
                v.p5,
                v.p50,
                v.p95,
                v.mean
            )
            .expect("a CSV row");
            eprintln!(
                "σ = {sigma} nm, {model}: stall {:.5}/{:.5}/{:.5} N, no-load {:.5}/{:.5}/{:.5} m/s, {wall:.1} s",
                s.p5, s.p50, s.p95, v.p5, v.p50, v.p95
            );
            for (name, value) in [
                ("stall P5", s.p5),
                ("stall P50", s.p50),
                ("stall P95", s.p95),
            ] {
                let key = format!("{model} {name}");
                match chart_points.iter_mut().find(|c| c.0 == key) {
                    Some(c) => c.1.push((sigma, value)),
                    None => chart_points.push((key, vec![(sigma, value)])),
                }
            }
        }
    }
    std::fs::write(a.out.join("bands.csv"), &csv).expect("bands.csv");
    let mut chart = Chart::new(
        format!(
            "stall thrust bands (P5, P50, P95) of {n} × {n} posts: lumped vs coupled, same samples",
            n = a.side
        ),
        "σ of the post heights (nm)",
        "stall thrust (N)",
    );
    for (name, points) in chart_points {
        let style = match (name.starts_with("coupled"), name.ends_with("P50")) {
            (true, true) => Style::Line,
            (true, false) => Style::Dashed,
            (false, _) => Style::Markers,
        };
        chart.series.push(Series::new(name, points, style));
    }
    write_chart(&chart, &a.out.join("bands")).expect("bands chart");
    print!("{csv}");
}
