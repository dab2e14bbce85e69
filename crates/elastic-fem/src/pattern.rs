//! Symbolic assembly: the sparsity pattern of the global stiffness (upper triangle, node-blocked
//! 3×3), the per-element scatter map, and an element colouring for parallel assembly. Built
//! once per mesh; numeric assembly ([`crate::assembly`]) reuses it for any material.

use rayon::prelude::*;

use crate::locality::morton_key;
use crate::model::{Connectivity, Model};

/// Nodes per rayon task when filling the row indices of the pattern. Dimensionless; default 256.
pub const PATTERN_NODES_PER_TASK: usize = 256;

/// Marker in the scatter map for node pairs stored through their transpose.
pub(crate) const LOWER_PAIR: u32 = u32::MAX;

/// Sparsity pattern of K (upper triangle in CSC; DOF `3 n + c`), plus the element scatter map.
///
/// For an element with nodes n_a and local pair (a, b) with n_a ≤ n_b, the scatter map holds
/// `rank` = position of n_a among the sorted neighbours ≤ n_b of node n_b. Then entry
/// (3 n_a + r, 3 n_b + c) of K sits at `col_ptr[3 n_b + c] + 3 rank + r` (r ≤ c when a = b).
#[derive(Debug, Clone)]
pub struct StiffnessPattern {
    node_count: usize,
    element_count: usize,
    nodes_per_element: usize,
    pub(crate) col_ptr: Vec<usize>,
    pub(crate) row_idx: Vec<usize>,
    /// `nodes_per_element²` entries per element (row-major over local pairs (a, b)).
    pub(crate) scatter: Vec<u32>,
    /// Elements in spatial blocks, coloured for parallel assembly.
    pub(crate) blocks: AssemblyBlocks,
}

/// Sorted neighbour lists (nodes ≤ self, self included) of every node, as CSR.
fn lower_node_neighbours(node_count: usize, connectivity: &Connectivity) -> (Vec<usize>, Vec<u32>) {
    let npe = connectivity.nodes_per_element();
    let mut count = vec![0usize; node_count];
    for e in 0..connectivity.len() {
        let en = connectivity.element_nodes(e);
        for &b in en {
            count[b] += en.iter().filter(|&&a| a <= b).count();
        }
    }
    let mut ptr = Vec::with_capacity(node_count + 1);
    ptr.push(0usize);
    for c in &count {
        ptr.push(ptr.last().copied().unwrap_or(0) + c);
    }
    let mut fill = ptr[..node_count].to_vec();
    let mut idx = vec![0u32; ptr[node_count]];
    for e in 0..connectivity.len() {
        let en = connectivity.element_nodes(e);
        for &b in en {
            for &a in en {
                if a <= b {
                    idx[fill[b]] = a as u32;
                    fill[b] += 1;
                }
            }
        }
    }
    debug_assert!(npe == 4 || npe == 10);
    // Sort and deduplicate each node's list (in parallel), then compact.
    let mut lists: Vec<Vec<u32>> = (0..node_count)
        .into_par_iter()
        .map(|b| {
            let mut l = idx[ptr[b]..ptr[b + 1]].to_vec();
            l.sort_unstable();
            l.dedup();
            if l.last() != Some(&(b as u32)) {
                // A node in no element still gets its diagonal block.
                l.push(b as u32);
            }
            l
        })
        .collect();
    let mut out_ptr = Vec::with_capacity(node_count + 1);
    out_ptr.push(0usize);
    let total: usize = lists.iter().map(Vec::len).sum();
    let mut out_idx = Vec::with_capacity(total);
    for l in lists.iter_mut() {
        out_idx.append(l);
        out_ptr.push(out_idx.len());
    }
    (out_ptr, out_idx)
}

/// Elements per assembly block: a run of elements close in space, assembled in order by one
/// thread. Large enough for the scatter to stay in cache and to amortise scheduling, small
/// enough for ≥ 10 blocks per colour at 10⁴ elements. Dimensionless; default 64.
pub const ASSEMBLY_BLOCK_ELEMENTS: usize = 64;

/// Elements in Morton order of their vertex centroids (ties by index): neighbours in space are
/// neighbours in the order, whatever order the mesher wrote them in.
fn spatial_order(model: &Model) -> Vec<u32> {
    let connectivity = model.connectivity();
    let nodes = model.nodes();
    let (lo, hi) = model.bounding_box();
    let mut keyed: Vec<(u64, u32)> = (0..connectivity.len())
        .into_par_iter()
        .map(|e| {
            let vertices = &connectivity.element_nodes(e)[..4];
            let centroid =
                std::array::from_fn(|c| vertices.iter().map(|&n| nodes[n][c]).sum::<f64>() / 4.0);
            (morton_key(centroid, lo, hi), e as u32)
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, e)| e).collect()
}

/// Elements cut into blocks of [`ASSEMBLY_BLOCK_ELEMENTS`] consecutive elements in space, and
/// the blocks coloured so that no two blocks of a colour share a node. A colour's blocks are
/// assembled in parallel, each by one thread in element order; every matrix entry then sums its
/// contributions in the same order (colour by colour, element by element within a block)
/// whatever the thread count.
#[derive(Debug, Clone)]
pub(crate) struct AssemblyBlocks {
    /// Element indices, block after block.
    pub(crate) elements: Vec<u32>,
    /// Block `b` holds `elements[block_ptr[b]..block_ptr[b + 1]]`.
    pub(crate) block_ptr: Vec<usize>,
    /// Block indices per colour.
    pub(crate) colors: Vec<Vec<u32>>,
}

impl AssemblyBlocks {
    /// The elements of block `b`.
    pub(crate) fn block(&self, b: u32) -> &[u32] {
        &self.elements[self.block_ptr[b as usize]..self.block_ptr[b as usize + 1]]
    }
}

/// Greedy block colouring with a 128-bit colour mask per node; blocks that find no free colour
/// among 128 go to extra colours of one block each at the end.
fn color_blocks(model: &Model) -> AssemblyBlocks {
    let connectivity = model.connectivity();
    let elements = spatial_order(model);
    let block_ptr: Vec<usize> = (0..elements.len())
        .step_by(ASSEMBLY_BLOCK_ELEMENTS)
        .chain(std::iter::once(elements.len()))
        .collect();
    let mut node_mask = vec![0u128; model.node_count()];
    let mut colors: Vec<Vec<u32>> = Vec::new();
    let mut overflow = Vec::new();
    for (b, w) in block_ptr.windows(2).enumerate() {
        let block_nodes = || {
            elements[w[0]..w[1]]
                .iter()
                .flat_map(|&e| connectivity.element_nodes(e as usize))
        };
        let used = block_nodes().fold(0u128, |m, &n| m | node_mask[n]);
        if used == u128::MAX {
            overflow.push(b as u32);
            continue;
        }
        let c = (!used).trailing_zeros() as usize;
        block_nodes().for_each(|&n| node_mask[n] |= 1u128 << c);
        if colors.len() <= c {
            colors.resize_with(c + 1, Vec::new);
        }
        colors[c].push(b as u32);
    }
    colors.extend(overflow.into_iter().map(|b| vec![b]));
    AssemblyBlocks {
        elements,
        block_ptr,
        colors,
    }
}

impl StiffnessPattern {
    /// Builds the pattern of the model's stiffness matrix.
    pub fn build(model: &Model) -> Self {
        let node_count = model.node_count();
        let connectivity = model.connectivity();
        let npe = connectivity.nodes_per_element();
        let (nptr, nidx) = lower_node_neighbours(node_count, connectivity);

        // DOF pattern: column 3B + c holds rows 3A..3A+2 for neighbours A < B and 3B..=3B+c.
        let n_dofs = 3 * node_count;
        let mut col_ptr = Vec::with_capacity(n_dofs + 1);
        col_ptr.push(0usize);
        for b in 0..node_count {
            let lower = nptr[b + 1] - nptr[b] - 1;
            for c in 0..3 {
                col_ptr.push(col_ptr.last().copied().unwrap_or(0) + 3 * lower + c + 1);
            }
        }
        // Rows of the three columns of every node (nodes in parallel; contiguous in row_idx).
        let mut row_idx = vec![0usize; col_ptr[n_dofs]];
        let mut per_node: Vec<&mut [usize]> = Vec::with_capacity(node_count);
        let mut rest = row_idx.as_mut_slice();
        for b in 0..node_count {
            let (block, tail) =
                std::mem::take(&mut rest).split_at_mut(col_ptr[3 * b + 3] - col_ptr[3 * b]);
            per_node.push(block);
            rest = tail;
        }
        per_node
            .into_par_iter()
            .enumerate()
            .with_min_len(PATTERN_NODES_PER_TASK)
            .for_each(|(b, out)| {
                let neighbours = &nidx[nptr[b]..nptr[b + 1]];
                let mut p = 0usize;
                for c in 0..3 {
                    for &a in neighbours {
                        let a = a as usize;
                        let rows = if a == b { c + 1 } else { 3 };
                        for r in 0..rows {
                            out[p] = 3 * a + r;
                            p += 1;
                        }
                    }
                }
                debug_assert_eq!(p, out.len());
            });

        // Scatter map: rank of n_a among the lower neighbours of n_b.
        let element_count = connectivity.len();
        let mut scatter = vec![LOWER_PAIR; element_count * npe * npe];
        scatter
            .par_chunks_mut(npe * npe)
            .enumerate()
            .for_each(|(e, map)| {
                let en = connectivity.element_nodes(e);
                for (a, &na) in en.iter().enumerate() {
                    for (b, &nb) in en.iter().enumerate() {
                        if na <= nb {
                            let neighbours = &nidx[nptr[nb]..nptr[nb + 1]];
                            let rank = neighbours
                                .binary_search(&(na as u32))
                                .expect("pattern contains every element node pair");
                            map[a * npe + b] = rank as u32;
                        }
                    }
                }
            });

        let blocks = color_blocks(model);
        Self {
            node_count,
            element_count,
            nodes_per_element: npe,
            col_ptr,
            row_idx,
            scatter,
            blocks,
        }
    }

    /// Number of unknowns (3 × nodes).
    pub fn dof_count(&self) -> usize {
        3 * self.node_count
    }

    /// Stored entries of the upper triangle.
    pub fn nnz_upper(&self) -> usize {
        self.row_idx.len()
    }

    /// Number of block colours (parallel assembly stages).
    pub fn color_count(&self) -> usize {
        self.blocks.colors.len()
    }

    /// Whether the pattern was built for a model of this size and element type.
    pub fn matches(&self, model: &Model) -> bool {
        self.node_count == model.node_count()
            && self.element_count == model.element_count()
            && self.nodes_per_element == model.connectivity().nodes_per_element()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Material;
    use crate::mesh_gen::BoxMesh;

    #[test]
    fn blocks_of_one_colour_share_no_node_and_hold_every_element_once() {
        let mesh = BoxMesh::tet10([1.0, 2.0, 0.5], [6, 9, 4]);
        let material = Material::isotropic(200e9, 0.3).expect("valid material");
        let model = Model::new(mesh.nodes.clone(), mesh.connectivity.clone(), material)
            .expect("valid box mesh");
        let blocks = color_blocks(&model);
        assert!(blocks.colors.len() > 1 && blocks.block_ptr.len() > 10);
        let mut seen = vec![0usize; model.element_count()];
        for color in &blocks.colors {
            let mut owner = vec![u32::MAX; model.node_count()];
            for &b in color {
                for &e in blocks.block(b) {
                    seen[e as usize] += 1;
                    for &n in model.connectivity().element_nodes(e as usize) {
                        assert!(
                            owner[n] == u32::MAX || owner[n] == b,
                            "node {n} in two blocks"
                        );
                        owner[n] = b;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&count| count == 1));
    }
}
