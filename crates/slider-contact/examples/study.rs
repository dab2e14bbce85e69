//! The whole-slider study of validation/whole-slider/README.md: η, contact fraction and load
//! sharing of the default slider (rigid back, Johnson near field) at 10, 40 and 100 N against
//! post-height scatter σ (5 seeds each), tilt and bow; post-force maps at θ₀ = 0 as CSV.
//!
//! The three preload mechanisms (rigid back, pressure on a free back, ball at a point) with and
//! without scatter go to `mechanisms.json` and their maps; `--mechanisms` runs only that part.
//!
//! `cargo run -p slider-contact --profile test --example study -- validation/whole-slider/results [--mechanisms]`

use std::io::Write;
use std::path::{Path, PathBuf};

use charts::{CategoryMap, Chart, Series, Style, write_category_map, write_chart};
use serde_json::json;
use slider_contact::{Imperfections, Mechanism, SliderModel, SliderParams, SliderReport};

const PRELOADS_N: [f64; 3] = [10.0, 40.0, 100.0];
const SEEDS: u64 = 5;

fn analyse(imperfections: Imperfections) -> anyhow::Result<Vec<SliderReport>> {
    let model = SliderModel::build(&SliderParams {
        imperfections,
        ..SliderParams::default()
    })?;
    PRELOADS_N.iter().map(|&p| Ok(model.analyse(p)?)).collect()
}

fn summary(reports: &[SliderReport]) -> serde_json::Value {
    json!(
        reports
            .iter()
            .map(|r| json!({
                "preload_n": r.preload_n,
                "effective_contact_ratio": r.effective_contact_ratio,
                "contact_fraction": r.contact_fraction,
                "load_sharing": r.load_sharing,
                "complementarity_residual": r.complementarity_residual,
                "iterations": r.iterations,
                "contact_s": r.contact_s,
            }))
            .collect::<Vec<_>>()
    )
}

fn mean_sd(v: &[f64]) -> (f64, f64) {
    let m = v.iter().sum::<f64>() / v.len() as f64;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len().max(2) - 1) as f64;
    (m, var.sqrt())
}

/// Force classes of the map, in units of the mean post force P/N.
const FORCE_CLASSES: [(f64, &str); 6] = [
    (0.0, "lifted off"),
    (0.5, "< 0.5 P/N"),
    (1.0, "0.5–1 P/N"),
    (2.0, "1–2 P/N"),
    (4.0, "2–4 P/N"),
    (f64::INFINITY, "> 4 P/N"),
];

fn write_map(dir: &Path, name: &str, r: &SliderReport) -> anyhow::Result<()> {
    let mean = r.preload_n / r.post_forces_n.len() as f64;
    let class = |f: f64| {
        if f <= 0.0 {
            0
        } else {
            FORCE_CLASSES
                .iter()
                .position(|(hi, _)| f / mean < *hi)
                .unwrap_or(5)
        }
    };
    let pitch_mm = 0.04;
    let map = CategoryMap {
        title: format!("post forces at θ₀ = 0, P = {} N ({name})", r.preload_n),
        x_label: "x (mm), wave direction".into(),
        y_label: "y (mm)".into(),
        xs: (0..r.posts_x)
            .map(|i| (i as f64 + 0.5) * pitch_mm)
            .collect(),
        ys: (0..r.posts_y)
            .map(|j| (j as f64 + 0.5) * pitch_mm)
            .collect(),
        cells: (0..r.posts_y)
            .map(|j| {
                (0..r.posts_x)
                    .map(|i| class(r.post_forces_n[i * r.posts_y + j]))
                    .collect()
            })
            .collect(),
        categories: FORCE_CLASSES.iter().map(|(_, n)| n.to_string()).collect(),
        ..CategoryMap::default()
    };
    let stem = dir.join(format!("post_force_map_{name}"));
    write_category_map(&map, &stem)?;
    // The 10 000-cell SVG is ≈ 0.9 MB; the PNG carries the map.
    std::fs::remove_file(stem.with_extension("svg"))?;
    let mut f = std::fs::File::create(dir.join(format!("post_forces_{name}.csv")))?;
    writeln!(f, "row,column,force_n")?;
    for i in 0..r.posts_x {
        for j in 0..r.posts_y {
            writeln!(f, "{j},{i},{:e}", r.post_forces_n[i * r.posts_y + j])?;
        }
    }
    Ok(())
}

/// The preload mechanisms of the default slider (σ = 0 and 5 nm, seed 1): η, contact fraction,
/// load sharing at 10/40/100 N, the flat-stator load sharing at 40 N, maps at 40 N.
fn mechanisms(dir: &Path) -> anyhow::Result<()> {
    let cases = [
        ("rigid", "rigid", Mechanism::Rigid),
        ("pressure", "pressure", Mechanism::Pressure),
        (
            "point at the centre",
            "point_centre",
            Mechanism::Point {
                x_m: 2.5e-3,
                y_m: 2.5e-3,
            },
        ),
        (
            "point at (1.5, 2.5) mm",
            "point_x1p5mm",
            Mechanism::Point {
                x_m: 1.5e-3,
                y_m: 2.5e-3,
            },
        ),
    ];
    let mut out = Vec::new();
    println!(
        "\n| mechanism | σ (nm) | P (N) | η | contact fraction | load sharing | fit misfit | CG iterations (4 phases) | contact solve (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for (name, tag, mechanism) in cases {
        for sigma_nm in [0.0, 5.0] {
            let start = std::time::Instant::now();
            let model = SliderModel::build(&SliderParams {
                mechanism,
                imperfections: Imperfections {
                    height_scatter_m: sigma_nm * 1e-9,
                    scatter_seed: 1,
                    ..Imperfections::default()
                },
                ..SliderParams::default()
            })?;
            let build_s = start.elapsed().as_secs_f64();
            let reports: Vec<SliderReport> = PRELOADS_N
                .iter()
                .map(|&p| model.analyse(p))
                .collect::<Result<_, _>>()?;
            for r in &reports {
                println!(
                    "| {name} | {sigma_nm} | {} | {:.4} | {:.3} | {:.3} | {:.3} | {} | {:.2} |",
                    r.preload_n,
                    r.effective_contact_ratio.unwrap_or(f64::NAN),
                    r.contact_fraction,
                    r.load_sharing,
                    r.eta_fit.relative_rms_residual,
                    r.iterations,
                    r.contact_s
                );
            }
            let flat = model.solve_phase(40.0, None)?;
            let f = &flat.force_n;
            let (lo, hi) = f
                .iter()
                .fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
            println!(
                "  flat stator 40 N: load sharing {:.3}, post force min/max {lo:.3e} / {hi:.3e} N, contact fraction {:.3}; build {build_s:.2} s",
                flat.load_sharing, flat.contact_fraction
            );
            if sigma_nm == 0.0 && name != "rigid" {
                write_map(dir, &format!("40n_{tag}"), &reports[1])?;
            }
            out.push(json!({
                "mechanism": name, "height_scatter_m": sigma_nm * 1e-9, "scatter_seed": 1,
                "results": summary(&reports),
                "eta_relative_rms_residual": reports.iter().map(|r| r.eta_fit.relative_rms_residual).collect::<Vec<_>>(),
                "flat_stator_40n": {"load_sharing": flat.load_sharing, "contact_fraction": flat.contact_fraction,
                    "post_force_min_n": lo, "post_force_max_n": hi},
                "build_s": build_s,
            }));
        }
    }
    std::fs::write(
        dir.join("mechanisms.json"),
        serde_json::to_string_pretty(&json!({
            "model": "slider: Johnson near field, 4 phases; pressure/point: free back (Kirchhoff plate of the 5 × 5 × 0.5 mm outline)",
            "cases": out,
        }))?,
    )?;
    Ok(())
}

fn main() -> anyhow::Result<()> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "results".into()));
    std::fs::create_dir_all(&dir)?;
    mechanisms(&dir)?;
    if std::env::args().any(|a| a == "--mechanisms") {
        return Ok(());
    }
    let mut out = serde_json::Map::new();
    let mut scatter = Vec::new();
    println!("| σ (nm) | P (N) | η mean ± sd | contact fraction | load sharing |");
    println!("|---|---|---|---|---|");
    for sigma_nm in [0.0, 1.0, 2.0, 5.0, 10.0] {
        let seeds = if sigma_nm == 0.0 { 1 } else { SEEDS };
        let runs: Vec<Vec<SliderReport>> = (1..=seeds)
            .map(|seed| {
                analyse(Imperfections {
                    height_scatter_m: sigma_nm * 1e-9,
                    scatter_seed: seed,
                    ..Imperfections::default()
                })
            })
            .collect::<anyhow::Result<_>>()?;
        if sigma_nm == 0.0 || sigma_nm == 5.0 {
            write_map(&dir, &format!("40n_sigma{sigma_nm}nm"), &runs[0][1])?;
        }
        for (k, p) in PRELOADS_N.iter().enumerate() {
            let col = |f: &dyn Fn(&SliderReport) -> f64| -> Vec<f64> {
                runs.iter().map(|r| f(&r[k])).collect()
            };
            let (eta, eta_sd) = mean_sd(&col(&|r| r.effective_contact_ratio.unwrap_or(f64::NAN)));
            let (cf, cf_sd) = mean_sd(&col(&|r| r.contact_fraction));
            let (ls, ls_sd) = mean_sd(&col(&|r| r.load_sharing));
            let (misfit, _) = mean_sd(&col(&|r| r.eta_fit.relative_rms_residual));
            println!(
                "| {sigma_nm} | {p} | {eta:.4} ± {eta_sd:.4} | {cf:.3} ± {cf_sd:.3} | {ls:.3} ± {ls_sd:.3} |"
            );
            scatter.push(json!({
                "height_scatter_m": sigma_nm * 1e-9, "seeds": seeds, "preload_n": p,
                "eta_mean": eta, "eta_sd": eta_sd, "contact_fraction_mean": cf,
                "contact_fraction_sd": cf_sd, "load_sharing_mean": ls, "load_sharing_sd": ls_sd,
                "eta_relative_rms_residual_mean": misfit,
            }));
        }
    }
    let mut chart = Chart::new(
        "η of the default slider against post-height scatter (mean ± sd over 5 seeds)",
        "σ (nm)",
        "η",
    );
    for p in PRELOADS_N {
        let rows: Vec<&serde_json::Value> =
            scatter.iter().filter(|v| v["preload_n"] == p).collect();
        let pts = |k: f64| -> Vec<(f64, f64)> {
            rows.iter()
                .map(|v| {
                    let sd = v["eta_sd"].as_f64().unwrap_or(0.0);
                    (
                        v["height_scatter_m"].as_f64().unwrap() * 1e9,
                        v["eta_mean"].as_f64().unwrap() + k * sd,
                    )
                })
                .collect()
        };
        chart
            .series
            .push(Series::new(format!("{p} N"), pts(0.0), Style::LineMarkers));
        chart
            .series
            .push(Series::new(format!("{p} N ± sd"), pts(1.0), Style::Dashed));
        chart
            .series
            .push(Series::new(String::new(), pts(-1.0), Style::Dashed));
    }
    write_chart(&chart, &dir.join("eta_vs_scatter"))?;
    out.insert("height_scatter".into(), json!(scatter));
    let mut shapes = Vec::new();
    println!("\n| shape | P (N) | η | contact fraction | load sharing |");
    println!("|---|---|---|---|---|");
    let cases: [(&str, Imperfections); 7] = [
        (
            "tilt_x 20 nm",
            Imperfections {
                tilt_x_m: 20e-9,
                ..Default::default()
            },
        ),
        (
            "tilt_x 100 nm",
            Imperfections {
                tilt_x_m: 100e-9,
                ..Default::default()
            },
        ),
        (
            "tilt_y 20 nm",
            Imperfections {
                tilt_y_m: 20e-9,
                ..Default::default()
            },
        ),
        (
            "tilt_y 100 nm",
            Imperfections {
                tilt_y_m: 100e-9,
                ..Default::default()
            },
        ),
        (
            "bow +10 nm",
            Imperfections {
                bow_m: 10e-9,
                ..Default::default()
            },
        ),
        (
            "bow +50 nm",
            Imperfections {
                bow_m: 50e-9,
                ..Default::default()
            },
        ),
        (
            "bow −10 nm",
            Imperfections {
                bow_m: -10e-9,
                ..Default::default()
            },
        ),
    ];
    for (name, imp) in cases {
        let reports = analyse(imp)?;
        for r in &reports {
            println!(
                "| {name} | {} | {:.4} | {:.3} | {:.3} | {:.3} |",
                r.preload_n,
                r.effective_contact_ratio.unwrap_or(f64::NAN),
                r.contact_fraction,
                r.load_sharing,
                r.eta_fit.relative_rms_residual
            );
        }
        if name == "tilt_y 100 nm" {
            write_map(&dir, "40n_tilt_y100nm", &reports[1])?;
        }
        shapes.push(json!({"case": name, "results": summary(&reports)}));
    }
    out.insert("tilt_and_bow".into(), json!(shapes));
    out.insert(
        "model".into(),
        json!("slider: rigid back, Johnson near field, 4 phases"),
    );
    std::fs::write(dir.join("study.json"), serde_json::to_string_pretty(&out)?)?;
    Ok(())
}
