//! Fuzz targets (proptest) for every input file besides the scene: sweep files, design files,
//! scatter sections, height maps and `--shard`. Each must give a value or a named error, never a
//! panic; what it accepts must be safe (a name that is one path component, a bounded grid).
//!
//! The case count is bounded so that the targets run in seconds in every `cargo test`; run them
//! longer with `PROPTEST_CASES=20000 cargo test --release -p sawdrive --test fuzz_inputs`.

use std::path::Path;

use design::scatter::load_uq_inputs;
use design::study::DesignSpec;
use proptest::prelude::*;
use sawdrive::pipeline::evaluate::SceneEvaluator;
use sawdrive::sweep::{MAX_SWEEP_POINTS, Shard, SweepFile};
use slider_contact::HeightMapCsv;

/// Cases per property in the default test run (each parses one small file; < 1 ms).
/// `PROPTEST_CASES` overrides it.
const DEFAULT_CASES: u32 = 256;

fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    ProptestConfig::with_cases(cases)
}

/// Strings as people and attackers write them: paths, dots, control characters, units.
fn text() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "",
            ".",
            "..",
            "../x",
            "/abs",
            ".cache",
            "a/b",
            "ok-name",
            "a\u{1b}[2J",
            "x\ny",
            "20 um",
            "1 m",
            "-5 N",
            "1e300",
            "nan",
            "auto",
            "100000x100000",
            "=cmd()",
        ])
        .prop_map(String::from),
        "[ -~]{0,12}",
        any::<String>(),
    ]
}

/// A TOML value: a number, a string or a short list of them.
fn value() -> impl Strategy<Value = String> {
    let scalar = prop_oneof![
        any::<f64>().prop_map(|x| format!("{x:e}")),
        any::<i64>().prop_map(|x| x.to_string()),
        text().prop_map(|t| format!("{t:?}")),
    ];
    prop_oneof![
        scalar.clone(),
        prop::collection::vec(scalar, 0..4).prop_map(|v| format!("[{}]", v.join(", "))),
    ]
}

/// Keys the input formats know, and some they do not.
fn key() -> impl Strategy<Value = String> {
    prop::sample::select(vec![
        "preload",
        "friction",
        "posts.diameter",
        "posts.count",
        "post_diameter",
        "posts_per_side",
        "samples",
        "cheap_samples",
        "quantile",
        "name",
        "file",
        "series",
        "label",
        "height",
        "tilt",
        "unknown_key",
    ])
    .prop_map(String::from)
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn sweep_files_load_or_are_refused_and_what_loads_is_safe(
        name in text(),
        grid in prop::collection::vec((key(), value()), 0..4),
        chart_file in text(),
        series in key(),
        labels in prop::collection::vec(text(), 0..3),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut toml = format!("name = {name:?}\n[grid]\n");
        for (k, v) in &grid {
            toml.push_str(&format!("{k:?} = {v}\n"));
        }
        for label in &labels {
            toml.push_str(&format!("[[variants]]\nlabel = {label:?}\nset = {{}}\n"));
        }
        toml.push_str(&format!(
            "[[charts]]\nx = \"preload_n\"\ny = \"stall_thrust_n\"\nfile = {chart_file:?}\nseries = {series:?}\n"
        ));
        if let Ok(sweep) = SweepFile::load(&write(dir.path(), "s.toml", &toml)) {
            prop_assert!(atomic_files::check_name(&sweep.name).is_ok());
            prop_assert!(sweep.points().len() <= MAX_SWEEP_POINTS);
        }
    }

    #[test]
    fn design_files_parse_or_are_refused_naming_a_key(
        name in text(),
        entries in prop::collection::vec((key(), value()), 0..5),
        variables in prop::collection::vec((key(), value()), 0..3),
    ) {
        let mut toml = format!("name = {name:?}\n");
        for (k, v) in &entries {
            toml.push_str(&format!("{k} = {v}\n"));
        }
        toml.push_str("[variables]\n");
        for (k, v) in &variables {
            toml.push_str(&format!("{k} = {v}\n"));
        }
        if let Ok(spec) = DesignSpec::parse(&SceneEvaluator, &toml, Path::new(".")) {
            prop_assert!(atomic_files::check_name(&spec.name).is_ok());
            prop_assert!(spec.cheap_samples <= spec.samples);
        }
    }

    #[test]
    fn scatter_sections_load_or_are_refused(
        entries in prop::collection::vec((key(), value()), 0..5),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut toml = String::from("[scatter]\n");
        for (k, v) in &entries {
            toml.push_str(&format!("{k:?} = {v}\n"));
        }
        let _ = load_uq_inputs(&SceneEvaluator, Some(&write(dir.path(), "u.toml", &toml)), &[]);
    }

    #[test]
    fn height_maps_parse_or_are_refused(
        lines in prop::collection::vec(
            (any::<i64>(), any::<i64>(), value()), 0..12),
        header in text(),
        (nx, ny) in (0usize..5, 0usize..5),
    ) {
        let mut csv = format!("{header}\n");
        for (r, c, h) in &lines {
            csv.push_str(&format!("{r},{c},{h}\n"));
        }
        if let Ok(map) = <motor::HeightMap as HeightMapCsv>::parse(&csv, "map.csv", nx, ny) {
            prop_assert_eq!(map.height_m.len(), nx * ny);
            prop_assert!(map.height_m.iter().all(|h| h.is_finite()));
        }
    }

    #[test]
    fn shard_arguments_parse_or_are_refused(text in text()) {
        if let Ok(shard) = text.parse::<Shard>() {
            // Asking a parsed shard (even 0/0, refused later against the sweep) which points
            // it owns never panics, and a shard K of N ≥ K owns point K - 1.
            let owns_first = shard.owns(shard.index.wrapping_sub(1));
            prop_assert_eq!(owns_first, (1..=shard.count).contains(&shard.index));
        }
    }
}
