//! Triangular solves with a [`NumericCholesky`]: one or many right-hand sides, in place.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::LltRef;
use faer::{Conj, MatMut};

use super::factor::NumericCholesky;
use crate::error::{FemError, FemResult};

impl NumericCholesky {
    /// Solves A x = b for the columns of `rhs` (overwritten with x). Fails if the result is not
    /// finite.
    pub fn solve_many_in_place(&self, mut rhs: MatMut<'_, f64>) -> FemResult<()> {
        let n = self.symbolic.dim();
        if rhs.nrows() != n {
            return Err(FemError::DimensionMismatch {
                what: "right-hand side rows",
                expected: n,
                found: rhs.nrows(),
            });
        }
        let par = self.options.par();
        let faer_symbolic = self.symbolic.faer();
        let req = faer_symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), par);
        let mut mem = MemBuffer::try_new(req)
            .map_err(|_| FemError::SparseBackend("out of memory for solve workspace".into()))?;
        let stack = MemStack::new(&mut mem);
        LltRef::<'_, usize, f64>::new(faer_symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs.as_mut(),
            par,
            stack,
        );
        for j in 0..rhs.ncols() {
            for i in 0..n {
                if !rhs[(i, j)].is_finite() {
                    return Err(FemError::NonFiniteSolution { unknown: i });
                }
            }
        }
        Ok(())
    }

    /// Solves A x = b for `ncols` right-hand sides stored column-major in `rhs`.
    pub fn solve_columns_in_place(&self, rhs: &mut [f64], ncols: usize) -> FemResult<()> {
        let n = self.symbolic.dim();
        if rhs.len() != n * ncols {
            return Err(FemError::DimensionMismatch {
                what: "column-major right-hand sides",
                expected: n * ncols,
                found: rhs.len(),
            });
        }
        self.solve_many_in_place(MatMut::from_column_major_slice_mut(rhs, n, ncols))
    }

    /// Solves A x = b in place for one right-hand side.
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> FemResult<()> {
        self.solve_columns_in_place(rhs, 1)
    }

    /// Returns x with A x = b.
    pub fn solve(&self, rhs: &[f64]) -> FemResult<Vec<f64>> {
        let mut x = rhs.to_vec();
        self.solve_in_place(&mut x)?;
        Ok(x)
    }
}
