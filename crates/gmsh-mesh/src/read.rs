//! Reading MSH 4.1 files into a [`TetMesh`].

use std::path::Path;

use crate::assemble::assemble;
use crate::error::{MeshError, Result};
use crate::mesh::TetMesh;
use crate::msh::{self, Source};
use crate::quality::MAX_LISTED_TAGS;

/// What to do with inverted or degenerate tetrahedra.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BadElementPolicy {
    /// Fail with [`MeshError::BadElements`] (default: such a mesh cannot be solved).
    #[default]
    Error,
    /// Load anyway; list them in [`TetMesh::notes`] (see also [`TetMesh::quality`]).
    Report,
}

/// Options of the reader.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ReadOptions {
    /// Inverted or degenerate tets: error (default) or report.
    pub bad_elements: BadElementPolicy,
}

/// Read the MSH 4.1 file at `path` (ASCII or binary) with default options.
pub fn read_msh(path: impl AsRef<Path>) -> Result<TetMesh> {
    read_msh_with(path, &ReadOptions::default())
}

/// Read the MSH 4.1 file at `path` (ASCII or binary).
pub fn read_msh_with(path: impl AsRef<Path>, options: &ReadOptions) -> Result<TetMesh> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        action: "reading".to_string(),
        source,
    })?;
    parse_msh(&bytes, &path.display().to_string(), options)
}

/// Parse the bytes of an MSH 4.1 file; `name` labels the source in error messages.
pub fn parse_msh(bytes: &[u8], name: &str, options: &ReadOptions) -> Result<TetMesh> {
    let raw = msh::parse(Source { name, bytes })?;
    let mut mesh = assemble(name, raw)?;
    let quality = mesh.quality();
    if quality.has_bad_elements() {
        match options.bad_elements {
            BadElementPolicy::Error => {
                return Err(MeshError::BadElements {
                    file: name.to_string(),
                    inverted_count: quality.inverted_count,
                    degenerate_count: quality.degenerate_count,
                    shown: MAX_LISTED_TAGS,
                    inverted_tags: quality.inverted_tags,
                    degenerate_tags: quality.degenerate_tags,
                });
            }
            BadElementPolicy::Report => mesh.notes.push(format!(
                "{} inverted tets (tags {:?}), {} degenerate tets (tags {:?}) loaded on request",
                quality.inverted_count,
                quality.inverted_tags,
                quality.degenerate_count,
                quality.degenerate_tags
            )),
        }
    }
    Ok(mesh)
}
