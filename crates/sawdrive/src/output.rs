//! Results folders written atomically: everything goes into a hidden staging folder next to the
//! destination, which replaces `OUT/<name>/` only when complete. An interrupted or failed run
//! leaves the previous results untouched (and at most a stale `.staging` folder, cleaned on the
//! next run).

use std::path::{Path, PathBuf};

/// Why a results folder could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// A file system operation failed.
    #[error("cannot {action} {path}: {source}")]
    Io {
        /// What was being done.
        action: &'static str,
        /// Path at fault.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
}

/// `map_err` adapter: an `io::Error` while doing `action` on `path` becomes [`OutputError::Io`].
pub(crate) fn io<'a>(
    action: &'static str,
    path: &'a Path,
) -> impl FnOnce(std::io::Error) -> OutputError + 'a {
    move |source| OutputError::Io {
        action,
        path: path.to_owned(),
        source,
    }
}

/// A results folder being written.
#[derive(Debug)]
pub struct StagedDir {
    staging: PathBuf,
    destination: PathBuf,
}

impl StagedDir {
    /// Start writing `destination` (e.g. `out/paper-motor`). Fails early if the parent folder
    /// cannot be created or written.
    pub fn create(destination: &Path) -> Result<Self, OutputError> {
        let parent = destination
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(io("create the output folder", parent))?;
        let name = destination
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("results");
        remove_abandoned_staging(parent, name);
        let staging = parent.join(format!(".{name}.staging-{}", std::process::id()));
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(io("clear the staging folder", &staging))?;
        }
        std::fs::create_dir(&staging).map_err(io("create the staging folder", &staging))?;
        Ok(Self {
            staging,
            destination: destination.to_owned(),
        })
    }

    /// Folder to write files into until [`StagedDir::commit`].
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Write one file into the staging folder.
    pub fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> Result<PathBuf, OutputError> {
        let path = self.staging.join(name);
        std::fs::write(&path, bytes).map_err(io("write", &path))?;
        Ok(path)
    }

    /// Replace the destination with the staged folder.
    pub fn commit(self) -> Result<PathBuf, OutputError> {
        let destination = self.destination.clone();
        let previous = destination.with_file_name(format!(
            ".{}.previous-{}",
            destination
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or("results"),
            std::process::id()
        ));
        let had_previous = destination.exists();
        if had_previous {
            std::fs::rename(&destination, &previous)
                .map_err(io("move aside the previous results", &destination))?;
        }
        if let Err(source) = std::fs::rename(&self.staging, &destination) {
            if had_previous {
                let _ = std::fs::rename(&previous, &destination);
            }
            return Err(OutputError::Io {
                action: "move the new results into",
                path: destination,
                source,
            });
        }
        if had_previous {
            let _ = std::fs::remove_dir_all(&previous);
        }
        std::mem::forget(self);
        Ok(destination)
    }
}

impl Drop for StagedDir {
    /// An abandoned run removes its staging folder; the destination is untouched.
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.staging);
    }
}

/// Remove `.{name}.staging-PID` folders left by runs that were killed (Ctrl-C, crash): those
/// whose process no longer exists (checked through /proc where there is one).
fn remove_abandoned_staging(parent: &Path, name: &str) {
    let prefix = format!(".{name}.staging-");
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(pid) = file_name.to_str().and_then(|n| n.strip_prefix(&prefix)) else {
            continue;
        };
        let alive = Path::new("/proc")
            .is_dir()
            .then(|| Path::new("/proc").join(pid).exists());
        if alive == Some(false) {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

/// Write `bytes` to `path` atomically (temporary sibling, then rename).
pub fn write_atomically(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), OutputError> {
    if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io("create the folder", dir))?;
    }
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("file");
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(io("write", &tmp))?;
    std::fs::rename(&tmp, path).map_err(io("rename into", path))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn committed_folder_replaces_the_previous_results() {
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        std::fs::create_dir(&dest).unwrap();
        std::fs::write(dest.join("old.txt"), "old").unwrap();
        let staged = StagedDir::create(&dest).unwrap();
        staged.write("summary.json", "{}").unwrap();
        staged.commit().unwrap();
        assert!(dest.join("summary.json").exists() && !dest.join("old.txt").exists());
        let names: Vec<_> = std::fs::read_dir(root.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(
            names.len(),
            1,
            "no staging or previous folders left: {names:?}"
        );
    }

    #[test]
    fn folders_of_killed_runs_are_cleaned_up_by_the_next_run() {
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        // No process has PID 4294967295: this folder belongs to a run that was killed.
        let stale = root.path().join(".scene.staging-4294967295");
        std::fs::create_dir(&stale).unwrap();
        let staged = StagedDir::create(&dest).unwrap();
        if Path::new("/proc").is_dir() {
            assert!(!stale.exists(), "stale staging folder removed");
        }
        staged.commit().unwrap();
    }

    #[test]
    fn abandoned_run_leaves_previous_results_untouched() {
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        std::fs::create_dir(&dest).unwrap();
        std::fs::write(dest.join("summary.json"), "good").unwrap();
        {
            let staged = StagedDir::create(&dest).unwrap();
            staged.write("summary.json", "half").unwrap();
            // dropped without commit: the run failed
        }
        assert_eq!(
            std::fs::read_to_string(dest.join("summary.json")).unwrap(),
            "good"
        );
        assert_eq!(
            std::fs::read_dir(root.path()).unwrap().count(),
            1,
            "staging folder removed"
        );
    }
}
