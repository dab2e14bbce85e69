//! Single files written atomically: temporary sibling, flush to disk, rename over the target.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::FileError;

/// Distinguishes temporary files of one process (threads may write siblings concurrently).
static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Temporary sibling of `target`: `.<stem>.tmp-<pid>-<n>[.<extension>]`. The extension is kept
/// so that writers choosing the format by extension (image encoders) still recognise it.
fn temporary_sibling(target: &Path) -> PathBuf {
    let n = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
    let pid = std::process::id();
    let stem = target
        .file_stem()
        .map_or_else(|| "output".into(), |s| s.to_string_lossy().into_owned());
    let name = match target.extension() {
        Some(ext) => format!(".{stem}.tmp-{pid}-{n}.{}", ext.to_string_lossy()),
        None => format!(".{stem}.tmp-{pid}-{n}"),
    };
    target.with_file_name(name)
}

/// Flush `temporary` to disk and rename it over `target`; removes `temporary` on failure.
fn finish(temporary: &Path, target: &Path) -> Result<(), FileError> {
    let synced = std::fs::File::open(temporary).and_then(|f| f.sync_all());
    let result = synced
        .map_err(FileError::io("flush to disk", target))
        .and_then(|()| {
            std::fs::rename(temporary, target).map_err(FileError::io("rename into place", target))
        });
    if result.is_err() {
        let _ = std::fs::remove_file(temporary);
    }
    result
}

/// Write `bytes` to `path` atomically. The parent folder must exist.
pub fn write_atomically(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), FileError> {
    write_atomically_with(path, |w| w.write_all(bytes.as_ref()))
}

/// Write what `fill` streams to `path` atomically (buffered). The parent folder must exist.
pub fn write_atomically_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), FileError> {
    let temporary = temporary_sibling(path);
    let written = (|| -> std::io::Result<()> {
        let mut writer = std::io::BufWriter::new(std::fs::File::create(&temporary)?);
        fill(&mut writer)?;
        writer.into_inner().map_err(|e| e.into_error())?.sync_all()
    })();
    if let Err(source) = written {
        let _ = std::fs::remove_file(&temporary);
        return Err(FileError::Io {
            verb: "write",
            path: path.to_owned(),
            source,
        });
    }
    std::fs::rename(&temporary, path).map_err(|source| {
        let _ = std::fs::remove_file(&temporary);
        FileError::Io {
            verb: "rename into place",
            path: path.to_owned(),
            source,
        }
    })
}

/// Let `fill` write the file at a temporary path (for writers that open files themselves, e.g.
/// image encoders; the extension of `path` is kept), then move it to `path` atomically. If `fill`
/// fails, its error is returned and the temporary file removed; `path` is untouched.
pub fn write_atomically_via<E: From<FileError>>(
    path: &Path,
    fill: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), E> {
    let temporary = temporary_sibling(path);
    if let Err(error) = fill(&temporary) {
        let _ = std::fs::remove_file(&temporary);
        return Err(error);
    }
    Ok(finish(&temporary, path)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn written_file_replaces_the_target_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.json");
        std::fs::write(&path, "old").unwrap();
        write_atomically(&path, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(names_in(dir.path()), ["a.json"]);
    }

    #[test]
    fn failing_stream_keeps_the_old_file_and_removes_the_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mesh.vtu");
        std::fs::write(&path, "old").unwrap();
        let error = write_atomically_with(&path, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("disk full"))
        })
        .unwrap_err();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(names_in(dir.path()), ["mesh.vtu"]);
        let message = error.to_string();
        assert!(
            message.contains("cannot write") && message.contains("mesh.vtu"),
            "error names verb and path: {message}"
        );
    }

    #[test]
    fn missing_folder_is_an_error_naming_the_target() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("no-such-folder").join("x.csv");
        let error = write_atomically(&path, "x").unwrap_err();
        assert_eq!(error.path(), path);
        assert_eq!(error.verb(), "write");
    }

    #[test]
    fn writer_through_a_path_sees_the_extension_and_its_failure_keeps_the_target() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("chart.png");
        write_atomically_via(&path, |tmp| -> Result<(), FileError> {
            assert_eq!(
                tmp.extension().unwrap(),
                "png",
                "temporary keeps the extension"
            );
            std::fs::write(tmp, "png").map_err(FileError::io("write", tmp))
        })
        .unwrap();
        let failed = write_atomically_via(&path, |tmp| -> Result<(), FileError> {
            std::fs::write(tmp, "half").unwrap();
            Err(FileError::io("draw", tmp)(std::io::Error::other("no font")))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "png");
        assert_eq!(names_in(dir.path()), ["chart.png"]);
    }
}
