//! Orders of points along a Morton (Z-order) curve, for memory locality: the assembly's element
//! blocks ([`crate::pattern`]) and a mesh's node numbering ([`morton_order`]).
//!
//! **Why nodes.** gmsh numbers the nodes of a second-order mesh entity by entity, the edge nodes
//! after the vertices. On the punch meshes the median column of the stiffness matrix then
//! reaches back 122 000 of 365 000 unknowns: every product with the matrix, its transposition
//! into rows and the gathers of the reduction touch memory far apart, and from ≈ 10⁶ unknowns
//! nearly every access misses the cache and the TLB. With the nodes in Morton order the median
//! reach was 637 unknowns, and on the 0.93M-unknown punch mesh, one thread, the whole FEM took
//! 20.5 instead of 29.6 s, the PCG solve 9.3 instead of 15.6 s (both measured with a first
//! version of the key, x the most significant axis; validation/fem-peers/README.md). A
//! fill-reducing ordering (METIS) for a direct solve is computed on top and does not depend on
//! it. The renumbering itself is the mesh's (`gmsh_mesh::TetMesh::renumber_nodes`).
//!
//! **Curve.** Each coordinate is scaled to the bounding box and cut to [`MORTON_BITS`] bits; the
//! key interleaves the bits, z above y above x. Points are sorted by (key, index): the order is a
//! pure function of the coordinates and their old order. Morton 1966 (IBM report "A computer
//! oriented geodetic data base and a new technique in file sequencing"); as an ordering of
//! unstructured-mesh data e.g. Warren & Salmon 1993 ("A parallel hashed oct-tree N-body
//! algorithm", SC'93).

use rayon::prelude::*;

/// Bits per axis of a Morton key (3 × 21 = 63 bits of a u64).
pub const MORTON_BITS: u32 = 21;

/// Morton key of a point in the box `lo`..`hi`: [`MORTON_BITS`] bits per axis, interleaved.
pub fn morton_key(x: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> u64 {
    const CELLS: f64 = ((1u64 << MORTON_BITS) - 1) as f64;
    let spread = |v: u64| {
        let mut v = v & 0x1f_ffff;
        v = (v | v << 32) & 0x1f_0000_0000_ffff;
        v = (v | v << 16) & 0x1f_0000_ff00_00ff;
        v = (v | v << 8) & 0x100f_00f0_0f00_f00f;
        v = (v | v << 4) & 0x10c3_0c30_c30c_30c3;
        (v | v << 2) & 0x1249_2492_4924_9249
    };
    let cell = |c: usize| {
        let span = hi[c] - lo[c];
        let t = if span > 0.0 {
            (x[c] - lo[c]) / span
        } else {
            0.0
        };
        (t.clamp(0.0, 1.0) * CELLS) as u64
    };
    spread(cell(0)) | spread(cell(1)) << 1 | spread(cell(2)) << 2
}

/// Smallest box holding `points`: (lower corner, upper corner).
pub fn bounding_box(points: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for x in points {
        for j in 0..3 {
            lo[j] = lo[j].min(x[j]);
            hi[j] = hi[j].max(x[j]);
        }
    }
    (lo, hi)
}

/// The points in Morton order (ties by index): `order[new] = old`.
pub fn morton_order(points: &[[f64; 3]]) -> Vec<usize> {
    let (lo, hi) = bounding_box(points);
    let mut keyed: Vec<(u64, usize)> = points
        .par_iter()
        .enumerate()
        .map(|(i, &p)| (morton_key(p, lo, hi), i))
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn morton_keys_interleave_the_axes_and_order_by_the_highest_bit() {
        let (lo, hi) = ([0.0; 3], [1.0; 3]);
        assert_eq!(morton_key([0.0; 3], lo, hi), 0);
        assert_eq!(morton_key([1.0; 3], lo, hi), (1u64 << 63) - 1);
        // The top cell bit of x, y, z lands at bits 60, 61, 62.
        assert_eq!(morton_key([0.6, 0.0, 0.0], lo, hi) >> 60, 0b001);
        assert_eq!(morton_key([0.0, 0.6, 0.0], lo, hi) >> 60, 0b010);
        assert_eq!(morton_key([0.0, 0.0, 0.6], lo, hi) >> 60, 0b100);
    }

    #[test]
    fn morton_order_visits_the_octants_of_a_cube_in_z_order() {
        // The eight corners of a cube listed in reverse Z order (z the most significant bit).
        let corners: Vec<[f64; 3]> = (0..8)
            .rev()
            .map(|k| {
                [
                    f64::from(k & 1),
                    f64::from(k >> 1 & 1),
                    f64::from(k >> 2 & 1),
                ]
            })
            .collect();
        assert_eq!(morton_order(&corners), vec![7, 6, 5, 4, 3, 2, 1, 0]);
    }

    #[test]
    fn equal_keys_keep_the_old_order_and_a_flat_set_is_ordered_in_its_plane() {
        let points = [
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(morton_order(&points), vec![1, 2, 0, 3]);
    }
}
