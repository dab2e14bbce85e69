//! Input that cannot harm: names that would leave or replace OUT, counts that would exhaust
//! memory, values that would silently give wrong results and files that are not files are each
//! refused in one line, with a non-zero exit, no panic, and nothing written or removed.

mod common;

use std::path::Path;

use common::{sawdrive_err, small_scene};

/// A folder `root` with `out/` holding a user's file and a `victim/` folder beside it holding
/// another; returns the listing to compare after a refused command.
fn sentinels(root: &Path) -> Vec<String> {
    std::fs::create_dir_all(root.join("out")).unwrap();
    std::fs::write(root.join("out").join("mine.txt"), "inside OUT").unwrap();
    std::fs::create_dir_all(root.join("victim")).unwrap();
    std::fs::write(root.join("victim").join("keep.txt"), "beside OUT").unwrap();
    listing(root)
}

/// Every path under `root`, sorted, with file contents.
fn listing(root: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut stack = vec![root.to_owned()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path.clone());
                found.push(format!("{}/", path.display()));
            } else {
                let text = std::fs::read_to_string(&path).unwrap_or_default();
                found.push(format!("{} = {text}", path.display()));
            }
        }
    }
    found.sort();
    found
}

/// Assert a one-line refusal naming `needle` and an unchanged `root`.
fn refused_and_untouched(root: &Path, before: &[String], args: &[&str], needle: &str) {
    let stderr = sawdrive_err(args, needle);
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert_eq!(
        listing(root),
        before,
        "nothing written or removed: {args:?}"
    );
}

#[test]
fn design_names_that_would_replace_out_or_escape_it_are_refused() {
    for name in ["", "../victim", "/tmp", ".."] {
        let root = tempfile::tempdir().unwrap();
        let design = root.path().join("d.toml");
        std::fs::write(
            &design,
            format!(
                "name = {name:?}\n[variables]\npreload = [\"10 N\", \"100 N\"]\n[optimiser]\npresearch_points = 2\n"
            ),
        )
        .unwrap();
        let before = sentinels(root.path());
        let out = root.path().join("out");
        let args = [
            "design",
            design.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        refused_and_untouched(root.path(), &before, &args, "name");
    }
}

#[test]
fn sweep_names_and_chart_files_that_would_escape_out_are_refused() {
    let scene = small_scene();
    for (line, needle) in [
        ("name = \"../escaped\"", "name"),
        ("name = \"..\"", "name"),
        ("name = \"/abs/path\"", "name"),
        ("name = \".cache\"", "name"),
        (
            "name = \"s\"\n[[charts]]\nx = \"preload_n\"\ny = \"stall_thrust_n\"\nfile = \"../victim/keep\"",
            "charts[0].file",
        ),
    ] {
        let root = tempfile::tempdir().unwrap();
        let sweep = root.path().join("s.toml");
        let (head, charts) = line.split_once("\n[[charts]]").unwrap_or((line, ""));
        let charts = if charts.is_empty() {
            String::new()
        } else {
            format!("[[charts]]{charts}\n")
        };
        std::fs::write(
            &sweep,
            format!(
                "{head}\nscene = {scene:?}\nset = {{ effective_ratio = 0.36 }}\n[grid]\npreload = [\"0.2 N\"]\n{charts}"
            ),
        )
        .unwrap();
        let before = sentinels(root.path());
        let out = root.path().join("out");
        let args = [
            "sweep",
            sweep.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        refused_and_untouched(root.path(), &before, &args, needle);
    }
}

#[test]
fn counts_and_steps_that_would_abort_or_mislead_are_refused_by_key() {
    let scene = small_scene();
    for (sets, needle) in [
        (
            vec!["model.lumped.time_step=\"1 us\""],
            "model.lumped.time_step",
        ),
        (vec!["static.phases=1000000000"], "static.phases"),
        (vec!["posts.count=100000x100000"], "posts.count"),
        (
            vec!["static.model=slider", "posts.height_scatter=\"1 m\""],
            "posts.height_scatter",
        ),
        (vec!["slider.bow=\"1 m\""], "slider.bow"),
        (vec!["friction.static=1e300"], "friction.static"),
        (vec!["wave.decay_length=\"1 nm\""], "wave.decay_length"),
        (
            vec![
                "model.dynamics=coupled",
                "model.coupled.steps_per_period=1000000000",
            ],
            "model.coupled.steps_per_period",
        ),
        (vec!["model.curve_points=1000000000"], "model.curve_points"),
    ] {
        let root = tempfile::tempdir().unwrap();
        let before = sentinels(root.path());
        let out = root.path().join("out");
        let mut args = vec!["run", scene.as_str(), "--out", out.to_str().unwrap()];
        for set in &sets {
            args.extend(["--set", set]);
        }
        refused_and_untouched(root.path(), &before, &args, needle);
    }
}

#[test]
fn a_sample_count_beyond_the_bound_is_refused_not_allocated() {
    let root = tempfile::tempdir().unwrap();
    let before = sentinels(root.path());
    let out = root.path().join("out");
    for samples in ["4294967296", "18446744073709551615"] {
        let args = [
            "uq",
            "--samples",
            samples,
            "--set",
            "scatter.friction=0.01",
            "--out",
            out.to_str().unwrap(),
        ];
        refused_and_untouched(root.path(), &before, &args, "--samples");
    }
}

#[test]
fn inputs_that_are_not_regular_files_are_refused_before_reading() {
    let root = tempfile::tempdir().unwrap();
    let before = sentinels(root.path());
    let out = root.path().join("out");
    for command in ["static", "run", "dynamic"] {
        let args = [command, "/dev/zero", "--out", out.to_str().unwrap()];
        refused_and_untouched(root.path(), &before, &args, "not a regular file");
    }
    let args = ["sweep", "/dev/zero", "--out", out.to_str().unwrap()];
    refused_and_untouched(root.path(), &before, &args, "not a regular file");
    let args = ["design", "/dev/zero", "--out", out.to_str().unwrap()];
    refused_and_untouched(root.path(), &before, &args, "not a regular file");
}

#[test]
fn a_scatter_spread_beyond_the_models_range_is_refused() {
    let root = tempfile::tempdir().unwrap();
    let before = sentinels(root.path());
    let out = root.path().join("out");
    for (set, key) in [
        ("scatter.friction=1e300", "scatter.friction"),
        ("scatter.bow=\"1 m\"", "scatter.bow"),
    ] {
        let args = [
            "uq",
            "--samples",
            "4",
            "--set",
            set,
            "--out",
            out.to_str().unwrap(),
        ];
        refused_and_untouched(root.path(), &before, &args, key);
    }
}

#[test]
fn height_map_heights_beyond_the_post_height_are_refused_naming_the_post() {
    let root = tempfile::tempdir().unwrap();
    let map = root.path().join("heights.csv");
    let mut csv = String::from("row,column,height_m\n");
    for row in 0..10 {
        for column in 0..10 {
            let h = if (row, column) == (3, 4) { 1.0 } else { 0.0 };
            csv.push_str(&format!("{row},{column},{h}\n"));
        }
    }
    std::fs::write(&map, csv).unwrap();
    let before = sentinels(root.path());
    let out = root.path().join("out");
    let set = format!("posts.height_map={:?}", map.to_str().unwrap());
    let scene = small_scene();
    let args = [
        "run",
        scene.as_str(),
        "--out",
        out.to_str().unwrap(),
        "--set",
        "static.model=slider",
        "--set",
        &set,
    ];
    let stderr = sawdrive_err(&args, "posts.height_map");
    assert!(stderr.contains("beyond"), "{stderr}");
    assert_eq!(listing(root.path()), before, "nothing written");
}

#[test]
fn design_settings_that_would_be_ignored_are_refused() {
    let root = tempfile::tempdir().unwrap();
    for (extra, needle) in [
        ("quantile = 0.1\n", "quantile"),
        ("samples = 4\ncheap_samples = 8\n", "cheap_samples"),
        (
            "[optimiser]\npresearch_points = 1000000000\n",
            "optimiser.presearch_points",
        ),
    ] {
        let design = root.path().join("d.toml");
        let (top, table) = extra
            .split_once("[optimiser]")
            .map_or((extra, ""), |(a, b)| (a, b));
        let optimiser = if table.is_empty() {
            String::new()
        } else {
            format!("[optimiser]{table}")
        };
        std::fs::write(
            &design,
            format!("name = \"d\"\n{top}[variables]\n\"load.preload\" = [\"10 N\", \"100 N\"]\n{optimiser}"),
        )
        .unwrap();
        let out = root.path().join("out");
        sawdrive_err(
            &[
                "design",
                design.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            needle,
        );
        assert!(!out.exists(), "nothing written for {needle}");
    }
}

#[cfg(target_os = "linux")]
#[test]
fn a_gmsh_child_dies_with_a_killed_sawdrive() {
    use std::os::unix::fs::PermissionsExt;
    let root = tempfile::tempdir().unwrap();
    let pid_file = root.path().join("gmsh.pid");
    let fake = root.path().join("gmsh");
    // A gmsh that never finishes: it records its PID and sleeps.
    std::fs::write(
        &fake,
        format!(
            "#!/bin/sh\necho $$ > {}\nexec sleep 120\n",
            pid_file.display()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let mut sawdrive = std::process::Command::new(env!("CARGO_BIN_EXE_sawdrive"))
        .args(["static", "--out"])
        .arg(root.path().join("out"))
        .arg("--cache")
        .arg(root.path().join("cache"))
        .args(["--set", "posts.count=12x12", "--set", "posts.array=0.48mm"])
        .args([
            "--set",
            "slider.length=0.5mm",
            "--set",
            "slider.width=0.5mm",
        ])
        .env("GMSH", &fake)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    let pid = loop {
        if let Some(pid) = std::fs::read_to_string(&pid_file)
            .ok()
            .and_then(|t| t.trim().parse::<u32>().ok())
        {
            break pid;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "sawdrive started gmsh"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    sawdrive.kill().unwrap();
    sawdrive.wait().unwrap();
    let proc = std::path::PathBuf::from(format!("/proc/{pid}"));
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
    // A killed child may linger as a zombie until reaped by init: check its state, not its entry.
    let alive = || {
        std::fs::read_to_string(proc.join("stat"))
            .ok()
            .is_some_and(|s| !s.split(") ").nth(1).is_some_and(|r| r.starts_with('Z')))
    };
    while alive() {
        assert!(
            std::time::Instant::now() < deadline,
            "gmsh {pid} still runs after sawdrive was killed"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}
