//! The workspace's one gmsh runner (`gmsh_mesh::gmsh::run_geo`): meshes a geometry with
//! `-setnumber` parameters atomically, and names a missing gmsh or a gmsh failure. Needs gmsh
//! (CI installs it); without it the meshing test prints a note and returns.

mod common;

use std::path::Path;

use gmsh_mesh::MeshError;
use gmsh_mesh::gmsh::{GmshOptions, run_geo};

fn only_file_in(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn a_punch_mesh_is_written_atomically_with_its_parameters() {
    if !common::gmsh_available() {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("sub/punch.msh");
    let parameters = [
        ("sym", 2.0),
        ("R_over_a", 5.0),
        ("h_edge_over_a", 0.3),
        ("growth", 0.5),
        ("order", 1.0),
    ];
    for binary in [true, false] {
        let options = GmshOptions {
            binary,
            ..GmshOptions::default()
        };
        run_geo(&common::geometry("punch"), &out, &parameters, &options)
            .expect("gmsh meshes punch.geo");
        let mesh = gmsh_mesh::read_msh(&out).expect("the mesh reads back");
        assert!(
            mesh.tets.len() > 100,
            "tets in the punch mesh: {}",
            mesh.tets.len()
        );
        mesh.group_faces("sym_x0")
            .expect("quarter model (sym = 2) has sym_x0");
        let head = std::fs::read(&out).expect("mesh bytes");
        let ascii_header = head.windows(8).any(|w| w == b"4.1 0 8\n");
        assert_eq!(
            !ascii_header, binary,
            "binary flag honoured (binary = {binary})"
        );
        assert_eq!(
            only_file_in(&out.with_file_name("")),
            vec!["punch.msh".to_string()],
            "no temporary file left beside the mesh"
        );
    }
}

#[test]
fn a_missing_gmsh_is_named_with_how_to_install_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("m.msh");
    let options = GmshOptions {
        program: "/nonexistent/gmsh-binary".into(),
        ..GmshOptions::default()
    };
    let err = run_geo(&common::geometry("punch"), &out, &[], &options).expect_err("no such gmsh");
    assert!(
        matches!(err, MeshError::GmshMissing { .. }),
        "missing gmsh reported as such: {err}"
    );
    let text = err.to_string();
    assert!(
        text.contains("/nonexistent/gmsh-binary") && text.contains("install"),
        "message names the program and how to install gmsh: {text}"
    );
    assert!(!out.exists(), "no mesh written");
}

#[test]
fn a_gmsh_failure_quotes_its_error_and_leaves_no_file() {
    if !common::gmsh_available() {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("strip.msh");
    // d ≥ pitch: slider-strip.geo stops with its own Error().
    let err = run_geo(
        &common::geometry("slider-strip"),
        &out,
        &[("pitch", 10e-6), ("d", 20e-6)],
        &GmshOptions::default(),
    )
    .expect_err("post diameter above the pitch is refused by the geometry");
    let text = err.to_string();
    assert!(
        matches!(err, MeshError::GmshFailed { .. }) && text.contains("smaller than the pitch"),
        "gmsh's own error is quoted: {text}"
    );
    assert!(
        only_file_in(dir.path()).is_empty(),
        "no mesh or temporary file left after a failure"
    );
    // A half along x needs an even post count (the plane x = L/2 between two posts).
    let err = run_geo(
        &common::geometry("slider-strip"),
        &out,
        &[("n_posts", 3.0), ("mirror_x", 1.0)],
        &GmshOptions::default(),
    )
    .expect_err("mirror_x with an odd post count is refused by the geometry");
    let text = err.to_string();
    assert!(
        text.contains("mirror_x = 1 needs an even n_posts"),
        "gmsh's own error is quoted: {text}"
    );
    assert!(only_file_in(dir.path()).is_empty());
}
