//! Fuzz target (proptest) for the scene parser: random TOML values, units and `--set` strings on
//! every key of the default scene must give a scene or a `SceneError`, never a panic.
//!
//! The case count is bounded so that the target runs in seconds in every `cargo test`; run it
//! longer with `PROPTEST_CASES=20000 cargo test --release -p sawdrive --test fuzz_scene`.

use std::io::Write;

use proptest::prelude::*;
use sawdrive::scene::{DEFAULT_SCENE_TOML, load_scene};

/// Cases per property in the default test run (each is a parse of the default scene plus one file
/// or override; ≈ 1 ms). `PROPTEST_CASES` overrides it.
const DEFAULT_CASES: u32 = 256;

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES)
}

/// Every `section.key` of the default scene (plus the documented short names).
fn scene_keys() -> Vec<String> {
    let table: toml::Table = DEFAULT_SCENE_TOML.parse().expect("default scene parses");
    let mut keys: Vec<String> = ["preload", "load", "friction", "effective_ratio", "mass"]
        .map(String::from)
        .to_vec();
    for (section, value) in &table {
        match value.as_table() {
            Some(inner) => keys.extend(inner.keys().map(|k| format!("{section}.{k}"))),
            None => keys.push(section.clone()),
        }
    }
    keys
}

/// Numbers as people (and attackers) write them: edge magnitudes, signs, hex, underscores.
fn number_text() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<f64>().prop_map(|x| format!("{x:e}")),
        any::<i64>().prop_map(|x| x.to_string()),
        prop::sample::select(vec![
            "0",
            "-0",
            "1e308",
            "1e309",
            "4.9e-324",
            "-1",
            "0x5",
            "0b11",
            "1_000",
            "nan",
            "inf",
            "-inf",
            "1e-400",
            "18446744073709551616",
            "4294967295",
            "5x5",
            "0x0",
            "100x",
            "x100",
            "",
            " ",
            "1..2",
            "--1",
            "1e",
            ".",
            "１２",
        ])
        .prop_map(String::from),
    ]
}

/// Units, valid, misspelt and hostile.
fn unit_text() -> impl Strategy<Value = String> {
    prop::sample::select(vec![
        "",
        "um",
        "µm",
        "mm",
        "m",
        "nm",
        "MHz",
        "Hz",
        "GHz",
        "N",
        "mN",
        "kN",
        "m/s",
        "GPa",
        "Pa",
        "kg/m3",
        "mg",
        "kg",
        "s",
        "us",
        "%",
        "deg",
        "rad",
        "u m",
        "MHZ",
        "\u{1b}[31m",
        "\n",
        "N N",
    ])
    .prop_map(String::from)
}

/// A TOML value for a scene key: quantity strings, bare numbers, booleans, strings, arrays, tables.
fn toml_value() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (number_text(), unit_text(), any::<bool>())
            .prop_map(|(n, u, space)| format!("{:?}", if space { format!("{n} {u}") } else { format!("{n}{u}") })),
        2 => number_text().prop_filter("bare TOML number", |n| n.parse::<f64>().is_ok()),
        1 => any::<bool>().prop_map(|b| b.to_string()),
        1 => "[a-z0-9 ._/-]{0,12}".prop_map(|s| format!("{s:?}")),
        1 => Just("[1, \"2 um\"]".to_owned()),
        1 => Just("{ kind = \"x\" }".to_owned()),
        1 => Just("\"auto\"".to_owned()),
        1 => Just("\"fem\"".to_owned()),
    ]
}

/// One `--set` override: a scene key or noise, `=`, a value with or without a unit.
fn override_text(keys: Vec<String>) -> impl Strategy<Value = String> {
    let key = prop_oneof![
        4 => prop::sample::select(keys),
        1 => "[a-z._=]{0,10}",
    ];
    let value = prop_oneof![
        (number_text(), unit_text()).prop_map(|(n, u)| format!("{n}{u}")),
        "\\PC{0,12}",
    ];
    (key, prop::sample::select(vec!["=", "==", " = ", ""]), value)
        .prop_map(|(k, eq, v)| format!("{k}{eq}{v}"))
}

/// Write `text` as a scene file and load it with `overrides`.
fn load_text(text: &str, overrides: &[String]) {
    let mut file = tempfile::Builder::new().suffix(".toml").tempfile().unwrap();
    file.write_all(text.as_bytes()).unwrap();
    // Ok or Err(SceneError): both fine; a panic fails the property.
    let _ = load_scene(Some(file.path()), overrides);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_values_for_scene_keys_are_a_scene_or_an_error(
        picks in proptest::collection::vec((any::<prop::sample::Index>(), toml_value()), 1..4),
    ) {
        let keys = scene_keys();
        // Top-level keys first, then one [section] per section (valid TOML structure, so the
        // values reach the scene checks).
        let mut top = String::new();
        let mut sections: std::collections::BTreeMap<String, String> = Default::default();
        for (index, value) in picks {
            let key = &keys[index.index(keys.len())];
            match key.split_once('.') {
                Some((section, name)) => sections
                    .entry(section.to_owned())
                    .or_default()
                    .push_str(&format!("{name} = {value}\n")),
                None => top.push_str(&format!("{key} = {value}\n")),
            }
        }
        for (section, lines) in sections {
            top.push_str(&format!("[{section}]\n{lines}"));
        }
        load_text(&top, &[]);
    }

    #[test]
    fn random_set_overrides_are_a_scene_or_an_error(
        overrides in proptest::collection::vec(override_text(scene_keys()), 1..4),
    ) {
        let _ = load_scene(None, &overrides);
    }

    #[test]
    fn random_text_as_a_scene_file_is_a_scene_or_an_error(text in "\\PC{0,200}") {
        load_text(&text, &[]);
    }

    #[test]
    fn default_scene_with_random_lines_cut_is_a_scene_or_an_error(
        drops in proptest::collection::vec(any::<prop::sample::Index>(), 1..6),
    ) {
        let mut lines: Vec<&str> = DEFAULT_SCENE_TOML.lines().collect();
        for drop in drops {
            if !lines.is_empty() {
                lines.remove(drop.index(lines.len()));
            }
        }
        load_text(&lines.join("\n"), &[]);
    }
}
