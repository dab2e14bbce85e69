//! Element/assembly consistency: patch test, rigid-body null space, assembled K against a
//! dense reference assembly, positive definiteness after constraints, ordering equivalence.

mod common;

use common::{Lcg, curved_tet10_box, distort, max_abs, model_of, steel};
use elastic_fem::element::{Constitutive, tet4_stiffness_into, tet10_stiffness_into};
use elastic_fem::mesh_gen::BoxMesh;
use elastic_fem::post::centroid_stresses;
use elastic_fem::sparse::{Ordering, SymbolicCholesky};
use elastic_fem::{
    Connectivity, Constraints, CubicCrystal, Dirichlet, DofMap, Material, Model, ReducedSystem,
    SolverOptions, StaticProblem, StiffnessPattern, assemble_stiffness, assemble_stiffness_into,
    solve_static,
};
use nalgebra::{DMatrix, SMatrix};

/// Affine field u(x) = c + A x.
fn affine(x: [f64; 3]) -> [f64; 3] {
    let a = [
        [1.0e-3, 2.0e-4, -3.0e-4],
        [-5.0e-4, 7.0e-4, 1.1e-4],
        [2.5e-4, -1.5e-4, -6.0e-4],
    ];
    let c = [1e-5, -2e-5, 3e-5];
    std::array::from_fn(|i| c[i] + a[i][0] * x[0] + a[i][1] * x[1] + a[i][2] * x[2])
}

/// Solves with u = affine on the boundary and checks the interior reproduces it.
fn patch_test(mesh: &BoxMesh, material: Material, label: &str) {
    let model = model_of(mesh, material);
    let boundary = mesh.boundary_nodes();
    let dirichlet = boundary
        .iter()
        .map(|&n| {
            let u = affine(mesh.nodes[n]);
            Dirichlet {
                nodes: vec![n],
                displacement_m: u.map(Some),
            }
        })
        .collect();
    let constraints = Constraints {
        dirichlet,
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
    let mut worst = 0.0f64;
    for n in 0..model.node_count() {
        let exact = affine(mesh.nodes[n]);
        let u = sol.node_displacement(n);
        for j in 0..3 {
            worst = worst.max((u[j] - exact[j]).abs());
        }
    }
    let scale = max_abs(&sol.displacement_m);
    assert!(
        worst < 1e-10 * scale,
        "{label}: patch test displacement error {worst:e} m vs scale {scale:e} m"
    );
    // Constant stress C : sym(A).
    let strain = {
        let g = |i: usize, j: usize| {
            let mut e = [0.0; 3];
            e[j] = 1.0;
            affine(e)[i] - affine([0.0; 3])[i]
        };
        [
            g(0, 0),
            g(1, 1),
            g(2, 2),
            g(1, 2) + g(2, 1),
            g(0, 2) + g(2, 0),
            g(0, 1) + g(1, 0),
        ]
    };
    let expected = material.voigt_stiffness() * nalgebra::Vector6::from(strain);
    let stresses = centroid_stresses(&model, &sol.displacement_m).unwrap();
    let smax = expected.amax();
    for (e, s) in stresses.iter().enumerate() {
        for k in 0..6 {
            assert!(
                (s.stress_pa[k] - expected[k]).abs() < 1e-8 * smax,
                "{label}: element {e} stress component {k} = {} Pa, expected {} Pa",
                s.stress_pa[k],
                expected[k]
            );
        }
    }
}

#[test]
fn patch_test_reproduces_affine_displacement_on_distorted_tet4_and_tet10_meshes() {
    let mut tet4 = BoxMesh::tet4([1.0, 1.2, 0.8], [3, 3, 3]);
    distort(&mut tet4, 0.08);
    patch_test(&tet4, steel(), "Tet4 distorted");

    let mut tet10 = BoxMesh::tet10([1.0, 1.2, 0.8], [2, 2, 2]);
    distort(&mut tet10, 0.08);
    tet10.straighten_edges();
    patch_test(&tet10, steel(), "Tet10 distorted straight-sided");

    let curved = curved_tet10_box();
    patch_test(&curved, steel(), "Tet10 curved (degree-5 rule)");

    let silicon_45 = Material::Cubic(
        CubicCrystal::new(
            165.7e9,
            63.9e9,
            79.6e9,
            CubicCrystal::rotation_about_z(0.785),
        )
        .unwrap(),
    );
    patch_test(&tet10, silicon_45, "Tet10 rotated cubic silicon");
}

/// The six rigid modes evaluated at the nodes.
fn rigid_modes(nodes: &[[f64; 3]]) -> Vec<Vec<f64>> {
    let mut modes = Vec::new();
    for k in 0..3 {
        modes.push(
            nodes
                .iter()
                .flat_map(|_| std::array::from_fn::<f64, 3, _>(|j| if j == k { 1.0 } else { 0.0 }))
                .collect(),
        );
    }
    for k in 0..3 {
        modes.push(
            nodes
                .iter()
                .flat_map(|x| {
                    let mut w = [0.0; 3];
                    w[k] = 1.0;
                    [
                        w[1] * x[2] - w[2] * x[1],
                        w[2] * x[0] - w[0] * x[2],
                        w[0] * x[1] - w[1] * x[0],
                    ]
                })
                .collect(),
        );
    }
    modes
}

#[test]
fn rigid_body_modes_lie_in_the_null_space_of_the_unconstrained_stiffness() {
    for (label, mut mesh) in [
        ("Tet4", BoxMesh::tet4([1.0, 2.0, 1.5], [3, 3, 2])),
        ("Tet10", BoxMesh::tet10([1.0, 2.0, 1.5], [2, 2, 2])),
    ] {
        distort(&mut mesh, 0.05);
        let model = model_of(&mesh, steel());
        let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
        let kmax = max_abs(k.values());
        for (m, r) in rigid_modes(&mesh.nodes).iter().enumerate() {
            let mut kr = vec![0.0; r.len()];
            k.mul_vec(r, &mut kr);
            let rel = max_abs(&kr) / (kmax * max_abs(r));
            assert!(
                rel < 1e-12,
                "{label}: |K r| / (|K| |r|) for rigid mode {m} = {rel:e}"
            );
        }
        // Strain energy of a rigid motion is zero; of a stretch it is positive.
        let stretch: Vec<f64> = mesh.nodes.iter().flat_map(|x| [x[0], 0.0, 0.0]).collect();
        assert!(
            k.quadratic_form(&stretch) > 0.0,
            "{label}: energy of a uniform stretch must be positive"
        );
    }
}

/// Dense reference assembly straight from the element kernels.
fn dense_reference(model: &Model) -> DMatrix<f64> {
    let n = model.dof_count();
    let mut k = DMatrix::zeros(n, n);
    let law = Constitutive::from(model.material_of(0));
    match model.connectivity() {
        Connectivity::Tet4(c) => {
            for el in c {
                let x = el.map(|i| model.nodes()[i]);
                let mut ke = SMatrix::<f64, 12, 12>::zeros();
                tet4_stiffness_into(&mut ke, &x, &law).unwrap();
                for a in 0..12 {
                    for b in 0..12 {
                        k[(3 * el[a / 3] + a % 3, 3 * el[b / 3] + b % 3)] += ke[(a, b)];
                    }
                }
            }
        }
        Connectivity::Tet10(c) => {
            for el in c {
                let x = el.map(|i| model.nodes()[i]);
                let mut ke = SMatrix::<f64, 30, 30>::zeros();
                tet10_stiffness_into(&mut ke, &x, &law).unwrap();
                for a in 0..30 {
                    for b in 0..30 {
                        k[(3 * el[a / 3] + a % 3, 3 * el[b / 3] + b % 3)] += ke[(a, b)];
                    }
                }
            }
        }
    }
    k
}

/// Renumbers the nodes of a mesh by a pseudo-random permutation.
fn shuffled(mesh: &BoxMesh) -> (Vec<[f64; 3]>, Connectivity) {
    let n = mesh.nodes.len();
    let mut perm: Vec<usize> = (0..n).collect();
    let mut rng = Lcg(7);
    for i in (1..n).rev() {
        let j = (rng.next_f64() * (i + 1) as f64) as usize;
        perm.swap(i, j);
    }
    let mut nodes = vec![[0.0; 3]; n];
    for (old, &new) in perm.iter().enumerate() {
        nodes[new] = mesh.nodes[old];
    }
    let conn = match &mesh.connectivity {
        Connectivity::Tet4(c) => Connectivity::Tet4(c.iter().map(|e| e.map(|i| perm[i])).collect()),
        Connectivity::Tet10(c) => {
            Connectivity::Tet10(c.iter().map(|e| e.map(|i| perm[i])).collect())
        }
    };
    (nodes, conn)
}

#[test]
fn assembled_stiffness_equals_dense_reference_and_is_symmetric_with_shuffled_numbering() {
    for mesh in [
        BoxMesh::tet4([1.0, 1.0, 1.0], [2, 2, 1]),
        BoxMesh::tet10([1.0, 1.0, 1.0], [2, 1, 1]),
    ] {
        let (nodes, conn) = shuffled(&mesh);
        let model = Model::new(nodes, conn, steel()).unwrap();
        let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
        let dense = dense_reference(&model);
        let scale = dense.amax();
        let asym = (&dense - dense.transpose()).amax() / scale;
        assert!(asym < 1e-14, "dense reference K asymmetry = {asym:e}");
        let full = k.to_full();
        for i in 0..model.dof_count() {
            for j in 0..model.dof_count() {
                let sparse = k.get(i, j);
                assert!(
                    (sparse - dense[(i, j)]).abs() <= 1e-13 * scale,
                    "K[{i},{j}]: sparse {sparse} vs dense {} N/m",
                    dense[(i, j)]
                );
            }
        }
        assert_eq!(full.nrows(), model.dof_count(), "full operator dimension");
    }
}

#[test]
fn reduced_stiffness_is_positive_definite_once_rigid_modes_are_removed() {
    let mesh = BoxMesh::tet10([1.0, 0.5, 0.5], [2, 1, 1]);
    let model = model_of(&mesh, steel());
    let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(
            mesh.face_nodes(elastic_fem::mesh_gen::BoxFace::XMin),
        )],
        ..Default::default()
    };
    let reduced =
        ReducedSystem::new(&k, DofMap::new(model.node_count(), &constraints).unwrap()).unwrap();
    let kr = reduced.reduce_matrix(&k).unwrap();
    let n = kr.dim();
    let dense = DMatrix::from_fn(n, n, |i, j| kr.get(i, j));
    let eig = dense.symmetric_eigenvalues();
    let (min, max) = (eig.min(), eig.max());
    assert!(
        min > 0.0,
        "smallest eigenvalue of the constrained stiffness = {min:e} N/m, must be positive"
    );
    assert!(
        min / max > 1e-10,
        "constrained stiffness condition estimate min/max = {:e}",
        min / max
    );
}

#[test]
fn metis_amd_and_natural_orderings_give_the_same_solution() {
    let mut mesh = BoxMesh::tet10([2.0, 1.0, 1.0], [4, 2, 2]);
    distort(&mut mesh, 0.05);
    let model = model_of(&mesh, steel());
    let mut f = vec![0.0; model.dof_count()];
    elastic_fem::loads::add_body_force(&model, |x| [0.0, 1e4 * x[0], -7.8e4], &mut f).unwrap();
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(
            mesh.face_nodes(elastic_fem::mesh_gen::BoxFace::XMin),
        )],
        ..Default::default()
    };
    let problem = StaticProblem {
        model: &model,
        constraints: &constraints,
        load_n: &f,
    };
    let solve = |ordering| {
        solve_static(
            &problem,
            &SolverOptions {
                ordering,
                ..Default::default()
            },
        )
        .unwrap()
    };
    let metis = solve(Ordering::Metis);
    assert_eq!(
        metis.report.ordering_used,
        Ordering::Metis,
        "METIS must be used, not its fallback"
    );
    let scale = max_abs(&metis.displacement_m);
    for ordering in [Ordering::Amd, Ordering::Natural] {
        let other = solve(ordering);
        let diff = metis
            .displacement_m
            .iter()
            .zip(&other.displacement_m)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            diff < 1e-10 * scale,
            "{ordering:?} vs METIS displacement difference {diff:e} m (scale {scale:e} m)"
        );
    }
}

#[test]
fn reassembly_for_a_new_material_reuses_pattern_reduction_and_symbolic_factorisation() {
    let mesh = BoxMesh::tet10([1.0, 1.0, 1.0], [2, 2, 2]);
    let mut model = model_of(&mesh, steel());
    let pattern = StiffnessPattern::build(&model);
    let mut k = assemble_stiffness(&model, &pattern).unwrap();
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(
            mesh.face_nodes(elastic_fem::mesh_gen::BoxFace::ZMin),
        )],
        ..Default::default()
    };
    let reduced =
        ReducedSystem::new(&k, DofMap::new(model.node_count(), &constraints).unwrap()).unwrap();
    let mut kr = reduced.reduce_matrix(&k).unwrap();
    let symbolic = SymbolicCholesky::analyze(&kr, Ordering::Metis).unwrap();
    let mut f = vec![0.0; model.dof_count()];
    f[3 * mesh.face_nodes(elastic_fem::mesh_gen::BoxFace::ZMax)[0] + 2] = -1e3;
    let mut numeric = symbolic.factor(&kr).unwrap();
    let u1 = numeric
        .solve(&reduced.reduce_load(&k, &f).unwrap())
        .unwrap();

    // Double Young's modulus: displacements halve.
    model
        .set_material(Material::isotropic(400e9, 0.3).unwrap())
        .unwrap();
    assemble_stiffness_into(&model, &pattern, &mut k).unwrap();
    reduced.reduce_matrix_into(&k, &mut kr).unwrap();
    numeric.refactor(&kr).unwrap();
    let u2 = numeric
        .solve(&reduced.reduce_load(&k, &f).unwrap())
        .unwrap();
    let worst = u1
        .iter()
        .zip(&u2)
        .map(|(a, b)| (a - 2.0 * b).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-12 * max_abs(&u1),
        "doubling E must halve the displacement: mismatch {worst:e} m"
    );
}

#[test]
fn a_negative_pivot_is_reported_at_its_own_column_by_simplicial_and_supernodal_kernels() {
    let mut kernels = Vec::new();
    for divisions in [1, 3] {
        let mesh = BoxMesh::tet10([1.0, 1.0, 1.0], [divisions; 3]);
        let model = model_of(&mesh, steel());
        let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
        let constraints = Constraints {
            dirichlet: vec![Dirichlet::clamped(
                mesh.face_nodes(elastic_fem::mesh_gen::BoxFace::ZMin),
            )],
            ..Default::default()
        };
        let reduced =
            ReducedSystem::new(&k, DofMap::new(model.node_count(), &constraints).unwrap()).unwrap();
        let mut kr = reduced.reduce_matrix(&k).unwrap();
        let column = kr.dim() / 2;
        let diag = kr.get(column, column);
        kr.add_to_diagonal(column, -3.0 * diag);
        let symbolic = SymbolicCholesky::analyze(&kr, Ordering::Metis).unwrap();
        kernels.push(symbolic.is_supernodal());
        match symbolic.factor(&kr) {
            Err(elastic_fem::FemError::NotPositiveDefinite { column: c, .. }) => assert_eq!(
                c,
                column,
                "failed column (supernodal = {}) must be the one with the negative diagonal",
                symbolic.is_supernodal()
            ),
            other => panic!("expected NotPositiveDefinite, got {other:?}"),
        }
    }
    assert_eq!(
        kernels,
        vec![false, true],
        "the small case must use the simplicial, the larger the supernodal kernel"
    );
}
