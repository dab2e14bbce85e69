//! Helpers shared by the end-to-end tests: run the `sawdrive` binary and capture its output.

#![allow(dead_code)]

use std::process::{Command, Output};

/// Run `sawdrive` with `args`; returns the process output.
pub fn sawdrive(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sawdrive"))
        .args(args)
        .output()
        .expect("sawdrive binary runs")
}

/// Run `sawdrive` expecting success; returns stdout.
pub fn sawdrive_ok(args: &[&str]) -> String {
    let out = sawdrive(args);
    assert!(
        out.status.success(),
        "sawdrive {} failed: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8 output")
}

/// Run `sawdrive` expecting failure; returns stderr, checked to be one line naming `needle`.
pub fn sawdrive_err(args: &[&str], needle: &str) -> String {
    let out = sawdrive(args);
    assert!(
        !out.status.success(),
        "sawdrive {} should fail",
        args.join(" ")
    );
    let stderr = String::from_utf8(out.stderr).expect("utf-8 stderr");
    assert!(
        stderr.contains(needle),
        "sawdrive {}: error should name {needle}: {stderr}",
        args.join(" ")
    );
    assert!(!stderr.contains("panicked"), "no panic: {stderr}");
    stderr
}

/// The small end-to-end scene (10 × 10 posts, committed 10-post strip mesh).
pub fn small_scene() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/scenes/small-strip.toml"
    )
    .to_owned()
}

/// `sawdrive dynamic` on the small scene with η = 0.36 and `sets`, into `out`; the parsed
/// `--json` result.
pub fn small_dynamic_json(out: &std::path::Path, sets: &[&str]) -> serde_json::Value {
    let scene = small_scene();
    let mut args = vec![
        "dynamic",
        scene.as_str(),
        "--out",
        out.to_str().unwrap(),
        "--json",
        "--set",
        "effective_ratio=0.36",
    ];
    for set in sets {
        args.extend(["--set", set]);
    }
    serde_json::from_str(&sawdrive_ok(&args)).expect("dynamic --json prints JSON")
}
