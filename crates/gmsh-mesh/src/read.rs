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

/// Largest mesh file the reader loads (bytes): 2 GiB. The finest committed-parameter strip
/// (100 posts, Tet10) is ≈ 40 MB binary, so this only stops inputs that are not meshes
/// (`/dev/zero`, a disk image) before they exhaust the memory.
pub const MAX_MSH_FILE_BYTES: u64 = 2 << 30;

/// Read the MSH 4.1 file at `path` (ASCII or binary).
pub fn read_msh_with(path: impl AsRef<Path>, options: &ReadOptions) -> Result<TetMesh> {
    let path = path.as_ref();
    check_head(path, options)?;
    let bytes = read_file_bounded(path, MAX_MSH_FILE_BYTES)?;
    parse_msh(&bytes, &path.display().to_string(), options)
}

/// Bytes read first to tell an MSH file (whose first non-blank byte starts a `$Section` tag)
/// from anything else before the whole file is read.
const HEAD_BYTES: u64 = 4096;

/// Refuse a file that does not start like an MSH file after reading only its first
/// [`HEAD_BYTES`], with the error the full parse would give there (a large file that is not a
/// mesh is not read whole).
fn check_head(path: &Path, options: &ReadOptions) -> Result<()> {
    use std::io::Read;
    let Ok(meta) = std::fs::metadata(path) else {
        return Ok(()); // the bounded read names the error
    };
    if !meta.is_file() || meta.len() <= HEAD_BYTES {
        return Ok(());
    }
    let mut head = Vec::new();
    let read = std::fs::File::open(path).and_then(|f| f.take(HEAD_BYTES).read_to_end(&mut head));
    if read.is_err() {
        return Ok(());
    }
    match head.iter().find(|b| !b.is_ascii_whitespace()) {
        Some(b'$') | None => Ok(()),
        Some(_) => parse_msh(&head, &path.display().to_string(), options).map(drop),
    }
}

/// The bytes of the regular file at `path`, refusing anything that is not a regular file
/// ([`MeshError::NotAFile`]: directories, devices such as `/dev/zero`, pipes) and files larger
/// than `limit` bytes ([`MeshError::TooLarge`]); the read itself stops after `limit` + 1 bytes,
/// so a file that grows while it is read cannot exceed the limit either.
pub fn read_file_bounded(path: &Path, limit: u64) -> Result<Vec<u8>> {
    use atomic_files::{FileError, InputProblem};
    atomic_files::read_input(path, limit).map_err(|e| match e {
        FileError::BadInput {
            path,
            problem: InputProblem::NotAFile { kind },
        } => MeshError::NotAFile { path, kind },
        FileError::BadInput {
            path,
            problem: InputProblem::TooLarge { size_bytes, .. },
        } => MeshError::TooLarge {
            path,
            size: format!("{size_bytes} bytes"),
            limit,
        },
        other => {
            let (path, source) = other.into_parts();
            MeshError::Io {
                path,
                action: "reading".to_string(),
                source,
            }
        }
    })
}

/// Parse the bytes of an MSH 4.1 file; `name` labels the source in error messages. Texts
/// quoted from the file are escaped in errors ([`MeshError::escaped`]).
pub fn parse_msh(bytes: &[u8], name: &str, options: &ReadOptions) -> Result<TetMesh> {
    parse_unescaped(bytes, name, options).map_err(MeshError::escaped)
}

fn parse_unescaped(bytes: &[u8], name: &str, options: &ReadOptions) -> Result<TetMesh> {
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
