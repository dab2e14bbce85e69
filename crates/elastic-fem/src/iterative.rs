//! Iterative solution of the reduced system K_red q = f_red: conjugate gradients preconditioned
//! by one p-multigrid V-cycle Tet10 → Tet4 with an exact (sparse Cholesky) coarse solve.
//!
//! **Hierarchy.** The coarse space is the Tet4 space on the vertices of the Tet10 mesh. The
//! prolongation P evaluates the linear (Tet4) shape functions at the Tet10 nodes: 1 at a vertex,
//! ½ + ½ of the two end vertices at a mid-edge node (in reference coordinates, so also for
//! curved elements). It acts on reduced unknowns: a fine unknown tied to a vertex (Dirichlet,
//! rigid-face or periodic ties of the [`DofMap`]) is represented by that vertex's coarse unknown,
//! prescribed vertices contribute 0 (homogeneous correction). The coarse operator is the
//! Galerkin product A_c = Pᵀ K_red P, factorised once by the sparse module (METIS + faer).
//! p-multigrid for high-order elasticity: Rønquist & Patera 1987 (IJNME 24:1467); with
//! Chebyshev smoothing and an exact P1 coarse solve as in Adams, Brezina, Hu & Tuminaro 2003
//! ("Parallel multigrid smoothing: polynomial versus Gauss–Seidel", JCP 188:593).
//!
//! **Smoother.** Chebyshev polynomial of degree [`DEFAULT_SMOOTHER_DEGREE`] in D⁻¹ K_red
//! (D = diagonal), targeting the eigenvalue interval [λ_max / [`CHEBYSHEV_INTERVAL_RATIO`],
//! [`CHEBYSHEV_UPPER_SAFETY`] λ_max], λ_max from [`LANCZOS_STEPS`] Lanczos steps. A
//! polynomial smoother is symmetric, parallel (only products with K_red) and independent of the
//! thread count, so the V-cycle (pre- and post-smoothing alike) is an SPD preconditioner for CG.
//!
//! **Stopping rule.** CG stops when its estimated relative energy-norm error (see
//! [`mod@crate::sparse::pcg`]) falls below `relative_energy_error`. The default ties it to the FEM
//! discretisation error: [`ALGEBRAIC_FRACTION`] × [`DEFAULT_DISCRETISATION_ERROR`] = 1e-6, so
//! the algebraic error changes the FEM energy error by < 0.01 % and energy-type quantities
//! (stiffness uᵀ K u / δ²) by ≈ ε² = 1e-12.
//!
//! **Coarse solve** ([`CoarseSolver`]): the Tet4 coarse problem is factorised (METIS + faer
//! Cholesky) or, when it is large ([`AMG_COARSE_UNKNOWNS`], where its factorisation grows like
//! N_c^1.3–1.5 and dominates set-up and memory), approximated by one V-cycle of smoothed-
//! aggregation AMG with rigid-body near-null space ([`crate::amg`], Vaněk–Mandel–Brezina 1996).
//! Both keep the preconditioner symmetric positive definite.
//!
//! **Singular systems** ([`check_null_space`]): CG on a consistent singular system (a body
//! left free to move rigidly, its load orthogonal to that motion) converges to one of infinitely
//! many solutions without any breakdown, so the set-up refuses such a matrix before building the
//! hierarchy, whatever called it, and so does [`IterativeSolver::refactor`] for new values on
//! the same pattern: the six rigid-body motions restricted to the reduced unknowns
//! (translations and rotations at each unknown's node, [`rigid_body_modes`]) are orthonormalised
//! in the D inner product (D = diag K_red) and the smallest eigenvalue of the 6 × 6 projection
//! QᵀK_red Q, i.e. the smallest generalised Rayleigh quotient qᵀKq / qᵀDq over their span, must
//! exceed [`NULL_SPACE_TOLERANCE`]. Rounding gives ≈ 1e-15 for a free motion; a motion held by
//! even a few prescribed unknowns among N gives ≈ (their share of D) ≳ 1/N, so the test separates
//! the two by orders of magnitude up to 1e9 unknowns. [`crate::solve_static`] applies the same
//! check before the direct factorisation, whose pivot check
//! ([`crate::sparse::FactorOptions::min_pivot_ratio`]) alone misses a free body on a graded mesh:
//! the floating Tet4 punch (71k unknowns, element sizes 0.01a to 25a) factorised with its
//! smallest pivot ratio above 1e-13 and was "solved".
//!
//! **Range.** Tet10 meshes (straight or curved) get the p-multigrid; Tet4-only meshes have no
//! p-hierarchy and are preconditioned by SA-AMG on the whole (reduced) Tet4 problem.

use crate::amg::{Amg, AmgWorkspace, rigid_body_modes};
use crate::chebyshev::Chebyshev;
use crate::error::{FemError, FemResult};
use crate::model::{Connectivity, Model};
use crate::reduction::{DofMap, DofTarget};
use crate::shape::TET10_EDGES;
use crate::sparse::pcg::{
    DEFAULT_CONTRACTION_LIMIT, DEFAULT_ERROR_DELAY, DEFAULT_MAX_ITERATIONS, PcgOptions, dot,
};
use crate::sparse::{
    CsrMatrix, FactorOptions, NumericCholesky, Ordering, PcgReport, PcgWorkspace, RowSparse,
    SymbolicCholesky, SymmetricMatrix, pcg,
};

/// Relative energy-norm discretisation error the default stopping rule assumes the caller
/// needs (a Tet10 mesh resolving the stress field to ≈ 0.01 %). Dimensionless; default 1e-4.
pub const DEFAULT_DISCRETISATION_ERROR: f64 = 1e-4;

/// Algebraic error allowed per unit of discretisation error: the CG tolerance is this fraction
/// of the discretisation error. Dimensionless; default 0.01.
pub const ALGEBRAIC_FRACTION: f64 = 0.01;

/// Degree of the Chebyshev smoother (products with K_red per smoothing). Default 2.
pub const DEFAULT_SMOOTHER_DEGREE: usize = 2;

/// λ_max / λ_min of the interval the Chebyshev smoother damps (the rest is left to the coarse
/// space). Dimensionless; default 12.
pub const CHEBYSHEV_INTERVAL_RATIO: f64 = 12.0;

pub use crate::chebyshev::{CHEBYSHEV_UPPER_SAFETY, LANCZOS_STEPS};

/// Above this many coarse (Tet4) unknowns [`CoarseSolver::Auto`] approximates the coarse solve by
/// SA-AMG instead of factorising it. Measured on the punch meshes (validation/fem-peers):
/// default 40 000.
pub const AMG_COARSE_UNKNOWNS: usize = 40_000;

/// Largest generalised Rayleigh quotient qᵀ K_red q / qᵀ D q of a rigid-body motion q that
/// counts as a null vector (module docs, Singular systems). Dimensionless; default 1e-10.
pub const NULL_SPACE_TOLERANCE: f64 = 1e-10;

/// A rigid-body motion whose part D-orthogonal to the motions kept before it is below this
/// fraction of its D-norm adds nothing to their span and is dropped (e.g. translation z when
/// every z unknown is prescribed). Dimensionless; default 1e-8.
const NULL_SPACE_RANK_TOLERANCE: f64 = 1e-8;

/// Refuses a reduced matrix `a` whose span of rigid-body motions `modes` (one row of six per
/// reduced unknown: translations x, y, z and rotations, [`rigid_body_modes`]) contains a
/// (near-)null vector: [`FemError::SingularSystem`] when the smallest generalised Rayleigh
/// quotient qᵀ a q / qᵀ D q over that span is ≤ [`NULL_SPACE_TOLERANCE`] (module docs).
/// Costs six products with `a`.
pub fn check_null_space(a: &CsrMatrix, modes: &[[f64; 6]]) -> FemResult<()> {
    check_null_space_of(|x, y| a.mul_vec(x, y), &a.diagonal(), modes)
}

/// [`check_null_space`] for any symmetric operator: `apply(x, y)` sets y = K x, `d` is the
/// diagonal of K (e.g. the direct path's upper-triangle [`SymmetricMatrix`]).
pub fn check_null_space_of(
    mut apply: impl FnMut(&[f64], &mut [f64]),
    d: &[f64],
    modes: &[[f64; 6]],
) -> FemResult<()> {
    let n = d.len();
    if n == 0 || modes.len() != n {
        return Ok(());
    }
    if d.iter().any(|&v| v.is_nan() || v <= 0.0) {
        // A zero or negative diagonal entry: the unknown has no stiffness at all (or the matrix
        // is indefinite); the unit vector there is a null (or negative) direction.
        let i = d.iter().position(|&v| v.is_nan() || v <= 0.0).unwrap_or(0);
        return Err(FemError::SingularSystem {
            ratio: d[i],
            tolerance: NULL_SPACE_TOLERANCE,
        });
    }
    let d_dot =
        |x: &[f64], y: &[f64]| -> f64 { x.iter().zip(y).zip(d).map(|((a, b), w)| a * b * w).sum() };
    // Modified Gram–Schmidt in the D inner product.
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(6);
    for k in 0..6 {
        let mut v: Vec<f64> = modes.iter().map(|row| row[k]).collect();
        let norm0 = d_dot(&v, &v).sqrt();
        if norm0 == 0.0 {
            continue;
        }
        for q in &basis {
            let c = d_dot(q, &v);
            v.iter_mut().zip(q).for_each(|(vi, qi)| *vi -= c * qi);
        }
        let norm = d_dot(&v, &v).sqrt();
        if norm > NULL_SPACE_RANK_TOLERANCE * norm0 {
            v.iter_mut().for_each(|vi| *vi /= norm);
            basis.push(v);
        }
    }
    if basis.is_empty() {
        return Ok(());
    }
    let m = basis.len();
    let mut aq = vec![0.0; n];
    let mut h = nalgebra::DMatrix::<f64>::zeros(m, m);
    for j in 0..m {
        apply(&basis[j], &mut aq);
        for i in 0..m {
            h[(i, j)] = dot(&basis[i], &aq);
        }
    }
    let h = 0.5 * (&h + h.transpose());
    let smallest = h.symmetric_eigenvalues().min();
    if smallest.is_nan() || smallest <= NULL_SPACE_TOLERANCE {
        return Err(FemError::SingularSystem {
            ratio: smallest,
            tolerance: NULL_SPACE_TOLERANCE,
        });
    }
    Ok(())
}

/// The six rigid-body motions at the reduced unknowns of `dof_map` (one row per unknown, at the
/// node and component of its representative DOF), as [`check_null_space`] takes them.
pub fn reduced_rigid_body_modes(model: &Model, dof_map: &DofMap) -> Vec<[f64; 6]> {
    let dofs: Vec<usize> = (0..dof_map.reduced_count())
        .map(|j| dof_map.representative_dof(j))
        .collect();
    amg_input(model, &dofs).0
}

/// How the p-multigrid solves its Tet4 coarse problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CoarseSolver {
    /// Factorised up to [`AMG_COARSE_UNKNOWNS`] coarse unknowns, SA-AMG above (default).
    #[default]
    Auto,
    /// Sparse Cholesky (exact coarse solve).
    Direct,
    /// One SA-AMG V-cycle (approximate, memory and time linear in the coarse size).
    Amg,
}

impl CoarseSolver {
    /// Parses `auto`, `direct` or `amg`.
    pub fn parse(text: &str) -> Option<Self> {
        match text {
            "auto" => Some(Self::Auto),
            "direct" => Some(Self::Direct),
            "amg" => Some(Self::Amg),
            _ => None,
        }
    }

    /// The name [`Self::parse`] accepts.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Direct => "direct",
            Self::Amg => "amg",
        }
    }
}

/// Options of the iterative path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterativeOptions {
    /// Tolerance on the estimated relative energy-norm error of the algebraic solution
    /// (default `ALGEBRAIC_FRACTION × DEFAULT_DISCRETISATION_ERROR` = 1e-6; see
    /// [`Self::for_discretisation_error`]).
    pub relative_energy_error: f64,
    /// Iteration limit (default [`DEFAULT_MAX_ITERATIONS`]).
    pub max_iterations: usize,
    /// Chebyshev degree (default [`DEFAULT_SMOOTHER_DEGREE`]).
    pub smoother_degree: usize,
    /// Ordering of the coarse Cholesky (default METIS).
    pub coarse_ordering: Ordering,
    /// Coarse solve of the p-multigrid (default [`CoarseSolver::Auto`]).
    pub coarse_solver: CoarseSolver,
}

impl Default for IterativeOptions {
    fn default() -> Self {
        Self::for_discretisation_error(DEFAULT_DISCRETISATION_ERROR)
    }
}

impl IterativeOptions {
    /// Options whose CG tolerance is [`ALGEBRAIC_FRACTION`] × `error` (the relative
    /// energy-norm discretisation error the caller accepts).
    pub fn for_discretisation_error(error: f64) -> Self {
        Self {
            relative_energy_error: ALGEBRAIC_FRACTION * error,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            smoother_degree: DEFAULT_SMOOTHER_DEGREE,
            coarse_ordering: Ordering::Metis,
            coarse_solver: CoarseSolver::Auto,
        }
    }

    /// Checks the ranges (tolerance in (0, 1), at least one iteration and smoothing step).
    pub fn validate(&self) -> FemResult<()> {
        let e = self.relative_energy_error;
        if !(e > 0.0 && e < 1.0) {
            return Err(FemError::InvalidSolverOption {
                field: "iterative.relative_energy_error",
                value: e,
                reason: "must lie in (0, 1)",
            });
        }
        if self.max_iterations == 0 {
            return Err(FemError::InvalidSolverOption {
                field: "iterative.max_iterations",
                value: 0.0,
                reason: "must be at least 1",
            });
        }
        if self.smoother_degree == 0 {
            return Err(FemError::InvalidSolverOption {
                field: "iterative.smoother_degree",
                value: 0.0,
                reason: "must be at least 1",
            });
        }
        Ok(())
    }

    fn pcg(&self) -> PcgOptions {
        PcgOptions {
            relative_energy_error: self.relative_energy_error,
            max_iterations: self.max_iterations,
            error_delay: DEFAULT_ERROR_DELAY,
            contraction_limit: DEFAULT_CONTRACTION_LIMIT,
        }
    }
}

/// Prolongation Tet4 → Tet10 on reduced unknowns (see the module docs), or an error for Tet4.
pub fn p_prolongation(model: &Model, dof_map: &DofMap) -> FemResult<RowSparse> {
    p_prolongation_with_dofs(model, dof_map).map(|(p, _)| p)
}

/// [`p_prolongation`] and, per coarse unknown, the global DOF (3 node + component) of the vertex
/// that first defined it.
fn p_prolongation_with_dofs(model: &Model, dof_map: &DofMap) -> FemResult<(RowSparse, Vec<usize>)> {
    let Connectivity::Tet10(conn) = model.connectivity() else {
        return Err(FemError::IterativeUnsupported {
            reason: "the p-multigrid preconditioner needs a Tet10 mesh".into(),
        });
    };
    let n_nodes = model.node_count();
    let mut is_vertex = vec![false; n_nodes];
    let mut edge_of: Vec<Option<(u32, u32)>> = vec![None; n_nodes];
    for el in conn {
        el[..4].iter().for_each(|&v| is_vertex[v] = true);
        for (k, &(a, b)) in TET10_EDGES.iter().enumerate() {
            edge_of[el[4 + k]] = Some((el[a] as u32, el[b] as u32));
        }
    }
    let m = dof_map.reduced_count();
    let mut coarse_of = vec![usize::MAX; m];
    let mut coarse_dofs: Vec<usize> = Vec::new();
    for node in (0..n_nodes).filter(|&n| is_vertex[n]) {
        for c in 0..3 {
            if let DofTarget::Reduced(j) = dof_map.target(3 * node + c)
                && coarse_of[j] == usize::MAX
            {
                coarse_of[j] = coarse_dofs.len();
                coarse_dofs.push(3 * node + c);
            }
        }
    }
    let nc = coarse_dofs.len();
    let coarse_at = |node: usize, c: usize| match dof_map.target(3 * node + c) {
        DofTarget::Reduced(j) => Some(coarse_of[j]),
        DofTarget::Prescribed(_) => None,
    };
    let rows: Vec<Vec<(usize, f64)>> = (0..m)
        .map(|j| {
            if coarse_of[j] != usize::MAX {
                return vec![(coarse_of[j], 1.0)];
            }
            let dof = dof_map.representative_dof(j);
            let (node, c) = (dof / 3, dof % 3);
            let Some((a, b)) = edge_of[node] else {
                return Vec::new();
            };
            let mut row: Vec<(usize, f64)> = Vec::with_capacity(2);
            for end in [a as usize, b as usize] {
                if let Some(cj) = coarse_at(end, c) {
                    match row.iter_mut().find(|(k, _)| *k == cj) {
                        Some(entry) => entry.1 += 0.5,
                        None => row.push((cj, 0.5)),
                    }
                }
            }
            row
        })
        .collect();
    Ok((RowSparse::from_rows(nc, &rows)?, coarse_dofs))
}

/// Near-null space (rigid-body modes at the nodes' coordinates) and node blocks of the unknowns
/// whose global DOFs are `dofs`, for [`Amg::new`].
fn amg_input(model: &Model, dofs: &[usize]) -> (Vec<[f64; 6]>, Vec<usize>) {
    let nodes = model.nodes();
    let points: Vec<[f64; 3]> = dofs.iter().map(|&d| nodes[d / 3]).collect();
    let components: Vec<usize> = dofs.iter().map(|&d| d % 3).collect();
    let mut block_of_node = vec![usize::MAX; model.node_count()];
    let mut count = 0usize;
    let blocks = dofs
        .iter()
        .map(|&d| {
            let b = &mut block_of_node[d / 3];
            if *b == usize::MAX {
                *b = count;
                count += 1;
            }
            *b
        })
        .collect();
    (rigid_body_modes(&points, &components), blocks)
}

/// Work vectors of one V-cycle (caller-owned, reused across iterations and right-hand sides).
#[derive(Debug, Clone)]
pub struct MultigridWorkspace {
    r: Vec<f64>,
    d: Vec<f64>,
    rc: Vec<f64>,
    xc: Vec<f64>,
    amg: Option<AmgWorkspace>,
    pcg: PcgWorkspace,
}

/// Wall time of each phase of an [`IterativeSolver`]'s (latest) set-up (s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MultigridSetupTimes {
    /// Full-row CSR copy of K_red.
    pub fine_csr_s: f64,
    /// Transfer operators P and Pᵀ (0 for AMG alone, and on re-factorisation).
    pub transfer_s: f64,
    /// Galerkin coarse operator Pᵀ K_red P (0 for AMG alone).
    pub coarse_operator_s: f64,
    /// Coarse Cholesky (ordering, symbolic and numeric) or coarse SA-AMG hierarchy; the whole
    /// SA-AMG hierarchy for AMG alone.
    pub coarse_solver_s: f64,
    /// Fine smoother: diagonal and the Lanczos steps for λ_max.
    pub smoother_s: f64,
}

/// Sizes and set-up figures of an [`IterativeSolver`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultigridReport {
    /// Fine (reduced Tet10) unknowns.
    pub fine_unknowns: usize,
    /// Coarse (Tet4 vertex) unknowns (0 for a Tet4 mesh preconditioned by AMG alone).
    pub coarse_unknowns: usize,
    /// Stored entries of the fine CSR matrix (both triangles).
    pub fine_nnz: usize,
    /// Stored entries of the coarse Cholesky factor (for AMG: of its coarsest level).
    pub coarse_factor_nnz: usize,
    /// Bytes held by the solver (CSR, transfer operators, coarse factor or AMG hierarchy).
    pub memory_bytes: usize,
    /// Estimated λ_max of D⁻¹ K_red.
    pub lambda_max: f64,
    /// `direct` (coarse Cholesky), `amg` (coarse SA-AMG) or `amg-only` (Tet4: SA-AMG on the
    /// whole problem).
    pub coarse_solver: &'static str,
    /// Levels of the AMG hierarchy (0 without AMG).
    pub amg_levels: usize,
    /// Σ nnz over the AMG levels / nnz of its finest (0 without AMG).
    pub amg_operator_complexity: f64,
    /// Where the set-up time went.
    pub setup: MultigridSetupTimes,
}

/// The Tet4 coarse solve of the p-multigrid.
#[derive(Debug, Clone)]
enum Coarse {
    Direct(NumericCholesky),
    Amg { a: CsrMatrix, amg: Amg },
}

/// The preconditioner: p-multigrid for Tet10, SA-AMG alone for Tet4 (one per solver, so the
/// variants' size difference costs nothing).
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)]
enum Preconditioner {
    PMultigrid {
        p: RowSparse,
        pt: RowSparse,
        smoother: Chebyshev,
        coarse: Coarse,
    },
    Amg(Amg),
}

/// PCG with the p-multigrid (Tet10) or SA-AMG (Tet4) preconditioner for one reduced stiffness
/// matrix. Set up once, then solve any number of right-hand sides (the set-up is shared).
#[derive(Debug, Clone)]
pub struct IterativeSolver {
    a: CsrMatrix,
    preconditioner: Preconditioner,
    /// Near-null space and node blocks of the AMG's finest level (kept for `refactor`).
    amg_input: Option<(Vec<[f64; 6]>, Vec<usize>)>,
    /// Rigid-body modes of the reduced unknowns (kept so `refactor` runs the null-space check
    /// on the new values too).
    fine_modes: Vec<[f64; 6]>,
    factor: FactorOptions,
    options: IterativeOptions,
    setup: MultigridSetupTimes,
}

/// Seconds since `t`, and restarts it.
fn lap(t: &mut std::time::Instant) -> f64 {
    let s = t.elapsed().as_secs_f64();
    *t = std::time::Instant::now();
    s
}

impl IterativeSolver {
    /// Sets up the hierarchy for `k_red` (the reduction of `model`'s stiffness by `dof_map`).
    /// `factor` holds the thread count of the coarse factorisation and solves.
    pub fn new(
        model: &Model,
        dof_map: &DofMap,
        k_red: &SymmetricMatrix,
        options: &IterativeOptions,
        factor: FactorOptions,
    ) -> FemResult<Self> {
        // `from_csr` checks the options and the dimension.
        let clock = std::time::Instant::now();
        let a = CsrMatrix::from_symmetric(k_red)?;
        let fine_csr_s = clock.elapsed().as_secs_f64();
        let mut solver = Self::from_csr(model, dof_map, a, options, factor)?;
        solver.setup.fine_csr_s = fine_csr_s;
        Ok(solver)
    }

    /// [`Self::new`] for the reduced matrix already in full-row CSR (e.g. from
    /// [`crate::ReducedSystem::reduce_matrix_csr`], which skips the upper-triangle copy).
    pub fn from_csr(
        model: &Model,
        dof_map: &DofMap,
        a: CsrMatrix,
        options: &IterativeOptions,
        factor: FactorOptions,
    ) -> FemResult<Self> {
        options.validate()?;
        if a.dim() != dof_map.reduced_count() {
            return Err(FemError::DimensionMismatch {
                what: "reduced matrix vs DOF map",
                expected: dof_map.reduced_count(),
                found: a.dim(),
            });
        }
        let mut clock = std::time::Instant::now();
        let mut setup = MultigridSetupTimes::default();
        let dofs: Vec<usize> = (0..a.dim())
            .map(|j| dof_map.representative_dof(j))
            .collect();
        let (fine_modes, fine_blocks) = amg_input(model, &dofs);
        check_null_space(&a, &fine_modes)?;
        if let Connectivity::Tet4(_) = model.connectivity() {
            let (b, blocks) = (fine_modes, fine_blocks);
            let amg = Amg::new(&a, b.clone(), blocks.clone(), factor)?;
            setup.coarse_solver_s = lap(&mut clock);
            return Ok(Self {
                a,
                preconditioner: Preconditioner::Amg(amg),
                fine_modes: b.clone(),
                amg_input: Some((b, blocks)),
                factor,
                options: *options,
                setup,
            });
        }
        drop(fine_blocks);
        let (p, coarse_dofs) = p_prolongation_with_dofs(model, dof_map)?;
        let pt = p.transpose();
        setup.transfer_s = lap(&mut clock);
        let coarse_matrix = a.galerkin(&p, &pt)?;
        setup.coarse_operator_s = lap(&mut clock);
        let use_amg = match options.coarse_solver {
            CoarseSolver::Direct => false,
            CoarseSolver::Amg => true,
            CoarseSolver::Auto => coarse_matrix.dim() > AMG_COARSE_UNKNOWNS,
        };
        let (coarse, amg_input) = if use_amg {
            let (b, blocks) = amg_input(model, &coarse_dofs);
            let ca = CsrMatrix::from_symmetric(&coarse_matrix)?;
            drop(coarse_matrix);
            let amg = Amg::new(&ca, b.clone(), blocks.clone(), factor)?;
            (Coarse::Amg { a: ca, amg }, Some((b, blocks)))
        } else {
            let symbolic = SymbolicCholesky::analyze(&coarse_matrix, options.coarse_ordering)?;
            (
                Coarse::Direct(symbolic.factor_with(&coarse_matrix, factor)?),
                None,
            )
        };
        setup.coarse_solver_s = lap(&mut clock);
        let smoother = Chebyshev::new(&a, options.smoother_degree, CHEBYSHEV_INTERVAL_RATIO)?;
        setup.smoother_s = lap(&mut clock);
        Ok(Self {
            a,
            preconditioner: Preconditioner::PMultigrid {
                p,
                pt,
                smoother,
                coarse,
            },
            amg_input,
            fine_modes,
            factor,
            options: *options,
            setup,
        })
    }

    /// Recomputes the fine matrix, coarse operator and smoothers for new values of `k_red`
    /// (same pattern), reusing the transfer operators and the coarse symbolic analysis (an AMG
    /// hierarchy is rebuilt). New values that leave a rigid-body motion without energy are
    /// refused by the null-space check of the set-up ([`FemError::SingularSystem`]), and the
    /// solver keeps its previous values.
    pub fn refactor(&mut self, k_red: &SymmetricMatrix) -> FemResult<()> {
        if k_red.dim() != self.a.dim() {
            return Err(FemError::PatternMismatch {
                detail: format!(
                    "iterative solver set up for dimension {}, got {}",
                    self.a.dim(),
                    k_red.dim()
                ),
            });
        }
        let mut clock = std::time::Instant::now();
        let mut setup = MultigridSetupTimes::default();
        let a = CsrMatrix::from_symmetric(k_red)?;
        check_null_space(&a, &self.fine_modes)?;
        self.a = a;
        setup.fine_csr_s = lap(&mut clock);
        let rebuild = |a: &CsrMatrix, input: &Option<(Vec<[f64; 6]>, Vec<usize>)>| {
            let (b, blocks) = input.clone().expect("AMG input kept at set-up");
            Amg::new(a, b, blocks, self.factor)
        };
        match &mut self.preconditioner {
            Preconditioner::Amg(amg) => {
                *amg = rebuild(&self.a, &self.amg_input)?;
                setup.coarse_solver_s = lap(&mut clock);
            }
            Preconditioner::PMultigrid {
                p,
                pt,
                smoother,
                coarse,
            } => {
                let coarse_matrix = self.a.galerkin(p, pt)?;
                setup.coarse_operator_s = lap(&mut clock);
                match coarse {
                    Coarse::Direct(factor) => factor.refactor(&coarse_matrix)?,
                    Coarse::Amg { a, amg } => {
                        *a = CsrMatrix::from_symmetric(&coarse_matrix)?;
                        *amg = rebuild(a, &self.amg_input)?;
                    }
                }
                setup.coarse_solver_s = lap(&mut clock);
                *smoother = Chebyshev::new(
                    &self.a,
                    self.options.smoother_degree,
                    CHEBYSHEV_INTERVAL_RATIO,
                )?;
                setup.smoother_s = lap(&mut clock);
            }
        }
        self.setup = setup;
        Ok(())
    }

    /// A workspace for [`Self::solve_in_place`].
    pub fn workspace(&self) -> MultigridWorkspace {
        let n = self.a.dim();
        let (nc, amg) = match &self.preconditioner {
            Preconditioner::Amg(amg) => (0, Some(amg.workspace())),
            Preconditioner::PMultigrid { pt, coarse, .. } => (
                pt.rows(),
                match coarse {
                    Coarse::Amg { amg, .. } => Some(amg.workspace()),
                    Coarse::Direct(_) => None,
                },
            ),
        };
        MultigridWorkspace {
            r: vec![0.0; n],
            d: vec![0.0; n],
            rc: vec![0.0; nc],
            xc: vec![0.0; nc],
            amg,
            pcg: PcgWorkspace::new(n),
        }
    }

    /// Sizes and memory.
    pub fn report(&self) -> MultigridReport {
        let mut report = MultigridReport {
            fine_unknowns: self.a.dim(),
            coarse_unknowns: 0,
            fine_nnz: self.a.nnz(),
            coarse_factor_nnz: 0,
            memory_bytes: self.a.memory_bytes() + 8 * self.a.dim(),
            lambda_max: 0.0,
            coarse_solver: "amg-only",
            amg_levels: 0,
            amg_operator_complexity: 0.0,
            setup: self.setup,
        };
        let add_amg = |report: &mut MultigridReport, amg: &Amg| {
            let r = amg.report();
            report.amg_levels = r.level_unknowns.len();
            report.amg_operator_complexity = r.operator_complexity;
            report.memory_bytes += r.memory_bytes;
            report.coarse_factor_nnz = amg.coarsest_factor_nnz();
        };
        match &self.preconditioner {
            Preconditioner::Amg(amg) => {
                add_amg(&mut report, amg);
                report.lambda_max = amg.finest_lambda_max();
            }
            Preconditioner::PMultigrid {
                p,
                pt,
                smoother,
                coarse,
            } => {
                report.coarse_unknowns = pt.rows();
                report.lambda_max = smoother.lambda_max();
                report.memory_bytes += p.memory_bytes() + pt.memory_bytes();
                match coarse {
                    Coarse::Direct(factor) => {
                        report.coarse_solver = "direct";
                        report.coarse_factor_nnz = factor.symbolic().factor_nnz();
                        report.memory_bytes += factor.memory_bytes();
                    }
                    Coarse::Amg { a, amg } => {
                        report.coarse_solver = "amg";
                        report.memory_bytes += a.memory_bytes();
                        add_amg(&mut report, amg);
                    }
                }
            }
        }
        report
    }

    /// The options in use.
    pub fn options(&self) -> &IterativeOptions {
        &self.options
    }

    /// z = M⁻¹ r: one p-multigrid V-cycle (pre-smoothing, coarse correction, post-smoothing) or
    /// one AMG V-cycle.
    fn precondition(&self, r_in: &[f64], z: &mut [f64], ws: &mut VCycleVectors) -> FemResult<()> {
        let VCycleVectors { r, d, rc, xc, amg } = ws;
        match &self.preconditioner {
            Preconditioner::Amg(h) => {
                h.v_cycle(&self.a, r_in, z, amg.as_mut().expect("AMG workspace"))
            }
            Preconditioner::PMultigrid {
                p,
                pt,
                smoother,
                coarse,
            } => {
                z.fill(0.0);
                smoother.smooth(&self.a, r_in, z, true, r, d);
                smoother.residual(&self.a, r_in, z, r);
                pt.mul_vec(r, rc);
                match coarse {
                    Coarse::Direct(factor) => {
                        factor.solve_in_place(rc)?;
                        p.mul_add_vec(rc, z);
                    }
                    Coarse::Amg { a, amg: h } => {
                        h.v_cycle(a, rc, xc, amg.as_mut().expect("AMG workspace"))?;
                        p.mul_add_vec(xc, z);
                    }
                }
                smoother.smooth(&self.a, r_in, z, false, r, d);
                Ok(())
            }
        }
    }

    /// Solves K_red x = b; on entry `rhs` = b, on exit x. Returns the iteration record.
    pub fn solve_in_place(
        &self,
        rhs: &mut [f64],
        ws: &mut MultigridWorkspace,
    ) -> FemResult<PcgReport> {
        let n = self.a.dim();
        if rhs.len() != n {
            return Err(FemError::DimensionMismatch {
                what: "right-hand side",
                expected: n,
                found: rhs.len(),
            });
        }
        let b = rhs.to_vec();
        let MultigridWorkspace {
            r,
            d,
            rc,
            xc,
            amg,
            pcg: pw,
        } = ws;
        let mut vectors = VCycleVectors { r, d, rc, xc, amg };
        let report = pcg(
            |v, out| self.a.mul_vec(v, out),
            |res, z| self.precondition(res, z, &mut vectors),
            &b,
            rhs,
            pw,
            &self.options.pcg(),
        )?;
        if let Some(i) = rhs.iter().position(|v| !v.is_finite()) {
            return Err(FemError::NonFiniteSolution { unknown: i });
        }
        Ok(report)
    }

    /// Solves for `ncols` right-hand sides stored column-major in `rhs` (overwritten with the
    /// solutions), one after the other with the shared set-up.
    pub fn solve_columns_in_place(
        &self,
        rhs: &mut [f64],
        ncols: usize,
        ws: &mut MultigridWorkspace,
    ) -> FemResult<Vec<PcgReport>> {
        let n = self.a.dim();
        if rhs.len() != n * ncols {
            return Err(FemError::DimensionMismatch {
                what: "column-major right-hand sides",
                expected: n * ncols,
                found: rhs.len(),
            });
        }
        if n == 0 {
            return Ok(vec![PcgReport::default(); ncols]);
        }
        rhs.chunks_mut(n)
            .map(|col| self.solve_in_place(col, ws))
            .collect()
    }
}

/// Borrowed work vectors of one preconditioner application.
struct VCycleVectors<'a> {
    r: &'a mut Vec<f64>,
    d: &'a mut Vec<f64>,
    rc: &'a mut Vec<f64>,
    xc: &'a mut Vec<f64>,
    amg: &'a mut Option<AmgWorkspace>,
}
