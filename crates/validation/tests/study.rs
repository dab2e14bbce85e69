//! The whole springs pipeline on coarse meshes (needs gmsh, as installed by scripts/install-deps.sh).

use validation::report::{read_results, write_charts, write_json};
use validation::{
    MeshCache, PunchMeshParameters, SpringsOptions, ValidationError, validate_springs,
};

#[test]
fn smoke_study_produces_cases_json_charts_and_reloads() {
    let dir = tempfile::tempdir().unwrap();
    let options = SpringsOptions::smoke();
    let validation = validate_springs(&options).expect("smoke study runs");
    assert_eq!(
        validation.cases.len(),
        8,
        "4 springs x 2 materials x 1 radius"
    );
    for c in &validation.cases {
        assert!(
            c.fem_n_per_m.is_finite() && c.fem_n_per_m > 0.0,
            "{} FEM stiffness {}",
            c.spring,
            c.fem_n_per_m
        );
        // Coarse meshes (h_e = 0.05…0.2 a, R = 20a): within 2 % after extrapolation.
        assert!(
            c.relative_difference.abs() < 0.02,
            "{} {} smoke FEM/formula - 1 = {}",
            c.spring,
            c.material,
            c.relative_difference
        );
        assert!(
            c.fem_error_estimate.is_finite(),
            "{} error estimate",
            c.spring
        );
    }
    let json: serde_json::Value = serde_json::from_str(&validation.cases_json().unwrap()).unwrap();
    let first = &json.as_array().expect("--json output is an array")[0];
    for key in [
        "spring",
        "material",
        "radius_m",
        "fem_n_per_m",
        "fem_error_estimate",
        "analytic_n_per_m",
        "relative_difference",
    ] {
        assert!(
            first.get(key).is_some(),
            "--json object lacks `{key}`: {first}"
        );
    }
    assert_eq!(first["spring"], "k_pn", "spring label in JSON");
    let files = write_json(&validation, dir.path()).unwrap();
    let charts = write_charts(&validation, dir.path()).unwrap();
    assert!(
        charts
            .iter()
            .any(|p| p.extension().is_some_and(|e| e == "svg")),
        "charts written: {charts:?}"
    );
    let reloaded = read_results(&files[0]).unwrap();
    assert_eq!(
        reloaded.cases.len(),
        validation.cases.len(),
        "results.json round trip: case count"
    );
    for (a, b) in reloaded.cases.iter().zip(&validation.cases) {
        assert_eq!(
            (a.spring, &a.material),
            (b.spring, &b.material),
            "results.json round trip: case order"
        );
        assert!(
            (a.fem_n_per_m / b.fem_n_per_m - 1.0).abs() < 1e-12,
            "results.json round trip: {} FEM stiffness",
            a.spring
        );
    }
    assert!(validation.to_string().contains("k_st"), "table lists k_st");
}

#[test]
fn missing_gmsh_is_reported_with_the_command() {
    let dir = tempfile::tempdir().unwrap();
    let cache = MeshCache {
        dir: dir.path().to_path_buf(),
        gmsh: "/nonexistent/gmsh".into(),
        ..MeshCache::default()
    };
    let parameters = PunchMeshParameters {
        radius_m: 10e-6,
        truncation_ratio: 20.0,
        h_edge_over_a: 0.2,
        growth: 0.6,
        h_max_over_a: 0.0,
        symmetry: validation::MeshSymmetry::Quarter,
        order: 2,
    };
    match cache.punch_mesh(&parameters) {
        Err(ValidationError::MeshGeneration { command, detail }) => {
            assert!(
                command.contains("/nonexistent/gmsh") && detail.contains("cannot run gmsh"),
                "{command}: {detail}"
            );
        }
        other => panic!("expected a mesh generation error, got {other:?}"),
    }
    assert!(
        std::fs::read_dir(dir.path()).unwrap().next().is_none(),
        "no partial mesh left in the cache"
    );
}

#[test]
fn fewer_than_three_levels_are_refused() {
    let options = SpringsOptions {
        levels: 2,
        ..SpringsOptions::smoke()
    };
    assert!(
        matches!(
            validate_springs(&options),
            Err(ValidationError::InvalidOption {
                option: "levels",
                ..
            })
        ),
        "levels = 2 must be refused"
    );
}

/// The full springs study (≈ 30 min on 2 cores): every case converged (estimated error
/// ≤ 0.3 %) and within 0.5 % of its formula.
/// `cargo test --release -p validation --test study -- --ignored`
#[test]
#[ignore = "full springs validation, ~30 min; run with --ignored"]
fn full_springs_validation_passes_acceptance() {
    let validation = validate_springs(&SpringsOptions::default()).unwrap();
    println!("{validation}");
    for c in &validation.cases {
        assert!(
            c.converged,
            "{} {} a = {} m: estimated error {} (order {})",
            c.spring, c.material, c.radius_m, c.fem_error_estimate, c.observed_order
        );
        assert!(
            c.agrees,
            "{} {} a = {} m: FEM/formula - 1 = {}",
            c.spring, c.material, c.radius_m, c.relative_difference
        );
        assert!(
            c.tells_partner_apart,
            "{} {}: cannot tell from {}",
            c.spring, c.material, c.partner_spring
        );
    }
}
