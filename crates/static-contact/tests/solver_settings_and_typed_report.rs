//! The contact solver's settings in [`StaticParams`] reach the active-set solver, and the
//! report is a typed value that survives a JSON round trip unchanged (the application's cache
//! stores it that way).

mod common;

use common::run;
use static_contact::params::StaticParams;
use static_contact::{ContactError, MeshChoice, StaticReport};

/// The default slider seen through the committed 10-post strip mesh (fast: Tet4, 10 k nodes).
fn ten_post_params() -> StaticParams {
    StaticParams {
        mesh: MeshChoice::Auto,
        ..common::ten_post_tet4()
    }
}

#[test]
fn an_iteration_limit_of_one_stops_the_contact_solver_with_a_named_error() {
    let converged = run(&ten_post_params()).expect("default solver settings converge");
    let most_per_solve = converged.report.preloads[0]
        .snapshots
        .iter()
        .map(|s| s.iterations)
        .max()
        .unwrap_or(0);
    assert!(
        most_per_solve > 1,
        "the wave snapshots need more than one active-set iteration ({most_per_solve})"
    );
    let limited = StaticParams {
        max_iterations: 1,
        ..ten_post_params()
    };
    match run(&limited) {
        Err(ContactError::NotConverged { iterations, .. }) => {
            assert_eq!(
                iterations, 1,
                "active-set iterations done under a limit of one"
            )
        }
        other => panic!("max_iterations = 1 must stop the solver, got {other:?}"),
    }
}

#[test]
fn a_looser_tolerance_is_what_the_solver_accepts() {
    let tight = run(&ten_post_params()).expect("default tolerance");
    assert!(
        tight.report.complementarity_residual <= ten_post_params().contact_tolerance,
        "residual {} within the default tolerance",
        tight.report.complementarity_residual
    );
    let impossible = StaticParams {
        contact_tolerance: f64::MIN_POSITIVE,
        ..ten_post_params()
    };
    let err = run(&impossible).expect_err("a tolerance below round-off cannot be met");
    assert!(
        matches!(err, ContactError::NotConverged { tolerance, .. } if tolerance == f64::MIN_POSITIVE),
        "the solver reports the tolerance it was given: {err}"
    );
}

#[test]
fn the_report_survives_a_json_round_trip_unchanged() {
    let report = run(&ten_post_params()).expect("10-post strip").report;
    let json = serde_json::to_string(&report).expect("report serialises");
    let back: StaticReport = serde_json::from_str(&json).expect("report deserialises");
    assert_eq!(back, report, "typed report after a JSON round trip");
    for key in [
        "effective_contact_ratio",
        "contact_fraction",
        "load_sharing",
        "complementarity_residual",
        "iterations",
        "eta_full_contact",
    ] {
        assert!(
            json.contains(&format!("\"{key}\":")),
            "report JSON keeps the field name {key}"
        );
    }
}
