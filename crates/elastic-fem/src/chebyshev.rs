//! Chebyshev polynomial smoother in D⁻¹ A (D = diag A) and the Lanczos estimate of
//! λ_max(D⁻¹ A) that sets its damped interval [λ_max / ratio, [`CHEBYSHEV_UPPER_SAFETY`] λ_max].
//!
//! Source: Adams, Brezina, Hu & Tuminaro 2003 ("Parallel multigrid smoothing: polynomial versus
//! Gauss–Seidel", JCP 188:593) for the smoother; Golub & Van Loan, Matrix Computations, 4th ed.,
//! §10.1 for the Lanczos estimate. Valid for symmetric A with a positive diagonal (refused
//! otherwise); the smoother is then a fixed symmetric operator, as a CG preconditioner needs.
//!
//! A leaf of the solver modules: it depends only on the sparse kernels and the error type, so
//! both the p-multigrid ([`crate::iterative`]) and the SA-AMG levels ([`crate::amg`]) use it
//! without depending on each other's internals.

use rayon::prelude::*;

use crate::error::{FemError, FemResult};
use crate::sparse::CsrMatrix;
use crate::sparse::csr::{ROW_BLOCK, SinglePrecision};
use crate::sparse::pcg::dot;

/// Factor applied to the Lanczos estimate of λ_max (which is a lower bound).
/// Dimensionless; default 1.1.
pub const CHEBYSHEV_UPPER_SAFETY: f64 = 1.1;

/// Lanczos steps for λ_max(D⁻¹ K_red) (one product with K_red each). On the punch meshes 12
/// steps come within 1.3 % (55k unknowns) and 2.5 % (350k) of λ_max, where 12 power iterations
/// (the earlier estimate) fell 12–14 % short, so that the upper end of the damped interval lay
/// below λ_max: Chebyshev then amplifies the top modes, and an estimate 26 % short made PCG
/// take 254 iterations instead of 10 (validation/fem-peers/README.md). Default 12.
pub const LANCZOS_STEPS: usize = 12;

/// Deterministic non-smooth start vector of the eigenvalue estimates.
fn start_vector(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 1.0 + ((i * 7919) % 13) as f64 / 13.0)
        .collect()
}

/// λ_max(D⁻¹ A) as the largest Ritz value of `steps` Lanczos steps on the pencil (A, D), i.e.
/// on D⁻¹ A in the D inner product (a lower bound; Golub & Van Loan, Matrix Computations,
/// 4th ed., §10.1: the extreme Ritz values converge much faster than the power method). No
/// re-orthogonalisation: only the largest Ritz value is used, which loss of orthogonality does
/// not spoil (it may appear twice).
fn lanczos_lambda_max(product: impl Fn(&[f64], &mut [f64]), inv_diag: &[f64], steps: usize) -> f64 {
    let n = inv_diag.len();
    // (x, y)_D with the fixed summation order of `dot` (same bits for any thread count).
    let d_dot = |x: &[f64], y: &[f64]| -> f64 {
        let partial: Vec<f64> = x
            .par_chunks(ROW_BLOCK)
            .zip(y.par_chunks(ROW_BLOCK))
            .zip(inv_diag.par_chunks(ROW_BLOCK))
            .map(|((x, y), d)| x.iter().zip(y).zip(d).map(|((a, b), d)| a * b / d).sum())
            .collect();
        partial.iter().sum()
    };
    let mut v = start_vector(n);
    let norm = d_dot(&v, &v).sqrt();
    v.iter_mut().for_each(|x| *x /= norm);
    let mut v_prev = vec![0.0; n];
    let mut w = vec![0.0; n];
    let (mut alpha, mut beta) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
    for _ in 0..steps {
        product(&v, &mut w);
        let alpha_j = dot(&w, &v);
        let beta_prev = beta.last().copied().unwrap_or(0.0);
        w.par_iter_mut()
            .zip(inv_diag)
            .zip(v.par_iter().zip(&v_prev))
            .for_each(|((x, d), (vj, vp))| *x = *x * d - alpha_j * vj - beta_prev * vp);
        alpha.push(alpha_j);
        let beta_j = d_dot(&w, &w).sqrt();
        // Stop on an invariant subspace (β ≈ 0) or a NaN.
        if beta_j.partial_cmp(&(1e-12 * alpha_j.abs())) != Some(std::cmp::Ordering::Greater) {
            break;
        }
        beta.push(beta_j);
        std::mem::swap(&mut v_prev, &mut v);
        w.par_iter_mut().for_each(|x| *x /= beta_j);
        std::mem::swap(&mut v, &mut w);
    }
    let k = alpha.len();
    let t = nalgebra::DMatrix::from_fn(k, k, |i, j| match i.abs_diff(j) {
        0 => alpha[i],
        1 => beta[i.min(j)],
        _ => 0.0,
    });
    t.symmetric_eigenvalues().max()
}

/// Chebyshev smoothing data: D⁻¹, A in single precision, and the eigenvalue interval of D⁻¹ A.
///
/// The smoother's products use A's values rounded to f32 ([`SinglePrecision`]; sums in f64): they
/// are memory bound, and single-precision values move 8 instead of 12 bytes per entry. The
/// smoother is then a fixed symmetric operator of Ã = fl32(A) (‖Ã − A‖ ≤ 2⁻²⁴‖A‖ entrywise), all
/// a preconditioner must be; CG's own products and residuals stay in double precision, so the
/// solution's accuracy is unchanged.
#[derive(Debug, Clone)]
pub(crate) struct Chebyshev {
    inv_diag: Vec<f64>,
    single: SinglePrecision,
    lambda_min: f64,
    lambda_max: f64,
    degree: usize,
}

impl Chebyshev {
    /// Smoother of `degree` on [λ_max/`interval_ratio`, λ_max] of D⁻¹ A.
    pub(crate) fn new(a: &CsrMatrix, degree: usize, interval_ratio: f64) -> FemResult<Self> {
        let diag = a.diagonal();
        if let Some(i) = diag.iter().position(|&d| d.is_nan() || d <= 0.0) {
            return Err(FemError::NotPositiveDefinite {
                column: i,
                pivot_ratio: 0.0,
                minimum: 0.0,
                location: " (non-positive diagonal entry, seen by the multigrid smoother)".into(),
            });
        }
        let inv_diag: Vec<f64> = diag.iter().map(|d| 1.0 / d).collect();
        let single = a.single_precision();
        let lambda = lanczos_lambda_max(
            |x, y| a.mul_vec_single(&single, x, y),
            &inv_diag,
            LANCZOS_STEPS,
        );
        let lambda_max = CHEBYSHEV_UPPER_SAFETY * lambda;
        Ok(Self {
            inv_diag,
            single,
            lambda_min: lambda_max / interval_ratio,
            lambda_max,
            degree,
        })
    }

    /// The Lanczos estimate of λ_max(D⁻¹ A) (without the safety factor).
    pub(crate) fn lambda_max_estimate(&self) -> f64 {
        self.lambda_max / CHEBYSHEV_UPPER_SAFETY
    }

    /// Upper end of the damped interval (safety factor included).
    pub(crate) fn lambda_max(&self) -> f64 {
        self.lambda_max
    }

    /// D⁻¹.
    pub(crate) fn inv_diag(&self) -> &[f64] {
        &self.inv_diag
    }

    /// r = b − Ã x with the smoother's single-precision A (e.g. the residual a V-cycle restricts).
    pub(crate) fn residual(&self, a: &CsrMatrix, b: &[f64], x: &[f64], r: &mut [f64]) {
        a.residual_single(&self.single, b, x, r);
    }

    /// x ← x + Chebyshev(b − Ã x); `x_is_zero` saves the first product. Work vectors r, d.
    pub(crate) fn smooth(
        &self,
        a: &CsrMatrix,
        b: &[f64],
        x: &mut [f64],
        x_is_zero: bool,
        r: &mut [f64],
        d: &mut [f64],
    ) {
        let theta = 0.5 * (self.lambda_max + self.lambda_min);
        let delta = 0.5 * (self.lambda_max - self.lambda_min);
        let sigma = theta / delta;
        let mut rho = 1.0 / sigma;
        if x_is_zero {
            r.copy_from_slice(b);
        } else {
            self.residual(a, b, x, r);
        }
        let inv = &self.inv_diag;
        d.par_chunks_mut(ROW_BLOCK)
            .enumerate()
            .for_each(|(blk, db)| {
                let base = blk * ROW_BLOCK;
                for (k, di) in db.iter_mut().enumerate() {
                    *di = inv[base + k] * r[base + k] / theta;
                }
            });
        for step in 0..self.degree {
            x.par_iter_mut()
                .zip(d.par_iter())
                .for_each(|(xi, di)| *xi += di);
            if step + 1 == self.degree {
                break;
            }
            self.residual(a, b, x, r);
            let rho_new = 1.0 / (2.0 * sigma - rho);
            let (c1, c2) = (rho_new * rho, 2.0 * rho_new / delta);
            d.par_chunks_mut(ROW_BLOCK)
                .enumerate()
                .for_each(|(blk, db)| {
                    let base = blk * ROW_BLOCK;
                    for (k, di) in db.iter_mut().enumerate() {
                        *di = c1 * *di + c2 * inv[base + k] * r[base + k];
                    }
                });
            rho = rho_new;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sparse::SymmetricMatrix;

    /// Tridiagonal A (n × n) with a_ii = 2 + i/n, a_i,i+1 = −1: SPD, non-uniform diagonal.
    fn chain(n: usize) -> CsrMatrix {
        let (mut cp, mut ri, mut v) = (vec![0usize], Vec::new(), Vec::new());
        for j in 0..n {
            if j > 0 {
                ri.push(j - 1);
                v.push(-1.0);
            }
            ri.push(j);
            v.push(2.0 + j as f64 / n as f64);
            cp.push(ri.len());
        }
        CsrMatrix::from_symmetric(&SymmetricMatrix::from_upper_parts(n, cp, ri, v).unwrap())
            .unwrap()
    }

    #[test]
    fn lanczos_estimate_is_a_close_lower_bound_of_lambda_max() {
        let n = 300;
        let a = chain(n);
        let diag = a.diagonal();
        let inv_diag: Vec<f64> = diag.iter().map(|d| 1.0 / d).collect();
        // Exact λ_max(D⁻¹ A) = λ_max(D^-½ A D^-½) from the dense symmetric eigenproblem.
        let scaled = nalgebra::DMatrix::from_fn(n, n, |i, j| {
            let aij = a.row(i).find(|e| e.0 == j).map_or(0.0, |e| e.1);
            aij / (diag[i] * diag[j]).sqrt()
        });
        let exact = scaled.symmetric_eigenvalues().max();
        let estimate = lanczos_lambda_max(|x, y| a.mul_vec(x, y), &inv_diag, LANCZOS_STEPS);
        assert!(
            estimate <= exact * (1.0 + 1e-12),
            "{estimate} above λ_max {exact}"
        );
        assert!(
            estimate >= 0.97 * exact,
            "{LANCZOS_STEPS} Lanczos steps give {estimate}, λ_max = {exact}"
        );
        // The safety factor then puts the smoother's upper end above λ_max.
        assert!(CHEBYSHEV_UPPER_SAFETY * estimate > exact);
    }
}
