//! Compressed-row matrices for the iterative path: the full (both triangles) copy of a
//! [`SymmetricMatrix`] for a row-parallel product y = A x (or its [`CsrLayout`], to fill it from
//! upper values without the copy), a rectangular row-sparse matrix for the multigrid transfer
//! operators, and the Galerkin product A_c = Pᵀ A P.
//!
//! Why assembled CSR: a stored entry costs 12 bytes of memory traffic per product, while a
//! matrix-free Tet10 product recomputes 30 × 30 element matrices (the whole assembly, 2.4 s at
//! 350k unknowns on the punch mesh) per product, against ≈ 0.1 s per CSR product there
//! (validation/fem-peers/README.md). The full-row layout lets each rayon task own a block of
//! rows (no write conflicts), which the upper-triangle CSC storage of the direct path does not.

use rayon::prelude::*;

use super::matrix::SymmetricMatrix;
use crate::error::{FemError, FemResult};

/// Rows per rayon task in the matrix–vector products. Large enough to amortise scheduling,
/// small enough to balance 2–64 threads on 10⁴–10⁷ rows. Dimensionless; default 2048.
pub const ROW_BLOCK: usize = 2048;

/// Independent partial sums per row in the matrix–vector product (4: covers the latency of a
/// floating-point addition on current x86 and ARM cores).
const DOT_LANES: usize = 4;

/// Most column blocks of [`CsrMatrix::from_symmetric`]'s transpose (one per rayon thread, each
/// a parallel task holding two arrays as long as the dimension: with 16 blocks on one thread the
/// transpose of the 2.5M-unknown punch took 9.4 instead of 5.5 s), and the row blocks of its
/// fill. The output does not depend on either. Dimensionless; default 16.
const TRANSPOSE_BLOCKS: usize = 16;

/// Splits `0..ptr.len() - 1` into at most `blocks` consecutive ranges of about equal entry
/// counts (`ptr`: CSC/CSR pointers); returns the boundaries (first 0, last the dimension).
pub(crate) fn split_columns(ptr: &[usize], blocks: usize) -> Vec<usize> {
    let n = ptr.len() - 1;
    let total = ptr[n];
    let mut bounds = vec![0usize];
    for b in 1..blocks {
        let target = total * b / blocks;
        let j = ptr.partition_point(|&p| p < target).min(n);
        if j > *bounds.last().unwrap_or(&0) {
            bounds.push(j);
        }
    }
    if *bounds.last().unwrap_or(&0) != n || bounds.len() == 1 {
        bounds.push(n);
    }
    bounds
}

/// The strictly upper entries (i, j) of a block of columns j, bucketed by row i (CSR over all
/// rows, each row's entries in increasing j), with a payload per entry (its value, or its
/// position in the upper storage).
struct RowBuckets<T> {
    ptr: Vec<usize>,
    col: Vec<u32>,
    val: Vec<T>,
}

impl<T: Copy + Default> RowBuckets<T> {
    /// `payload(k)`: what entry k of the upper storage carries.
    fn new(
        n: usize,
        cp: &[usize],
        ri: &[usize],
        payload: impl Fn(usize) -> T,
        cols: std::ops::Range<usize>,
    ) -> Self {
        let mut ptr = vec![0usize; n + 1];
        for j in cols.clone() {
            for &i in &ri[cp[j]..cp[j + 1] - 1] {
                ptr[i + 1] += 1;
            }
        }
        for i in 0..n {
            ptr[i + 1] += ptr[i];
        }
        let mut fill = ptr[..n].to_vec();
        let mut col = vec![0u32; ptr[n]];
        let mut val = vec![T::default(); ptr[n]];
        for j in cols {
            for k in cp[j]..cp[j + 1] - 1 {
                let i = ri[k];
                col[fill[i]] = j as u32;
                val[fill[i]] = payload(k);
                fill[i] += 1;
            }
        }
        Self { ptr, col, val }
    }
}

/// Row `i` of the full matrix is column i of the upper triangle (rows ≤ i), then the entries
/// (i, j > i) in increasing j. Buckets the strictly upper entries by row per block of columns
/// (blocks in parallel), then fills rows in parallel, each copying its upper column and its
/// buckets in block order: pure copies, the result is independent of the threads. Returns the
/// row pointers, column indices and every entry's payload.
fn full_rows<T: Copy + Default + Send + Sync>(
    cp: &[usize],
    ri: &[usize],
    payload: impl Fn(usize) -> T + Sync,
) -> (Vec<usize>, Vec<u32>, Vec<T>) {
    let n = cp.len() - 1;
    let blocks = split_columns(cp, rayon::current_num_threads().clamp(1, TRANSPOSE_BLOCKS));
    let buckets: Vec<RowBuckets<T>> = blocks
        .par_windows(2)
        .map(|w| RowBuckets::new(n, cp, ri, &payload, w[0]..w[1]))
        .collect();
    let mut row_ptr = vec![0usize; n + 1];
    for i in 0..n {
        let lower = cp[i + 1] - cp[i];
        let upper: usize = buckets.iter().map(|b| b.ptr[i + 1] - b.ptr[i]).sum();
        row_ptr[i + 1] = row_ptr[i] + lower + upper;
    }
    let nnz = row_ptr[n];
    let mut col_idx = vec![0u32; nnz];
    let mut values = vec![T::default(); nnz];
    let row_ranges = split_columns(&row_ptr, TRANSPOSE_BLOCKS);
    let mut pieces = Vec::with_capacity(row_ranges.len());
    let (mut ci_rest, mut va_rest) = (col_idx.as_mut_slice(), values.as_mut_slice());
    for w in row_ranges.windows(2) {
        let len = row_ptr[w[1]] - row_ptr[w[0]];
        let (ci, ci_tail) = std::mem::take(&mut ci_rest).split_at_mut(len);
        let (va, va_tail) = std::mem::take(&mut va_rest).split_at_mut(len);
        pieces.push((w[0]..w[1], ci, va));
        (ci_rest, va_rest) = (ci_tail, va_tail);
    }
    pieces.into_par_iter().for_each(|(rows, ci, va)| {
        let mut k = 0usize;
        for i in rows {
            for p in cp[i]..cp[i + 1] {
                ci[k] = ri[p] as u32;
                va[k] = payload(p);
                k += 1;
            }
            for b in &buckets {
                for q in b.ptr[i]..b.ptr[i + 1] {
                    ci[k] = b.col[q];
                    va[k] = b.val[q];
                    k += 1;
                }
            }
        }
    });
    (row_ptr, col_idx, values)
}

fn check_u32_dimension(n: usize) -> FemResult<()> {
    if n >= u32::MAX as usize {
        return Err(FemError::SparseBackend(format!(
            "CSR matrix of dimension {n} exceeds 32-bit column indices"
        )));
    }
    Ok(())
}

/// Where the entries of a symmetric matrix's full-row CSR ([`CsrMatrix`]) come from in its
/// upper-triangle CSC storage (`cp`, `ri`): entry q of the CSR is upper entry `source[q]`. Built
/// once per pattern; [`Self::gather`] then fills the CSR values from any upper values with that
/// pattern, rows in parallel (pure copies: the same bits for any thread count).
#[derive(Debug, Clone)]
pub struct CsrLayout {
    row_ptr: Vec<usize>,
    col_idx: Vec<u32>,
    /// Per CSR entry: its position in the upper storage.
    source: Vec<u32>,
    upper_nnz: usize,
}

/// CSR entries per rayon task in [`CsrLayout::gather`]. Dimensionless; default 16384.
const GATHER_CHUNK: usize = 16384;

impl CsrLayout {
    /// The layout of the upper CSC pattern (`cp`, `ri`; rows sorted, every diagonal last in
    /// its column). Fails beyond 32-bit indices.
    pub fn of_upper(cp: &[usize], ri: &[usize]) -> FemResult<Self> {
        check_u32_dimension(cp.len() - 1)?;
        if ri.len() >= u32::MAX as usize {
            return Err(FemError::SparseBackend(format!(
                "upper triangle with {} entries exceeds 32-bit positions",
                ri.len()
            )));
        }
        let (row_ptr, col_idx, source) = full_rows(cp, ri, |k| k as u32);
        Ok(Self {
            row_ptr,
            col_idx,
            source,
            upper_nnz: ri.len(),
        })
    }

    /// Stored entries of the full matrix.
    pub fn nnz(&self) -> usize {
        self.col_idx.len()
    }

    /// Stored entries of the upper triangle the layout was built for.
    pub fn upper_nnz(&self) -> usize {
        self.upper_nnz
    }

    /// The full-row values of the matrix whose upper values are `upper`.
    pub fn gather(&self, upper: &[f64]) -> Vec<f64> {
        assert_eq!(
            upper.len(),
            self.upper_nnz,
            "CsrLayout::gather: wrong value count"
        );
        let mut values = vec![0.0; self.nnz()];
        values
            .par_chunks_mut(GATHER_CHUNK)
            .zip(self.source.par_chunks(GATHER_CHUNK))
            .for_each(|(out, src)| {
                for (o, &k) in out.iter_mut().zip(src) {
                    *o = upper[k as usize];
                }
            });
        values
    }

    /// The CSR matrix with this layout and the given `values` (one per full entry).
    pub fn into_matrix(self, values: Vec<f64>) -> CsrMatrix {
        assert_eq!(
            values.len(),
            self.nnz(),
            "CsrLayout::into_matrix: wrong value count"
        );
        CsrMatrix {
            row_ptr: self.row_ptr,
            col_idx: self.col_idx,
            values,
        }
    }
}

/// The values of a [`CsrMatrix`] rounded to f32 ([`CsrMatrix::single_precision`]): 8 instead of
/// 12 bytes per entry with the column index, for the smoothers' products, which are memory bound
/// and need no double precision (a fixed symmetric operator is all a preconditioner must be).
#[derive(Debug, Clone)]
pub struct SinglePrecision {
    values: Vec<f32>,
}

/// A square symmetric matrix with both triangles stored by rows (32-bit column indices).
#[derive(Debug, Clone)]
pub struct CsrMatrix {
    row_ptr: Vec<usize>,
    col_idx: Vec<u32>,
    values: Vec<f64>,
}

impl CsrMatrix {
    /// The full matrix of a symmetric upper-triangle matrix. Fails if the dimension exceeds
    /// 32-bit column indices.
    pub fn from_symmetric(a: &SymmetricMatrix) -> FemResult<Self> {
        check_u32_dimension(a.dim())?;
        let v = a.values();
        let (row_ptr, col_idx, values) = full_rows(a.col_ptr(), a.row_idx(), |k| v[k]);
        Ok(Self {
            row_ptr,
            col_idx,
            values,
        })
    }

    /// Number of rows.
    pub fn dim(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// Stored entries (both triangles).
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Bytes of the stored arrays.
    pub fn memory_bytes(&self) -> usize {
        self.values.len() * 12 + self.row_ptr.len() * 8
    }

    /// The diagonal.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.dim())
            .map(|i| {
                let (s, e) = (self.row_ptr[i], self.row_ptr[i + 1]);
                self.col_idx[s..e]
                    .binary_search(&(i as u32))
                    .map_or(0.0, |k| self.values[s + k])
            })
            .collect()
    }

    /// Entries (column, value) of row `i`.
    pub(crate) fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (s, e) = (self.row_ptr[i], self.row_ptr[i + 1]);
        self.col_idx[s..e]
            .iter()
            .zip(&self.values[s..e])
            .map(|(&c, &v)| (c as usize, v))
    }

    /// Σ_j A_ij x_j with `values` for A's entries (the matrix's own, or them in another
    /// precision: same length), summed in f64 with [`DOT_LANES`] independent partial sums, so
    /// the additions' latency (≈ 4 cycles each, one chain per row otherwise) overlaps the memory
    /// traffic.
    fn row_dot_with<V: Copy + Into<f64>>(&self, values: &[V], i: usize, x: &[f64]) -> f64 {
        let (s, e) = (self.row_ptr[i], self.row_ptr[i + 1]);
        let mut cols = self.col_idx[s..e].chunks_exact(DOT_LANES);
        let mut vals = values[s..e].chunks_exact(DOT_LANES);
        let mut acc = [0.0; DOT_LANES];
        for (c, v) in (&mut cols).zip(&mut vals) {
            for k in 0..DOT_LANES {
                acc[k] += v[k].into() * x[c[k] as usize];
            }
        }
        let tail: f64 = cols
            .remainder()
            .iter()
            .zip(vals.remainder())
            .map(|(&j, &a)| a.into() * x[j as usize])
            .sum();
        (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
    }

    /// The values rounded to single precision, for operators that need no more (smoothers).
    pub fn single_precision(&self) -> SinglePrecision {
        SinglePrecision {
            values: self.values.par_iter().map(|&v| v as f32).collect(),
        }
    }

    /// y = Ã x with Ã = `single`, this matrix in single precision (sums in f64).
    pub fn mul_vec_single(&self, single: &SinglePrecision, x: &[f64], y: &mut [f64]) {
        self.check_single(single);
        self.mul_vec_with(&single.values, x, y);
    }

    /// r = b − Ã x with Ã = `single`, this matrix in single precision (sums in f64).
    pub(crate) fn residual_single(
        &self,
        single: &SinglePrecision,
        b: &[f64],
        x: &[f64],
        r: &mut [f64],
    ) {
        self.check_single(single);
        self.residual_with(&single.values, b, x, r);
    }

    fn check_single(&self, single: &SinglePrecision) {
        assert_eq!(
            single.values.len(),
            self.values.len(),
            "values of another matrix"
        );
    }

    /// y = A x, rows in parallel blocks of [`ROW_BLOCK`].
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        self.mul_vec_with(&self.values, x, y);
    }

    /// y = A x with `values` for this matrix's entries ([`Self::row_dot_with`]).
    fn mul_vec_with<V: Copy + Into<f64> + Sync>(&self, values: &[V], x: &[f64], y: &mut [f64]) {
        assert_eq!(
            x.len(),
            self.dim(),
            "CsrMatrix::mul_vec: x has the wrong length"
        );
        assert_eq!(
            y.len(),
            self.dim(),
            "CsrMatrix::mul_vec: y has the wrong length"
        );
        y.par_chunks_mut(ROW_BLOCK).enumerate().for_each(|(b, yb)| {
            let base = b * ROW_BLOCK;
            for (k, yi) in yb.iter_mut().enumerate() {
                *yi = self.row_dot_with(values, base + k, x);
            }
        });
    }

    /// r = b − A x, rows in parallel.
    pub fn residual(&self, b: &[f64], x: &[f64], r: &mut [f64]) {
        self.residual_with(&self.values, b, x, r);
    }

    /// r = b − A x with `values` for this matrix's entries ([`Self::row_dot_with`]).
    fn residual_with<V: Copy + Into<f64> + Sync>(
        &self,
        values: &[V],
        b: &[f64],
        x: &[f64],
        r: &mut [f64],
    ) {
        assert_eq!(
            b.len(),
            self.dim(),
            "CsrMatrix::residual: b has the wrong length"
        );
        r.par_chunks_mut(ROW_BLOCK)
            .enumerate()
            .for_each(|(blk, rb)| {
                let base = blk * ROW_BLOCK;
                for (k, ri) in rb.iter_mut().enumerate() {
                    *ri = b[base + k] - self.row_dot_with(values, base + k, x);
                }
            });
    }

    /// The Galerkin coarse operator A_c = Pᵀ A P (upper triangle, every diagonal present) for a
    /// prolongation `p` (fine rows × coarse columns) and its transpose `pt`.
    ///
    /// Blocks of [`GALERKIN_BLOCK`] coarse columns are computed in parallel, each column
    /// independently of the thread count, by one of two products:
    /// - **one pass** when P has at most [`ONE_PASS_MAX_P_ROW`] entries per row (the
    ///   p-multigrid's Tet10 → Tet4 interpolation: 1 or 2): column c of A_c is
    ///   Σ_{j ∈ Pᵀ row c} P_jc Σ_i A_ij P_i,· over the fine rows j it touches, ≈ nnz(P)·(nnz(A)/n)·p
    ///   multiply-adds with p ≤ 2 and no intermediate matrix;
    /// - **two steps** otherwise (smoothed aggregation, p ≈ 20–50): first the rows of A P for
    ///   the fine rows the block's columns touch (Gustavson, keeping only coarse columns ≤ the
    ///   block's last), then column c of A_c = Σ_i P_ic (A P)_i,·. Cost ≈ nnz(A)·p + nnz(P)·q
    ///   (q: entries per row of A P), ≈ p× less than one pass; a fine row shared by two blocks
    ///   is multiplied twice.
    pub fn galerkin(&self, p: &RowSparse, pt: &RowSparse) -> FemResult<SymmetricMatrix> {
        let nc = pt.rows();
        if p.rows() != self.dim() || p.cols() != nc || pt.cols() != self.dim() {
            return Err(FemError::DimensionMismatch {
                what: "prolongation vs fine matrix",
                expected: self.dim(),
                found: p.rows(),
            });
        }
        let one_pass = p.max_row_len() <= ONE_PASS_MAX_P_ROW;
        let slots = (p.max_row_len() <= 2).then(|| TwoSlots::of(p));
        let blocks: Vec<(Vec<usize>, Vec<usize>, Vec<f64>)> = (0..nc)
            .into_par_iter()
            .chunks(GALERKIN_BLOCK)
            .map_init(
                || Accumulator::new(nc),
                |acc, cols| {
                    if one_pass {
                        self.galerkin_block_one_pass(p, slots.as_ref(), pt, &cols, acc)
                    } else {
                        self.galerkin_block(p, pt, &cols, acc)
                    }
                },
            )
            .collect();
        let total: usize = blocks.iter().map(|b| b.1.len()).sum();
        let mut col_ptr = Vec::with_capacity(nc + 1);
        col_ptr.push(0usize);
        let (mut row_idx, mut values) = (Vec::with_capacity(total), Vec::with_capacity(total));
        for (ptr, rows, vals) in blocks {
            let base = row_idx.len();
            col_ptr.extend(ptr[1..].iter().map(|p| p + base));
            row_idx.extend(rows);
            values.extend(vals);
        }
        SymmetricMatrix::from_upper_parts(nc, col_ptr, row_idx, values)
    }

    /// Adds `scale` × (row i of A) P into `acc`, coarse columns ≤ `last` only.
    fn add_row_times_p(
        &self,
        i: usize,
        scale: f64,
        p: &RowSparse,
        last: usize,
        acc: &mut Accumulator,
    ) {
        for k in self.row_ptr[i]..self.row_ptr[i + 1] {
            let a = scale * self.values[k];
            for (c2, w) in p.row(self.col_idx[k] as usize) {
                if c2 <= last {
                    acc.add(c2, w * a);
                }
            }
        }
    }

    /// Upper columns `cols` (consecutive) of Pᵀ A P as (column pointers, rows, values), in one
    /// pass over the rows of A that the columns touch (short rows of P).
    fn galerkin_block_one_pass(
        &self,
        p: &RowSparse,
        slots: Option<&TwoSlots>,
        pt: &RowSparse,
        cols: &[usize],
        acc: &mut Accumulator,
    ) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let (mut ptr, mut rows, mut vals) = (vec![0usize], Vec::new(), Vec::new());
        for &c in cols {
            for (j, w_j) in pt.row(c) {
                match slots {
                    Some(slots) => self.add_row_times_two_slots(j, w_j, slots, c, acc),
                    None => self.add_row_times_p(j, w_j, p, c, acc),
                }
            }
            acc.add(c, 0.0);
            acc.drain_into(true, &mut rows, &mut vals);
            ptr.push(rows.len());
        }
        (ptr, rows, vals)
    }

    /// [`Self::add_row_times_p`] for P in two slots per row: the same additions in the same
    /// order, without the row iterator.
    fn add_row_times_two_slots(
        &self,
        i: usize,
        scale: f64,
        p: &TwoSlots,
        last: usize,
        acc: &mut Accumulator,
    ) {
        for k in self.row_ptr[i]..self.row_ptr[i + 1] {
            let a = scale * self.values[k];
            let j = self.col_idx[k] as usize;
            let ([c1, c2], [w1, w2]) = (p.cols[j], p.weights[j]);
            // An empty slot holds u32::MAX, beyond every `last`.
            if c1 as usize <= last {
                acc.add(c1 as usize, w1 * a);
            }
            if c2 as usize <= last {
                acc.add(c2 as usize, w2 * a);
            }
        }
    }

    /// Upper columns `cols` (consecutive) of Pᵀ A P as (column pointers, rows, values), in two
    /// steps through the rows of A P (long rows of P).
    fn galerkin_block(
        &self,
        p: &RowSparse,
        pt: &RowSparse,
        cols: &[usize],
        acc: &mut Accumulator,
    ) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let last = cols.last().copied().unwrap_or(0);
        let mut fine: Vec<usize> = cols
            .iter()
            .flat_map(|&c| pt.row(c).map(|(i, _)| i))
            .collect();
        fine.sort_unstable();
        fine.dedup();
        // Rows of A P (coarse columns ≤ last) for the touched fine rows.
        let (mut ap_ptr, mut ap_col, mut ap_val) = (vec![0usize], Vec::new(), Vec::new());
        for &i in &fine {
            self.add_row_times_p(i, 1.0, p, last, acc);
            acc.drain_into(false, &mut ap_col, &mut ap_val);
            ap_ptr.push(ap_col.len());
        }
        let (mut ptr, mut rows, mut vals) = (vec![0usize], Vec::new(), Vec::new());
        for &c in cols {
            for (i, w) in pt.row(c) {
                let li = fine.binary_search(&i).expect("fine row collected above");
                for k in ap_ptr[li]..ap_ptr[li + 1] {
                    let c2 = ap_col[k];
                    if c2 <= c {
                        acc.add(c2, w * ap_val[k]);
                    }
                }
            }
            acc.add(c, 0.0);
            acc.drain_into(true, &mut rows, &mut vals);
            ptr.push(rows.len());
        }
        (ptr, rows, vals)
    }
}

/// Longest row of P for which [`CsrMatrix::galerkin`] uses the one-pass product (module docs
/// of the method). Dimensionless; default 4.
pub const ONE_PASS_MAX_P_ROW: usize = 4;

/// Coarse columns per task of [`CsrMatrix::galerkin`]: large enough that few fine rows are
/// shared between blocks (and multiplied twice), small enough to balance threads and keep the
/// block's rows of A P (≈ 10–50 MB) in memory. Dimensionless; default 1024.
pub const GALERKIN_BLOCK: usize = 1024;

/// A dense accumulator over `n` columns with the list of touched columns (Gustavson).
struct Accumulator {
    value: Vec<f64>,
    mark: Vec<bool>,
    touched: Vec<usize>,
}

impl Accumulator {
    fn new(n: usize) -> Self {
        Self {
            value: vec![0.0; n],
            mark: vec![false; n],
            touched: Vec::new(),
        }
    }

    fn add(&mut self, c: usize, v: f64) {
        if !self.mark[c] {
            self.mark[c] = true;
            self.touched.push(c);
        }
        self.value[c] += v;
    }

    /// Appends the touched (column, value) pairs (sorted by column if `sorted`) and resets.
    fn drain_into(&mut self, sorted: bool, cols: &mut Vec<usize>, vals: &mut Vec<f64>) {
        if sorted {
            self.touched.sort_unstable();
        }
        for &c in &self.touched {
            cols.push(c);
            vals.push(self.value[c]);
            self.value[c] = 0.0;
            self.mark[c] = false;
        }
        self.touched.clear();
    }
}

/// The rows of a prolongation with at most two entries per row (the p-multigrid's Tet10 → Tet4
/// interpolation) in two fixed slots, in row order; an empty slot has column u32::MAX.
struct TwoSlots {
    cols: Vec<[u32; 2]>,
    weights: Vec<[f64; 2]>,
}

impl TwoSlots {
    fn of(p: &RowSparse) -> Self {
        let (mut cols, mut weights) = (Vec::with_capacity(p.rows()), Vec::with_capacity(p.rows()));
        for i in 0..p.rows() {
            let (mut c, mut w) = ([u32::MAX; 2], [0.0; 2]);
            for (slot, (col, v)) in p.row(i).enumerate() {
                c[slot] = col as u32;
                w[slot] = v;
            }
            cols.push(c);
            weights.push(w);
        }
        Self { cols, weights }
    }
}

/// A rectangular sparse matrix stored by rows (few entries per row), e.g. a multigrid
/// prolongation P (fine × coarse) or restriction Pᵀ.
#[derive(Debug, Clone, PartialEq)]
pub struct RowSparse {
    cols: usize,
    row_ptr: Vec<usize>,
    col_idx: Vec<u32>,
    values: Vec<f64>,
}

impl RowSparse {
    /// Builds from per-row lists of (column, value); fails on a column out of range.
    pub fn from_rows(cols: usize, rows: &[Vec<(usize, f64)>]) -> FemResult<Self> {
        let mut row_ptr = Vec::with_capacity(rows.len() + 1);
        row_ptr.push(0);
        let (mut col_idx, mut values) = (Vec::new(), Vec::new());
        for row in rows {
            for &(c, v) in row {
                if c >= cols {
                    return Err(FemError::DimensionMismatch {
                        what: "row-sparse column index",
                        expected: cols,
                        found: c,
                    });
                }
                col_idx.push(c as u32);
                values.push(v);
            }
            row_ptr.push(col_idx.len());
        }
        Ok(Self {
            cols,
            row_ptr,
            col_idx,
            values,
        })
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// Bytes of the stored arrays.
    pub fn memory_bytes(&self) -> usize {
        self.values.len() * 12 + self.row_ptr.len() * 8
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Most entries in one row (0 for an empty matrix).
    pub fn max_row_len(&self) -> usize {
        self.row_ptr
            .windows(2)
            .map(|w| w[1] - w[0])
            .max()
            .unwrap_or(0)
    }

    /// Entries (column, value) of row `i`.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (s, e) = (self.row_ptr[i], self.row_ptr[i + 1]);
        self.col_idx[s..e]
            .iter()
            .zip(&self.values[s..e])
            .map(|(&c, &v)| (c as usize, v))
    }

    /// The transpose.
    pub fn transpose(&self) -> Self {
        let mut lists: Vec<Vec<(usize, f64)>> = vec![Vec::new(); self.cols];
        for i in 0..self.rows() {
            for (c, v) in self.row(i) {
                lists[c].push((i, v));
            }
        }
        Self::from_rows(self.rows(), &lists).expect("transpose indices are in range")
    }

    /// y = M x, rows in parallel.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(
            x.len(),
            self.cols,
            "RowSparse::mul_vec: x has the wrong length"
        );
        assert_eq!(
            y.len(),
            self.rows(),
            "RowSparse::mul_vec: y has the wrong length"
        );
        y.par_chunks_mut(ROW_BLOCK).enumerate().for_each(|(b, yb)| {
            for (k, yi) in yb.iter_mut().enumerate() {
                *yi = self.row(b * ROW_BLOCK + k).map(|(c, v)| v * x[c]).sum();
            }
        });
    }

    /// y += M x, rows in parallel.
    pub fn mul_add_vec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(
            y.len(),
            self.rows(),
            "RowSparse::mul_add_vec: y has the wrong length"
        );
        y.par_chunks_mut(ROW_BLOCK).enumerate().for_each(|(b, yb)| {
            for (k, yi) in yb.iter_mut().enumerate() {
                *yi += self
                    .row(b * ROW_BLOCK + k)
                    .map(|(c, v)| v * x[c])
                    .sum::<f64>();
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> SymmetricMatrix {
        // [[4,1,0],[1,5,2],[0,2,6]]
        SymmetricMatrix::from_upper_parts(
            3,
            vec![0, 1, 3, 5],
            vec![0, 0, 1, 1, 2],
            vec![4.0, 1.0, 5.0, 2.0, 6.0],
        )
        .unwrap()
    }

    #[test]
    fn csr_product_equals_the_symmetric_product() {
        let a = small();
        let csr = CsrMatrix::from_symmetric(&a).unwrap();
        let x = [1.0, -2.0, 0.5];
        let (mut y1, mut y2) = (vec![0.0; 3], vec![0.0; 3]);
        a.mul_vec(&x, &mut y1);
        csr.mul_vec(&x, &mut y2);
        assert_eq!(y1, y2, "A x from CSR and from the upper triangle");
        assert_eq!(csr.diagonal(), vec![4.0, 5.0, 6.0], "diagonal of A");
    }

    #[test]
    fn single_precision_products_are_those_of_the_values_rounded_to_f32() {
        let a = banded(40);
        let csr = CsrMatrix::from_symmetric(&a).unwrap();
        let single = csr.single_precision();
        let rounded = CsrMatrix {
            values: csr.values.iter().map(|&v| f64::from(v as f32)).collect(),
            ..csr.clone()
        };
        let x: Vec<f64> = (0..40).map(|i| (0.37 * i as f64).sin()).collect();
        let b: Vec<f64> = (0..40).map(|i| 1.0 / (1.0 + i as f64)).collect();
        let (mut y, mut y_rounded, mut y_double) = (vec![0.0; 40], vec![0.0; 40], vec![0.0; 40]);
        csr.mul_vec_single(&single, &x, &mut y);
        rounded.mul_vec(&x, &mut y_rounded);
        csr.mul_vec(&x, &mut y_double);
        assert_eq!(
            y, y_rounded,
            "Ã x is the f64 product with the rounded values, bit for bit"
        );
        assert_ne!(y, y_double, "the rounding is seen: 1/(1 + i + j) is no f32");
        let scale = y_double.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (s, d) in y.iter().zip(&y_double) {
            assert!((s - d).abs() <= 1e-6 * scale, "{s} vs {d}");
        }
        let (mut r, mut r_rounded) = (vec![0.0; 40], vec![0.0; 40]);
        csr.residual_single(&single, &b, &x, &mut r);
        rounded.residual(&b, &x, &mut r_rounded);
        assert_eq!(r, r_rounded, "b − Ã x likewise");
    }

    #[test]
    fn the_full_rows_are_the_same_for_any_thread_count() {
        let a = banded(500);
        let with = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| CsrMatrix::from_symmetric(&a).unwrap())
        };
        let one = with(1);
        for threads in [2, 3, 16, 20] {
            let other = with(threads);
            assert_eq!(one.row_ptr, other.row_ptr, "{threads} threads");
            assert_eq!(one.col_idx, other.col_idx, "{threads} threads");
            assert_eq!(one.values, other.values, "{threads} threads");
        }
        let x: Vec<f64> = (0..500).map(|i| (0.1 * i as f64).sin()).collect();
        let (mut y, mut y_csr) = (vec![0.0; 500], vec![0.0; 500]);
        a.mul_vec(&x, &mut y);
        one.mul_vec(&x, &mut y_csr);
        for (u, v) in y.iter().zip(&y_csr) {
            assert!((u - v).abs() <= 1e-14 * u.abs().max(1.0), "{u} vs {v}");
        }
    }

    /// Full n × n matrix with a_ii = 4 + i, a_ij = 1/(1 + i + j) for |i − j| ≤ 3, as upper CSC.
    fn banded(n: usize) -> SymmetricMatrix {
        let (mut cp, mut ri, mut v) = (vec![0usize], Vec::new(), Vec::new());
        for j in 0..n {
            for i in j.saturating_sub(3)..=j {
                ri.push(i);
                v.push(if i == j {
                    4.0 + i as f64
                } else {
                    1.0 / (1 + i + j) as f64
                });
            }
            cp.push(ri.len());
        }
        SymmetricMatrix::from_upper_parts(n, cp, ri, v).unwrap()
    }

    /// Both Galerkin algorithms (one pass for rows of P with ≤ ONE_PASS_MAX_P_ROW entries, P's
    /// rows in two fixed slots when they have ≤ 2; two steps for longer ones) against the dense
    /// Pᵀ A P.
    #[test]
    fn galerkin_one_pass_and_two_step_products_equal_the_dense_triple_product() {
        let (n, nc) = (13, ONE_PASS_MAX_P_ROW + 2);
        let a = banded(n);
        let csr = CsrMatrix::from_symmetric(&a).unwrap();
        let short: Vec<Vec<(usize, f64)>> = (0..n)
            .map(|i| {
                vec![
                    (i * nc / n, 0.5 + 0.1 * i as f64),
                    ((i * nc / n + 1) % nc, 0.25),
                ]
            })
            .collect();
        // Three entries per row: one pass, without the two fixed slots.
        let three: Vec<Vec<(usize, f64)>> = (0..n)
            .map(|i| {
                let c = i * nc / n;
                vec![
                    (c, 0.5),
                    ((c + 2) % nc, 0.125 * i as f64),
                    ((c + 4) % nc, 0.3),
                ]
            })
            .collect();
        let long: Vec<Vec<(usize, f64)>> = (0..n)
            .map(|i| (0..nc).map(|c| (c, 1.0 / (1 + i + 2 * c) as f64)).collect())
            .collect();
        for (rows, name) in [
            (short, "one pass, two slots"),
            (three, "one pass, three per row"),
            (long, "two steps"),
        ] {
            let p = RowSparse::from_rows(nc, &rows).unwrap();
            assert_eq!(
                p.max_row_len() <= ONE_PASS_MAX_P_ROW,
                name.starts_with("one pass"),
                "{name}: the test P selects the algorithm it is named after"
            );
            let ac = csr.galerkin(&p, &p.transpose()).unwrap();
            for c in 0..nc {
                for r in 0..=c {
                    let mut dense = 0.0;
                    for i in 0..n {
                        for j in 0..n {
                            let pi: f64 = p.row(i).filter(|e| e.0 == r).map(|e| e.1).sum();
                            let pj: f64 = p.row(j).filter(|e| e.0 == c).map(|e| e.1).sum();
                            dense += pi * a.get(i.min(j), i.max(j)) * pj;
                        }
                    }
                    let got = ac.get(r, c);
                    assert!(
                        (got - dense).abs() <= 1e-13 * dense.abs().max(1.0),
                        "{name}: coarse entry ({r},{c}) = {got}, dense {dense}"
                    );
                }
            }
        }
    }

    #[test]
    fn galerkin_product_equals_the_dense_triple_product() {
        let a = small();
        let csr = CsrMatrix::from_symmetric(&a).unwrap();
        // P = [[1,0],[0.5,0.5],[0,1]]
        let p = RowSparse::from_rows(
            2,
            &[vec![(0, 1.0)], vec![(0, 0.5), (1, 0.5)], vec![(1, 1.0)]],
        )
        .unwrap();
        let ac = csr.galerkin(&p, &p.transpose()).unwrap();
        // Pᵀ A P by hand: A P = [[4.5,0.5],[3.5,4.5],[1,7]]; Pᵀ (A P) = [[6.25,2.75],[2.75,9.25]].
        for (i, j, v) in [(0, 0, 6.25), (0, 1, 2.75), (1, 1, 9.25)] {
            assert!((ac.get(i, j) - v).abs() < 1e-14, "coarse entry ({i},{j})");
        }
    }
}
