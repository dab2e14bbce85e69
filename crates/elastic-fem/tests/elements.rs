//! Element behaviour: volumetric locking of Tet4 as ν → ½, badly shaped elements, materials,
//! consistent surface loads, stress post-processing.

mod common;

use common::model_of;
use elastic_fem::mesh_gen::{BoxFace, BoxMesh};
use elastic_fem::post::{centroid_stresses, nodal_averaged_stress};
use elastic_fem::{
    Constraints, CubicCrystal, Dirichlet, FemError, LameParameters, Material, Model, SolverOptions,
    StaticProblem, SurfaceTriangles, loads, solve_static,
};

/// Tip deflection of a clamped cantilever (L = 10, 1 × 1 section, E = 1 Pa) under a total tip
/// shear P = 1e-3 N, divided by the Timoshenko beam value P L³/(3 E I) + P L/(κ G A), κ = 5/6.
fn cantilever_ratio(mesh: &BoxMesh, nu: f64) -> f64 {
    let (e, length, p) = (1.0, mesh.lengths_m[0], 1e-3);
    let model = model_of(mesh, Material::isotropic(e, nu).unwrap());
    let mut f = vec![0.0; model.dof_count()];
    loads::add_surface_traction(
        model.nodes(),
        &mesh.face_triangles(BoxFace::XMax),
        [0.0, 0.0, -p],
        &mut f,
    )
    .unwrap();
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::XMin))],
        ..Default::default()
    };
    let sol = solve_static(
        &StaticProblem {
            model: &model,
            constraints: &constraints,
            load_n: &f,
        },
        &SolverOptions::default(),
    )
    .unwrap();
    let tip = mesh.face_nodes(BoxFace::XMax);
    let deflection = -tip
        .iter()
        .map(|&n| sol.node_displacement(n)[2])
        .sum::<f64>()
        / tip.len() as f64;
    let g = e / (2.0 * (1.0 + nu));
    let beam = p * length.powi(3) / (3.0 * e / 12.0) + p * length / (5.0 / 6.0 * g);
    deflection / beam
}

/// Measured (this code, METIS ordering), deflection / Timoshenko value, with the same node
/// count (21 × 3 × 3 nodes) for both element types:
///
/// | mesh                 | ν = 0.3 | ν = 0.499 |
/// |----------------------|---------|-----------|
/// | Tet4  20 × 2 × 2     | 0.504   | 0.021     |
/// | Tet10 10 × 1 × 1     | 0.976   | 0.863     |
///
/// Tet4 is already too stiff at ν = 0.3 (bending with constant-strain elements) and locks
/// volumetrically at ν = 0.499 (40× too stiff); Tet10 with one element through the thickness
/// stays within 15 % of beam theory (the clamp restrains the Poisson contraction).
#[test]
fn tet4_locks_near_incompressibility_while_tet10_does_not() {
    let tet4 = BoxMesh::tet4([10.0, 1.0, 1.0], [20, 2, 2]);
    let tet10 = BoxMesh::tet10([10.0, 1.0, 1.0], [10, 1, 1]);
    assert_eq!(
        tet4.nodes.len(),
        tet10.nodes.len(),
        "same number of nodes for a fair comparison"
    );
    let r4 = [cantilever_ratio(&tet4, 0.3), cantilever_ratio(&tet4, 0.499)];
    let r10 = [
        cantilever_ratio(&tet10, 0.3),
        cantilever_ratio(&tet10, 0.499),
    ];
    eprintln!("cantilever deflection / Timoshenko: Tet4 {r4:?}, Tet10 {r10:?} (nu = 0.3, 0.499)");
    assert!(
        r10[1] > 0.8 && r10[1] < 1.05,
        "Tet10 at nu = 0.499: deflection ratio {} should be near 1",
        r10[1]
    );
    assert!(
        r4[1] < 0.25 * r10[1],
        "Tet4 at nu = 0.499 ({}) must be far stiffer than Tet10 ({})",
        r4[1],
        r10[1]
    );
    assert!(
        r4[1] < 0.5 * r4[0],
        "Tet4 must stiffen as nu -> 0.5: ratio {} at 0.3, {} at 0.499",
        r4[0],
        r4[1]
    );
}

#[test]
fn inverted_and_flat_elements_are_rejected_with_their_index_and_slivers_are_flagged() {
    let nodes = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 0.0],
        [0.5, 0.5, 1e-13],
        [0.5, 0.5, 0.02],
    ];
    let m = Material::isotropic(1e9, 0.25).unwrap();
    let inverted = Model::tet4(&nodes, &[[0, 1, 2, 3], [1, 0, 4, 3]], m).unwrap_err();
    assert!(
        matches!(inverted, FemError::InvertedElement { element: 1, .. }),
        "inverted element 1 expected, got: {inverted}"
    );
    let flat = Model::tet4(&nodes, &[[0, 1, 2, 3], [0, 1, 4, 5]], m).unwrap_err();
    assert!(
        matches!(flat, FemError::DegenerateElement { element: 1, .. }),
        "degenerate element 1 expected, got: {flat}"
    );
    // A thin but valid sliver (height 0.02 over a unit base): accepted, flagged.
    let model = Model::tet4(&nodes, &[[0, 1, 2, 3], [0, 1, 4, 6]], m).unwrap();
    assert_eq!(
        model.quality().poor_elements,
        vec![1],
        "the sliver must be flagged as poorly shaped"
    );
    assert!(
        model.quality().min_quality < 0.05,
        "sliver quality {}",
        model.quality().min_quality
    );
    // Out-of-range node and repeated node.
    let err = Model::tet4(&nodes, &[[0, 1, 2, 9]], m).unwrap_err();
    assert!(
        matches!(
            err,
            FemError::NodeIndexOutOfRange {
                element: 0,
                node: 9,
                ..
            }
        ),
        "got: {err}"
    );
    let err = Model::tet4(&nodes, &[[0, 1, 1, 3]], m).unwrap_err();
    assert!(
        matches!(
            err,
            FemError::RepeatedNodeInElement {
                element: 0,
                node: 1
            }
        ),
        "got: {err}"
    );
}

#[test]
fn tangled_curved_tet10_is_reported_as_inverted() {
    let mut mesh = BoxMesh::tet10([1.0, 1.0, 1.0], [1, 1, 1]);
    // Slide the mid-edge node of element 2's edge (0,1) past the quarter point towards vertex 0:
    // det J vanishes at the vertex for the quarter point and turns negative beyond it.
    let elastic_fem::Connectivity::Tet10(conn) = &mesh.connectivity else {
        unreachable!()
    };
    let el = conn[2];
    let (x0, x1) = (mesh.nodes[el[0]], mesh.nodes[el[1]]);
    mesh.nodes[el[4]] = std::array::from_fn(|j| x0[j] + 0.1 * (x1[j] - x0[j]));
    let err = Model::new(
        mesh.nodes.clone(),
        mesh.connectivity.clone(),
        Material::isotropic(1e9, 0.3).unwrap(),
    )
    .unwrap_err();
    assert!(
        matches!(err, FemError::InvertedElement { .. }),
        "expected a tangled (inverted) curved element, got: {err}"
    );
}

#[test]
fn material_conversions_match_tabulated_values_and_reject_bad_parameters() {
    let steel = LameParameters::from_young_poisson(200e9, 0.3).unwrap();
    assert!(
        (steel.mu - 76.923_076_923e9).abs() < 1e3,
        "steel shear modulus {} Pa",
        steel.mu
    );
    assert!(
        (steel.lambda - 115.384_615_385e9).abs() < 1e3,
        "steel lambda {} Pa",
        steel.lambda
    );
    assert!(
        (steel.young_modulus_pa() - 200e9).abs() < 1e-3
            && (steel.poisson_ratio() - 0.3).abs() < 1e-15,
        "round trip E, nu"
    );
    let si = LameParameters::from_shear_poisson(66.5e9, 0.22).unwrap();
    assert!(
        (si.young_modulus_pa() - 162.26e9).abs() < 1e4,
        "Si Young's modulus {} Pa",
        si.young_modulus_pa()
    );
    for (e, nu, parameter) in [
        (200e9, 0.5, "poisson_ratio"),
        (200e9, -1.0, "poisson_ratio"),
        (-1.0, 0.3, "young_modulus_pa"),
        (f64::NAN, 0.3, "young_modulus_pa"),
    ] {
        match LameParameters::from_young_poisson(e, nu) {
            Err(FemError::InvalidMaterialParameter { parameter: p, .. }) => {
                assert_eq!(p, parameter, "E = {e}, nu = {nu}")
            }
            other => {
                panic!("E = {e}, nu = {nu}: expected an error naming {parameter}, got {other:?}")
            }
        }
    }
    // Cubic silicon rotated 45° about z: C11' = (C11 + C12)/2 + C44, C12' = (C11 + C12)/2 − C44,
    // C66' = (C11 − C12)/2; a 90° rotation leaves the tensor unchanged.
    let si100 = CubicCrystal::silicon_100();
    let c = CubicCrystal::new(
        si100.c11_pa,
        si100.c12_pa,
        si100.c44_pa,
        CubicCrystal::rotation_about_z(std::f64::consts::FRAC_PI_4),
    )
    .unwrap()
    .voigt_stiffness();
    let (c11, c12, c44) = (165.7e9, 63.9e9, 79.6e9);
    assert!(
        (c[(0, 0)] - ((c11 + c12) / 2.0 + c44)).abs() < 1e-3,
        "rotated C11' = {}",
        c[(0, 0)]
    );
    assert!(
        (c[(0, 1)] - ((c11 + c12) / 2.0 - c44)).abs() < 1e-3,
        "rotated C12' = {}",
        c[(0, 1)]
    );
    assert!(
        (c[(5, 5)] - (c11 - c12) / 2.0).abs() < 1e-3,
        "rotated C66' = {}",
        c[(5, 5)]
    );
    let c90 = CubicCrystal::new(
        c11,
        c12,
        c44,
        CubicCrystal::rotation_about_z(std::f64::consts::FRAC_PI_2),
    )
    .unwrap()
    .voigt_stiffness();
    assert!(
        (c90 - si100.voigt_stiffness()).amax() < 1e-2,
        "90 degree rotation must leave cubic C unchanged"
    );
    assert!(
        CubicCrystal::new(c11, c11 + 1.0, c44, nalgebra::Matrix3::identity()).is_err(),
        "C11 < C12 must be rejected"
    );
}

#[test]
fn consistent_surface_loads_on_tri3_and_tri6_sum_to_pressure_times_area() {
    for mesh in [
        BoxMesh::tet4([2.0, 3.0, 1.0], [2, 3, 1]),
        BoxMesh::tet10([2.0, 3.0, 1.0], [2, 3, 1]),
    ] {
        let tris = mesh.face_triangles(BoxFace::ZMax);
        let area = loads::surface_area(&mesh.nodes, &tris).unwrap();
        assert!(
            (area - 6.0).abs() < 1e-12,
            "top face area {area} m², expected 6"
        );
        let mut f = vec![0.0; 3 * mesh.nodes.len()];
        loads::add_pressure(&mesh.nodes, &tris, 1e5, &mut f).unwrap();
        let fz: f64 = f.iter().skip(2).step_by(3).sum();
        assert!(
            (fz + 6e5).abs() < 1e-6,
            "pressure resultant {fz} N, expected -6e5 N (into the body)"
        );
        if let SurfaceTriangles::Tri6(t) = &tris {
            // Flat quadratic triangle under uniform load: corner nodes carry nothing.
            for tri in t {
                for &corner in &tri[..3] {
                    assert!(
                        f[3 * corner + 2].abs() < 1e-6,
                        "Tri6 corner node {corner} load {} N, expected 0",
                        f[3 * corner + 2]
                    );
                }
            }
        }
    }
    // Gravity: total = rho g V.
    let mesh = BoxMesh::tet10([2.0, 1.0, 0.5], [2, 1, 1]);
    let model = model_of(&mesh, Material::isotropic(1e9, 0.3).unwrap());
    let mut f = vec![0.0; model.dof_count()];
    loads::add_body_force(&model, |_| [0.0, 0.0, -2329.0 * 9.81], &mut f).unwrap();
    let fz: f64 = f.iter().skip(2).step_by(3).sum();
    assert!((fz + 2329.0 * 9.81 * 1.0).abs() < 1e-8, "weight {fz} N");
}

#[test]
fn uniaxial_tension_gives_uniform_stress_von_mises_and_energy() {
    let (e, nu, sigma) = (70e9, 0.33, 1e8);
    let mesh = BoxMesh::tet10([2.0, 1.0, 1.0], [2, 1, 1]);
    let model = model_of(&mesh, Material::isotropic(e, nu).unwrap());
    let mut f = vec![0.0; model.dof_count()];
    loads::add_surface_traction(
        model.nodes(),
        &mesh.face_triangles(BoxFace::XMax),
        [sigma, 0.0, 0.0],
        &mut f,
    )
    .unwrap();
    loads::add_surface_traction(
        model.nodes(),
        &mesh.face_triangles(BoxFace::XMin),
        [-sigma, 0.0, 0.0],
        &mut f,
    )
    .unwrap();
    // Statically determinate supports: pin the origin, fix y,z at (0,1,0)... rigid modes only.
    let node = |x: [f64; 3]| {
        mesh.nodes
            .iter()
            .position(|p| (0..3).all(|j| (p[j] - x[j]).abs() < 1e-12))
            .unwrap()
    };
    let constraints = Constraints {
        dirichlet: vec![
            Dirichlet::clamped(vec![node([0.0, 0.0, 0.0])]),
            Dirichlet {
                nodes: vec![node([2.0, 0.0, 0.0])],
                displacement_m: [None, Some(0.0), Some(0.0)],
            },
            Dirichlet::component(vec![node([0.0, 1.0, 0.0])], 2, 0.0),
        ],
        ..Default::default()
    };
    let sol = solve_static(
        &StaticProblem {
            model: &model,
            constraints: &constraints,
            load_n: &f,
        },
        &SolverOptions::default(),
    )
    .unwrap();
    for (k, s) in centroid_stresses(&model, &sol.displacement_m)
        .unwrap()
        .iter()
        .enumerate()
    {
        assert!(
            (s.stress_pa[0] - sigma).abs() < 1e-6 * sigma,
            "element {k} sigma_xx {} Pa",
            s.stress_pa[0]
        );
        assert!(
            (s.von_mises_pa() - sigma).abs() < 1e-6 * sigma,
            "element {k} von Mises {} Pa",
            s.von_mises_pa()
        );
        assert!(
            (s.strain[1] + nu * sigma / e).abs() < 1e-6 * sigma / e,
            "element {k} lateral strain {}",
            s.strain[1]
        );
    }
    for (n, s) in nodal_averaged_stress(&model, &sol.displacement_m)
        .unwrap()
        .iter()
        .enumerate()
    {
        assert!(
            (s[0] - sigma).abs() < 1e-6 * sigma,
            "node {n} averaged sigma_xx {} Pa",
            s[0]
        );
    }
    let energy = sigma * sigma / (2.0 * e) * 2.0;
    assert!(
        (sol.strain_energy_j - energy).abs() < 1e-6 * energy,
        "strain energy {} J, expected {energy} J",
        sol.strain_energy_j
    );
}
