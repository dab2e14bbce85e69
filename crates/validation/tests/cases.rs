//! The whole-slider, coupled-dynamics and paper-figures cases: their checks pass on the models
//! and turn red on a wrong model or reference (the pipeline seams fed by stand-in runners).

use std::cell::Cell;

use validation::cases::coupled_dynamics::{self, WholeRowFigures};
use validation::cases::paper_figures::{self, PointFigures};
use validation::cases::{self, Level, whole_slider};

#[test]
fn the_fft_lattice_operator_equals_the_pairwise_sum_of_its_kernel() {
    let mismatch = whole_slider::operator_mismatch(12).unwrap();
    assert!(
        mismatch <= whole_slider::OPERATOR_TOLERANCE,
        "FFT vs pairwise sum: {mismatch:e}"
    );
}

#[test]
fn whole_slider_smoke_checks_pass_and_write_the_case_layout() {
    let dir = tempfile::tempdir().unwrap();
    let checks = whole_slider::run(Level::Smoke, dir.path()).unwrap();
    assert!(checks.len() >= 10, "{} checks", checks.len());
    for c in &checks {
        assert!(c.pass, "{}", c.line());
    }
    for file in [
        "results/study.json",
        "results/mechanisms.json",
        "figures/eta_vs_scatter.svg",
    ] {
        assert!(dir.path().join(file).is_file(), "{file} written");
    }
    assert!(!dir.path().join("figures/eta_vs_scatter.png").exists());
}

/// A stand-in for the pipeline: the paper's trends (stiffer arrays faster and stronger), or
/// with `reversed` the 50 µm slider faster than the 20 µm one.
fn paper_like(sets: &[String], reversed: bool) -> PointFigures {
    let diameter: f64 = sets
        .iter()
        .find_map(|s| s.strip_prefix("posts.diameter="))
        .and_then(|s| s.trim_end_matches(" um").parse().ok())
        .unwrap();
    let preload: f64 = sets
        .iter()
        .find_map(|s| s.strip_prefix("preload="))
        .and_then(|s| s.trim_end_matches(" N").parse().ok())
        .unwrap();
    let stiffness = if reversed { diameter } else { 100.0 - diameter };
    PointFigures {
        stall_thrust_n: (0.3 * preload).min(0.1 * stiffness + 0.2 * preload),
        no_load_speed_m_per_s: 1.02 - 0.002 * preload + 0.0002 * stiffness,
        effective_contact_ratio: 0.7,
    }
}

#[test]
fn paper_figures_checks_follow_the_runner_and_catch_a_reversed_trend() {
    let dir = tempfile::tempdir().unwrap();
    let calls = Cell::new(0);
    let good = |sets: &[String]| {
        calls.set(calls.get() + 1);
        Ok(paper_like(sets, false))
    };
    let checks = paper_figures::run(Level::Smoke, dir.path(), &good).unwrap();
    assert_eq!(calls.get(), 2, "smoke runs two points");
    let speed_order = checks
        .iter()
        .find(|c| c.quantity.contains("no-load speed 20 um"))
        .expect("a speed-order check");
    assert!(speed_order.pass, "{}", speed_order.line());
    let bad = |sets: &[String]| Ok(paper_like(sets, true));
    let checks = paper_figures::run(Level::Smoke, dir.path(), &bad).unwrap();
    let speed_order = checks
        .iter()
        .find(|c| c.quantity.contains("no-load speed 20 um"))
        .unwrap();
    assert!(
        !speed_order.pass,
        "a reversed trend must fail: {}",
        speed_order.line()
    );
    let failing = |_: &[String]| Err("no FEM here".to_string());
    let e = paper_figures::run(Level::Smoke, dir.path(), &failing).unwrap_err();
    assert!(e.to_string().contains("no FEM here"), "{e}");
}

#[test]
fn paper_figures_quick_runs_each_shared_grid_point_once() {
    let dir = tempfile::tempdir().unwrap();
    let calls = Cell::new(0);
    let runner = |sets: &[String]| {
        calls.set(calls.get() + 1);
        Ok(paper_like(sets, false))
    };
    paper_figures::run(Level::Quick, dir.path(), &runner).unwrap();
    // 5 × 5 + 4 × 5 + 2 × 9 points, the 20 µm × 10 000 preloads shared: 25 + 15 + 9 + 4 (the
    // 50 µm × 1600 points at 10, 20, 40, 70 and 100 N are shared with Figs 9-10).
    assert_eq!(calls.get(), 25 + 15 + 4 + 4);
}

#[test]
fn coupled_dynamics_smoke_passes_against_the_committed_whole_row_and_fails_on_a_wrong_one() {
    let dir = tempfile::tempdir().unwrap();
    // The committed coupled figures of the 50 µm × 1600 slider at 10 N (results/whole-row.csv),
    // as a stand-in pipeline would return them.
    let committed = WholeRowFigures {
        stall_thrust_n: 3.0000000000000018,
        no_load_speed_m_per_s: 0.9610273227493864,
        lumped_stall_thrust_n: 3.0000000000000084,
        lumped_no_load_speed_m_per_s: 0.9462836231288743,
        lumped_error_estimate: 0.07653973639014981,
        energy_balance_residual: 5.0e-15,
    };
    let checks =
        coupled_dynamics::run(Level::Smoke, dir.path(), &|_: &[String]| Ok(committed)).unwrap();
    for c in &checks {
        assert!(c.pass, "{}", c.line());
    }
    assert!(dir.path().join("results/row_work_precision.csv").is_file());
    assert!(dir.path().join("figures/row_work_precision.svg").is_file());
    // 1e-3 slower: ten times the reproduction tolerance.
    let slower = WholeRowFigures {
        no_load_speed_m_per_s: 0.9610273227493864 * (1.0 - 1e-3),
        ..committed
    };
    let checks =
        coupled_dynamics::run(Level::Smoke, dir.path(), &|_: &[String]| Ok(slower)).unwrap();
    let failed: Vec<_> = checks.iter().filter(|c| !c.pass).collect();
    assert!(
        failed
            .iter()
            .any(|c| c.quantity.contains("coupled no-load speed")),
        "a 0.1 % slower coupled row must fail its reproduction check"
    );
}

#[test]
fn png_copies_of_svg_figures_are_dropped_and_lone_pngs_kept() {
    let dir = tempfile::tempdir().unwrap();
    let figures = dir.path().join("figures");
    std::fs::create_dir_all(&figures).unwrap();
    for f in ["chart.svg", "chart.png", "map.png"] {
        std::fs::write(figures.join(f), "x").unwrap();
    }
    assert_eq!(cases::drop_png_duplicates(dir.path()).unwrap(), 1);
    assert!(!figures.join("chart.png").exists());
    assert!(figures.join("chart.svg").exists() && figures.join("map.png").exists());
}

#[test]
fn summary_table_cells_escape_the_bars_of_absolute_values() {
    let outcome = cases::CaseOutcome {
        case: "x".into(),
        level: Level::Smoke,
        checks: vec![cases::Check::at_most("x", "|a − b|", 0.1, 1.0, "source")],
        skipped: None,
        wall_s: 0.0,
    };
    let table = cases::summary_markdown(&[outcome], "abc");
    assert!(table.contains("| \\|a − b\\| |"), "{table}");
    assert!(table.contains("--level smoke"), "{table}");
}

fn outcome(case: &str, level: Level, pass: bool) -> cases::CaseOutcome {
    cases::CaseOutcome {
        case: case.into(),
        level,
        checks: vec![cases::Check::at_most(
            case,
            "q",
            if pass { 0.5 } else { 2.0 },
            1.0,
            "s",
        )],
        skipped: None,
        wall_s: 1.0,
    }
}

#[test]
fn summary_update_keeps_the_sections_of_cases_not_run_and_counts_them() {
    let first = cases::summary_markdown(
        &[
            outcome("springs", Level::Full, true),
            outcome("design", Level::Quick, false),
        ],
        "aaa",
    );
    // Rerun only stick-slip: springs and design keep their rows (level, commit), in case order.
    let second = cases::update_summary(
        Some(&first),
        &[outcome("stick-slip", Level::Full, true)],
        "bbb",
    );
    let springs = second.find("## springs (full level").expect("springs kept");
    let stick = second
        .find("## stick-slip (full level")
        .expect("stick-slip added");
    let design = second.find("## design (quick level").expect("design kept");
    assert!(springs < stick && stick < design, "{second}");
    assert!(second.contains("| full | `aaa` |") && second.contains("| full | `bbb` |"));
    assert!(
        second.contains("3 checks, 1 failing, 0 case(s) skipped"),
        "{second}"
    );
    // A section run below the full level names the command of the full level.
    assert!(second.contains("`sawdrive validate design --level full --summary"));
    // Rerunning design replaces its section instead of adding one.
    let third = cases::update_summary(
        Some(&second),
        &[outcome("design", Level::Full, true)],
        "ccc",
    );
    assert_eq!(third.matches("## design").count(), 1, "{third}");
    assert!(third.contains("3 checks, 0 failing"), "{third}");
}

#[test]
fn summary_lines_stay_short_whatever_the_length_of_sources_and_reasons() {
    let long = "a reference source described at great length, ".repeat(20);
    let mut checked = outcome("springs", Level::Quick, true);
    checked.checks[0].source = long.clone();
    let skipped = cases::CaseOutcome {
        case: "fem-peers".into(),
        level: Level::Full,
        checks: Vec::new(),
        skipped: Some(long.clone()),
        wall_s: 0.0,
    };
    let text = cases::summary_markdown(&[checked, skipped], "abc");
    for line in text.lines() {
        assert!(
            line.chars().count() <= 2 * cases::SUMMARY_WIDTH,
            "{} characters: {line}",
            line.chars().count()
        );
    }
    // The source is listed once under the table, the row cites its number.
    assert!(text.contains("| `abc` | [1] |"), "{text}");
    assert!(text.contains("\n1. a reference source"), "{text}");
    assert!(text.contains("\nSkipped: a reference source"), "{text}");
}

#[test]
fn the_committed_summary_has_no_markdown_line_over_400_characters() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation/SUMMARY.md");
    let text = std::fs::read_to_string(&path).expect("validation/SUMMARY.md");
    for (k, line) in text.lines().enumerate() {
        assert!(
            line.chars().count() <= 400,
            "validation/SUMMARY.md line {}: {} characters",
            k + 1,
            line.chars().count()
        );
    }
}
