//! What a user sets or trusts in the static stage is honoured end to end: the solver settings
//! reach the solver, the post height is checked against an explicit mesh, a hostile mesh path
//! is refused, the FEM cache is verified on read (an edited report or a swapped cached mesh is
//! rebuilt and reported), results are copies rather than links into the cache, and printing to
//! a closed stdout or a mesh with terminal escapes is handled. Small 10 × 10-post scene.

mod common;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use common::{sawdrive, sawdrive_err, sawdrive_ok, small_scene};

fn committed_mesh() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/slider-strip_p40um_d20um_n10_tet4_10k.msh"
    )
    .to_owned()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).expect("json file")).expect("valid json")
}

/// The `static-<hash>.json` entries of a cache folder.
fn cache_entries(cache: &Path) -> Vec<PathBuf> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(cache)
        .expect("cache folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| {
            p.is_file()
                && p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with("static-") && n.ends_with(".json"))
        })
        .collect();
    entries.sort();
    entries
}

#[test]
fn an_iteration_limit_of_one_stops_the_static_stage_naming_the_key() {
    let out = tempfile::tempdir().expect("temp dir");
    let stderr = sawdrive_err(
        &[
            "static",
            &small_scene(),
            "--out",
            out.path().to_str().expect("utf-8"),
            "--set",
            "static.max_iterations=1",
        ],
        "static.max_iterations = 1",
    );
    assert!(
        stderr.contains("did not converge") && stderr.lines().count() == 1,
        "one line saying the solver stopped: {stderr}"
    );
}

#[test]
fn a_post_height_the_explicit_mesh_does_not_have_is_refused() {
    let out = tempfile::tempdir().expect("temp dir");
    for height in ["1nm", "1m"] {
        let stderr = sawdrive_err(
            &[
                "static",
                &small_scene(),
                "--out",
                out.path().to_str().expect("utf-8"),
                "--set",
                &format!("posts.height={height}"),
            ],
            "post_height_m",
        );
        assert!(
            stderr.contains("2.0000e-6") && stderr.contains("tolerance"),
            "the mesh's height, the scene's and the tolerance are named: {stderr}"
        );
    }
}

#[test]
fn a_device_as_static_mesh_is_refused_by_name() {
    if !Path::new("/dev/zero").exists() {
        return;
    }
    let out = tempfile::tempdir().expect("temp dir");
    sawdrive_err(
        &[
            "static",
            &small_scene(),
            "--out",
            out.path().to_str().expect("utf-8"),
            "--set",
            "static.mesh=/dev/zero",
        ],
        "/dev/zero: not a regular file",
    );
}

#[test]
fn an_edited_cached_report_is_recomputed_and_results_are_not_links_into_the_cache() {
    let out = tempfile::tempdir().expect("temp dir");
    let out_arg = out.path().to_str().expect("utf-8");
    let args = ["static", &small_scene(), "--out", out_arg];
    sawdrive_ok(&args);
    let results = out.path().join("small-strip/static");
    let eta = json(&results.join("static.json"))["effective_contact_ratio"]
        .as_f64()
        .expect("η");

    // Editing a result must not reach the cache: the next run is still served from it.
    let vtu = results.join("static_snapshot0.vtu");
    std::fs::write(&vtu, "edited by hand").expect("edit a result file");
    let cached = sawdrive(&args);
    assert!(cached.status.success(), "cached run succeeds");
    assert!(
        String::from_utf8_lossy(&cached.stdout).contains("(cached)"),
        "an edited result file leaves the cache intact"
    );
    assert_ne!(
        std::fs::read(&vtu).expect("vtu"),
        b"edited by hand",
        "the results folder was rewritten from the cache"
    );

    // Edit η in the cached report by hand: the next run must not trust it.
    let cache = out.path().join(".cache");
    let entries = cache_entries(&cache);
    assert_eq!(entries.len(), 1, "one cache entry: {entries:?}");
    let text = std::fs::read_to_string(&entries[0]).expect("entry");
    let edited = text.replacen(
        &format!(
            "\"effective_contact_ratio\":{}",
            serde_json::to_string(&eta).expect("η")
        ),
        "\"effective_contact_ratio\":0.999",
        1,
    );
    assert_ne!(edited, text, "the cached report holds η = {eta}");
    std::fs::write(&entries[0], edited).expect("edit the cache");
    let rerun = sawdrive(&args);
    let stdout = String::from_utf8_lossy(&rerun.stdout);
    let stderr = String::from_utf8_lossy(&rerun.stderr);
    assert!(rerun.status.success(), "rerun succeeds: {stderr}");
    assert!(
        !stdout.contains("(cached)"),
        "an edited report is recomputed: {stdout}"
    );
    assert!(
        stderr.contains("static cache entry")
            && stderr.contains(&entries[0].display().to_string())
            && stderr.contains("recomputing"),
        "stderr says which entry and why: {stderr}"
    );
    assert_eq!(
        json(&results.join("static.json"))["effective_contact_ratio"].as_f64(),
        Some(eta),
        "the recomputed η is the FEM's, not the edited one"
    );

    // A damaged cached field file is detected too.
    let fields = entries[0].with_extension("");
    std::fs::write(fields.join("static_snapshot0.vtu"), "truncated").expect("damage the VTU");
    let rerun = sawdrive(&args);
    let stderr = String::from_utf8_lossy(&rerun.stderr);
    assert!(
        rerun.status.success() && !String::from_utf8_lossy(&rerun.stdout).contains("(cached)"),
        "a damaged cached field file is rebuilt: {stderr}"
    );
    assert!(
        stderr.contains("field files") && stderr.contains(&fields.display().to_string()),
        "stderr names the damaged field folder: {stderr}"
    );
    assert_ne!(
        std::fs::read(results.join("static_snapshot0.vtu")).expect("vtu"),
        b"truncated",
        "the results get the rebuilt VTU"
    );
}

#[test]
fn a_swapped_cached_mesh_is_detected_and_rebuilt() {
    if !Command::new("gmsh")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
    {
        println!("note: gmsh not installed; skipping");
        return;
    }
    let out = tempfile::tempdir().expect("temp dir");
    let out_arg = out.path().to_str().expect("utf-8");
    let run = |preload: &str| {
        sawdrive(&[
            "static",
            &small_scene(),
            "--out",
            out_arg,
            "--set",
            "static.mesh=auto",
            "--set",
            &format!("load.preload={preload}"),
        ])
    };
    assert!(run("0.4 N").status.success(), "first run meshes with gmsh");
    let meshes: Vec<PathBuf> = std::fs::read_dir(out.path().join(".cache/meshes"))
        .expect("mesh cache")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "msh"))
        .collect();
    assert_eq!(meshes.len(), 1, "one cached mesh: {meshes:?}");
    std::fs::copy(committed_mesh(), &meshes[0]).expect("swap the cached mesh");
    // Another preload misses the report cache and needs the mesh again.
    let second = run("0.5 N");
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert!(second.status.success(), "second run succeeds: {stderr}");
    assert!(
        stderr.contains("cached mesh") && stderr.contains(&meshes[0].display().to_string()),
        "the swapped mesh is reported by name: {stderr}"
    );
}

#[test]
fn printing_to_a_closed_stdout_is_a_quiet_exit() {
    for args in [
        vec!["mesh", "info", committed_mesh().leak() as &str],
        vec!["springs", "--diameter", "20um"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_sawdrive"))
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("sawdrive starts");
        drop(child.stdout.take());
        let mut stderr = String::new();
        child
            .stderr
            .take()
            .expect("stderr")
            .read_to_string(&mut stderr)
            .expect("read stderr");
        let status = child.wait().expect("sawdrive ends");
        assert!(
            !stderr.contains("panicked"),
            "sawdrive {} must not panic on a closed stdout: {stderr}",
            args.join(" ")
        );
        assert!(
            status.success(),
            "quiet exit for {}: {stderr}",
            args.join(" ")
        );
    }
}

#[test]
fn a_mesh_with_terminal_escapes_is_reported_escaped() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("evil.msh");
    std::fs::write(
        &path,
        b"$MeshFormat\n\x1b]0;owned\x07 0 8\n$EndMeshFormat\n",
    )
    .expect("write");
    let out = sawdrive(&["mesh", "info", path.to_str().expect("utf-8")]);
    assert!(!out.status.success(), "a broken mesh fails");
    assert!(
        !out.stderr.contains(&0x1b) && !out.stderr.contains(&0x07),
        "no raw control bytes on stderr: {:?}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("\\x1b"),
        "ESC shown escaped: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}
