//! PCG condensation ([`elastic_fem::condense`]) against the direct factor's solves, and the cost
//! model's choice between the two ([`elastic_fem::CostEstimate`]).

mod common;

use common::{distort, model_of, steel};
use elastic_fem::condense::{Pattern, condense_by_pcg};
use elastic_fem::iterative::IterativeSolver;
use elastic_fem::mesh_gen::{BoxFace, BoxMesh};
use elastic_fem::sparse::{FactorOptions, Ordering, SymbolicCholesky, SymmetricMatrix};
use elastic_fem::static_solver::DIRECT_FACTOR_MEMORY_BYTES;
use elastic_fem::{
    Constraints, CostEstimate, CostQuery, Dirichlet, DofMap, DofTarget, IterativeOptions, Model,
    ReducedSystem, SolverMethod, StiffnessPattern, assemble_stiffness,
};

/// A distorted Tet10 block clamped at z = 0; its reduced stiffness and DOF map.
fn clamped_block(divisions: usize) -> (Model, ReducedSystem, SymmetricMatrix, BoxMesh) {
    let mut mesh = BoxMesh::tet10([2.0, 1.0, 1.0], [2 * divisions, divisions, divisions]);
    distort(&mut mesh, 0.05);
    let model = model_of(&mesh, steel());
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMin))],
        ..Default::default()
    };
    let k = assemble_stiffness(&model, &StiffnessPattern::build(&model)).unwrap();
    let map = DofMap::new(model.node_count(), &constraints).unwrap();
    let reduced = ReducedSystem::new(&k, map).unwrap();
    let k_red = reduced.reduce_matrix(&k).unwrap();
    (model, reduced, k_red, mesh)
}

/// Unit z forces on `count` nodes of the top face (like a strip's disk ties), and x loads
/// spread over pairs of top nodes (like its x-averaging loads).
fn top_patterns(mesh: &BoxMesh, reduced: &ReducedSystem, count: usize) -> Vec<Pattern> {
    let top = mesh.face_nodes(BoxFace::ZMax);
    let step = top.len() / count;
    let unknown = |node: usize, c: usize| match reduced.dof_map().target(3 * node + c) {
        DofTarget::Reduced(j) => j,
        DofTarget::Prescribed(_) => panic!("top nodes are free"),
    };
    let mut patterns: Vec<Pattern> = (0..count)
        .map(|i| vec![(unknown(top[i * step], 2), 1.0)])
        .collect();
    patterns.extend((0..count / 2).map(|i| {
        let (a, b) = (top[i * step], top[i * step + 1]);
        vec![(unknown(a, 0), 0.5), (unknown(b, 0), 0.5)]
    }));
    patterns
}

#[test]
fn pcg_compliance_equals_the_direct_one_within_the_stated_bound() {
    let (model, reduced, k_red, mesh) = clamped_block(3);
    let patterns = top_patterns(&mesh, &reduced, 8);
    let options = IterativeOptions::default();
    let solver = IterativeSolver::new(
        &model,
        reduced.dof_map(),
        &k_red,
        &options,
        FactorOptions::default(),
    )
    .unwrap();
    let pcg = condense_by_pcg(&solver, &patterns, &[&patterns], &mut solver.workspace()).unwrap();
    let c = &pcg.blocks[0];
    // Direct: one solve per column with the Cholesky factor.
    let factor = SymbolicCholesky::analyze(&k_red, Ordering::Metis)
        .unwrap()
        .factor(&k_red)
        .unwrap();
    let n = k_red.dim();
    let s = patterns.len();
    let mut rhs = vec![0.0; n * s];
    for (col, p) in patterns.iter().enumerate() {
        p.iter().for_each(|&(j, w)| rhs[col * n + j] += w);
    }
    factor.solve_columns_in_place(&mut rhs, s).unwrap();
    let exact =
        |i: usize, j: usize| -> f64 { patterns[i].iter().map(|&(u, w)| w * rhs[j * n + u]).sum() };
    let eps = options.relative_energy_error;
    for i in 0..s {
        for j in 0..s {
            let scale = (exact(i, i) * exact(j, j)).sqrt();
            let error = (c[(i, j)] - exact(i, j)).abs() / scale;
            // PCG's error estimate is tight within ≈ 1.5 (sparse/pcg.rs): allow 2 ε.
            assert!(
                error <= 2.0 * eps,
                "compliance C[{i},{j}] = {:e} m/N vs direct {:e}: error {error:e} of √(C_ii C_jj) > 2 ε = {:e}",
                c[(i, j)],
                exact(i, j),
                2.0 * eps
            );
            if i == j {
                assert!(
                    error <= 4.0 * eps * eps + 1e-12,
                    "diagonal compliance C[{i},{i}] error {error:e} of C_ii, bound ε² = {:e}",
                    eps * eps
                );
            }
        }
    }
    assert_eq!(pcg.iterations.len(), s, "one PCG solve per load column");
    assert!(
        pcg.relative_energy_error.iter().all(|&e| e <= eps),
        "every column meets the tolerance: {:?}",
        pcg.relative_energy_error
    );
}

#[test]
fn a_stalled_column_is_named_in_the_error() {
    let (model, reduced, k_red, mesh) = clamped_block(2);
    let patterns = top_patterns(&mesh, &reduced, 4);
    let options = IterativeOptions {
        max_iterations: 1,
        ..IterativeOptions::default()
    };
    let solver = IterativeSolver::new(
        &model,
        reduced.dof_map(),
        &k_red,
        &options,
        FactorOptions::default(),
    )
    .unwrap();
    let error = condense_by_pcg(&solver, &patterns, &[&patterns], &mut solver.workspace())
        .expect_err("one iteration cannot reach 1e-6");
    assert!(
        error
            .to_string()
            .contains("condensation load column 0 of 6"),
        "the error names the column: {error}"
    );
}

/// The default strip's figures (`sawdrive run`, Tet10 half strip: 185 905 unknowns, factor
/// 36.75 M entries and 9.41 G multiply–adds), 100 posts: one PCG column each, none direct
/// (trailing block).
fn default_strip(memory_limit_bytes: f64) -> CostEstimate {
    let query = CostQuery {
        rhs_count: 100,
        direct_solves: 0,
        factor_memory_limit_bytes: memory_limit_bytes,
    };
    CostEstimate::from_figures(185_905, 7_600_000, 9.413_888_049e9, 36_752_422, query)
}

#[test]
fn auto_picks_direct_for_the_default_strip_and_says_why() {
    let choice = default_strip(DIRECT_FACTOR_MEMORY_BYTES).decide(false);
    assert_eq!(choice.method, SolverMethod::Direct, "{}", choice.reason);
    for figure in ["9.414 G madds", "0.294 GB", "100 columns × 13 it."] {
        assert!(
            choice.reason.contains(figure),
            "the reason states {figure}: {}",
            choice.reason
        );
    }
}

#[test]
fn auto_picks_iterative_when_the_factor_would_not_fit_in_memory() {
    let choice = default_strip(0.2e9).decide(false);
    assert_eq!(choice.method, SolverMethod::Iterative, "{}", choice.reason);
    assert!(
        choice.reason.contains("memory limit"),
        "the reason names the memory limit: {}",
        choice.reason
    );
    // The same rule on a real (small) matrix's symbolic analysis.
    let (_, _, k_red, _) = clamped_block(2);
    let symbolic = SymbolicCholesky::analyze(&k_red, Ordering::Metis).unwrap();
    let bytes = 8.0 * symbolic.factor_nnz() as f64;
    let query = |limit| CostQuery {
        factor_memory_limit_bytes: limit,
        ..CostQuery::solves(1)
    };
    let fits = CostEstimate::new(&symbolic, &k_red, query(2.0 * bytes)).decide(false);
    let over = CostEstimate::new(&symbolic, &k_red, query(0.5 * bytes)).decide(false);
    assert_eq!(fits.method, SolverMethod::Direct, "{}", fits.reason);
    assert_eq!(over.method, SolverMethod::Iterative, "{}", over.reason);
}
