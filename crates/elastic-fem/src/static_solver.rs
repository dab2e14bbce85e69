//! Linear static solve: pattern → assembly → reduction → (direct: ordering → Cholesky → solve |
//! iterative: p-multigrid PCG) → expansion → reactions. A convenience pipeline over the public
//! building blocks; solvers that refactor many times (contact) compose those blocks themselves.
//!
//! **Choice of method** ([`choose_method`], `SolverMethod::Auto`, the default): a cost model in
//! seconds on one core,
//!
//! - direct: t_d = F / [`DIRECT_FLOP_RATE`] + s · 4 nnz(L) / [`TRIANGULAR_SOLVE_RATE`], with the
//!   factorisation flops F = Σ c_j² and nnz(L) from the symbolic analysis (METIS), s the number
//!   of right-hand sides;
//! - iterative: t_i = N ([`ITERATIVE_SETUP_S_PER_UNKNOWN`] + s · [`ITERATIVE_SOLVE_S_PER_UNKNOWN`]),
//!   linear in the N unknowns (multigrid: bounded iteration counts);
//!
//! picks the smaller, and the iterative one whenever the factor would exceed
//! [`DIRECT_FACTOR_MEMORY_BYTES`] (or the limit of the [`CostQuery`]). A condensation states its
//! right-hand sides separately per method ([`CostQuery`]: the strip's normal compliance is one
//! PCG column per post, but free from the direct factor's trailing block); [`CostEstimate`]
//! holds the figures (factor multiply–adds and bytes from the symbolic analysis, columns ×
//! [`ITERATIVE_ITERATIONS_PER_SOLVE`], iterative memory by [`ITERATIVE_BYTES_PER_ENTRY`]) and
//! [`CostEstimate::decide`] the rule and its printed reason. Below [`ALWAYS_DIRECT_UNKNOWNS`] it picks direct without
//! analysis; above [`ALWAYS_ITERATIVE_UNKNOWNS`] iterative without analysis. Tet4 meshes (whose
//! iterative path is SA-AMG alone, rates not measured) go direct whenever the factor fits. Rates measured on the punch meshes
//! (validation/fem-peers/README.md). The choice and its reason are in [`StaticSolution::choice`].

use crate::assembly::assemble_stiffness;
use crate::constraints::Constraints;
use crate::error::{FemError, FemResult};
use crate::iterative::{
    IterativeOptions, IterativeSolver, check_null_space_of, reduced_rigid_body_modes,
};
use crate::model::Connectivity;
use crate::model::Model;
use crate::pattern::StiffnessPattern;
use crate::post::{reaction_forces, strain_energy};
use crate::reduction::{DofMap, DofTarget, ReducedSystem, describe_dof};
use crate::rigid_modes::check_rigid_body_modes;
use crate::sparse::{
    CsrMatrix, FactorOptions, NumericCholesky, Ordering, SymbolicCholesky, SymmetricMatrix,
};

/// Sustained rate of the supernodal Cholesky on one core (multiply–adds/s, the unit of
/// [`SymbolicCholesky::factor_flops`]): faer 0.24.4's sequential factor of the default strip ran
/// 9.41 G multiply–adds in 1.2–1.6 s of CPU (loaded machine), ≈ 6–8 G/s; 2.5e10 before
/// (from a GFlop/s figure, 2 flops per multiply–add) overstated it 3–4×. Default 7e9.
pub const DIRECT_FLOP_RATE: f64 = 7e9;

/// Rate of the two triangular solves (flop/s, 4 flops per stored entry of L): memory-bound.
/// Default 2e9.
pub const TRIANGULAR_SOLVE_RATE: f64 = 2e9;

/// Set-up time of the iterative path per unknown (s): CSR copy, Galerkin coarse operator,
/// coarse Cholesky, smoother bounds. Measured on the punch meshes (23k–350k unknowns, one
/// thread, shared machine: ≈ 1e-5 s at 55k); default 1e-5 s.
pub const ITERATIVE_SETUP_S_PER_UNKNOWN: f64 = 1e-5;

/// Solve time of the iterative path per unknown and right-hand side (s) at the default
/// tolerance (13 PCG iterations on the punch meshes, 23k–350k unknowns, one thread, shared
/// machine: 1.25e-5 s); default 1.25e-5 s.
pub const ITERATIVE_SOLVE_S_PER_UNKNOWN: f64 = 1.25e-5;

/// Largest Cholesky factor the automatic choice accepts (bytes); larger goes iterative.
/// Default 8 GB.
pub const DIRECT_FACTOR_MEMORY_BYTES: f64 = 8e9;

/// Below this many reduced unknowns the automatic choice takes the direct solver without a
/// cost estimate (a direct solve is then about a second; measured at 23k unknowns: direct
/// 1.4 s, iterative 1.3 s whole process). Default 30 000.
pub const ALWAYS_DIRECT_UNKNOWNS: usize = 30_000;

/// Above this many reduced unknowns the automatic choice takes the iterative solver without
/// the (then costly) symbolic analysis. Default 3 000 000.
pub const ALWAYS_ITERATIVE_UNKNOWNS: usize = 3_000_000;

/// Linear solver of the reduced system.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SolverMethod {
    /// Choose by the cost model of the module docs (default).
    #[default]
    Auto,
    /// Sparse Cholesky (METIS + faer).
    Direct,
    /// PCG with the p-multigrid preconditioner ([`crate::iterative`]).
    Iterative,
}

impl SolverMethod {
    /// Parses `auto`, `direct` or `iterative` (for scene files and command lines).
    pub fn parse(text: &str) -> Option<Self> {
        match text {
            "auto" => Some(Self::Auto),
            "direct" => Some(Self::Direct),
            "iterative" => Some(Self::Iterative),
            _ => None,
        }
    }

    /// The lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Direct => "direct",
            Self::Iterative => "iterative",
        }
    }
}

/// The method used for a solve and why.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverChoice {
    /// `Direct` or `Iterative` (never `Auto`).
    pub method: SolverMethod,
    /// Human-readable reason (requested, or the cost-model figures).
    pub reason: String,
}

impl SolverChoice {
    /// `method` because the caller asked for it (reason "requested").
    pub fn requested(method: SolverMethod) -> Self {
        Self {
            method,
            reason: "requested".into(),
        }
    }
}

/// Iterations per right-hand side behind [`ITERATIVE_SOLVE_S_PER_UNKNOWN`] (the punch meshes'
/// count at the default tolerance); used to state the iterative estimate as columns ×
/// iterations. Default 13.
pub const ITERATIVE_ITERATIONS_PER_SOLVE: usize = 13;

/// Memory of the iterative path per stored entry of the fine matrix (both triangles, bytes):
/// 12 for the CSR entry (value and column index) and ≈ 6 assumed for the p-multigrid's
/// transfer operators, coarse Tet4 operator and factor (≈ 1/8 of the unknowns) and work vectors
/// (not yet checked against [`crate::iterative::MultigridReport::memory_bytes`]). Default 18.
pub const ITERATIVE_BYTES_PER_ENTRY: f64 = 18.0;

/// What the solves of one matrix will be: how many right-hand sides each method needs, and the
/// memory the direct factor may take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CostQuery {
    /// Right-hand sides the iterative path solves (one PCG solve each).
    pub rhs_count: usize,
    /// Pairs of triangular solves the direct path needs (fewer than `rhs_count` when the
    /// answer comes from the factor itself, e.g. a trailing-block inverse).
    pub direct_solves: usize,
    /// Largest accepted Cholesky factor (bytes); default [`DIRECT_FACTOR_MEMORY_BYTES`].
    pub factor_memory_limit_bytes: f64,
}

impl CostQuery {
    /// `rhs_count` right-hand sides solved one by one by either method, default memory limit.
    pub fn solves(rhs_count: usize) -> Self {
        Self {
            rhs_count,
            direct_solves: rhs_count,
            factor_memory_limit_bytes: DIRECT_FACTOR_MEMORY_BYTES,
        }
    }
}

/// The cost model's figures for one matrix (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CostEstimate {
    /// Reduced unknowns N.
    pub unknowns: usize,
    /// The query the estimate answers.
    pub query: CostQuery,
    /// Multiply–adds of the numeric factorisation (Σ c_j², symbolic analysis).
    pub factor_madds: f64,
    /// Bytes of the Cholesky factor (8 per stored entry).
    pub factor_bytes: f64,
    /// Estimated direct time (s): factorisation and `direct_solves` solve pairs.
    pub direct_s: f64,
    /// Estimated iterative time (s): set-up and `rhs_count` PCG solves.
    pub iterative_s: f64,
    /// Estimated memory of the iterative solver (bytes, [`ITERATIVE_BYTES_PER_ENTRY`]).
    pub iterative_bytes: f64,
}

impl CostEstimate {
    /// Figures of a matrix with `unknowns` rows and `matrix_nnz_upper` stored upper-triangle
    /// entries whose factor (symbolic analysis) has `factor_nnz` entries and costs
    /// `factor_madds` multiply–adds.
    pub fn from_figures(
        unknowns: usize,
        matrix_nnz_upper: usize,
        factor_madds: f64,
        factor_nnz: usize,
        query: CostQuery,
    ) -> Self {
        let n = unknowns as f64;
        let solves = query.direct_solves as f64;
        let columns = query.rhs_count.max(1) as f64;
        let full_entries = (2 * matrix_nnz_upper).saturating_sub(unknowns) as f64;
        Self {
            unknowns,
            query,
            factor_madds,
            factor_bytes: 8.0 * factor_nnz as f64,
            direct_s: factor_madds / DIRECT_FLOP_RATE
                + solves * 4.0 * factor_nnz as f64 / TRIANGULAR_SOLVE_RATE,
            iterative_s: n
                * (ITERATIVE_SETUP_S_PER_UNKNOWN + columns * ITERATIVE_SOLVE_S_PER_UNKNOWN),
            iterative_bytes: ITERATIVE_BYTES_PER_ENTRY * full_entries,
        }
    }

    /// Figures of `k_red` from its symbolic analysis.
    pub fn new(symbolic: &SymbolicCholesky, k_red: &SymmetricMatrix, query: CostQuery) -> Self {
        Self::from_figures(
            k_red.dim(),
            k_red.nnz_upper(),
            symbolic.factor_flops(),
            symbolic.factor_nnz(),
            query,
        )
    }

    /// The cheaper method, the iterative one whenever the factor exceeds the query's memory
    /// limit; `tet4` meshes (no measured iterative rates) go direct whenever the factor fits.
    /// The reason states every figure, e.g. "auto: direct cheaper: 185905 unknowns, 100
    /// right-hand side(s): direct ≈ 0.38 s (factor 9.4 G madds, 0.29 GB; 0 solves),
    /// iterative ≈ 234 s (100 columns × 13 it., 0.27 GB)".
    pub fn decide(&self, tet4: bool) -> SolverChoice {
        let q = &self.query;
        let figures = format!(
            "{} unknowns, {} right-hand side(s): direct ≈ {:.3} s (factor {:.3} G madds, {:.3} GB; \
             {} solves), iterative ≈ {:.3} s ({} columns × {ITERATIVE_ITERATIONS_PER_SOLVE} it., \
             {:.3} GB)",
            self.unknowns,
            q.rhs_count,
            self.direct_s,
            self.factor_madds / 1e9,
            self.factor_bytes / 1e9,
            q.direct_solves,
            self.iterative_s,
            q.rhs_count.max(1),
            self.iterative_bytes / 1e9
        );
        let (method, why) = if self.factor_bytes > q.factor_memory_limit_bytes {
            let why = format!(
                "factor over the memory limit of {:.3} GB",
                q.factor_memory_limit_bytes / 1e9
            );
            (SolverMethod::Iterative, why)
        } else if tet4 {
            let why = "Tet4 mesh (its AMG-only iterative path has no measured rates) and the \
                       factor fits";
            (SolverMethod::Direct, why.to_owned())
        } else if self.iterative_s < self.direct_s {
            (SolverMethod::Iterative, "iterative cheaper".to_owned())
        } else {
            (SolverMethod::Direct, "direct cheaper".to_owned())
        };
        SolverChoice {
            method,
            reason: format!("auto: {why}: {figures}"),
        }
    }
}

/// Chooses the method for a reduced matrix with `rhs_count` right-hand sides (module docs).
/// `Auto` may run the symbolic analysis (returned for reuse by the direct path).
pub fn choose_method(
    requested: SolverMethod,
    k_red: &SymmetricMatrix,
    rhs_count: usize,
    connectivity: &Connectivity,
    ordering: Ordering,
) -> FemResult<(SolverChoice, Option<SymbolicCholesky>)> {
    choose_method_with(
        requested,
        k_red,
        CostQuery::solves(rhs_count),
        connectivity,
        || SymbolicCholesky::analyze(k_red, ordering),
    )
}

/// [`choose_method`] for any [`CostQuery`], with the caller's symbolic analysis `analyse` (run
/// only when the cost model needs it; e.g. an ordering with some unknowns last, or cached).
pub fn choose_method_with(
    requested: SolverMethod,
    k_red: &SymmetricMatrix,
    query: CostQuery,
    connectivity: &Connectivity,
    analyse: impl FnOnce() -> FemResult<SymbolicCholesky>,
) -> FemResult<(SolverChoice, Option<SymbolicCholesky>)> {
    let n = k_red.dim();
    let choice = |method, reason: String, symbolic| (SolverChoice { method, reason }, symbolic);
    if requested != SolverMethod::Auto {
        return Ok((SolverChoice::requested(requested), None));
    }
    let tet4 = matches!(connectivity, Connectivity::Tet4(_));
    if n < ALWAYS_DIRECT_UNKNOWNS {
        let mesh = if tet4 { " (Tet4 mesh)" } else { "" };
        let reason = format!("auto: {n} unknowns < {ALWAYS_DIRECT_UNKNOWNS}{mesh}");
        return Ok(choice(SolverMethod::Direct, reason, None));
    }
    if n > ALWAYS_ITERATIVE_UNKNOWNS {
        let reason = format!("auto: {n} unknowns > {ALWAYS_ITERATIVE_UNKNOWNS}");
        return Ok(choice(SolverMethod::Iterative, reason, None));
    }
    let symbolic = analyse()?;
    let decided = CostEstimate::new(&symbolic, k_red, query).decide(tet4);
    Ok((decided, Some(symbolic)))
}

/// Options of [`solve_static`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    /// Fill-reducing ordering (default METIS).
    pub ordering: Ordering,
    /// Check for unconstrained rigid-body modes before factorising (default true).
    pub check_rigid_body_modes: bool,
    /// Numeric factorisation options (also the coarse factorisation of the iterative path).
    pub factor: FactorOptions,
    /// Direct, iterative or automatic (default [`SolverMethod::Auto`]).
    pub method: SolverMethod,
    /// Stopping rule and smoother of the iterative path.
    pub iterative: IterativeOptions,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            ordering: Ordering::Metis,
            check_rigid_body_modes: true,
            factor: FactorOptions::default(),
            method: SolverMethod::Auto,
            iterative: IterativeOptions::default(),
        }
    }
}

/// The data of a linear static problem.
#[derive(Debug, Clone, Copy)]
pub struct StaticProblem<'a> {
    /// Mesh and materials.
    pub model: &'a Model,
    /// Constraints.
    pub constraints: &'a Constraints,
    /// Full external load vector (N), length 3 × nodes.
    pub load_n: &'a [f64],
}

/// Result for one rigid face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidFaceResult {
    /// Shared displacement per tied component (m); `None` for free components.
    pub displacement_m: [Option<f64>; 3],
    /// Total force the constraints exert on the body through the face nodes, Σ (K u − f) (N).
    /// For a loaded component this equals the applied force; for a prescribed one it is the
    /// reaction.
    pub force_n: [f64; 3],
}

/// Sizes and choices of a solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveReport {
    /// Full unknowns (3 × nodes).
    pub full_unknowns: usize,
    /// Reduced unknowns after constraints.
    pub reduced_unknowns: usize,
    /// Stored entries of the reduced matrix (upper triangle).
    pub matrix_nnz: usize,
    /// Stored entries of the Cholesky factor.
    pub factor_nnz: usize,
    /// Ordering actually used.
    pub ordering_used: Ordering,
    /// Whether faer used its supernodal factorisation.
    pub supernodal: bool,
    /// PCG iterations (0 for the direct method).
    pub iterations: usize,
    /// Final estimated relative energy-norm error of PCG (0 for the direct method).
    pub relative_energy_error: f64,
}

/// Solution of a linear static problem.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    /// Displacements (m), DOF `3 n + c`.
    pub displacement_m: Vec<f64>,
    /// Reactions K u − f (N); non-zero only at constrained DOFs (up to round-off).
    pub reaction_n: Vec<f64>,
    /// Per rigid face, in the order of [`Constraints::rigid_faces`].
    pub rigid_faces: Vec<RigidFaceResult>,
    /// Strain energy ½ uᵀ K u (J).
    pub strain_energy_j: f64,
    /// Sizes and choices.
    pub report: SolveReport,
    /// The method used and why.
    pub choice: SolverChoice,
}

impl StaticSolution {
    /// Displacement of node `n` (m).
    pub fn node_displacement(&self, n: usize) -> [f64; 3] {
        [
            self.displacement_m[3 * n],
            self.displacement_m[3 * n + 1],
            self.displacement_m[3 * n + 2],
        ]
    }
}

/// Adds the node/component behind a reduced column to a factorisation error.
pub fn locate_factor_error(error: FemError, dof_map: &DofMap) -> FemError {
    match error {
        FemError::NotPositiveDefinite {
            column,
            pivot_ratio,
            minimum,
            ..
        } if column < dof_map.reduced_count() => FemError::NotPositiveDefinite {
            column,
            pivot_ratio,
            minimum,
            location: format!(
                " (unknown of {})",
                describe_dof(dof_map.representative_dof(column))
            ),
        },
        other => other,
    }
}

fn report_for(
    model: &Model,
    reduced: &ReducedSystem,
    matrix_nnz: usize,
    ordering: Ordering,
) -> SolveReport {
    SolveReport {
        full_unknowns: model.dof_count(),
        reduced_unknowns: reduced.dim(),
        matrix_nnz,
        factor_nnz: 0,
        ordering_used: ordering,
        supernodal: false,
        iterations: 0,
        relative_energy_error: 0.0,
    }
}

/// The requested iterative path: K_red goes straight into the solver's full-row CSR
/// ([`ReducedSystem::reduce_matrix_csr`]), no upper-triangle copy; solves `q` in place.
fn solve_iterative_requested(
    model: &Model,
    stiffness: &SymmetricMatrix,
    reduced: &ReducedSystem,
    q: &mut [f64],
    options: &SolverOptions,
) -> FemResult<(SolverChoice, SolveReport)> {
    let a = reduced.reduce_matrix_csr(stiffness)?;
    let mut report = report_for(model, reduced, (a.nnz() + a.dim()) / 2, options.ordering);
    if reduced.dim() > 0 {
        solve_by_pcg(model, reduced, a, q, options, &mut report)?;
    }
    Ok((SolverChoice::requested(SolverMethod::Iterative), report))
}

/// PCG with the p-multigrid (or AMG) preconditioner on `a` (K_red, full rows); solves `q` in
/// place and records the iterations in `report`.
fn solve_by_pcg(
    model: &Model,
    reduced: &ReducedSystem,
    a: CsrMatrix,
    q: &mut [f64],
    options: &SolverOptions,
    report: &mut SolveReport,
) -> FemResult<()> {
    let solver = IterativeSolver::from_csr(
        model,
        reduced.dof_map(),
        a,
        &options.iterative,
        options.factor,
    )?;
    let pcg = solver.solve_in_place(q, &mut solver.workspace())?;
    report.iterations = pcg.iterations;
    report.relative_energy_error = pcg.relative_energy_error;
    Ok(())
}

/// Chooses the method for `k_red` (options) and solves `q` in place.
fn solve_reduced(
    model: &Model,
    reduced: &ReducedSystem,
    k_red: &SymmetricMatrix,
    q: &mut [f64],
    options: &SolverOptions,
) -> FemResult<(SolverChoice, SolveReport)> {
    let (choice, mut analysed) = choose_method(
        options.method,
        k_red,
        1,
        model.connectivity(),
        options.ordering,
    )?;
    let mut report = report_for(model, reduced, k_red.nnz_upper(), options.ordering);
    if reduced.dim() == 0 {
        return Ok((choice, report));
    }
    match choice.method {
        SolverMethod::Iterative => {
            let a = CsrMatrix::from_symmetric(k_red)?;
            solve_by_pcg(model, reduced, a, q, options, &mut report)?;
        }
        _ => {
            // The pivot check alone misses a free body on a graded mesh (iterative module docs).
            check_null_space_of(
                |x, y| k_red.mul_vec(x, y),
                &k_red.diagonal(),
                &reduced_rigid_body_modes(model, reduced.dof_map()),
            )?;
            let symbolic = match analysed.take() {
                Some(s) => s,
                None => SymbolicCholesky::analyze(k_red, options.ordering)?,
            };
            let numeric: NumericCholesky = symbolic
                .factor_with(k_red, options.factor)
                .map_err(|e| locate_factor_error(e, reduced.dof_map()))?;
            numeric.solve_in_place(q)?;
            report.factor_nnz = symbolic.factor_nnz();
            report.ordering_used = symbolic.ordering_used();
            report.supernodal = symbolic.is_supernodal();
        }
    }
    Ok((choice, report))
}

/// Solves K u = f under the constraints.
pub fn solve_static(
    problem: &StaticProblem<'_>,
    options: &SolverOptions,
) -> FemResult<StaticSolution> {
    let model = problem.model;
    if problem.load_n.len() != model.dof_count() {
        return Err(FemError::DimensionMismatch {
            what: "load vector",
            expected: model.dof_count(),
            found: problem.load_n.len(),
        });
    }
    let pattern = StiffnessPattern::build(model);
    let stiffness = assemble_stiffness(model, &pattern)?;
    let dof_map = DofMap::new(model.node_count(), problem.constraints)?;
    if options.check_rigid_body_modes {
        check_rigid_body_modes(model, &dof_map)?;
    }
    let reduced = ReducedSystem::new(&stiffness, dof_map)?;
    let mut q = reduced.reduce_load(&stiffness, problem.load_n)?;
    let (choice, report) = if options.method == SolverMethod::Iterative {
        solve_iterative_requested(model, &stiffness, &reduced, &mut q, options)?
    } else {
        let k_red = reduced.reduce_matrix(&stiffness)?;
        solve_reduced(model, &reduced, &k_red, &mut q, options)?
    };
    let u = reduced.expand(&q)?;
    if let Some(i) = u.iter().position(|v| !v.is_finite()) {
        return Err(FemError::NonFiniteSolution { unknown: i });
    }
    let reaction = reaction_forces(&stiffness, &u, problem.load_n)?;
    let energy = strain_energy(&stiffness, &u)?;
    let rigid_faces = problem
        .constraints
        .rigid_faces
        .iter()
        .zip(reduced.dof_map().rigid_face_targets())
        .map(|(face, targets)| {
            let mut force_n = [0.0; 3];
            for &n in &face.nodes {
                for c in 0..3 {
                    force_n[c] += reaction[3 * n + c];
                }
            }
            let displacement_m = std::array::from_fn(|c| {
                targets[c].map(|t| match t {
                    DofTarget::Reduced(j) => q[j],
                    DofTarget::Prescribed(v) => v,
                })
            });
            RigidFaceResult {
                displacement_m,
                force_n,
            }
        })
        .collect();
    Ok(StaticSolution {
        displacement_m: u,
        reaction_n: reaction,
        rigid_faces,
        strain_energy_j: energy,
        report,
        choice,
    })
}
