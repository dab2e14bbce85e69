//! The binary does not depend on the folder it was built in: it holds no path of the
//! checkout's `crates/` (the gmsh scripts and the committed strip mesh are embedded), and a copy
//! run from an empty folder, with `HOME` and `XDG_CACHE_HOME` there and no other sawdrive
//! variable, meshes into its cache folder: `$XDG_CACHE_HOME/sawdrive`, else
//! `$HOME/.cache/sawdrive`, `--cache DIR` overriding both.
//!
//! The meshing runs need gmsh and take about a minute:
//! `cargo test -p sawdrive-cli --test relocated_binary -- --ignored`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The checkout's `crates/` folder, as an absolute path.
fn checkout_crates() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .canonicalize()
        .expect("crates folder")
}

#[test]
fn binary_holds_no_path_of_the_checkouts_crates_folder() {
    let binary = std::fs::read(env!("CARGO_BIN_EXE_sawdrive")).expect("built binary");
    let needle = checkout_crates();
    let needle = needle.to_str().expect("UTF-8 path").as_bytes();
    let found = binary
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|at| String::from_utf8_lossy(&binary[at..(at + 200).min(binary.len())]).into_owned());
    assert_eq!(
        found,
        None,
        "the binary names the checkout's crates folder {}",
        checkout_crates().display()
    );
}

/// A 6 × 6 post strip (Tet4): meshed by gmsh, no committed mesh matches it.
const SMALL_SCENE: &str = r#"name = "relocated"
[slider]
length = "0.24 mm"
width = "0.24 mm"
[posts]
count = "6x6"
array = "0.24 mm"
[load]
preload = "0.144 N"
[static]
element_order = 1
"#;

/// A copy of the binary in an empty temporary folder, with its home and XDG cache folders.
struct Relocated {
    root: tempfile::TempDir,
}

impl Relocated {
    fn new() -> Self {
        let root = tempfile::tempdir().unwrap();
        for dir in ["bin", "work", "home", "xdg"] {
            std::fs::create_dir(root.path().join(dir)).unwrap();
        }
        std::fs::copy(
            env!("CARGO_BIN_EXE_sawdrive"),
            root.path().join("bin/sawdrive"),
        )
        .unwrap();
        std::fs::write(root.path().join("work/scene.toml"), SMALL_SCENE).unwrap();
        Self { root }
    }

    fn path(&self, rel: &str) -> PathBuf {
        self.root.path().join(rel)
    }

    /// Runs the copy in `work/` with only PATH, HOME and (if `xdg`) XDG_CACHE_HOME set.
    fn run(&self, args: &[&str], xdg: bool) -> String {
        let mut command = Command::new(self.path("bin/sawdrive"));
        command
            .args(args)
            .current_dir(self.path("work"))
            .env_clear()
            .env("PATH", std::env::var_os("PATH").unwrap_or_default())
            .env("HOME", self.path("home"));
        if xdg {
            command.env("XDG_CACHE_HOME", self.path("xdg"));
        }
        let output = command.output().unwrap();
        assert!(
            output.status.success(),
            "sawdrive {args:?} failed:\n{}",
            String::from_utf8_lossy(&output.stderr)
        );
        String::from_utf8_lossy(&output.stdout).into_owned()
    }

    /// Names of the files in `rel` (empty if it does not exist).
    fn files(&self, rel: &str) -> Vec<String> {
        std::fs::read_dir(self.path(rel))
            .map(|d| {
                d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default()
    }
}

#[test]
#[ignore = "meshes with gmsh (about a minute): cargo test -p sawdrive-cli --test relocated_binary -- --ignored"]
fn copied_binary_meshes_and_validates_from_an_empty_folder_into_its_cache() {
    let r = Relocated::new();
    // A meshed static run: the embedded slider-strip.geo and the mesh go to the XDG cache.
    r.run(
        &["static", "scene.toml", "--no-cache", "--out", "out"],
        true,
    );
    assert!(
        r.files("xdg/sawdrive/geo")
            .contains(&"slider-strip.geo".into()),
        "embedded gmsh script written into the cache: {:?}",
        r.files("xdg/sawdrive/geo")
    );
    assert!(
        r.files("xdg/sawdrive/meshes")
            .iter()
            .any(|f| f.ends_with(".msh")),
        "strip mesh in $XDG_CACHE_HOME/sawdrive/meshes: {:?}",
        r.files("xdg/sawdrive/meshes")
    );
    // The quick springs study: punch meshes from the embedded punch.geo.
    let json = r.run(&["validate", "springs", "--level", "quick", "--json"], true);
    let checks: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(
        checks["checks"].as_array().is_some_and(|c| !c.is_empty()),
        "{json}"
    );
    assert!(
        r.files("xdg/sawdrive/meshes")
            .iter()
            .any(|f| f.starts_with("punch-")),
        "punch meshes in the XDG cache"
    );
    // Without XDG_CACHE_HOME: $HOME/.cache/sawdrive.
    r.run(
        &["static", "scene.toml", "--no-cache", "--out", "out2"],
        false,
    );
    assert!(
        r.files("home/.cache/sawdrive/meshes")
            .iter()
            .any(|f| f.ends_with(".msh")),
        "strip mesh in $HOME/.cache/sawdrive/meshes"
    );
    // --cache overrides both.
    let flag = r.path("flag");
    r.run(
        &[
            "--cache",
            flag.to_str().unwrap(),
            "static",
            "scene.toml",
            "--no-cache",
            "--out",
            "out3",
        ],
        true,
    );
    assert!(
        r.files("flag/meshes").iter().any(|f| f.ends_with(".msh")),
        "strip mesh in the --cache folder"
    );
}
