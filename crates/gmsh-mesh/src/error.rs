//! The crate's one error type. Every variant names the file and the place in it.

use std::path::PathBuf;

/// Where in an MSH file a problem was found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// Section name without the `$`, e.g. `Nodes`; empty before the first section.
    pub section: String,
    /// Byte offset from the start of the file.
    pub byte_offset: usize,
    /// 1-based line number (counted over `\n`; approximate inside binary data).
    pub line: usize,
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.section.is_empty() {
            write!(f, "line {}, byte offset {}", self.line, self.byte_offset)
        } else {
            write!(
                f,
                "section ${}, line {}, byte offset {}",
                self.section, self.line, self.byte_offset
            )
        }
    }
}

/// Errors of the MSH reader, the mesh queries and the VTU writer.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read or written.
    #[error("{path}: {action} failed: {source}")]
    Io {
        /// File at fault.
        path: PathBuf,
        /// What was attempted ("reading", "writing", "renaming ... into place").
        action: String,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },

    /// The `$MeshFormat` header names a version this reader does not read.
    #[error(
        "{file}: unsupported MSH format version {found} ({at}); this reader supports MSH 4.1 \
         (ASCII and binary), which gmsh >= 4.1 writes with `-format msh41`"
    )]
    UnsupportedVersion {
        /// File at fault.
        file: String,
        /// Version string as written in the file.
        found: String,
        /// Where the version was read.
        at: Location,
    },

    /// The file ends before a section or value is complete.
    #[error("{file}: truncated file: {at}: expected {expected}")]
    Truncated {
        /// File at fault.
        file: String,
        /// Where the data stops.
        at: Location,
        /// What should have followed.
        expected: String,
    },

    /// Malformed content: a value, keyword or count that is not what the format requires.
    #[error("{file}: {at}: expected {expected}, found {found}")]
    Syntax {
        /// File at fault.
        file: String,
        /// Where the problem is.
        at: Location,
        /// What the format requires there.
        expected: String,
        /// What the file holds there.
        found: String,
    },

    /// Sections are missing, repeated or out of the order MSH 4.1 prescribes.
    #[error("{file}: wrong section order: {detail}")]
    SectionOrder {
        /// File at fault.
        file: String,
        /// Which sections and why.
        detail: String,
    },

    /// The low-level parser (mshio) rejected the file's entities, nodes or elements.
    #[error("{file}: {at}: {detail}")]
    Parse {
        /// File at fault.
        file: String,
        /// Innermost location the parser reported.
        at: Location,
        /// The parser's context chain, outermost first.
        detail: String,
    },

    /// The file parses but its content is inconsistent (dangling node tag, duplicate tag,
    /// mixed element orders, non-finite coordinate, ...).
    #[error("{file}: invalid mesh: {detail}")]
    Invalid {
        /// File at fault.
        file: String,
        /// What is inconsistent, naming the element or node tag.
        detail: String,
    },

    /// Tetrahedra with a negative Jacobian (inverted) or a vanishing volume (degenerate).
    #[error(
        "{file}: {inverted_count} inverted and {degenerate_count} degenerate tetrahedra \
         (element tags, first {shown}: inverted {inverted_tags:?}, degenerate {degenerate_tags:?}); \
         regenerate the mesh, or read with BadElementPolicy::Report to inspect it"
    )]
    BadElements {
        /// File at fault.
        file: String,
        /// Number of tets with a negative Jacobian somewhere.
        inverted_count: usize,
        /// Number of tets with a vanishing volume.
        degenerate_count: usize,
        /// How many tags are listed at most per kind.
        shown: usize,
        /// Tags of the first inverted tets.
        inverted_tags: Vec<u64>,
        /// Tags of the first degenerate tets.
        degenerate_tags: Vec<u64>,
    },

    /// A physical group asked for by name does not exist (or has the wrong dimension).
    #[error("{file}: no {kind} physical group named \"{name}\"; available: {available}")]
    MissingGroup {
        /// Mesh the group was looked up in.
        file: String,
        /// "surface" or "volume".
        kind: &'static str,
        /// The requested name.
        name: String,
        /// Names that exist for that dimension, comma separated.
        available: String,
    },

    /// A field handed to the VTU writer does not fit the mesh.
    #[error("{file}: field \"{field}\": {detail}")]
    Field {
        /// The VTU file being written.
        file: String,
        /// Field name.
        field: String,
        /// What does not fit (length, non-finite value, ...).
        detail: String,
    },
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, MeshError>;
