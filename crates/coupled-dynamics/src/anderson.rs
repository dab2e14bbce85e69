//! Anderson acceleration of a fixed point z = G(z) (type II, with mixing β): the accelerator
//! the energy-conserving wave's joint map of tips and amplitude profile uses
//! (`crate::attenuation`, `CoupledModel::steady_profiled`).
//!
//! Source: H. F. Walker and P. Ni, "Anderson acceleration for fixed-point iterations", SIAM J.
//! Numer. Anal. 49 (2011) 1715–1735. Valid for a contractive or mildly expansive G near its
//! fixed point; the restart on a growing residual is a safeguard, not a line search.

use nalgebra::{DMatrix, DVector};

/// Anderson acceleration (type II, Walker & Ni, SIAM J. Numer. Anal. 49 (2011) 1715, with
/// mixing β) of a fixed point z = G(z): with the last `DEPTH` differences of iterates ΔZ and
/// of residuals ΔR (r = G(z) − z), γ = argmin ‖r − ΔR γ‖ and z⁺ = z + β r − (ΔZ + β ΔR) γ.
/// Depth 0 (no history yet, or a least-squares failure) is plain relaxation z⁺ = z + β r. The
/// history restarts when the residual grows (a safeguard, not a line search). The caller keeps
/// its unknowns in their ranges (an amplitude ≥ 0).
#[derive(Clone)]
pub(crate) struct Anderson {
    beta: f64,
    last: Option<(Vec<f64>, Vec<f64>)>,
    d_alpha: Vec<Vec<f64>>,
    d_residual: Vec<Vec<f64>>,
}

impl Anderson {
    const DEPTH: usize = 5;

    pub(crate) fn new(beta: f64) -> Self {
        Self {
            beta,
            last: None,
            d_alpha: Vec::new(),
            d_residual: Vec::new(),
        }
    }

    /// The differences without the last iterate: the start of a neighbouring problem whose
    /// Jacobian is close (the next speed), whose first residual is not comparable.
    pub(crate) fn carried(&self) -> Self {
        Self {
            last: None,
            ..self.clone()
        }
    }

    /// The next iterate from `alpha` (z) and its `residual` G(z) − z.
    pub(crate) fn next(&mut self, alpha: &[f64], residual: &[f64]) -> Vec<f64> {
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if let Some((a0, r0)) = self.last.take() {
            if a0.len() != alpha.len() || norm(residual) > norm(&r0) {
                self.d_alpha.clear();
                self.d_residual.clear();
            } else {
                self.d_alpha
                    .push(alpha.iter().zip(&a0).map(|(a, b)| a - b).collect());
                self.d_residual
                    .push(residual.iter().zip(&r0).map(|(a, b)| a - b).collect());
                if self.d_alpha.len() > Self::DEPTH {
                    self.d_alpha.remove(0);
                    self.d_residual.remove(0);
                }
            }
        }
        self.last = Some((alpha.to_vec(), residual.to_vec()));
        let mut next: Vec<f64> = alpha
            .iter()
            .zip(residual)
            .map(|(a, r)| a + self.beta * r)
            .collect();
        if let Some(gamma) = self.coefficients(residual) {
            for (k, g) in gamma.iter().enumerate() {
                for (i, x) in next.iter_mut().enumerate() {
                    *x -= g * (self.d_alpha[k][i] + self.beta * self.d_residual[k][i]);
                }
            }
        }
        next
    }

    /// γ of the least-squares problem (SVD, rank-revealing: near-dependent differences are
    /// dropped at 1e-12 of the largest singular value); `None` without history.
    fn coefficients(&self, residual: &[f64]) -> Option<Vec<f64>> {
        let depth = self.d_residual.len();
        if depth == 0 {
            return None;
        }
        let n = residual.len();
        let dr = DMatrix::from_fn(n, depth, |i, k| self.d_residual[k][i]);
        let svd = dr.svd(true, true);
        let cutoff = 1e-12 * svd.singular_values.max();
        let gamma = svd
            .solve(&DVector::from_column_slice(residual), cutoff)
            .ok()?;
        gamma
            .iter()
            .all(|g| g.is_finite())
            .then(|| gamma.iter().copied().collect())
    }
}
