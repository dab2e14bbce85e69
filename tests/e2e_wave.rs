//! The stator's crystal cut through the command line: `sawdrive wave` for the three named cuts,
//! `--cut` over the scene's `stator.cut`, bad cuts and apertures refused in one line with
//! nothing written, `wave.phase_velocity = "auto"` changing the run, and a given value that
//! contradicts the cut reported as a warning in `dynamic --json` and `summary.json`.

mod common;

use common::{sawdrive, sawdrive_err, sawdrive_ok, small_dynamic_json, small_scene};
use saw_wave::Cut;

/// `sawdrive wave ARGS --json`, parsed.
fn wave_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["wave", "--json"];
    all.extend_from_slice(args);
    serde_json::from_str(&sawdrive_ok(&all)).expect("wave --json prints JSON")
}

fn number(json: &serde_json::Value, key: &str) -> f64 {
    json[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is a number in {json}"))
}

fn assert_close(what: &str, value: f64, expected: f64, relative: f64) {
    let rel = (value / expected - 1.0).abs();
    assert!(
        rel <= relative,
        "{what}: {value} vs {expected} (relative {rel:.2e}, allowed {relative:.0e})"
    );
}

/// A named cut: name, textbook free velocity (m/s, within 1 %), K² range of the published
/// constant sets, |u_x/u_z| and power per width at 20 nm, 9.61 MHz of crates/saw-wave/README.md.
type Expected = (&'static str, f64, (f64, f64), f64, f64);

/// The three named cuts.
const CUTS: [Expected; 3] = [
    ("128yx-linbo3", 3979.0, (0.053, 0.056), 0.898, 2447.0),
    (
        "yz-linbo3",
        3488.0,
        (0.045 * 0.9, 0.045 * 1.1),
        0.692,
        3083.0,
    ),
    ("st-x-quartz", 3158.0, (0.0011, 0.0016), 0.658, 1342.0),
];

#[test]
fn wave_json_gives_each_named_cuts_velocities_coupling_ratio_and_power() {
    for (name, textbook_velocity, (k2_lo, k2_hi), ratio, power_w_per_m) in CUTS {
        let json = wave_json(&["--cut", name]);
        assert_eq!(json["cut"], name);
        let free = number(&json, "phase_velocity_free_m_per_s");
        let metallized = number(&json, "phase_velocity_metallized_m_per_s");
        let k2 = number(&json, "coupling_k2");
        assert_close(name, free, textbook_velocity, 0.01);
        assert!(metallized < free, "{name}: metallizing slows the wave");
        assert!((k2_lo..=k2_hi).contains(&k2), "{name}: K² {k2}");
        assert!((number(&json, "displacement_ratio_ux_over_uz") - ratio).abs() < 1e-3);
        let per_width = number(&json, "power_per_width_w_per_m");
        assert_close(name, per_width, power_w_per_m, 1e-3);

        // The same numbers as the crate's, to rounding.
        let wave = Cut::from_name(name).unwrap().solve().unwrap();
        assert_eq!(json["constant_set"], constant_set(name));
        assert_close(name, free, wave.phase_velocity_free_m_per_s, 1e-12);
        assert_close(
            name,
            metallized,
            wave.phase_velocity_metallized_m_per_s,
            1e-12,
        );
        assert_close(name, k2, wave.coupling_k2, 1e-12);
        let at_scene = wave.power_per_width_w_per_m(20e-9, 9.61e6).unwrap();
        assert_close(name, per_width, at_scene, 1e-12);

        // The default scene's 4 mm post array lies inside the 9 mm beam.
        assert_close(
            name,
            number(&json, "power_under_array_w"),
            per_width * 4e-3,
            1e-12,
        );
        assert_close(
            name,
            number(&json, "power_in_beam_w"),
            per_width * 9e-3,
            1e-12,
        );
    }
}

fn constant_set(cut: &str) -> String {
    Cut::from_name(cut).unwrap().material.name
}

#[test]
fn the_default_scene_wave_matches_the_papers_motor_without_warnings() {
    let json = wave_json(&[]);
    assert_eq!(json["cut"], "128yx-linbo3");
    assert_eq!(json["scene_phase_velocity_m_per_s"], 3979.0);
    assert_eq!(json["phase_velocity_source"], "given");
    assert_eq!(json["warnings"], serde_json::json!([]));
    // 9.8 W under the 4 mm array, 22.0 W in the 9 mm beam (crates/saw-wave/README.md).
    assert!((9.7..9.9).contains(&number(&json, "power_under_array_w")));
    assert!((21.9..22.1).contains(&number(&json, "power_in_beam_w")));
    // Without --json: a short table.
    let text = sawdrive_ok(&["wave"]);
    assert!(
        text.contains("128yx-linbo3") && text.contains("power in the beam"),
        "{text}"
    );
}

#[test]
fn the_cut_flag_overrides_the_scenes_stator_cut() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("quartz.toml");
    std::fs::write(
        &scene,
        "name = \"quartz\"\n[stator]\ncut = \"st-x-quartz\"\n[wave]\naperture = \"2 mm\"\n",
    )
    .unwrap();
    let scene = scene.to_str().unwrap();
    let from_scene = wave_json(&[scene]);
    assert_eq!(from_scene["cut"], "st-x-quartz");
    assert_eq!(from_scene["constant_set"], constant_set("st-x-quartz"));
    let overridden = wave_json(&[scene, "--cut", "yz-linbo3"]);
    assert_eq!(overridden["cut"], "yz-linbo3");
    assert_close(
        "Y-Z over the scene's ST-X",
        number(&overridden, "phase_velocity_free_m_per_s"),
        3495.0,
        1e-3,
    );
    // The scene's 2 mm beam is narrower than the 4 mm array: the power under the array is the
    // beam's, and the narrow beam is a warning naming wave.aperture.
    let per_width = number(&overridden, "power_per_width_w_per_m");
    assert_close(
        "capped",
        number(&overridden, "power_under_array_w"),
        per_width * 2e-3,
        1e-12,
    );
    let keys: Vec<_> = overridden["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["parameter"].as_str().unwrap().to_owned())
        .collect();
    assert!(keys.iter().any(|k| k == "wave.aperture"), "{keys:?}");
}

/// A failed command: non-zero exit, one line on stderr naming `needle`, no results folder.
fn refused_in_one_line(args: &[&str], needle: &str) {
    let stderr = sawdrive_err(args, needle);
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
}

#[test]
fn bad_cuts_and_apertures_are_refused_in_one_line_naming_the_key_and_writing_nothing() {
    let out = tempfile::tempdir().unwrap();
    let out_dir = out.path().to_str().unwrap();
    let scene = small_scene();
    let bad = [
        ("stator.cut=36yx-litao3", "stator.cut"),
        ("stator.cut={ euler = [0, -30, 90] }", "stator.cut"),
        (
            "stator.cut={ crystal = \"gan\", euler = [0, 0, 0] }",
            "stator.cut",
        ),
        ("wave.aperture=0mm", "wave.aperture"),
        ("wave.aperture=-9mm", "wave.aperture"),
    ];
    for (set, key) in bad {
        refused_in_one_line(&["wave", "--set", set], key);
        refused_in_one_line(
            &[
                "dynamic",
                scene.as_str(),
                "--out",
                out_dir,
                "--set",
                "effective_ratio=0.36",
                "--set",
                set,
            ],
            key,
        );
        assert!(
            std::fs::read_dir(out.path()).unwrap().next().is_none(),
            "{set}: nothing written"
        );
    }
    // The unknown cut's line lists the known ones.
    let stderr = sawdrive_err(&["wave", "--cut", "36yx-litao3"], "stator.cut");
    for name in Cut::KNOWN_NAMES {
        assert!(stderr.contains(name), "{stderr} lists {name}");
    }
    let stderr = sawdrive_err(
        &["wave", "--set", "stator.cut={ euler = [0, -30, 90] }"],
        "no surface wave",
    );
    assert!(stderr.contains("leaky"), "{stderr}");
}

#[test]
fn phase_velocity_auto_takes_the_cuts_velocity_and_changes_the_run() {
    let resolved = |sets: &[&str]| -> serde_json::Value {
        let mut args = vec!["scene", "--resolve", "--json"];
        for set in sets {
            args.extend(["--set", set]);
        }
        serde_json::from_str(&sawdrive_ok(&args)).unwrap()
    };
    let given = resolved(&[]);
    let auto = resolved(&["wave.phase_velocity=auto"]);
    let cut_velocity = Cut::from_name("128yx-linbo3")
        .unwrap()
        .solve()
        .unwrap()
        .phase_velocity_free_m_per_s;
    assert_eq!(given["wave"]["phase_velocity_m_per_s"], 3979.0);
    assert_eq!(auto["wave"]["phase_velocity_m_per_s"], cut_velocity);
    assert_eq!(auto["phase_velocity_source"], "cut");
    assert_close(
        "wavelength",
        auto["wave"]["wavelength_m"].as_f64().unwrap(),
        cut_velocity / 9.61e6,
        1e-12,
    );
    // On a Y-Z stator, "auto" follows the cut: 3495 m/s.
    let yz = resolved(&["stator.cut=yz-linbo3", "wave.phase_velocity=auto"]);
    assert_close(
        "Y-Z",
        yz["wave"]["phase_velocity_m_per_s"].as_f64().unwrap(),
        3495.0,
        1e-3,
    );

    let out = tempfile::tempdir().unwrap();
    let given = small_dynamic_json(out.path(), &[]);
    let auto = small_dynamic_json(out.path(), &["wave.phase_velocity=auto"]);
    assert_ne!(
        given["curve"], auto["curve"],
        "the cut's phase velocity changes the speed–thrust curve"
    );
}

#[test]
fn a_given_value_contradicting_the_cut_is_a_warning_in_dynamic_json_and_the_summary() {
    let out = tempfile::tempdir().unwrap();
    let contradicting = "wave.phase_velocity=3600m/s";
    let json = small_dynamic_json(out.path(), &[contradicting]);
    let warnings = json["warnings"].as_array().expect("warnings array");
    let warning = warnings
        .iter()
        .find(|w| w["parameter"] == "wave.phase_velocity")
        .unwrap_or_else(|| panic!("a phase-velocity warning in {warnings:?}"));
    assert!(
        warning["message"]
            .as_str()
            .unwrap()
            .contains("128yx-linbo3"),
        "{warning}"
    );
    // The run goes on with the given value.
    let quiet = small_dynamic_json(out.path(), &[]);
    assert!(
        quiet["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .all(|w| w["parameter"] != "wave.phase_velocity"),
        "no warning within 2 %"
    );

    let scene = small_scene();
    let run = sawdrive(&[
        "run",
        scene.as_str(),
        "--out",
        out.path().to_str().unwrap(),
        "--set",
        "effective_ratio=0.36",
        "--set",
        contradicting,
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        String::from_utf8_lossy(&run.stderr).contains("warning: wave.phase_velocity"),
        "the run tells the user"
    );
    let summary: serde_json::Value = serde_json::from_slice(
        &std::fs::read(out.path().join("small-strip").join("summary.json")).unwrap(),
    )
    .unwrap();
    for pointer in ["/warnings", "/scene/warnings"] {
        let in_summary = summary
            .pointer(pointer)
            .and_then(|w| w.as_array())
            .unwrap_or_else(|| panic!("summary.json has {pointer}"));
        assert!(
            in_summary
                .iter()
                .any(|w| w["parameter"] == "wave.phase_velocity"),
            "{pointer}: {in_summary:?}"
        );
    }
}
