#![doc = include_str!("../README.md")]

mod assemble;
mod atomic;
pub mod cache;
pub mod elevate;
mod error;
pub mod geo_scripts;
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
