//! Renumbering a mesh's nodes: [`TetMesh::renumber_nodes`] applies a permutation to the node
//! coordinates, gmsh tags, elements, faces and periodic pairs. The order itself is the caller's:
//! elastic-fem's `locality::morton_order` of the coordinates puts nodes close in space close in
//! memory (gmsh numbers a second-order mesh entity by entity, the edge nodes after the vertices;
//! why that matters and what it gains: elastic-fem's `locality` module).

use crate::mesh::{Faces, TetMesh, Tets};

impl TetMesh {
    /// Renumbers the nodes: new node `k` is old node `order[k]` (a permutation of the nodes).
    /// Coordinates, gmsh tags, elements, faces and periodic pairs follow; element and face order,
    /// groups and everything else stay. Panics if `order` is not a permutation of the nodes.
    pub fn renumber_nodes(&mut self, order: &[usize]) {
        let n = self.nodes.len();
        assert_eq!(order.len(), n, "renumber_nodes: one entry per node");
        let mut new_of = vec![usize::MAX; n];
        for (new, &old) in order.iter().enumerate() {
            assert!(
                old < n && new_of[old] == usize::MAX,
                "renumber_nodes: not a permutation (node {old})"
            );
            new_of[old] = new;
        }
        self.nodes = order.iter().map(|&o| self.nodes[o]).collect();
        self.node_tags = order.iter().map(|&o| self.node_tags[o]).collect();
        let map = |v: &mut usize| *v = new_of[*v];
        match &mut self.tets {
            Tets::Linear(t) => t.iter_mut().flatten().for_each(map),
            Tets::Quadratic(t) => t.iter_mut().flatten().for_each(map),
        }
        for faces in self.surface_groups.values_mut() {
            match faces {
                Faces::Linear(f) => f.iter_mut().flatten().for_each(map),
                Faces::Quadratic(f) => f.iter_mut().flatten().for_each(map),
            }
        }
        self.periodic_node_pairs.iter_mut().flatten().for_each(map);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two tets sharing the face 1-2-3, a face group on the first one's base and a periodic
    /// pair.
    fn two_tets() -> TetMesh {
        TetMesh {
            node_tags: vec![50, 51, 52, 53, 54],
            periodic_node_pairs: vec![[3, 4]],
            ..TetMesh::linear_for_tests(
                vec![
                    [1.0, 1.0, 1.0],
                    [1.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [0.0, 0.0, 1.0],
                    [0.0, 0.0, 0.0],
                ],
                vec![[4, 1, 2, 3], [0, 1, 3, 2]],
                &[("base", vec![[4, 2, 1]])],
            )
        }
    }

    #[test]
    fn renumbered_nodes_carry_their_coordinates_tags_elements_faces_and_pairs() {
        let before = two_tets();
        let mut after = before.clone();
        // Not an involution, so that the order and its inverse cannot be mixed up unseen.
        after.renumber_nodes(&[2, 4, 0, 3, 1]);
        assert_eq!(
            after.node_tags,
            vec![52, 54, 50, 53, 51],
            "new node k is old node order[k]"
        );
        let by_tag = |m: &TetMesh, i: usize| (m.node_tags[i], m.nodes[i]);
        for e in 0..2 {
            let old: Vec<_> = before
                .tets
                .nodes(e)
                .iter()
                .map(|&i| by_tag(&before, i))
                .collect();
            let new: Vec<_> = after
                .tets
                .nodes(e)
                .iter()
                .map(|&i| by_tag(&after, i))
                .collect();
            assert_eq!(old, new, "tet {e} lists the same nodes in the same order");
            assert_eq!(before.tet_volume(e), after.tet_volume(e));
        }
        let face = |m: &TetMesh| -> Vec<u64> {
            m.surface_groups["base"]
                .nodes(0)
                .iter()
                .map(|&i| m.node_tags[i])
                .collect()
        };
        assert_eq!(face(&before), face(&after));
        let pair = |m: &TetMesh| m.periodic_node_pairs[0].map(|i| m.node_tags[i]);
        assert_eq!(pair(&before), pair(&after));
    }

    #[test]
    #[should_panic(expected = "not a permutation")]
    fn an_order_that_is_no_permutation_is_refused() {
        two_tets().renumber_nodes(&[0, 1, 2, 3, 3]);
    }
}
