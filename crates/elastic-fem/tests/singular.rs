//! A floating body is refused by every solver path, with the rigid-mode pre-check switched off:
//! the direct path and the iterative paths (p-multigrid with a direct or AMG coarse solve,
//! SA-AMG alone on Tet4) by their null-space check (the direct one also by its Cholesky pivot
//! check), and `auto` by whichever of them it picks. The body is a block with only u_z prescribed on its bottom face (a punch
//! pressed into a block that nothing else holds): translations x, y and the rotation about z
//! are free, and the load (the prescribed u_z alone) is orthogonal to them, so the singular
//! system is consistent and CG would "solve" it without a breakdown.

mod common;

use common::{distort, model_of, steel};
use elastic_fem::iterative::{CoarseSolver, IterativeSolver, NULL_SPACE_TOLERANCE};
use elastic_fem::mesh_gen::{BoxFace, BoxMesh};
use elastic_fem::sparse::{FactorOptions, SymbolicCholesky};
use elastic_fem::{
    Constraints, Dirichlet, DofMap, FemError, IterativeOptions, Model, ReducedSystem, SolverMethod,
    SolverOptions, StaticProblem, StiffnessPattern, assemble_stiffness, solve_static,
};

/// The floating block: only u_z = −1 µm on the bottom face.
fn floating(mesh: &BoxMesh) -> (Model, Constraints) {
    let model = model_of(mesh, steel());
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::component(
            mesh.face_nodes(BoxFace::ZMin),
            2,
            -1e-6,
        )],
        ..Default::default()
    };
    (model, constraints)
}

fn tet10(divisions: usize) -> BoxMesh {
    let mut mesh = BoxMesh::tet10([2.0, 1.0, 1.0], [2 * divisions, divisions, divisions]);
    distort(&mut mesh, 0.05);
    mesh
}

/// `solve_static` with the rigid-mode pre-check off: the solver's own answer.
fn solve_unchecked(
    model: &Model,
    constraints: &Constraints,
    options: SolverOptions,
) -> Result<elastic_fem::StaticSolution, FemError> {
    let load = vec![0.0; model.dof_count()];
    solve_static(
        &StaticProblem {
            model,
            constraints,
            load_n: &load,
        },
        &SolverOptions {
            check_rigid_body_modes: false,
            ..options
        },
    )
}

fn assert_singular(result: Result<elastic_fem::StaticSolution, FemError>, path: &str) {
    match result {
        Err(FemError::SingularSystem { ratio, tolerance }) => assert!(
            ratio <= tolerance && tolerance == NULL_SPACE_TOLERANCE,
            "{path}: ratio {ratio:e}, tolerance {tolerance:e}"
        ),
        Err(other) => panic!("{path}: refused, but not as singular: {other}"),
        Ok(s) => panic!(
            "{path}: the floating block was solved ({} PCG iterations)",
            s.report.iterations
        ),
    }
}

#[test]
fn direct_solver_refuses_a_floating_body_by_its_null_space_check() {
    let (model, constraints) = floating(&tet10(2));
    let result = solve_unchecked(
        &model,
        &constraints,
        SolverOptions {
            method: SolverMethod::Direct,
            ..SolverOptions::default()
        },
    );
    assert_singular(result, "direct");
}

/// Behind the null-space check, the factorisation's own pivot check refuses the floating body
/// too (on this small uniform mesh; a graded one can slip past it, hence the null-space check).
#[test]
fn cholesky_pivot_check_refuses_a_floating_body_on_a_uniform_mesh() {
    let (model, constraints) = floating(&tet10(2));
    let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
    let map = DofMap::new(model.node_count(), &constraints).unwrap();
    let reduced = ReducedSystem::new(&k, map).unwrap();
    let k_red = reduced.reduce_matrix(&k).unwrap();
    let symbolic = SymbolicCholesky::analyze(&k_red, SolverOptions::default().ordering).unwrap();
    let result = symbolic.factor_with(&k_red, FactorOptions::default());
    assert!(
        matches!(result, Err(FemError::NotPositiveDefinite { .. })),
        "pivot check: {:?}",
        result.err()
    );
}

#[test]
fn iterative_solver_refuses_a_floating_tet10_body_with_either_coarse_solve() {
    let (model, constraints) = floating(&tet10(2));
    for coarse_solver in [CoarseSolver::Direct, CoarseSolver::Amg] {
        let result = solve_unchecked(
            &model,
            &constraints,
            SolverOptions {
                method: SolverMethod::Iterative,
                iterative: IterativeOptions {
                    coarse_solver,
                    ..IterativeOptions::default()
                },
                ..SolverOptions::default()
            },
        );
        assert_singular(
            result,
            &format!("p-multigrid, coarse {}", coarse_solver.name()),
        );
    }
}

#[test]
fn iterative_solver_refuses_a_floating_tet4_body_preconditioned_by_amg_alone() {
    let mut mesh = BoxMesh::tet4([2.0, 1.0, 1.0], [8, 4, 4]);
    distort(&mut mesh, 0.05);
    let (model, constraints) = floating(&mesh);
    let result = solve_unchecked(
        &model,
        &constraints,
        SolverOptions {
            method: SolverMethod::Iterative,
            ..SolverOptions::default()
        },
    );
    assert_singular(result, "SA-AMG on Tet4");
}

/// Contact solvers set up the iterative solver themselves (no `solve_static`): the refusal is
/// in its set-up.
#[test]
fn iterative_solver_set_up_refuses_a_floating_body() {
    let (model, constraints) = floating(&tet10(2));
    let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
    let map = DofMap::new(model.node_count(), &constraints).unwrap();
    let reduced = ReducedSystem::new(&k, map).unwrap();
    let k_red = reduced.reduce_matrix(&k).unwrap();
    let result = IterativeSolver::new(
        &model,
        reduced.dof_map(),
        &k_red,
        &IterativeOptions::default(),
        FactorOptions::default(),
    );
    assert!(
        matches!(result, Err(FemError::SingularSystem { .. })),
        "set-up: {:?}",
        result.err()
    );
}

/// `auto` picks the iterative path for this 170k-unknown block (the cost model) and that path
/// refuses it; the same block held by a clamped face is solved (the check does not refuse a
/// constrained system).
#[test]
fn auto_refuses_a_floating_body_when_it_picks_the_iterative_path() {
    let mesh = tet10(12);
    let (model, constraints) = floating(&mesh);
    let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
    let map = DofMap::new(model.node_count(), &constraints).unwrap();
    let reduced = ReducedSystem::new(&k, map).unwrap();
    let k_red = reduced.reduce_matrix(&k).unwrap();
    let (choice, _) = elastic_fem::choose_method(
        SolverMethod::Auto,
        &k_red,
        1,
        model.connectivity(),
        SolverOptions::default().ordering,
    )
    .unwrap();
    assert_eq!(choice.method, SolverMethod::Iterative, "{}", choice.reason);
    assert_singular(
        solve_unchecked(&model, &constraints, SolverOptions::default()),
        "auto",
    );
    let held = Constraints {
        dirichlet: vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMin))],
        ..Default::default()
    };
    let solution = solve_unchecked(&model, &held, SolverOptions::default())
        .expect("a clamped block is not singular");
    assert_eq!(solution.choice.method, SolverMethod::Iterative);
}

/// Contact solvers re-factor the set-up solver with new values on the same pattern
/// (`IterativeSolver::refactor`): new values that free a rigid-body motion are refused there
/// too, and the solver keeps its previous values. The set-up matrix is the floating block's
/// K_red plus 10 % of its diagonal (positive definite, same pattern: a spring to ground at every
/// unknown); the re-factored one is the floating K_red itself.
#[test]
fn iterative_solver_refactor_refuses_values_that_free_a_rigid_body_motion() {
    let (model, constraints) = floating(&tet10(2));
    let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
    let map = DofMap::new(model.node_count(), &constraints).unwrap();
    let reduced = ReducedSystem::new(&k, map).unwrap();
    let k_red = reduced.reduce_matrix(&k).unwrap();
    let mut grounded = k_red.clone();
    for (j, d) in k_red.diagonal().into_iter().enumerate() {
        grounded.add_to_diagonal(j, 0.1 * d);
    }
    for coarse_solver in [CoarseSolver::Direct, CoarseSolver::Amg] {
        let options = IterativeOptions {
            coarse_solver,
            ..IterativeOptions::default()
        };
        let mut solver = IterativeSolver::new(
            &model,
            reduced.dof_map(),
            &grounded,
            &options,
            FactorOptions::default(),
        )
        .expect("a grounded block is not singular");
        let result = solver.refactor(&k_red);
        match result {
            Err(FemError::SingularSystem { ratio, tolerance }) => assert!(
                ratio <= tolerance,
                "coarse {}: ratio {ratio:e}, tolerance {tolerance:e}",
                coarse_solver.name()
            ),
            other => panic!(
                "coarse {}: refactor with a free rigid-body motion must be refused, got {other:?}",
                coarse_solver.name()
            ),
        }
        solver
            .refactor(&grounded)
            .expect("re-factoring the grounded values again is accepted");
    }
}
