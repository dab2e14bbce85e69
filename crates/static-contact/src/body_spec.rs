//! The description of one elastic body to condense (mesh, groups, material, contact disks and
//! their in-plane condition): plain data, no behaviour. A leaf module (it uses nothing else of this
//! crate) so that both the condensation ([`crate::body`]) and the choice of its linear solver
//! ([`crate::body_solver`]) can take it without importing each other; re-exported from
//! [`crate::body`], its public path.

use gmsh_mesh::TetMesh;
use serde::Serialize;

/// A contact disk: centre (m) and radius (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Disk {
    /// Centre (m).
    pub centre_m: [f64; 3],
    /// Radius (m).
    pub radius_m: f64,
}

/// In-plane condition of the disk nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TipLateral {
    /// x and y free: frictionless contact.
    Free,
    /// x and y fixed: the disk is bonded to a rigid punch (the k_pn condition).
    Bonded,
}

/// Everything needed to condense one body of a mesh onto its disks.
#[derive(Debug, Clone)]
pub struct BodySpec<'a> {
    /// Name used in messages ("slider", "stator").
    pub name: &'static str,
    /// The mesh.
    pub mesh: &'a TetMesh,
    /// Physical volume of this body.
    pub volume_group: String,
    /// Material.
    pub material: elastic_fem::Material,
    /// Physical surface holding the contact disks.
    pub contact_group: String,
    /// The disks, in the order of the posts.
    pub disks: Vec<Disk>,
    /// In-plane condition of the disk nodes.
    pub lateral: TipLateral,
    /// Surfaces clamped (u = 0).
    pub clamped_groups: Vec<String>,
    /// Surfaces with one component fixed to 0 (symmetry planes, rollers): (group, component).
    pub roller_groups: Vec<(String, usize)>,
    /// Fraction of each disk inside the mesh (1; ½ or ¼ for symmetry-cut punch models).
    pub disk_fraction: f64,
    /// +1 if the contact force on this body points along +z (slider), −1 if along −z (stator).
    pub force_sign: f64,
}
