//! Box-constrained convex QP: min ½ xᵀA x − bᵀx subject to lo ≤ x ≤ hi, A symmetric positive
//! definite. Its KKT conditions are the incremental frictional (and, with lo = 0, hi = ∞, the
//! frictionless unilateral) contact problem: with λ = b − A x,
//! x_i = hi_i ⇒ λ_i ≥ 0, x_i = lo_i ⇒ λ_i ≤ 0, lo_i < x_i < hi_i ⇒ λ_i = 0.
//!
//! Method: primal–dual active set = semi-smooth Newton on x − clamp(x + λ, lo, hi) = 0
//! (Hintermüller, Ito & Kunisch, SIAM J. Optim. 13 (2003) 865), warm-started from the caller's
//! sets; it terminates at the exact solution once the sets repeat. Safeguard: if it has not
//! settled after [`MAX_ACTIVE_SET_ITERATIONS`], projected Gauss–Seidel from the best iterate,
//! which converges for any SPD A (Cryer, SIAM J. Control 9 (1971) 385; Luo & Tseng, JOTA 72
//! (1992) 7), to the natural residual tolerance, else a named error.
//!
//! Cost: a Newton step factors the free block of A (m³/3 for m free unknowns). Between steps
//! of a stick phase the free set rarely changes, so [`ActiveSet`] keeps the last free block's
//! Cholesky factor and reuses it while the free set repeats (the same bits as refactoring).

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

/// Active-set iterations before the projected Gauss–Seidel fallback. Default 40.
pub const MAX_ACTIVE_SET_ITERATIONS: usize = 40;
/// Projected Gauss–Seidel sweeps at most. Default 20000.
pub const MAX_GAUSS_SEIDEL_SWEEPS: usize = 20000;

/// Where each unknown sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bound {
    /// Strictly inside the box (stick for friction, contact for the normal problem).
    Free,
    /// At the lower bound.
    Lower,
    /// At the upper bound.
    Upper,
}

/// Warm start of a sequence of solves with the same matrix A: the sets of the last solve and
/// the Cholesky factor of A's block on its free unknowns.
#[derive(Debug, Clone)]
pub struct ActiveSet {
    /// Where each unknown sat at the end of the last solve (the next one's first guess).
    pub sets: Vec<Bound>,
    /// The free unknowns of the last factorisation and the factor of A on them.
    factor: Option<(Vec<usize>, Cholesky<f64, Dyn>)>,
}

impl ActiveSet {
    /// All `n` unknowns free, no factor yet.
    pub fn new(n: usize) -> Self {
        Self {
            sets: vec![Bound::Free; n],
            factor: None,
        }
    }

    /// The Cholesky factor of `a` on `free`: the kept one if `free` is the last free set,
    /// else a new one (kept). `None` if that block is not positive definite.
    fn factor_on(&mut self, a: &DMatrix<f64>, free: &[usize]) -> Option<&Cholesky<f64, Dyn>> {
        if self.factor.as_ref().is_none_or(|(kept, _)| kept != free) {
            let m = free.len();
            let sub = DMatrix::from_fn(m, m, |r, c| a[(free[r], free[c])]);
            self.factor = Some((free.to_vec(), sub.cholesky()?));
        }
        self.factor.as_ref().map(|(_, chol)| chol)
    }
}

/// Outcome of a solve.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxSolution {
    /// The minimiser.
    pub x: DVector<f64>,
    /// λ = b − A x (the slip increment for friction, the gap for normal contact).
    pub lambda: DVector<f64>,
    /// Natural residual max|x − clamp(x + λ, lo, hi)| relative to `scale`.
    pub residual: f64,
    /// Active-set iterations plus Gauss–Seidel sweeps.
    pub iterations: usize,
    /// Whether the fallback ran.
    pub fallback: bool,
}

fn natural_residual(x: &DVector<f64>, lambda: &DVector<f64>, lo: &[f64], hi: &[f64]) -> f64 {
    (0..x.len())
        .map(|i| (x[i] - (x[i] + lambda[i]).clamp(lo[i], hi[i])).abs())
        .fold(0.0, f64::max)
}

/// Solve with `active` as warm start (updated to the final sets; its factor must be of this
/// `a`: use one [`ActiveSet`] per matrix). `scale` makes the residual relative; `tolerance`
/// applies to it. `Err((iterations, residual))` if neither method reaches the tolerance.
pub fn solve(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    lo: &[f64],
    hi: &[f64],
    active: &mut ActiveSet,
    scale: f64,
    tolerance: f64,
) -> std::result::Result<BoxSolution, (usize, f64)> {
    let n = b.len();
    let scale = scale.max(1e-300);
    let mut x = DVector::zeros(n);
    let mut best: Option<(f64, DVector<f64>)> = None;
    for iteration in 1..=MAX_ACTIVE_SET_ITERATIONS {
        // Fixed unknowns at their bounds, Newton step on the free ones.
        for i in 0..n {
            if lo[i] == hi[i] {
                active.sets[i] = Bound::Lower;
            }
            x[i] = match active.sets[i] {
                Bound::Lower => lo[i],
                Bound::Upper => hi[i],
                Bound::Free => 0.0,
            };
        }
        let free: Vec<usize> = (0..n).filter(|&i| active.sets[i] == Bound::Free).collect();
        if !free.is_empty() {
            let m = free.len();
            // x is zero on the free unknowns here, so A x is the bound unknowns' pull on them.
            let pull = a * &x;
            let rhs = DVector::from_fn(m, |r, _| b[free[r]] - pull[free[r]]);
            let Some(chol) = active.factor_on(a, &free) else {
                return Err((iteration, f64::INFINITY));
            };
            let xf = chol.solve(&rhs);
            for (r, &i) in free.iter().enumerate() {
                x[i] = xf[r];
            }
        }
        let lambda = b - a * &x;
        let residual = natural_residual(&x, &lambda, lo, hi) / scale;
        if residual <= tolerance {
            return Ok(BoxSolution {
                x,
                lambda,
                residual,
                iterations: iteration,
                fallback: false,
            });
        }
        if best.as_ref().is_none_or(|(r, _)| residual < *r) {
            best = Some((residual, x.clone()));
        }
        for i in 0..n {
            let trial = x[i] + lambda[i];
            active.sets[i] = if lo[i] == hi[i] || trial < lo[i] {
                Bound::Lower
            } else if trial > hi[i] {
                Bound::Upper
            } else {
                Bound::Free
            };
        }
    }
    // Projected Gauss–Seidel from the best iterate, clamped into the box.
    let mut x = best.map_or(DVector::zeros(n), |(_, x)| x);
    for i in 0..n {
        x[i] = x[i].clamp(lo[i], hi[i]);
    }
    let mut residual = f64::INFINITY;
    for sweep in 1..=MAX_GAUSS_SEIDEL_SWEEPS {
        for i in 0..n {
            let off: f64 = (0..n).filter(|&j| j != i).map(|j| a[(i, j)] * x[j]).sum();
            x[i] = ((b[i] - off) / a[(i, i)]).clamp(lo[i], hi[i]);
        }
        if sweep % 8 == 0 || sweep == MAX_GAUSS_SEIDEL_SWEEPS {
            let lambda = b - a * &x;
            residual = natural_residual(&x, &lambda, lo, hi) / scale;
            if residual <= tolerance {
                for i in 0..n {
                    active.sets[i] = if x[i] <= lo[i] {
                        Bound::Lower
                    } else if x[i] >= hi[i] {
                        Bound::Upper
                    } else {
                        Bound::Free
                    };
                }
                return Ok(BoxSolution {
                    x,
                    lambda,
                    residual,
                    iterations: MAX_ACTIVE_SET_ITERATIONS + sweep,
                    fallback: true,
                });
            }
        }
    }
    Err((
        MAX_ACTIVE_SET_ITERATIONS + MAX_GAUSS_SEIDEL_SWEEPS,
        residual,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_solve_that_cannot_converge_reports_its_iterations_and_residual() {
        // Indefinite A: no Cholesky factor of the free block, the solve stops with an error
        // that the model turns into CoupledError::NotConverged naming the speed and step.
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        let b = DVector::from_vec(vec![0.1, 0.2]);
        let mut active = ActiveSet::new(2);
        let err = solve(&a, &b, &[-1.0; 2], &[1.0; 2], &mut active, 1.0, 1e-12).unwrap_err();
        assert!(
            err.0 >= 1 && err.1.is_infinite(),
            "non-convergence reported with iterations and residual: {err:?}"
        );
    }

    #[test]
    fn diagonal_problem_is_the_clamped_unconstrained_minimiser() {
        let a = DMatrix::from_diagonal(&DVector::from_vec(vec![2.0, 1.0, 4.0]));
        let b = DVector::from_vec(vec![4.0, -3.0, 1.0]);
        let mut active = ActiveSet::new(3);
        let s = solve(&a, &b, &[-1.0; 3], &[1.0; 3], &mut active, 1.0, 1e-14).unwrap();
        assert_eq!(s.x.as_slice(), &[1.0, -1.0, 0.25], "clamped minimiser");
        assert_eq!(
            active.sets,
            vec![Bound::Upper, Bound::Lower, Bound::Free],
            "final sets"
        );
    }

    #[test]
    fn coupled_problem_satisfies_the_kkt_conditions_exactly() {
        let n = 12;
        let a = DMatrix::from_fn(n, n, |i, j| 1.0 / (1.0 + (i as f64 - j as f64).abs()));
        let b = DVector::from_fn(n, |i, _| (i as f64 * 1.7).sin() * 3.0);
        let lo: Vec<f64> = (0..n).map(|i| -0.2 - 0.05 * i as f64).collect();
        let hi: Vec<f64> = lo.iter().map(|l| -l).collect();
        let mut active = ActiveSet::new(n);
        let s = solve(&a, &b, &lo, &hi, &mut active, 1.0, 1e-13).unwrap();
        for i in 0..n {
            let inside = s.x[i] > lo[i] + 1e-12 && s.x[i] < hi[i] - 1e-12;
            assert!(
                !inside || s.lambda[i].abs() < 1e-12,
                "interior unknown {i} has slip λ = {}",
                s.lambda[i]
            );
            assert!(
                s.x[i] < hi[i] - 1e-12 || s.lambda[i] >= -1e-12,
                "upper-bound unknown {i} slips the wrong way"
            );
        }
        assert!(!s.fallback, "active set settles without the fallback");
    }
}
