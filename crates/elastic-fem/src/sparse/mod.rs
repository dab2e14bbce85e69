//! The workspace's only door to sparse linear algebra (faer + METIS).
//!
//! - [`matrix`]: [`SymmetricMatrix`], upper-triangle CSC storage;
//! - [`ordering`]: METIS nested dissection / AMD / natural ([`Ordering`]);
//! - [`factor`]: [`SymbolicCholesky::analyze`] once per pattern, then
//!   [`SymbolicCholesky::factor`] / [`NumericCholesky::refactor`] per set of values;
//! - [`solve`]: [`NumericCholesky::solve_in_place`], many right-hand sides;
//! - [`sparse_rhs`]: [`NumericCholesky::inverse_gram`], Bᵀ K⁻¹ B for a few sparse columns from
//!   forward solves on their elimination-tree paths only;
//! - [`csr`]: [`CsrMatrix`] (both triangles by rows) for row-parallel products and the Galerkin
//!   product Pᵀ A P, [`RowSparse`] transfer operators;
//! - [`mod@pcg`]: preconditioned conjugate gradients with an energy-norm stopping rule.
//!
//! ```
//! use elastic_fem::sparse::{Ordering, SymbolicCholesky, SymmetricMatrix};
//! // [[4, 1], [1, 3]] stored as its upper triangle.
//! let a = SymmetricMatrix::from_upper_parts(2, vec![0, 1, 3], vec![0, 0, 1], vec![4.0, 1.0, 3.0]).unwrap();
//! let symbolic = SymbolicCholesky::analyze(&a, Ordering::Amd).unwrap();
//! let numeric = symbolic.factor(&a).unwrap();
//! let x = numeric.solve(&[1.0, 2.0]).unwrap();
//! assert!((4.0 * x[0] + x[1] - 1.0).abs() < 1e-14 && (x[0] + 3.0 * x[1] - 2.0).abs() < 1e-14);
//! ```

pub mod csr;
pub mod factor;
pub mod matrix;
pub mod ordering;
pub mod pcg;
pub mod solve;
pub mod sparse_rhs;

pub use csr::{CsrLayout, CsrMatrix, RowSparse, SinglePrecision};
pub use factor::fill_reducing_order;
pub use factor::{DEFAULT_MIN_PIVOT_RATIO, FactorOptions, NumericCholesky, SymbolicCholesky};
pub use matrix::SymmetricMatrix;
pub use ordering::{Ordering, Permutation, metis_nested_dissection};
pub use pcg::{PcgOptions, PcgReport, PcgWorkspace, pcg};
pub use sparse_rhs::{InverseGramStats, SparseColumn};

/// Matrices shared by the sparse module's unit tests.
#[cfg(test)]
pub(crate) mod test_matrices {
    use super::SymmetricMatrix;

    /// SPD test matrix: the 7-point Laplacian on a kx × ky × kz grid plus a diagonal shift.
    pub(crate) fn laplacian(kx: usize, ky: usize, kz: usize) -> SymmetricMatrix {
        let n = kx * ky * kz;
        let mut col_ptr = vec![0];
        let (mut rows, mut vals) = (Vec::new(), Vec::new());
        for j in 0..n {
            for (stride, has_neighbour) in [
                (kx * ky, j >= kx * ky),
                (kx, j % (kx * ky) >= kx),
                (1, j % kx != 0),
            ] {
                if has_neighbour {
                    rows.push(j - stride);
                    vals.push(-1.0);
                }
            }
            rows.push(j);
            vals.push(6.1);
            col_ptr.push(rows.len());
        }
        SymmetricMatrix::from_upper_parts(n, col_ptr, rows, vals).unwrap()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::FemError;

    /// 1D Laplacian-like SPD tridiagonal matrix plus a long-range coupling, size n.
    fn test_matrix(n: usize, shift: f64) -> SymmetricMatrix {
        let mut col_ptr = vec![0];
        let mut rows = Vec::new();
        let mut vals = Vec::new();
        for j in 0..n {
            if j >= 7 {
                rows.push(j - 7);
                vals.push(-0.5);
            }
            if j >= 1 {
                rows.push(j - 1);
                vals.push(-1.0);
            }
            rows.push(j);
            vals.push(4.0 + shift);
            col_ptr.push(rows.len());
        }
        SymmetricMatrix::from_upper_parts(n, col_ptr, rows, vals).unwrap()
    }

    fn residual(a: &SymmetricMatrix, x: &[f64], b: &[f64]) -> f64 {
        let mut y = vec![0.0; a.dim()];
        a.mul_vec(x, &mut y);
        y.iter()
            .zip(b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn all_orderings_solve_the_same_system_and_refactor_reuses_the_symbolic_analysis() {
        let n = 60;
        let a = test_matrix(n, 0.0);
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        for ordering in [Ordering::Metis, Ordering::Amd, Ordering::Natural] {
            let symbolic = SymbolicCholesky::analyze(&a, ordering).unwrap();
            assert_eq!(symbolic.ordering_used(), ordering, "ordering used");
            let mut numeric = symbolic.factor(&a).unwrap();
            let x = numeric.solve(&b).unwrap();
            assert!(
                residual(&a, &x, &b) < 1e-12,
                "{ordering:?}: residual of A x = b"
            );
            // New values, same pattern: refactor reuses the symbolic structure.
            let a2 = test_matrix(n, 2.5);
            numeric.refactor(&a2).unwrap();
            let x2 = numeric.solve(&b).unwrap();
            assert!(
                residual(&a2, &x2, &b) < 1e-12,
                "{ordering:?}: residual after refactorisation"
            );
        }
    }

    #[test]
    fn many_right_hand_sides_are_solved_column_by_column() {
        let n = 40;
        let a = test_matrix(n, 0.0);
        let numeric = SymbolicCholesky::analyze(&a, Ordering::Metis)
            .unwrap()
            .factor(&a)
            .unwrap();
        let ncols = 3;
        let b: Vec<f64> = (0..n * ncols)
            .map(|i| ((i * 7 % 11) as f64) - 5.0)
            .collect();
        let mut x = b.clone();
        numeric.solve_columns_in_place(&mut x, ncols).unwrap();
        for c in 0..ncols {
            let r = residual(&a, &x[c * n..(c + 1) * n], &b[c * n..(c + 1) * n]);
            assert!(r < 1e-12, "residual of right-hand side {c}: {r}");
        }
    }

    #[test]
    fn indefinite_and_singular_matrices_are_rejected_with_a_column() {
        // Indefinite: a negative diagonal entry.
        let a = SymmetricMatrix::from_upper_parts(
            3,
            vec![0, 1, 2, 3],
            vec![0, 1, 2],
            vec![1.0, -2.0, 1.0],
        )
        .unwrap();
        let err = SymbolicCholesky::analyze(&a, Ordering::Natural)
            .unwrap()
            .factor(&a)
            .unwrap_err();
        assert!(
            matches!(err, FemError::NotPositiveDefinite { column: 1, .. }),
            "indefinite matrix error: {err}"
        );
        // Singular: [[1, 1], [1, 1]] (pivot exactly 0 or roundoff-small).
        let s =
            SymmetricMatrix::from_upper_parts(2, vec![0, 1, 3], vec![0, 0, 1], vec![1.0, 1.0, 1.0])
                .unwrap();
        let err = SymbolicCholesky::analyze(&s, Ordering::Natural)
            .unwrap()
            .factor(&s)
            .unwrap_err();
        assert!(
            matches!(err, FemError::NotPositiveDefinite { .. }),
            "singular matrix error: {err}"
        );
    }

    #[test]
    fn a_matrix_with_another_pattern_is_refused_by_the_symbolic_analysis() {
        let a = test_matrix(20, 0.0);
        let b = test_matrix(21, 0.0);
        let symbolic = SymbolicCholesky::analyze(&a, Ordering::Amd).unwrap();
        assert!(
            matches!(symbolic.factor(&b), Err(FemError::PatternMismatch { .. })),
            "factorising a matrix with a different pattern must fail"
        );
    }

    #[test]
    fn malformed_upper_triangles_are_rejected() {
        // Entry below the diagonal.
        assert!(
            SymmetricMatrix::from_upper_parts(2, vec![0, 2, 3], vec![0, 1, 1], vec![1.0, 0.5, 1.0])
                .is_err()
        );
        // Missing diagonal in column 1.
        assert!(
            SymmetricMatrix::from_upper_parts(2, vec![0, 1, 2], vec![0, 0], vec![1.0, 0.5])
                .is_err()
        );
    }
}
