//! Settings, dynamic side: every dynamic setting is honoured or refused, scenes the period average
//! cannot represent still write their files, and sizes a user sets are bounded before allocating.
//! All on the small 10 × 10-post scene with a given η (no FEM).

mod common;

use std::path::Path;

use common::{sawdrive_err, sawdrive_ok, small_dynamic_json, small_scene};

/// A slider light enough (0.04 mg) that the post phases of the small scene ripple its speed by
/// ≈ 1.3e-2 of A_t ω: `auto` runs the transient, whose settings these tests exercise (with the
/// scene's own mass the ripple is 4.5e-4 and `auto` rightly runs the period average).
const LIGHT_SLIDER: &str = "slider.mass=0.04mg";

/// `sawdrive dynamic` on the small scene with η = 0.36, the light slider and `sets`; returns the
/// parsed JSON result.
fn dynamic_json(out: &Path, sets: &[&str]) -> serde_json::Value {
    let mut all = vec![LIGHT_SLIDER];
    all.extend_from_slice(sets);
    small_dynamic_json(out, &all)
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
        "--set",
        LIGHT_SLIDER,
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
        &[
            "model.dynamics=transient",
            "model.transient.periods=4294967295",
        ],
        "model.transient.periods",
    );
    assert!(
        stderr.contains("bytes") && stderr.contains("limit"),
        "the refusal states the memory estimate and the limit: {stderr}"
    );
}

#[test]
fn the_regularized_integrator_is_refused_with_its_estimated_cost() {
    let stderr = dynamic_err(&["model.lumped.integrator=regularized"], "post-steps");
    assert!(
        stderr.contains("exceeds the limit") && stderr.contains("model.lumped.time_step"),
        "the refusal states the estimated cost, the limit and the keys to change: {stderr}"
    );
}

#[test]
fn a_time_step_with_the_auto_integrator_is_honoured_or_refused_never_ignored() {
    let out = tempfile::tempdir().unwrap();
    let auto = dynamic_json(out.path(), &[]);
    let coarse = dynamic_json(out.path(), &["model.lumped.time_step=6ns"]);
    assert_eq!(
        auto["model"], "transient",
        "the small scene with a light slider runs the transient"
    );
    assert_ne!(
        auto["stall_thrust_n"], coarse["stall_thrust_n"],
        "a 6 ns step (T/17, the coarsest accepted) changes the stall thrust (it is passed to the transient's return mapping)"
    );
    let warnings = coarse["warnings"].to_string();
    assert!(
        warnings.contains("T/50"),
        "the coarse step is warned about: {warnings}"
    );
    for (step, says) in [
        ("100ns", "T/1.041"),
        ("50ns", "T/2.08"),
        ("1e-30 s", "T/16384"),
    ] {
        let stderr = dynamic_err(
            &[&format!("model.lumped.time_step={step}")],
            "model.lumped.time_step",
        );
        assert!(
            stderr.contains(says),
            "a step outside T/16384..T/16 is refused: {stderr}"
        );
    }
    // The paper motor runs the closed-form period average: no scheme takes a time step.
    let stderr = sawdrive_err(
        &[
            "dynamic",
            "--set",
            "effective_ratio=0.36",
            "--set",
            "model.lumped.time_step=1ns",
        ],
        "model.lumped.time_step",
    );
    assert!(stderr.contains("no time step"), "{stderr}");
}

#[test]
fn model_settings_the_running_model_does_not_use_are_refused_naming_the_key() {
    for (set, key) in [
        ("model.transient.periods=10", "model.transient.periods"),
        (
            "model.lumped.regularization_velocity=1mm/s",
            "model.lumped.regularization_velocity",
        ),
        (
            "model.lumped.vertical_damping_ratio=0.1",
            "model.lumped.vertical_damping_ratio",
        ),
    ] {
        sawdrive_err(
            &["dynamic", "--set", "effective_ratio=0.36", "--set", set],
            key,
        );
    }
}

#[test]
fn periods_and_curve_points_change_the_transient() {
    let out = tempfile::tempdir().unwrap();
    let short = dynamic_json(
        out.path(),
        &["model.transient.periods=40", "model.curve_points=3"],
    );
    let long = dynamic_json(
        out.path(),
        &["model.transient.periods=400", "model.curve_points=3"],
    );
    assert_ne!(
        short["curve"], long["curve"],
        "model.transient.periods changes the transient's curve"
    );
    let more = dynamic_json(
        out.path(),
        &["model.transient.periods=40", "model.curve_points=5"],
    );
    assert!(
        more["curve"].as_array().unwrap().len() > short["curve"].as_array().unwrap().len(),
        "model.curve_points sets the transient's loads"
    );
}

#[test]
fn dynamic_prints_the_estimated_work_with_its_limit() {
    let out = tempfile::tempdir().unwrap();
    let scene = small_scene();
    let stdout = sawdrive_ok(&[
        "dynamic",
        scene.as_str(),
        "--out",
        out.path().to_str().unwrap(),
        "--set",
        "effective_ratio=0.36",
        "--set",
        LIGHT_SLIDER,
    ]);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("estimated work"))
        .unwrap_or_else(|| panic!("an estimated-work line: {stdout}"));
    assert!(
        line.contains("post-steps") && line.contains("return-mapping") && line.contains("limit"),
        "estimated work names the integrator and the limit: {line}"
    );
}
