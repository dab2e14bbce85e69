//! The `design` case: the optimiser on known optima and the convergence of the Monte Carlo
//! statistics of uncertainty quantification (crate `design`, as `sawdrive design` and
//! `sawdrive uq` use it).
//!
//! Optimiser (Latin-hypercube pre-search + Nelder–Mead, feasibility first): on
//! f = 1 − (x − 0.3)² − 4(y − 0.7)² over [0, 1]² the optimum (0.3, 0.7) is found within the
//! stated tolerance (a fraction of each range); with x + y ≤ 1.2 on −(x − 0.9)² − (y − 0.9)² the
//! optimum moves onto the boundary (0.6, 0.6); an integer variable on −(n − 7.3)² lands on 7.
//! UQ: N draws of N(2, 0.5²) through `design::draw_inputs` (the seeded per-sample generators
//! of `sawdrive uq`); the band's mean, standard deviation and P95 converge to the exact values
//! within 4 standard errors (mean: σ/√N; sd: σ/√(2N); P95: √(p(1−p))/(√N φ(z₀.₉₅)) σ).
//! N = 2 000 (smoke), 20 000 (quick), 200 000 (full). The convergence on the way there (N from
//! 500 up to the level's N, each statistic's relative error and its 4-standard-error band) is
//! written as `results/uq_convergence.csv` and `figures/uq_convergence.svg`.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use charts::{Chart, Series, Style, write_chart};

use design::{
    Distribution, Objective, OptimiserSettings, Outcome, ScatterInput, Sense, Variable, band,
    draw_inputs, optimise,
};

use super::{Check, Level};
use crate::error::ValidationError;

const CASE: &str = "design";

/// Standard errors a converged Monte Carlo statistic may lie from its exact value. 4.
pub const STANDARD_ERRORS: f64 = 4.0;

fn variable(name: &str, lower: f64, upper: f64, integer: bool) -> Variable {
    Variable {
        name: name.into(),
        lower,
        upper,
        integer,
    }
}

fn outcome(objective: f64, violation: Option<f64>) -> Outcome {
    Outcome {
        objective,
        violations: violation
            .filter(|g| *g > 0.0)
            .map(|g| vec![("sum_limit".into(), g)])
            .unwrap_or_default(),
        outputs: BTreeMap::new(),
    }
}

fn failed(e: design::DesignError) -> ValidationError {
    ValidationError::InvalidOption {
        option: "design case",
        value: e.to_string(),
        reason: "the optimiser or the statistics failed",
    }
}

/// The checks at `level`; writes the UQ convergence (`results/uq_convergence.csv`,
/// `figures/uq_convergence.svg`) into `out`.
pub fn run(level: Level, out: &Path) -> Result<Vec<Check>, ValidationError> {
    let maximise = Objective {
        output: "f".into(),
        sense: Sense::Maximise,
    };
    let settings = OptimiserSettings::default();
    let mut checks = Vec::new();
    let source = "known optimum of a toy objective (crates/design optimise module docs)";

    let toy = |x: &[f64]| -> Result<Outcome, String> {
        Ok(outcome(
            1.0 - (x[0] - 0.3).powi(2) - 4.0 * (x[1] - 0.7).powi(2),
            None,
        ))
    };
    let vars = [
        variable("x", 0.0, 1.0, false),
        variable("y", 0.0, 1.0, false),
    ];
    let r = optimise(&vars, &maximise, &settings, "exact", &toy).map_err(failed)?;
    for (k, (name, truth)) in [("x", 0.3), ("y", 0.7)].into_iter().enumerate() {
        checks.push(Check::at_most(
            CASE,
            format!("unconstrained optimum: |{name} − {truth}| (fraction of the range)"),
            (r.best.x[k] - truth).abs(),
            settings.x_tolerance,
            source,
        ));
    }

    let constrained = |x: &[f64]| -> Result<Outcome, String> {
        Ok(outcome(
            -(x[0] - 0.9).powi(2) - (x[1] - 0.9).powi(2),
            Some(x[0] + x[1] - 1.2),
        ))
    };
    let tight = OptimiserSettings {
        x_tolerance: 1e-3,
        max_evaluations_per_start: 200,
        ..settings
    };
    let r = optimise(&vars, &maximise, &tight, "exact", &constrained).map_err(failed)?;
    checks.push(Check::at_most(
        CASE,
        "active constraint x + y ≤ 1.2: x + y at the optimum",
        r.best.x[0] + r.best.x[1],
        1.2,
        source,
    ));
    for (k, name) in ["x", "y"].into_iter().enumerate() {
        checks.push(Check::at_most(
            CASE,
            format!("active constraint: |{name} − 0.6| at the optimum"),
            (r.best.x[k] - 0.6).abs(),
            0.02,
            source,
        ));
    }

    checks.push(integer_optimum(&maximise, &settings, source)?);
    checks.extend(uq(level, out)?);
    Ok(checks)
}

/// An integer variable on −(n − 7.3)² lands on 7.
fn integer_optimum(
    maximise: &Objective,
    settings: &OptimiserSettings,
    source: &str,
) -> Result<Check, ValidationError> {
    let integer =
        |x: &[f64]| -> Result<Outcome, String> { Ok(outcome(-(x[0] - 7.3).powi(2), None)) };
    let r = optimise(
        &[variable("n", 1.0, 20.0, true)],
        maximise,
        settings,
        "exact",
        &integer,
    )
    .map_err(failed)?;
    Ok(Check::relative(
        CASE,
        "integer variable: optimum of −(n − 7.3)²",
        r.best.x[0],
        7.0,
        0.0,
        source,
    ))
}

/// Samples of the level's Monte Carlo check.
fn samples(level: Level) -> usize {
    match level {
        Level::Smoke => 2_000,
        Level::Quick => 20_000,
        Level::Full => 200_000,
    }
}

/// (statistic, value, exact value, standard error) of the mean, standard deviation and P95 of
/// the first `n` draws of N(`mean`, `sd`²).
fn statistics(
    draws: &[f64],
    mean: f64,
    sd: f64,
) -> Result<[(&'static str, f64, f64, f64); 3], ValidationError> {
    let b = band(draws, "x").map_err(failed)?;
    let n = draws.len() as f64;
    let z95: f64 = 1.644_853_626_951_472_2;
    let density = (-0.5 * z95 * z95).exp() / (2.0 * std::f64::consts::PI).sqrt();
    Ok([
        ("mean", b.mean, mean, sd / n.sqrt()),
        ("standard deviation", b.sd, sd, sd / (2.0 * n).sqrt()),
        (
            "P95",
            b.p95,
            mean + z95 * sd,
            sd * (0.95f64 * 0.05).sqrt() / (n.sqrt() * density),
        ),
    ])
}

/// Monte Carlo convergence: the checks at the level's sample count, the convergence files.
fn uq(level: Level, out: &Path) -> Result<Vec<Check>, ValidationError> {
    let samples = samples(level);
    let (mean, sd) = (2.0, 0.5);
    let inputs = [ScatterInput {
        name: "x".into(),
        distribution: Distribution::Normal { mean, sd },
    }];
    let draws: Vec<f64> = (0..samples as u64)
        .map(|i| draw_inputs(&inputs, 1, i).0[0])
        .collect();
    let uq_source = "exact moments and quantile of N(2, 0.5²), standard errors (module docs)";
    let mut checks = Vec::new();
    for (what, value, exact, standard_error) in statistics(&draws, mean, sd)? {
        checks.push(Check::relative(
            CASE,
            format!("UQ, {samples} samples of N(2, 0.5²): {what}"),
            value,
            exact,
            STANDARD_ERRORS * standard_error / exact,
            uq_source,
        ));
    }
    convergence(&draws, (mean, sd), out)?;
    Ok(checks)
}

/// `results/uq_convergence.csv` and `figures/uq_convergence.svg`: each statistic's relative
/// error and its 4-standard-error band over the first N draws, N from 500 to all of them.
fn convergence(draws: &[f64], (mean, sd): (f64, f64), out: &Path) -> Result<(), ValidationError> {
    let ladder: Vec<usize> = [500, 2_000, 5_000, 20_000, 50_000, 200_000]
        .into_iter()
        .filter(|&n| n <= draws.len())
        .collect();
    let mut csv = String::from("samples,statistic,value,exact,relative_error,relative_band\n");
    let mut errors: BTreeMap<&str, Vec<(f64, f64)>> = BTreeMap::new();
    let mut bands: BTreeMap<&str, Vec<(f64, f64)>> = BTreeMap::new();
    for &n in &ladder {
        for (what, value, exact, standard_error) in statistics(&draws[..n], mean, sd)? {
            let error = (value / exact - 1.0).abs();
            let band = STANDARD_ERRORS * standard_error / exact;
            let _ = writeln!(csv, "{n},{what},{value},{exact},{error},{band}");
            errors
                .entry(what)
                .or_default()
                .push((n as f64, error.max(1e-12)));
            bands.entry(what).or_default().push((n as f64, band));
        }
    }
    super::write_text(&out.join("results/uq_convergence.csv"), &csv)?;
    let mut chart = Chart::new(
        "UQ convergence, N(2, 0.5²): relative error of each statistic and its 4-standard-error band",
        "samples N",
        "|statistic / exact − 1|",
    )
    .log_log();
    for (what, points) in errors {
        chart
            .series
            .push(Series::new(what, points, Style::LineMarkers));
        let band = bands.remove(what).unwrap_or_default();
        chart.series.push(Series::new(
            format!("{what}, 4 standard errors"),
            band,
            Style::Dashed,
        ));
    }
    write_chart(&chart, &out.join("figures/uq_convergence"))
        .map(|_| ())
        .map_err(|e| ValidationError::InvalidOption {
            option: "design case",
            value: e.to_string(),
            reason: "the UQ convergence chart could not be written",
        })
}
