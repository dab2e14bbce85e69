//! Atomic file writes: write a temporary file beside the target, flush it to disk, rename it
//! into place. A failed or interrupted write never leaves a partial file under the target name.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{MeshError, Result};

fn io_error(path: &Path, action: &str, source: std::io::Error) -> MeshError {
    MeshError::Io {
        path: path.to_path_buf(),
        action: action.to_string(),
        source,
    }
}

/// Temporary path next to `target`: `.<name>.tmp-<pid>`.
fn temporary_path(target: &Path) -> PathBuf {
    let name = target
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    target.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// Write the bytes produced by `fill` to `target` atomically.
pub(crate) fn write_atomically(
    target: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let temporary = temporary_path(target);
    let result = (|| -> std::io::Result<()> {
        let file = std::fs::File::create(&temporary)?;
        let mut writer = std::io::BufWriter::new(file);
        fill(&mut writer)?;
        let file = writer.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()
    })();
    if let Err(source) = result {
        let _ = std::fs::remove_file(&temporary);
        return Err(io_error(target, "writing", source));
    }
    std::fs::rename(&temporary, target).map_err(|source| {
        let _ = std::fs::remove_file(&temporary);
        io_error(
            target,
            &format!("renaming {} into place", temporary.display()),
            source,
        )
    })
}
