//! Where the studies write: results folders staged beside their destination and committed only
//! when complete, and single files (saved samples and evaluations) written atomically — both
//! through the workspace's one writer, `atomic-files`.

use std::path::Path;

use atomic_files::{FileError, StagedDir};

/// Starts the results folder `destination` of kind `kind` (`uq`, `design`: the folder's
/// marker, so that it replaces only a result of its own kind). Earlier results that a killed
/// run had hidden are restored, and the user is told on stderr.
pub fn staged_results(destination: &Path, kind: &str) -> Result<StagedDir, FileError> {
    let staged = StagedDir::create(destination, kind)?;
    for recovery in staged.recovered() {
        eprintln!("note: {recovery}");
    }
    Ok(staged)
}

/// Writes `bytes` to `path` atomically (temporary sibling, then rename), creating its folder.
pub fn write_atomically(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), FileError> {
    if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(FileError::io("create the folder", dir))?;
    }
    atomic_files::write_atomically(path, bytes)
}
