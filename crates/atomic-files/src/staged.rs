//! Results folders swapped in whole, with a commit that a later run recovers.
//!
//! Names beside the destination `P/<name>`:
//! * `.<name>.staging-<pid>`: being written by process `pid`;
//! * `.<name>.previous-<pid>`: the earlier results, moved aside by process `pid` during its
//!   commit, removed once the new folder is in place.
//!
//! A process killed while writing leaves a staging folder (removed by the next run). Killed
//! between the commit's two renames, it leaves the destination missing and the earlier results
//! in `.previous-<pid>`: the next run moves them back ([`Recovery`]). Killed after the second
//! rename, it leaves a `.previous-<pid>` beside a complete destination: removed.

use std::path::{Path, PathBuf};

use crate::FileError;
use crate::process::{owner_pid, process_alive};

/// Earlier results put back in place by [`recover`]: a run was killed between the renames of its
/// commit.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Recovery {
    /// The results folder restored.
    pub destination: PathBuf,
    /// The hidden folder it was restored from.
    pub from: PathBuf,
    /// Process that was killed while replacing the results.
    pub killed_pid: u32,
}

impl std::fmt::Display for Recovery {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "restored the earlier results {} from {} (run {} was killed while replacing them)",
            self.destination.display(),
            self.from.display(),
            self.killed_pid
        )
    }
}

/// Parent folder and file name of `destination`.
fn split(destination: &Path) -> (PathBuf, String) {
    let parent = destination
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = destination
        .file_name()
        .map_or_else(|| "results".into(), |n| n.to_string_lossy().into_owned());
    (parent.to_owned(), name)
}

/// Hidden sibling `.<name>.<kind>-<pid>` of `destination`.
fn hidden_sibling(destination: &Path, kind: &str, pid: u32) -> PathBuf {
    let (parent, name) = split(destination);
    parent.join(format!(".{name}.{kind}-{pid}"))
}

/// Clean up after runs on `destination` that were killed (their process no longer exists):
/// restore earlier results hidden by an interrupted commit when the destination is missing,
/// remove leftover `.previous` folders beside a complete destination, and remove abandoned
/// staging folders. Returns what was restored. Folders of live processes are left alone.
pub fn recover(destination: &Path) -> Result<Vec<Recovery>, FileError> {
    let (parent, name) = split(destination);
    let Ok(entries) = std::fs::read_dir(&parent) else {
        return Ok(Vec::new());
    };
    let mut orphans: Vec<(u32, PathBuf, bool)> = Vec::new();
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(file_name) = file_name.to_str() else {
            continue;
        };
        let (pid, previous) = match owner_pid(file_name, &name, "previous") {
            Some(pid) => (pid, true),
            None => match owner_pid(file_name, &name, "staging") {
                Some(pid) => (pid, false),
                None => continue,
            },
        };
        if pid != std::process::id() && process_alive(pid) == Some(false) {
            orphans.push((pid, entry.path(), previous));
        }
    }
    // Restore before removing anything, so the destination's presence is decided first.
    orphans.sort_by_key(|(_, _, previous)| !previous);
    let mut restored = Vec::new();
    for (pid, path, previous) in orphans {
        if previous && !destination.exists() {
            std::fs::rename(&path, destination).map_err(FileError::io(
                "restore the earlier results into",
                destination,
            ))?;
            restored.push(Recovery {
                destination: destination.to_owned(),
                from: path,
                killed_pid: pid,
            });
        } else {
            std::fs::remove_dir_all(&path).map_err(FileError::io(
                "remove the folder left by a killed run",
                &path,
            ))?;
        }
    }
    Ok(restored)
}

/// File in every committed results folder, holding the kind of result (one line).
pub const RESULT_MARKER: &str = ".sawdrive-result";

/// The kind recorded in `folder`'s [`RESULT_MARKER`], if it has one.
pub fn result_kind(folder: &Path) -> Option<String> {
    let text = std::fs::read_to_string(folder.join(RESULT_MARKER)).ok()?;
    Some(text.trim().to_owned())
}

/// May a results folder of `kind` replace `destination`? Yes if it does not exist, is empty,
/// carries the same kind, or holds nothing but marked results (of any kind: a scene's folder
/// after `static` and `dynamic` runs). A folder holding anything else, hidden files included, is
/// refused: it is not ours to remove.
fn check_replaceable(destination: &Path, kind: &str) -> Result<(), FileError> {
    let refuse = |reason: String| FileError::NotAResult {
        path: destination.to_owned(),
        kind: kind.to_owned(),
        reason,
    };
    let Ok(meta) = std::fs::symlink_metadata(destination) else {
        return Ok(());
    };
    if !meta.is_dir() {
        return Err(refuse("it exists and is not a folder".into()));
    }
    match result_kind(destination) {
        Some(found) if found == kind => return Ok(()),
        Some(found) => return Err(refuse(format!("it holds a {found} result"))),
        None => {}
    }
    let entries = std::fs::read_dir(destination)
        .map_err(FileError::io("list the earlier results", destination))?;
    for entry in entries {
        let entry = entry.map_err(FileError::io("list the earlier results", destination))?;
        let name = entry.file_name();
        let is_result =
            entry.file_type().is_ok_and(|t| t.is_dir()) && result_kind(&entry.path()).is_some();
        if !is_result {
            return Err(refuse(format!(
                "it holds {:?}",
                name.to_string_lossy().chars().take(60).collect::<String>()
            )));
        }
    }
    Ok(())
}

/// A results folder being written; replaces its destination on [`StagedDir::commit`], is removed
/// if dropped uncommitted (the destination then stays untouched).
#[derive(Debug)]
pub struct StagedDir {
    staging: PathBuf,
    destination: PathBuf,
    recovered: Vec<Recovery>,
}

impl StagedDir {
    /// Start writing `destination`: recover after killed runs ([`recover`]; see
    /// [`StagedDir::recovered`]), create the parent folders and a fresh staging folder.
    ///
    /// `kind` names the kind of result ("run", "sweep", ...): it is written into the folder as
    /// [`RESULT_MARKER`], and an existing destination is replaced only if it carries the same
    /// kind, is empty, or holds nothing but marked results (a scene's folder after `static` and
    /// `dynamic` runs). Anything else is refused with
    /// [`FileError::NotAResult`] before anything is written.
    pub fn create(destination: &Path, kind: &str) -> Result<Self, FileError> {
        let (parent, _) = split(destination);
        std::fs::create_dir_all(&parent)
            .map_err(FileError::io("create the output folder", &parent))?;
        let recovered = recover(destination)?;
        check_replaceable(destination, kind)?;
        let staging = hidden_sibling(destination, "staging", std::process::id());
        if staging.exists() {
            std::fs::remove_dir_all(&staging)
                .map_err(FileError::io("clear the staging folder", &staging))?;
        }
        std::fs::create_dir(&staging)
            .map_err(FileError::io("create the staging folder", &staging))?;
        let marker = staging.join(RESULT_MARKER);
        std::fs::write(&marker, format!("{kind}\n")).map_err(FileError::io("write", &marker))?;
        Ok(Self {
            staging,
            destination: destination.to_owned(),
            recovered,
        })
    }

    /// Earlier results restored by [`StagedDir::create`] (tell the user).
    pub fn recovered(&self) -> &[Recovery] {
        &self.recovered
    }

    /// Folder to write files into until [`StagedDir::commit`].
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The folder the results will replace.
    pub fn destination(&self) -> &Path {
        &self.destination
    }

    /// Write one file into the staging folder (plain write: the folder is not visible yet).
    pub fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> Result<PathBuf, FileError> {
        let path = self.staging.join(name);
        std::fs::write(&path, bytes).map_err(FileError::io("write", &path))?;
        Ok(path)
    }

    /// Replace the destination with the staged folder; returns the destination.
    pub fn commit(self) -> Result<PathBuf, FileError> {
        self.commit_with(|_| {})
    }

    /// [`StagedDir::commit`], calling `between_renames` with the `.previous` folder after the
    /// earlier results were moved aside and before the new ones are moved in (only when there
    /// were earlier results). For tests that kill a run at the worst moment.
    pub fn commit_with(self, between_renames: impl FnOnce(&Path)) -> Result<PathBuf, FileError> {
        let destination = self.destination.clone();
        let previous = hidden_sibling(&destination, "previous", std::process::id());
        let had_previous = destination.exists();
        if had_previous {
            std::fs::rename(&destination, &previous).map_err(FileError::io(
                "move aside the earlier results",
                &destination,
            ))?;
            between_renames(&previous);
        }
        if let Err(source) = std::fs::rename(&self.staging, &destination) {
            if had_previous {
                let _ = std::fs::rename(&previous, &destination);
            }
            return Err(FileError::Io {
                verb: "move the new results into",
                path: destination,
                source,
            });
        }
        if had_previous {
            let _ = std::fs::remove_dir_all(&previous);
        }
        // Nothing left to clean: the staging folder is now the destination.
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

#[cfg(test)]
mod tests {
    use super::*;

    /// No process has this PID (above Linux's pid_max of 2^22): a run that was killed.
    const DEAD_PID: u32 = 4_294_967_295;

    fn names_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    /// A folder holding an earlier committed "run" result (its marker only).
    fn earlier_run(dest: &Path) {
        std::fs::create_dir(dest).unwrap();
        std::fs::write(dest.join(RESULT_MARKER), "run\n").unwrap();
    }

    fn has_proc() -> bool {
        Path::new("/proc").is_dir()
    }

    #[test]
    fn committed_folder_replaces_the_previous_results() {
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        earlier_run(&dest);
        std::fs::write(dest.join("old.txt"), "old").unwrap();
        let staged = StagedDir::create(&dest, "run").unwrap();
        staged.write("summary.json", "{}").unwrap();
        staged.commit().unwrap();
        assert!(dest.join("summary.json").exists() && !dest.join("old.txt").exists());
        assert_eq!(
            names_in(root.path()),
            ["scene"],
            "no staging or previous folders left"
        );
    }

    #[test]
    fn folders_of_killed_runs_are_cleaned_up_by_the_next_run() {
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        let stale = root.path().join(format!(".scene.staging-{DEAD_PID}"));
        std::fs::create_dir(&stale).unwrap();
        let staged = StagedDir::create(&dest, "run").unwrap();
        if has_proc() {
            assert!(!stale.exists(), "stale staging folder removed");
        }
        staged.commit().unwrap();
    }

    #[test]
    fn abandoned_run_leaves_previous_results_untouched() {
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        earlier_run(&dest);
        std::fs::write(dest.join("summary.json"), "good").unwrap();
        {
            let staged = StagedDir::create(&dest, "run").unwrap();
            staged.write("summary.json", "half").unwrap();
        }
        assert_eq!(
            std::fs::read_to_string(dest.join("summary.json")).unwrap(),
            "good"
        );
        assert_eq!(names_in(root.path()), ["scene"], "staging folder removed");
    }

    #[test]
    fn results_hidden_by_a_commit_killed_between_its_renames_are_restored() {
        if !has_proc() {
            return;
        }
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        // State left by a run killed between the renames: destination missing, earlier results
        // aside, its complete staging folder beside them.
        let previous = root.path().join(format!(".scene.previous-{DEAD_PID}"));
        std::fs::create_dir(&previous).unwrap();
        std::fs::write(previous.join("summary.json"), "earlier").unwrap();
        std::fs::write(previous.join(RESULT_MARKER), "run\n").unwrap();
        std::fs::create_dir(root.path().join(format!(".scene.staging-{DEAD_PID}"))).unwrap();
        let staged = StagedDir::create(&dest, "run").unwrap();
        assert_eq!(staged.recovered().len(), 1, "one folder restored");
        assert_eq!(staged.recovered()[0].from, previous);
        assert!(
            staged.recovered()[0]
                .to_string()
                .contains("restored the earlier results")
        );
        assert_eq!(
            std::fs::read_to_string(dest.join("summary.json")).unwrap(),
            "earlier"
        );
        drop(staged);
        assert_eq!(
            names_in(root.path()),
            ["scene"],
            "only the restored results remain"
        );
    }

    #[test]
    fn previous_folder_beside_complete_results_is_removed_not_restored() {
        if !has_proc() {
            return;
        }
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        earlier_run(&dest);
        std::fs::write(dest.join("summary.json"), "new").unwrap();
        std::fs::create_dir(root.path().join(format!(".scene.previous-{DEAD_PID}"))).unwrap();
        let restored = recover(&dest).unwrap();
        assert!(restored.is_empty());
        assert_eq!(
            std::fs::read_to_string(dest.join("summary.json")).unwrap(),
            "new"
        );
        assert_eq!(names_in(root.path()), ["scene"]);
    }

    #[test]
    fn folders_of_a_live_process_are_left_alone() {
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        // PID 1 always exists: a concurrent run in the middle of its commit.
        let busy = root.path().join(".scene.previous-1");
        std::fs::create_dir(&busy).unwrap();
        assert!(recover(&dest).unwrap().is_empty());
        assert!(busy.exists() && !dest.exists());
    }

    #[test]
    fn hook_runs_between_the_renames_with_the_earlier_results_aside() {
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("scene");
        earlier_run(&dest);
        std::fs::write(dest.join("a"), "earlier").unwrap();
        let staged = StagedDir::create(&dest, "run").unwrap();
        let mut seen = None;
        staged
            .commit_with(|previous| {
                seen = Some((
                    dest.exists(),
                    std::fs::read_to_string(previous.join("a")).ok(),
                ));
            })
            .unwrap();
        assert_eq!(seen, Some((false, Some("earlier".into()))));
    }

    #[test]
    fn a_folder_that_is_not_a_result_of_the_same_kind_is_refused_and_kept() {
        let root = tempfile::tempdir().unwrap();
        let user = root.path().join("user");
        std::fs::create_dir(&user).unwrap();
        std::fs::write(user.join("thesis.tex"), "mine").unwrap();
        let other = root.path().join("other");
        earlier_run(&other);
        let file = root.path().join("file");
        std::fs::write(&file, "mine").unwrap();
        let hidden = root.path().join("hidden");
        std::fs::create_dir(&hidden).unwrap();
        std::fs::write(hidden.join(".cache"), "mine").unwrap();
        for (dest, says) in [
            (&user, "thesis.tex"),
            (&other, "holds a run result"),
            (&file, "not a folder"),
            (&hidden, ".cache"),
        ] {
            let err = StagedDir::create(dest, "design").unwrap_err();
            assert!(
                matches!(err, FileError::NotAResult { .. }) && err.to_string().contains(says),
                "{err}"
            );
        }
        assert_eq!(
            std::fs::read_to_string(user.join("thesis.tex")).unwrap(),
            "mine"
        );
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
        assert_eq!(
            names_in(root.path()),
            ["file", "hidden", "other", "user"],
            "nothing staged"
        );
    }

    #[test]
    fn an_empty_folder_or_one_of_marked_results_is_replaced_and_marked() {
        let root = tempfile::tempdir().unwrap();
        let empty = root.path().join("empty");
        std::fs::create_dir(&empty).unwrap();
        let scene = root.path().join("scene");
        std::fs::create_dir(&scene).unwrap();
        let statics = scene.join("static");
        std::fs::create_dir(&statics).unwrap();
        std::fs::write(statics.join(RESULT_MARKER), "static\n").unwrap();
        for dest in [&empty, &scene] {
            StagedDir::create(dest, "run").unwrap().commit().unwrap();
            assert_eq!(result_kind(dest).as_deref(), Some("run"));
        }
    }
}
