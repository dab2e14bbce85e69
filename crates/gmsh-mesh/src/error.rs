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

    /// The path is not a regular file (a directory, device such as /dev/zero, pipe or socket):
    /// refused before reading.
    #[error("{path}: not a regular file ({kind}); give the path of a .msh file")]
    NotAFile {
        /// Path at fault.
        path: PathBuf,
        /// What it is instead.
        kind: &'static str,
    },

    /// The file is larger than the reader accepts ([`crate::MAX_MSH_FILE_BYTES`]).
    #[error("{path}: {size} is larger than the mesh reader's limit of {limit} bytes")]
    TooLarge {
        /// Path at fault.
        path: PathBuf,
        /// Its size as far as known, e.g. "5000000000 bytes" or "the stream".
        size: String,
        /// The limit (bytes).
        limit: u64,
    },

    /// gmsh could not be started (not installed, not on PATH, or `$GMSH` wrong).
    #[error(
        "meshing {geometry}: cannot run gmsh `{program}` ({source}); install it \
         (apt-get install gmsh) or set GMSH to the gmsh binary"
    )]
    GmshMissing {
        /// The .geo file to mesh.
        geometry: PathBuf,
        /// The program looked for.
        program: String,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },

    /// gmsh ran and failed (non-zero exit, `Error` lines in its log, or no mesh written).
    #[error("meshing {geometry} into {out}: gmsh failed ({status}): {log_tail}")]
    GmshFailed {
        /// The .geo file.
        geometry: PathBuf,
        /// The mesh that was to be written.
        out: PathBuf,
        /// Exit status, or why the run counts as failed.
        status: String,
        /// gmsh's `Error` lines, or the last lines of its output, joined by " | ".
        log_tail: String,
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

impl MeshError {
    /// The same error with every control byte of its texts escaped ([`escape_control`]): the
    /// reader's messages quote names and tokens from the file, which must not reach a terminal
    /// as escape sequences.
    pub fn escaped(self) -> Self {
        let e = |s: String| escape_control(&s);
        match self {
            MeshError::UnsupportedVersion { file, found, at } => MeshError::UnsupportedVersion {
                file: e(file),
                found: e(found),
                at: at.escaped(),
            },
            MeshError::Truncated { file, at, expected } => MeshError::Truncated {
                file: e(file),
                at: at.escaped(),
                expected: e(expected),
            },
            MeshError::Syntax {
                file,
                at,
                expected,
                found,
            } => MeshError::Syntax {
                file: e(file),
                at: at.escaped(),
                expected: e(expected),
                found: e(found),
            },
            MeshError::SectionOrder { file, detail } => MeshError::SectionOrder {
                file: e(file),
                detail: e(detail),
            },
            MeshError::Parse { file, at, detail } => MeshError::Parse {
                file: e(file),
                at: at.escaped(),
                detail: e(detail),
            },
            MeshError::Invalid { file, detail } => MeshError::Invalid {
                file: e(file),
                detail: e(detail),
            },
            MeshError::MissingGroup {
                file,
                kind,
                name,
                available,
            } => MeshError::MissingGroup {
                file: e(file),
                kind,
                name: e(name),
                available: e(available),
            },
            MeshError::BadElements {
                file,
                inverted_count,
                degenerate_count,
                shown,
                inverted_tags,
                degenerate_tags,
            } => MeshError::BadElements {
                file: e(file),
                inverted_count,
                degenerate_count,
                shown,
                inverted_tags,
                degenerate_tags,
            },
            other => other,
        }
    }
}

impl Location {
    fn escaped(self) -> Self {
        Location {
            section: escape_control(&self.section),
            ..self
        }
    }
}

/// `text` with every control character written as an escape: `\x1b` for ESC, `\x00`..`\x1f`
/// and `\x7f` likewise, `\u{85}` for the C1 controls; tab and other text unchanged. Messages
/// that quote bytes of a file go through this so that they cannot drive the terminal.
pub fn escape_control(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\t' => out.push(c),
            c if (c as u32) < 0x80 && c.is_control() => {
                out.push_str(&format!("\\x{:02x}", c as u32))
            }
            c if c.is_control() => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => out.push(c),
        }
    }
    out
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, MeshError>;
