//! The `paper-figures` case: the source paper's Figs 7–12 (stall thrust and no-load speed
//! against preload for five post counts, four diameters at equal tip area, and 20 µm against
//! 50 µm posts), each point the whole `sawdrive` pipeline (contact springs → static FEM η at that
//! preload and array → the lumped period-average model, as `validation/paper-figures/*.toml`
//! set it), and checks of the trends the paper states and of the numbers it gives
//! (validation/paper-figures/README.md; the paper:
//! `/work/shared/paper/saw-motor-friction-drive.txt`, Secs 2–4).
//!
//! The pipeline lives in the `sawdrive` crate, which links this one; the case therefore takes
//! a [`PointRunner`]: a function that runs one scene (the default scene with `--set KEY=VALUE`
//! overrides) and returns its [`PointFigures`]. `sawdrive validate` injects the pipeline; the
//! checks, grids, levels and tolerances live here.
//!
//! Checks (each trend at every preload of the grid where the paper states it):
//! * Figs 7, 8: more posts give more no-load speed at every preload, and more thrust once it
//!   leaves the friction limit μP (preload ≥ 40 N); at 10 N the 10 000-post slider's thrust is
//!   μP = 3 N within [`FRICTION_LIMIT_TOLERANCE`] (the paper: friction-limited at low preload);
//! * Figs 9, 10: at equal tip area the no-load speed falls from 20 to 50 µm at every preload and
//!   the thrust falls at ≥ 70 N;
//! * Figs 11, 12: the 20 µm slider is faster than the 50 µm one at every preload and stronger
//!   at ≥ 55 N;
//! * every no-load speed ≤ the crest velocity 1.1 m/s (the paper's Sec. 2: the speed limit is
//!   the crest velocity; Sec. 3: 1.1 m/s for its 20 nm wave), and at 10 N the 10 000-post
//!   slider's within [`ANCHOR_SPEED_TOLERANCE`] of it (the limit approached at light preload);
//! * the largest stall thrust ≥ the [`DEMONSTRATED_THRUST_N`] = 10 N the paper's motor
//!   demonstrated (Sec. 1). The paper's figures are not tabulated; these are the numbers its
//!   text states.
//!
//! Levels: smoke — two points (20 µm × 10 000 and 50 µm × 1 600 at 40 N: speed order, bound,
//! demonstrated thrust); quick and full — the three figures' grids of the sweep files (5 × 5, 4 × 5,
//! 2 × 9 points; shared points run once). Writes `results/<figure>.csv` and
//! `figures/<figure>_{stall_thrust,no_load_speed}.svg`.

use std::collections::BTreeMap;
use std::path::Path;

use charts::{Chart, Series, Style, write_chart};

use super::{Check, Level};
use crate::error::ValidationError;

const CASE: &str = "paper-figures";

/// |stall / μP − 1| at 10 N for the 10 000-post slider. 0.01.
pub const FRICTION_LIMIT_TOLERANCE: f64 = 0.01;
/// |v₀ / 1.1 m/s − 1| at 10 N preload: the crest velocity is the speed limit, approached at
/// light preload (measured 1.02 m/s, 7 % below). 0.1.
pub const ANCHOR_SPEED_TOLERANCE: f64 = 0.1;
/// The thrust the paper's motor demonstrated (N; its Sec. 1, ref. \[4\]).
pub const DEMONSTRATED_THRUST_N: f64 = 10.0;
/// The crest speed A_t ω of the paper's wave (m/s).
pub const CREST_SPEED_M_PER_S: f64 = 1.1;

/// What one pipeline run returns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointFigures {
    /// Stall thrust (N).
    pub stall_thrust_n: f64,
    /// No-load speed (m/s).
    pub no_load_speed_m_per_s: f64,
    /// η of the static stage.
    pub effective_contact_ratio: f64,
}

/// Runs the default scene with these `KEY=VALUE` overrides through the whole pipeline.
pub type PointRunner<'a> = dyn Fn(&[String]) -> Result<PointFigures, String> + 'a;

/// A variant of a figure: label and its overrides.
#[derive(Debug, Clone, PartialEq)]
pub struct Variant {
    /// Label (as the sweep file's).
    pub label: &'static str,
    /// Post diameter (µm) and posts per side.
    pub diameter_um: u32,
    /// Posts per side.
    pub per_side: usize,
}

/// One figure pair: its variants (in the order the trend is checked: from the stiffest) and
/// preloads.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Name (the sweep file's stem).
    pub name: &'static str,
    /// The paper's figure numbers.
    pub paper: &'static str,
    /// Variants, stiffest first.
    pub variants: Vec<Variant>,
    /// Preloads (N).
    pub preloads_n: Vec<f64>,
    /// Thrust must fall along the variants from this preload on (N).
    pub thrust_trend_from_n: f64,
}

const fn v(label: &'static str, diameter_um: u32, per_side: usize) -> Variant {
    Variant {
        label,
        diameter_um,
        per_side,
    }
}

/// The figures at `level`.
pub fn figures(level: Level) -> Vec<Figure> {
    if level == Level::Smoke {
        return vec![Figure {
            name: "smoke-20-vs-50",
            paper: "Figs 11, 12",
            variants: vec![v("20 um x 10000", 20, 100), v("50 um x 1600", 50, 40)],
            preloads_n: vec![40.0],
            thrust_trend_from_n: f64::INFINITY,
        }];
    }
    let grid = vec![10.0, 20.0, 40.0, 70.0, 100.0];
    vec![
        Figure {
            name: "fig7-8-post-count",
            paper: "Figs 7, 8",
            variants: vec![
                v("10000 posts", 20, 100),
                v("6400 posts", 20, 80),
                v("4356 posts", 20, 66),
                v("2500 posts", 20, 50),
                v("1089 posts", 20, 33),
            ],
            preloads_n: grid.clone(),
            thrust_trend_from_n: 40.0,
        },
        Figure {
            name: "fig9-10-diameter",
            paper: "Figs 9, 10",
            variants: vec![
                v("20 um x 10000", 20, 100),
                v("30 um x 4489", 30, 67),
                v("40 um x 2500", 40, 50),
                v("50 um x 1600", 50, 40),
            ],
            preloads_n: grid,
            thrust_trend_from_n: 70.0,
        },
        Figure {
            name: "fig11-12-20-vs-50",
            paper: "Figs 11, 12",
            variants: vec![v("20 um x 10000", 20, 100), v("50 um x 1600", 50, 40)],
            preloads_n: vec![5.0, 10.0, 20.0, 30.0, 40.0, 55.0, 70.0, 85.0, 100.0],
            thrust_trend_from_n: 55.0,
        },
    ]
}

fn failed(context: &str, e: impl std::fmt::Display) -> ValidationError {
    ValidationError::InvalidOption {
        option: "paper-figures case",
        value: format!("{context}: {e}"),
        reason: "a pipeline point failed",
    }
}

fn io(path: &Path, source: std::io::Error) -> ValidationError {
    ValidationError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The overrides of one point (the sweep files' settings: the paper's model, the lumped period
/// average at the static η with the wave at constant amplitude).
pub fn point_sets(variant: &Variant, preload_n: f64) -> Vec<String> {
    vec![
        "model.dynamics=periodic-average".into(),
        // The paper's model: the wave at constant amplitude under the slider.
        "wave.attenuation=off".into(),
        format!("posts.diameter={} um", variant.diameter_um),
        format!("posts.count={0}x{0}", variant.per_side),
        format!("preload={preload_n} N"),
    ]
}

type Key = (u32, usize, u64);

/// Runs the case at `level` with `runner`, writing into `out`.
pub fn run(level: Level, out: &Path, runner: &PointRunner) -> Result<Vec<Check>, ValidationError> {
    let mut memo: BTreeMap<Key, PointFigures> = BTreeMap::new();
    let mut checks = Vec::new();
    for figure in figures(level) {
        let mut table: Vec<Vec<PointFigures>> = Vec::new();
        for variant in &figure.variants {
            let mut row = Vec::new();
            for &p in &figure.preloads_n {
                let key = (variant.diameter_um, variant.per_side, p.to_bits());
                let point = match memo.get(&key) {
                    Some(point) => *point,
                    None => {
                        let point = runner(&point_sets(variant, p))
                            .map_err(|e| failed(&format!("{} at {p} N", variant.label), e))?;
                        memo.insert(key, point);
                        point
                    }
                };
                row.push(point);
            }
            table.push(row);
        }
        write_figure(&figure, &table, out)?;
        checks.extend(trend_checks(&figure, &table));
    }
    checks.extend(anchor_checks(&memo));
    Ok(checks)
}

fn trend_checks(figure: &Figure, table: &[Vec<PointFigures>]) -> Vec<Check> {
    let source = format!(
        "the paper's {} (trend; validation/paper-figures/README.md)",
        figure.paper
    );
    let mut checks = Vec::new();
    for (k, &p) in figure.preloads_n.iter().enumerate() {
        for w in 0..figure.variants.len().saturating_sub(1) {
            let (stiff, soft) = (&figure.variants[w], &figure.variants[w + 1]);
            let (a, b) = (table[w][k], table[w + 1][k]);
            checks.push(Check::at_least(
                CASE,
                format!(
                    "{}, {p} N: no-load speed {} over {}",
                    figure.name, stiff.label, soft.label
                ),
                a.no_load_speed_m_per_s / b.no_load_speed_m_per_s,
                1.0,
                source.clone(),
            ));
            if p >= figure.thrust_trend_from_n {
                checks.push(Check::at_least(
                    CASE,
                    format!(
                        "{}, {p} N: stall thrust {} over {}",
                        figure.name, stiff.label, soft.label
                    ),
                    a.stall_thrust_n / b.stall_thrust_n,
                    1.0,
                    source.clone(),
                ));
            }
        }
        let fastest = table
            .iter()
            .map(|row| row[k].no_load_speed_m_per_s)
            .fold(0.0, f64::max);
        checks.push(Check::at_most(
            CASE,
            format!("{}, {p} N: largest no-load speed (m/s)", figure.name),
            fastest,
            CREST_SPEED_M_PER_S,
            "the paper, Sec. 2: the speed limit is the crest velocity (1.1 m/s, Sec. 3)",
        ));
    }
    checks
}

fn anchor_checks(memo: &BTreeMap<Key, PointFigures>) -> Vec<Check> {
    let mut checks = Vec::new();
    if let Some(point) = memo.get(&(20, 100, 10f64.to_bits())) {
        checks.push(Check::relative(
            CASE,
            "20 µm × 10 000, 10 N: stall thrust over μP = 3 N (friction-limited)",
            point.stall_thrust_n,
            3.0,
            FRICTION_LIMIT_TOLERANCE,
            "the paper, Sec. 2: the output force is limited by preload × friction coefficient (Fig. 7 at low preload)",
        ));
        checks.push(Check::relative(
            CASE,
            "20 µm × 10 000, 10 N: no-load speed (m/s) against the crest velocity 1.1 m/s",
            point.no_load_speed_m_per_s,
            CREST_SPEED_M_PER_S,
            ANCHOR_SPEED_TOLERANCE,
            "the paper, Sec. 2: the speed limit is the crest velocity, 1.1 m/s for its 20 nm wave (Sec. 3); approached at light preload",
        ));
    }
    let strongest = memo.values().map(|p| p.stall_thrust_n).fold(0.0, f64::max);
    checks.push(Check::at_least(
        CASE,
        "largest stall thrust over the points run (N), against the 10 N the motor demonstrated",
        strongest,
        DEMONSTRATED_THRUST_N,
        "the paper, Sec. 1: thrust of 10 N demonstrated on the 60 × 14 × 1 mm stator (its ref. [4])",
    ));
    checks
}

fn write_figure(
    figure: &Figure,
    table: &[Vec<PointFigures>],
    out: &Path,
) -> Result<(), ValidationError> {
    let (results, figures) = (out.join("results"), out.join("figures"));
    for dir in [&results, &figures] {
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    }
    let mut csv = String::from(
        "variant,preload_n,effective_contact_ratio,stall_thrust_n,no_load_speed_m_per_s\n",
    );
    for (variant, row) in figure.variants.iter().zip(table) {
        for (p, point) in figure.preloads_n.iter().zip(row) {
            csv += &format!(
                "{},{p},{},{},{}\n",
                variant.label,
                point.effective_contact_ratio,
                point.stall_thrust_n,
                point.no_load_speed_m_per_s
            );
        }
    }
    let path = results.join(format!("{}.csv", figure.name));
    std::fs::write(&path, csv).map_err(|e| io(&path, e))?;
    for (what, unit, pick) in [
        ("stall_thrust", "stall thrust (N)", 0usize),
        ("no_load_speed", "no-load speed (m/s)", 1),
    ] {
        let mut chart = Chart::new(
            format!("{}: {unit} against preload", figure.paper),
            "preload (N)",
            unit,
        );
        for (variant, row) in figure.variants.iter().zip(table) {
            let points = figure
                .preloads_n
                .iter()
                .zip(row)
                .map(|(p, q)| {
                    let y = if pick == 0 {
                        q.stall_thrust_n
                    } else {
                        q.no_load_speed_m_per_s
                    };
                    (*p, y)
                })
                .collect();
            chart
                .series
                .push(Series::new(variant.label, points, Style::LineMarkers));
        }
        let paths = write_chart(&chart, &figures.join(format!("{}_{what}", figure.name)))
            .map_err(|e| failed("chart", e))?;
        for p in paths
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "png"))
        {
            std::fs::remove_file(p).map_err(|e| io(p, e))?;
        }
    }
    Ok(())
}
