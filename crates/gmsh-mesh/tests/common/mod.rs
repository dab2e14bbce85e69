//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::PathBuf;

use gmsh_mesh::TetMesh;
use gmsh_mesh::geometry::{Point, triangle_normal};

/// `meshes/NAME.geo`, the parametric geometry `name`.
pub fn geometry(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../meshes/{name}.geo"))
}

/// Whether the gmsh that `gmsh_mesh::gmsh::run_geo` would start runs; prints a note when not
/// (the gmsh tests then return: CI installs gmsh).
pub fn gmsh_available() -> bool {
    let found = std::process::Command::new(gmsh_mesh::gmsh::GmshOptions::default().program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        println!("note: gmsh not installed (apt-get install -y gmsh); skipping");
    }
    found
}

/// Path of a committed mesh in meshes/.
pub fn committed_mesh(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes")
        .join(name)
}

/// Path of a test fixture.
pub fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Number of triangles of surface group `name` whose corner normal points into the tet they
/// bound (0 when all point outward).
pub fn inward_face_count(mesh: &TetMesh, name: &str) -> usize {
    let mut tets_by_face: HashMap<[usize; 3], Vec<(usize, usize)>> = HashMap::new();
    for t in 0..mesh.tets.len() {
        let c = mesh.tets.corners(t);
        for (face, opposite) in [
            ([1, 2, 3], 0),
            ([0, 2, 3], 1),
            ([0, 1, 3], 2),
            ([0, 1, 2], 3),
        ] {
            let mut key = face.map(|k| c[k]);
            key.sort_unstable();
            tets_by_face.entry(key).or_default().push((t, c[opposite]));
        }
    }
    let faces = mesh.group_faces(name).expect("surface group exists");
    (0..faces.len())
        .filter(|&i| {
            let corners = faces.corners(i);
            let mut key = corners;
            key.sort_unstable();
            let adjacent = &tets_by_face[&key];
            assert_eq!(
                adjacent.len(),
                1,
                "boundary triangle {i} of {name} bounds exactly one tet"
            );
            let p = corners.map(|n| mesh.nodes[n]);
            dot(triangle_normal(p), sub(mesh.nodes[adjacent[0].1], p[0])) > 0.0
        })
        .count()
}

/// Relative difference |a − b| / |b|.
pub fn relative_error(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
