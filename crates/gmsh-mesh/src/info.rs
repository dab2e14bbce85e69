//! A summary of a mesh for `sawdrive mesh info FILE`: counts, groups, volume, bounding box,
//! quality.

use std::path::Path;

use serde::Serialize;

use crate::error::{Result, escape_control};
use crate::mesh::{PhysicalGroup, TetMesh};
use crate::quality::QualityReport;
use crate::read::{ReadOptions, read_msh_with};

/// Summary of a mesh. Lengths in metres, volume in cubic metres, areas in square metres.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshInfo {
    /// The file read.
    pub file: String,
    /// "MSH 4.1 ASCII" or "MSH 4.1 binary".
    pub format: String,
    /// Nodes kept (nodes of tetrahedra).
    pub node_count: usize,
    /// Number of tetrahedra.
    pub tet_count: usize,
    /// "Tet4" or "Tet10".
    pub element_kind: String,
    /// Physical groups of every dimension.
    pub groups: Vec<GroupInfo>,
    /// Total volume of the tetrahedra (m³).
    pub volume_m3: f64,
    /// Smallest node coordinates (m).
    pub bounding_box_min_m: [f64; 3],
    /// Largest node coordinates (m).
    pub bounding_box_max_m: [f64; 3],
    /// Element quality.
    pub quality: QualityReport,
    /// Number of periodic node pairs.
    pub periodic_node_pairs: usize,
    /// What the reader skipped or adjusted.
    pub notes: Vec<String>,
}

/// One physical group in a [`MeshInfo`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroupInfo {
    /// The group as declared.
    #[serde(flatten)]
    pub group: PhysicalGroup,
    /// Surface groups: area (m²); volume groups: volume (m³); else `None`.
    pub measure: Option<f64>,
}

impl MeshInfo {
    /// Summarise an already loaded mesh.
    pub fn from_mesh(mesh: &TetMesh) -> MeshInfo {
        let [lo, hi] = mesh.bounding_box().unwrap_or([[0.0; 3]; 2]);
        let groups = mesh
            .groups
            .iter()
            .map(|g| {
                let measure = match g.dim {
                    2 => mesh.face_area(&g.name).ok(),
                    3 => mesh
                        .group_tets(&g.name)
                        .ok()
                        .map(|tets| tets.iter().map(|&t| mesh.tet_volume(t)).sum()),
                    _ => None,
                };
                GroupInfo {
                    group: g.clone(),
                    measure,
                }
            })
            .collect();
        MeshInfo {
            file: mesh.source.clone(),
            format: format!(
                "MSH {} {}",
                crate::msh::SUPPORTED_VERSION,
                if mesh.binary { "binary" } else { "ASCII" }
            ),
            node_count: mesh.nodes.len(),
            tet_count: mesh.tets.len(),
            element_kind: mesh.tets.kind().to_string(),
            groups,
            volume_m3: mesh.volume(),
            bounding_box_min_m: lo,
            bounding_box_max_m: hi,
            quality: mesh.quality(),
            periodic_node_pairs: mesh.periodic_node_pairs.len(),
            notes: mesh.notes.clone(),
        }
    }
}

/// Read `path` with the default options (inverted or degenerate tets are an error) and
/// summarise it.
pub fn mesh_info(path: impl AsRef<Path>) -> Result<MeshInfo> {
    let mesh = read_msh_with(path, &ReadOptions::default())?;
    Ok(MeshInfo::from_mesh(&mesh))
}

impl std::fmt::Display for MeshInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "file      {}", escape_control(&self.file))?;
        writeln!(f, "format    {}", self.format)?;
        writeln!(
            f,
            "elements  {} {} tets, {} nodes",
            self.tet_count, self.element_kind, self.node_count
        )?;
        writeln!(f, "volume    {:.6e} m^3", self.volume_m3)?;
        let (lo, hi) = (self.bounding_box_min_m, self.bounding_box_max_m);
        writeln!(
            f,
            "bbox      x [{:.6e}, {:.6e}] y [{:.6e}, {:.6e}] z [{:.6e}, {:.6e}] m",
            lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
        )?;
        writeln!(f, "quality   {}", self.quality)?;
        if self.periodic_node_pairs > 0 {
            writeln!(f, "periodic  {} node pairs", self.periodic_node_pairs)?;
        }
        writeln!(
            f,
            "physical groups (dim tag name: entities, elements, measure):"
        )?;
        for g in &self.groups {
            let measure = match (g.group.dim, g.measure) {
                (2, Some(a)) => format!("{a:.6e} m^2"),
                (3, Some(v)) => format!("{v:.6e} m^3"),
                _ => "-".to_string(),
            };
            writeln!(
                f,
                "  {} {:>4} {:<16} {:>4} entities {:>9} elements  {}",
                g.group.dim,
                g.group.tag,
                if g.group.named {
                    format!("\"{}\"", escape_control(&g.group.name))
                } else {
                    format!("({})", escape_control(&g.group.name))
                },
                g.group.entity_count,
                g.group.element_count,
                measure
            )?;
        }
        for note in &self.notes {
            writeln!(f, "note: {}", escape_control(note))?;
        }
        Ok(())
    }
}
