//! The `whole-slider` case: static contact of every post of the slider (`slider-contact`'s
//! two-scale lattice model, validation/whole-slider/README.md) and its checks.
//!
//! Model: the compliance of n × n posts at 40 µm pitch is the lattice operator C = stator
//! half-space (rigid-disk self and mutual terms) + slider body (a layer bonded to a rigid back,
//! or a Kirchhoff plate for a free back), applied by FFT; the unilateral, frictionless contact
//! under the preload P is solved by Polonsky–Keer's constrained CG, and η is the static stage's
//! fit of independent posts to the frozen-wave post forces (docs/physics.md §6). Checks:
//!
//! * the FFT operator against the direct pairwise sum Σ_j C(r_ij) f_j of the same kernel, for a
//!   random force field (the convolution's padding and indexing), to [`OPERATOR_TOLERANCE`];
//! * the mechanisms' balance: Σ f = P (rigid back, pressure and ball on a free back) to
//!   [`BALANCE_TOLERANCE`], and for the free back the moments about the load point,
//!   |Σ f ξ|/P and |Σ f η|/P (arms in half array lengths), below the same bound;
//! * trends of the README: η of the ideal slider falls with preload; σ = 5 nm of post-height
//!   scatter raises η at 40 N by ≥ [`SCATTER_RAISES_ETA`] while removing contacts; a flat stator
//!   under a rigid back loads the edge frame of posts ≥ [`EDGE_LOAD_RATIO`] × the interior mean;
//! * full level only (the default 100 × 100 slider): η at 10 / 40 / 100 N and the flat-stator
//!   load sharing against the committed `results/study.json` and `results/mechanisms.json`
//!   (compiled in) to [`COMMITTED_TOLERANCE`] (a re-run reproduces them within 1e-6), and the
//!   ideal slider's η against the default strip FEM (`validation/static-contact/results/
//!   strip.json`) within [`STRIP_FEM_TOLERANCE`]: the Johnson near field the study uses
//!   stiffens η by +6.3 / +3.4 / +1.8 % (README, strip comparison).
//!
//! Levels (preloads scaled by n²/10 000, so the mean post force is the default's at 10, 40 and
//! 100 N): smoke 20 × 20 posts, σ ∈ {0, 5} nm with 1 seed, every mechanism at σ = 0; quick
//! 40 × 40, σ ∈ {0, 5} nm with 2 seeds, one tilt and one bow, every mechanism at σ = 0 and 5 nm;
//! full the study of the README (100 × 100, σ ∈ {0, 1, 2, 5, 10} nm with 5 seeds, 7 tilts and
//! bows, every mechanism at σ = 0 and 5 nm, post-force maps). At every level, the band study's
//! claims on its committed CSV ([`super::whole_slider_bands`]). Valid for the lattice model's range
//! (docs/physics.md §6: rigid-disk tips, quasi-static, frictionless normal contact).

use std::io::Write as _;
use std::path::Path;

use charts::{CategoryMap, Chart, Series, Style, write_category_map, write_chart};
use serde_json::json;
use slider_contact::{
    ComplianceOperator, Imperfections, LatticeKernel, LatticeOperator, Mechanism, SliderModel,
    SliderParams, SliderReport,
};

use super::{Check, Level};
use crate::error::ValidationError;

const CASE: &str = "whole-slider";

/// Largest max|C f (FFT) − C f (pairwise sum)| / max|C f|. 1e-10.
pub const OPERATOR_TOLERANCE: f64 = 1e-10;
/// Largest |Σ f / P − 1| and |moment| / P of the balanced solvers. 1e-9.
pub const BALANCE_TOLERANCE: f64 = 1e-9;
/// Smallest η(σ = 5 nm) / η(σ = 0) at 40 N (measured 1.36 on the default slider). 1.05.
pub const SCATTER_RAISES_ETA: f64 = 1.05;
/// Smallest mean force of the edge frame of posts over the interior mean, flat stator, rigid
/// back (corners 24.9 mN against 2.41 mN interior on the default slider). 1.5.
pub const EDGE_LOAD_RATIO: f64 = 1.5;
/// Relative tolerance of the full level against the committed study. 1e-5.
pub const COMMITTED_TOLERANCE: f64 = 1e-5;
/// Relative tolerance of η (Johnson near field) against the default strip FEM. 0.07.
pub const STRIP_FEM_TOLERANCE: f64 = 0.07;

/// The default preloads (N); scaled by n²/10 000 on smaller lattices.
pub const PRELOADS_N: [f64; 3] = [10.0, 40.0, 100.0];

const STUDY_JSON: &str = include_str!("../../../../validation/whole-slider/results/study.json");
const MECHANISMS_JSON: &str =
    include_str!("../../../../validation/whole-slider/results/mechanisms.json");
const STRIP_JSON: &str = include_str!("../../../../validation/static-contact/results/strip.json");

/// What a level runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Setup {
    /// Posts per side.
    pub posts_per_side: usize,
    /// Scatter σ (nm), each with `seeds` seeds (σ = 0: one).
    pub scatter_nm: Vec<f64>,
    /// Seeds per σ > 0.
    pub seeds: u64,
    /// Tilt and bow cases.
    pub shapes: Vec<(&'static str, Imperfections)>,
    /// Scatter σ (nm) of the mechanisms' runs.
    pub mechanism_scatter_nm: Vec<f64>,
    /// Write the post-force maps (PNG; the 10 000-cell SVG is ≈ 0.9 MB).
    pub maps: bool,
}

fn shape(tilt_x_m: f64, tilt_y_m: f64, bow_m: f64) -> Imperfections {
    Imperfections {
        tilt_x_m,
        tilt_y_m,
        bow_m,
        ..Imperfections::default()
    }
}

/// The setup of `level`.
pub fn setup(level: Level) -> Setup {
    match level {
        Level::Smoke => Setup {
            posts_per_side: 20,
            scatter_nm: vec![0.0, 5.0],
            seeds: 1,
            shapes: Vec::new(),
            mechanism_scatter_nm: vec![0.0],
            maps: false,
        },
        Level::Quick => Setup {
            posts_per_side: 40,
            scatter_nm: vec![0.0, 5.0],
            seeds: 2,
            shapes: vec![
                ("tilt_x 20 nm", shape(20e-9, 0.0, 0.0)),
                ("bow +10 nm", shape(0.0, 0.0, 10e-9)),
            ],
            mechanism_scatter_nm: vec![0.0, 5.0],
            maps: false,
        },
        Level::Full => Setup {
            posts_per_side: 100,
            scatter_nm: vec![0.0, 1.0, 2.0, 5.0, 10.0],
            seeds: 5,
            shapes: vec![
                ("tilt_x 20 nm", shape(20e-9, 0.0, 0.0)),
                ("tilt_x 100 nm", shape(100e-9, 0.0, 0.0)),
                ("tilt_y 20 nm", shape(0.0, 20e-9, 0.0)),
                ("tilt_y 100 nm", shape(0.0, 100e-9, 0.0)),
                ("bow +10 nm", shape(0.0, 0.0, 10e-9)),
                ("bow +50 nm", shape(0.0, 0.0, 50e-9)),
                ("bow −10 nm", shape(0.0, 0.0, -10e-9)),
            ],
            mechanism_scatter_nm: vec![0.0, 5.0],
            maps: true,
        },
    }
}

fn failed(context: &str, e: impl std::fmt::Display) -> ValidationError {
    ValidationError::InvalidOption {
        option: "whole-slider case",
        value: format!("{context}: {e}"),
        reason: "the slider-contact model failed",
    }
}

fn io(path: &Path, source: std::io::Error) -> ValidationError {
    ValidationError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The default slider's parameters on an n × n lattice (the default's 0.5 mm margins).
pub fn params(n: usize, imperfections: Imperfections, mechanism: Mechanism) -> SliderParams {
    let base = SliderParams::default();
    let margin = base.slider_length_m - base.posts_x as f64 * base.post_pitch_m;
    let side = n as f64 * base.post_pitch_m + margin;
    SliderParams {
        posts_x: n,
        posts_y: n,
        slider_length_m: side,
        slider_width_m: side,
        imperfections,
        mechanism,
        ..base
    }
}

/// The preloads of an n × n lattice (N): the default's mean post force.
pub fn preloads_n(n: usize) -> [f64; 3] {
    PRELOADS_N.map(|p| p * (n * n) as f64 / 1e4)
}

fn analyse(n: usize, imperfections: Imperfections) -> Result<Vec<SliderReport>, ValidationError> {
    let model = SliderModel::build(&params(n, imperfections, Mechanism::Rigid))
        .map_err(|e| failed("building the slider", e))?;
    preloads_n(n)
        .iter()
        .map(|&p| model.analyse(p).map_err(|e| failed("analysing", e)))
        .collect()
}

fn eta(r: &SliderReport) -> f64 {
    r.effective_contact_ratio.unwrap_or(f64::NAN)
}

/// The FFT operator against the direct pairwise sum of its kernel for a seeded random force
/// field: max|Δu| / max|u|.
pub fn operator_mismatch(n: usize) -> Result<f64, ValidationError> {
    let spec = params(n, Imperfections::default(), Mechanism::Rigid).operator_spec();
    let kernel = LatticeKernel::new(&spec).map_err(|e| failed("lattice kernel", e))?;
    let op = LatticeOperator::new(&spec).map_err(|e| failed("lattice operator", e))?;
    let g = spec.geometry;
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let force: Vec<f64> = (0..g.len())
        .map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect();
    let mut fft = vec![0.0; g.len()];
    op.apply(&force, &mut fft);
    let (nx, ny) = (g.posts_x as i64, g.posts_y as i64);
    let width = (2 * ny - 1) as usize;
    let offsets: Vec<f64> = (-(nx - 1)..nx)
        .flat_map(|di| (-(ny - 1)..ny).map(move |dj| (di, dj)))
        .map(|(di, dj)| kernel.at_offset(di, dj))
        .collect();
    let mut worst: f64 = 0.0;
    let mut largest: f64 = 0.0;
    for i in 0..g.posts_x {
        for j in 0..g.posts_y {
            let mut sum = 0.0;
            for k in 0..g.posts_x {
                let row = (i as i64 - k as i64 + nx - 1) as usize * width;
                for l in 0..g.posts_y {
                    sum += offsets[row + (j as i64 - l as i64 + ny - 1) as usize]
                        * force[g.index(k, l)];
                }
            }
            worst = worst.max((fft[g.index(i, j)] - sum).abs());
            largest = largest.max(sum.abs());
        }
    }
    Ok(worst / largest)
}

/// The mechanisms of an n × n slider: (name, tag, mechanism).
fn mechanisms(n: usize) -> Vec<(String, &'static str, Mechanism)> {
    let side = params(n, Imperfections::default(), Mechanism::Rigid).slider_length_m;
    vec![
        ("rigid".into(), "rigid", Mechanism::Rigid),
        ("pressure".into(), "pressure", Mechanism::Pressure),
        (
            "point at the centre".into(),
            "point_centre",
            Mechanism::Point {
                x_m: 0.5 * side,
                y_m: 0.5 * side,
            },
        ),
        (
            format!("point at ({:.1}, {:.1}) mm", 0.3e3 * side, 0.5e3 * side),
            "point_off_centre",
            Mechanism::Point {
                x_m: 0.3 * side,
                y_m: 0.5 * side,
            },
        ),
    ]
}

/// Runs the case at `level`, writing `out/results/{study,mechanisms}.json` and
/// `out/figures/eta_vs_scatter.svg` (and at full the post-force maps).
pub fn run(level: Level, out: &Path) -> Result<Vec<Check>, ValidationError> {
    let s = setup(level);
    let n = s.posts_per_side;
    let (results, figures) = (out.join("results"), out.join("figures"));
    for dir in [&results, &figures] {
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    }
    let mut checks = Vec::new();
    let operator_n = n.min(60);
    checks.push(Check::at_most(
        CASE,
        format!(
            "lattice operator {operator_n} × {operator_n}: max|C f (FFT) − Σ_j C_ij f_j| / max|C f|"
        ),
        operator_mismatch(operator_n)?,
        OPERATOR_TOLERANCE,
        "direct pairwise sum of the same lattice kernel (slider-contact lattice module)",
    ));
    let mechanism_rows = run_mechanisms(&s, &figures, &mut checks)?;
    let (scatter, ideal, eta_scatter) = run_scatter(&s, &figures)?;
    let shapes = run_shapes(&s, &figures)?;
    write_json(
        &results.join("mechanisms.json"),
        &json!({
            "model": "slider: Johnson near field, 4 phases; pressure/point: free back (Kirchhoff plate of the outline)",
            "posts_per_side": n,
            "cases": mechanism_rows,
        }),
    )?;
    write_json(
        &results.join("study.json"),
        &json!({
            "model": "slider: rigid back, Johnson near field, 4 phases",
            "posts_per_side": n,
            "preloads_n": preloads_n(n),
            "height_scatter": scatter,
            "tilt_and_bow": shapes,
        }),
    )?;
    let labels = ["10 N", "40 N", "100 N"];
    let source = "validation/whole-slider/README.md, height scatter";
    for k in 0..2 {
        checks.push(Check::at_most(
            CASE,
            format!(
                "ideal slider {n} × {n}: η at {} over η at {} (η falls with preload)",
                labels[k + 1],
                labels[k]
            ),
            eta(&ideal[k + 1]) / eta(&ideal[k]),
            1.0,
            source,
        ));
    }
    let (eta0, eta5, cf0, cf5) = eta_scatter;
    checks.push(Check::at_least(
        CASE,
        format!("{n} × {n}, 40 N: η(σ = 5 nm) / η(σ = 0) (scatter raises η)"),
        eta5 / eta0,
        SCATTER_RAISES_ETA,
        source,
    ));
    checks.push(Check::at_most(
        CASE,
        format!(
            "{n} × {n}, 40 N: contact fraction at σ = 5 nm over σ = 0 (scatter removes contacts)"
        ),
        cf5 / cf0,
        1.0,
        source,
    ));
    if level == Level::Full {
        committed_checks(&ideal, &mechanism_rows, &mut checks)?;
    }
    // The lumped-against-coupled band study, from its committed CSV at every level.
    checks.extend(super::whole_slider_bands::checks()?);
    Ok(checks)
}

fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), ValidationError> {
    let text = serde_json::to_string_pretty(value).unwrap_or_default() + "\n";
    std::fs::write(path, text).map_err(|e| io(path, e))
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
                "eta_relative_rms_residual": r.eta_fit.relative_rms_residual,
                "complementarity_residual": r.complementarity_residual,
                "iterations": r.iterations,
            }))
            .collect::<Vec<_>>()
    )
}

/// Every mechanism at the setup's σ: balance checks on the 40 N-equivalent phase-0 snapshot,
/// the edge-load check on the rigid back's flat stator; one JSON row per (mechanism, σ).
fn run_mechanisms(
    s: &Setup,
    figures: &Path,
    checks: &mut Vec<Check>,
) -> Result<Vec<serde_json::Value>, ValidationError> {
    let n = s.posts_per_side;
    let preloads = preloads_n(n);
    let mut rows = Vec::new();
    for (name, tag, mechanism) in mechanisms(n) {
        for &sigma_nm in &s.mechanism_scatter_nm {
            let imperfections = Imperfections {
                height_scatter_m: sigma_nm * 1e-9,
                scatter_seed: 1,
                ..Imperfections::default()
            };
            let model = SliderModel::build(&params(n, imperfections, mechanism))
                .map_err(|e| failed(&name, e))?;
            let reports: Vec<SliderReport> = preloads
                .iter()
                .map(|&p| model.analyse(p).map_err(|e| failed(&name, e)))
                .collect::<Result<_, _>>()?;
            let flat = model
                .solve_phase(preloads[1], None)
                .map_err(|e| failed(&name, e))?;
            if sigma_nm == 0.0 {
                balance_checks(&model, &name, preloads[1], &reports[1], checks);
                if mechanism == Mechanism::Rigid {
                    checks.push(Check::at_least(
                        CASE,
                        format!("flat stator, rigid back, {n} × {n}: edge-frame mean post force over interior mean"),
                        edge_over_interior(&flat.force_n, n),
                        EDGE_LOAD_RATIO,
                        "validation/whole-slider/README.md, flat stator (edges loaded like a rigid punch)",
                    ));
                }
                if s.maps && mechanism != Mechanism::Rigid {
                    write_map(figures, &format!("40n_{tag}"), &reports[1])?;
                }
            }
            let (lo, hi) = flat
                .force_n
                .iter()
                .fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
            rows.push(json!({
                "mechanism": name, "height_scatter_m": sigma_nm * 1e-9, "scatter_seed": 1,
                "results": summary(&reports),
                "flat_stator_40n": {"load_sharing": flat.load_sharing,
                    "contact_fraction": flat.contact_fraction,
                    "post_force_min_n": lo, "post_force_max_n": hi},
            }));
        }
    }
    Ok(rows)
}

/// Σ f = P, and for a free back the moments about the load point.
fn balance_checks(
    model: &SliderModel,
    name: &str,
    preload_n: f64,
    report: &SliderReport,
    checks: &mut Vec<Check>,
) {
    let source =
        "force (and moment) balance of the constrained CG (slider-contact solver, balanced)";
    let forces = &report.snapshots[0].force_n;
    checks.push(Check::relative(
        CASE,
        format!("{name}: Σ post forces (N), phase 0, {preload_n:.3} N"),
        forces.iter().sum(),
        preload_n,
        BALANCE_TOLERANCE,
        source,
    ));
    if let Some(back) = &model.free_back {
        for (axis, pick) in [("x", 0usize), ("y", 1)] {
            let moment: f64 = forces
                .iter()
                .zip(&back.arms)
                .map(|(f, a)| f * if pick == 0 { a.0 } else { a.1 })
                .sum();
            checks.push(Check::at_most(
                CASE,
                format!("{name}: |moment about the load point| / P, arm along {axis}"),
                moment.abs() / preload_n,
                BALANCE_TOLERANCE,
                source,
            ));
        }
    }
}

/// Mean force of the outermost ring of posts over the mean of the others.
fn edge_over_interior(force_n: &[f64], n: usize) -> f64 {
    let (mut edge, mut inner) = ((0.0, 0usize), (0.0, 0usize));
    for i in 0..n {
        for j in 0..n {
            let f = force_n[i * n + j];
            let slot = if i == 0 || j == 0 || i == n - 1 || j == n - 1 {
                &mut edge
            } else {
                &mut inner
            };
            slot.0 += f;
            slot.1 += 1;
        }
    }
    (edge.0 / edge.1 as f64) / (inner.0 / inner.1 as f64)
}

type ScatterOutcome = (
    Vec<serde_json::Value>,
    Vec<SliderReport>,
    (f64, f64, f64, f64),
);

fn mean_sd(v: &[f64]) -> (f64, f64) {
    let m = v.iter().sum::<f64>() / v.len() as f64;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len().max(2) - 1) as f64;
    (m, var.sqrt())
}

/// η, contact fraction and load sharing against σ (mean ± sd over seeds), the chart; returns
/// the rows, the ideal slider's reports and (η, contact fraction) at 40 N for σ = 0 and 5 nm.
fn run_scatter(s: &Setup, figures: &Path) -> Result<ScatterOutcome, ValidationError> {
    let n = s.posts_per_side;
    let mut rows = Vec::new();
    let mut ideal = Vec::new();
    let mut at_40 = [(f64::NAN, f64::NAN); 2];
    for &sigma_nm in &s.scatter_nm {
        let seeds = if sigma_nm == 0.0 { 1 } else { s.seeds };
        let runs: Vec<Vec<SliderReport>> = (1..=seeds)
            .map(|seed| {
                analyse(
                    n,
                    Imperfections {
                        height_scatter_m: sigma_nm * 1e-9,
                        scatter_seed: seed,
                        ..Imperfections::default()
                    },
                )
            })
            .collect::<Result<_, _>>()?;
        if s.maps && (sigma_nm == 0.0 || sigma_nm == 5.0) {
            write_map(figures, &format!("40n_sigma{sigma_nm}nm"), &runs[0][1])?;
        }
        for (k, p) in preloads_n(n).iter().enumerate() {
            let col = |f: &dyn Fn(&SliderReport) -> f64| -> Vec<f64> {
                runs.iter().map(|r| f(&r[k])).collect()
            };
            let (eta_mean, eta_sd) = mean_sd(&col(&eta));
            let (cf, cf_sd) = mean_sd(&col(&|r| r.contact_fraction));
            let (ls, ls_sd) = mean_sd(&col(&|r| r.load_sharing));
            if k == 1 && (sigma_nm == 0.0 || sigma_nm == 5.0) {
                at_40[usize::from(sigma_nm > 0.0)] = (eta_mean, cf);
            }
            rows.push(json!({
                "height_scatter_m": sigma_nm * 1e-9, "seeds": seeds, "preload_n": p,
                "eta_mean": eta_mean, "eta_sd": eta_sd, "contact_fraction_mean": cf,
                "contact_fraction_sd": cf_sd, "load_sharing_mean": ls, "load_sharing_sd": ls_sd,
            }));
        }
        if sigma_nm == 0.0 {
            ideal = runs.into_iter().next().unwrap_or_default();
        }
    }
    scatter_chart(&rows, n, &figures.join("eta_vs_scatter"))?;
    let [(eta0, cf0), (eta5, cf5)] = at_40;
    Ok((rows, ideal, (eta0, eta5, cf0, cf5)))
}

fn scatter_chart(rows: &[serde_json::Value], n: usize, stem: &Path) -> Result<(), ValidationError> {
    let mut chart = Chart::new(
        format!(
            "η of the {n} × {n}-post slider against post-height scatter (mean ± sd over seeds)"
        ),
        "σ (nm)",
        "η",
    );
    for (label, p) in ["10 N", "40 N", "100 N"].iter().zip(preloads_n(n)) {
        let pts = |k: f64| -> Vec<(f64, f64)> {
            rows.iter()
                .filter(|v| v["preload_n"].as_f64() == Some(p))
                .map(|v| {
                    let num = |key: &str| v[key].as_f64().unwrap_or(f64::NAN);
                    (
                        num("height_scatter_m") * 1e9,
                        num("eta_mean") + k * num("eta_sd"),
                    )
                })
                .collect()
        };
        let label = format!("{label} (per post as the default)");
        chart
            .series
            .push(Series::new(label.clone(), pts(0.0), Style::LineMarkers));
        chart.series.push(Series::new(
            format!("{label} ± sd"),
            pts(1.0),
            Style::Dashed,
        ));
        chart
            .series
            .push(Series::new(String::new(), pts(-1.0), Style::Dashed));
    }
    svg_only(write_chart(&chart, stem).map_err(|e| failed("η chart", e))?)
}

/// Removes the PNG of a written chart (the case's figures are SVG).
fn svg_only(paths: Vec<std::path::PathBuf>) -> Result<(), ValidationError> {
    for p in paths
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
    {
        std::fs::remove_file(p).map_err(|e| io(p, e))?;
    }
    Ok(())
}

fn run_shapes(s: &Setup, figures: &Path) -> Result<Vec<serde_json::Value>, ValidationError> {
    let mut rows = Vec::new();
    for (name, imperfections) in &s.shapes {
        let reports = analyse(s.posts_per_side, imperfections.clone())?;
        if s.maps && *name == "tilt_y 100 nm" {
            write_map(figures, "40n_tilt_y100nm", &reports[1])?;
        }
        rows.push(json!({"case": name, "results": summary(&reports)}));
    }
    Ok(rows)
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

/// The post-force map at θ₀ = 0 as a PNG (the README embeds it; the 10 000-cell SVG is
/// ≈ 0.9 MB) and the forces behind it as `post_forces_NAME.csv` (`row,column,force_n`).
fn write_map(dir: &Path, name: &str, r: &SliderReport) -> Result<(), ValidationError> {
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
    write_category_map(&map, &stem).map_err(|e| failed("post-force map", e))?;
    let svg = stem.with_extension("svg");
    std::fs::remove_file(&svg).map_err(|e| io(&svg, e))?;
    let csv = dir
        .parent()
        .unwrap_or(dir)
        .join(format!("results/post_forces_{name}.csv"));
    let mut text = String::from("row,column,force_n\n");
    for i in 0..r.posts_x {
        for j in 0..r.posts_y {
            text += &format!("{j},{i},{:e}\n", r.post_forces_n[i * r.posts_y + j]);
        }
    }
    std::fs::File::create(&csv)
        .and_then(|mut f| f.write_all(text.as_bytes()))
        .map_err(|e| io(&csv, e))
}

/// Full level: the default slider against the committed study and the strip FEM.
fn committed_checks(
    ideal: &[SliderReport],
    mechanism_rows: &[serde_json::Value],
    checks: &mut Vec<Check>,
) -> Result<(), ValidationError> {
    let parse = |text: &str, what: &str| -> Result<serde_json::Value, ValidationError> {
        serde_json::from_str(text).map_err(|e| failed(what, e))
    };
    let study = parse(STUDY_JSON, "committed study.json")?;
    let committed_mechanisms = parse(MECHANISMS_JSON, "committed mechanisms.json")?;
    let strip = parse(STRIP_JSON, "committed strip.json")?;
    let number = |v: &serde_json::Value, what: &str| -> Result<f64, ValidationError> {
        v.as_f64()
            .ok_or_else(|| failed("committed results", format!("{what} is not a number")))
    };
    let committed_eta = study["height_scatter"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    for (k, r) in ideal.iter().enumerate() {
        let row = committed_eta
            .iter()
            .find(|v| v["height_scatter_m"] == 0.0 && v["preload_n"].as_f64() == Some(r.preload_n))
            .ok_or_else(|| failed("study.json", format!("no σ = 0 row at {} N", r.preload_n)))?;
        checks.push(Check::relative(
            CASE,
            format!("default slider, ideal, {} N: η", r.preload_n),
            eta(r),
            number(&row["eta_mean"], "eta_mean")?,
            COMMITTED_TOLERANCE,
            "committed validation/whole-slider/results/study.json",
        ));
        let fem = &strip[0]["eta_against_preload"][k];
        checks.push(Check::relative(
            CASE,
            format!(
                "default slider, ideal, {} N: η (Johnson near field) against the default strip FEM",
                r.preload_n
            ),
            eta(r),
            number(&fem["eta"], "strip eta")?,
            STRIP_FEM_TOLERANCE,
            "validation/static-contact/results/strip.json (Tet10 strip FEM); Johnson's near field +6.3/+3.4/+1.8 % (whole-slider README)",
        ));
    }
    let committed_cases = committed_mechanisms["cases"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    for row in mechanism_rows {
        let (name, sigma) = (&row["mechanism"], &row["height_scatter_m"]);
        let Some(reference) = committed_cases
            .iter()
            .find(|c| &c["mechanism"] == name && c["height_scatter_m"].as_f64() == sigma.as_f64())
        else {
            continue;
        };
        let value = number(&row["results"][1]["effective_contact_ratio"], "η")?;
        checks.push(Check::relative(
            CASE,
            format!(
                "mechanism {}, σ = {} nm, 40 N: η",
                name.as_str().unwrap_or("?"),
                sigma.as_f64().unwrap_or(f64::NAN) * 1e9
            ),
            value,
            number(&reference["results"][1]["effective_contact_ratio"], "η")?,
            COMMITTED_TOLERANCE,
            "committed validation/whole-slider/results/mechanisms.json",
        ));
        if name == "rigid" && sigma.as_f64() == Some(0.0) {
            checks.push(Check::relative(
                CASE,
                "flat stator, rigid back, 40 N: load sharing",
                number(&row["flat_stator_40n"]["load_sharing"], "load sharing")?,
                number(
                    &reference["flat_stator_40n"]["load_sharing"],
                    "load sharing",
                )?,
                COMMITTED_TOLERANCE,
                "committed validation/whole-slider/results/mechanisms.json (README: 0.768)",
            ));
        }
    }
    Ok(())
}
