//! Condensation onto a few unknowns straight from the factor: order them last.
//!
//! With the unknowns of interest m eliminated last, P K Pᵀ = [[A, B], [Bᵀ, D]] factors as
//! L = [[L_A, 0], [L_B, L_m]] with L_m L_mᵀ = D − Bᵀ A⁻¹ B, the Schur complement S on m (Golub &
//! Van Loan 2013, §4.2.10). Its inverse is the block of K⁻¹ on m — the condensed compliance —
//! so it costs one dense n × n inversion after the factorisation instead of n sparse solves
//! (for the 100 post tips of the default strip: ≈ 7 s of solves replaced by < 1 ms).
//!
//! Range: any SPD K; the unknowns m must be distinct. Moving n unknowns behind a nested
//! dissection ordering adds fill only along their elimination-tree paths (a few thousand
//! entries per unknown on the strip meshes; measured with the factor size in static-contact's
//! README). Declared as a child of `factor` (it builds a `SymbolicCholesky` from a custom
//! permutation); a separate file so that the merge with other work on `factor.rs` stays trivial.

use std::sync::Arc;

use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::{Side, sparse::linalg::amd};
use nalgebra::DMatrix;

use super::super::ordering::metis_nested_dissection;
use super::{NumericCholesky, Ordering, SymbolicCholesky, SymbolicInner, SymmetricMatrix};
use crate::error::{FemError, FemResult};

/// Fill-reducing permutation (forward: new → old) of `matrix` by `ordering`, with the Ordering
/// actually used (METIS falls back to AMD if it refuses the graph). It depends on the pattern
/// only, so a caller may store it (e.g. beside a cached mesh) and pass it to
/// [`SymbolicCholesky::analyze_with_last_ordered`] later.
pub fn fill_reducing_order(
    matrix: &SymmetricMatrix,
    ordering: Ordering,
) -> FemResult<(Vec<usize>, Ordering)> {
    let n = matrix.dim();
    if ordering == Ordering::Metis
        && let Some(p) = metis_nested_dissection(matrix)
    {
        return Ok((p.forward, Ordering::Metis));
    }
    if ordering == Ordering::Natural {
        return Ok(((0..n).collect(), Ordering::Natural));
    }
    let (cp, ri) = (matrix.col_ptr(), matrix.row_idx());
    let mut forward = vec![0usize; n];
    let mut inverse = vec![0usize; n];
    let mut mem = faer::dyn_stack::MemBuffer::try_new(amd::order_scratch::<usize>(n, cp[n]))
        .map_err(|_| FemError::SparseBackend("out of memory for the AMD ordering".into()))?;
    let symbolic = faer::sparse::SymbolicSparseColMatRef::new_checked(n, n, cp, None, ri);
    amd::order(
        &mut forward,
        &mut inverse,
        symbolic,
        amd::Control::default(),
        faer::dyn_stack::MemStack::new(&mut mem),
    )
    .map_err(|e| FemError::SparseBackend(format!("AMD ordering failed: {e:?}")))?;
    Ok((forward, Ordering::Amd))
}

/// Marks the unknowns `last`, refusing repeated or out-of-range ones.
fn last_mask(dim: usize, last: &[usize]) -> FemResult<Vec<bool>> {
    let mut is_last = vec![false; dim];
    for &j in last {
        if j >= dim || is_last[j] {
            return Err(FemError::SparseBackend(format!(
                "unknown {j} to be eliminated last is out of range (dim {dim}) or repeated"
            )));
        }
        is_last[j] = true;
    }
    Ok(is_last)
}

impl SymbolicCholesky {
    /// [`SymbolicCholesky::analyze`] with the unknowns `last` (distinct, in this order)
    /// eliminated after all others, so that [`NumericCholesky::trailing_inverse`] gives the
    /// block of K⁻¹ on them. The others keep the relative order of `ordering`.
    pub fn analyze_with_last(
        matrix: &SymmetricMatrix,
        ordering: Ordering,
        last: &[usize],
    ) -> FemResult<Self> {
        last_mask(matrix.dim(), last)?;
        let (base, ordering_used) = fill_reducing_order(matrix, ordering)?;
        Self::analyze_with_last_ordered(matrix, &base, ordering_used, last)
    }

    /// [`Self::analyze_with_last`] with the fill-reducing permutation `base` (forward: new →
    /// old, e.g. a stored [`fill_reducing_order`]) instead of computing one; `ordering_used`
    /// is reported by [`Self::ordering_used`]. `base` must be a permutation of 0..dim.
    pub fn analyze_with_last_ordered(
        matrix: &SymmetricMatrix,
        base: &[usize],
        ordering_used: Ordering,
        last: &[usize],
    ) -> FemResult<Self> {
        let dim = matrix.dim();
        let is_last = last_mask(dim, last)?;
        let mut seen = vec![false; dim];
        let repeated = |j: usize| j >= dim || std::mem::replace(&mut seen[j], true);
        if base.len() != dim || base.iter().copied().any(repeated) {
            return Err(FemError::SparseBackend(format!(
                "the given ordering is not a permutation of the {dim} unknowns"
            )));
        }
        let mut forward: Vec<usize> = base.iter().copied().filter(|&j| !is_last[j]).collect();
        forward.extend_from_slice(last);
        let mut inverse = vec![0usize; dim];
        for (new, &old) in forward.iter().enumerate() {
            inverse[old] = new;
        }
        let faer = factorize_symbolic_cholesky(
            matrix.upper().symbolic(),
            Side::Upper,
            SymmetricOrdering::Custom(PermRef::new_checked(&forward, &inverse, dim)),
            super::symbolic_params(),
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
}

impl NumericCholesky {
    /// The trailing n × n block L_m of the factor (lower triangular, permuted order).
    fn trailing_block(&self, n: usize) -> FemResult<DMatrix<f64>> {
        let dim = self.symbolic.dim();
        if n > dim {
            return Err(FemError::SparseBackend(format!(
                "trailing block of {n} unknowns asked from a factor of dim {dim}"
            )));
        }
        let first = dim - n;
        let mut l = DMatrix::zeros(n, n);
        match self.symbolic.faer().raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (cp, ri) = (s.col_ptr(), s.row_idx());
                for c in first..dim {
                    for p in cp[c]..cp[c + 1] {
                        l[(ri[p] - first, c - first)] = self.values[p];
                    }
                }
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                for k in 0..s.n_supernodes() {
                    let (begin, end) = (s.supernode_begin()[k], s.supernode_end()[k]);
                    if end <= first {
                        continue;
                    }
                    let values = &self.values[s.col_ptr_for_val()[k]..s.col_ptr_for_val()[k + 1]];
                    let pattern =
                        &s.row_idx()[s.col_ptr_for_row_idx()[k]..s.col_ptr_for_row_idx()[k + 1]];
                    let rows = (end - begin) + pattern.len();
                    let row_of = |r: usize| {
                        if r < end - begin {
                            begin + r
                        } else {
                            pattern[r - (end - begin)]
                        }
                    };
                    for c in begin.max(first)..end {
                        let column = &values[(c - begin) * rows..(c - begin + 1) * rows];
                        for (r, v) in column.iter().enumerate().skip(c - begin) {
                            let row = row_of(r);
                            if row >= first {
                                l[(row - first, c - first)] = *v;
                            }
                        }
                    }
                }
            }
        }
        Ok(l)
    }

    /// The block of K⁻¹ on the n unknowns given as `last` to
    /// [`SymbolicCholesky::analyze_with_last`] (their order): (L_m L_mᵀ)⁻¹, n × n, symmetric.
    pub fn trailing_inverse(&self, n: usize) -> FemResult<DMatrix<f64>> {
        let l = self.trailing_block(n)?;
        let identity = DMatrix::<f64>::identity(n, n);
        let l_inv = l.solve_lower_triangular(&identity).ok_or_else(|| {
            FemError::SparseBackend("zero pivot in the trailing block of the factor".into())
        })?;
        let inverse = l_inv.transpose() * &l_inv;
        Ok((&inverse + inverse.transpose()) * 0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::sparse::test_matrices::laplacian;

    fn check_block_against_solves(
        a: &SymmetricMatrix,
        picked: &[usize],
        ordering: Ordering,
    ) -> bool {
        let n = a.dim();
        let symbolic = SymbolicCholesky::analyze_with_last(a, ordering, picked).unwrap();
        let numeric = symbolic.factor(a).unwrap();
        let block = numeric.trailing_inverse(picked.len()).unwrap();
        for (j, &pj) in picked.iter().enumerate() {
            let mut e = vec![0.0; n];
            e[pj] = 1.0;
            let x = numeric.solve(&e).unwrap();
            for (i, &pi) in picked.iter().enumerate() {
                let err = (block[(i, j)] - x[pi]).abs();
                assert!(
                    err < 1e-13 * x[pj].abs(),
                    "{ordering:?}: compliance (K⁻¹)[{pi}, {pj}] from the trailing block {} vs solve {}",
                    block[(i, j)],
                    x[pi]
                );
            }
        }
        symbolic.is_supernodal()
    }

    #[test]
    fn the_trailing_inverse_equals_the_block_of_the_inverse_from_full_solves() {
        let plate = laplacian(30, 30, 1);
        for ordering in [Ordering::Metis, Ordering::Amd, Ordering::Natural] {
            check_block_against_solves(&plate, &[17, 450, 3, 899, 222, 610], ordering);
        }
        // A 3D grid: supernodal storage, the tie unknowns spread over several supernodes.
        let cube = laplacian(18, 18, 18);
        let picked: Vec<usize> = (0..40).map(|i| (i * 1453 + 11) % cube.dim()).collect();
        assert!(
            check_block_against_solves(&cube, &picked, Ordering::Metis),
            "the 3D grid's factor should be supernodal (the branch under test)"
        );
    }

    #[test]
    fn a_stored_fill_reducing_order_gives_the_same_factor_and_a_non_permutation_is_refused() {
        let cube = laplacian(10, 10, 10);
        let picked = [5, 500, 999];
        let (base, used) = fill_reducing_order(&cube, Ordering::Metis).unwrap();
        assert_eq!(used, Ordering::Metis, "ordering used");
        let direct = SymbolicCholesky::analyze_with_last(&cube, Ordering::Metis, &picked).unwrap();
        let stored =
            SymbolicCholesky::analyze_with_last_ordered(&cube, &base, used, &picked).unwrap();
        assert_eq!(
            direct.permutation(),
            stored.permutation(),
            "a stored ordering must give the permutation of a fresh analysis"
        );
        let block = |s: &SymbolicCholesky| s.factor(&cube).unwrap().trailing_inverse(3).unwrap();
        assert_eq!(
            block(&direct),
            block(&stored),
            "compliance block from a stored ordering"
        );
        let mut repeated = base.clone();
        repeated[1] = repeated[0];
        for bad in [&base[1..], &repeated[..]] {
            assert!(
                SymbolicCholesky::analyze_with_last_ordered(&cube, bad, used, &picked).is_err(),
                "an ordering that is not a permutation of the unknowns must be refused"
            );
        }
    }

    #[test]
    fn repeated_or_out_of_range_last_unknowns_are_refused() {
        let a = laplacian(4, 4, 1);
        assert!(SymbolicCholesky::analyze_with_last(&a, Ordering::Metis, &[1, 1]).is_err());
        assert!(SymbolicCholesky::analyze_with_last(&a, Ordering::Metis, &[16]).is_err());
    }
}
