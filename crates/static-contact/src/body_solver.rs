//! The linear solver behind a condensed body ([`crate::BodyCompliance`]): its Cholesky factor
//! (direct) or one PCG set-up (iterative), chosen by elastic-fem's cost model
//! ([`elastic_fem::CostEstimate`]) unless the scene asks (`static.fem_solver`).
//!
//! - **Direct**: METIS ordering with the disk z ties last, sparse Cholesky; the normal
//!   compliance is the inverse of the factor's trailing block (no solve per disk).
//! - **Iterative**: the p-multigrid (Tet10) or SA-AMG (Tet4) preconditioner set up once; the
//!   normal compliance C_ij = e_iᵀ K⁻¹ e_j (e_j: a unit force on disk j's z tie) from one PCG
//!   column per disk ([`elastic_fem::condense`]), symmetrised. Every entry lies within
//!   ε √(C_ii C_jj) of the exact one, the diagonal within ε² C_ii, with ε the PCG tolerance
//!   (default 1e-6: 1 % of the 1e-4 relative error assumed of the mesh). Later solves
//!   (displacement fields, the tangential compliance) are PCG solves with the same set-up.
//!
//! Cost model inputs for a body: N unknowns, one PCG column per disk for the iterative path,
//! no solve for the direct one (the trailing block), the factor's multiply–adds and bytes from
//! the symbolic analysis, the memory limit [`elastic_fem::static_solver::DIRECT_FACTOR_MEMORY_BYTES`].
//! On the default strip (185 905 unknowns, 100 posts) it picks direct: ≈ 1.3 s against ≈ 230 s.

use std::cell::Cell;
use std::path::Path;
use std::time::Instant;

use elastic_fem::condense::{Pattern, condense_by_pcg};
use elastic_fem::sparse::{
    FactorOptions, NumericCholesky, Ordering, SymbolicCholesky, SymmetricMatrix,
    fill_reducing_order,
};
use elastic_fem::static_solver::{DIRECT_FACTOR_MEMORY_BYTES, locate_factor_error};
use elastic_fem::{
    CostQuery, FemError, FemResult, IterativeOptions, IterativeSolver, Model, ReducedSystem,
    SolverMethod, choose_method_with,
};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::body_spec::BodySpec;
use crate::error::{ContactError, Result};
use crate::order_cache::{self, order_file};

/// `static.fem_solver`: how a body's stiffness is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FemSolver {
    /// The cost model chooses (default); never the value of a solver that ran.
    #[default]
    Auto,
    /// Sparse Cholesky.
    Direct,
    /// Preconditioned conjugate gradients.
    Iterative,
}

impl FemSolver {
    /// Parses `auto`, `direct` or `iterative`.
    pub fn parse(text: &str) -> Option<Self> {
        SolverMethod::parse(text).map(Self::from_method)
    }

    /// The lower-case name.
    pub fn name(self) -> &'static str {
        self.method().name()
    }

    /// elastic-fem's method.
    pub fn method(self) -> SolverMethod {
        match self {
            Self::Auto => SolverMethod::Auto,
            Self::Direct => SolverMethod::Direct,
            Self::Iterative => SolverMethod::Iterative,
        }
    }

    fn from_method(method: SolverMethod) -> Self {
        match method {
            SolverMethod::Auto => Self::Auto,
            SolverMethod::Direct => Self::Direct,
            SolverMethod::Iterative => Self::Iterative,
        }
    }

    /// Whether this is `Auto` (the default, left out of content hashes).
    pub fn is_auto(&self) -> bool {
        *self == Self::Auto
    }

    /// `Direct`: the solver of reports written before the key existed.
    pub fn direct() -> Self {
        Self::Direct
    }
}

/// A body's solver: the factor, or the PCG set-up.
#[derive(Debug)]
#[allow(clippy::large_enum_variant)]
pub enum BodySolver {
    /// Sparse Cholesky factor (disk z ties last).
    Direct(NumericCholesky),
    /// PCG with its preconditioner.
    Iterative(IterativeSolver),
}

impl BodySolver {
    /// Solves K_red x = b in place.
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> FemResult<()> {
        match self {
            Self::Direct(f) => f.solve_in_place(rhs),
            Self::Iterative(s) => s.solve_in_place(rhs, &mut s.workspace()).map(|_| ()),
        }
    }

    /// Solves `ncols` column-major right-hand sides in place.
    pub fn solve_columns_in_place(&self, rhs: &mut [f64], ncols: usize) -> FemResult<()> {
        match self {
            Self::Direct(f) => f.solve_columns_in_place(rhs, ncols),
            Self::Iterative(s) => s
                .solve_columns_in_place(rhs, ncols, &mut s.workspace())
                .map(|_| ()),
        }
    }

    /// The Cholesky factor, if direct.
    pub fn cholesky(&self) -> Option<&NumericCholesky> {
        match self {
            Self::Direct(f) => Some(f),
            Self::Iterative(_) => None,
        }
    }

    /// `Direct` or `Iterative`.
    pub fn method(&self) -> FemSolver {
        match self {
            Self::Direct(_) => FemSolver::Direct,
            Self::Iterative(_) => FemSolver::Iterative,
        }
    }
}

/// A body's solver with its normal disk compliance and figures (for [`crate::FemStats`]).
#[derive(Debug)]
pub(crate) struct Condensed {
    pub solver: BodySolver,
    /// Normal disk compliance (m/N), the disk fraction applied.
    pub compliance: DMatrix<f64>,
    /// Why this solver (the cost model's figures, or "requested").
    pub reason: String,
    pub factor_nnz: usize,
    pub factor_flops: f64,
    pub analysis_s: f64,
    pub ordering_cached: bool,
    /// Factorisation, or the preconditioner set-up (s).
    pub factor_s: f64,
    /// Trailing-block inverse, or the PCG columns (s).
    pub solve_s: f64,
    pub pcg_iterations: usize,
}

/// The solver chosen for a body, with the direct path's symbolic analysis: everything that
/// needs only the structure of the reduced stiffness ([`plan_body`]), so that it can run while
/// the values are assembled.
#[derive(Debug)]
pub(crate) struct SolverPlan {
    method: SolverMethod,
    /// Why this solver (the cost model's figures, or "requested").
    reason: String,
    /// The direct path's symbolic analysis (`None` for the iterative path).
    symbolic: Option<SymbolicCholesky>,
    ordering_cached: bool,
    /// METIS ordering (or the cached one) and symbolic analysis (s).
    analysis_s: f64,
}

/// Chooses the solver of a body whose reduced stiffness has the structure of `k_red` (values
/// unused; `masters` are the disks' z tie unknowns) and, for the direct path, runs the symbolic
/// analysis.
pub(crate) fn plan_body(
    spec: &BodySpec<'_>,
    model: &Model,
    k_red: &SymmetricMatrix,
    masters: &[usize],
    order_cache: Option<&Path>,
    requested: FemSolver,
) -> Result<SolverPlan> {
    let start = Instant::now();
    let query = CostQuery {
        rhs_count: masters.len(),
        direct_solves: 0,
        factor_memory_limit_bytes: DIRECT_FACTOR_MEMORY_BYTES,
    };
    let cached = Cell::new(false);
    let mut analysis_error = None;
    let chosen = choose_method_with(
        requested.method(),
        k_red,
        query,
        model.connectivity(),
        || match analyse(spec, k_red, masters, order_cache) {
            Ok((symbolic, from_cache)) => {
                cached.set(from_cache);
                Ok(symbolic)
            }
            Err(e) => {
                analysis_error = Some(e);
                Err(FemError::IterativeUnsupported {
                    reason: "symbolic analysis failed".into(),
                })
            }
        },
    );
    if let Some(e) = analysis_error {
        return Err(e);
    }
    let (choice, symbolic) = chosen.map_err(|e| fem_error(spec, e))?;
    let (symbolic, ordering_cached) = match (choice.method, symbolic) {
        (SolverMethod::Iterative, _) => (None, false),
        (_, Some(s)) => (Some(s), cached.get()),
        (_, None) => {
            let (s, from_cache) = analyse(spec, k_red, masters, order_cache)?;
            (Some(s), from_cache)
        }
    };
    Ok(SolverPlan {
        method: choice.method,
        reason: choice.reason,
        symbolic,
        ordering_cached,
        analysis_s: start.elapsed().as_secs_f64(),
    })
}

/// Symbolic analysis of the body's reduced stiffness with the disk ties eliminated last; the
/// fill-reducing ordering is read from, or stored in, the folder `order_cache` when given.
/// Returns whether the ordering came from the cache.
fn analyse(
    spec: &BodySpec<'_>,
    k_red: &SymmetricMatrix,
    masters: &[usize],
    order_cache: Option<&Path>,
) -> Result<(SymbolicCholesky, bool)> {
    let fem = |e| fem_error(spec, e);
    let Some(dir) = order_cache else {
        let symbolic = SymbolicCholesky::analyze_with_last(k_red, Ordering::Metis, masters);
        return Ok((symbolic.map_err(fem)?, false));
    };
    let file = order_file(
        dir,
        &spec.mesh.source,
        spec.name,
        k_red.pattern_fingerprint(),
    );
    if let Some((base, used)) = order_cache::load(&file, k_red.dim()) {
        let symbolic = SymbolicCholesky::analyze_with_last_ordered(k_red, &base, used, masters);
        return Ok((symbolic.map_err(fem)?, true));
    }
    let (base, used) = fill_reducing_order(k_red, Ordering::Metis).map_err(fem)?;
    order_cache::store(&file, &base, used).map_err(|e| ContactError::CacheWrite {
        path: file.clone(),
        detail: e.to_string(),
    })?;
    let symbolic = SymbolicCholesky::analyze_with_last_ordered(k_red, &base, used, masters);
    Ok((symbolic.map_err(fem)?, false))
}

/// Factors (or sets up PCG for) `k_red`, the body's reduced stiffness, as `plan` says, and
/// condenses it onto the disks (`masters`: their z tie unknowns).
pub(crate) fn condense_body(
    spec: &BodySpec<'_>,
    model: &Model,
    reduced: &ReducedSystem,
    k_red: &SymmetricMatrix,
    masters: &[usize],
    plan: SolverPlan,
) -> Result<Condensed> {
    let fem = |e| fem_error(spec, e);
    let (reason, analysis_s) = (plan.reason, plan.analysis_s);
    let symbolic = match (plan.method, plan.symbolic) {
        (SolverMethod::Iterative, _) | (_, None) => {
            return condense_iterative(spec, model, reduced, k_red, masters, reason);
        }
        (_, Some(symbolic)) => symbolic,
    };
    let start = Instant::now();
    let factor = symbolic
        .factor_with(k_red, direct_factor_options())
        .map_err(|e| fem(locate_factor_error(e, reduced.dof_map())))?;
    let factor_s = analysis_s + start.elapsed().as_secs_f64();
    let start = Instant::now();
    let compliance = factor.trailing_inverse(masters.len()).map_err(fem)? * spec.disk_fraction;
    Ok(Condensed {
        solver: BodySolver::Direct(factor),
        compliance,
        reason,
        factor_nnz: symbolic.factor_nnz(),
        factor_flops: symbolic.factor_flops(),
        analysis_s,
        ordering_cached: plan.ordering_cached,
        factor_s,
        solve_s: start.elapsed().as_secs_f64(),
        pcg_iterations: 0,
    })
}

/// Threads of a body's numeric Cholesky factorisation and of its solves: one. faer 0.24's
/// supernodal factor is left-looking with parallelism only inside each supernode's dense
/// kernels; on the default strip two threads gave 0.61–1.0× the speed of one (measured) and
/// cost ≈ 0.5 s more CPU (idle workers spinning). One thread also gives the same factor bits on
/// any machine and thread count. Default 1.
pub const DIRECT_FACTOR_THREADS: usize = 1;

fn direct_factor_options() -> FactorOptions {
    FactorOptions {
        threads: DIRECT_FACTOR_THREADS,
        ..FactorOptions::default()
    }
}

/// The iterative path: one set-up, one PCG column per disk (module docs).
fn condense_iterative(
    spec: &BodySpec<'_>,
    model: &Model,
    reduced: &ReducedSystem,
    k_red: &SymmetricMatrix,
    masters: &[usize],
    reason: String,
) -> Result<Condensed> {
    let fem = |e| fem_error(spec, e);
    let start = Instant::now();
    let options = IterativeOptions::default();
    let solver = IterativeSolver::new(
        model,
        reduced.dof_map(),
        k_red,
        &options,
        FactorOptions::default(),
    )
    .map_err(fem)?;
    let factor_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let ties: Vec<Pattern> = masters.iter().map(|&j| vec![(j, 1.0)]).collect();
    let condensed =
        condense_by_pcg(&solver, &ties, &[&ties], &mut solver.workspace()).map_err(fem)?;
    let c = &condensed.blocks[0];
    let compliance = (c + c.transpose()) * (0.5 * spec.disk_fraction);
    Ok(Condensed {
        reason,
        compliance,
        factor_nnz: 0,
        factor_flops: 0.0,
        analysis_s: 0.0,
        ordering_cached: false,
        factor_s,
        solve_s: start.elapsed().as_secs_f64(),
        pcg_iterations: condensed.total_iterations(),
        solver: BodySolver::Iterative(solver),
    })
}

fn fem_error(spec: &BodySpec<'_>, source: FemError) -> ContactError {
    ContactError::Fem {
        body: spec.name,
        file: spec.mesh.source.clone(),
        source: Box::new(source),
    }
}
