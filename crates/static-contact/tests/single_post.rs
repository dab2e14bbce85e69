//! A single post on a flat stator: the condensed FEM compliance of the slider side and of a
//! meshed stator reproduce the Johnson springs, and the contact solve returns their series
//! stiffness k_pn ⊕ k_sn.
//!
//! Mesh: the committed quarter punch model (Tet10, half-space truncated at R = 100 a, clamped
//! there), whose truncation makes it stiffer by ≈ 0.6 a/R = 0.6 % (docs/physics.md §8); the edge
//! singularity costs another ≈ 1.4 % at this edge size (0.05 a): measured 2.0 % (bonded) and
//! 1.9 % (frictionless) too stiff, converging under refinement (see the `report` example's
//! single-post section). Tolerance: 2.5 %.

use contact_springs::{Material, k_pn, k_sn, series};
use nalgebra::DMatrix;
use static_contact::body::{BodyCompliance, BodySpec, Disk, TipLateral};
use static_contact::{ActiveSetSolver, ContactProblem};

const RADIUS_M: f64 = 10e-6;
/// Truncation (≈ 0.6 %) plus discretisation (≈ 1.4 %) error of the quarter punch mesh.
const FEM_TOLERANCE: f64 = 0.025;

fn punch_compliance(material: &Material, lateral: TipLateral) -> f64 {
    let path = static_contact::mesh_source::workspace_root()
        .join("meshes/punch-quarter_a10um_R100a_tet10_8k.msh");
    let mesh = gmsh_mesh::read_msh(&path).expect("committed quarter punch mesh");
    let body = BodyCompliance::build(&BodySpec {
        name: "slider",
        mesh: &mesh,
        volume_group: "body".into(),
        material: elastic_fem::Material::isotropic(
            material.youngs_modulus_pa(),
            material.poisson_ratio,
        )
        .unwrap(),
        contact_group: "punch".into(),
        disks: vec![Disk {
            centre_m: [0.0; 3],
            radius_m: RADIUS_M,
        }],
        lateral,
        clamped_groups: vec!["far_field".into()],
        roller_groups: vec![("sym_x0".into(), 0), ("sym_y0".into(), 1)],
        disk_fraction: 0.25,
        force_sign: 1.0,
    })
    .expect("quarter punch condenses");
    body.compliance_m_per_n[(0, 0)]
}

#[test]
fn single_post_on_a_flat_stator_has_the_series_stiffness_of_the_johnson_springs() {
    let si = Material::silicon();
    let ln = Material::lithium_niobate();
    let slider = punch_compliance(&si, TipLateral::Bonded);
    let stator = punch_compliance(&ln, TipLateral::Free);
    let k_pn = k_pn(&si, RADIUS_M).unwrap();
    let k_sn = k_sn(&ln, RADIUS_M).unwrap();
    assert!(
        (1.0 / (slider * k_pn) - 1.0).abs() < FEM_TOLERANCE,
        "bonded post stiffness {:.5e} vs k_pn {k_pn:.5e} N/m",
        1.0 / slider
    );
    assert!(
        (1.0 / (stator * k_sn) - 1.0).abs() < FEM_TOLERANCE,
        "frictionless stator disk stiffness {:.5e} vs k_sn {k_sn:.5e} N/m",
        1.0 / stator
    );
    // Contact of the one post: meshed slider side + meshed stator side, load control.
    let preload_n = 0.01;
    let problem = ContactProblem {
        compliance_m_per_n: DMatrix::from_element(1, 1, slider + stator),
        obstacle_height_m: vec![0.0],
        preload_n,
        length_scale_m: None,
    };
    let solution = ActiveSetSolver::default().solve(&problem).unwrap();
    let stiffness = preload_n / -solution.reference_height_m;
    let expected = series(k_pn, k_sn);
    assert!(
        (stiffness / expected - 1.0).abs() < FEM_TOLERANCE,
        "single-post contact stiffness {stiffness:.5e} vs k_pn ⊕ k_sn {expected:.5e} N/m"
    );
    assert!(
        (solution.force_n[0] - preload_n).abs() < 1e-15,
        "the one post carries the preload"
    );
    println!(
        "k_slider/k_pn = {:.5}, k_stator/k_sn = {:.5}, k/(k_pn ⊕ k_sn) = {:.5}",
        1.0 / (slider * k_pn),
        1.0 / (stator * k_sn),
        stiffness / expected
    );
}
