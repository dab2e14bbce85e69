//! The pipeline commands end to end on the small 10 × 10-post scene (committed Tet4 mesh).

mod common;

use std::path::{Path, PathBuf};

use common::{sawdrive_err, sawdrive_ok, small_scene};

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(
        &std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())),
    )
    .unwrap()
}

#[test]
fn run_writes_a_summary_within_the_physical_bounds() {
    let out = tempfile::tempdir().unwrap();
    let stdout = sawdrive_ok(&[
        "run",
        &small_scene(),
        "--out",
        out.path().to_str().unwrap(),
        "--json",
    ]);
    let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let folder = out.path().join("small-strip");
    assert_eq!(
        read_json(&folder.join("summary.json")),
        summary,
        "summary.json holds what --json printed"
    );

    let eta = summary["effective_contact_ratio"].as_f64().unwrap();
    assert!(
        eta > 0.0 && eta <= 1.2,
        "η from the FEM is a ratio near or below 1, got {eta}"
    );
    assert_eq!(summary["effective_contact_ratio_source"], "fem");
    let preload = summary["scene"]["load"]["preload_n"].as_f64().unwrap();
    let mu = summary["scene"]["friction"]["mu_kinetic"].as_f64().unwrap();
    let stall = summary["stall_thrust_n"].as_f64().unwrap();
    assert!(
        stall > 0.0 && stall <= mu * preload * (1.0 + 1e-9),
        "0 < stall thrust {stall} ≤ μP = {}",
        mu * preload
    );
    let crest = summary["scene"]["wave"]["tangential_velocity_m_per_s"]
        .as_f64()
        .unwrap();
    let speed = summary["no_load_speed_m_per_s"].as_f64().unwrap();
    assert!(
        speed > 0.0 && speed <= crest,
        "0 < no-load speed {speed} ≤ A_t ω = {crest}"
    );
    let efficiency = summary["efficiency"].as_f64().unwrap();
    assert!(
        efficiency > 0.0 && efficiency < 1.0,
        "efficiency in (0, 1): {efficiency}"
    );
    for stage in ["springs_s", "static_s", "dynamic_s", "total_s"] {
        assert!(
            summary["timings"][stage].as_f64().is_some(),
            "timing {stage}"
        );
    }
    for file in [
        "curve.csv",
        "speed_thrust.svg",
        "post_history.svg",
        "post_forces.svg",
        "static_snapshot0.vtu",
        "static.json",
    ] {
        assert!(folder.join(file).is_file(), "{file} written");
    }
    let csv = std::fs::read_to_string(folder.join("curve.csv")).unwrap();
    assert!(
        csv.starts_with("speed_m_per_s,thrust_n"),
        "curve CSV header"
    );
}

#[test]
fn a_failed_run_leaves_the_previous_results_untouched() {
    let out = tempfile::tempdir().unwrap();
    let out_arg = out.path().to_str().unwrap();
    sawdrive_ok(&[
        "run",
        &small_scene(),
        "--out",
        out_arg,
        "--set",
        "effective_ratio=0.5",
    ]);
    let summary_path = out.path().join("small-strip/summary.json");
    let before = std::fs::read(&summary_path).unwrap();
    // The static stage fails on a mesh that does not exist: nothing may be overwritten.
    sawdrive_err(
        &[
            "run",
            &small_scene(),
            "--out",
            out_arg,
            "--set",
            "static.mesh=/nonexistent/strip.msh",
        ],
        "/nonexistent/strip.msh",
    );
    assert_eq!(
        std::fs::read(&summary_path).unwrap(),
        before,
        "previous summary kept"
    );
    let stray: Vec<_> = std::fs::read_dir(out.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.contains("staging"))
        .collect();
    assert!(stray.is_empty(), "no staging folder left: {stray:?}");
}

#[test]
fn static_and_dynamic_stages_run_on_their_own() {
    let out = tempfile::tempdir().unwrap();
    let out_arg = out.path().to_str().unwrap();
    let report: serde_json::Value = serde_json::from_str(&sawdrive_ok(&[
        "static",
        &small_scene(),
        "--out",
        out_arg,
        "--json",
    ]))
    .unwrap();
    for key in [
        "effective_contact_ratio",
        "load_sharing",
        "contact_fraction",
        "complementarity_residual",
        "post_forces_n",
        "eta_full_contact",
    ] {
        assert!(!report[key].is_null(), "static JSON key {key}");
    }
    let (eta, eta_full) = (
        report["effective_contact_ratio"].as_f64().unwrap(),
        report["eta_full_contact"].as_f64().unwrap(),
    );
    assert!(
        eta_full < eta,
        "η at full contact ({eta_full}) below η at the scene's preload ({eta})"
    );
    let residual = report["complementarity_residual"].as_f64().unwrap();
    assert!(residual < 1e-8, "complementarity residual {residual}");
    let forces: Vec<f64> = report["post_forces_n"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_f64().unwrap())
        .collect();
    assert!(forces.iter().all(|&f| f >= 0.0), "no tension: {forces:?}");

    let result: serde_json::Value = serde_json::from_str(&sawdrive_ok(&[
        "dynamic",
        &small_scene(),
        "--out",
        out_arg,
        "--set",
        "effective_ratio=0.36",
        "--set",
        "model.dynamics=periodic-average",
        "--json",
    ]))
    .unwrap();
    for key in [
        "stall_thrust_n",
        "no_load_speed_m_per_s",
        "curve",
        "stick_fraction",
        "efficiency",
        "model",
        "wall_time_s",
    ] {
        assert!(!result[key].is_null(), "dynamic JSON key {key}");
    }
    assert_eq!(result["model"], "periodic-average");
    assert_eq!(
        result["curve"].as_array().unwrap().len(),
        50,
        "default 50 curve points"
    );
    assert!(out.path().join("small-strip/dynamic/curve.csv").is_file());
}

#[test]
fn dynamic_refuses_unphysical_input_with_the_limit() {
    sawdrive_err(
        &[
            "dynamic",
            "--set",
            "effective_ratio=0.36",
            "--set",
            "friction=-0.3",
        ],
        "friction.static",
    );
    sawdrive_err(
        &[
            "dynamic",
            "--set",
            "effective_ratio=0.36",
            "--set",
            "preload=0N",
        ],
        "load.preload",
    );
    sawdrive_err(
        &[
            "dynamic",
            "--set",
            "effective_ratio=0.36",
            "--set",
            "mass=-1mg",
        ],
        "slider.mass",
    );
    sawdrive_err(
        &[
            "dynamic",
            "--set",
            "effective_ratio=0.36",
            "--set",
            "model.lumped.integrator=post-mass",
            "--set",
            "model.lumped.time_step=5ns",
            "--set",
            "model.dynamics=transient",
        ],
        "stability",
    );
}

#[test]
fn sweep_writes_one_table_and_resumes() {
    let out = tempfile::tempdir().unwrap();
    let out_arg = out.path().to_str().unwrap();
    let sweep = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/sweeps/small-preload.toml"
    );
    let first = sawdrive_ok(&["sweep", sweep, "--out", out_arg]);
    assert!(first.contains("2 points (0 resumed)"), "{first}");
    let folder: PathBuf = out.path().join("small-preload");
    let csv = std::fs::read_to_string(folder.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "header + 2 points:\n{csv}");
    assert!(
        folder.join("stall_thrust_n_vs_preload_n.svg").is_file(),
        "chart written"
    );
    let second = sawdrive_ok(&["sweep", sweep, "--out", out_arg]);
    assert!(second.contains("2 points (2 resumed)"), "{second}");
}

#[test]
fn sweep_refuses_empty_grids_and_unwritable_folders() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "name = \"bad\"\n[grid]\npreload = []\n").unwrap();
    sawdrive_err(&["sweep", bad.to_str().unwrap()], "grid.preload is empty");
    let blocker = dir.path().join("file");
    std::fs::write(&blocker, "not a folder").unwrap();
    let sweep = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/sweeps/small-preload.toml"
    );
    sawdrive_err(
        &[
            "sweep",
            sweep,
            "--out",
            blocker.join("out").to_str().unwrap(),
        ],
        "file/out",
    );
}

#[test]
fn readme_dynamic_example_runs() {
    let out = tempfile::tempdir().unwrap();
    let json: serde_json::Value = serde_json::from_str(&sawdrive_ok(&[
        "dynamic",
        "--set",
        "preload=20N",
        "--set",
        "posts.count=50x50",
        "--set",
        "effective_ratio=0.36",
        "--json",
        "--out",
        out.path().to_str().unwrap(),
    ]))
    .unwrap();
    let stall = json["stall_thrust_n"].as_f64().unwrap();
    assert!(
        stall > 0.0 && stall <= 0.3 * 20.0 + 1e-9,
        "stall thrust {stall} ≤ μP = 6 N"
    );
}

#[test]
fn validate_stick_slip_smoke_writes_its_figures() {
    let out = tempfile::tempdir().unwrap();
    sawdrive_ok(&[
        "validate",
        "stick-slip",
        "--level",
        "smoke",
        "--out",
        out.path().to_str().unwrap(),
    ]);
    assert!(
        out.path().join("results/report.json").is_file(),
        "results/report.json"
    );
    let svgs = std::fs::read_dir(out.path().join("figures"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "svg")
        })
        .count();
    assert!(
        svgs >= 3,
        "work-precision and stability charts written, found {svgs} svg files"
    );
}

#[test]
fn validate_springs_smoke_reports_every_spring_as_json() {
    if std::process::Command::new("gmsh")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!(
            "gmsh is not installed (scripts/install-deps.sh): the punch meshes cannot be made; skipped"
        );
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let json: serde_json::Value = serde_json::from_str(&sawdrive_ok(&[
        "validate",
        "springs",
        "--level",
        "smoke",
        "--json",
        "--out",
        out.path().to_str().unwrap(),
    ]))
    .unwrap();
    let checks = json["checks"].as_array().expect("{\"checks\": [...]}");
    for spring in ["k_pn", "k_pt", "k_sn", "k_st"] {
        let check = checks
            .iter()
            .find(|c| {
                c["quantity"]
                    .as_str()
                    .is_some_and(|q| q.starts_with(spring))
            })
            .unwrap_or_else(|| panic!("check of {spring}"));
        for key in [
            "case",
            "quantity",
            "value",
            "reference",
            "tolerance",
            "pass",
            "source",
        ] {
            assert!(!check[key].is_null(), "{spring}: key {key}");
        }
        assert_eq!(check["case"], "springs");
        assert_eq!(check["pass"], true, "{spring}: {check}");
    }
    assert!(
        out.path().join("results/cases.json").is_file(),
        "cases.json written"
    );
}

#[test]
fn a_static_run_served_from_the_cache_still_writes_its_chart_and_fields() {
    let out = tempfile::tempdir().unwrap();
    let out_arg = out.path().to_str().unwrap();
    let folder = out.path().join("small-strip").join("static");
    let expected = [
        "post_forces.png",
        "post_forces.svg",
        "static.json",
        "static_snapshot0.vtu",
    ];
    for attempt in ["fresh", "cached"] {
        let text = sawdrive_ok(&["static", &small_scene(), "--out", out_arg]);
        assert_eq!(
            text.contains("(cached)"),
            attempt == "cached",
            "{attempt} run reports its cache state: {text}"
        );
        for name in expected {
            assert!(
                folder.join(name).is_file(),
                "{attempt} static run wrote {name}"
            );
        }
    }
    // A cache entry with the report only (as a sweep leaves it) is completed, not trusted.
    let cache = out.path().join(".cache");
    for entry in std::fs::read_dir(&cache).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir()
            && path
                .file_name()
                .unwrap()
                .to_str()
                .unwrap()
                .starts_with("static-")
        {
            std::fs::remove_dir_all(&path).unwrap();
        }
    }
    let text = sawdrive_ok(&["static", &small_scene(), "--out", out_arg]);
    assert!(
        !text.contains("(cached)"),
        "a report-only cache entry reruns the FEM: {text}"
    );
    for name in expected {
        assert!(folder.join(name).is_file(), "rerun wrote {name}");
    }
}
