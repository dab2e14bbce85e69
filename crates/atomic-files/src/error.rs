//! The crate's one error type.

use std::path::PathBuf;

/// A file system operation failed; names what was being done and on which path.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// An I/O operation failed.
    #[error("cannot {verb} {path}: {source}")]
    Io {
        /// What was being done, as a verb phrase ("write", "rename into place").
        verb: &'static str,
        /// Path at fault.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// An input file was refused before being read: not a regular file, or too large.
    #[error("{path} {problem}")]
    BadInput {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        problem: InputProblem,
    },
    /// A results folder would replace a folder that is not a result of the same kind (the
    /// user's own files, another kind of result, a file): refused before anything is written.
    #[error(
        "refusing to replace {path}: {reason}, not a {kind} result written by this program; choose another name or output folder, or remove it yourself"
    )]
    NotAResult {
        /// The folder that would have been replaced.
        path: PathBuf,
        /// The kind of result being written ("run", "sweep", "design", ...).
        kind: String,
        /// What was found there instead.
        reason: String,
    },
}

/// Why an input file was refused before being read ([`crate::read_input`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InputProblem {
    /// A folder, device, pipe or socket.
    #[error("is {kind}, not a regular file; give a regular file")]
    NotAFile {
        /// What it is instead: "a directory" or "a device, pipe or socket".
        kind: &'static str,
    },
    /// Larger than the limit for its kind of input.
    #[error(
        "is {size_bytes} bytes, more than the {limit_bytes} bytes accepted for this kind of input"
    )]
    TooLarge {
        /// Its size (bytes), or how far it was read if it grew while read.
        size_bytes: u64,
        /// The limit (bytes).
        limit_bytes: u64,
    },
    /// Not UTF-8 text.
    #[error("is not UTF-8 text (invalid byte at offset {offset})")]
    NotText {
        /// Offset of the first invalid byte.
        offset: usize,
    },
}

impl FileError {
    /// `map_err` adapter: an `io::Error` while doing `verb` on `path` becomes [`FileError::Io`].
    pub fn io<'a>(
        verb: &'static str,
        path: &'a std::path::Path,
    ) -> impl FnOnce(std::io::Error) -> Self + 'a {
        move |source| FileError::Io {
            verb,
            path: path.to_owned(),
            source,
        }
    }

    /// The path at fault.
    pub fn path(&self) -> &std::path::Path {
        match self {
            FileError::Io { path, .. }
            | FileError::NotAResult { path, .. }
            | FileError::BadInput { path, .. } => path,
        }
    }

    /// What was being done.
    pub fn verb(&self) -> &'static str {
        match self {
            FileError::Io { verb, .. } => verb,
            FileError::NotAResult { .. } => "replace",
            FileError::BadInput { .. } => "read",
        }
    }

    /// The underlying I/O error (moved out), with the path at fault.
    pub fn into_parts(self) -> (PathBuf, std::io::Error) {
        match self {
            FileError::Io { path, source, .. } => (path, source),
            FileError::NotAResult { path, reason, .. } => (
                path,
                std::io::Error::new(std::io::ErrorKind::AlreadyExists, reason),
            ),
            FileError::BadInput { path, problem } => (
                path,
                std::io::Error::new(std::io::ErrorKind::InvalidInput, problem.to_string()),
            ),
        }
    }
}
