//! From volts to velocity through the command line: `wave.drive_voltage` on the `[stator.idt]`
//! transducer gives the scene's amplitude from `saw_wave::idt` (the paper's transducer at 125 V:
//! the amplitude of validation/idt, read from the library), changes the run, scales the
//! amplitude with the voltage, and puts `normal_amplitude_m`, `electrical_power_w` and
//! `overall_efficiency` into `dynamic --json` and `summary.json`; bad inputs are refused in one
//! line naming the key, with nothing written.

mod common;

use std::path::Path;

use common::{sawdrive_err, sawdrive_ok, small_scene};
use motor::Transducer;
use saw_wave::{Cut, Idt, IdtResponse, IdtSubstrate};

/// `--set` overrides giving the paper's transducer (from `motor`) and drive voltage `volts`.
fn paper_drive(volts: f64) -> Vec<String> {
    let t = Transducer::paper();
    vec![
        format!("wave.drive_voltage={volts}V"),
        format!("stator.idt.finger_pairs={}", t.finger_pairs),
        format!("stator.idt.finger_width={}m", t.finger_width_m),
        format!("stator.idt.gap={}m", t.gap_m),
        format!("stator.idt.aperture={}m", t.aperture_m),
    ]
}

/// The library's response of the paper's transducer on 128° Y-X LiNbO3 at `volts`, 9.61 MHz
/// (the scene's frequency).
fn library_response(volts: f64) -> IdtResponse {
    let t = Transducer::paper();
    let idt = Idt {
        finger_pairs: t.finger_pairs,
        finger_width_m: t.finger_width_m,
        gap_m: t.gap_m,
        aperture_m: t.aperture_m,
        metallisation: None,
    };
    let substrate = IdtSubstrate::from_cut(&Cut::from_name("128yx-linbo3").unwrap()).unwrap();
    idt.drive(&substrate, volts, motor::paper::FREQUENCY_HZ)
        .unwrap()
}

fn with_sets(head: &[&str], sets: &[String]) -> Vec<String> {
    let mut args: Vec<String> = head.iter().map(|s| (*s).to_owned()).collect();
    for set in sets {
        args.push("--set".into());
        args.push(set.clone());
    }
    args
}

fn json_of(args: &[String]) -> serde_json::Value {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    serde_json::from_str(&sawdrive_ok(&args)).expect("the command prints JSON")
}

fn number(json: &serde_json::Value, key: &str) -> f64 {
    json[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is a number in the JSON"))
}

fn assert_close(what: &str, value: f64, expected: f64, relative: f64) {
    let rel = (value / expected - 1.0).abs();
    assert!(
        rel <= relative,
        "{what}: {value} vs {expected} (relative {rel:.2e}, allowed {relative:.0e})"
    );
}

fn parameters(warnings: &serde_json::Value) -> Vec<String> {
    warnings
        .as_array()
        .expect("warnings are a list")
        .iter()
        .map(|w| w["parameter"].as_str().unwrap().to_owned())
        .collect()
}

#[test]
fn the_papers_transducer_at_125_v_gives_the_studys_amplitude_and_power() {
    let volts = motor::paper::DRIVE_VOLTAGE_PEAK_V;
    let expected = library_response(volts);
    let scene = json_of(&with_sets(
        &["scene", "--resolve", "--json"],
        &paper_drive(volts),
    ));
    let amplitude = scene["wave"]["normal_amplitude_m"].as_f64().unwrap();
    assert_close(
        "normal amplitude",
        amplitude,
        expected.amplitude_uz_m,
        1e-12,
    );
    let drive = &scene["drive"];
    assert_close(
        "electrical input power",
        number(drive, "electrical_input_power_w"),
        expected.input_power_w,
        1e-12,
    );
    assert_close(
        "acoustic power per direction",
        number(drive, "acoustic_power_per_direction_w"),
        expected.acoustic_power_per_direction_w,
        1e-12,
    );
    assert_close(
        "f0",
        number(drive, "synchronous_frequency_hz"),
        expected.admittance.synchronous_frequency_hz,
        1e-12,
    );
    // The tangential amplitude is the cut's ratio times the launched one ("auto").
    assert_close(
        "tangential amplitude",
        scene["wave"]["tangential_amplitude_m"].as_f64().unwrap(),
        expected.amplitude_ux_m,
        1e-12,
    );
    assert_eq!(scene["tangential_amplitude_source"], "cut");
    // The model's caveats are warnings naming the key to change: 20 pairs on 128° Y-X are
    // strongly coupled, and 9.61 MHz is 3.8 % off the 400 µm period's f0.
    let keys = parameters(&scene["warnings"]);
    assert!(
        keys.iter().any(|k| k == "stator.idt.finger_pairs"),
        "{keys:?}"
    );
    assert!(keys.iter().any(|k| k == "wave.frequency"), "{keys:?}");
    // `sawdrive wave` prints the transducer's figures too.
    let wave = json_of(&with_sets(&["wave", "--json"], &paper_drive(volts)));
    assert_close(
        "wave --json amplitude",
        number(&wave, "normal_amplitude_m"),
        expected.amplitude_uz_m,
        1e-12,
    );
    assert_close(
        "wave --json transducer current",
        number(&wave["transducer"], "current_peak_a"),
        expected.current_peak_a,
        1e-12,
    );
    // The acoustic power each way is what the wave of that amplitude carries in the beam.
    assert_close(
        "books: beam power = acoustic power per direction",
        number(&wave, "power_in_beam_w"),
        expected.acoustic_power_per_direction_w,
        1e-9,
    );
    let text = sawdrive_ok(
        &with_sets(&["wave"], &paper_drive(volts))
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    assert!(text.contains("electrical input power"), "{text}");
}

/// `sawdrive dynamic --json` of the small scene at η = 0.36 with `sets`.
fn dynamic_json(out: &Path, sets: &[String]) -> serde_json::Value {
    let scene = small_scene();
    let mut all = vec!["effective_ratio=0.36".to_owned()];
    all.extend_from_slice(sets);
    json_of(&with_sets(
        &[
            "dynamic",
            scene.as_str(),
            "--out",
            out.to_str().unwrap(),
            "--json",
        ],
        &all,
    ))
}

#[test]
fn a_drive_voltage_changes_the_run_and_twice_the_voltage_gives_twice_the_amplitude() {
    let out = tempfile::tempdir().unwrap();
    let plain = dynamic_json(out.path(), &[]);
    for key in [
        "normal_amplitude_m",
        "electrical_power_w",
        "overall_efficiency",
    ] {
        assert!(plain.get(key).is_none(), "{key} only with a drive voltage");
    }
    let at_125 = dynamic_json(out.path(), &paper_drive(125.0));
    let at_250 = dynamic_json(out.path(), &paper_drive(250.0));
    let expected = library_response(125.0);
    assert_close(
        "amplitude at 125 V",
        number(&at_125, "normal_amplitude_m"),
        expected.amplitude_uz_m,
        1e-12,
    );
    assert_close(
        "2× voltage → 2× amplitude",
        number(&at_250, "normal_amplitude_m"),
        2.0 * number(&at_125, "normal_amplitude_m"),
        1e-12,
    );
    assert_close(
        "2× voltage → 4× electrical power",
        number(&at_250, "electrical_power_w"),
        4.0 * number(&at_125, "electrical_power_w"),
        1e-12,
    );
    // The drive's wave (7.3 nm) is not the default 20 nm: the run changes.
    let (stall_plain, stall_driven) = (
        number(&plain, "stall_thrust_n"),
        number(&at_125, "stall_thrust_n"),
    );
    assert!(
        (stall_driven / stall_plain - 1.0).abs() > 0.05,
        "stall thrust {stall_driven} N with the drive vs {stall_plain} N at 20 nm"
    );
    // Overall efficiency: the largest mechanical output along the curve over P_in, and the
    // books: no more than the power launched towards the slider (half of the acoustic power).
    for run in [&at_125, &at_250] {
        let curve = run["curve"].as_array().unwrap();
        let max_output = curve
            .iter()
            .map(|p| p["output_power_w"].as_f64().unwrap())
            .fold(0.0, f64::max);
        let p_in = number(run, "electrical_power_w");
        assert_close(
            "overall efficiency",
            number(run, "overall_efficiency"),
            max_output / p_in,
            1e-12,
        );
        assert!(
            number(run, "overall_efficiency") > 0.0 && number(run, "overall_efficiency") < 0.5,
            "0 < overall efficiency < ½ (one direction of the wave drives)"
        );
    }
    // summary.json of `sawdrive run` carries the same figures.
    let scene = small_scene();
    let mut sets = vec!["effective_ratio=0.36".to_owned()];
    sets.extend(paper_drive(125.0));
    let run = json_of(&with_sets(
        &[
            "run",
            scene.as_str(),
            "--out",
            out.path().to_str().unwrap(),
            "--json",
        ],
        &sets,
    ));
    let summary: serde_json::Value = serde_json::from_slice(
        &std::fs::read(out.path().join("small-strip/summary.json")).unwrap(),
    )
    .unwrap();
    for json in [&run, &summary] {
        assert_close(
            "summary amplitude",
            number(json, "normal_amplitude_m"),
            expected.amplitude_uz_m,
            1e-12,
        );
        assert_close(
            "summary electrical power",
            number(json, "electrical_power_w"),
            expected.input_power_w,
            1e-12,
        );
        assert!(number(json, "overall_efficiency") > 0.0);
        assert!(
            parameters(&json["warnings"])
                .iter()
                .any(|k| k == "wave.frequency"),
            "the detuning warning reaches the summary"
        );
    }
}

/// A failed `dynamic`: non-zero exit, one line on stderr naming `key`, nothing under `out`.
fn refused(out: &Path, scene: &str, sets: &[String], key: &str) {
    let mut all = vec!["effective_ratio=0.36".to_owned()];
    all.extend_from_slice(sets);
    let args = with_sets(&["dynamic", scene, "--out", out.to_str().unwrap()], &all);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let stderr = sawdrive_err(&args, key);
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert!(
        std::fs::read_dir(out).unwrap().next().is_none(),
        "{sets:?}: nothing written"
    );
}

#[test]
fn bad_drive_inputs_are_refused_in_one_line_naming_the_key_and_writing_nothing() {
    let out = tempfile::tempdir().unwrap();
    let small = small_scene();
    let drive = paper_drive(125.0);
    let replaced = |key: &str, value: &str| -> Vec<String> {
        drive
            .iter()
            .map(|s| match s.split_once('=') {
                Some((k, _)) if k == key => format!("{key}={value}"),
                _ => s.clone(),
            })
            .collect()
    };
    let with_extra = |extra: &str| {
        let mut sets = drive.clone();
        sets.push(extra.to_owned());
        sets
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["wave.drive_voltage=125V".into()], "wave.drive_voltage"),
        (
            replaced("stator.idt.finger_width", "-100um"),
            "stator.idt.finger_width",
        ),
        (
            replaced("stator.idt.finger_pairs", "0"),
            "stator.idt.finger_pairs",
        ),
        (
            replaced("stator.idt.aperture", "-9mm"),
            "stator.idt.aperture",
        ),
        (replaced("wave.drive_voltage", "125"), "wave.drive_voltage"),
        (
            replaced("wave.drive_voltage", "-125V"),
            "wave.drive_voltage",
        ),
        (
            with_extra("wave.tangential_velocity=1.1m/s"),
            "wave.tangential_velocity",
        ),
        (with_extra("stator.idt.fingers=3"), "stator.idt"),
        (
            with_extra("stator.idt.metallisation={ metal = \"lead\", thickness = \"100 nm\" }"),
            "stator.idt.metallisation.metal",
        ),
        (drive[1..].to_vec(), "stator.idt"),
    ];
    for (sets, key) in &cases {
        refused(out.path(), &small, sets, key);
    }
    // Both the amplitude and the voltage in one scene: refused naming both.
    let dir = tempfile::tempdir().unwrap();
    let both = dir.path().join("both.toml");
    std::fs::write(
        &both,
        "name = \"both\"\n[wave]\nnormal_amplitude = \"20 nm\"\ndrive_voltage = \"125 V\"\n\
         [stator.idt]\nfinger_pairs = 20\nfinger_width = \"100 um\"\ngap = \"100 um\"\n\
         aperture = \"9 mm\"\n",
    )
    .unwrap();
    let stderr = sawdrive_err(
        &["scene", "--resolve", both.to_str().unwrap()],
        "wave.normal_amplitude, wave.drive_voltage",
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    refused(
        out.path(),
        both.to_str().unwrap(),
        &[],
        "wave.normal_amplitude, wave.drive_voltage",
    );
}
