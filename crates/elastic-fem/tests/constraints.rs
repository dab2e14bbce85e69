//! Constraints: rigid face (bar stiffness E A / L), periodic pairs (exact simple shear of a
//! periodic layer), singular systems (named rigid-body modes), conflicting values.

mod common;

use common::{max_abs, model_of};
use elastic_fem::mesh_gen::{BoxFace, BoxMesh};
use elastic_fem::{
    Constraints, Dirichlet, FemError, LameParameters, Material, PeriodicPairs, RigidComponent,
    RigidFace, SolverOptions, StaticProblem, loads, solve_static,
};

const E_PA: f64 = 200e9;
const NU: f64 = 0.3;

/// Node of the mesh closest to `x`.
fn node_at(mesh: &BoxMesh, x: [f64; 3]) -> usize {
    (0..mesh.nodes.len())
        .min_by(|&a, &b| {
            let d = |n: usize| {
                (0..3)
                    .map(|j| (mesh.nodes[n][j] - x[j]).powi(2))
                    .sum::<f64>()
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap()
}

/// Bar [0, L] × [0, 1] × [0, 1]: rollers on x = 0 (u_x = 0) plus the three rigid-mode pins
/// that a uniaxial stress state satisfies exactly.
fn bar_supports(mesh: &BoxMesh) -> Vec<Dirichlet> {
    vec![
        Dirichlet::component(mesh.face_nodes(BoxFace::XMin), 0, 0.0),
        Dirichlet {
            nodes: vec![node_at(mesh, [0.0, 0.0, 0.0])],
            displacement_m: [None, Some(0.0), Some(0.0)],
        },
        Dirichlet::component(vec![node_at(mesh, [0.0, 1.0, 0.0])], 2, 0.0),
        Dirichlet::component(vec![node_at(mesh, [0.0, 0.0, 1.0])], 1, 0.0),
    ]
}

#[test]
fn bar_compressed_by_a_loaded_rigid_face_has_stiffness_ea_over_l() {
    let length = 4.0;
    let mesh = BoxMesh::tet10([length, 1.0, 1.0], [6, 2, 2]);
    let model = model_of(&mesh, Material::isotropic(E_PA, NU).unwrap());
    let force = -1e6; // N, compressive
    let face = RigidFace {
        nodes: mesh.face_nodes(BoxFace::XMax),
        components: [
            RigidComponent::Loaded { force_n: force },
            RigidComponent::Free,
            RigidComponent::Free,
        ],
    };
    let constraints = Constraints {
        dirichlet: bar_supports(&mesh),
        rigid_faces: vec![face],
        ..Default::default()
    };
    let f = vec![0.0; model.dof_count()];
    let sol = solve_static(
        &StaticProblem {
            model: &model,
            constraints: &constraints,
            load_n: &f,
        },
        &SolverOptions::default(),
    )
    .unwrap();
    let delta = sol.rigid_faces[0].displacement_m[0].expect("x is tied");
    let expected = force * length / (E_PA * 1.0);
    assert!(
        (delta - expected).abs() < 1e-10 * expected.abs(),
        "rigid face displacement {delta:e} m, E A / L predicts {expected:e} m"
    );
    let stiffness = force / delta;
    assert!(
        (stiffness - E_PA / length).abs() < 1e-9 * E_PA / length,
        "bar stiffness {stiffness:e} N/m vs E A / L"
    );
    // The face force is the applied force; the rollers carry it back.
    assert!(
        (sol.rigid_faces[0].force_n[0] - force).abs() < 1e-6 * force.abs(),
        "rigid face force {} N",
        sol.rigid_faces[0].force_n[0]
    );
    let roller_reaction: f64 = mesh
        .face_nodes(BoxFace::XMin)
        .iter()
        .map(|&n| sol.reaction_n[3 * n])
        .sum();
    assert!(
        (roller_reaction + force).abs() < 1e-6 * force.abs(),
        "reaction at x = 0: {roller_reaction} N, expected {}",
        -force
    );
    // Every face node moved by the same amount.
    for &n in &mesh.face_nodes(BoxFace::XMax) {
        assert!(
            (sol.node_displacement(n)[0] - delta).abs() < 1e-15,
            "face node {n} x displacement differs from the face's"
        );
    }
}

#[test]
fn prescribed_rigid_face_displacement_reports_reaction_ea_delta_over_l() {
    let length = 3.0;
    let mesh = BoxMesh::tet4([length, 1.0, 1.0], [6, 2, 2]);
    let model = model_of(&mesh, Material::isotropic(E_PA, NU).unwrap());
    let delta = -1e-5;
    let face = RigidFace {
        nodes: mesh.face_nodes(BoxFace::XMax),
        components: [
            RigidComponent::Prescribed {
                displacement_m: delta,
            },
            RigidComponent::Free,
            RigidComponent::Free,
        ],
    };
    let constraints = Constraints {
        dirichlet: bar_supports(&mesh),
        rigid_faces: vec![face],
        ..Default::default()
    };
    let f = vec![0.0; model.dof_count()];
    let sol = solve_static(
        &StaticProblem {
            model: &model,
            constraints: &constraints,
            load_n: &f,
        },
        &SolverOptions::default(),
    )
    .unwrap();
    let expected = E_PA * delta / length;
    let got = sol.rigid_faces[0].force_n[0];
    assert!(
        (got - expected).abs() < 1e-9 * expected.abs(),
        "rigid face reaction {got:e} N, E A delta / L = {expected:e} N"
    );
    let energy = 0.5 * E_PA / length * delta * delta;
    assert!(
        (sol.strain_energy_j - energy).abs() < 1e-9 * energy,
        "strain energy {} J vs {energy} J",
        sol.strain_energy_j
    );
}

#[test]
fn periodic_layer_under_shear_traction_deforms_in_exact_simple_shear() {
    let (lx, ly, h) = (1.0, 0.8, 0.5);
    let mesh = BoxMesh::tet4([lx, ly, h], [4, 3, 2]);
    let lame = LameParameters::from_young_poisson(E_PA, NU).unwrap();
    let model = model_of(&mesh, Material::Isotropic(lame));
    let tau = 1e6;
    let mut f = vec![0.0; model.dof_count()];
    loads::add_surface_traction(
        model.nodes(),
        &mesh.face_triangles(BoxFace::ZMax),
        [tau, 0.0, 0.0],
        &mut f,
    )
    .unwrap();
    let tol = 1e-9;
    let px = PeriodicPairs::match_by_translation(
        &mesh.nodes,
        &mesh.face_nodes(BoxFace::XMax),
        &mesh.face_nodes(BoxFace::XMin),
        [lx, 0.0, 0.0],
        tol,
        [true; 3],
    )
    .unwrap();
    let py = PeriodicPairs::match_by_translation(
        &mesh.nodes,
        &mesh.face_nodes(BoxFace::YMax),
        &mesh.face_nodes(BoxFace::YMin),
        [0.0, ly, 0.0],
        tol,
        [true; 3],
    )
    .unwrap();
    assert_eq!(
        px.pairs.len(),
        mesh.face_nodes(BoxFace::XMax).len(),
        "every x-slave node is paired"
    );
    let clamp = vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMin))];
    let periodic = Constraints {
        dirichlet: clamp.clone(),
        periodic: vec![px, py],
        ..Default::default()
    };
    let sol = solve_static(
        &StaticProblem {
            model: &model,
            constraints: &periodic,
            load_n: &f,
        },
        &SolverOptions::default(),
    )
    .unwrap();
    let mut worst = 0.0f64;
    for (n, x) in mesh.nodes.iter().enumerate() {
        let exact = [tau * x[2] / lame.mu, 0.0, 0.0];
        let u = sol.node_displacement(n);
        worst = worst.max((0..3).map(|j| (u[j] - exact[j]).abs()).fold(0.0, f64::max));
    }
    let scale = tau * h / lame.mu;
    assert!(
        worst < 1e-10 * scale,
        "periodic layer: deviation from simple shear {worst:e} m (scale {scale:e} m)"
    );

    // Contrast: without the periodic ties the free side faces spoil the simple shear.
    let free = Constraints {
        dirichlet: clamp,
        ..Default::default()
    };
    let sol = solve_static(
        &StaticProblem {
            model: &model,
            constraints: &free,
            load_n: &f,
        },
        &SolverOptions::default(),
    )
    .unwrap();
    let deviation = mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(n, x)| (sol.node_displacement(n)[0] - tau * x[2] / lame.mu).abs())
        .fold(0.0, f64::max);
    assert!(
        deviation > 1e-3 * scale,
        "non-periodic block should deviate from simple shear, deviation {deviation:e} m"
    );
}

#[test]
fn periodic_matching_names_an_unmatched_slave_node() {
    let mesh = BoxMesh::tet4([1.0, 1.0, 1.0], [2, 2, 2]);
    let err = PeriodicPairs::match_by_translation(
        &mesh.nodes,
        &mesh.face_nodes(BoxFace::XMax),
        &mesh.face_nodes(BoxFace::XMin),
        [0.9, 0.0, 0.0],
        1e-6,
        [true; 3],
    )
    .unwrap_err();
    let slave = mesh.face_nodes(BoxFace::XMax)[0];
    assert!(
        matches!(err, FemError::UnmatchedPeriodicNode { slave_node, .. } if slave_node == slave),
        "expected the first x-max node {slave} unmatched, got: {err}"
    );
}

fn solve_err(constraints: &Constraints, options: SolverOptions) -> FemError {
    let mesh = BoxMesh::tet4([2.0, 1.0, 1.0], [2, 2, 2]);
    let model = model_of(&mesh, Material::isotropic(E_PA, NU).unwrap());
    let mut f = vec![0.0; model.dof_count()];
    f[3 * 5 + 2] = 1.0;
    solve_static(
        &StaticProblem {
            model: &model,
            constraints,
            load_n: &f,
        },
        &options,
    )
    .unwrap_err()
}

#[test]
fn floating_body_error_names_every_unconstrained_rigid_mode() {
    let err = solve_err(&Constraints::default(), SolverOptions::default());
    let text = err.to_string();
    for mode in [
        "translation x",
        "translation y",
        "translation z",
        "rotation about x",
        "rotation about y",
        "rotation about z",
    ] {
        assert!(
            text.contains(mode),
            "error for a free body must name {mode}: {text}"
        );
    }

    // Only u_z = 0 on the bottom: x, y translations and rotation about z remain.
    let mesh = BoxMesh::tet4([2.0, 1.0, 1.0], [2, 2, 2]);
    let bottom_z = Constraints {
        dirichlet: vec![Dirichlet::component(mesh.face_nodes(BoxFace::ZMin), 2, 0.0)],
        ..Default::default()
    };
    let text = solve_err(&bottom_z, SolverOptions::default()).to_string();
    for mode in ["translation x", "translation y", "rotation about z"] {
        assert!(text.contains(mode), "error must name {mode}: {text}");
    }
    for mode in ["translation z", "rotation about x", "rotation about y"] {
        assert!(
            !text.contains(mode),
            "error must not name the constrained {mode}: {text}"
        );
    }
}

#[test]
fn singular_system_without_the_precheck_is_refused_as_singular_not_with_nan() {
    let mesh = BoxMesh::tet4([2.0, 1.0, 1.0], [2, 2, 2]);
    let bottom_z = Constraints {
        dirichlet: vec![Dirichlet::component(mesh.face_nodes(BoxFace::ZMin), 2, 0.0)],
        ..Default::default()
    };
    let err = solve_err(
        &bottom_z,
        SolverOptions {
            check_rigid_body_modes: false,
            ..Default::default()
        },
    );
    assert!(
        matches!(err, FemError::SingularSystem { .. }),
        "expected the null-space check's error, got: {err}"
    );
}

#[test]
fn conflicting_prescribed_values_on_a_tied_dof_are_rejected() {
    let mesh = BoxMesh::tet4([1.0, 1.0, 1.0], [1, 1, 1]);
    let face = mesh.face_nodes(BoxFace::ZMax);
    let constraints = Constraints {
        dirichlet: vec![
            Dirichlet::component(vec![face[0]], 2, 1e-3),
            Dirichlet::component(vec![face[1]], 2, 2e-3),
        ],
        rigid_faces: vec![RigidFace {
            nodes: face,
            components: [
                RigidComponent::Free,
                RigidComponent::Free,
                RigidComponent::Loaded { force_n: 0.0 },
            ],
        }],
        ..Default::default()
    };
    let err = elastic_fem::DofMap::new(mesh.nodes.len(), &constraints).unwrap_err();
    assert!(
        matches!(
            err,
            FemError::ConflictingPrescribedValues { component: 2, .. }
        ),
        "expected a conflict on z, got: {err}"
    );
}

#[test]
fn reactions_balance_applied_loads() {
    let mesh = BoxMesh::tet10([1.0, 1.0, 2.0], [2, 2, 3]);
    let model = model_of(&mesh, Material::isotropic(E_PA, NU).unwrap());
    let mut f = vec![0.0; model.dof_count()];
    loads::add_pressure(
        model.nodes(),
        &mesh.face_triangles(BoxFace::ZMax),
        2e6,
        &mut f,
    )
    .unwrap();
    loads::add_body_force(&model, |_| [0.0, 1e4, 0.0], &mut f).unwrap();
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMin))],
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
    for c in 0..3 {
        let applied: f64 = f.iter().skip(c).step_by(3).sum();
        let reaction: f64 = sol.reaction_n.iter().skip(c).step_by(3).sum();
        assert!(
            (applied + reaction).abs() < 1e-8 * max_abs(&f) * f.len() as f64,
            "component {c}: applied {applied} N, reaction {reaction} N"
        );
    }
    // Pressure 2 MPa on 1 m² pushes down with 2 MN.
    let fz: f64 = f.iter().skip(2).step_by(3).sum();
    assert!(
        (fz + 2e6).abs() < 1e-6,
        "total pressure force {fz} N, expected -2e6 N"
    );
}

/// Regression: the body detection once linked a stale root, so an element whose first node
/// was not the smallest (e.g. [2, 1, 3, 0]) split one connected mesh into two "bodies".
#[test]
fn one_element_with_unsorted_nodes_is_one_body_with_six_rigid_modes() {
    let nodes = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let model = elastic_fem::Model::tet4(
        &nodes,
        &[[2, 1, 3, 0]],
        Material::isotropic(E_PA, NU).unwrap(),
    )
    .unwrap();
    let modes =
        elastic_fem::free_rigid_body_modes(&model, &elastic_fem::DofMap::unconstrained(4)).unwrap();
    assert_eq!(
        modes.len(),
        6,
        "a single free tetrahedron has 6 rigid modes, found {modes:?}"
    );
    assert!(
        modes.iter().all(|m| m.body == 0),
        "all modes must belong to body 0: {modes:?}"
    );

    // A shuffled box mesh is one body too.
    let mesh = BoxMesh::tet10([1.0, 1.0, 1.0], [2, 2, 2]);
    let n = mesh.nodes.len();
    let perm: Vec<usize> = (0..n).map(|i| (i * 37 + 11) % n).collect();
    assert!(
        {
            let mut p = perm.clone();
            p.sort_unstable();
            p.dedup();
            p.len() == n
        },
        "37 must be coprime with the node count for a permutation"
    );
    let mut nodes = vec![[0.0; 3]; n];
    for (old, &new) in perm.iter().enumerate() {
        nodes[new] = mesh.nodes[old];
    }
    let elastic_fem::Connectivity::Tet10(conn) = &mesh.connectivity else {
        unreachable!()
    };
    let conn: Vec<[usize; 10]> = conn.iter().map(|e| e.map(|i| perm[i])).collect();
    let model =
        elastic_fem::Model::tet10(&nodes, &conn, Material::isotropic(E_PA, NU).unwrap()).unwrap();
    let modes =
        elastic_fem::free_rigid_body_modes(&model, &elastic_fem::DofMap::unconstrained(n)).unwrap();
    assert_eq!(
        modes.len(),
        6,
        "a free shuffled box has 6 rigid modes in one body, found {} modes",
        modes.len()
    );
}

/// Two disjoint blocks: A clamped at its bottom, B floating. B is reported alone (body 1);
/// tying B's x-min face to A's x-max face (periodic pairs across the gap) fixes it.
#[test]
fn a_floating_second_body_is_named_and_ties_to_a_fixed_body_constrain_it() {
    let a = BoxMesh::tet4([1.0, 1.0, 1.0], [2, 2, 2]);
    let offset = a.nodes.len();
    let mut nodes = a.nodes.clone();
    nodes.extend(a.nodes.iter().map(|x| [x[0] + 2.0, x[1], x[2]]));
    let elastic_fem::Connectivity::Tet4(conn) = &a.connectivity else {
        unreachable!()
    };
    let mut tets = conn.clone();
    tets.extend(conn.iter().map(|e| e.map(|i| i + offset)));
    let model =
        elastic_fem::Model::tet4(&nodes, &tets, Material::isotropic(E_PA, NU).unwrap()).unwrap();
    let clamp = vec![Dirichlet::clamped(a.face_nodes(BoxFace::ZMin))];
    let loose = Constraints {
        dirichlet: clamp.clone(),
        ..Default::default()
    };
    let modes = elastic_fem::free_rigid_body_modes(
        &model,
        &elastic_fem::DofMap::new(nodes.len(), &loose).unwrap(),
    )
    .unwrap();
    assert_eq!(
        modes.len(),
        6,
        "the floating block has 6 free modes: {modes:?}"
    );
    assert!(
        modes.iter().all(|m| m.body == 1 && m.body_node == offset),
        "all free modes belong to the second block: {modes:?}"
    );

    let slaves: Vec<usize> = a
        .face_nodes(BoxFace::XMin)
        .iter()
        .map(|i| i + offset)
        .collect();
    let tie = PeriodicPairs::match_by_translation(
        &nodes,
        &slaves,
        &a.face_nodes(BoxFace::XMax),
        [1.0, 0.0, 0.0],
        1e-9,
        [true; 3],
    )
    .unwrap();
    let tied = Constraints {
        dirichlet: clamp,
        periodic: vec![tie],
        ..Default::default()
    };
    let modes = elastic_fem::free_rigid_body_modes(
        &model,
        &elastic_fem::DofMap::new(nodes.len(), &tied).unwrap(),
    )
    .unwrap();
    assert!(
        modes.is_empty(),
        "the tied block must have no free rigid mode: {modes:?}"
    );
}

/// The Tet10 bar on its supports with a rigid end face: x and y tied (merged DOFs, doubled
/// couplings), z prescribed. Exercises every kind of reduced entry.
fn bar_with_a_tied_end_face() -> (elastic_fem::Model, Constraints) {
    let mesh = BoxMesh::tet10([4.0, 1.0, 1.0], [6, 2, 2]);
    let model = model_of(&mesh, Material::isotropic(E_PA, NU).unwrap());
    let constraints = Constraints {
        dirichlet: bar_supports(&mesh),
        rigid_faces: vec![RigidFace {
            nodes: mesh.face_nodes(BoxFace::XMax),
            components: [
                RigidComponent::Loaded { force_n: 1.0 },
                RigidComponent::Loaded { force_n: 0.0 },
                RigidComponent::Prescribed {
                    displacement_m: 1e-6,
                },
            ],
        }],
        ..Default::default()
    };
    (model, constraints)
}

#[test]
fn reduction_built_from_the_pattern_before_assembly_equals_the_one_built_from_the_matrix() {
    use elastic_fem::{DofMap, ReducedSystem, StiffnessPattern, assemble_stiffness};
    let (model, constraints) = bar_with_a_tied_end_face();
    let pattern = StiffnessPattern::build(&model);
    let dof_map = || DofMap::new(model.node_count(), &constraints).unwrap();
    let early = ReducedSystem::from_pattern(&pattern, dof_map()).unwrap();
    let stiffness = assemble_stiffness(&model, &pattern).unwrap();
    let late = ReducedSystem::new(&stiffness, dof_map()).unwrap();
    let mut k_early = early.zero_matrix();
    assert!(k_early.values().iter().all(|&v| v == 0.0));
    early.reduce_matrix_into(&stiffness, &mut k_early).unwrap();
    let k_late = late.reduce_matrix(&stiffness).unwrap();
    assert_eq!(k_early.col_ptr(), k_late.col_ptr());
    assert_eq!(k_early.row_idx(), k_late.row_idx());
    assert_eq!(k_early.values(), k_late.values());
    assert!(k_late.values().iter().any(|&v| v != 0.0));
}

#[test]
fn reduction_straight_into_full_rows_has_the_bits_of_the_upper_copy_made_full() {
    use elastic_fem::sparse::CsrMatrix;
    use elastic_fem::{DofMap, ReducedSystem, StiffnessPattern, assemble_stiffness};
    let (model, constraints) = bar_with_a_tied_end_face();
    let pattern = StiffnessPattern::build(&model);
    let stiffness = assemble_stiffness(&model, &pattern).unwrap();
    let dof_map = DofMap::new(model.node_count(), &constraints).unwrap();
    let reduced = ReducedSystem::new(&stiffness, dof_map).unwrap();
    let direct = reduced.reduce_matrix_csr(&stiffness).unwrap();
    let via_upper = CsrMatrix::from_symmetric(&reduced.reduce_matrix(&stiffness).unwrap()).unwrap();
    assert_eq!(direct.nnz(), via_upper.nnz());
    assert_eq!(direct.diagonal(), via_upper.diagonal());
    let n = reduced.dim();
    for seed in 1..4 {
        let x: Vec<f64> = (0..n)
            .map(|i| ((i * 7919 + seed * 104729) % 1000) as f64 - 499.5)
            .collect();
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        direct.mul_vec(&x, &mut a);
        via_upper.mul_vec(&x, &mut b);
        assert_eq!(a, b, "products differ for seed {seed}");
    }
}
