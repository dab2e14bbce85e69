//! The iterative path (p-multigrid PCG) against the direct Cholesky on the same reduced system,
//! its named failure, and the automatic choice between the two.

mod common;

use common::{distort, model_of, steel};
use elastic_fem::iterative::{CoarseSolver, IterativeSolver};
use elastic_fem::mesh_gen::{BoxFace, BoxMesh};
use elastic_fem::sparse::FactorOptions;
use elastic_fem::{
    Constraints, Dirichlet, DofMap, FemError, IterativeOptions, Model, ReducedSystem,
    RigidComponent, RigidFace, SolverMethod, SolverOptions, StaticProblem, StaticSolution,
    StiffnessPattern, assemble_stiffness, loads, solve_static,
};

/// A distorted Tet10 block clamped at z = 0 with an oblique traction on top and a rigid face
/// (tied x displacement) at x = L: exercises Dirichlet, ties and a full 3D stress state.
fn block(divisions: usize) -> (Model, Constraints, Vec<f64>) {
    let mut mesh = BoxMesh::tet10([2.0, 1.0, 1.0], [2 * divisions, divisions, divisions]);
    distort(&mut mesh, 0.05);
    let model = model_of(&mesh, steel());
    let mut f = vec![0.0; model.dof_count()];
    loads::add_surface_traction(
        model.nodes(),
        &mesh.face_triangles(BoxFace::ZMax),
        [1e6, -3e5, 5e5],
        &mut f,
    )
    .unwrap();
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMin))],
        rigid_faces: vec![RigidFace {
            nodes: mesh.face_nodes(BoxFace::XMax),
            components: [
                RigidComponent::Loaded { force_n: 2e5 },
                RigidComponent::Free,
                RigidComponent::Free,
            ],
        }],
        ..Default::default()
    };
    (model, constraints, f)
}

fn solve(
    model: &Model,
    constraints: &Constraints,
    f: &[f64],
    method: SolverMethod,
) -> StaticSolution {
    let options = SolverOptions {
        method,
        ..SolverOptions::default()
    };
    solve_static(
        &StaticProblem {
            model,
            constraints,
            load_n: f,
        },
        &options,
    )
    .unwrap()
}

/// ‖u − v‖_K / ‖v‖_K with the full stiffness of `model`.
fn relative_energy_difference(model: &Model, u: &[f64], v: &[f64]) -> f64 {
    let k = assemble_stiffness(model, &StiffnessPattern::build(model)).unwrap();
    let d: Vec<f64> = u.iter().zip(v).map(|(a, b)| a - b).collect();
    (k.quadratic_form(&d) / k.quadratic_form(v)).sqrt()
}

#[test]
fn iterative_and_direct_solutions_agree_within_the_energy_tolerance_on_a_block() {
    let (model, constraints, f) = block(4);
    let direct = solve(&model, &constraints, &f, SolverMethod::Direct);
    let iterative = solve(&model, &constraints, &f, SolverMethod::Iterative);
    assert_eq!(
        iterative.choice.method,
        SolverMethod::Iterative,
        "method used"
    );
    let tolerance = IterativeOptions::default().relative_energy_error;
    let error =
        relative_energy_difference(&model, &iterative.displacement_m, &direct.displacement_m);
    // The estimate is a lower bound that is tight within a small factor (module docs of pcg).
    assert!(
        error < 10.0 * tolerance,
        "relative energy-norm displacement difference {error:e} vs tolerance {tolerance:e}"
    );
    let energy_difference =
        (iterative.strain_energy_j - direct.strain_energy_j).abs() / direct.strain_energy_j;
    assert!(
        energy_difference < 1e-9,
        "strain energy: iterative {} J, direct {} J",
        iterative.strain_energy_j,
        direct.strain_energy_j
    );
    assert!(
        iterative.report.iterations > 0 && iterative.report.iterations < 60,
        "PCG iterations with the p-multigrid preconditioner: {}",
        iterative.report.iterations
    );
}

#[test]
fn a_tighter_discretisation_error_gives_a_smaller_algebraic_error() {
    let (model, constraints, f) = block(3);
    let direct = solve(&model, &constraints, &f, SolverMethod::Direct);
    let run = |discretisation_error: f64| {
        let options = SolverOptions {
            method: SolverMethod::Iterative,
            iterative: IterativeOptions::for_discretisation_error(discretisation_error),
            ..SolverOptions::default()
        };
        let sol = solve_static(
            &StaticProblem {
                model: &model,
                constraints: &constraints,
                load_n: &f,
            },
            &options,
        )
        .unwrap();
        let error = relative_energy_difference(&model, &sol.displacement_m, &direct.displacement_m);
        (sol.report.iterations, error)
    };
    let (loose_iterations, loose_error) = run(1e-2);
    let (tight_iterations, tight_error) = run(1e-7);
    assert!(
        tight_iterations > loose_iterations && tight_error < loose_error,
        "iterations {loose_iterations} → {tight_iterations}, energy error {loose_error:e} → {tight_error:e}"
    );
    assert!(
        tight_error < 1e-8,
        "energy error at a 1e-9 algebraic tolerance: {tight_error:e}"
    );
}

#[test]
fn iterative_solver_names_its_stopping_rule_when_it_cannot_converge() {
    let (model, constraints, f) = block(2);
    let options = SolverOptions {
        method: SolverMethod::Iterative,
        iterative: IterativeOptions {
            max_iterations: 2,
            relative_energy_error: 1e-12,
            ..IterativeOptions::default()
        },
        ..SolverOptions::default()
    };
    let err = solve_static(
        &StaticProblem {
            model: &model,
            constraints: &constraints,
            load_n: &f,
        },
        &options,
    )
    .unwrap_err();
    let text = err.to_string();
    assert!(
        matches!(err, FemError::IterativeNotConverged { iterations: 2, .. })
            && text.contains("iteration limit"),
        "stall error: {text}"
    );
}

/// Tet4 meshes have no p-hierarchy: the iterative path preconditions them by SA-AMG alone
/// (rigid-body near-null space) and must reach the direct solution; `auto` still goes direct.
#[test]
fn tet4_meshes_solve_iteratively_through_amg_and_auto_goes_direct() {
    let mut mesh = BoxMesh::tet4([1.0; 3], [14, 14, 14]);
    distort(&mut mesh, 0.05);
    let model = model_of(&mesh, steel());
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMin))],
        ..Default::default()
    };
    let mut f = vec![0.0; model.dof_count()];
    loads::add_surface_traction(
        model.nodes(),
        &mesh.face_triangles(BoxFace::ZMax),
        [1e6, -2e5, 4e5],
        &mut f,
    )
    .unwrap();
    let direct = solve(&model, &constraints, &f, SolverMethod::Direct);
    let iterative = solve(&model, &constraints, &f, SolverMethod::Iterative);
    let tolerance = IterativeOptions::default().relative_energy_error;
    let error =
        relative_energy_difference(&model, &iterative.displacement_m, &direct.displacement_m);
    assert!(
        error < 10.0 * tolerance,
        "Tet4 AMG-PCG vs direct: relative energy-norm difference {error:e}"
    );
    assert!(
        iterative.report.iterations > 0 && iterative.report.iterations < 100,
        "PCG iterations with SA-AMG on Tet4: {}",
        iterative.report.iterations
    );
    let (k_red, reduced) = reduced_matrix(&model, &constraints);
    let solver = IterativeSolver::new(
        &model,
        reduced.dof_map(),
        &k_red,
        &IterativeOptions::default(),
        FactorOptions::default(),
    )
    .unwrap();
    let report = solver.report();
    assert_eq!(report.coarse_solver, "amg-only", "Tet4 preconditioner");
    assert!(
        report.amg_levels >= 2,
        "AMG levels for {} unknowns: {}",
        report.fine_unknowns,
        report.amg_levels
    );
    let auto = solve(&model, &constraints, &f, SolverMethod::Auto);
    assert_eq!(
        auto.choice.method,
        SolverMethod::Direct,
        "auto on Tet4: {}",
        auto.choice.reason
    );
    assert!(
        auto.choice.reason.contains("Tet4"),
        "reason: {}",
        auto.choice.reason
    );
}

/// The Tet4 coarse level of the p-multigrid solved by one SA-AMG V-cycle instead of a Cholesky
/// factorisation: same solution within the tolerance, a few more iterations at most.
#[test]
fn coarse_amg_reaches_the_direct_solution_on_a_block() {
    let (model, constraints, f) = block(6);
    let direct = solve(&model, &constraints, &f, SolverMethod::Direct);
    let options = |coarse_solver| SolverOptions {
        method: SolverMethod::Iterative,
        iterative: IterativeOptions {
            coarse_solver,
            ..IterativeOptions::default()
        },
        ..SolverOptions::default()
    };
    let problem = StaticProblem {
        model: &model,
        constraints: &constraints,
        load_n: &f,
    };
    let amg = solve_static(&problem, &options(CoarseSolver::Amg)).unwrap();
    let exact = solve_static(&problem, &options(CoarseSolver::Direct)).unwrap();
    let tolerance = IterativeOptions::default().relative_energy_error;
    let error = relative_energy_difference(&model, &amg.displacement_m, &direct.displacement_m);
    assert!(
        error < 10.0 * tolerance,
        "coarse AMG vs direct: relative energy-norm difference {error:e}"
    );
    assert!(
        amg.report.iterations <= 2 * exact.report.iterations + 5,
        "PCG iterations: coarse AMG {} vs exact coarse solve {}",
        amg.report.iterations,
        exact.report.iterations
    );
    let (k_red, reduced) = reduced_matrix(&model, &constraints);
    let iterative = IterativeOptions {
        coarse_solver: CoarseSolver::Amg,
        ..IterativeOptions::default()
    };
    let solver = IterativeSolver::new(
        &model,
        reduced.dof_map(),
        &k_red,
        &iterative,
        FactorOptions::default(),
    )
    .unwrap();
    let report = solver.report();
    assert_eq!(report.coarse_solver, "amg", "coarse solver");
    assert!(
        report.amg_levels >= 2 && report.amg_operator_complexity < 2.0,
        "AMG levels {} and operator complexity {}",
        report.amg_levels,
        report.amg_operator_complexity
    );
}

fn reduced_matrix(
    model: &Model,
    constraints: &Constraints,
) -> (elastic_fem::sparse::SymmetricMatrix, ReducedSystem) {
    let k = assemble_stiffness(model, &StiffnessPattern::build(model)).unwrap();
    let map = DofMap::new(model.node_count(), constraints).unwrap();
    let reduced = ReducedSystem::new(&k, map).unwrap();
    let k_red = reduced.reduce_matrix(&k).unwrap();
    (k_red, reduced)
}

#[test]
fn auto_picks_direct_for_a_small_system_with_its_reason() {
    let (model, constraints, f) = block(2);
    let sol = solve(&model, &constraints, &f, SolverMethod::Auto);
    assert_eq!(
        sol.choice.method,
        SolverMethod::Direct,
        "reason: {}",
        sol.choice.reason
    );
    assert!(
        sol.choice.reason.contains("unknowns"),
        "reason: {}",
        sol.choice.reason
    );
}

#[test]
fn auto_cost_model_picks_iterative_for_a_large_system_and_direct_for_many_right_hand_sides() {
    // 2 × 1 × 1 block with 24 × 12 × 12 Tet10 cubes: ≈ 170k unknowns.
    let (model, constraints, _) = block(12);
    let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
    let map = DofMap::new(model.node_count(), &constraints).unwrap();
    let reduced = ReducedSystem::new(&k, map).unwrap();
    let k_red = reduced.reduce_matrix(&k).unwrap();
    let ordering = SolverOptions::default().ordering;
    let (one, _) = elastic_fem::choose_method(
        SolverMethod::Auto,
        &k_red,
        1,
        model.connectivity(),
        ordering,
    )
    .unwrap();
    assert_eq!(
        one.method,
        SolverMethod::Iterative,
        "one right-hand side: {}",
        one.reason
    );
    assert!(
        one.reason.contains("direct ≈"),
        "reason gives the estimates: {}",
        one.reason
    );
    let (many, analysed) = elastic_fem::choose_method(
        SolverMethod::Auto,
        &k_red,
        400,
        model.connectivity(),
        ordering,
    )
    .unwrap();
    assert_eq!(
        many.method,
        SolverMethod::Direct,
        "400 right-hand sides: {}",
        many.reason
    );
    assert!(
        analysed.is_some(),
        "the symbolic analysis is handed to the direct path"
    );
}

#[test]
fn many_right_hand_sides_share_one_setup_and_each_meets_the_tolerance() {
    let (model, constraints, f) = block(3);
    let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
    let map = DofMap::new(model.node_count(), &constraints).unwrap();
    let reduced = ReducedSystem::new(&k, map).unwrap();
    let k_red = reduced.reduce_matrix(&k).unwrap();
    let b = reduced.reduce_load(&k, &f).unwrap();
    let m = b.len();
    let mut rhs: Vec<f64> = b
        .iter()
        .chain(b.iter().map(|v| -2.0 * v).collect::<Vec<_>>().iter())
        .copied()
        .collect();
    let solver = IterativeSolver::new(
        &model,
        reduced.dof_map(),
        &k_red,
        &IterativeOptions::default(),
        FactorOptions::default(),
    )
    .unwrap();
    let reports = solver
        .solve_columns_in_place(&mut rhs, 2, &mut solver.workspace())
        .unwrap();
    assert_eq!(reports.len(), 2, "one report per right-hand side");
    for (i, r) in reports.iter().enumerate() {
        assert!(
            r.relative_energy_error <= IterativeOptions::default().relative_energy_error,
            "column {i}: estimated energy error {:e}",
            r.relative_energy_error
        );
        assert_eq!(
            r.residual_history.len(),
            r.iterations,
            "residual history of column {i}"
        );
    }
    let ratio_error = rhs[..m]
        .iter()
        .zip(&rhs[m..])
        .map(|(a, b)| (b + 2.0 * a).abs())
        .fold(0.0, f64::max)
        / rhs[..m].iter().fold(0.0, |x: f64, v| x.max(v.abs()));
    assert!(
        ratio_error < 1e-4,
        "linearity: x(−2b) = −2 x(b) within the tolerance, got {ratio_error:e}"
    );
}

/// The solution of `method` computed inside a rayon pool of `threads` threads.
fn solve_with_threads(
    threads: usize,
    model: &Model,
    constraints: &Constraints,
    f: &[f64],
    method: SolverMethod,
) -> Vec<f64> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| solve(model, constraints, f, method).displacement_m)
}

/// Entries of `a` and `b` whose bits differ.
fn differing_bits(a: &[f64], b: &[f64]) -> usize {
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count()
}

#[test]
fn both_paths_repeat_their_bits_for_a_thread_count_and_the_iterative_one_for_any() {
    // 12.7k unknowns: several row blocks of the parallel products, dot products and reduction.
    let (model, constraints, f) = block(6);
    for method in [SolverMethod::Iterative, SolverMethod::Direct] {
        let one = solve_with_threads(1, &model, &constraints, &f, method);
        for threads in [1, 2, 3] {
            let first = solve_with_threads(threads, &model, &constraints, &f, method);
            {
                let again = solve_with_threads(threads, &model, &constraints, &f, method);
                let differing = differing_bits(&first, &again);
                assert_eq!(
                    differing, 0,
                    "{method:?} displacement (m): {differing} entries differ in bits between two runs with {threads} threads"
                );
            }
            if method == SolverMethod::Iterative {
                // faer's parallel dense kernels in the supernodal Cholesky round differently
                // with 1 and more threads (the direct path); the iterative path's own reductions
                // have a fixed order, and its coarse factor here (as at 350k unknowns) is too
                // small for faer to split.
                let differing = differing_bits(&one, &first);
                assert_eq!(
                    differing, 0,
                    "{method:?} displacement (m): {differing} entries differ in bits between 1 and {threads} threads"
                );
            }
        }
    }
}
