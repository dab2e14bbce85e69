//! Sparse Cholesky factorisation A = L Lᵀ (faer), symbolic and numeric phases kept apart.
//!
//! [`SymbolicCholesky::analyze`] computes the fill-reducing ordering and the structure of L once
//! per sparsity pattern; [`SymbolicCholesky::factor`] / [`NumericCholesky::refactor`] compute
//! the values for any matrix with that pattern (e.g. a contact solver that changes penalty
//! springs on the diagonal every iteration). faer picks simplicial or supernodal storage.

use std::sync::Arc;

use faer::Par;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
    supernodal::SupernodalLltRef,
};
use faer::{Side, Spec};

use super::matrix::{SymmetricMatrix, fingerprint};
use super::ordering::{Ordering, metis_nested_dissection};
use crate::error::{FemError, FemResult};

/// Smallest accepted ratio L_jj² / A_jj (pivot over original diagonal) in a numeric
/// factorisation. Smaller pivots mean the matrix is singular to working precision (e.g. an
/// unconstrained rigid-body mode) and the factorisation is rejected. Dimensionless; default 1e-13.
pub const DEFAULT_MIN_PIVOT_RATIO: f64 = 1e-13;

/// Options of the numeric factorisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FactorOptions {
    /// See [`DEFAULT_MIN_PIVOT_RATIO`].
    pub min_pivot_ratio: f64,
    /// Threads for faer (`0` = all rayon threads, `1` = sequential).
    pub threads: usize,
}

impl Default for FactorOptions {
    fn default() -> Self {
        Self {
            min_pivot_ratio: DEFAULT_MIN_PIVOT_RATIO,
            threads: 0,
        }
    }
}

impl FactorOptions {
    pub(crate) fn par(&self) -> Par {
        if self.threads == 1 {
            Par::Seq
        } else {
            Par::rayon(self.threads)
        }
    }
}

/// faer's symbolic parameters used for every analysis (its defaults: supernodal when the flop
/// ratio says so, relaxed amalgamation (4, 1.0), (16, 0.8), (48, 0.1), (∞, 0.05)). Wider
/// relaxations ((8, 1.0), (32, 0.5); (4, 1.0), …, (48, 0.2), (∞, 0.1)) and a narrower one ((2, 1.0),
/// (8, 0.5), (∞, 0.02)) changed the numeric factorisation of the default strip by < 10 % (within
/// the noise of a loaded machine) while changing its bits, so the defaults stay.
pub(crate) fn symbolic_params() -> CholeskySymbolicParams<'static> {
    CholeskySymbolicParams::default()
}

#[derive(Debug)]
struct SymbolicInner {
    faer: faer::sparse::linalg::cholesky::SymbolicCholesky<usize>,
    dim: usize,
    nnz_upper: usize,
    pattern_fingerprint: u64,
    ordering_used: Ordering,
}

/// Symbolic Cholesky analysis of one sparsity pattern: ordering + structure of L. Cheap to
/// clone (shared).
#[derive(Debug, Clone)]
pub struct SymbolicCholesky {
    inner: Arc<SymbolicInner>,
}

impl SymbolicCholesky {
    /// Analyses the pattern of `matrix` (its values are ignored) with the given ordering.
    /// `Ordering::Metis` silently falls back to AMD when METIS is unusable; see
    /// [`Self::ordering_used`].
    pub fn analyze(matrix: &SymmetricMatrix, ordering: Ordering) -> FemResult<Self> {
        let dim = matrix.dim();
        let metis = match ordering {
            Ordering::Metis => metis_nested_dissection(matrix),
            _ => None,
        };
        let ordering_used = match (ordering, &metis) {
            (Ordering::Metis, None) => Ordering::Amd,
            (o, _) => o,
        };
        let symmetric_ordering = match (&metis, ordering_used) {
            (Some(p), _) => {
                SymmetricOrdering::Custom(PermRef::new_checked(&p.forward, &p.inverse, dim))
            }
            (None, Ordering::Natural) => SymmetricOrdering::Identity,
            (None, _) => SymmetricOrdering::Amd,
        };
        let faer = factorize_symbolic_cholesky(
            matrix.upper().symbolic(),
            Side::Upper,
            symmetric_ordering,
            symbolic_params(),
        )
        .map_err(|e| FemError::SparseBackend(format!("symbolic Cholesky failed: {e:?}")))?;
        Ok(Self {
            inner: Arc::new(SymbolicInner {
                faer,
                dim,
                nnz_upper: matrix.nnz_upper(),
                pattern_fingerprint: matrix.pattern_fingerprint(),
                ordering_used,
            }),
        })
    }

    /// Matrix dimension.
    pub fn dim(&self) -> usize {
        self.inner.dim
    }

    /// Number of stored values of L (memory of a numeric factor = 8 bytes × this).
    pub fn factor_nnz(&self) -> usize {
        self.inner.faer.len_val()
    }

    /// Floating-point operations of one numeric factorisation, Σ_j c_j² over the
    /// below-diagonal column counts c_j of L (the classical count, George & Liu 1981), from the
    /// symbolic structure alone. Feeds the direct/iterative cost model.
    pub fn factor_flops(&self) -> f64 {
        let sum_sq = |lo: usize, hi: usize| -> f64 {
            // Σ_{t=lo}^{hi-1} t², in f64.
            let f = |t: f64| (t - 1.0) * t * (2.0 * t - 1.0) / 6.0;
            f(hi as f64) - f(lo as f64)
        };
        match self.inner.faer.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => s
                .col_ptr()
                .windows(2)
                .map(|w| {
                    let c = (w[1] - w[0]).saturating_sub(1) as f64;
                    c * c
                })
                .sum(),
            SymbolicCholeskyRaw::Supernodal(s) => (0..s.n_supernodes())
                .map(|k| {
                    let width = s.supernode_end()[k] - s.supernode_begin()[k];
                    let below = s.col_ptr_for_row_idx()[k + 1] - s.col_ptr_for_row_idx()[k];
                    sum_sq(below, below + width)
                })
                .sum(),
        }
    }

    /// Whether faer chose the supernodal (blocked) variant.
    pub fn is_supernodal(&self) -> bool {
        matches!(self.inner.faer.raw(), SymbolicCholeskyRaw::Supernodal(_))
    }

    /// The ordering actually used (METIS may have fallen back to AMD).
    pub fn ordering_used(&self) -> Ordering {
        self.inner.ordering_used
    }

    /// The fill-reducing permutation (`forward[new] = old`), if any.
    pub fn permutation(&self) -> Option<Vec<usize>> {
        self.inner.faer.perm().map(|p| p.arrays().0.to_vec())
    }

    pub(crate) fn faer(&self) -> &faer::sparse::linalg::cholesky::SymbolicCholesky<usize> {
        &self.inner.faer
    }

    fn check_pattern(&self, matrix: &SymmetricMatrix) -> FemResult<()> {
        if matrix.dim() != self.inner.dim || matrix.nnz_upper() != self.inner.nnz_upper {
            return Err(FemError::PatternMismatch {
                detail: format!(
                    "analysed dim {} with {} entries, got dim {} with {} entries",
                    self.inner.dim,
                    self.inner.nnz_upper,
                    matrix.dim(),
                    matrix.nnz_upper()
                ),
            });
        }
        if fingerprint(matrix.dim(), matrix.col_ptr(), matrix.row_idx())
            != self.inner.pattern_fingerprint
        {
            return Err(FemError::PatternMismatch {
                detail: "same size, different row indices".into(),
            });
        }
        Ok(())
    }

    /// Numeric factorisation of `matrix` (same pattern as analysed) with default options.
    pub fn factor(&self, matrix: &SymmetricMatrix) -> FemResult<NumericCholesky> {
        self.factor_with(matrix, FactorOptions::default())
    }

    /// Numeric factorisation with explicit options.
    pub fn factor_with(
        &self,
        matrix: &SymmetricMatrix,
        options: FactorOptions,
    ) -> FemResult<NumericCholesky> {
        let mut numeric = NumericCholesky {
            symbolic: self.clone(),
            values: vec![0.0; self.factor_nnz()],
            options,
        };
        numeric.refactor(matrix)?;
        Ok(numeric)
    }
}

/// Numeric Cholesky factor L (values for a [`SymbolicCholesky`] structure).
#[derive(Debug, Clone)]
pub struct NumericCholesky {
    pub(crate) symbolic: SymbolicCholesky,
    pub(crate) values: Vec<f64>,
    pub(crate) options: FactorOptions,
}

impl NumericCholesky {
    /// The symbolic structure this factor uses.
    pub fn symbolic(&self) -> &SymbolicCholesky {
        &self.symbolic
    }

    /// Recomputes the factor for new values with the same pattern, reusing the storage of L.
    /// Fails with [`FemError::NotPositiveDefinite`] on a non-positive or negligible pivot
    /// (column reported in the matrix's own numbering).
    pub fn refactor(&mut self, matrix: &SymmetricMatrix) -> FemResult<()> {
        let symbolic = self.symbolic.clone();
        symbolic.check_pattern(matrix)?;
        if let Some((j, _)) = matrix
            .values()
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite())
        {
            return Err(FemError::SparseBackend(format!(
                "matrix value #{j} is not finite"
            )));
        }
        let faer_symbolic = symbolic.faer();
        let par = self.options.par();
        let params = Spec::default();
        let req = faer_symbolic.factorize_numeric_llt_scratch::<f64>(par, params);
        let mut mem = MemBuffer::try_new(req).map_err(|_| {
            FemError::SparseBackend("out of memory for factorisation workspace".into())
        })?;
        let stack = MemStack::new(&mut mem);
        let result = faer_symbolic.factorize_numeric_llt(
            &mut self.values,
            matrix.upper(),
            Side::Upper,
            LltRegularization::default(),
            par,
            stack,
            params,
        );
        let forward = faer_symbolic.perm().map(|p| p.arrays().0.to_vec());
        let to_original = |permuted: usize| {
            forward
                .as_ref()
                .map_or(permuted, |f| f[permuted.min(f.len() - 1)])
        };
        if let Err(LltError::NonPositivePivot { index }) = result {
            // faer 0.24.4 reports a 1-based column from its simplicial kernel and a 0-based one
            // from its supernodal kernel.
            let permuted = match faer_symbolic.raw() {
                SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
                SymbolicCholeskyRaw::Supernodal(_) => index,
            };
            return Err(FemError::NotPositiveDefinite {
                column: to_original(permuted.min(symbolic.dim().saturating_sub(1))),
                pivot_ratio: 0.0,
                minimum: self.options.min_pivot_ratio,
                location: String::new(),
            });
        }
        // Pivot check: L_jj² / A_jj over all columns (permuted order).
        let diag = matrix.diagonal();
        let l_diag = self.factor_diagonal();
        let mut worst = (f64::INFINITY, 0usize);
        for (jp, l) in l_diag.iter().enumerate() {
            let a = diag[to_original(jp)];
            let ratio = l * l / a;
            if ratio < worst.0 {
                worst = (ratio, jp);
            }
        }
        if worst.0 < self.options.min_pivot_ratio {
            return Err(FemError::NotPositiveDefinite {
                column: to_original(worst.1),
                pivot_ratio: worst.0,
                minimum: self.options.min_pivot_ratio,
                location: String::new(),
            });
        }
        Ok(())
    }

    /// Diagonal of L in the permuted order.
    fn factor_diagonal(&self) -> Vec<f64> {
        let n = self.symbolic.dim();
        match self.symbolic.faer().raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                (0..n).map(|j| self.values[s.col_ptr()[j]]).collect()
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let l = SupernodalLltRef::new(s, &self.values);
                let mut d = Vec::with_capacity(n);
                for k in 0..s.n_supernodes() {
                    let node = l.supernode(k);
                    let val = node.val();
                    let width = s.supernode_end()[k] - s.supernode_begin()[k];
                    for j in 0..width {
                        d.push(val[(j, j)]);
                    }
                }
                d
            }
        }
    }

    /// Bytes held by the numeric factor.
    pub fn memory_bytes(&self) -> usize {
        self.values.len() * std::mem::size_of::<f64>()
    }
}

// Condensation onto unknowns ordered last (a child module: it builds `SymbolicCholesky` values).
#[path = "trailing.rs"]
mod trailing;
pub use trailing::fill_reducing_order;
