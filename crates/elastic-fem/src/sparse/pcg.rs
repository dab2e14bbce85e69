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
//! bound survives rounding). The iteration stops when ε_k ≤ tolerance and returns x_{k+d}, which
//! is more accurate than x_k. With a multigrid preconditioner the contraction per step is
//! ≈ 0.1–0.3, so d = [`DEFAULT_ERROR_DELAY`] steps make the bound tight within a factor ≈ 1.5.
//!
//! **Failure.** More than `max_iterations` steps, pᵀ A p ≤ 0 (A or M not SPD) or a non-finite
//! value end in [`FemError::IterativeNotConverged`], naming the rule, the iterations and the
//! estimate reached.

use rayon::prelude::*;

use super::csr::ROW_BLOCK;
use crate::error::{FemError, FemResult};

/// Delay d of the energy-error estimate (iterations). Default 4.
pub const DEFAULT_ERROR_DELAY: usize = 4;

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
    /// Final estimate of the relative energy-norm error (upper side: of the iterate d steps
    /// before the returned one).
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
        let k = report.energy_increments.len();
        if k >= d {
            let tail: f64 = report.energy_increments[k - d..].iter().sum();
            report.relative_energy_error = (tail / energy).sqrt();
            if report.relative_energy_error <= options.relative_energy_error {
                return Ok(report);
            }
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

    #[test]
    fn pcg_meets_its_energy_error_rule() {
        let n = 200;
        let a = CsrMatrix::from_symmetric(&laplacian(n)).unwrap();
        let b: Vec<f64> = (0..n).map(|i| ((i * 7) % 11) as f64 - 5.0).collect();
        let mut x = vec![0.0; n];
        let options = PcgOptions {
            relative_energy_error: 1e-8,
            max_iterations: 1000,
            error_delay: 4,
        };
        let report = pcg(
            |v, o| a.mul_vec(v, o),
            |r, z| {
                z.copy_from_slice(r);
                Ok(())
            },
            &b,
            &mut x,
            &mut PcgWorkspace::new(n),
            &options,
        )
        .unwrap();
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

    #[test]
    fn pcg_names_the_iteration_limit_when_it_stalls() {
        let n = 200;
        let a = CsrMatrix::from_symmetric(&laplacian(n)).unwrap();
        let b = vec![1.0; n];
        let options = PcgOptions {
            relative_energy_error: 1e-12,
            max_iterations: 5,
            error_delay: 4,
        };
        let err = pcg(
            |v, o| a.mul_vec(v, o),
            |r, z| {
                z.copy_from_slice(r);
                Ok(())
            },
            &b,
            &mut vec![0.0; n],
            &mut PcgWorkspace::new(n),
            &options,
        )
        .unwrap_err();
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
