//! Linear static solve: pattern → assembly → reduction → ordering → Cholesky → solve →
//! expansion → reactions. A convenience pipeline over the public building blocks; solvers that
//! refactor many times (contact) compose those blocks themselves.

use crate::assembly::assemble_stiffness;
use crate::constraints::Constraints;
use crate::error::{FemError, FemResult};
use crate::model::Model;
use crate::pattern::StiffnessPattern;
use crate::post::{reaction_forces, strain_energy};
use crate::reduction::{DofMap, DofTarget, ReducedSystem, describe_dof};
use crate::rigid_modes::check_rigid_body_modes;
use crate::sparse::{FactorOptions, NumericCholesky, Ordering, SymbolicCholesky};

/// Options of [`solve_static`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    /// Fill-reducing ordering (default METIS).
    pub ordering: Ordering,
    /// Check for unconstrained rigid-body modes before factorising (default true).
    pub check_rigid_body_modes: bool,
    /// Numeric factorisation options.
    pub factor: FactorOptions,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            ordering: Ordering::Metis,
            check_rigid_body_modes: true,
            factor: FactorOptions::default(),
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
    let k_red = reduced.reduce_matrix(&stiffness)?;
    let mut q = reduced.reduce_load(&stiffness, problem.load_n)?;
    let (factor_nnz, ordering_used, supernodal) = if reduced.dim() > 0 {
        let symbolic = SymbolicCholesky::analyze(&k_red, options.ordering)?;
        let numeric: NumericCholesky = symbolic
            .factor_with(&k_red, options.factor)
            .map_err(|e| locate_factor_error(e, reduced.dof_map()))?;
        numeric.solve_in_place(&mut q)?;
        (
            symbolic.factor_nnz(),
            symbolic.ordering_used(),
            symbolic.is_supernodal(),
        )
    } else {
        (0, options.ordering, false)
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
        report: SolveReport {
            full_unknowns: model.dof_count(),
            reduced_unknowns: reduced.dim(),
            matrix_nnz: k_red.nnz_upper(),
            factor_nnz,
            ordering_used,
            supernodal,
        },
    })
}
