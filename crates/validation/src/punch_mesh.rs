//! A mesh of the `meshes/punch.geo` family, checked and prepared for the FEM: the node sets of
//! its physical groups, its symmetry, the punch radius a and the truncation radius R.

use std::path::Path;

use elastic_fem::Connectivity;
use gmsh_mesh::{TetMesh, Tets};
use serde::{Deserialize, Serialize};

use crate::error::ValidationError;

/// Largest |z| of a punch node relative to the punch radius (the disk lies on z = 0).
/// Dimensionless; default 1e-9.
pub const PUNCH_PLANE_TOLERANCE: f64 = 1e-9;

/// Which part of the hemisphere a punch mesh covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MeshSymmetry {
    /// The full hemisphere.
    Full,
    /// The half y ≥ 0 (group `sym_y0`).
    Half,
    /// The quarter x ≥ 0, y ≥ 0 (groups `sym_x0`, `sym_y0`).
    Quarter,
}

impl MeshSymmetry {
    /// How many copies of the model make the full problem (1, 2 or 4).
    pub fn multiplicity(&self) -> f64 {
        match self {
            MeshSymmetry::Full => 1.0,
            MeshSymmetry::Half => 2.0,
            MeshSymmetry::Quarter => 4.0,
        }
    }

    /// Name used in reports.
    pub fn name(&self) -> &'static str {
        match self {
            MeshSymmetry::Full => "full",
            MeshSymmetry::Half => "half",
            MeshSymmetry::Quarter => "quarter",
        }
    }
}

/// A punch mesh ready for the FEM.
#[derive(Debug, Clone)]
pub struct PunchMesh {
    /// Where it came from (file name).
    pub source: String,
    /// Covered part of the hemisphere.
    pub symmetry: MeshSymmetry,
    /// Element order: 1 (Tet4) or 2 (Tet10).
    pub order: u8,
    /// Punch radius a: largest distance of a punch node from the z axis (m).
    pub radius_m: f64,
    /// Truncation radius R: largest distance of a far-field node from the origin (m).
    pub truncation_radius_m: f64,
    /// Node coordinates (m).
    pub nodes: Vec<[f64; 3]>,
    /// Tetrahedra (gmsh node order).
    pub connectivity: Connectivity,
    /// Nodes of the punch disk r ≤ a on z = 0 (its edge included).
    pub punch_nodes: Vec<usize>,
    /// Nodes of the truncation hemisphere r = R.
    pub far_field_nodes: Vec<usize>,
    /// Nodes of the traction-free surface z = 0, r > a (empty if the group is absent).
    pub free_surface_nodes: Vec<usize>,
    /// Nodes on the plane x = 0 (quarter model), else empty.
    pub sym_x0_nodes: Vec<usize>,
    /// Nodes on the plane y = 0 (half and quarter models), else empty.
    pub sym_y0_nodes: Vec<usize>,
}

fn group_nodes(
    mesh: &TetMesh,
    group: &'static str,
    why: &'static str,
) -> Result<Vec<usize>, ValidationError> {
    if !mesh.surface_groups.contains_key(group) {
        return Err(ValidationError::MissingGroup {
            mesh: mesh.source.clone(),
            group,
            why,
        });
    }
    mesh.group_nodes(group)
        .map_err(|source| ValidationError::MeshRead {
            path: mesh.source.clone().into(),
            source: Box::new(source),
        })
}

impl PunchMesh {
    /// Reads and checks a punch mesh file; its nodes are renumbered along a Morton curve
    /// ([`elastic_fem::locality`]: gmsh's numbering puts coupled unknowns far apart in memory).
    pub fn read(path: &Path) -> Result<Self, ValidationError> {
        let mut mesh = gmsh_mesh::read_msh(path).map_err(|source| ValidationError::MeshRead {
            path: path.to_path_buf(),
            source: Box::new(source),
        })?;
        mesh.renumber_nodes(&elastic_fem::locality::morton_order(&mesh.nodes));
        Self::from_tet_mesh(mesh)
    }

    /// Checks a punch mesh: groups `punch` and `far_field` present, `sym_y0` / `sym_x0` decide
    /// the symmetry, the punch disk lies on z = 0 and inside the truncation radius.
    pub fn from_tet_mesh(mesh: TetMesh) -> Result<Self, ValidationError> {
        let punch_nodes = group_nodes(
            &mesh,
            "punch",
            "the punch disk where the displacement is prescribed",
        )?;
        let far_field_nodes = group_nodes(
            &mesh,
            "far_field",
            "the truncation surface where the far-field condition acts",
        )?;
        let has_x0 = mesh.surface_groups.contains_key("sym_x0");
        let has_y0 = mesh.surface_groups.contains_key("sym_y0");
        let symmetry = match (has_x0, has_y0) {
            (false, false) => MeshSymmetry::Full,
            (false, true) => MeshSymmetry::Half,
            (true, true) => MeshSymmetry::Quarter,
            (true, false) => {
                return Err(ValidationError::MissingGroup {
                    mesh: mesh.source.clone(),
                    group: "sym_y0",
                    why: "a mesh with the symmetry plane x = 0 must also have y = 0 (quarter model)",
                });
            }
        };
        let free_surface_nodes = if mesh.surface_groups.contains_key("free_surface") {
            group_nodes(&mesh, "free_surface", "traction-free surface")?
        } else {
            Vec::new()
        };
        let sym_x0_nodes = if has_x0 {
            group_nodes(&mesh, "sym_x0", "symmetry plane x = 0")?
        } else {
            Vec::new()
        };
        let sym_y0_nodes = if has_y0 {
            group_nodes(&mesh, "sym_y0", "symmetry plane y = 0")?
        } else {
            Vec::new()
        };
        let radial = |n: usize| (mesh.nodes[n][0].powi(2) + mesh.nodes[n][1].powi(2)).sqrt();
        let radius_m = punch_nodes.iter().map(|&n| radial(n)).fold(0.0, f64::max);
        let truncation_radius_m = far_field_nodes
            .iter()
            .map(|&n| mesh.nodes[n].iter().map(|v| v * v).sum::<f64>().sqrt())
            .fold(0.0, f64::max);
        if radius_m.is_nan() || radius_m <= 0.0 || punch_nodes.is_empty() {
            return Err(ValidationError::BadPunchMesh {
                mesh: mesh.source.clone(),
                detail: "the punch group has no extent".into(),
            });
        }
        if let Some(&n) = punch_nodes
            .iter()
            .find(|&&n| mesh.nodes[n][2].abs() > PUNCH_PLANE_TOLERANCE * radius_m)
        {
            return Err(ValidationError::BadPunchMesh {
                mesh: mesh.source.clone(),
                detail: format!(
                    "punch node {n} at {:?} is not on the plane z = 0",
                    mesh.nodes[n]
                ),
            });
        }
        if truncation_radius_m.is_nan() || truncation_radius_m <= radius_m {
            return Err(ValidationError::BadPunchMesh {
                mesh: mesh.source.clone(),
                detail: format!(
                    "truncation radius {truncation_radius_m:e} m is not larger than the punch radius {radius_m:e} m"
                ),
            });
        }
        let (order, connectivity) = match mesh.tets {
            Tets::Linear(t) => (1, Connectivity::Tet4(t)),
            Tets::Quadratic(t) => (2, Connectivity::Tet10(t)),
        };
        Ok(Self {
            source: mesh.source,
            symmetry,
            order,
            radius_m,
            truncation_radius_m,
            nodes: mesh.nodes,
            connectivity,
            punch_nodes,
            far_field_nodes,
            free_surface_nodes,
            sym_x0_nodes,
            sym_y0_nodes,
        })
    }

    /// Whether node `n` lies on none of the boundary groups (an interior node).
    pub fn interior_mask(&self) -> Vec<bool> {
        let mut interior = vec![true; self.nodes.len()];
        for set in [
            &self.punch_nodes,
            &self.far_field_nodes,
            &self.free_surface_nodes,
            &self.sym_x0_nodes,
            &self.sym_y0_nodes,
        ] {
            for &n in set {
                interior[n] = false;
            }
        }
        interior
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of tetrahedra.
    pub fn element_count(&self) -> usize {
        self.connectivity.len()
    }

    /// R / a.
    pub fn truncation_ratio(&self) -> f64 {
        self.truncation_radius_m / self.radius_m
    }
}

/// A symmetry plane of the punch models.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MirrorPlane {
    /// The plane x = 0 (group `sym_x0`).
    X0,
    /// The plane y = 0 (group `sym_y0`).
    Y0,
}

/// Gmsh Tet10 node order after swapping corners 1 and 2 (restores a positive volume after a
/// reflection): corners 0 2 1 3, then the edges (0,2) (2,1) (1,0) (3,0) (3,1) (3,2).
const TET10_REFLECTED_ORDER: [usize; 10] = [0, 2, 1, 3, 6, 5, 4, 7, 9, 8];
/// Tet4 node order after swapping corners 1 and 2.
const TET4_REFLECTED_ORDER: [usize; 4] = [0, 2, 1, 3];

impl PunchMesh {
    /// The mesh united with its mirror image in `plane`: a quarter model becomes a half model
    /// (plane x = 0) and a half model the full one (plane y = 0). The two halves share the nodes
    /// of the plane, so the discrete problem on the united mesh is exactly the symmetric
    /// extension of the original one: solving both must give the same stiffness to round-off
    /// (the test of the symmetry conditions).
    pub fn mirrored(&self, plane: MirrorPlane) -> Result<PunchMesh, ValidationError> {
        let (axis, plane_nodes, name) = match plane {
            MirrorPlane::X0 => (0, &self.sym_x0_nodes, "sym_x0"),
            MirrorPlane::Y0 => (1, &self.sym_y0_nodes, "sym_y0"),
        };
        if plane_nodes.is_empty() {
            return Err(ValidationError::MissingGroup {
                mesh: self.source.clone(),
                group: name,
                why: "the mirror plane",
            });
        }
        let on_plane: std::collections::HashSet<usize> = plane_nodes.iter().copied().collect();
        let mut nodes = self.nodes.clone();
        let mut image = vec![usize::MAX; self.nodes.len()];
        for (n, x) in self.nodes.iter().enumerate() {
            if on_plane.contains(&n) {
                image[n] = n;
            } else {
                let mut y = *x;
                y[axis] = -y[axis];
                image[n] = nodes.len();
                nodes.push(y);
            }
        }
        let connectivity = match &self.connectivity {
            Connectivity::Tet4(t) => {
                let mirrored = t.iter().map(|e| TET4_REFLECTED_ORDER.map(|k| image[e[k]]));
                Connectivity::Tet4(t.iter().copied().chain(mirrored).collect())
            }
            Connectivity::Tet10(t) => {
                let mirrored = t.iter().map(|e| TET10_REFLECTED_ORDER.map(|k| image[e[k]]));
                Connectivity::Tet10(t.iter().copied().chain(mirrored).collect())
            }
        };
        let unite = |set: &[usize]| -> Vec<usize> {
            let mut all: Vec<usize> = set
                .iter()
                .copied()
                .chain(set.iter().map(|&n| image[n]))
                .collect();
            all.sort_unstable();
            all.dedup();
            all
        };
        let (sym_x0_nodes, sym_y0_nodes, symmetry) = match plane {
            MirrorPlane::X0 => (
                Vec::new(),
                unite(&self.sym_y0_nodes),
                if self.sym_y0_nodes.is_empty() {
                    MeshSymmetry::Full
                } else {
                    MeshSymmetry::Half
                },
            ),
            MirrorPlane::Y0 => {
                if !self.sym_x0_nodes.is_empty() {
                    return Err(ValidationError::BadPunchMesh {
                        mesh: self.source.clone(),
                        detail: "mirror a quarter model in x = 0 first (a y-mirrored quarter is not one of the three models)".into(),
                    });
                }
                (Vec::new(), Vec::new(), MeshSymmetry::Full)
            }
        };
        Ok(PunchMesh {
            source: format!("{} mirrored in {name}", self.source),
            symmetry,
            order: self.order,
            radius_m: self.radius_m,
            truncation_radius_m: self.truncation_radius_m,
            nodes,
            connectivity,
            punch_nodes: unite(&self.punch_nodes),
            far_field_nodes: unite(&self.far_field_nodes),
            free_surface_nodes: unite(&self.free_surface_nodes),
            sym_x0_nodes,
            sym_y0_nodes,
        })
    }
}
