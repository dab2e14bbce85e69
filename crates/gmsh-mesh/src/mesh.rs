//! The tetrahedral mesh with its physical groups, and the queries the FEM needs.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::error::{MeshError, Result};
use crate::geometry::{self, Point};

/// Tetrahedra, all of one order. Node indices are 0-based into [`TetMesh::nodes`].
///
/// Node order is gmsh's: corners 0..3 (positive signed volume), then for Tet10 the midside nodes
/// 4:(0,1) 5:(1,2) 6:(2,0) 7:(3,0) 8:(3,2) 9:(3,1). VTK's quadratic tetra swaps the last two
/// (VTK 8 = edge 1-3, 9 = edge 2-3); [`crate::write_vtu`] converts.
#[derive(Debug, Clone, PartialEq)]
pub enum Tets {
    /// 4-node tetrahedra (gmsh type 4).
    Linear(Vec<[usize; 4]>),
    /// 10-node tetrahedra (gmsh type 11).
    Quadratic(Vec<[usize; 10]>),
}

impl Tets {
    /// Number of tetrahedra.
    pub fn len(&self) -> usize {
        match self {
            Tets::Linear(t) => t.len(),
            Tets::Quadratic(t) => t.len(),
        }
    }

    /// Whether there are no tetrahedra.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Polynomial order: 1 (Tet4) or 2 (Tet10).
    pub fn order(&self) -> u8 {
        match self {
            Tets::Linear(_) => 1,
            Tets::Quadratic(_) => 2,
        }
    }

    /// Nodes per tetrahedron: 4 or 10.
    pub fn nodes_per_tet(&self) -> usize {
        match self {
            Tets::Linear(_) => 4,
            Tets::Quadratic(_) => 10,
        }
    }

    /// All node indices of tet `i` (4 or 10, gmsh order).
    pub fn nodes(&self, i: usize) -> &[usize] {
        match self {
            Tets::Linear(t) => &t[i],
            Tets::Quadratic(t) => &t[i],
        }
    }

    /// Corner node indices of tet `i`.
    pub fn corners(&self, i: usize) -> [usize; 4] {
        let n = self.nodes(i);
        [n[0], n[1], n[2], n[3]]
    }

    /// Element kind name: "Tet4" or "Tet10".
    pub fn kind(&self) -> &'static str {
        match self {
            Tets::Linear(_) => "Tet4",
            Tets::Quadratic(_) => "Tet10",
        }
    }
}

/// Boundary triangles of one surface group, of the same order as the tets. Node indices are
/// 0-based into [`TetMesh::nodes`]; order is gmsh's: corners 0..2, then for Tri6 the midside
/// nodes 3:(0,1) 4:(1,2) 5:(2,0).
///
/// Orientation: the reader re-orients every triangle that bounds exactly one tet so that the
/// corner normal (p1 − p0) × (p2 − p0) points out of that tet, i.e. out of the body. Triangles
/// between two tets (internal interfaces) keep gmsh's orientation (noted in [`TetMesh::notes`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Faces {
    /// 3-node triangles (gmsh type 2).
    Linear(Vec<[usize; 3]>),
    /// 6-node triangles (gmsh type 9).
    Quadratic(Vec<[usize; 6]>),
}

impl Faces {
    /// Number of triangles.
    pub fn len(&self) -> usize {
        match self {
            Faces::Linear(f) => f.len(),
            Faces::Quadratic(f) => f.len(),
        }
    }

    /// Whether there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// All node indices of triangle `i` (3 or 6).
    pub fn nodes(&self, i: usize) -> &[usize] {
        match self {
            Faces::Linear(f) => &f[i],
            Faces::Quadratic(f) => &f[i],
        }
    }

    /// Corner node indices of triangle `i`.
    pub fn corners(&self, i: usize) -> [usize; 3] {
        let n = self.nodes(i);
        [n[0], n[1], n[2]]
    }
}

/// A physical group as declared by the file.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct PhysicalGroup {
    /// Dimension: 0 point, 1 curve, 2 surface, 3 volume.
    pub dim: u8,
    /// gmsh physical tag (unique per dimension).
    pub tag: i32,
    /// Name from `$PhysicalNames`; unnamed groups get `"<kind>_<tag>"`, e.g. `surface_7`.
    pub name: String,
    /// Whether the name came from `$PhysicalNames`.
    pub named: bool,
    /// Number of geometric entities carrying this physical tag.
    pub entity_count: usize,
    /// Number of elements of the kinds this reader keeps (tets for dim 3, triangles for dim 2).
    pub element_count: usize,
}

/// A tetrahedral mesh read from a gmsh MSH 4.1 file.
#[derive(Debug, Clone)]
pub struct TetMesh {
    /// File (or label) the mesh was read from, used in error messages.
    pub source: String,
    /// Node coordinates (m), indexed 0..n. Only nodes of tetrahedra are kept, in file order.
    pub nodes: Vec<Point>,
    /// Original gmsh tag of each node.
    pub node_tags: Vec<u64>,
    /// The tetrahedra.
    pub tets: Tets,
    /// Original gmsh element tag of each tet (use these when talking to the user).
    pub tet_tags: Vec<u64>,
    /// Physical volume tag of each tet (`None` if its entity has no physical volume).
    /// If an entity carries several volume tags, the first is used (noted in `notes`).
    pub tet_groups: Vec<Option<i32>>,
    /// Boundary triangles of each physical surface group, by group name.
    pub surface_groups: BTreeMap<String, Faces>,
    /// All physical groups in the file (every dimension), sorted by (dim, tag).
    pub groups: Vec<PhysicalGroup>,
    /// Node pairs `[slave, master]` (node indices) from gmsh `Periodic` constraints: the slave
    /// node is the image of the master node under the periodic translation.
    pub periodic_node_pairs: Vec<[usize; 2]>,
    /// Whether the file was binary.
    pub binary: bool,
    /// What the reader skipped or adjusted (element types, sections, orientation fixes).
    pub notes: Vec<String>,
}

#[cfg(test)]
impl TetMesh {
    /// A Tet4 mesh for unit tests: `nodes` tagged 1, 2, …, `tets` tagged 1, 2, … in volume
    /// group 1, the given face groups; no physical group list, periodic pairs or notes. Tests
    /// override the fields they need (`TetMesh { node_tags: …, ..TetMesh::linear_for_tests(…) }`).
    pub(crate) fn linear_for_tests(
        nodes: Vec<Point>,
        tets: Vec<[usize; 4]>,
        faces: &[(&str, Vec<[usize; 3]>)],
    ) -> Self {
        Self {
            source: "test".into(),
            node_tags: (1..=nodes.len() as u64).collect(),
            nodes,
            tet_tags: (1..=tets.len() as u64).collect(),
            tet_groups: vec![Some(1); tets.len()],
            tets: Tets::Linear(tets),
            surface_groups: faces
                .iter()
                .map(|(name, f)| (name.to_string(), Faces::Linear(f.clone())))
                .collect(),
            groups: Vec::new(),
            periodic_node_pairs: Vec::new(),
            binary: false,
            notes: Vec::new(),
        }
    }
}

impl TetMesh {
    /// The physical group called `name` (any dimension).
    pub fn group(&self, name: &str) -> Option<&PhysicalGroup> {
        self.groups.iter().find(|g| g.name == name)
    }

    fn missing_group(&self, kind: &'static str, name: &str, dim: u8) -> MeshError {
        let names: Vec<&str> = self
            .groups
            .iter()
            .filter(|g| g.dim == dim)
            .map(|g| g.name.as_str())
            .collect();
        MeshError::MissingGroup {
            file: self.source.clone(),
            kind,
            name: name.to_string(),
            available: if names.is_empty() {
                "(none)".to_string()
            } else {
                names.join(", ")
            },
        }
        .escaped()
    }

    /// Boundary triangles of the physical surface group `name`.
    pub fn group_faces(&self, name: &str) -> Result<&Faces> {
        self.surface_groups
            .get(name)
            .ok_or_else(|| self.missing_group("surface", name, 2))
    }

    /// Indices of the tets in the physical volume group `name`.
    pub fn group_tets(&self, name: &str) -> Result<Vec<usize>> {
        let group = self
            .groups
            .iter()
            .find(|g| g.dim == 3 && g.name == name)
            .ok_or_else(|| self.missing_group("volume", name, 3))?;
        Ok(self
            .tet_groups
            .iter()
            .enumerate()
            .filter(|(_, g)| **g == Some(group.tag))
            .map(|(i, _)| i)
            .collect())
    }

    /// Sorted, unique node indices (all nodes, midside included) of the surface group `name`,
    /// or of the volume group `name` if no surface group has that name.
    pub fn group_nodes(&self, name: &str) -> Result<Vec<usize>> {
        let mut nodes: Vec<usize> = if let Some(faces) = self.surface_groups.get(name) {
            (0..faces.len())
                .flat_map(|i| faces.nodes(i).iter().copied())
                .collect()
        } else if self.groups.iter().any(|g| g.dim == 3 && g.name == name) {
            self.group_tets(name)?
                .into_iter()
                .flat_map(|t| self.tets.nodes(t).iter().copied())
                .collect()
        } else {
            return Err(self.missing_group("surface or volume", name, 2));
        };
        nodes.sort_unstable();
        nodes.dedup();
        Ok(nodes)
    }

    /// Coordinates of the nodes of tet `i`.
    fn tet_points(&self, i: usize) -> Vec<Point> {
        self.tets.nodes(i).iter().map(|&n| self.nodes[n]).collect()
    }

    /// Volume of tet `i` (m³) (exact for the curved Tet10 map).
    pub fn tet_volume(&self, i: usize) -> f64 {
        let p = self.tet_points(i);
        match &self.tets {
            Tets::Linear(_) => geometry::tet4_signed_volume([p[0], p[1], p[2], p[3]]),
            Tets::Quadratic(_) => {
                let mut q = [[0.0; 3]; 10];
                q.copy_from_slice(&p);
                geometry::tet10_volume(&q)
            }
        }
    }

    /// Total volume of all tets (m³).
    pub fn volume(&self) -> f64 {
        (0..self.tets.len()).map(|i| self.tet_volume(i)).sum()
    }

    /// Area of the surface group `name` (m²) (curved Tri6 integrated by quadrature).
    pub fn face_area(&self, name: &str) -> Result<f64> {
        let faces = self.group_faces(name)?;
        Ok((0..faces.len())
            .map(|i| {
                let p: Vec<Point> = faces.nodes(i).iter().map(|&n| self.nodes[n]).collect();
                match faces {
                    Faces::Linear(_) => geometry::triangle_area([p[0], p[1], p[2]]),
                    Faces::Quadratic(_) => {
                        let mut q = [[0.0; 3]; 6];
                        q.copy_from_slice(&p);
                        geometry::tri6_area(&q)
                    }
                }
            })
            .sum())
    }

    /// Axis-aligned bounding box `[min, max]` of the nodes (m); `None` for an empty mesh.
    pub fn bounding_box(&self) -> Option<[Point; 2]> {
        let first = *self.nodes.first()?;
        Some(self.nodes.iter().fold([first, first], |[lo, hi], p| {
            [
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            ]
        }))
    }
}
