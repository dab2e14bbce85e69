//! The tutorial (`docs/tutorial.md`) as a test: its ```` ```sh tutorial ```` blocks are run in
//! order, in one empty folder, with `sawdrive` on the PATH being the binary under test, and every
//! figure of its *Check* tables is compared with the file the commands wrote — to the digits
//! shown or 0.5 % of the value, whichever is looser (the tolerance the tutorial states).
//!
//! The whole tutorial runs the paper's motor twice, a 6-point sweep and a 20-sample UQ: ≈ 20 s
//! with the release build, under a minute with the test profile.

use clap::Parser;
use sawdrive_cli::cli::Cli;
use std::path::{Path, PathBuf};
use std::process::Command;

const TUTORIAL: &str = include_str!("../../../docs/tutorial.md");

/// The info string of the blocks the test runs.
const EXECUTABLE: &str = "sh tutorial";

/// Relative tolerance of a quoted figure (besides the rounding to the digits shown).
const RELATIVE_TOLERANCE: f64 = 0.005;

/// The text of every ```` ```sh tutorial ```` block, in order.
fn executable_blocks() -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in TUTORIAL.lines() {
        let fence = line.trim_start().strip_prefix("```");
        match (&mut current, fence) {
            (None, Some(info)) if info.trim() == EXECUTABLE => current = Some(String::new()),
            (Some(block), Some("")) => {
                blocks.push(std::mem::take(block));
                current = None;
            }
            (Some(block), _) => {
                block.push_str(line);
                block.push('\n');
            }
            _ => {}
        }
    }
    assert!(
        current.is_none(),
        "an executable block of the tutorial is not closed"
    );
    blocks
}

/// One row of a *Check* table: `| quantity | value | `file` | `key` |`.
#[derive(Debug)]
struct Check {
    quantity: String,
    value: String,
    file: String,
    key: String,
}

/// The rows of every table whose header starts with `| Check`.
fn checks() -> Vec<Check> {
    let mut rows = Vec::new();
    let mut in_check_table = false;
    for line in TUTORIAL.lines() {
        let line = line.trim();
        if !line.starts_with('|') {
            in_check_table = false;
            continue;
        }
        if line.starts_with("| Check") {
            in_check_table = true;
            continue;
        }
        if !in_check_table || line.starts_with("|---") {
            continue;
        }
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        assert_eq!(cells.len(), 4, "a check row has 4 cells: {line}");
        let unquote = |cell: &str| cell.trim_matches('`').to_owned();
        rows.push(Check {
            quantity: cells[0].to_owned(),
            value: cells[1].to_owned(),
            file: unquote(cells[2]),
            key: unquote(cells[3]),
        });
    }
    rows
}

/// A quoted figure and the number of decimals it shows.
fn quoted(value: &str) -> (f64, i32) {
    let number = value.split_whitespace().next().unwrap_or_default();
    let decimals = number.split_once('.').map_or(0, |(_, d)| d.len() as i32);
    let parsed = number
        .parse()
        .unwrap_or_else(|_| panic!("tutorial figure `{value}` is not a number"));
    (parsed, decimals)
}

/// Whether a figure quoted with `decimals` decimals stands for `actual`.
fn holds(quoted: f64, decimals: i32, actual: f64) -> bool {
    let rounding = 0.5 * 10f64.powi(-decimals);
    (quoted - actual).abs() <= rounding.max(RELATIVE_TOLERANCE * actual.abs())
}

/// `a.b.c` of a JSON file.
fn json_value(path: &Path, key: &str) -> f64 {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut value = &json;
    for part in key.split('.') {
        value = value
            .get(part)
            .unwrap_or_else(|| panic!("{}: no key `{key}` (at `{part}`)", path.display()));
    }
    value
        .as_f64()
        .unwrap_or_else(|| panic!("{}: `{key}` is not a number: {value}", path.display()))
}

/// The fields of one CSV record (RFC 4180: a field in double quotes may hold commas and `""`).
fn csv_fields(line: &str) -> Vec<String> {
    let (mut fields, mut field, mut quoted, mut chars) =
        (Vec::new(), String::new(), false, line.chars().peekable());
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            (_, '"') => quoted = !quoted,
            (false, ',') => fields.push(std::mem::take(&mut field)),
            (_, c) => field.push(c),
        }
    }
    fields.push(field);
    fields
}

/// `column=value; …; column` of a CSV file: the last column of the one row matching the filters.
fn csv_value(path: &Path, key: &str) -> f64 {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = csv_fields(lines.next().unwrap_or_default());
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("{}: no column `{name}`", path.display()))
    };
    let parts: Vec<&str> = key.split(';').map(str::trim).collect();
    let (wanted, filters) = parts.split_last().unwrap();
    let filters: Vec<(usize, &str)> = filters
        .iter()
        .map(|f| {
            let (name, value) = f.split_once('=').expect("a filter is column=value");
            (column(name), value)
        })
        .collect();
    let rows: Vec<Vec<String>> = lines
        .map(csv_fields)
        .filter(|row| {
            filters
                .iter()
                .all(|(i, v)| row.get(*i).map(String::as_str) == Some(*v))
        })
        .collect();
    assert_eq!(
        rows.len(),
        1,
        "{}: `{key}` matches {} rows",
        path.display(),
        rows.len()
    );
    rows[0][column(wanted)].parse().unwrap()
}

#[test]
fn the_tutorial_blocks_parse_and_its_checks_are_well_formed() {
    let blocks = executable_blocks();
    assert!(
        blocks.len() >= 5,
        "executable blocks found: {}",
        blocks.len()
    );
    let mut commands = 0;
    for line in blocks.iter().flat_map(|b| b.lines()) {
        let command = line.split(" #").next().unwrap_or_default().trim();
        let command = command.split(" > ").next().unwrap_or_default();
        if command.starts_with("sawdrive ") {
            commands += 1;
            let words: Vec<&str> = command.split_whitespace().collect();
            if let Err(error) = Cli::try_parse_from(&words) {
                panic!("tutorial command `{command}` does not parse:\n{error}");
            }
        }
    }
    assert!(commands >= 6, "sawdrive commands found: {commands}");
    let checks = checks();
    assert!(checks.len() >= 15, "check rows found: {}", checks.len());
    for check in &checks {
        quoted(&check.value);
        assert!(
            check.file.starts_with("out/") && !check.key.is_empty(),
            "check `{}` names a file under out/ and a key: {check:?}",
            check.quantity
        );
    }
}

#[test]
fn the_tutorial_runs_and_its_figures_hold() {
    let folder = tempfile::tempdir().unwrap();
    let binary = PathBuf::from(env!("CARGO_BIN_EXE_sawdrive"));
    let path = std::env::join_paths(
        std::iter::once(binary.parent().unwrap().to_path_buf()).chain(std::env::split_paths(
            &std::env::var_os("PATH").unwrap_or_default(),
        )),
    )
    .unwrap();
    for block in executable_blocks() {
        let output = Command::new("bash")
            .args(["-euo", "pipefail", "-c", &block])
            .current_dir(folder.path())
            .env("PATH", &path)
            .env("SAWDRIVE_MESH_CACHE", folder.path().join("meshes"))
            .output()
            .expect("bash runs");
        assert!(
            output.status.success(),
            "tutorial block failed:\n{block}\nstderr:\n{}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let mut failures = Vec::new();
    for check in checks() {
        let file = folder.path().join(&check.file);
        let actual = if check.file.ends_with(".csv") {
            csv_value(&file, &check.key)
        } else {
            json_value(&file, &check.key)
        };
        let (value, decimals) = quoted(&check.value);
        if !holds(value, decimals, actual) {
            failures.push(format!(
                "{}: the tutorial says {}, {} {} is {actual}",
                check.quantity, check.value, check.file, check.key
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "tutorial figures that do not hold:\n{}",
        failures.join("\n")
    );
}

#[test]
fn a_figure_holds_to_its_digits_or_half_a_percent() {
    assert!(holds(0.38, 2, 0.3825));
    assert!(!holds(0.38, 2, 0.3951));
    assert!(holds(11.76, 2, 11.7603));
    assert!(holds(17.15, 2, 17.149));
    assert!(!holds(17.15, 2, 17.5));
    assert_eq!(quoted("12.00"), (12.0, 2));
    assert_eq!(
        csv_fields(r#",20 um,"a, ""b""",0.5"#),
        ["", "20 um", r#"a, "b""#, "0.5"]
    );
}
