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

/// The kinds of results folder; a folder is replaced only by a result of its own kind
/// ([`atomic_files::RESULT_MARKER`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ResultKind {
    /// `OUT/<scene>/` of `run`.
    Run,
    /// `OUT/<scene>/static/` of `static`.
    Static,
    /// `OUT/<scene>/dynamic/` of `dynamic`.
    Dynamic,
    /// The cached VTU fields of a static solution.
    Fields,
    /// `OUT/<scene>-uq/` of `uq`.
    Uq,
    /// `OUT/<design>/` of `design`.
    Design,
}

impl ResultKind {
    /// The name written into the folder's marker.
    pub fn name(self) -> &'static str {
        match self {
            ResultKind::Run => "run",
            ResultKind::Static => "static",
            ResultKind::Dynamic => "dynamic",
            ResultKind::Fields => "fields",
            ResultKind::Uq => "uq",
            ResultKind::Design => "design",
        }
    }
}

/// A results folder being written ([`atomic_files::StagedDir`], telling the user on stderr when
/// earlier results hidden by a killed run were restored).
#[derive(Debug)]
pub struct StagedDir(atomic_files::StagedDir);

impl StagedDir {
    /// Start writing `destination` (e.g. `out/paper-motor`). Fails early if the parent folder
    /// cannot be created or written, or if `destination` exists and is not a result of `kind`.
    pub fn create(destination: &Path, kind: ResultKind) -> Result<Self, OutputError> {
        let staged = atomic_files::StagedDir::create(destination, kind.name())?;
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

/// A value saved as JSON together with the SHA-256 of its compact JSON, so that a file edited
/// or truncated by hand is recognised ([`read_verified_json`]) and recomputed, never merged.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Verified<T> {
    /// SHA-256 (hex) of `serde_json::to_vec(&value)`.
    sha256: String,
    value: T,
}

fn sha256_of_json<T: serde::Serialize>(value: &T) -> Result<String, serde_json::Error> {
    use sha2::Digest;
    let digest = sha2::Sha256::digest(serde_json::to_vec(value)?);
    Ok(digest.iter().map(|b| format!("{b:02x}")).collect())
}

/// `value` as pretty JSON with its SHA-256 (the file format [`read_verified_json`] checks).
pub fn to_verified_json<T: serde::Serialize>(value: &T) -> Result<Vec<u8>, serde_json::Error> {
    let sha256 = sha256_of_json(value)?;
    serde_json::to_vec_pretty(&Verified { sha256, value })
}

/// What [`read_verified_json`] found.
#[derive(Debug, PartialEq)]
pub enum Saved<T> {
    /// No file.
    Missing,
    /// The file holds a value whose hash matches.
    Valid(T),
    /// The file exists but is not what was saved (unreadable, malformed or edited): why.
    Altered(String),
}

/// Read a file written with [`to_verified_json`], checking its hash.
pub fn read_verified_json<T>(path: &Path) -> Saved<T>
where
    T: serde::Serialize + serde::de::DeserializeOwned,
{
    let bytes = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Saved::Missing,
        Err(e) => return Saved::Altered(format!("cannot be read: {e}")),
    };
    let saved: Verified<T> = match serde_json::from_slice(&bytes) {
        Ok(saved) => saved,
        Err(e) => return Saved::Altered(format!("is not a saved result: {e}")),
    };
    match sha256_of_json(&saved.value) {
        Ok(hash) if hash == saved.sha256 => Saved::Valid(saved.value),
        _ => Saved::Altered("does not match its checksum (edited since it was saved)".into()),
    }
}

/// One cell of a results table.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// User-given text (a label, a grid value as written): quoted as RFC 4180 needs, and
    /// neutralised against spreadsheet formulas ([`neutralise_formula`]).
    Text(String),
    /// A number, written with Rust's shortest round-trip formatting (`NaN` for a missing value).
    Number(f64),
}

/// A text cell starting with `=`, `+`, `-` or `@` (what a spreadsheet evaluates as a formula)
/// gets a leading `'`, as OWASP recommends; the Python package strips it when reading back.
pub fn neutralise_formula(text: &str) -> String {
    if text.starts_with(['=', '+', '-', '@']) {
        format!("'{text}")
    } else {
        text.to_owned()
    }
}

/// A CSV table (header, then rows) written by the `csv` crate: RFC 4180 quoting of commas,
/// quotes and line breaks, `\n` line ends.
pub fn csv_table(header: &[&str], rows: impl IntoIterator<Item = Vec<Cell>>) -> String {
    let mut writer = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    let record = |writer: &mut csv::Writer<Vec<u8>>, fields: Vec<String>| {
        writer
            .write_record(fields)
            .expect("writing CSV to memory cannot fail");
    };
    record(
        &mut writer,
        header.iter().map(|h| (*h).to_owned()).collect(),
    );
    for row in rows {
        let fields = row
            .into_iter()
            .map(|cell| match cell {
                Cell::Text(t) => neutralise_formula(&t),
                Cell::Number(v) => v.to_string(),
            })
            .collect();
        record(&mut writer, fields);
    }
    let bytes = writer
        .into_inner()
        .expect("flushing CSV to memory cannot fail");
    String::from_utf8(bytes).expect("CSV of UTF-8 fields is UTF-8")
}

#[cfg(test)]
mod tests {
    #[test]
    fn an_edited_or_emptied_verified_file_is_recognised() {
        let root = tempfile::tempdir().unwrap();
        let path = root.path().join("p.json");
        assert_eq!(read_verified_json::<Vec<f64>>(&path), Saved::Missing);
        std::fs::write(&path, to_verified_json(&vec![1.5, 2.0]).unwrap()).unwrap();
        assert_eq!(read_verified_json(&path), Saved::Valid(vec![1.5, 2.0]));
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::write(&path, text.replace("1.5", "9.5")).unwrap();
        assert!(
            matches!(read_verified_json::<Vec<f64>>(&path), Saved::Altered(m) if m.contains("checksum"))
        );
        std::fs::write(&path, "").unwrap();
        assert!(matches!(
            read_verified_json::<Vec<f64>>(&path),
            Saved::Altered(_)
        ));
    }

    #[test]
    fn text_cells_are_quoted_and_formulas_neutralised() {
        let table = csv_table(
            &["label", "x"],
            [
                vec![Cell::Text("a,\"b\"\nc".into()), Cell::Number(0.5)],
                vec![Cell::Text("=HYPERLINK(1)".into()), Cell::Number(f64::NAN)],
                vec![Cell::Text("-5 N".into()), Cell::Number(-1.0)],
            ],
        );
        assert_eq!(
            table,
            "label,x\n\"a,\"\"b\"\"\nc\",0.5\n'=HYPERLINK(1),NaN\n'-5 N,-1\n"
        );
    }

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
        StagedDir::create(&dest, ResultKind::Run)
            .unwrap()
            .commit()
            .unwrap();
        std::fs::write(dest.join("summary.json"), "good").unwrap();
        {
            let staged = StagedDir::create(&dest, ResultKind::Run).unwrap();
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
