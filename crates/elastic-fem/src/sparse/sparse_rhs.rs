//! Bᵀ K⁻¹ B for a few sparse columns B from the factor, with forward solves on their
//! elimination-tree paths only.
//!
//! With P K Pᵀ = L Lᵀ, Bᵀ K⁻¹ B = (L⁻¹ P B)ᵀ (L⁻¹ P B) = Yᵀ Y: one forward solve per column and
//! no backward solve. A column y = L⁻¹ b is nonzero only on the *reach* of b's rows, the union
//! of their paths to the root of L's elimination tree (Gilbert 1994, "Predicting structure in
//! sparse matrix computations", SIAM J. Matrix Anal. Appl. 15; Davis 2006, "Direct Methods for
//! Sparse Linear Systems", §3.2 and §4.1). So the solve visits only the supernodes on those
//! paths, each with only the columns that reach it (a dense triangular solve and a dense
//! update on that column subset), and Yᵀ Y = Σ_k Y_kᵀ Y_k sums over the supernode row blocks.
//! Cost Σ_k (w_k² + 2 p_k w_k + w_k a_k) a_k multiply–adds (w_k columns, p_k rows below the
//! diagonal block, a_k active right-hand sides of supernode k) against 2 a nnz(L) for a full
//! solves, forward and backward, of a columns.
//!
//! Range: any factor of this module (simplicial columns are supernodes of width one); columns
//! with rows spread over the whole tree cost as much as a forward solve. Sequential and in a
//! fixed order: the same bits for any thread count.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::{Accum, MatMut, MatRef, Par};
use nalgebra::DMatrix;

use super::factor::NumericCholesky;
use crate::error::{FemError, FemResult};

/// A sparse column: (row in the matrix's own numbering, value) pairs; a row may repeat (the
/// values add).
pub type SparseColumn = Vec<(usize, f64)>;

/// Work of one [`NumericCholesky::inverse_gram`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InverseGramStats {
    /// Supernodes on the columns' paths.
    pub supernodes_visited: usize,
    /// All supernodes of the factor (columns of a simplicial factor).
    pub supernodes_total: usize,
    /// Multiply–adds of the partial forward solves and the Gram sums.
    pub flops: f64,
    /// Values of Y = L⁻¹ P B held at once (8 bytes each).
    pub stored_values: usize,
}

/// One supernode of L: columns begin..begin + width, the rows `pattern` below its diagonal
/// block, and its values column-major with (width + pattern.len()) rows.
struct Supernode<'a> {
    begin: usize,
    width: usize,
    pattern: &'a [usize],
    values: &'a [f64],
}

impl Supernode<'_> {
    fn rows(&self) -> usize {
        self.width + self.pattern.len()
    }
}

impl NumericCholesky {
    /// The supernodes of L in elimination order (simplicial columns as supernodes of width 1).
    fn supernodes(&self) -> FemResult<Vec<Supernode<'_>>> {
        match self.symbolic.faer().raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (cp, ri) = (s.col_ptr(), s.row_idx());
                (0..self.symbolic.dim())
                    .map(|c| {
                        if ri[cp[c]] != c {
                            return Err(FemError::SparseBackend(format!(
                                "column {c} of the simplicial factor does not start at its diagonal"
                            )));
                        }
                        Ok(Supernode {
                            begin: c,
                            width: 1,
                            pattern: &ri[cp[c] + 1..cp[c + 1]],
                            values: &self.values[cp[c]..cp[c + 1]],
                        })
                    })
                    .collect()
            }
            SymbolicCholeskyRaw::Supernodal(s) => Ok((0..s.n_supernodes())
                .map(|k| {
                    let start = s.col_ptr_for_row_idx()[k];
                    Supernode {
                        begin: s.supernode_begin()[k],
                        width: s.supernode_end()[k] - s.supernode_begin()[k],
                        pattern: &s.row_idx()[start..start + s.nnz_per_super()[k]],
                        values: &self.values[s.col_ptr_for_val()[k]..s.col_ptr_for_val()[k + 1]],
                    }
                })
                .collect()),
        }
    }

    /// Bᵀ K⁻¹ B (m × m, symmetric) for the m sparse columns of B, with the work done; see the
    /// module doc. Fails on a row out of range or a non-finite result.
    pub fn inverse_gram(
        &self,
        columns: &[SparseColumn],
    ) -> FemResult<(DMatrix<f64>, InverseGramStats)> {
        let dim = self.symbolic.dim();
        let nodes = self.supernodes()?;
        let inverse_perm: Vec<usize> = match self.symbolic.faer().perm() {
            Some(p) => p.arrays().1.to_vec(),
            None => (0..dim).collect(),
        };
        let mut owner = vec![0usize; dim];
        for (k, node) in nodes.iter().enumerate() {
            owner[node.begin..node.begin + node.width].fill(k);
        }
        let parent: Vec<Option<usize>> = nodes
            .iter()
            .map(|node| node.pattern.iter().min().map(|&r| owner[r]))
            .collect();
        let active = active_columns(columns, dim, (&owner, &inverse_perm, &parent))?;
        // Y block of supernode k: width × |active[k]| column-major at offset[k].
        let mut offset = Vec::with_capacity(nodes.len() + 1);
        offset.push(0usize);
        for (node, a) in nodes.iter().zip(&active) {
            offset.push(offset.last().unwrap() + node.width * a.len());
        }
        let mut y = vec![0.0; *offset.last().unwrap()];
        for (c, column) in columns.iter().enumerate() {
            for &(row, value) in column {
                let r = inverse_perm[row];
                let k = owner[r];
                let pos = active[k]
                    .binary_search(&c)
                    .expect("a column is active at its rows");
                y[offset[k] + pos * nodes[k].width + (r - nodes[k].begin)] += value;
            }
        }
        let mut gram = DMatrix::zeros(columns.len(), columns.len());
        let mut stats = InverseGramStats {
            stored_values: y.len(),
            supernodes_total: nodes.len(),
            ..Default::default()
        };
        for (k, node) in nodes.iter().enumerate() {
            if active[k].is_empty() {
                continue;
            }
            let (done, ancestors) = y.split_at_mut(offset[k + 1]);
            let own = &mut done[offset[k]..];
            stats.supernodes_visited += 1;
            stats.flops += eliminate(node, &active[k], own, &mut gram);
            if node.pattern.is_empty() {
                continue;
            }
            let update = below_diagonal_product(node, own, active[k].len());
            stats.flops += (node.pattern.len() * node.width * active[k].len()) as f64;
            scatter_update(
                node, &active, k, &update, ancestors, &offset, &owner, &nodes,
            );
        }
        if let Some(bad) = gram.iter().position(|v| !v.is_finite()) {
            return Err(FemError::NonFiniteSolution {
                unknown: bad % columns.len().max(1),
            });
        }
        Ok(((&gram + gram.transpose()) * 0.5, stats))
    }
}

/// Active columns of every supernode (ascending): the columns whose reach (the supernodes of
/// their rows and the ancestors of those in the elimination tree) holds it. `owner` maps a
/// permuted row to its supernode, `inverse_perm` a row to its permuted row, `parent` a
/// supernode to its parent. Fails on a row out of range.
fn active_columns(
    columns: &[SparseColumn],
    dim: usize,
    (owner, inverse_perm, parent): (&[usize], &[usize], &[Option<usize>]),
) -> FemResult<Vec<Vec<usize>>> {
    let mut active: Vec<Vec<usize>> = vec![Vec::new(); parent.len()];
    let mut stamp = vec![usize::MAX; parent.len()];
    for (c, column) in columns.iter().enumerate() {
        for &(row, _) in column {
            if row >= dim {
                return Err(FemError::SparseBackend(format!(
                    "row {row} of sparse column {c} is out of range (dim {dim})"
                )));
            }
            let mut k = Some(owner[inverse_perm[row]]);
            while let Some(s) = k.filter(|&s| stamp[s] != c) {
                stamp[s] = c;
                active[s].push(c);
                k = parent[s];
            }
        }
    }
    Ok(active)
}

/// Solves L_kk Y_k = (accumulated right-hand side) in place and adds Y_kᵀ Y_k to the Gram matrix
/// on the active columns. Returns the multiply–adds.
fn eliminate(
    node: &Supernode<'_>,
    active: &[usize],
    own: &mut [f64],
    gram: &mut DMatrix<f64>,
) -> f64 {
    let (w, a) = (node.width, active.len());
    let diagonal = MatRef::from_column_major_slice_with_stride(node.values, w, w, node.rows());
    let mut block = MatMut::from_column_major_slice_mut(own, w, a);
    solve_lower_triangular_in_place(diagonal, block.as_mut(), Par::Seq);
    let mut product = faer::Mat::<f64>::zeros(a, a);
    matmul(
        product.as_mut(),
        Accum::Replace,
        block.as_ref().transpose(),
        block.as_ref(),
        1.0,
        Par::Seq,
    );
    for (j, &cj) in active.iter().enumerate() {
        for (i, &ci) in active.iter().enumerate() {
            gram[(ci, cj)] += product[(i, j)];
        }
    }
    ((w * w * a) / 2 + w * a * a) as f64
}

/// L_pk Y_k: the update of the rows below supernode k's diagonal block (pattern × active).
fn below_diagonal_product(node: &Supernode<'_>, own: &[f64], active: usize) -> faer::Mat<f64> {
    let (w, p) = (node.width, node.pattern.len());
    let below = MatRef::from_column_major_slice_with_stride(&node.values[w..], p, w, node.rows());
    let block = MatRef::from_column_major_slice(own, w, active);
    let mut update = faer::Mat::<f64>::zeros(p, active);
    matmul(update.as_mut(), Accum::Replace, below, block, 1.0, Par::Seq);
    update
}

/// Subtracts supernode k's update from its ancestors' Y blocks (`ancestors` starts at
/// offset[k + 1]); the active columns of k are a subset of every ancestor's.
#[allow(clippy::too_many_arguments)]
fn scatter_update(
    node: &Supernode<'_>,
    active: &[Vec<usize>],
    k: usize,
    update: &faer::Mat<f64>,
    ancestors: &mut [f64],
    offset: &[usize],
    owner: &[usize],
    nodes: &[Supernode<'_>],
) {
    let base = offset[k + 1];
    let mut target = usize::MAX;
    let mut position: Vec<usize> = Vec::with_capacity(active[k].len());
    for (idx, &r) in node.pattern.iter().enumerate() {
        let p = owner[r];
        if p != target {
            target = p;
            position.clear();
            let mut q = 0;
            for &c in &active[k] {
                while active[p][q] != c {
                    q += 1;
                }
                position.push(q);
            }
        }
        let (start, w_p) = (offset[p] - base + (r - nodes[p].begin), nodes[p].width);
        for (i, &q) in position.iter().enumerate() {
            ancestors[start + q * w_p] -= update[(idx, i)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sparse::{Ordering, SymbolicCholesky, SymmetricMatrix};

    use crate::sparse::test_matrices::laplacian;

    /// Columns averaging a few scattered unknowns each (like a disk's x displacements), one unit
    /// column, and one column sharing rows with another.
    fn columns(dim: usize) -> Vec<SparseColumn> {
        let mut out: Vec<SparseColumn> = (0..7)
            .map(|c| {
                (0..5)
                    .map(|i| ((c * 977 + i * 131 + 3) % dim, 0.2 + 0.1 * i as f64))
                    .collect()
            })
            .collect();
        out.push(vec![(dim - 1, 1.0)]);
        out.push(vec![(out[2][1].0, -0.5), (11, 2.0), (11, 1.0)]);
        out
    }

    fn check_against_full_solves(a: &SymmetricMatrix, ordering: Ordering) -> bool {
        let dim = a.dim();
        let symbolic = SymbolicCholesky::analyze(a, ordering).unwrap();
        let numeric = symbolic.factor(a).unwrap();
        let b = columns(dim);
        let (gram, stats) = numeric.inverse_gram(&b).unwrap();
        assert!(
            stats.flops > 0.0 && stats.supernodes_visited > 0,
            "work counted"
        );
        for (j, bj) in b.iter().enumerate() {
            let mut x = vec![0.0; dim];
            for &(r, v) in bj {
                x[r] += v;
            }
            numeric.solve_in_place(&mut x).unwrap();
            for (i, bi) in b.iter().enumerate() {
                let reference: f64 = bi.iter().map(|&(r, v)| v * x[r]).sum();
                assert!(
                    (gram[(i, j)] - reference).abs() < 1e-13 * gram[(j, j)].abs().max(1e-300),
                    "{ordering:?}: (Bᵀ K⁻¹ B)[{i}, {j}] from partial forward solves {} vs full solves {reference}",
                    gram[(i, j)]
                );
            }
        }
        symbolic.is_supernodal()
    }

    #[test]
    fn the_inverse_gram_from_partial_forward_solves_equals_the_one_from_full_solves() {
        let plate = laplacian(30, 30, 1);
        for ordering in [Ordering::Metis, Ordering::Amd, Ordering::Natural] {
            check_against_full_solves(&plate, ordering);
        }
        let cube = laplacian(18, 18, 18);
        assert!(
            check_against_full_solves(&cube, Ordering::Metis),
            "the 3D grid's factor should be supernodal (the branch under test)"
        );
    }

    #[test]
    fn the_partial_solves_skip_the_supernodes_off_the_columns_paths() {
        let cube = laplacian(18, 18, 18);
        let numeric = SymbolicCholesky::analyze(&cube, Ordering::Metis)
            .unwrap()
            .factor(&cube)
            .unwrap();
        let (_, one) = numeric.inverse_gram(&[vec![(0, 1.0)]]).unwrap();
        let (_, all) = numeric.inverse_gram(&columns(cube.dim())).unwrap();
        let total = one.supernodes_total;
        assert!(
            one.supernodes_visited < total / 4 && one.supernodes_visited < all.supernodes_visited,
            "supernodes visited for one unit column: {} of {total} ({} for nine columns)",
            one.supernodes_visited,
            all.supernodes_visited
        );
    }

    #[test]
    fn a_row_out_of_range_is_refused() {
        let a = laplacian(4, 4, 1);
        let numeric = SymbolicCholesky::analyze(&a, Ordering::Amd)
            .unwrap()
            .factor(&a)
            .unwrap();
        assert!(numeric.inverse_gram(&[vec![(16, 1.0)]]).is_err());
    }
}
