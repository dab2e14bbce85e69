//! The commands shown in the README, run on small cases.

mod common;

use common::{sawdrive_err, sawdrive_ok};

#[test]
fn springs_prints_a_table_and_json_with_si_keys() {
    let table = sawdrive_ok(&["springs", "--diameter", "20um"]);
    for name in ["k_pn", "k_pt", "k_sn", "k_st", "k_n", "k_t"] {
        assert!(table.contains(name), "table row {name}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&sawdrive_ok(&["springs", "--diameter", "20um", "--json"])).unwrap();
    for key in [
        "k_pn_n_per_m",
        "k_pt_n_per_m",
        "k_sn_n_per_m",
        "k_st_n_per_m",
        "k_n_n_per_m",
        "k_t_n_per_m",
    ] {
        assert!(
            json[key].as_f64().is_some_and(|k| k > 0.0),
            "positive {key}"
        );
    }
    let k_n = json["k_n_n_per_m"].as_f64().unwrap();
    assert!(
        (k_n / 1.8e6 - 1.0).abs() < 0.03,
        "k_n of a 20 µm post ≈ 1.8e6 N/m, got {k_n}"
    );
}

#[test]
fn springs_refuses_bad_diameters_and_materials() {
    sawdrive_err(&["springs", "--diameter", "-2um"], "--diameter");
    sawdrive_err(&["springs", "--diameter", "20"], "unit is missing");
    sawdrive_err(
        &["springs", "--diameter", "20um", "--slider", "steel"],
        "--slider steel",
    );
}

#[test]
fn a_strip_wider_than_the_slider_is_refused_naming_the_key() {
    sawdrive_err(
        &["scene", "--resolve", "--set", "static.strip_rows=101"],
        "static.strip_rows",
    );
    sawdrive_err(
        &["scene", "--resolve", "--set", "static.strip_rows=0"],
        "static.strip_rows",
    );
}

#[test]
fn scene_prints_the_default_which_resolves_with_overrides() {
    let text = sawdrive_ok(&["scene"]);
    assert!(
        text.contains("9.61 MHz") && text.contains("100x100"),
        "default scene is the paper's motor"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("motor.toml");
    std::fs::write(&path, &text).unwrap();
    let resolved = sawdrive_ok(&[
        "scene",
        "--resolve",
        path.to_str().unwrap(),
        "--set",
        "preload=20N",
        "--set",
        "posts.count=50x50",
        "--json",
    ]);
    let json: serde_json::Value = serde_json::from_str(&resolved).unwrap();
    assert_eq!(
        json["load"]["preload_n"].as_f64(),
        Some(20.0),
        "preload override"
    );
    assert_eq!(
        json["posts"]["count"].as_u64(),
        Some(2500),
        "post count override"
    );
}

#[test]
fn scene_refuses_unknown_keys_in_one_line() {
    let err = sawdrive_err(
        &["scene", "--resolve", "--set", "posts.colour=red"],
        "posts.colour",
    );
    assert_eq!(err.trim_end().lines().count(), 1, "one-line error: {err}");
}

#[test]
fn mesh_info_summarises_a_committed_mesh_and_refuses_a_broken_one() {
    let mesh = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/punch_a10um_R20a_tet4_5k.msh"
    );
    let text = sawdrive_ok(&["mesh", "info", mesh]);
    assert!(
        text.contains("punch") && text.contains("far_field"),
        "physical groups by name: {text}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&sawdrive_ok(&["mesh", "info", mesh, "--json"])).unwrap();
    assert!(
        json["tet_count"].as_u64().is_some_and(|n| n > 0),
        "tet count"
    );
    assert!(
        json["volume_m3"].as_f64().is_some_and(|v| v > 0.0),
        "volume"
    );

    let dir = tempfile::tempdir().unwrap();
    let broken = dir.path().join("broken.msh");
    let bytes = std::fs::read(mesh).unwrap();
    std::fs::write(&broken, &bytes[..bytes.len() / 2]).unwrap();
    sawdrive_err(&["mesh", "info", broken.to_str().unwrap()], "broken.msh");
    sawdrive_err(&["mesh", "info", "/nonexistent.msh"], "nonexistent.msh");
}
