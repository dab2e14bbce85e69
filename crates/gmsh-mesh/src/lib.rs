//! Gmsh MSH 4.1 reader (ASCII and binary) producing a tetrahedral mesh with physical groups,
//! element quality checks, a mesh summary and a ParaView VTU writer. No physics here.
//!
//! ```no_run
//! let mesh = gmsh_mesh::read_msh("meshes/punch_a10um_R20a_tet4_5k.msh")?;
//! let punch = mesh.group_faces("punch")?;          // outward-oriented boundary triangles
//! let fixed = mesh.group_nodes("far_field")?;      // sorted unique node indices
//! println!("{} tets, volume {:.3e} m^3", mesh.tets.len(), mesh.volume());
//! # Ok::<(), gmsh_mesh::MeshError>(())
//! ```
//!
//! Why not `mshio`: it drops node tags when the header's tag range is dense, so a file whose
//! node blocks list their tags out of order is silently misread; it also ignores
//! `$PhysicalNames` and `$Periodic`, reports errors without file offsets, and can underflow on
//! an empty `$Nodes`. This crate's own parser checks every count against the bytes left before
//! allocating, names the section, line and byte offset of every error, and never panics on input
//! (see the corrupted-file property tests).

mod assemble;
mod atomic;
pub mod elevate;
mod error;
pub mod geometry;
pub mod gmsh;
mod info;
mod mesh;
pub mod mirror;
mod msh;
mod quality;
mod read;
pub mod renumber;
mod vtu;

pub use error::{Location, MeshError, Result, escape_control};
pub use info::{GroupInfo, MeshInfo, mesh_info};
pub use mesh::{Faces, PhysicalGroup, TetMesh, Tets};
pub use quality::{
    DEGENERATE_NORMALIZED_VOLUME, MAX_LISTED_TAGS, POOR_RADIUS_RATIO, QualityReport,
};
pub use read::{
    BadElementPolicy, MAX_MSH_FILE_BYTES, ReadOptions, parse_msh, read_file_bounded, read_msh,
    read_msh_with,
};
pub use vtu::{Field, FieldValues, GMSH_TO_VTK_TET10, VTK_QUADRATIC_TETRA, VTK_TETRA, write_vtu};
