//! The validation study (`cargo run -p validation --example validate_stick_slip --release`) at smoke level:
//! every documented figure and the report are produced.

use validation::stick_slip::{ValidationLevel, ValidationSetup, run_validation};

#[test]
fn validation_study_writes_every_figure_and_the_report() {
    let setup = ValidationSetup::paper_posts(ValidationLevel::Smoke).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let report = run_validation(&setup, dir.path()).unwrap();
    for stem in [
        "work_precision",
        "stability_regularized-explicit",
        "stability_post-mass",
        "speed_thrust_transient_vs_periodic",
        "transient_step_response",
        "transient_burst",
        "trend_post_count",
        "trend_diameter",
        "speed_thrust_preloads",
        "fig6_post_history",
    ] {
        assert!(
            dir.path().join(format!("{stem}.svg")).exists(),
            "figure {stem}.svg missing"
        );
    }
    assert!(
        dir.path().join("report.json").exists(),
        "report.json missing"
    );
    assert!(
        report.agreement.max_speed_difference < 0.01,
        "transient vs period average speed {}",
        report.agreement.max_speed_difference
    );
    let exact = report
        .work_precision
        .iter()
        .find(|p| p.scheme == "event-driven")
        .unwrap();
    assert!(
        exact.stall_error <= f64::EPSILON,
        "closed-form reference error {}",
        exact.stall_error
    );
    // Post-mass cells beyond the theoretical limit diverge; cells well inside do not.
    let map = report
        .stability_maps
        .iter()
        .find(|m| m.scheme == "post-mass")
        .unwrap();
    for (row, limit) in map.cells.iter().zip(&map.theoretical_limit_over_period) {
        for (cell, step) in row.iter().zip(&map.step_over_period) {
            if *step > 1.05 * limit {
                assert_eq!(
                    *cell, 3,
                    "post-mass step {step:.2e} T beyond the limit {limit:.2e} T should diverge"
                );
            }
            if *step < 0.2 * limit {
                assert!(
                    *cell <= 1,
                    "post-mass step {step:.2e} T well inside the limit {limit:.2e} T should be stable"
                );
            }
        }
    }
}
