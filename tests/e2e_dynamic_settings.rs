//! Issue 11, dynamic side: every dynamic setting is honoured or refused, scenes the period average
//! cannot represent still write their files, and sizes a user sets are bounded before allocating.
//! All on the small 10 × 10-post scene with a given η (no FEM).

mod common;

use std::path::Path;

#[allow(unused_imports)]
use common::{sawdrive, sawdrive_err, sawdrive_ok};

fn small_scene() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/scenes/small-strip.toml"
    )
    .to_owned()
}

/// `sawdrive dynamic` on the small scene with η = 0.36 and `sets`; returns the parsed JSON result.
fn dynamic_json(out: &Path, sets: &[&str]) -> serde_json::Value {
    let scene = small_scene();
    let mut args = vec![
        "dynamic",
        scene.as_str(),
        "--out",
        out.to_str().unwrap(),
        "--json",
        "--set",
        "effective_ratio=0.36",
    ];
    for set in sets {
        args.extend(["--set", set]);
    }
    serde_json::from_str(&sawdrive_ok(&args)).expect("dynamic --json prints JSON")
}

/// `sawdrive dynamic` on the small scene with η = 0.36 and `sets`, expected to fail naming `needle`.
fn dynamic_err(sets: &[&str], needle: &str) -> String {
    let out = tempfile::tempdir().unwrap();
    let scene = small_scene();
    let mut args = vec![
        "dynamic",
        scene.as_str(),
        "--out",
        out.path().to_str().unwrap(),
        "--set",
        "effective_ratio=0.36",
    ];
    for set in sets {
        args.extend(["--set", set]);
    }
    let stderr = sawdrive_err(&args, needle);
    assert!(
        !out.path().join("small-strip").exists(),
        "a refused run writes nothing"
    );
    stderr
}

#[test]
fn bursts_and_decaying_waves_run_through_dynamic_and_write_their_files() {
    for set in ["wave.burst_periods=100", "wave.decay_length=20mm"] {
        let out = tempfile::tempdir().unwrap();
        let result = dynamic_json(out.path(), &[set]);
        assert_eq!(
            result["model"], "transient",
            "{set}: only the transient represents it"
        );
        let stall = result["stall_thrust_n"].as_f64().unwrap();
        assert!(
            stall > 0.0 && stall <= 0.3 * 0.4 * (1.0 + 1e-9),
            "{set}: 0 < stall thrust {stall} ≤ μP = 0.12 N"
        );
        let folder = out.path().join("small-strip/dynamic");
        for file in [
            "dynamic.json",
            "curve.csv",
            "speed_thrust.svg",
            "post_history.svg",
            "slider_history.svg",
        ] {
            assert!(folder.join(file).is_file(), "{set}: {file} written");
        }
    }
}

#[test]
fn four_billion_periods_are_refused_with_the_memory_estimate_naming_the_key() {
    let stderr = dynamic_err(
        &["model.dynamics=transient", "model.periods=4294967295"],
        "model.periods",
    );
    assert!(
        stderr.contains("bytes") && stderr.contains("limit"),
        "the refusal states the memory estimate and the limit: {stderr}"
    );
}

#[test]
fn the_regularized_integrator_is_refused_with_its_estimated_cost() {
    let stderr = dynamic_err(&["model.integrator=regularized"], "post-steps");
    assert!(
        stderr.contains("exceeds the limit") && stderr.contains("model.time_step"),
        "the refusal states the estimated cost, the limit and the keys to change: {stderr}"
    );
}
