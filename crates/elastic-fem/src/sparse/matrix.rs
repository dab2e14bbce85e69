//! Symmetric sparse matrix stored as its upper triangle in faer's compressed-column format.

use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};

use crate::error::{FemError, FemResult};

/// A symmetric matrix stored as its upper triangle (row ≤ column, rows sorted, diagonal
/// structurally present in every column) in a faer [`SparseColMat`].
#[derive(Debug, Clone)]
pub struct SymmetricMatrix {
    upper: SparseColMat<usize, f64>,
}

impl SymmetricMatrix {
    /// Builds from raw upper-triangle CSC arrays, checking: `col_ptr` non-decreasing with
    /// `col_ptr[0] = 0`, rows strictly increasing within a column, every row ≤ its column,
    /// and the diagonal present as the last entry of every column.
    pub fn from_upper_parts(
        dim: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<f64>,
    ) -> FemResult<Self> {
        if col_ptr.len() != dim + 1 {
            return Err(FemError::DimensionMismatch {
                what: "column pointer array",
                expected: dim + 1,
                found: col_ptr.len(),
            });
        }
        let nnz = col_ptr[dim];
        if row_idx.len() != nnz || values.len() != nnz || col_ptr[0] != 0 {
            return Err(FemError::DimensionMismatch {
                what: "row index / value arrays",
                expected: nnz,
                found: row_idx.len(),
            });
        }
        for j in 0..dim {
            let (start, end) = (col_ptr[j], col_ptr[j + 1]);
            if end <= start || end > nnz {
                return Err(FemError::PatternMismatch {
                    detail: format!("column {j} is empty or its pointers are out of order"),
                });
            }
            let rows = &row_idx[start..end];
            if rows[rows.len() - 1] != j || rows.windows(2).any(|w| w[0] >= w[1]) {
                return Err(FemError::PatternMismatch {
                    detail: format!(
                        "column {j}: rows must be strictly increasing, at most {j}, and end with the diagonal"
                    ),
                });
            }
        }
        let symbolic = SymbolicSparseColMat::new_checked(dim, dim, col_ptr, None, row_idx);
        Ok(Self {
            upper: SparseColMat::new(symbolic, values),
        })
    }

    /// Crate-internal constructor for patterns built correctly by construction.
    pub(crate) fn from_trusted_parts(
        dim: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<f64>,
    ) -> Self {
        debug_assert!(
            Self::from_upper_parts(dim, col_ptr.clone(), row_idx.clone(), values.clone()).is_ok()
        );
        let symbolic = SymbolicSparseColMat::new_checked(dim, dim, col_ptr, None, row_idx);
        Self {
            upper: SparseColMat::new(symbolic, values),
        }
    }

    /// Number of rows (= columns).
    pub fn dim(&self) -> usize {
        self.upper.ncols()
    }

    /// Stored entries (upper triangle incl. diagonal).
    pub fn nnz_upper(&self) -> usize {
        self.upper.val().len()
    }

    /// The upper triangle as a faer matrix view.
    pub fn upper(&self) -> SparseColMatRef<'_, usize, f64> {
        self.upper.as_ref()
    }

    /// Column pointers of the upper triangle.
    pub fn col_ptr(&self) -> &[usize] {
        self.upper.symbolic().col_ptr()
    }

    /// Row indices of the upper triangle.
    pub fn row_idx(&self) -> &[usize] {
        self.upper.symbolic().row_idx()
    }

    /// Stored values.
    pub fn values(&self) -> &[f64] {
        self.upper.val()
    }

    /// Stored values, mutable (the pattern stays fixed).
    pub fn values_mut(&mut self) -> &mut [f64] {
        self.upper.val_mut()
    }

    /// Position in [`Self::values`] of the diagonal entry of column `j` (the last of the column).
    pub fn diagonal_position(&self, j: usize) -> usize {
        self.col_ptr()[j + 1] - 1
    }

    /// The diagonal.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.dim())
            .map(|j| self.values()[self.diagonal_position(j)])
            .collect()
    }

    /// Adds `value` to the diagonal entry (j, j), e.g. a penalty or contact spring.
    pub fn add_to_diagonal(&mut self, j: usize, value: f64) {
        let p = self.diagonal_position(j);
        self.values_mut()[p] += value;
    }

    /// Entry (i, j) of the symmetric matrix (0 if not stored).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (r, c) = if i <= j { (i, j) } else { (j, i) };
        let (start, end) = (self.col_ptr()[c], self.col_ptr()[c + 1]);
        match self.row_idx()[start..end].binary_search(&r) {
            Ok(k) => self.values()[start + k],
            Err(_) => 0.0,
        }
    }

    /// y = A x for the full symmetric matrix.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(
            x.len(),
            self.dim(),
            "SymmetricMatrix::mul_vec: x has the wrong length"
        );
        assert_eq!(
            y.len(),
            self.dim(),
            "SymmetricMatrix::mul_vec: y has the wrong length"
        );
        y.fill(0.0);
        let (cp, ri, v) = (self.col_ptr(), self.row_idx(), self.values());
        for j in 0..self.dim() {
            let xj = x[j];
            let mut acc = 0.0;
            for k in cp[j]..cp[j + 1] {
                let i = ri[k];
                if i == j {
                    acc += v[k] * xj;
                } else {
                    y[i] += v[k] * xj;
                    acc += v[k] * x[i];
                }
            }
            y[j] += acc;
        }
    }

    /// xᵀ A x.
    pub fn quadratic_form(&self, x: &[f64]) -> f64 {
        let mut y = vec![0.0; self.dim()];
        self.mul_vec(x, &mut y);
        x.iter().zip(&y).map(|(a, b)| a * b).sum()
    }

    /// Both triangles as a general faer matrix (for users who need a full operator).
    pub fn to_full(&self) -> SparseColMat<usize, f64> {
        let mut triplets = Vec::with_capacity(2 * self.nnz_upper());
        let (cp, ri, v) = (self.col_ptr(), self.row_idx(), self.values());
        for j in 0..self.dim() {
            for k in cp[j]..cp[j + 1] {
                triplets.push(faer::sparse::Triplet::new(ri[k], j, v[k]));
                if ri[k] != j {
                    triplets.push(faer::sparse::Triplet::new(j, ri[k], v[k]));
                }
            }
        }
        SparseColMat::try_new_from_triplets(self.dim(), self.dim(), &triplets)
            .expect("a valid upper triangle always yields valid triplets")
    }

    /// Whether `other` has exactly the same sparsity pattern.
    pub fn same_pattern(&self, other: &SymmetricMatrix) -> bool {
        self.dim() == other.dim()
            && self.col_ptr() == other.col_ptr()
            && self.row_idx() == other.row_idx()
    }

    /// A 64-bit fingerprint of the sparsity pattern (FNV-1a over dimension, pointers and rows).
    pub fn pattern_fingerprint(&self) -> u64 {
        fingerprint(self.dim(), self.col_ptr(), self.row_idx())
    }
}

/// FNV-1a style fingerprint of a CSC pattern.
pub(crate) fn fingerprint(dim: usize, col_ptr: &[usize], row_idx: &[usize]) -> u64 {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut h = OFFSET;
    let mut mix = |v: usize| {
        h ^= v as u64;
        h = h.wrapping_mul(PRIME);
    };
    mix(dim);
    col_ptr.iter().for_each(|&v| mix(v));
    row_idx.iter().for_each(|&v| mix(v));
    h
}
