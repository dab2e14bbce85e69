//! Fill-reducing orderings: METIS nested dissection (through `metis-sys`), faer's AMD, or none.
//!
//! All `unsafe` code of the crate lives in this file (the METIS FFI call).

use metis_sys::{
    METIS_NOPTIONS, METIS_NodeND, METIS_SetDefaultOptions, idx_t,
    moptions_et_METIS_OPTION_COMPRESS, moptions_et_METIS_OPTION_NUMBERING, rstatus_et_METIS_OK,
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

/// Order-independent hash contribution of vertex `v` to a neighbourhood hash (splitmix64).
fn vertex_hash(v: usize) -> u64 {
    let mut z = (v as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Supervariables of a symmetric pattern: groups of unknowns with the same closed neighbourhood
/// (row pattern including the diagonal), e.g. the x, y, z unknowns of one mesh node. Each group
/// is a clique that nested dissection never separates, so ordering the graph of groups with
/// their sizes as vertex weights orders the whole matrix (Ashcraft 1995, "Compressed graphs and
/// the minimum degree algorithm"; METIS' own `CompressGraph` does the same inside, but then
/// doubles its separator trials, METIS 5.1 `ometis.c`).
///
/// Groups are found by (degree, 64-bit hash of the closed neighbourhood); a hash collision could
/// only merge two unrelated unknowns into one ordering vertex, which changes the fill, never the
/// correctness of the factorisation (any permutation is a valid ordering).
struct Supervariables {
    /// group[v]: the group of unknown v (0..count).
    group: Vec<usize>,
    /// Members of group g: members[start[g]..start[g + 1]], increasing.
    start: Vec<usize>,
    members: Vec<usize>,
}

impl Supervariables {
    fn find(matrix: &SymmetricMatrix) -> Self {
        let n = matrix.dim();
        let (cp, ri) = (matrix.col_ptr(), matrix.row_idx());
        let mut hash: Vec<u64> = (0..n).map(vertex_hash).collect();
        let mut degree = vec![0usize; n];
        for j in 0..n {
            for &i in &ri[cp[j]..cp[j + 1]] {
                if i != j {
                    hash[i] = hash[i].wrapping_add(vertex_hash(j));
                    hash[j] = hash[j].wrapping_add(vertex_hash(i));
                    degree[i] += 1;
                    degree[j] += 1;
                }
            }
        }
        let mut index = std::collections::HashMap::with_capacity(n);
        let mut group = Vec::with_capacity(n);
        let mut size = Vec::new();
        for v in 0..n {
            let g = *index.entry((degree[v], hash[v])).or_insert(size.len());
            if g == size.len() {
                size.push(0usize);
            }
            size[g] += 1;
            group.push(g);
        }
        let mut start = Vec::with_capacity(size.len() + 1);
        start.push(0);
        for s in &size {
            start.push(start[start.len() - 1] + s);
        }
        let mut fill = start[..size.len()].to_vec();
        let mut members = vec![0usize; n];
        for (v, &g) in group.iter().enumerate() {
            members[fill[g]] = v;
            fill[g] += 1;
        }
        Self {
            group,
            start,
            members,
        }
    }

    fn count(&self) -> usize {
        self.start.len() - 1
    }

    fn representative(&self, g: usize) -> usize {
        self.members[self.start[g]]
    }
}

/// METIS' CSR arrays (no self loops) of the graph of supervariables and its vertex weights
/// (group sizes), or `None` if it does not fit METIS' 32-bit `idx_t`. Two groups are adjacent
/// iff their representatives (first members) are: members share their closed neighbourhood.
fn metis_graph(
    matrix: &SymmetricMatrix,
    groups: &Supervariables,
) -> Option<(Vec<idx_t>, Vec<idx_t>, Vec<idx_t>)> {
    let count = groups.count();
    let (cp, ri) = (matrix.col_ptr(), matrix.row_idx());
    let is_rep = |v: usize| groups.representative(groups.group[v]) == v;
    let edges = || {
        (0..count).flat_map(move |gj| {
            let j = groups.representative(gj);
            ri[cp[j]..cp[j + 1]]
                .iter()
                .filter(move |&&i| i != j && is_rep(i))
                .map(move |&i| (groups.group[i], gj))
        })
    };
    let mut degree = vec![0usize; count];
    for (gi, gj) in edges() {
        degree[gi] += 1;
        degree[gj] += 1;
    }
    let total: usize = degree.iter().sum();
    if total > idx_t::MAX as usize || count > idx_t::MAX as usize {
        return None;
    }
    let mut xadj = Vec::with_capacity(count + 1);
    xadj.push(0 as idx_t);
    let mut acc = 0usize;
    for d in &degree {
        acc += d;
        xadj.push(acc as idx_t);
    }
    let mut fill: Vec<usize> = xadj[..count].iter().map(|&v| v as usize).collect();
    let mut adjncy = vec![0 as idx_t; total];
    for (gi, gj) in edges() {
        adjncy[fill[gi]] = gj as idx_t;
        fill[gi] += 1;
        adjncy[fill[gj]] = gi as idx_t;
        fill[gj] += 1;
    }
    let vwgt = (0..count)
        .map(|g| (groups.start[g + 1] - groups.start[g]) as idx_t)
        .collect();
    Some((xadj, adjncy, vwgt))
}

/// Serialises the calls into METIS (see [`metis_nested_dissection`]).
static METIS_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

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
    let groups = Supervariables::find(matrix);
    let (mut xadj, mut adjncy, mut vwgt) = metis_graph(matrix, &groups)?;
    let count = groups.count();
    let mut nvtxs = count as idx_t;
    let mut options = [0 as idx_t; METIS_NOPTIONS as usize];
    let mut perm = vec![0 as idx_t; count];
    let mut iperm = vec![0 as idx_t; count];
    // SAFETY: `options` has METIS_NOPTIONS entries as METIS_SetDefaultOptions requires.
    let status = unsafe { METIS_SetDefaultOptions(options.as_mut_ptr()) };
    if status != rstatus_et_METIS_OK {
        return None;
    }
    options[moptions_et_METIS_OPTION_NUMBERING as usize] = 0;
    // The graph is compressed already (supervariables above).
    options[moptions_et_METIS_OPTION_COMPRESS as usize] = 0;
    // METIS draws from GKlib's random generator, whose state is one process-wide static (not
    // thread-local): two orderings computed at once (parallel sweep points, parallel tests)
    // would interleave their draws and give run-dependent permutations, hence run-dependent
    // factor bits. One METIS call at a time keeps every ordering a function of its graph.
    let _metis = METIS_LOCK
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    // SAFETY: with m = `count` vertices: `xadj` has m+1 entries, `adjncy` has xadj[m] entries
    // with values in 0..m (a symmetric graph without self loops, built above), `vwgt`, `perm`
    // and `iperm` have m entries; all buffers outlive the call and METIS does not retain the
    // pointers.
    let status = unsafe {
        METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            vwgt.as_mut_ptr(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != rstatus_et_METIS_OK {
        return None;
    }
    // METIS: row i of the permuted matrix is row perm[i] of the original, i.e. perm = forward;
    // each group expands to its members, in their original order.
    let forward: Vec<usize> = perm
        .iter()
        .flat_map(|&g| {
            let g = g as usize;
            groups.members[groups.start[g.min(count - 1)]..groups.start[g.min(count - 1) + 1]]
                .iter()
                .copied()
        })
        .collect();
    let mut inverse = vec![usize::MAX; n];
    for (new, &old) in forward.iter().enumerate() {
        inverse[old] = new;
    }
    let valid = forward.len() == n && inverse.iter().all(|&v| v < n);
    valid.then_some(Permutation { forward, inverse })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Upper triangle of a 3-unknowns-per-node matrix of an n-node chain with second-neighbour
    /// coupling (every unknown of node a coupled to every unknown of nodes a ± 1, a ± 2).
    fn block_chain(nodes: usize) -> SymmetricMatrix {
        let n = 3 * nodes;
        let (mut col_ptr, mut rows, mut vals) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            let node = j / 3;
            for i in 3 * node.saturating_sub(2)..=j {
                rows.push(i);
                vals.push(if i == j { 20.0 } else { -0.5 });
            }
            col_ptr.push(rows.len());
        }
        SymmetricMatrix::from_upper_parts(n, col_ptr, rows, vals).unwrap()
    }

    #[test]
    fn the_unknowns_of_one_node_form_one_supervariable_and_stay_together_in_the_ordering() {
        let a = block_chain(50);
        let groups = Supervariables::find(&a);
        assert_eq!(groups.count(), 50, "one supervariable per node");
        for v in 0..a.dim() {
            assert_eq!(
                groups.group[v],
                groups.group[3 * (v / 3)],
                "unknown {v}'s group"
            );
        }
        let p = metis_nested_dissection(&a).expect("METIS ordering");
        for (new, &old) in p.forward.iter().enumerate() {
            assert_eq!(p.inverse[old], new, "inverse permutation");
        }
        for triple in p.forward.chunks(3) {
            assert!(
                triple.iter().all(|&v| v / 3 == triple[0] / 3),
                "the three unknowns of a node are ordered together: {triple:?}"
            );
        }
    }
}
