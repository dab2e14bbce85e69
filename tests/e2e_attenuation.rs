//! `wave.attenuation` through the command line: `auto` turns the energy-conserving wave on when
//! the posts draw more than 1 % of the wave power under the array and says why, every curve
//! point carries the wave's books (which close), `off` gives the constant wave, and the
//! combinations the models cannot honour are refused in one line naming the key.

mod common;

use common::{sawdrive_err, small_dynamic_json, small_scene};

fn number(json: &serde_json::Value, key: &str) -> f64 {
    json[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is a number in {json}"))
}

/// Largest |P_in − P_out − stator power| / P_in over the curve.
fn books_residual(run: &serde_json::Value) -> f64 {
    let curve = run["curve"].as_array().expect("a curve");
    assert!(!curve.is_empty());
    curve
        .iter()
        .map(|p| {
            let p_in = number(p, "wave_power_in_w");
            (p_in - number(p, "wave_power_out_w") - number(p, "stator_power_w")).abs() / p_in
        })
        .fold(0.0, f64::max)
}

#[test]
fn auto_attenuates_when_the_posts_draw_over_one_percent_and_the_books_close() {
    let out = tempfile::tempdir().unwrap();
    let auto = small_dynamic_json(out.path(), &[]);
    let off = small_dynamic_json(out.path(), &["wave.attenuation=off"]);
    // The small slider (0.4 mm wide) draws about 10 % of the power under its array at stall.
    assert_eq!(
        auto["wave_attenuation"], "on",
        "{}",
        auto["wave_attenuation_reason"]
    );
    let reason = auto["wave_attenuation_reason"].as_str().unwrap();
    assert!(
        reason.starts_with("auto:") && reason.contains("0.01"),
        "{reason}"
    );
    assert_eq!(off["wave_attenuation"], "off");
    assert_eq!(
        number(&auto, "wave_power_in_w"),
        number(&off, "wave_power_in_w")
    );
    assert!(
        books_residual(&auto) <= 1e-6,
        "books {}",
        books_residual(&auto)
    );
    assert!(
        books_residual(&off) <= 1e-12,
        "books {}",
        books_residual(&off)
    );
    // Attenuated, the posts never draw more than the wave brings, and less than at constant
    // amplitude; the stall thrust falls.
    for p in auto["curve"].as_array().unwrap() {
        assert!(number(p, "wave_power_out_w") >= 0.0, "{p}");
    }
    let stall_draw = |run: &serde_json::Value| number(&run["curve"][0], "stator_power_w");
    assert!(stall_draw(&auto) < stall_draw(&off));
    assert!(number(&auto, "stall_thrust_n") < number(&off, "stall_thrust_n"));
}

#[test]
fn auto_keeps_the_constant_wave_when_the_posts_draw_under_one_percent() {
    let out = tempfile::tempdir().unwrap();
    // A 100 times stronger wave (10× the amplitude carries 100× the power) at the same load:
    // the posts' draw is a small share of it.
    let strong = small_dynamic_json(out.path(), &["wave.normal_amplitude=200nm"]);
    let reason = strong["wave_attenuation_reason"].as_str().unwrap();
    let draw = number(&strong["curve"][0], "stator_power_w");
    let p_in = number(&strong, "wave_power_in_w");
    assert_eq!(
        strong["wave_attenuation"] == "on",
        draw > 0.01 * p_in,
        "{reason}"
    );
    let forced_on = small_dynamic_json(
        out.path(),
        &["wave.normal_amplitude=200nm", "wave.attenuation=on"],
    );
    assert_eq!(forced_on["wave_attenuation"], "on");
    assert_eq!(
        forced_on["wave_attenuation_reason"],
        "wave.attenuation = on"
    );
}

#[test]
fn combinations_the_models_cannot_honour_are_refused_naming_the_key() {
    let out = tempfile::tempdir().unwrap();
    let scene = small_scene();
    let dir = out.path().to_str().unwrap();
    let run = |sets: &[&str], needle: &str| {
        let mut args = vec![
            "dynamic",
            scene.as_str(),
            "--out",
            dir,
            "--set",
            "effective_ratio=0.36",
        ];
        for set in sets {
            args.extend(["--set", set]);
        }
        sawdrive_err(&args, needle)
    };
    run(&["wave.attenuation=maybe"], "wave.attenuation");
    let decay = run(
        &["wave.attenuation=on", "wave.decay_length=20mm"],
        "wave.attenuation",
    );
    assert!(decay.contains("wave.decay_length"), "{decay}");
    assert!(
        std::fs::read_dir(out.path()).unwrap().next().is_none(),
        "a refused run writes nothing"
    );
}

#[test]
fn every_dynamic_model_honours_the_energy_conserving_wave() {
    let out = tempfile::tempdir().unwrap();
    for model in ["periodic-average", "transient"] {
        let dynamics = format!("model.dynamics={model}");
        let on = small_dynamic_json(out.path(), &[&dynamics, "wave.attenuation=on"]);
        let off = small_dynamic_json(out.path(), &[&dynamics, "wave.attenuation=off"]);
        assert_eq!(on["model"], model);
        assert_eq!(on["wave_attenuation"], "on");
        assert!(
            books_residual(&on) <= 1e-6,
            "{model}: books {}",
            books_residual(&on)
        );
        for p in on["curve"].as_array().unwrap() {
            assert!(number(p, "wave_power_out_w") >= 0.0, "{model}: {p}");
        }
        assert!(
            number(&on, "stall_thrust_n") < number(&off, "stall_thrust_n"),
            "{model}: the finite wave lowers the stall thrust"
        );
    }
}

#[test]
fn the_whole_sliders_eta_is_fitted_at_the_local_amplitude_of_the_attenuated_wave() {
    let out = tempfile::tempdir().unwrap();
    let scene = small_scene();
    let dynamic = |sets: &[&str]| -> serde_json::Value {
        let mut args = vec![
            "dynamic",
            scene.as_str(),
            "--out",
            out.path().to_str().unwrap(),
        ];
        // The lumped model (`auto` may pick the coupled one, which runs every post at its own
        // amplitude instead of one η).
        args.extend(["--json", "--set", "static.model=slider"]);
        args.extend(["--set", "model.dynamics=periodic-average"]);
        for set in sets {
            args.extend(["--set", set]);
        }
        serde_json::from_str(&common::sawdrive_ok(&args)).expect("dynamic --json prints JSON")
    };
    let on = dynamic(&[]);
    assert_eq!(on["wave_attenuation"], "on");
    let local = &on["local_amplitude"];
    let (eta, eta_constant) = (
        number(local, "effective_contact_ratio"),
        number(local, "constant_wave_effective_contact_ratio"),
    );
    // A smaller wave near the trailing edge: fewer posts lift off, the whole slider's η falls
    // (on the default slider 0.653 at 20 nm, 0.523 at 10 nm).
    assert!(
        eta < eta_constant,
        "η {eta} at the local amplitude, {eta_constant} at A₀"
    );
    assert!(number(local, "passes") >= 2.0, "{local}");
    assert!(number(local, "last_change") < 1e-3, "{local}");
    let profile = local["stall_profile"]["amplitude_scale"]
        .as_array()
        .unwrap();
    let (first, last) = (
        profile[0].as_f64().unwrap(),
        profile.last().unwrap().as_f64().unwrap(),
    );
    assert!(
        first <= 1.0 && last < first,
        "the wave falls along the slider: {first} → {last}"
    );
    // Off, or with the strip's static stage, the static η stands as it is.
    let off = dynamic(&["wave.attenuation=off"]);
    assert!(off.get("local_amplitude").is_none(), "{off}");
    let strip = small_dynamic_json(out.path(), &[]);
    assert!(strip.get("local_amplitude").is_none());
    // The run's summary reports the η the curve ran at, and where it came from.
    let run: serde_json::Value = serde_json::from_str(&common::sawdrive_ok(&[
        "run",
        scene.as_str(),
        "--out",
        out.path().to_str().unwrap(),
        "--json",
        "--set",
        "static.model=slider",
        "--set",
        "model.dynamics=periodic-average",
    ]))
    .unwrap();
    assert_eq!(
        run["effective_contact_ratio_source"],
        "fem at the local amplitude"
    );
    assert_eq!(number(&run, "effective_contact_ratio"), eta);
}
