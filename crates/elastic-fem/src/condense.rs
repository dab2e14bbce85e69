//! Condensation onto a few load patterns by PCG: the generalised compliance
//! C_ij = v_iᵀ K_red⁻¹ w_j of load patterns w_j (columns) observed through patterns v_i, from one
//! PCG solve K_red x_j = w_j per column with **one** preconditioner set-up
//! ([`IterativeSolver`], built once by the caller) and one workspace reused by every column.
//! The iterative alternative to a direct factor's trailing-block inverse or per-column solves
//! (e.g. static-contact's disk compliances: a unit force on each contact disk's z tie, or each
//! disk's x-averaging load).
//!
//! **Accuracy.** Each column stops when PCG's estimate of its relative energy-norm error
//! ‖x_j − x̃_j‖_K / ‖x_j‖_K falls below ε ([`crate::IterativeOptions::relative_energy_error`];
//! [`mod@crate::sparse::pcg`] for the estimate). For patterns observed as they are loaded (v = w),
//! Cauchy–Schwarz in the K inner product bounds every entry:
//!
//! |C_ij − w_iᵀ x̃_j| = |x_iᵀ K (x_j − x̃_j)| ≤ ‖x_i‖_K · ε ‖x_j‖_K = ε √(C_ii C_jj),
//!
//! and on the diagonal, since CG's error is K-orthogonal to its Krylov space (which holds x̃_j),
//! C_jj − w_jᵀ x̃_j = ‖x_j − x̃_j‖²_K ≤ ε² C_jj (Hestenes & Stiefel 1952). The default
//! ε = [`crate::iterative::ALGEBRAIC_FRACTION`] × [`crate::iterative::DEFAULT_DISCRETISATION_ERROR`]
//! = 1e-6 keeps every entry within 1e-6 √(C_ii C_jj): 1 % of the relative error the Tet10 mesh
//! is assumed to resolve; [`crate::IterativeOptions::for_discretisation_error`] ties ε to another.
//! The bound holds as far as PCG's estimate of ‖x_j − x̃_j‖_K does: its delayed bound certifies
//! an earlier iterate (the returned one is more accurate), its geometric-tail estimate, which
//! usually stops first, extrapolates the observed contraction (an estimate, not a bound; see
//! [`mod@crate::sparse::pcg`]).
//! A cross pattern (v ≠ w, e.g. the z tie under an x load) obeys the same bound with C_ii the
//! compliance of v itself.
//!
//! **Columns one by one, cold.** The columns are solved in order, each from x = 0 (so the
//! Galerkin property above holds and each column's bits do not depend on the others). A warm
//! start from the previous columns does not pay here: each load sits on its own disk and its
//! solution is local to that disk, nearly K-orthogonal to the others'. A column that does not
//! converge ends in [`FemError::IterativeNotConverged`] naming the column.
//!
//! **Range.** Any SPD reduced system the [`IterativeSolver`] handles (Tet10: p-multigrid;
//! Tet4: SA-AMG). Bit-for-bit: the same for the same thread count (PCG's reductions split by
//! rayon); not necessarily across thread counts.

use nalgebra::DMatrix;

use crate::error::{FemError, FemResult};
use crate::iterative::{IterativeSolver, MultigridWorkspace};

/// A load or observation pattern on reduced unknowns: (unknown, weight) pairs.
pub type Pattern = Vec<(usize, f64)>;

/// The compliance blocks of [`condense_by_pcg`] and the PCG record of its columns.
#[derive(Debug, Clone, PartialEq)]
pub struct PcgCondensation {
    /// One matrix per observation set: entry (i, j) = v_iᵀ K⁻¹ w_j.
    pub blocks: Vec<DMatrix<f64>>,
    /// PCG iterations of each load column.
    pub iterations: Vec<usize>,
    /// Final estimated relative energy-norm error of each load column.
    pub relative_energy_error: Vec<f64>,
}

impl PcgCondensation {
    /// Total PCG iterations (products with K_red, each with one preconditioner application).
    pub fn total_iterations(&self) -> usize {
        self.iterations.iter().sum()
    }
}

/// Solves K_red x_j = w_j for every load pattern of `loads` with `solver`'s one set-up and
/// observes each solution through every set of `observe` (module docs). `ws` is the solver's
/// workspace, reused by every column.
pub fn condense_by_pcg(
    solver: &IterativeSolver,
    loads: &[Pattern],
    observe: &[&[Pattern]],
    ws: &mut MultigridWorkspace,
) -> FemResult<PcgCondensation> {
    let n = solver.report().fine_unknowns;
    let check = |p: &Pattern| match p.iter().find(|(j, _)| *j >= n) {
        Some(&(j, _)) => Err(FemError::DimensionMismatch {
            what: "condensation pattern unknown",
            expected: n,
            found: j,
        }),
        None => Ok(()),
    };
    loads.iter().try_for_each(check)?;
    observe
        .iter()
        .flat_map(|set| set.iter())
        .try_for_each(check)?;
    let mut blocks: Vec<DMatrix<f64>> = observe
        .iter()
        .map(|set| DMatrix::zeros(set.len(), loads.len()))
        .collect();
    let mut iterations = Vec::with_capacity(loads.len());
    let mut errors = Vec::with_capacity(loads.len());
    let mut x = vec![0.0; n];
    for (col, load) in loads.iter().enumerate() {
        x.fill(0.0);
        for &(j, w) in load {
            x[j] += w;
        }
        let report = solver
            .solve_in_place(&mut x, ws)
            .map_err(|e| name_column(e, col, loads.len()))?;
        for (block, set) in blocks.iter_mut().zip(observe) {
            for (i, pattern) in set.iter().enumerate() {
                block[(i, col)] = pattern.iter().map(|&(j, v)| v * x[j]).sum();
            }
        }
        iterations.push(report.iterations);
        errors.push(report.relative_energy_error);
    }
    Ok(PcgCondensation {
        blocks,
        iterations,
        relative_energy_error: errors,
    })
}

/// Adds the load column to a PCG failure.
fn name_column(error: FemError, col: usize, count: usize) -> FemError {
    match error {
        FemError::IterativeNotConverged {
            iterations,
            relative_energy_error,
            tolerance,
            rule,
        } => FemError::IterativeNotConverged {
            iterations,
            relative_energy_error,
            tolerance,
            rule: format!("condensation load column {col} of {count}: {rule}"),
        },
        other => other,
    }
}
