//! End-to-end checks of the coupled dynamic model from the command line:
//! `model.dynamics = "coupled"`, the `auto` choice between lumped and coupled, the keys of
//! `sawdrive dynamic --json` and of the run summary, the compliance cache, and bad input.

mod common;

use std::path::Path;

use common::{sawdrive_err, sawdrive_ok, small_scene};

fn dynamic_json(out: &Path, sets: &[&str]) -> serde_json::Value {
    let scene = small_scene();
    let out = out.to_str().expect("utf-8 path");
    let mut args = vec!["dynamic", &scene, "--out", out, "--json"];
    for set in sets {
        args.extend(["--set", set]);
    }
    serde_json::from_str(&sawdrive_ok(&args)).expect("dynamic --json is JSON")
}

fn number(json: &serde_json::Value, key: &str) -> f64 {
    json[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is a number in {json}"))
}

#[test]
fn coupled_dynamics_reports_the_contract_keys_and_balances_energy() {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = dynamic_json(dir.path(), &["model.dynamics=coupled"]);
    assert_eq!(json["model"], "coupled", "model of the run: {json}");
    let stall = number(&json, "stall_thrust_n");
    let speed = number(&json, "no_load_speed_m_per_s");
    let friction_limit = 0.3 * 0.4;
    assert!(
        stall > 0.0 && stall <= friction_limit * (1.0 + 1e-9),
        "coupled stall thrust {stall} N within (0, μP = {friction_limit} N]"
    );
    assert!(
        speed > 0.0 && speed < 1.1,
        "coupled no-load speed {speed} m/s within (0, A_t ω)"
    );
    let residual = number(&json, "energy_balance_residual");
    assert!(
        residual < 1e-6,
        "energy balance residual {residual} of the power flow (required: < 1e-6)"
    );
    let eta_dyn = number(&json, "eta_dyn");
    assert!(eta_dyn > 0.0 && eta_dyn.is_finite(), "η_dyn {eta_dyn}");
    assert!(number(&json, "wall_time_s") > 0.0, "wall time recorded");
    assert!(
        number(&json, "lumped_error_estimate") >= 0.0,
        "the lumped model's estimated error is reported"
    );
    let step_error = number(&json, "model_error_estimate");
    assert!(
        step_error > 0.0 && step_error < 0.05,
        "the coupled run's step error estimate {step_error} is reported and small at T/64"
    );
    let curve = json["curve"].as_array().expect("curve is an array");
    assert_eq!(curve.len(), 50, "default curve points of the coupled model");
    assert_eq!(
        curve[0]["thrust_n"].as_f64(),
        Some(stall),
        "the curve starts at the stall thrust"
    );
    assert_eq!(
        json["lumped"]["model"], "periodic-average",
        "the lumped figures are reported beside the coupled ones"
    );
    let folder = dir.path().join("small-strip/dynamic");
    let histories = std::fs::read_to_string(folder.join("coupled_post_histories.csv"))
        .expect("the coupled post histories are written");
    let posts = json["posts"].as_u64().expect("posts") as usize;
    let rows = histories.lines().count() - 1;
    assert!(
        rows >= 16 * posts && rows.is_multiple_of(posts),
        "one row per post and step over a period: {rows} rows for {posts} posts"
    );
    assert!(
        folder.join("coupled_post_forces.svg").exists(),
        "the coupled post-force chart is written"
    );
    let written: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(folder.join("dynamic.json")).expect("dynamic.json"),
    )
    .expect("dynamic.json is JSON");
    assert_eq!(
        written["stall_thrust_n"], json["stall_thrust_n"],
        "dynamic.json holds the coupled result"
    );
}

#[test]
fn the_cached_strip_compliance_gives_the_same_coupled_result_bitwise() {
    let dir = tempfile::tempdir().expect("temp dir");
    let set = [
        "model.dynamics=coupled",
        "model.coupled.steps_per_period=32",
        "model.curve_points=5",
    ];
    let fresh = dynamic_json(dir.path(), &set);
    let cache = dir.path().join(".cache");
    let entries: Vec<_> = std::fs::read_dir(&cache)
        .expect("cache folder")
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with("compliance-"))
        .collect();
    assert_eq!(entries.len(), 1, "one compliance entry for one geometry");
    let cached = dynamic_json(dir.path(), &set);
    for key in ["stall_thrust_n", "no_load_speed_m_per_s", "eta_dyn"] {
        assert_eq!(
            fresh[key], cached[key],
            "{key}: fresh and cached compliance agree"
        );
    }
    assert_eq!(
        fresh["steps_per_period"].as_u64(),
        Some(32),
        "steps_per_period honoured"
    );
    assert_eq!(
        fresh["curve"].as_array().map(Vec::len),
        Some(5),
        "curve_points honoured"
    );

    // A damaged entry is recomputed, not trusted.
    let entry = entries[0].path();
    let text = std::fs::read_to_string(&entry).expect("entry");
    std::fs::write(
        &entry,
        text.replacen("\"post_x_m\":[", "\"post_x_m\":[1.0,", 1),
    )
    .expect("edit entry");
    let rebuilt = dynamic_json(dir.path(), &set);
    assert_eq!(
        fresh["stall_thrust_n"], rebuilt["stall_thrust_n"],
        "a damaged compliance entry is rebuilt"
    );
}

#[test]
fn auto_picks_the_coupled_model_only_beyond_the_lumped_tolerance() {
    let dir = tempfile::tempdir().expect("temp dir");
    let loose = dynamic_json(dir.path(), &["model.lumped_tolerance=0.99"]);
    let estimate = number(&loose, "lumped_error_estimate");
    assert!(
        estimate < 0.99,
        "estimate {estimate} below the loose tolerance"
    );
    assert_ne!(
        loose["model"], "coupled",
        "auto keeps the lumped model: {loose}"
    );
    assert!(
        loose["dynamics_reason"]
            .as_str()
            .is_some_and(|r| r.contains("lumped")),
        "auto says why: {}",
        loose["dynamics_reason"]
    );
    let tight = format!("model.lumped_tolerance={}", 0.5 * estimate);
    let strict = dynamic_json(
        dir.path(),
        &[
            &tight,
            "model.coupled.steps_per_period=32",
            "model.curve_points=5",
        ],
    );
    assert_eq!(
        strict["model"], "coupled",
        "auto runs the coupled model: {strict}"
    );
    assert_eq!(
        strict["lumped_error_estimate"], loose["lumped_error_estimate"],
        "the estimate does not depend on the tolerance"
    );
}

#[test]
fn every_run_summary_carries_the_lumped_error_estimate() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().to_str().expect("utf-8");
    let scene = small_scene();
    sawdrive_ok(&[
        "run",
        &scene,
        "--out",
        out,
        "--set",
        "model.dynamics=periodic-average",
    ]);
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("small-strip/summary.json")).expect("summary"),
    )
    .expect("summary JSON");
    assert!(
        number(&summary, "lumped_error_estimate") >= 0.0,
        "summary.json has lumped_error_estimate: {summary}"
    );
    assert_eq!(
        summary["model_error_estimate"], summary["lumped_error_estimate"],
        "the lumped run's model error is the lumped estimate"
    );
    assert_eq!(summary["model"], "periodic-average");
    assert!(
        summary["coupled"].is_null(),
        "no coupled figures without a coupled run"
    );
}

#[test]
fn coupled_settings_that_cannot_apply_are_refused_by_name() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().to_str().expect("utf-8");
    let scene = small_scene();
    let cases = [
        (
            vec!["model.dynamics=coupled", "effective_ratio=0.36"],
            "contact.effective_ratio",
        ),
        (
            vec!["model.dynamics=coupled", "model.lumped.vertical=dynamic"],
            "model.lumped.vertical",
        ),
        (
            vec!["model.dynamics=coupled", "model.coupled.steps_per_period=8"],
            "model.coupled.steps_per_period",
        ),
        (
            vec![
                "model.dynamics=transient",
                "model.coupled.steps_per_period=64",
            ],
            "model.coupled.steps_per_period",
        ),
        (
            vec!["model.dynamics=coupled", "model.lumped_tolerance=0.1"],
            "model.lumped_tolerance",
        ),
        (vec!["model.lumped_tolerance=1.5"], "model.lumped_tolerance"),
    ];
    for (sets, key) in cases {
        let mut args = vec!["dynamic", scene.as_str(), "--out", out];
        for set in &sets {
            args.extend(["--set", set]);
        }
        let stderr = sawdrive_err(&args, key);
        assert_eq!(stderr.trim().lines().count(), 1, "one-line error: {stderr}");
    }
    assert!(
        !dir.path().join("small-strip/dynamic").exists(),
        "a refused run writes no results"
    );
}

#[test]
fn a_sweep_cache_fill_stores_the_tip_compliances_so_coupled_points_need_no_second_fem() {
    let cache = tempfile::tempdir().expect("temp dir");
    let scene = small_scene();
    let scene = sawdrive::scene::load_scene(
        Some(Path::new(&scene)),
        &["model.dynamics=coupled".to_owned()],
    )
    .expect("the small scene loads");
    let (built, failures) = sawdrive::pipeline::fill_static_cache(&[scene], cache.path());
    assert_eq!((built, failures.len()), (1, 0), "one geometry condensed");
    let compliances: Vec<_> = std::fs::read_dir(cache.path())
        .expect("cache folder")
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().starts_with("compliance-"))
        .collect();
    assert_eq!(
        compliances.len(),
        1,
        "the fill stored the strip's tip compliances beside its static report"
    );
}
