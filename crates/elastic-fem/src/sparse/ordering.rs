//! Fill-reducing orderings: METIS nested dissection (through `metis-sys`), faer's AMD, or none.
//!
//! All `unsafe` code of the crate lives in this file (the METIS FFI call).

use metis_sys::{
    METIS_NOPTIONS, METIS_NodeND, METIS_SetDefaultOptions, idx_t,
    moptions_et_METIS_OPTION_NUMBERING, rstatus_et_METIS_OK,
};

use super::matrix::SymmetricMatrix;

/// Which fill-reducing ordering the symbolic Cholesky uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Ordering {
    /// METIS nested dissection (`METIS_NodeND`); falls back to AMD if METIS fails or the graph
    /// exceeds METIS' 32-bit index range. Best for 3D meshes.
    #[default]
    Metis,
    /// faer's approximate minimum degree.
    Amd,
    /// No reordering (only sensible for tiny or banded matrices).
    Natural,
}

/// A permutation with `forward[new] = old` and `inverse[old] = new` (the convention of both
/// METIS' `perm`/`iperm` and faer's `PermRef`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Permutation {
    /// forward[new index] = old index.
    pub forward: Vec<usize>,
    /// inverse[old index] = new index.
    pub inverse: Vec<usize>,
}

/// Adjacency graph (no self loops) of a symmetric matrix in METIS' CSR arrays, or `None` if it
/// does not fit METIS' 32-bit `idx_t`.
fn metis_graph(matrix: &SymmetricMatrix) -> Option<(Vec<idx_t>, Vec<idx_t>)> {
    let n = matrix.dim();
    let (cp, ri) = (matrix.col_ptr(), matrix.row_idx());
    let mut degree = vec![0usize; n];
    for j in 0..n {
        for &i in &ri[cp[j]..cp[j + 1]] {
            if i != j {
                degree[i] += 1;
                degree[j] += 1;
            }
        }
    }
    let total: usize = degree.iter().sum();
    if total > idx_t::MAX as usize || n > idx_t::MAX as usize {
        return None;
    }
    let mut xadj = Vec::with_capacity(n + 1);
    xadj.push(0 as idx_t);
    let mut acc = 0usize;
    for d in &degree {
        acc += d;
        xadj.push(acc as idx_t);
    }
    let mut fill: Vec<usize> = xadj[..n].iter().map(|&v| v as usize).collect();
    let mut adjncy = vec![0 as idx_t; total];
    for j in 0..n {
        for &i in &ri[cp[j]..cp[j + 1]] {
            if i != j {
                adjncy[fill[i]] = j as idx_t;
                fill[i] += 1;
                adjncy[fill[j]] = i as idx_t;
                fill[j] += 1;
            }
        }
    }
    Some((xadj, adjncy))
}

/// METIS nested-dissection ordering of the matrix graph. `None` if METIS cannot be used
/// (graph too large for 32-bit indices, or METIS reports an error).
pub fn metis_nested_dissection(matrix: &SymmetricMatrix) -> Option<Permutation> {
    let n = matrix.dim();
    if n <= 1 {
        return Some(Permutation {
            forward: (0..n).collect(),
            inverse: (0..n).collect(),
        });
    }
    let (mut xadj, mut adjncy) = metis_graph(matrix)?;
    let mut nvtxs = n as idx_t;
    let mut options = [0 as idx_t; METIS_NOPTIONS as usize];
    let mut perm = vec![0 as idx_t; n];
    let mut iperm = vec![0 as idx_t; n];
    // SAFETY: `options` has METIS_NOPTIONS entries as METIS_SetDefaultOptions requires.
    let status = unsafe { METIS_SetDefaultOptions(options.as_mut_ptr()) };
    if status != rstatus_et_METIS_OK {
        return None;
    }
    options[moptions_et_METIS_OPTION_NUMBERING as usize] = 0;
    // SAFETY: `xadj` has n+1 entries, `adjncy` has xadj[n] entries with values in 0..n (a
    // symmetric graph without self loops, built above), `perm` and `iperm` have n entries;
    // vertex weights are absent (null is allowed by METIS); all buffers outlive the call and
    // METIS does not retain the pointers.
    let status = unsafe {
        METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != rstatus_et_METIS_OK {
        return None;
    }
    // METIS: row i of the permuted matrix is row perm[i] of the original, i.e. perm = forward.
    let forward: Vec<usize> = perm.iter().map(|&v| v as usize).collect();
    let inverse: Vec<usize> = iperm.iter().map(|&v| v as usize).collect();
    let valid = forward.len() == n
        && forward
            .iter()
            .enumerate()
            .all(|(new, &old)| old < n && inverse[old] == new);
    valid.then_some(Permutation { forward, inverse })
}
