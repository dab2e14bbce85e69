//! The static stage's one verified cache: a typed (serde) value stored as compact JSON in one
//! file, with the SHA-256 of the value's JSON, optionally the key of the inputs it was computed
//! from, and optionally the SHA-256 of each of its sidecar files (the field files a results
//! folder copies). [`get`] returns the value only if every check passes (a damaged or foreign
//! entry is named, so the caller rebuilds it and says so); [`put`] writes the entry atomically
//! (`atomic-files`: temporary sibling, flush, rename), so a killed run never leaves half an
//! entry.
//!
//! Every cached artefact of the stage goes through here: the strip's report
//! (`static-<content hash>.json`), the strip's tip compliances (`compliance-<geometry key>.json`),
//! the whole slider's near field and report (`near-field-<key>.json`, `slider-<hash>.json`).
//! Each artefact keeps its own [`Layout`] (its field names and format version), so that the
//! entries written before the cache was one type stay valid byte for byte.

use std::collections::BTreeMap;
use std::path::Path;

use serde::de::DeserializeOwned;
use serde::ser::SerializeMap;
use serde::{Deserialize, Serialize};

use super::keys::sha256_hex;
use crate::output::io;
use crate::pipeline::PipelineError;

/// How one artefact's entries are laid out: a JSON object with, in this order, `format`, the
/// key field (if any), the hash field, the sidecar field (if any) and the value field.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Layout {
    /// Layout version of the artefact's entries (the physics is in the keys, not here): an
    /// entry of another version is rebuilt.
    pub format: u32,
    /// Name of the field holding the key of the inputs (`None`: the value carries its own key,
    /// checked by [`get`]'s `check`).
    pub key_field: Option<&'static str>,
    /// Name of the field holding the SHA-256 (hex) of `serde_json::to_vec(&value)`.
    pub hash_field: &'static str,
    /// Name of the field holding the SHA-256 of each sidecar file by name (`None`: the
    /// artefact has no sidecar files).
    pub sidecar_field: Option<&'static str>,
    /// Name of the field holding the value.
    pub value_field: &'static str,
}

/// One entry: its file, the key of the inputs asked for and the folder of its sidecar files.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Entry<'a> {
    /// The entry's JSON file.
    pub file: &'a Path,
    /// The artefact's layout.
    pub layout: &'a Layout,
    /// The key of the inputs (written to, and checked against, [`Layout::key_field`]).
    pub key: &'a str,
    /// The folder of the sidecar files to record or check (`None`: none asked for).
    pub sidecars: Option<&'a Path>,
}

/// What [`get`] found.
#[derive(Debug)]
pub(crate) enum Lookup<T> {
    /// A verified value (and verified sidecar files, if they were asked for).
    Hit(T),
    /// No entry, or one without the sidecar files that were asked for.
    Miss,
    /// An entry that fails verification, and why (one line).
    Damaged(String),
}

/// SHA-256 of every file of `dir` by name.
pub(crate) fn hash_folder(dir: &Path) -> Result<BTreeMap<String, String>, PipelineError> {
    let mut hashes = BTreeMap::new();
    for entry in std::fs::read_dir(dir).map_err(io("read the cached files", dir))? {
        let path = entry.map_err(io("read the cached files", dir))?.path();
        let bytes = std::fs::read(&path).map_err(io("read a cached file", &path))?;
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        hashes.insert(name.into_owned(), sha256_hex(&bytes));
    }
    Ok(hashes)
}

/// The field `name` of the entry `object`, or why the entry is damaged.
fn field<'v>(object: &'v Object, name: &str) -> Result<&'v serde_json::Value, String> {
    object
        .get(name)
        .ok_or_else(|| format!("not a cache entry (no `{name}`)"))
}

/// The entry's fields.
type Object = serde_json::Map<String, serde_json::Value>;

/// The entry's value and fields if its format, hash and key check, or why not (`Ok(None)`: no
/// file).
fn read_value<T: Serialize + DeserializeOwned>(
    entry: &Entry<'_>,
) -> Result<Option<(T, Object)>, String> {
    let Ok(bytes) = std::fs::read(entry.file) else {
        return Ok(None);
    };
    let object: Object =
        serde_json::from_slice(&bytes).map_err(|e| format!("not a cache entry ({e})"))?;
    let layout = entry.layout;
    let format = field(&object, "format")?.as_u64();
    if format != Some(u64::from(layout.format)) {
        return Err(format!(
            "cache format {} (now {})",
            format.map_or("?".into(), |f| f.to_string()),
            layout.format
        ));
    }
    let value = T::deserialize(field(&object, layout.value_field)?)
        .map_err(|e| format!("not a cache entry ({e})"))?;
    let again = serde_json::to_vec(&value).unwrap_or_default();
    if field(&object, layout.hash_field)?.as_str() != Some(sha256_hex(&again).as_str()) {
        return Err("its content does not match the hash stored with it (edited?)".into());
    }
    if let Some(key_field) = layout.key_field
        && field(&object, key_field)?.as_str() != Some(entry.key)
    {
        return Err("it holds the result of other inputs".into());
    }
    Ok(Some((value, object)))
}

/// Reads and verifies `entry`: format, the value's hash, the key of its inputs, `check` (the
/// artefact's own test of the value, e.g. the key it carries), and, if `entry.sidecars` is
/// given, the sidecar files against the hashes recorded (an entry that recorded none is a
/// miss, so that a caller asking for them rebuilds them).
pub(crate) fn get<T: Serialize + DeserializeOwned>(
    entry: &Entry<'_>,
    check: impl FnOnce(&T) -> Result<(), String>,
) -> Lookup<T> {
    let (value, object) = match read_value::<T>(entry) {
        Ok(Some(read)) => read,
        Ok(None) => return Lookup::Miss,
        Err(why) => return Lookup::Damaged(why),
    };
    if let Err(why) = check(&value) {
        return Lookup::Damaged(why);
    }
    if let (Some(dir), Some(sidecar_field)) = (entry.sidecars, entry.layout.sidecar_field) {
        let recorded = object
            .get(sidecar_field)
            .and_then(|v| Option::<BTreeMap<String, String>>::deserialize(v).ok())
            .flatten();
        let Some(recorded) = recorded else {
            return Lookup::Miss;
        };
        match hash_folder(dir) {
            Ok(found) if found == recorded => {}
            Ok(_) => {
                return Lookup::Damaged(format!(
                    "the {} in {} differ from those recorded with it",
                    sidecar_field.replace('_', " "),
                    dir.display()
                ));
            }
            Err(_) => return Lookup::Miss,
        }
    }
    Lookup::Hit(value)
}

/// An entry as written: the fields of its [`Layout`] in order.
struct Written<'a, T> {
    layout: &'a Layout,
    key: &'a str,
    hash: String,
    sidecars: Option<BTreeMap<String, String>>,
    value: &'a T,
}

impl<T: Serialize> Serialize for Written<'_, T> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let layout = self.layout;
        let mut map = serializer.serialize_map(None)?;
        map.serialize_entry("format", &layout.format)?;
        if let Some(key_field) = layout.key_field {
            map.serialize_entry(key_field, self.key)?;
        }
        map.serialize_entry(layout.hash_field, &self.hash)?;
        if let Some(sidecar_field) = layout.sidecar_field {
            map.serialize_entry(sidecar_field, &self.sidecars)?;
        }
        map.serialize_entry(layout.value_field, self.value)?;
        map.end()
    }
}

/// Writes `value` as `entry` (with the hashes of the sidecar files in `entry.sidecars`, if
/// any), atomically.
pub(crate) fn put<T: Serialize>(entry: &Entry<'_>, value: &T) -> Result<(), PipelineError> {
    let written = Written {
        layout: entry.layout,
        key: entry.key,
        hash: sha256_hex(&serde_json::to_vec(value)?),
        sidecars: entry.sidecars.map(hash_folder).transpose()?,
        value,
    };
    crate::output::write_atomically(entry.file, serde_json::to_vec(&written)?)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAYOUT: Layout = Layout {
        format: 3,
        key_field: Some("key"),
        hash_field: "sha256",
        sidecar_field: Some("files"),
        value_field: "value",
    };

    fn entry<'a>(file: &'a Path, key: &'a str, sidecars: Option<&'a Path>) -> Entry<'a> {
        Entry {
            file,
            layout: &LAYOUT,
            key,
            sidecars,
        }
    }

    #[test]
    fn a_value_put_is_got_back_with_its_fields_in_layout_order() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("e.json");
        put(&entry(&file, "k1", None), &vec![1.5, 2.0]).unwrap();
        let text = std::fs::read_to_string(&file).unwrap();
        assert!(
            text.starts_with("{\"format\":3,\"key\":\"k1\",\"sha256\":\"")
                && text.ends_with("\"files\":null,\"value\":[1.5,2.0]}"),
            "entry layout: {text}"
        );
        match get::<Vec<f64>>(&entry(&file, "k1", None), |_| Ok(())) {
            Lookup::Hit(v) => assert_eq!(v, vec![1.5, 2.0], "cached value"),
            other => panic!("cached value not found: {other:?}"),
        }
    }

    #[test]
    fn an_edited_foreign_or_refused_entry_is_damaged_and_a_missing_one_a_miss() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("e.json");
        let damaged = |key: &str, check: fn(&u32) -> Result<(), String>| {
            matches!(
                get::<u32>(&entry(&file, key, None), check),
                Lookup::Damaged(_)
            )
        };
        assert!(matches!(
            get::<u32>(&entry(&file, "k", None), |_| Ok(())),
            Lookup::Miss
        ));
        put(&entry(&file, "k", None), &7u32).unwrap();
        assert!(damaged("other", |_| Ok(())), "an entry of other inputs");
        assert!(
            damaged("k", |_| Err("no".into())),
            "an entry the artefact refuses"
        );
        let text = std::fs::read_to_string(&file).unwrap();
        std::fs::write(&file, text.replace(":7}", ":8}")).unwrap();
        assert!(damaged("k", |_| Ok(())), "an edited value");
    }

    #[test]
    fn sidecar_files_are_checked_when_asked_for() {
        let dir = tempfile::tempdir().unwrap();
        let (file, side) = (dir.path().join("e.json"), dir.path().join("side"));
        std::fs::create_dir(&side).unwrap();
        std::fs::write(side.join("a.txt"), "a").unwrap();
        put(&entry(&file, "k", None), &1u8).unwrap();
        let got = |sidecars| get::<u8>(&entry(&file, "k", sidecars), |_| Ok(()));
        assert!(matches!(got(Some(&side)), Lookup::Miss), "none recorded");
        put(&entry(&file, "k", Some(&side)), &1u8).unwrap();
        assert!(
            matches!(got(Some(&side)), Lookup::Hit(1)),
            "recorded and unchanged"
        );
        std::fs::write(side.join("a.txt"), "b").unwrap();
        assert!(
            matches!(got(Some(&side)), Lookup::Damaged(_)),
            "a changed file"
        );
        assert!(
            matches!(got(None), Lookup::Hit(1)),
            "sidecars not asked for"
        );
    }
}
