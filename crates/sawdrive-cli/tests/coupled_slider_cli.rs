//! The coupled model of every post of the whole slider through `sawdrive dynamic`
//! (`static.model = "slider"`): the contract's JSON keys, its files (the strip's coupled files
//! plus the three 2D maps), the `auto` choice with its reason, and the energy-conserving wave
//! under every post (its books closed, the amplitude map written).
//!
//! Scene: a small slider of 12 × 12 posts of the default post cell (20 µm at 40 µm) on a 0.5 mm
//! square body, the paper's 4 mN a post, Tet4 for the near field's one-off strip FEM,
//! 32 steps per period and 4 curve points (the run takes about a second).

use std::path::Path;
use std::process::{Command, Output};

const SCENE: &str = r#"
name = "small-slider"
[slider]
length = "0.5 mm"
width = "0.5 mm"
[posts]
count = "12x12"
array = "0.48 mm"
[load]
preload = "0.576 N"
[static]
element_order = 1
model = "slider"
[model]
curve_points = 4
[model.coupled]
steps_per_period = 32
"#;

fn sawdrive(dir: &Path, sets: &[&str]) -> Output {
    let scene = dir.join("small-slider.toml");
    std::fs::write(&scene, SCENE).expect("scene file");
    let mut command = Command::new(env!("CARGO_BIN_EXE_sawdrive"));
    command
        .arg("dynamic")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--json");
    for set in sets {
        command.args(["--set", set]);
    }
    command.output().expect("sawdrive binary runs")
}

fn json_ok(dir: &Path, sets: &[&str]) -> serde_json::Value {
    let out = sawdrive(dir, sets);
    assert!(
        out.status.success(),
        "sawdrive dynamic {sets:?} fails: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("dynamic --json prints JSON")
}

fn number(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is a number in {v}"))
}

#[test]
fn the_whole_sliders_coupled_model_prints_the_contract_and_writes_its_maps() {
    let dir = tempfile::tempdir().unwrap();
    let json = json_ok(dir.path(), &["model.dynamics=coupled"]);
    assert_eq!(json["model"], "coupled");
    assert_eq!(
        json["coupled_posts"], 144,
        "every post of the 12 × 12 slider"
    );
    assert_eq!(json["coupled_slider"]["posts_x"], 12);
    let stall = number(&json, "stall_thrust_n");
    let lumped_stall = number(&json["lumped"], "stall_thrust_n");
    assert!(
        stall > 0.0 && (stall / lumped_stall - 1.0).abs() < 0.1,
        "stall thrust {stall} N against the lumped model's {lumped_stall} N"
    );
    let crest = 1.1;
    let v0 = number(&json, "no_load_speed_m_per_s");
    assert!(v0 > 0.0 && v0 < crest, "no-load speed {v0} m/s");
    assert!(
        number(&json, "energy_balance_residual") < 1e-12,
        "energy balance residual {}",
        json["energy_balance_residual"]
    );
    let eta_dyn = number(&json, "eta_dyn");
    assert!(eta_dyn > 0.0 && eta_dyn < 1.5, "eta_dyn {eta_dyn}");
    assert!(number(&json, "wall_time_s") > 0.0);
    assert!(
        json["dynamics_reason"]
            .as_str()
            .unwrap()
            .contains("whole slider"),
        "{}",
        json["dynamics_reason"]
    );
    let folder = dir.path().join("out/small-slider/dynamic");
    for file in [
        "dynamic.json",
        "curve.csv",
        "speed_thrust.svg",
        "coupled_post_histories.csv",
        "coupled_map_mean_normal_force.svg",
        "coupled_map_slip_fraction.svg",
        "coupled_map_friction_power.svg",
        "coupled_post_means_stall.csv",
        "coupled_post_means_half_no_load.csv",
    ] {
        assert!(folder.join(file).is_file(), "{file} written");
    }
    let means = std::fs::read_to_string(folder.join("coupled_post_means_stall.csv")).unwrap();
    assert_eq!(means.lines().count(), 1 + 144, "one row per post");
}

#[test]
fn auto_on_the_whole_slider_estimates_the_lumped_error_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let loose = json_ok(dir.path(), &["model.lumped_tolerance=0.9"]);
    assert_eq!(loose["model"], "periodic-average");
    let estimate = number(&loose, "lumped_error_estimate");
    let reason = loose["dynamics_reason"].as_str().unwrap();
    assert!(
        reason.contains("whole slider") && reason.contains("lumped: estimated error"),
        "{reason}"
    );
    let tolerance = format!("model.lumped_tolerance={}", 0.5 * estimate);
    let tight = json_ok(dir.path(), &[&tolerance, "wave.attenuation=off"]);
    assert_eq!(tight["model"], "coupled", "{}", tight["dynamics_reason"]);
    assert_eq!(tight["coupled_posts"], 144);
    // The small slider's posts draw 14 % of the wave's power at stall: `auto` turns the
    // energy-conserving wave on, and the whole slider's coupled model runs on it.
    let attenuated = json_ok(dir.path(), &[&tolerance]);
    assert_eq!(attenuated["model"], "coupled");
    assert_eq!(attenuated["wave_attenuation"], "on");
    let reason = attenuated["dynamics_reason"].as_str().unwrap();
    assert!(
        reason.contains("coupled: the lumped model's estimated error"),
        "{reason}"
    );
}

#[test]
fn the_whole_sliders_coupled_model_runs_on_the_energy_conserving_wave_and_closes_its_books() {
    let dir = tempfile::tempdir().unwrap();
    let off = json_ok(
        dir.path(),
        &["model.dynamics=coupled", "wave.attenuation=off"],
    );
    let on = json_ok(
        dir.path(),
        &["model.dynamics=coupled", "wave.attenuation=on"],
    );
    assert_eq!(on["model"], "coupled");
    assert_eq!(on["wave_attenuation"], "on");
    assert_eq!(off["wave_attenuation"], "off");
    let p_in = number(&on, "wave_power_in_w");
    for point in on["curve"].as_array().unwrap() {
        let (stator, out) = (
            number(point, "stator_power_w"),
            number(point, "wave_power_out_w"),
        );
        assert!(
            stator < p_in,
            "the posts draw {stator} W of the wave's {p_in} W"
        );
        assert!(
            (p_in - out - stator).abs() <= 1e-9 * p_in,
            "books: P_in {p_in} − P_out {out} vs stator power {stator} W"
        );
    }
    assert!(
        number(&on, "stall_thrust_n") < number(&off, "stall_thrust_n"),
        "less wave under the trailing posts, less thrust"
    );
    assert_eq!(
        on["eta_dyn"], off["eta_dyn"],
        "η_dyn is the constant wave's"
    );
    let folder = dir.path().join("out/small-slider/dynamic");
    assert!(folder.join("coupled_map_amplitude_scale.svg").is_file());
    let means = std::fs::read_to_string(folder.join("coupled_post_means_stall.csv")).unwrap();
    let header: Vec<&str> = means.lines().next().unwrap().split(',').collect();
    let column = header.iter().position(|c| *c == "amplitude_scale").unwrap();
    let trailing: f64 = means
        .lines()
        .last()
        .unwrap()
        .split(',')
        .nth(column)
        .unwrap()
        .parse()
        .unwrap();
    assert!(trailing < 1.0, "the trailing post's amplitude {trailing}");
}
