//! Layering: embedded default ← user scene ← `--set key=value` overrides, on TOML tables.

use toml::{Table, Value};

use super::SceneError;

/// Keys of which a scene gives exactly one; setting one in an upper layer removes the other.
/// A drive voltage replaces the lower layers' amplitudes (the transducer sets both); a
/// transducer's aperture the lower layers' beam width; a slider shape their slider material
/// (each shape has its own default).
const EXCLUSIVE_KEYS: [(&str, &str); 8] = [
    ("wave.tangential_velocity", "wave.tangential_amplitude"),
    ("wave.tangential_amplitude", "wave.tangential_velocity"),
    ("wave.drive_voltage", "wave.normal_amplitude"),
    ("wave.drive_voltage", "wave.tangential_velocity"),
    ("wave.drive_voltage", "wave.tangential_amplitude"),
    ("wave.normal_amplitude", "wave.drive_voltage"),
    ("stator.idt.aperture", "wave.aperture"),
    ("slider.shape", "slider.material"),
];

/// Short names accepted by `--set`, and the keys they set.
const OVERRIDE_ALIASES: [(&str, &[&str]); 5] = [
    ("preload", &["load.preload"]),
    ("load", &["load.external"]),
    ("friction", &["friction.static", "friction.kinetic"]),
    ("effective_ratio", &["contact.effective_ratio"]),
    ("mass", &["slider.mass"]),
];

/// Merge `overlay` into `base`, table by table; overlay values win.
pub(crate) fn deep_merge(base: &mut Table, overlay: Table) {
    let mut overlay_paths = Vec::new();
    collect_paths("", &overlay, &mut overlay_paths);
    for (set, removed) in EXCLUSIVE_KEYS {
        if overlay_paths.iter().any(|p| p == set) && !overlay_paths.iter().any(|p| p == removed) {
            remove_path(base, removed);
        }
    }
    merge_tables(base, overlay);
}

fn merge_tables(base: &mut Table, overlay: Table) {
    for (key, value) in overlay {
        match (base.get_mut(&key), value) {
            (Some(Value::Table(base_table)), Value::Table(overlay_table)) => {
                merge_tables(base_table, overlay_table)
            }
            (_, value) => {
                base.insert(key, value);
            }
        }
    }
}

fn collect_paths(prefix: &str, table: &Table, out: &mut Vec<String>) {
    for (key, value) in table {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        if let Value::Table(inner) = value {
            collect_paths(&path, inner, out);
        }
        out.push(path);
    }
}

fn remove_path(table: &mut Table, path: &str) {
    match path.split_once('.') {
        Some((head, rest)) => {
            if let Some(Value::Table(inner)) = table.get_mut(head) {
                remove_path(inner, rest);
            }
        }
        None => {
            table.remove(path);
        }
    }
}

/// Parse `key=value` into the table it sets. The value is read as TOML (`0.4`, `"x"`, `true`)
/// and otherwise taken as a string, so `preload=20N` and `posts.count=50x50` need no quotes.
pub(crate) fn override_table(text: &str) -> Result<Table, SceneError> {
    let bad = |reason: &str| SceneError::BadOverride {
        text: text.to_owned(),
        reason: reason.to_owned(),
    };
    let (key, raw) = text
        .split_once('=')
        .ok_or_else(|| bad("expected key=value, e.g. preload=20N"))?;
    let (key, raw) = (key.trim(), raw.trim());
    if key.is_empty() || raw.is_empty() {
        return Err(bad("expected key=value, e.g. preload=20N"));
    }
    if !key
        .split('.')
        .all(|part| !part.is_empty() && part.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
    {
        return Err(bad("keys are dotted names like posts.count"));
    }
    if is_non_decimal_integer(raw) {
        return Err(bad(
            "decimal integers only: hexadecimal, octal and binary literals are not read as numbers",
        ));
    }
    let value = format!("v = {raw}")
        .parse::<Table>()
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| Value::String(raw.to_owned()));
    let keys = OVERRIDE_ALIASES
        .iter()
        .find(|(alias, _)| *alias == key)
        .map(|(_, keys)| keys.to_vec())
        .unwrap_or(vec![key]);
    let mut table = Table::new();
    for path in keys {
        insert_path(&mut table, path, value.clone());
    }
    Ok(table)
}

/// Whether `text` is a TOML integer literal in base 16, 8 or 2 (`0x5`, `-0o7`, `0b1`).
pub(crate) fn is_non_decimal_integer(text: &str) -> bool {
    let digits = text.trim().trim_start_matches(['+', '-']);
    let lower = digits.get(..2).map(str::to_ascii_lowercase);
    matches!(lower.as_deref(), Some("0x" | "0o" | "0b"))
}

fn insert_path(table: &mut Table, path: &str, value: Value) {
    match path.split_once('.') {
        Some((head, rest)) => {
            let inner = table
                .entry(head)
                .or_insert_with(|| Value::Table(Table::new()));
            if let Value::Table(inner) = inner {
                insert_path(inner, rest, value);
            }
        }
        None => {
            table.insert(path.to_owned(), value);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aliases_expand_and_unquoted_values_become_strings() {
        let t = override_table("preload=20N").unwrap();
        assert_eq!(t["load"]["preload"].as_str(), Some("20N"));
        let t = override_table("friction=0.4").unwrap();
        assert_eq!(t["friction"]["static"].as_float(), Some(0.4));
        assert_eq!(t["friction"]["kinetic"].as_float(), Some(0.4));
        let t = override_table("posts.count = 50x50").unwrap();
        assert_eq!(t["posts"]["count"].as_str(), Some("50x50"));
    }

    #[test]
    fn malformed_overrides_are_refused() {
        for text in [
            "preload",
            "=3",
            "a..b=1",
            "posts.count=",
            "posts.count=0x5",
            "model.transient.periods=0o17",
            "model.transient.periods=-0b1",
        ] {
            assert!(override_table(text).is_err(), "{text} must be refused");
        }
    }

    #[test]
    fn giving_the_tangential_amplitude_replaces_the_default_velocity() {
        let mut base: Table = "[wave]\ntangential_velocity = \"1.1 m/s\"\nfrequency = \"1 MHz\""
            .parse()
            .unwrap();
        let overlay: Table = "[wave]\ntangential_amplitude = \"10 nm\"".parse().unwrap();
        deep_merge(&mut base, overlay);
        assert!(base["wave"].get("tangential_velocity").is_none());
        assert_eq!(
            base["wave"]["frequency"].as_str(),
            Some("1 MHz"),
            "other keys kept"
        );
    }
}
