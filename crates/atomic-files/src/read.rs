//! Input files read with their kind and size checked first.
//!
//! A user-given path may name a device (`/dev/zero`), a pipe, a folder or a file far larger than
//! any input of its kind; reading it whole would run out of memory. [`read_input`] accepts only
//! a regular file (after following links) of at most `max_bytes`, and reads at most that many
//! bytes even if the file grows while it is read.

use std::io::Read;
use std::path::Path;

use crate::{FileError, InputProblem};

/// 1 MiB: the largest scene, sweep, design or scatter file accepted (a scene is a few kB).
pub const MAX_SETTINGS_FILE_BYTES: u64 = 1 << 20;

/// The bytes of the regular file `path`, refused with [`FileError::BadInput`] (naming the
/// limit) if it is not a regular file or is larger than `max_bytes`.
pub fn read_input(path: &Path, max_bytes: u64) -> Result<Vec<u8>, FileError> {
    let refuse = |problem| FileError::BadInput {
        path: path.to_owned(),
        problem,
    };
    // stat before open: opening a FIFO would block until someone writes to it.
    let meta = std::fs::metadata(path).map_err(FileError::io("read", path))?;
    if !meta.is_file() {
        let kind = if meta.is_dir() {
            "a directory"
        } else {
            "a device, pipe or socket"
        };
        return Err(refuse(InputProblem::NotAFile { kind }));
    }
    let too_large = |size_bytes| {
        refuse(InputProblem::TooLarge {
            size_bytes,
            limit_bytes: max_bytes,
        })
    };
    if meta.len() > max_bytes {
        return Err(too_large(meta.len()));
    }
    let file = std::fs::File::open(path).map_err(FileError::io("open", path))?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(FileError::io("read", path))?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// [`read_input`] as UTF-8 text.
pub fn read_input_text(path: &Path, max_bytes: u64) -> Result<String, FileError> {
    String::from_utf8(read_input(path, max_bytes)?).map_err(|e| FileError::BadInput {
        path: path.to_owned(),
        problem: InputProblem::NotText {
            offset: e.utf8_error().valid_up_to(),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_folders_and_oversized_files_are_refused_before_reading() {
        let root = tempfile::tempdir().unwrap();
        let big = root.path().join("big.toml");
        std::fs::write(&big, vec![b'#'; 101]).unwrap();
        for (path, says) in [
            (Path::new("/dev/zero"), "not a regular file"),
            (root.path(), "a directory"),
            (big.as_path(), "more than the 100 bytes"),
        ] {
            if !path.exists() {
                continue;
            }
            let err = read_input(path, 100).unwrap_err();
            assert!(err.to_string().contains(says), "{err}");
        }
        assert_eq!(read_input(&big, 101).unwrap().len(), 101);
    }

    #[test]
    fn text_that_is_not_utf8_names_the_byte() {
        let root = tempfile::tempdir().unwrap();
        let path = root.path().join("s.toml");
        std::fs::write(&path, b"ab\xff").unwrap();
        assert!(
            read_input_text(&path, 10)
                .unwrap_err()
                .to_string()
                .contains("offset 2")
        );
    }
}
