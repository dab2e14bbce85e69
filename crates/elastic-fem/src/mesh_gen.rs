//! Structured box meshes for tests and benchmarks: a box split into cubes (cuboids), each
//! split into 6 tetrahedra around its main diagonal (Kuhn/Freudenthal split, conforming across
//! cubes). Tet10 adds mid-edge nodes in gmsh order; with this split the Tet10 nodes are exactly
//! the points of the twice-refined grid, so a box with divisions (nx, ny, nz) has
//! (2nx+1)(2ny+1)(2nz+1) Tet10 nodes.
//!
//! ```
//! use elastic_fem::mesh_gen::{BoxFace, BoxMesh};
//! let mesh = BoxMesh::tet10([1.0, 1.0, 1.0], [2, 2, 2]);
//! assert_eq!(mesh.nodes.len(), 125);
//! assert_eq!(mesh.connectivity.len(), 48);
//! assert_eq!(mesh.face_nodes(BoxFace::ZMin).len(), 25);
//! ```

use crate::loads::SurfaceTriangles;
use crate::model::Connectivity;
use crate::shape::{TET10_EDGES, TRI6_EDGES};

/// A face of the box.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoxFace {
    /// x = x_min.
    XMin,
    /// x = x_max.
    XMax,
    /// y = y_min.
    YMin,
    /// y = y_max.
    YMax,
    /// z = z_min.
    ZMin,
    /// z = z_max.
    ZMax,
}

impl BoxFace {
    /// All six faces.
    pub const ALL: [BoxFace; 6] = [
        BoxFace::XMin,
        BoxFace::XMax,
        BoxFace::YMin,
        BoxFace::YMax,
        BoxFace::ZMin,
        BoxFace::ZMax,
    ];

    /// (normal axis, is the max side).
    fn axis_side(self) -> (usize, bool) {
        match self {
            BoxFace::XMin => (0, false),
            BoxFace::XMax => (0, true),
            BoxFace::YMin => (1, false),
            BoxFace::YMax => (1, true),
            BoxFace::ZMin => (2, false),
            BoxFace::ZMax => (2, true),
        }
    }
}

/// A structured tetrahedral mesh of the box [0, Lx] × [0, Ly] × [0, Lz].
#[derive(Debug, Clone)]
pub struct BoxMesh {
    /// Node coordinates (m).
    pub nodes: Vec<[f64; 3]>,
    /// Tet4 or Tet10 (gmsh order) connectivity.
    pub connectivity: Connectivity,
    /// Box edge lengths (m).
    pub lengths_m: [f64; 3],
    /// Cubes per axis.
    pub divisions: [usize; 3],
    /// Grid steps per cube edge: 1 (Tet4) or 2 (Tet10).
    refinement: usize,
}

impl BoxMesh {
    /// Linear tetrahedra.
    pub fn tet4(lengths_m: [f64; 3], divisions: [usize; 3]) -> Self {
        Self::build(lengths_m, divisions, 1)
    }

    /// Quadratic tetrahedra (gmsh node order).
    pub fn tet10(lengths_m: [f64; 3], divisions: [usize; 3]) -> Self {
        Self::build(lengths_m, divisions, 2)
    }

    /// Divisions n of a Tet10 cube mesh with about `unknowns` displacement unknowns
    /// (3 (2n+1)³ ≈ unknowns).
    pub fn tet10_divisions_for_unknowns(unknowns: usize) -> usize {
        let points_per_axis = (unknowns as f64 / 3.0).cbrt();
        (((points_per_axis - 1.0) / 2.0).round() as usize).max(1)
    }

    fn grid_points(&self) -> [usize; 3] {
        self.divisions.map(|d| self.refinement * d + 1)
    }

    fn node_index(&self, g: [usize; 3]) -> usize {
        let p = self.grid_points();
        g[0] + p[0] * (g[1] + p[1] * g[2])
    }

    fn build(lengths_m: [f64; 3], divisions: [usize; 3], refinement: usize) -> Self {
        assert!(
            divisions.iter().all(|&d| d > 0),
            "BoxMesh: divisions must be positive"
        );
        let mut mesh = Self {
            nodes: Vec::new(),
            connectivity: Connectivity::Tet4(Vec::new()),
            lengths_m,
            divisions,
            refinement,
        };
        let p = mesh.grid_points();
        mesh.nodes.reserve(p[0] * p[1] * p[2]);
        for k in 0..p[2] {
            for j in 0..p[1] {
                for i in 0..p[0] {
                    let g = [i, j, k];
                    mesh.nodes.push(std::array::from_fn(|a| {
                        lengths_m[a] * g[a] as f64 / (p[a] - 1) as f64
                    }));
                }
            }
        }
        const PERMUTATIONS: [([usize; 3], bool); 6] = [
            ([0, 1, 2], true),
            ([1, 2, 0], true),
            ([2, 0, 1], true),
            ([0, 2, 1], false),
            ([2, 1, 0], false),
            ([1, 0, 2], false),
        ];
        let m = refinement;
        let mut tet4 = Vec::new();
        let mut tet10 = Vec::new();
        for ck in 0..divisions[2] {
            for cj in 0..divisions[1] {
                for ci in 0..divisions[0] {
                    let base = [m * ci, m * cj, m * ck];
                    for (perm, even) in PERMUTATIONS {
                        let mut v = [base; 4];
                        for s in 0..3 {
                            v[s + 1] = v[s];
                            v[s + 1][perm[s]] += m;
                        }
                        if !even {
                            v.swap(1, 2);
                        }
                        if m == 1 {
                            tet4.push(v.map(|g| mesh.node_index(g)));
                        } else {
                            let mut el = [0usize; 10];
                            for a in 0..4 {
                                el[a] = mesh.node_index(v[a]);
                            }
                            for (e, &(a, b)) in TET10_EDGES.iter().enumerate() {
                                el[4 + e] = mesh
                                    .node_index(std::array::from_fn(|t| (v[a][t] + v[b][t]) / 2));
                            }
                            tet10.push(el);
                        }
                    }
                }
            }
        }
        mesh.connectivity = if m == 1 {
            Connectivity::Tet4(tet4)
        } else {
            Connectivity::Tet10(tet10)
        };
        mesh
    }

    /// Number of displacement unknowns (3 × nodes).
    pub fn dof_count(&self) -> usize {
        3 * self.nodes.len()
    }

    /// Nodes on a face of the box (sorted).
    pub fn face_nodes(&self, face: BoxFace) -> Vec<usize> {
        let (axis, max_side) = face.axis_side();
        let p = self.grid_points();
        let fixed = if max_side { p[axis] - 1 } else { 0 };
        let mut out = Vec::new();
        for k in 0..p[2] {
            for j in 0..p[1] {
                for i in 0..p[0] {
                    let g = [i, j, k];
                    if g[axis] == fixed {
                        out.push(self.node_index(g));
                    }
                }
            }
        }
        out
    }

    /// Nodes on any face of the box (sorted, unique).
    pub fn boundary_nodes(&self) -> Vec<usize> {
        let mut all: Vec<usize> = BoxFace::ALL
            .iter()
            .flat_map(|&f| self.face_nodes(f))
            .collect();
        all.sort_unstable();
        all.dedup();
        all
    }

    /// Boundary triangles of a face (Tri3 for Tet4, Tri6 for Tet10, gmsh order), ordered so
    /// that (x1 − x0) × (x2 − x0) points out of the box. They coincide with element faces.
    pub fn face_triangles(&self, face: BoxFace) -> SurfaceTriangles {
        let (axis, max_side) = face.axis_side();
        // In-plane axes (u, v) with e_u × e_v = +e_axis.
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let p = self.grid_points();
        let m = self.refinement;
        let fixed = if max_side { p[axis] - 1 } else { 0 };
        let mut tri3 = Vec::new();
        let mut tri6 = Vec::new();
        for cv in 0..self.divisions[v] {
            for cu in 0..self.divisions[u] {
                let corner = |du: usize, dv: usize| {
                    let mut g = [0usize; 3];
                    g[axis] = fixed;
                    g[u] = m * (cu + du);
                    g[v] = m * (cv + dv);
                    g
                };
                // The Kuhn split cuts each face square along its (min, min) → (max, max) diagonal.
                let mut tris = [
                    [corner(0, 0), corner(1, 0), corner(1, 1)],
                    [corner(0, 0), corner(1, 1), corner(0, 1)],
                ];
                if !max_side {
                    for t in tris.iter_mut() {
                        t.swap(1, 2);
                    }
                }
                for t in tris {
                    if m == 1 {
                        tri3.push(t.map(|g| self.node_index(g)));
                    } else {
                        let mut el = [0usize; 6];
                        for a in 0..3 {
                            el[a] = self.node_index(t[a]);
                        }
                        for (e, &(a, b)) in TRI6_EDGES.iter().enumerate() {
                            el[3 + e] =
                                self.node_index(std::array::from_fn(|s| (t[a][s] + t[b][s]) / 2));
                        }
                        tri6.push(el);
                    }
                }
            }
        }
        if m == 1 {
            SurfaceTriangles::Tri3(tri3)
        } else {
            SurfaceTriangles::Tri6(tri6)
        }
    }

    /// Moves every node by `f(x)` (e.g. to distort or curve the mesh in tests).
    pub fn map_nodes(&mut self, f: impl Fn([f64; 3]) -> [f64; 3]) {
        for x in self.nodes.iter_mut() {
            *x = f(*x);
        }
    }

    /// For Tet10: puts every mid-edge node back at the midpoint of its edge (straight-sided
    /// elements after a vertex-only distortion).
    pub fn straighten_edges(&mut self) {
        if let Connectivity::Tet10(conn) = &self.connectivity {
            for el in conn {
                for (e, &(a, b)) in TET10_EDGES.iter().enumerate() {
                    let (xa, xb) = (self.nodes[el[a]], self.nodes[el[b]]);
                    self.nodes[el[4 + e]] = std::array::from_fn(|t| 0.5 * (xa[t] + xb[t]));
                }
            }
        }
    }
}
