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
            FileError::Io { path, .. } => path,
        }
    }

    /// What was being done.
    pub fn verb(&self) -> &'static str {
        match self {
            FileError::Io { verb, .. } => verb,
        }
    }

    /// The underlying I/O error (moved out), with the path at fault.
    pub fn into_parts(self) -> (PathBuf, std::io::Error) {
        match self {
            FileError::Io { path, source, .. } => (path, source),
        }
    }
}
