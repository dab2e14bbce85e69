//! Atomic file writes through the workspace's one writer (crate `atomic-files`): a temporary
//! file beside the target, flushed to disk and renamed into place. A failed or interrupted write
//! never leaves a partial file under the target name.

use std::io::Write;
use std::path::Path;

use crate::error::{MeshError, Result};

/// Write the bytes produced by `fill` to `target` atomically.
pub(crate) fn write_atomically(
    target: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    Ok(atomic_files::write_atomically_with(target, fill)?)
}

impl From<atomic_files::FileError> for MeshError {
    fn from(error: atomic_files::FileError) -> Self {
        let action = match error.verb() {
            "write" => "writing".to_owned(),
            verb => format!("writing ({verb})"),
        };
        let (path, source) = error.into_parts();
        MeshError::Io {
            path,
            action,
            source,
        }
    }
}
