//! Behaviour unchanged: the files of four small but real studies, compared byte for byte with
//! golden copies made before the design/UQ code was restructured.
//!
//! Each case runs the built `sawdrive` binary in an empty folder on the inputs of
//! `tests/golden/inputs/`, then compares every file it wrote under `--out` (results folders, their
//! `.sawdrive-result` markers, the FEM cache `.cache/`, the UQ samples `.uq-samples/` and the design
//! evaluations `.design-evaluations/`, whose names are content hashes) with
//! `tests/golden/<case>/`:
//! * `run`: `sawdrive run` of the default scene's cheap variant (10 × 10 posts, the committed
//!   10-post Tet4 strip mesh): strip FEM, coupled dynamics, every file of a default run;
//! * `sweep`: `sawdrive sweep` of two preloads on the same scene;
//! * `uq`: `sawdrive uq` of a 10 × 10-post slider under every kind of scatter (4 samples);
//! * `design`: `sawdrive design` of a robust two-variable design with a constraint (cheap search,
//!   confirmation, refinement, sensitivity, baseline).
//!
//! What is compared: the list of files, and for each file the SHA-256 of its bytes after two
//! normalisations, and nothing else:
//! * wall-clock values, by name: the JSON keys in [`TIMING_KEYS`] (seconds measured with a
//!   clock), the hashes of files that contain them ([`CLOCK_HASH_KEYS`]), the seconds of the
//!   design's `cost` rows (`[fidelity, count, seconds]`), and the `wall_time_s` column of CSV
//!   tables, each replaced by `"<clock>"`;
//! * the absolute path of the repository (the strip mesh's path is written into the results),
//!   replaced by `<repo>`.
//!
//! `.json` and `.csv` files are also kept whole (normalised) beside `digests.txt`, so that a
//! failure shows the first line that changed; charts (SVG, PNG) and VTU files only by digest.
//! Every path here is deterministic (seeded samples, no clock in a number), so the comparison is
//! exact. Runtime: ≈ 10 s in the test profile (the design case is the longest).
//!
//! Regenerate (only for a change of behaviour that is meant, and say so in the commit):
//! `SAWDRIVE_BLESS_GOLDEN=1 cargo test -p sawdrive-cli --test behaviour_unchanged`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use sha2::{Digest, Sha256};

/// JSON keys whose values are wall-clock durations (s).
const TIMING_KEYS: [&str; 20] = [
    "wall_time_s",
    "sample_cost_s",
    "total_s",
    "springs_s",
    "static_s",
    "dynamic_s",
    "output_s",
    "analysis_s",
    "assembly_s",
    "factor_s",
    "solve_s",
    "condensation_s",
    "contact_s",
    "mesh_s",
    "operator_s",
    "sample_operator_s",
    "normal_grid_s",
    "stall_s",
    "no_load_s",
    "points_s",
];

/// JSON keys holding the hash of a file that contains wall-clock values.
const CLOCK_HASH_KEYS: [&str; 2] = ["sha256", "report_sha256"];

/// The stand-in for a wall-clock value.
const CLOCK: &str = "\"<clock>\"";

/// Where the golden files live.
fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// The repository's root, as the binary writes it into paths.
fn repo_root() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
        .display()
        .to_string()
}

/// Length of the JSON value starting at `text[0]` (a number, string, literal or bracketed).
fn value_len(text: &str) -> usize {
    let bytes = text.as_bytes();
    match bytes.first() {
        Some(b'"') => {
            let mut i = 1;
            while i < bytes.len() && bytes[i] != b'"' {
                i += if bytes[i] == b'\\' { 2 } else { 1 };
            }
            i + 1
        }
        Some(b'[' | b'{') => {
            let (mut depth, mut i, mut in_string) = (0i32, 0, false);
            while i < bytes.len() {
                match bytes[i] {
                    b'\\' if in_string => i += 1,
                    b'"' => in_string = !in_string,
                    b'[' | b'{' if !in_string => depth += 1,
                    b']' | b'}' if !in_string => {
                        depth -= 1;
                        if depth == 0 {
                            return i + 1;
                        }
                    }
                    _ => {}
                }
                i += 1;
            }
            bytes.len()
        }
        _ => text
            .find(|c: char| c == ',' || c == '}' || c == ']' || c.is_whitespace())
            .unwrap_or(text.len()),
    }
}

/// The design's `cost` rows `[[fidelity, count, seconds], …]` with the seconds masked.
fn mask_cost_rows(array: &str) -> String {
    let mut out = String::new();
    let mut rest = array;
    while let Some(open) = rest[1..].find('[').map(|i| i + 1) {
        let len = value_len(&rest[open..]);
        let row = &rest[open..open + len];
        let last = row.rfind(',').expect("a cost row has three entries");
        let tail = &row[last + 1..row.len() - 1];
        let ws = tail.len() - tail.trim_start().len();
        let trailing = tail.len() - tail.trim_end().len();
        out.push_str(&rest[..open]);
        out.push_str(&row[..last + 1 + ws]);
        out.push_str(CLOCK);
        out.push_str(&tail[tail.len() - trailing..]);
        out.push(']');
        rest = &rest[open + len..];
    }
    out.push_str(rest);
    out
}

/// `text` (JSON) with the values of the wall-clock keys replaced by [`CLOCK`].
fn mask_json(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find('"') {
        out.push_str(&rest[..start]);
        rest = &rest[start..];
        let len = value_len(rest);
        let key = &rest[1..len - 1];
        out.push_str(&rest[..len]);
        rest = &rest[len..];
        let after = rest.trim_start();
        let Some(colon) = after.strip_prefix(':') else {
            continue;
        };
        let value = colon.trim_start();
        let head = rest.len() - value.len();
        let masked = if TIMING_KEYS.contains(&key) || CLOCK_HASH_KEYS.contains(&key) {
            Some(CLOCK.to_owned())
        } else if key == "cost" && value.starts_with('[') {
            Some(mask_cost_rows(&value[..value_len(value)]))
        } else {
            None
        };
        if let Some(m) = masked {
            out.push_str(&rest[..head]);
            out.push_str(&m);
            rest = &value[value_len(value)..];
        }
    }
    out.push_str(rest);
    out
}

/// `text` (CSV with a header) with its `wall_time_s` column replaced by [`CLOCK`].
fn mask_csv(text: &str) -> String {
    let mut lines = text.split_inclusive('\n');
    let Some(header) = lines.next() else {
        return String::new();
    };
    let Some(column) = header
        .trim_end()
        .split(',')
        .position(|c| c == "wall_time_s")
    else {
        return text.to_owned();
    };
    let mut out = header.to_owned();
    for line in lines {
        let body = line.trim_end_matches('\n');
        let mut cells: Vec<&str> = body.split(',').collect();
        if let Some(c) = cells.get_mut(column) {
            *c = CLOCK;
        }
        out.push_str(&cells.join(","));
        out.push_str(&line[body.len()..]);
    }
    out
}

/// The bytes of `path` as compared: normalised when it is text.
fn normalised(path: &Path, scratch: &str) -> Vec<u8> {
    let bytes = std::fs::read(path).unwrap();
    let Ok(text) = String::from_utf8(bytes.clone()) else {
        return bytes;
    };
    let text = text
        .replace(scratch, "<scratch>")
        .replace(&repo_root(), "<repo>");
    match path.extension().and_then(|e| e.to_str()) {
        Some("json") => mask_json(&text).into_bytes(),
        Some("csv") => mask_csv(&text).into_bytes(),
        _ => text.into_bytes(),
    }
}

/// Every file under `dir`, by path relative to it ('/'-separated), normalised.
fn files(dir: &Path, scratch: &str) -> BTreeMap<String, Vec<u8>> {
    let mut found = BTreeMap::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let rel = path.strip_prefix(dir).unwrap();
                let rel: Vec<String> = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                found.insert(rel.join("/"), normalised(&path, scratch));
            }
        }
    }
    found
}

fn digest(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Whether a file is kept whole in the golden folder (besides its digest).
fn kept_whole(rel: &str) -> bool {
    rel.ends_with(".json") || rel.ends_with(".csv")
}

/// Writes `found` as the golden copy of `case`.
fn bless(case: &str, found: &BTreeMap<String, Vec<u8>>) {
    let dir = golden_dir().join(case);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).unwrap();
    }
    std::fs::create_dir_all(&dir).unwrap();
    let mut digests = String::new();
    for (rel, bytes) in found {
        digests.push_str(&format!("{}  {rel}\n", digest(bytes)));
        if kept_whole(rel) {
            let path = dir.join("files").join(rel);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, bytes).unwrap();
        }
    }
    std::fs::write(dir.join("digests.txt"), digests).unwrap();
}

/// The first line where `actual` differs from the golden copy of `rel`, if it was kept.
fn first_difference(case: &str, rel: &str, actual: &[u8]) -> String {
    let path = golden_dir().join(case).join("files").join(rel);
    let Ok(expected) = std::fs::read_to_string(&path) else {
        return String::new();
    };
    let actual = String::from_utf8_lossy(actual);
    for (k, (e, a)) in expected.lines().zip(actual.lines()).enumerate() {
        if e != a {
            return format!("\n  line {}:\n  golden: {e}\n  now:    {a}", k + 1);
        }
    }
    format!(
        "\n  {} lines golden, {} now",
        expected.lines().count(),
        actual.lines().count()
    )
}

/// Compares `found` with the golden copy of `case`, naming every file that differs.
fn compare(case: &str, found: &BTreeMap<String, Vec<u8>>) {
    let text = std::fs::read_to_string(golden_dir().join(case).join("digests.txt"))
        .unwrap_or_else(|e| panic!("golden digests of {case}: {e} (bless them first)"));
    let golden: BTreeMap<&str, &str> = text
        .lines()
        .filter_map(|l| l.split_once("  "))
        .map(|(d, rel)| (rel, d))
        .collect();
    let mut problems = Vec::new();
    for rel in golden.keys().filter(|r| !found.contains_key(**r)) {
        problems.push(format!("{rel}: golden, not written now"));
    }
    for (rel, bytes) in found {
        match golden.get(rel.as_str()) {
            None => problems.push(format!("{rel}: written now, not in the golden set")),
            Some(d) if *d != digest(bytes) => problems.push(format!(
                "{rel}: bytes differ{}",
                first_difference(case, rel, bytes)
            )),
            Some(_) => {}
        }
    }
    assert!(
        problems.is_empty(),
        "result files of the {case} case differ from tests/golden/{case}/:\n{}",
        problems.join("\n")
    );
}

/// Runs `sawdrive ARGS --out out` in a fresh folder holding the golden inputs, then compares
/// (or, with `SAWDRIVE_BLESS_GOLDEN=1`, writes) the files under `out`.
fn check_case(case: &str, args: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let inputs = golden_dir().join("inputs");
    // The committed strip mesh beside the inputs, named relative to them: the inputs (and so
    // the sweep's point hashes) do not depend on where the repository lies.
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes/slider-strip_p40um_d20um_n10_tet4_10k.msh");
    std::fs::copy(&mesh, dir.path().join("strip.msh")).unwrap();
    for entry in std::fs::read_dir(&inputs).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path)
            .unwrap()
            .replace("\"MESH\"", "\"strip.msh\"");
        std::fs::write(dir.path().join(path.file_name().unwrap()), text).unwrap();
    }
    let output = Command::new(env!("CARGO_BIN_EXE_sawdrive"))
        .args(args)
        .args(["--out", "out"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "sawdrive {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&output.stderr)
    );
    let scratch = dir.path().canonicalize().unwrap().display().to_string();
    let found = files(&dir.path().join("out"), &scratch);
    if std::env::var_os("SAWDRIVE_BLESS_GOLDEN").is_some() {
        bless(case, &found);
    } else {
        compare(case, &found);
    }
}

#[test]
fn the_default_runs_files_are_unchanged() {
    check_case("run", &["run", "small-strip.toml"]);
}

#[test]
fn a_sweeps_files_are_unchanged() {
    check_case("sweep", &["sweep", "sweep.toml"]);
}

#[test]
fn a_uq_runs_files_are_unchanged() {
    check_case("uq", &["uq", "uq.toml", "--samples", "4", "--seed", "3"]);
}

#[test]
fn a_design_runs_files_are_unchanged() {
    check_case("design", &["design", "design.toml"]);
}

#[test]
fn wall_clock_values_are_masked_by_name_and_nothing_else() {
    let json = r#"{"wall_time_s": 1.5e-3, "stall_thrust_n": 2.0, "cost": [["a", 3, 0.25], ["b", 1, 7]], "t": {"sha256": "ab", "speed_m_per_s": [1, 2]}}"#;
    assert_eq!(
        mask_json(json),
        r#"{"wall_time_s": "<clock>", "stall_thrust_n": 2.0, "cost": [["a", 3, "<clock>"], ["b", 1, "<clock>"]], "t": {"sha256": "<clock>", "speed_m_per_s": [1, 2]}}"#,
        "masked JSON"
    );
    let pretty = "{\n  \"cost\": [\n    [\n      \"lattice-patch\",\n      9,\n      1.64\n    ]\n  ],\n  \"x\": 1\n}";
    assert_eq!(
        mask_json(pretty),
        "{\n  \"cost\": [\n    [\n      \"lattice-patch\",\n      9,\n      \"<clock>\"\n    ]\n  ],\n  \"x\": 1\n}",
        "masked pretty JSON"
    );
    let csv = "a,wall_time_s,b\n1,0.5,2\n3,0.7,4\n";
    assert_eq!(
        mask_csv(csv),
        "a,wall_time_s,b\n1,\"<clock>\",2\n3,\"<clock>\",4\n"
    );
}
