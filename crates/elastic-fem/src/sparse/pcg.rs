//! Preconditioned conjugate gradients (Hestenes & Stiefel 1952) for SPD systems A x = b, with
//! the stopping rule on the *energy-norm* error, not on the residual.
//!
//! **Error estimate.** With x₀ = 0, CG's energy increments α_j γ_j (γ_j = r_jᵀ M⁻¹ r_j) satisfy
//! ‖x − x_k‖²_A = Σ_{j ≥ k} α_j γ_j and ‖x_k‖²_A = Σ_{j < k} α_j γ_j (exact arithmetic), so
//! the delayed estimate
//!
//! ε_k² = Σ_{j=k}^{k+d−1} α_j γ_j / Σ_{j<k+d} α_j γ_j
//!
//! is a lower bound of the relative energy error ‖x − x_k‖_A / ‖x‖_A that becomes tight once the
//! convergence is fast over d steps (Strakoš & Tichý 2002, ETNA 13:56–80, "On error estimation
//! in the conjugate gradient method and why it works in finite precision computations"; the
//! bound survives rounding). With a multigrid preconditioner the contraction per step is
//! ≈ 0.1–0.3, so d = [`DEFAULT_ERROR_DELAY`] steps make the bound tight within a factor ≈ 1.5.
//!
//! **Stopping rule.** Two tests, the first met ends the iteration:
//! 1. *Delayed bound*: ε_k ≤ tolerance; the iterate returned is x_{k+d}, d steps beyond the one
//!    the bound certifies (its error is smaller by about the contraction to the power d, i.e.
//!    ≈ 100× for d = 4: accuracy nobody asked for, at the price of d products).
//! 2. *Geometric tail* (the adaptive idea of Meurant, Papež & Tichý 2021, Numer. Algorithms
//!    88:1337, "Accurate error estimation in CG"): once the energy increments contract steadily,
//!    q = the largest of the last [`TAIL_RATIOS`] ratios α_j γ_j / α_{j−1} γ_{j−1} is below
//!    `contraction_limit`, the error of the *current* iterate is estimated by the geometric tail
//!    ‖x − x_k‖²_A ≈ α_{k−1} γ_{k−1} q / (1 − q), and the iteration stops when that is within the
//!    tolerance. This returns an iterate whose estimated error is the tolerance asked for, about
//!    d steps earlier than rule 1. It is an estimate, not a bound: it assumes the contraction
//!    observed over the last steps continues; irregular convergence (q ≥ the limit) leaves only
//!    rule 1. `contraction_limit` = 0 switches rule 2 off.
//!
//! **Failure.** More than `max_iterations` steps, pᵀ A p ≤ 0 (A or M not SPD) or a non-finite
//! value end in [`FemError::IterativeNotConverged`], naming the rule, the iterations and the
//! estimate reached.

use rayon::prelude::*;

use super::csr::ROW_BLOCK;
use crate::error::{FemError, FemResult};

/// Delay d of the energy-error estimate (iterations). Default 4.
pub const DEFAULT_ERROR_DELAY: usize = 4;

/// Largest ratio of consecutive energy increments for which the geometric-tail rule applies.
/// Dimensionless; default 0.5 (a multigrid-preconditioned elasticity solve contracts the energy
/// increments by ≈ 0.01–0.1 per step; 0.5 keeps the tail estimate within a factor 2 when the
/// contraction slows).
pub const DEFAULT_CONTRACTION_LIMIT: f64 = 0.5;

/// Consecutive increment ratios whose largest is the contraction q of the geometric-tail rule.
/// Default 3.
pub const TAIL_RATIOS: usize = 3;

/// Iteration limit of one solve (a well-preconditioned elasticity solve needs 10–40).
/// Default 500.
pub const DEFAULT_MAX_ITERATIONS: usize = 500;

/// Stopping rule and limits of [`pcg`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PcgOptions {
    /// Tolerance on the estimated relative energy-norm error ‖x − x_k‖_A / ‖x‖_A (> 0).
    pub relative_energy_error: f64,
    /// See [`DEFAULT_MAX_ITERATIONS`].
    pub max_iterations: usize,
    /// See [`DEFAULT_ERROR_DELAY`].
    pub error_delay: usize,
    /// See [`DEFAULT_CONTRACTION_LIMIT`] (0: the delayed bound alone).
    pub contraction_limit: f64,
}

/// Iteration record of one PCG solve.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PcgReport {
    /// Iterations performed (matrix–vector products with A).
    pub iterations: usize,
    /// ‖r_k‖₂ / ‖b‖₂ after each iteration.
    pub residual_history: Vec<f64>,
    /// Energy increment α_k γ_k of each iteration (‖x‖²_A units, i.e. J·2 for stiffness systems).
    pub energy_increments: Vec<f64>,
    /// Final estimate of the relative energy-norm error: of the returned iterate when the
    /// geometric-tail rule stopped, else the delayed bound of the iterate d steps before it.
    pub relative_energy_error: f64,
}

/// Vectors PCG works in, owned by the caller (reuse across right-hand sides).
#[derive(Debug, Clone, Default)]
pub struct PcgWorkspace {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

impl PcgWorkspace {
    /// Workspace for systems of dimension `n`.
    pub fn new(n: usize) -> Self {
        Self {
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            q: vec![0.0; n],
        }
    }
}

/// Parallel dot product with a fixed summation order: one partial sum per block of
/// [`ROW_BLOCK`] entries (blocks in parallel), the block sums then added in block order. The
/// result has the same bits for any thread count and run (a rayon `sum` combines partial sums
/// along the work-stealing tree, which varies from run to run with more than one thread).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let partial: Vec<f64> = a
        .par_chunks(ROW_BLOCK)
        .zip(b.par_chunks(ROW_BLOCK))
        .map(|(x, y)| x.iter().zip(y).map(|(u, v)| u * v).sum::<f64>())
        .collect();
    partial.iter().sum()
}

/// y += a x, in parallel.
pub fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    y.par_chunks_mut(ROW_BLOCK)
        .zip(x.par_chunks(ROW_BLOCK))
        .for_each(|(yb, xb)| yb.iter_mut().zip(xb).for_each(|(yi, xi)| *yi += a * xi));
}

fn failure(rule: &str, report: &PcgReport, options: &PcgOptions) -> FemError {
    FemError::IterativeNotConverged {
        iterations: report.iterations,
        relative_energy_error: report.relative_energy_error,
        tolerance: options.relative_energy_error,
        rule: rule.to_string(),
    }
}

/// The geometric-tail estimate of ‖x − x_k‖²_A from the energy increments of steps 0..k (see the
/// module docs), or `None` while fewer than [`TAIL_RATIOS`] ratios are known or the contraction
/// is not below `limit`.
fn geometric_tail(increments: &[f64], limit: f64) -> Option<f64> {
    let k = increments.len();
    if k < TAIL_RATIOS + 1 {
        return None;
    }
    let q = increments[k - TAIL_RATIOS - 1..]
        .windows(2)
        .map(|w| w[1] / w[0])
        .fold(0.0, f64::max);
    (q < limit).then(|| increments[k - 1] * q / (1.0 - q))
}

/// Whether the energy error estimate meets the tolerance: the last `d` increments over the
/// energy (delayed estimate, kept in the report), or the geometric tail of the increments.
fn converged(report: &mut PcgReport, energy: f64, d: usize, options: &PcgOptions) -> bool {
    let k = report.energy_increments.len();
    if k >= d {
        let tail: f64 = report.energy_increments[k - d..].iter().sum();
        report.relative_energy_error = (tail / energy).sqrt();
        if report.relative_energy_error <= options.relative_energy_error {
            return true;
        }
    }
    if let Some(tail) = geometric_tail(&report.energy_increments, options.contraction_limit) {
        let estimate = (tail / energy).sqrt();
        if estimate <= options.relative_energy_error {
            report.relative_energy_error = estimate;
            return true;
        }
    }
    false
}

/// Solves A x = b by PCG from x₀ = 0. `apply_a(v, out)` sets out = A v, `apply_m(r, out)` sets
/// out = M⁻¹ r (symmetric positive definite). On success `x` holds the solution.
pub fn pcg(
    mut apply_a: impl FnMut(&[f64], &mut [f64]),
    mut apply_m: impl FnMut(&[f64], &mut [f64]) -> FemResult<()>,
    b: &[f64],
    x: &mut [f64],
    ws: &mut PcgWorkspace,
    options: &PcgOptions,
) -> FemResult<PcgReport> {
    let n = b.len();
    if x.len() != n || ws.r.len() != n {
        return Err(FemError::DimensionMismatch {
            what: "PCG vectors",
            expected: n,
            found: x.len().min(ws.r.len()),
        });
    }
    let mut report = PcgReport {
        relative_energy_error: f64::INFINITY,
        ..PcgReport::default()
    };
    x.fill(0.0);
    let b_norm = dot(b, b).sqrt();
    if b_norm == 0.0 {
        report.relative_energy_error = 0.0;
        return Ok(report);
    }
    let PcgWorkspace { r, z, p, q } = ws;
    r.copy_from_slice(b);
    apply_m(r, z)?;
    p.copy_from_slice(z);
    let mut gamma = dot(r, z);
    let mut energy = 0.0;
    let d = options.error_delay.max(1);
    loop {
        if report.iterations >= options.max_iterations {
            return Err(failure("iteration limit reached", &report, options));
        }
        apply_a(p, q);
        let pq = dot(p, q);
        if pq.is_nan() || pq <= 0.0 || !gamma.is_finite() {
            return Err(failure(
                "breakdown: pᵀ A p ≤ 0 or not finite (matrix or preconditioner not SPD)",
                &report,
                options,
            ));
        }
        let alpha = gamma / pq;
        axpy(alpha, p, x);
        axpy(-alpha, q, r);
        report.iterations += 1;
        let increment = alpha * gamma;
        energy += increment;
        report.energy_increments.push(increment);
        report.residual_history.push(dot(r, r).sqrt() / b_norm);
        if converged(&mut report, energy, d, options) {
            return Ok(report);
        }
        apply_m(r, z)?;
        let gamma_new = dot(r, z);
        let beta = gamma_new / gamma;
        gamma = gamma_new;
        p.par_chunks_mut(ROW_BLOCK)
            .zip(z.par_chunks(ROW_BLOCK))
            .for_each(|(pb, zb)| {
                pb.iter_mut()
                    .zip(zb)
                    .for_each(|(pi, zi)| *pi = zi + beta * *pi)
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sparse::{CsrMatrix, SymmetricMatrix};

    /// 1D Laplacian of size n (SPD, condition ≈ n²).
    fn laplacian(n: usize) -> SymmetricMatrix {
        let mut col_ptr = vec![0];
        let (mut rows, mut vals) = (Vec::new(), Vec::new());
        for j in 0..n {
            if j > 0 {
                rows.push(j - 1);
                vals.push(-1.0);
            }
            rows.push(j);
            vals.push(2.0);
            col_ptr.push(rows.len());
        }
        SymmetricMatrix::from_upper_parts(n, col_ptr, rows, vals).unwrap()
    }

    /// A non-smooth right-hand side of length n.
    fn test_rhs(n: usize) -> Vec<f64> {
        (0..n).map(|i| ((i * 7) % 11) as f64 - 5.0).collect()
    }

    /// CG (identity preconditioner) on `a` x = `b` from zero; the report and x.
    fn unpreconditioned(
        a: &CsrMatrix,
        b: &[f64],
        options: &PcgOptions,
    ) -> FemResult<(PcgReport, Vec<f64>)> {
        let mut x = vec![0.0; b.len()];
        let report = pcg(
            |v, o| a.mul_vec(v, o),
            |r, z| {
                z.copy_from_slice(r);
                Ok(())
            },
            b,
            &mut x,
            &mut PcgWorkspace::new(b.len()),
            options,
        )?;
        Ok((report, x))
    }

    #[test]
    fn pcg_meets_its_energy_error_rule() {
        let n = 200;
        let a = CsrMatrix::from_symmetric(&laplacian(n)).unwrap();
        let b = test_rhs(n);
        let options = PcgOptions {
            relative_energy_error: 1e-8,
            max_iterations: 1000,
            error_delay: 4,
            contraction_limit: DEFAULT_CONTRACTION_LIMIT,
        };
        let (report, x) = unpreconditioned(&a, &b, &options).unwrap();
        let mut ax = vec![0.0; n];
        a.mul_vec(&x, &mut ax);
        let res: f64 = ax
            .iter()
            .zip(&b)
            .map(|(p, q)| (p - q).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            res < 1e-6 * dot(&b, &b).sqrt(),
            "residual of CG on the 1D Laplacian: {res}"
        );
        assert_eq!(
            report.residual_history.len(),
            report.iterations,
            "one residual per iteration"
        );
    }

    /// Solves the shifted 1D Laplacian (2 + shift on the diagonal: steady contraction) to
    /// `tolerance` with the given contraction limit; returns the iterations and the solution.
    fn shifted_solve(tolerance: f64, contraction_limit: f64) -> (usize, Vec<f64>, CsrMatrix) {
        let n = 300;
        let lap = laplacian(n);
        let mut values = lap.values().to_vec();
        for j in 0..n {
            values[lap.col_ptr()[j + 1] - 1] += 0.6;
        }
        let shifted = SymmetricMatrix::from_upper_parts(
            n,
            lap.col_ptr().to_vec(),
            lap.row_idx().to_vec(),
            values,
        )
        .unwrap();
        let a = CsrMatrix::from_symmetric(&shifted).unwrap();
        let options = PcgOptions {
            relative_energy_error: tolerance,
            max_iterations: 1000,
            error_delay: DEFAULT_ERROR_DELAY,
            contraction_limit,
        };
        let (report, x) = unpreconditioned(&a, &test_rhs(n), &options).unwrap();
        (report.iterations, x, a)
    }

    #[test]
    fn geometric_tail_rule_stops_earlier_within_its_tolerance() {
        let tolerance = 1e-6;
        let (tail_iterations, x, a) = shifted_solve(tolerance, DEFAULT_CONTRACTION_LIMIT);
        let (bound_iterations, _, _) = shifted_solve(tolerance, 0.0);
        let (_, exact, _) = shifted_solve(1e-15, 0.0);
        assert!(
            tail_iterations < bound_iterations,
            "iterations with the tail rule {tail_iterations} vs the delayed bound alone {bound_iterations}"
        );
        let e: Vec<f64> = x.iter().zip(&exact).map(|(u, v)| u - v).collect();
        let (mut ae, mut ax) = (vec![0.0; e.len()], vec![0.0; e.len()]);
        a.mul_vec(&e, &mut ae);
        a.mul_vec(&exact, &mut ax);
        let relative = (dot(&e, &ae) / dot(&exact, &ax)).sqrt();
        assert!(
            relative <= 2.0 * tolerance,
            "relative energy error {relative:.3e} of the iterate returned by the tail rule (tolerance {tolerance:.0e})"
        );
    }

    #[test]
    fn pcg_names_the_iteration_limit_when_it_stalls() {
        let n = 200;
        let a = CsrMatrix::from_symmetric(&laplacian(n)).unwrap();
        let b = vec![1.0; n];
        let options = PcgOptions {
            relative_energy_error: 1e-12,
            max_iterations: 5,
            error_delay: 4,
            contraction_limit: DEFAULT_CONTRACTION_LIMIT,
        };
        let err = unpreconditioned(&a, &b, &options).unwrap_err();
        match err {
            FemError::IterativeNotConverged {
                iterations, rule, ..
            } => {
                assert_eq!(iterations, 5, "iterations at the limit");
                assert!(rule.contains("iteration limit"), "rule named: {rule}");
            }
            other => panic!("expected IterativeNotConverged, got {other}"),
        }
    }
}
