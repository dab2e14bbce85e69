//! Lagrange shape functions of Tet4, Tet10, Tri3 and Tri6 in **gmsh node order**.
//!
//! Reference tetrahedron: vertices 0 = (0,0,0), 1 = (1,0,0), 2 = (0,1,0), 3 = (0,0,1);
//! barycentric L0 = 1−ξ−η−ζ, L1 = ξ, L2 = η, L3 = ζ.
//! Tet10 (gmsh element type 11): vertices 0–3, then one node per edge in the order of gmsh's
//! `MTetrahedron::edges_tetra` table: (0,1), (1,2), (2,0), (3,0), (3,2), (3,1) — checked against
//! gmsh's `src/geo/MTetrahedron.h`. Note that VTK swaps the last two (VTK 8 = edge (1,3)).
//! Tri6 (gmsh type 9): vertices 0–2, then edges (0,1), (1,2), (2,0).

/// Edges of the Tet10 in gmsh order: mid-edge node `4 + k` lies on `TET10_EDGES[k]`.
pub const TET10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)];

/// Edges of the Tri6 in gmsh order: mid-edge node `3 + k` lies on `TRI6_EDGES[k]`.
pub const TRI6_EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// Reference-coordinate gradients of the four barycentric coordinates L0..L3.
const BARYCENTRIC_GRADIENTS: [[f64; 3]; 4] = [
    [-1.0, -1.0, -1.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];

/// Reference vertices of the tetrahedron.
pub const TET_VERTICES: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];

fn barycentric(xi: [f64; 3]) -> [f64; 4] {
    [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]]
}

/// Shape functions of an `N`-node tetrahedron on the reference element.
pub trait TetShape<const N: usize> {
    /// Values N_a(ξ).
    fn values(xi: [f64; 3]) -> [f64; N];
    /// Reference gradients ∂N_a/∂ξ_j.
    fn reference_gradients(xi: [f64; 3]) -> [[f64; 3]; N];
    /// Reference coordinates of the nodes.
    fn reference_nodes() -> [[f64; 3]; N];
}

/// Linear 4-node tetrahedron.
#[derive(Debug, Clone, Copy)]
pub struct Tet4;

/// Quadratic 10-node tetrahedron (gmsh order).
#[derive(Debug, Clone, Copy)]
pub struct Tet10;

impl TetShape<4> for Tet4 {
    fn values(xi: [f64; 3]) -> [f64; 4] {
        barycentric(xi)
    }
    fn reference_gradients(_xi: [f64; 3]) -> [[f64; 3]; 4] {
        BARYCENTRIC_GRADIENTS
    }
    fn reference_nodes() -> [[f64; 3]; 4] {
        TET_VERTICES
    }
}

impl TetShape<10> for Tet10 {
    fn values(xi: [f64; 3]) -> [f64; 10] {
        let l = barycentric(xi);
        let mut n = [0.0; 10];
        for i in 0..4 {
            n[i] = l[i] * (2.0 * l[i] - 1.0);
        }
        for (k, &(a, b)) in TET10_EDGES.iter().enumerate() {
            n[4 + k] = 4.0 * l[a] * l[b];
        }
        n
    }
    fn reference_gradients(xi: [f64; 3]) -> [[f64; 3]; 10] {
        let l = barycentric(xi);
        let g = &BARYCENTRIC_GRADIENTS;
        let mut d = [[0.0; 3]; 10];
        for i in 0..4 {
            for j in 0..3 {
                d[i][j] = (4.0 * l[i] - 1.0) * g[i][j];
            }
        }
        for (k, &(a, b)) in TET10_EDGES.iter().enumerate() {
            for j in 0..3 {
                d[4 + k][j] = 4.0 * (l[a] * g[b][j] + l[b] * g[a][j]);
            }
        }
        d
    }
    fn reference_nodes() -> [[f64; 3]; 10] {
        let mut x = [[0.0; 3]; 10];
        x[..4].copy_from_slice(&TET_VERTICES);
        for (k, &(a, b)) in TET10_EDGES.iter().enumerate() {
            for j in 0..3 {
                x[4 + k][j] = 0.5 * (TET_VERTICES[a][j] + TET_VERTICES[b][j]);
            }
        }
        x
    }
}

/// Values and reference gradients of Tri3 (`N = 3`) or Tri6 (`N = 6`) shape functions at
/// (ξ, η) on the reference triangle (0,0), (1,0), (0,1).
pub fn triangle_shape<const N: usize>(xi: [f64; 2]) -> ([f64; N], [[f64; 2]; N]) {
    let l = [1.0 - xi[0] - xi[1], xi[0], xi[1]];
    let g = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    let mut n = [0.0; N];
    let mut d = [[0.0; 2]; N];
    match N {
        3 => {
            n.copy_from_slice(&l[..N]);
            d.copy_from_slice(&g[..N]);
        }
        6 => {
            for i in 0..3 {
                n[i] = l[i] * (2.0 * l[i] - 1.0);
                for j in 0..2 {
                    d[i][j] = (4.0 * l[i] - 1.0) * g[i][j];
                }
            }
            for (k, &(a, b)) in TRI6_EDGES.iter().enumerate() {
                n[3 + k] = 4.0 * l[a] * l[b];
                for j in 0..2 {
                    d[3 + k][j] = 4.0 * (l[a] * g[b][j] + l[b] * g[a][j]);
                }
            }
        }
        _ => unreachable!("triangle_shape is only instantiated for 3 and 6 nodes"),
    }
    (n, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_kronecker<const N: usize, S: TetShape<N>>(name: &str) {
        let nodes = S::reference_nodes();
        for (i, x) in nodes.iter().enumerate() {
            let n = S::values(*x);
            for (j, v) in n.iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (v - expected).abs() < 1e-14,
                    "{name}: shape function {j} at node {i} = {v}, expected {expected}"
                );
            }
        }
    }

    #[test]
    fn tet_shape_functions_are_kronecker_at_their_nodes_in_gmsh_order() {
        check_kronecker::<4, Tet4>("Tet4");
        check_kronecker::<10, Tet10>("Tet10");
        // gmsh Tet10: node 8 on edge (3,2) = midpoint of (0,0,1) and (0,1,0); node 9 on edge (3,1).
        let x = Tet10::reference_nodes();
        assert_eq!(
            x[8],
            [0.0, 0.5, 0.5],
            "Tet10 node 8 position (gmsh edge 3-2)"
        );
        assert_eq!(
            x[9],
            [0.5, 0.0, 0.5],
            "Tet10 node 9 position (gmsh edge 3-1)"
        );
    }

    #[test]
    fn tet_shape_gradients_match_finite_differences_and_sum_to_zero() {
        let xi = [0.21, 0.17, 0.33];
        let h = 1e-6;
        let g = Tet10::reference_gradients(xi);
        for j in 0..3 {
            let mut p = xi;
            let mut m = xi;
            p[j] += h;
            m[j] -= h;
            let (np, nm) = (Tet10::values(p), Tet10::values(m));
            for a in 0..10 {
                let fd = (np[a] - nm[a]) / (2.0 * h);
                assert!(
                    (fd - g[a][j]).abs() < 1e-8,
                    "Tet10 gradient dN{a}/dxi{j}: analytic {} vs fd {fd}",
                    g[a][j]
                );
            }
            let sum: f64 = g.iter().map(|row| row[j]).sum();
            assert!(
                sum.abs() < 1e-14,
                "Tet10 partition of unity: sum of dN/dxi{j} = {sum}"
            );
        }
    }

    #[test]
    fn tri6_shape_functions_are_kronecker_at_their_nodes() {
        let nodes = [
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [0.5, 0.0],
            [0.5, 0.5],
            [0.0, 0.5],
        ];
        for (i, x) in nodes.iter().enumerate() {
            let (n, _) = triangle_shape::<6>(*x);
            for (j, v) in n.iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (v - expected).abs() < 1e-14,
                    "Tri6 shape function {j} at node {i} = {v}"
                );
            }
        }
    }
}
