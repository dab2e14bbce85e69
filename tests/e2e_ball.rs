//! A ball slider through the command line: `slider.shape = "ball"` with `slider.ball_diameter`
//! runs the ball model of crate `ball-slider` in `sawdrive dynamic` and `sawdrive run`, and its
//! stall thrust and no-load speed are `ball_slider::solve`'s on the same inputs (at two wave
//! amplitudes); `sawdrive static` and what a ball does not use are refused in one line naming
//! the key, with nothing written.

mod common;

use std::path::{Path, PathBuf};

use ball_slider::{BallScene, BallSlider};
use common::{sawdrive_err, sawdrive_ok};

/// Curve points of the test runs (the crate's default is 21; 5 keep the test short).
const CURVE_POINTS: usize = 5;
/// The ball of the tests: the crate's default study ball, 2 mm at 20 mN.
const DIAMETER_M: f64 = ball_slider::DEFAULT_BALL_DIAMETER_M;
const PRELOAD_N: f64 = ball_slider::DEFAULT_PRELOAD_N;

/// A ball scene file in `dir`: the default motor's wave, stator and μ with the test's ball.
fn ball_scene_file(dir: &Path) -> PathBuf {
    let path = dir.join("ball.toml");
    std::fs::write(
        &path,
        format!(
            "name = \"ball\"\n[slider]\nshape = \"ball\"\nball_diameter = \"{} mm\"\n\
             [load]\npreload = \"{} mN\"\n[model]\ncurve_points = {CURVE_POINTS}\n",
            DIAMETER_M * 1e3,
            PRELOAD_N * 1e3
        ),
    )
    .unwrap();
    path
}

/// `ball_slider::solve` on the same inputs: the paper's motor with a steel ball, the test's
/// preload and curve points, and the normal amplitude `amplitude_m` (tangential velocity kept).
fn library(amplitude_m: f64) -> ball_slider::BallResult {
    let mut motor = motor::Motor::paper();
    motor.load.preload_n = PRELOAD_N;
    motor.wave.normal_amplitude_m = amplitude_m;
    let mut scene = BallScene::for_motor(&motor, BallSlider::steel(DIAMETER_M)).unwrap();
    scene.numerics.curve_points = CURVE_POINTS;
    ball_slider::solve(&scene).unwrap()
}

fn args_with_sets<'a>(head: &[&'a str], sets: &'a [&'a str]) -> Vec<&'a str> {
    let mut args = head.to_vec();
    for set in sets {
        args.extend(["--set", set]);
    }
    args
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

#[test]
fn a_ball_scene_reports_the_libraries_stall_thrust_and_no_load_speed_at_two_amplitudes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = ball_scene_file(dir.path());
    let scene = scene.to_str().unwrap();
    let out = dir.path().join("out");
    let out_s = out.to_str().unwrap();
    for (amplitude_m, sets) in [
        (
            motor::paper::NORMAL_AMPLITUDE_M,
            &["wave.attenuation=off"][..],
        ),
        (
            10e-9,
            &["wave.normal_amplitude=10nm", "wave.attenuation=off"][..],
        ),
    ] {
        let expected = library(amplitude_m);
        assert!(
            expected.drives,
            "the test ball is driven at {amplitude_m} m"
        );
        let args = args_with_sets(&["dynamic", scene, "--out", out_s, "--json"], sets);
        let json: serde_json::Value = serde_json::from_str(&sawdrive_ok(&args)).unwrap();
        assert_eq!(json["model"], "ball");
        assert_close(
            "stall thrust",
            number(&json, "stall_thrust_n"),
            expected.stall_thrust_n,
            1e-12,
        );
        assert_close(
            "no-load speed",
            number(&json, "no_load_speed_m_per_s"),
            expected.no_load_speed_m_per_s,
            1e-12,
        );
        assert_eq!(json["curve"].as_array().unwrap().len(), CURVE_POINTS);
        // Bounds of the physics: thrust below μP, speed below the crest speed, books closed.
        assert!(number(&json, "stall_thrust_n") < number(&json, "friction_limit_n"));
        assert!(number(&json, "no_load_speed_m_per_s") < number(&json, "crest_speed_m_per_s"));
        assert!(number(&json, "max_energy_residual") < 1e-7);
        assert_eq!(json["wave_attenuation"], "off", "as set");
        let folder = out.join("ball/dynamic");
        for file in ["dynamic.json", "curve.csv", "speed_thrust.svg"] {
            assert!(folder.join(file).is_file(), "{file} written");
        }
        let csv = std::fs::read_to_string(folder.join("curve.csv")).unwrap();
        assert_eq!(csv.lines().count(), CURVE_POINTS + 1, "header and points");
    }
    // The amplitude matters: the two runs differ.
    assert!(
        (library(10e-9).stall_thrust_n / library(20e-9).stall_thrust_n - 1.0).abs() > 0.01,
        "halving the amplitude changes the stall thrust"
    );
    // `sawdrive run` writes the same figures into summary.json.
    let run: serde_json::Value = serde_json::from_str(&sawdrive_ok(&[
        "run",
        scene,
        "--out",
        out_s,
        "--json",
        "--set",
        "wave.attenuation=off",
    ]))
    .unwrap();
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("ball/summary.json")).unwrap()).unwrap();
    let expected = library(motor::paper::NORMAL_AMPLITUDE_M);
    for json in [&run, &summary] {
        assert_eq!(json["model"], "ball");
        assert_close(
            "summary stall thrust",
            number(json, "stall_thrust_n"),
            expected.stall_thrust_n,
            1e-12,
        );
        assert_close(
            "summary no-load speed",
            number(json, "no_load_speed_m_per_s"),
            expected.no_load_speed_m_per_s,
            1e-12,
        );
        assert_eq!(json["scene"]["ball"]["diameter_m"], DIAMETER_M);
        assert_eq!(json["scene"]["ball"]["material"]["name"], "steel");
    }
}

/// The energy-conserving wave at the contact: `auto` turns it on for the test ball (it draws
/// about 10 % of the power across its contact), every curve point closes the wave's books and
/// sits at the fixed point α = √(1 − ½P_d/P_in), and the result is the library's with that wave
/// share.
#[test]
fn a_ball_on_the_energy_conserving_wave_closes_its_books_at_the_fixed_point_amplitude() {
    let dir = tempfile::tempdir().unwrap();
    let scene = ball_scene_file(dir.path());
    let out = dir.path().join("out");
    let args = [
        "dynamic",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ];
    let json: serde_json::Value = serde_json::from_str(&sawdrive_ok(&args)).unwrap();
    assert_eq!(
        json["wave_attenuation"], "on",
        "{}",
        json["wave_attenuation_reason"]
    );
    assert!(
        json["wave_attenuation_reason"]
            .as_str()
            .unwrap()
            .starts_with("auto"),
        "the reason says auto decided"
    );
    let power_in_w = number(&json, "wave_power_in_w");
    for p in json["curve"].as_array().unwrap() {
        let (stator, p_in, p_out) = (
            number(p, "stator_power_w"),
            number(p, "wave_power_in_w"),
            number(p, "wave_power_out_w"),
        );
        assert!(
            (p_in - p_out - stator).abs() <= 1e-12 * p_in,
            "books of {p}"
        );
        let alpha = number(p, "amplitude_scale");
        let fixed = (1.0 - 0.5 * stator / power_in_w).sqrt();
        assert!(
            alpha < 1.0 && (alpha - fixed).abs() < 1e-9,
            "α {alpha} vs {fixed}"
        );
    }
    let mut motor = motor::Motor::paper();
    motor.load.preload_n = PRELOAD_N;
    let mut library_scene = BallScene::for_motor(&motor, BallSlider::steel(DIAMETER_M)).unwrap();
    library_scene.numerics.curve_points = CURVE_POINTS;
    library_scene.wave_share = Some(ball_slider::WaveShare::new(power_in_w).unwrap());
    let expected = ball_slider::solve(&library_scene).unwrap();
    assert_close(
        "stall thrust",
        number(&json, "stall_thrust_n"),
        expected.stall_thrust_n,
        1e-12,
    );
    let constant = library(motor::paper::NORMAL_AMPLITUDE_M);
    assert!(
        expected.stall_thrust_n < constant.stall_thrust_n,
        "the ball that draws power sees less wave and pushes less"
    );
}

/// A failed command: non-zero exit, one line on stderr naming `key`, nothing under `out`.
fn refused(command: &str, scene: &str, out: &Path, sets: &[&str], key: &str) {
    let args = args_with_sets(&[command, scene, "--out", out.to_str().unwrap()], sets);
    let stderr = sawdrive_err(&args, key);
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert!(
        !out.exists() || std::fs::read_dir(out).unwrap().next().is_none(),
        "{sets:?}: nothing written"
    );
}

#[test]
fn bad_ball_inputs_are_refused_in_one_line_naming_the_key_and_writing_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scene = ball_scene_file(dir.path());
    let scene = scene.to_str().unwrap();
    let out = dir.path().join("out");
    let cases = [
        ("slider.ball_diameter=-2mm", "slider.ball_diameter"),
        ("slider.ball_diameter=0mm", "slider.ball_diameter"),
        ("slider.shape=cube", "slider.shape"),
        ("slider.material=brass", "slider.material"),
        ("slider.mass=-1mg", "slider.mass"),
        ("posts.count=50x50", "posts.count"),
        ("static.phases=2", "static.phases"),
        ("slider.length=3mm", "slider.length"),
        ("contact.effective_ratio=0.36", "contact.effective_ratio"),
        (
            "model.lumped.integrator=post-mass",
            "model.lumped.integrator",
        ),
        ("friction.kinetic=0.2", "friction.kinetic"),
        ("wave.decay_length=20mm", "wave.decay_length"),
        ("load.preload=-1N", "load.preload"),
    ];
    for (set, key) in cases {
        refused("dynamic", scene, &out, &[set], key);
    }
    // A ball needs its diameter; a post array refuses one.
    refused(
        "dynamic",
        scene,
        &out,
        &["slider.shape=post-array"],
        "slider.ball_diameter",
    );
    let tmp = dir.path().join("no-diameter.toml");
    std::fs::write(&tmp, "name = \"b\"\n[slider]\nshape = \"ball\"\n").unwrap();
    refused(
        "dynamic",
        tmp.to_str().unwrap(),
        &out,
        &[],
        "slider.ball_diameter",
    );
    // A ball has no static stage.
    refused("static", scene, &out, &[], "slider.shape");
}
