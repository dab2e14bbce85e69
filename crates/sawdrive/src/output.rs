//! Results written atomically, through the workspace's one writer (crate `atomic-files`):
//! single files via a temporary sibling and a rename; results folders staged in a hidden folder
//! next to the destination, which replaces `OUT/<name>/` only when complete. An interrupted or
//! failed run leaves the previous results untouched; a run killed between the two renames of the
//! commit leaves them in `.NAME.previous-PID`, and the next run restores them and says so.

use std::path::{Path, PathBuf};

/// Why a results folder or file could not be written (names the verb and the path).
pub use atomic_files::FileError as OutputError;

/// Test hook (not a user setting): when set to `1`, a commit that replaces earlier results stops
/// between its two renames and waits to be killed, so that tests can check the recovery.
pub const PAUSE_COMMIT_ENV: &str = "SAWDRIVE_TEST_PAUSE_COMMIT";

/// `map_err` adapter: an `io::Error` while doing `verb` on `path` becomes an [`OutputError`].
pub(crate) fn io<'a>(
    verb: &'static str,
    path: &'a Path,
) -> impl FnOnce(std::io::Error) -> OutputError + 'a {
    OutputError::io(verb, path)
}

/// A results folder being written ([`atomic_files::StagedDir`], telling the user on stderr when
/// earlier results hidden by a killed run were restored).
#[derive(Debug)]
pub struct StagedDir(atomic_files::StagedDir);

impl StagedDir {
    /// Start writing `destination` (e.g. `out/paper-motor`). Fails early if the parent folder
    /// cannot be created or written.
    pub fn create(destination: &Path) -> Result<Self, OutputError> {
        let staged = atomic_files::StagedDir::create(destination)?;
        for recovery in staged.recovered() {
            eprintln!("note: {recovery}");
        }
        Ok(Self(staged))
    }

    /// Folder to write files into until [`StagedDir::commit`].
    pub fn path(&self) -> &Path {
        self.0.path()
    }

    /// Write one file into the staging folder.
    pub fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> Result<PathBuf, OutputError> {
        self.0.write(name, bytes)
    }

    /// Replace the destination with the staged folder.
    pub fn commit(self) -> Result<PathBuf, OutputError> {
        if std::env::var(PAUSE_COMMIT_ENV).as_deref() != Ok("1") {
            return self.0.commit();
        }
        self.0.commit_with(|previous| {
            eprintln!(
                "{PAUSE_COMMIT_ENV}: paused between the renames, earlier results in {}",
                previous.display()
            );
            loop {
                std::thread::sleep(std::time::Duration::from_secs(1));
            }
        })
    }
}

/// Write `bytes` to `path` atomically (temporary sibling, then rename), creating its folder.
pub fn write_atomically(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), OutputError> {
    if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io("create the folder", dir))?;
    }
    atomic_files::write_atomically(path, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_file_lands_in_a_new_folder() {
        let root = tempfile::tempdir().unwrap();
        let path = root.path().join("a").join("b.json");
        write_atomically(&path, "{}").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "{}");
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
