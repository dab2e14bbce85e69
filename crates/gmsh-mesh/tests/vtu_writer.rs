//! The VTU writer: valid structure, gmsh → VTK Tet10 node order, atomic failure.

mod common;

use common::fixture;
use gmsh_mesh::{Field, FieldValues, MeshError, VTK_QUADRATIC_TETRA, read_msh, write_vtu};

/// Numbers of the `<DataArray Name="name">` of a VTU document.
fn data_array(document: &str, name: &str) -> Vec<f64> {
    let start = document
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("array {name} present"));
    let body_start = start + document[start..].find('>').unwrap() + 1;
    let body_end = body_start + document[body_start..].find("</DataArray>").unwrap();
    document[body_start..body_end]
        .split_whitespace()
        .map(|t| t.parse().expect("number"))
        .collect()
}

#[test]
fn tet10_cells_use_vtk_edge_order_and_fields_round_trip() {
    let mesh = read_msh(fixture("box_coarse_tet10.msh")).expect("Tet10 box");
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("box.vtu");
    let displacement: Vec<[f64; 3]> = mesh
        .nodes
        .iter()
        .map(|p| [p[0], 2.0 * p[1], -p[2]])
        .collect();
    let temperature: Vec<f64> = (0..mesh.nodes.len()).map(|i| i as f64 * 0.5).collect();
    let volume: Vec<f64> = (0..mesh.tets.len()).map(|t| mesh.tet_volume(t)).collect();
    write_vtu(
        &path,
        &mesh,
        &[
            Field {
                name: "displacement_m",
                values: FieldValues::Vector(&displacement),
            },
            Field {
                name: "temperature_k",
                values: FieldValues::Scalar(&temperature),
            },
        ],
        &[Field {
            name: "volume_m3",
            values: FieldValues::Scalar(&volume),
        }],
    )
    .expect("writes");
    let document = std::fs::read_to_string(&path).expect("reads back");
    assert!(
        document.contains(&format!("NumberOfPoints=\"{}\"", mesh.nodes.len())),
        "point count"
    );
    let types = data_array(&document, "types");
    assert!(
        types.iter().all(|&t| t == f64::from(VTK_QUADRATIC_TETRA)),
        "cell type 24"
    );
    let connectivity = data_array(&document, "connectivity");
    let points = {
        let start = document.find("<Points>").unwrap();
        let body_start = start
            + document[start..].find("format=\"ascii\">").unwrap()
            + "format=\"ascii\">".len();
        let body_end = body_start + document[body_start..].find("</DataArray>").unwrap();
        let flat: Vec<f64> = document[body_start..body_end]
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        flat.chunks(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect::<Vec<_>>()
    };
    // VTK midside nodes: 4:(0,1) 5:(1,2) 6:(2,0) 7:(0,3) 8:(1,3) 9:(2,3).
    const VTK_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
    for cell in connectivity.chunks(10) {
        let p = |k: usize| points[cell[k] as usize];
        for (e, [i, j]) in VTK_EDGES.iter().enumerate() {
            for d in 0..3 {
                let midpoint = 0.5 * (p(*i)[d] + p(*j)[d]);
                assert!(
                    (p(4 + e)[d] - midpoint).abs() < 1e-12,
                    "VTK node {} at the midpoint of edge {i}-{j}",
                    4 + e
                );
            }
        }
    }
    let written = data_array(&document, "displacement_m");
    assert_eq!(
        written.len(),
        3 * mesh.nodes.len(),
        "displacement components"
    );
    assert_eq!(
        written[4], displacement[1][1],
        "displacement value round-trips"
    );
    assert_eq!(
        data_array(&document, "volume_m3").len(),
        mesh.tets.len(),
        "one volume per cell"
    );
    assert_eq!(
        data_array(&document, "gmsh_physical_tag")[0],
        1.0,
        "physical tag of the slider volume"
    );
}

#[test]
fn bad_field_fails_without_touching_the_target() {
    let mesh = read_msh(fixture("sparse_tags_two_tets.msh")).expect("fixture");
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("bad.vtu");
    let short = vec![1.0; mesh.nodes.len() - 1];
    let error = write_vtu(
        &path,
        &mesh,
        &[Field {
            name: "p",
            values: FieldValues::Scalar(&short),
        }],
        &[],
    )
    .expect_err("length mismatch");
    assert!(
        matches!(error, MeshError::Field { .. }) && error.to_string().contains("\"p\""),
        "field error: {error}"
    );
    let nan = vec![f64::NAN; mesh.nodes.len()];
    assert!(
        write_vtu(
            &path,
            &mesh,
            &[Field {
                name: "q",
                values: FieldValues::Scalar(&nan)
            }],
            &[]
        )
        .is_err(),
        "NaN rejected"
    );
    assert!(!path.exists(), "no file written on error");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "no temporary file left behind"
    );
}

#[test]
fn write_into_missing_directory_is_an_io_error_naming_the_path() {
    let mesh = read_msh(fixture("sparse_tags_two_tets.msh")).expect("fixture");
    let path = std::path::Path::new("/nonexistent-dir-for-gmsh-mesh-tests/out.vtu");
    let message = write_vtu(path, &mesh, &[], &[])
        .expect_err("cannot write")
        .to_string();
    assert!(
        message.contains("out.vtu") && message.contains("writing"),
        "io error: {message}"
    );
}
