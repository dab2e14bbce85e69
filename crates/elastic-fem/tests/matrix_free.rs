//! The matrix-free product equals the product with the assembled stiffness (both ways of
//! holding the geometry, isotropic and rotated cubic material, straight and curved Tet10).

mod common;

use common::{Lcg, curved_tet10_box, distort, max_abs, model_of, steel};
use elastic_fem::matrix_free::{MatrixFreeGeometry, MatrixFreeStiffness};
use elastic_fem::mesh_gen::BoxMesh;
use elastic_fem::{CubicCrystal, FemError, Material, Model, StiffnessPattern, assemble_stiffness};

/// max |K_mf x − K x| / max |K x| for a random x.
fn relative_difference(model: &Model, geometry: MatrixFreeGeometry) -> f64 {
    let k = assemble_stiffness(model, &StiffnessPattern::build(model)).unwrap();
    let operator = MatrixFreeStiffness::new(model, geometry).unwrap();
    assert_eq!(operator.dim(), model.dof_count(), "dimension");
    let mut rng = Lcg(7);
    let x: Vec<f64> = (0..model.dof_count())
        .map(|_| rng.next_f64() - 0.5)
        .collect();
    let mut assembled = vec![0.0; x.len()];
    let mut free = vec![1.0; x.len()];
    k.mul_vec(&x, &mut assembled);
    operator.mul_vec(&x, &mut free);
    let diff: Vec<f64> = free.iter().zip(&assembled).map(|(a, b)| a - b).collect();
    max_abs(&diff) / max_abs(&assembled)
}

fn straight_distorted_box() -> BoxMesh {
    let mut mesh = BoxMesh::tet10([2e-5, 1e-5, 1.5e-5], [3, 2, 4]);
    distort(&mut mesh, 0.08);
    mesh.straighten_edges();
    mesh
}

#[test]
fn matrix_free_products_equal_the_assembled_stiffness_times_x() {
    let mesh = straight_distorted_box();
    let rotated_silicon =
        CubicCrystal::new(165.7e9, 63.9e9, 79.6e9, CubicCrystal::rotation_about_z(0.4)).unwrap();
    for (label, material) in [
        ("isotropic", steel()),
        ("rotated cubic", Material::from(rotated_silicon)),
    ] {
        let model = model_of(&mesh, material);
        for geometry in [MatrixFreeGeometry::Gradients, MatrixFreeGeometry::Jacobians] {
            let d = relative_difference(&model, geometry);
            assert!(
                d < 1e-13,
                "{label}, {geometry:?}: relative difference {d:e}"
            );
        }
    }
}

#[test]
fn curved_elements_use_their_own_rule_with_gradients_and_are_refused_with_jacobians() {
    let model = model_of(&curved_tet10_box(), steel());
    let d = relative_difference(&model, MatrixFreeGeometry::Gradients);
    assert!(d < 1e-13, "curved, Gradients: relative difference {d:e}");
    match MatrixFreeStiffness::new(&model, MatrixFreeGeometry::Jacobians) {
        Err(FemError::IterativeUnsupported { reason }) => {
            assert!(reason.contains("curved"), "{reason}")
        }
        other => panic!("expected a refusal naming the curved element, got {other:?}"),
    }
}

#[test]
fn a_tet4_mesh_is_refused_by_name() {
    let mesh = BoxMesh::tet4([1.0; 3], [1, 1, 1]);
    let model = model_of(&mesh, steel());
    let err = MatrixFreeStiffness::new(&model, MatrixFreeGeometry::Gradients).unwrap_err();
    assert!(err.to_string().contains("Tet10"), "{err}");
}
