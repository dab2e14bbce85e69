//! The one reader of the motor's input files (scene, sweep, design and scatter files): TOML
//! text into a serde struct whose tables refuse unknown keys (`deny_unknown_fields`), each error
//! one line naming the dotted path of the key at fault (`model.coupled.steps_per_period`,
//! `variables.posts.diameter`). It lives here, at the bottom of the workspace, because every
//! crate that reads an input (the `sawdrive` library, `design`) links `motor`.
//!
//! Dotted keys are one spelling: `posts.diameter = …` (a table `posts` holding `diameter`) and
//! `"posts.diameter" = …` (one quoted key) name the same entry ([`nest_dotted_keys`]). A key
//! that moved is refused with its new spelling ([`first_moved`]) before the struct sees it.

use serde::de::DeserializeOwned;

/// A refused input: the dotted path of the key at fault (`(file)` for a syntax error) and what
/// is wrong, in one line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputError {
    /// Dotted path of the key, or `(file)`.
    pub field: String,
    /// What is wrong and the accepted form.
    pub message: String,
}

impl std::fmt::Display for InputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl std::error::Error for InputError {}

/// The TOML table of `text`; a syntax error is one line (the parser's message with its line and
/// column) under the field `(file)`.
pub fn parse_table(text: &str) -> Result<toml::Table, InputError> {
    text.parse::<toml::Table>().map_err(|e| InputError {
        field: "(file)".into(),
        message: format!(
            "not valid TOML: {}",
            e.to_string().trim().replace('\n', " ")
        ),
    })
}

/// `table` as `T`; the error names the dotted path of the key at fault, with the first line of
/// the deserializer's message (the TOML value deserializer repeats the path on later lines).
pub fn from_table<T: DeserializeOwned>(table: toml::Table) -> Result<T, InputError> {
    serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
        let field = e.path().to_string();
        let message = e.into_inner().to_string();
        InputError {
            field,
            message: message.lines().next().unwrap_or_default().to_owned(),
        }
    })
}

/// `table` with every quoted dotted key (`"posts.diameter" = …`) nested as the bare dotted
/// key would be (`posts = { diameter = … }`), merged with what is already there.
pub fn nest_dotted_keys(table: &toml::Table) -> toml::Table {
    let mut out = toml::Table::new();
    for (key, value) in table {
        let value = match value {
            toml::Value::Table(inner) => toml::Value::Table(nest_dotted_keys(inner)),
            other => other.clone(),
        };
        let mut parts: Vec<&str> = key.split('.').collect();
        let last = parts.pop().unwrap_or_default();
        let mut at = &mut out;
        for part in parts {
            let entry = at
                .entry(part)
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if !entry.is_table() {
                *entry = toml::Value::Table(toml::Table::new());
            }
            at = entry.as_table_mut().expect("a table was just put here");
        }
        match (at.get_mut(last), value) {
            (Some(toml::Value::Table(there)), toml::Value::Table(new)) => there.extend(new),
            (_, value) => {
                at.insert(last.to_owned(), value);
            }
        }
    }
    out
}

/// `table` with nested tables as dotted keys, in order (`posts = { diameter = … }` →
/// `("posts.diameter", …)`): the inverse of [`nest_dotted_keys`], for free maps of scene keys.
pub fn dotted_keys(table: &toml::Table) -> Vec<(String, toml::Value)> {
    let mut out = Vec::new();
    for (key, value) in table {
        match value {
            toml::Value::Table(inner) => out.extend(
                dotted_keys(inner)
                    .into_iter()
                    .map(|(k, v)| (format!("{key}.{k}"), v)),
            ),
            _ => out.push((key.clone(), value.clone())),
        }
    }
    out
}

/// The value at a dotted `path` of `table`, if any.
pub fn at<'a>(table: &'a toml::Table, path: &str) -> Option<&'a toml::Value> {
    let mut parts = path.split('.');
    let mut value = table.get(parts.next()?)?;
    for part in parts {
        value = value.as_table()?.get(part)?;
    }
    Some(value)
}

/// The first old key of `moved` (old spelling, new spelling) that `table` gives, as a refusal
/// naming the new spelling; `table`'s keys may be dotted or nested.
pub fn first_moved(table: &toml::Table, moved: &[(&str, &str)]) -> Option<InputError> {
    let nested = nest_dotted_keys(table);
    moved
        .iter()
        .find(|(old, _)| at(&nested, old).is_some())
        .map(|(old, new)| InputError {
            field: (*old).to_owned(),
            message: format!("this key has moved: write {new}"),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Outer {
        posts: Inner,
    }

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Inner {
        diameter: String,
    }

    #[test]
    fn a_quoted_and_a_bare_dotted_key_read_the_same() {
        let bare = parse_table("posts.diameter = \"20 um\"").unwrap();
        let quoted = parse_table("\"posts.diameter\" = \"20 um\"").unwrap();
        assert_eq!(nest_dotted_keys(&bare), nest_dotted_keys(&quoted));
        let outer: Outer = from_table(nest_dotted_keys(&quoted)).unwrap();
        assert_eq!(outer.posts.diameter, "20 um");
    }

    #[test]
    fn an_unknown_key_is_refused_naming_its_dotted_path() {
        let t = parse_table("posts.diameter = \"20 um\"\nposts.height = \"2 um\"").unwrap();
        let e = from_table::<Outer>(t).unwrap_err();
        assert_eq!(e.field, "posts.height", "{e}");
        assert!(e.message.contains("unknown field"), "{e}");
        let e = parse_table("posts = [").unwrap_err();
        assert_eq!(e.field, "(file)");
    }

    #[test]
    fn a_moved_key_is_refused_naming_its_new_spelling() {
        let t = parse_table("\"model.periods\" = 3").unwrap();
        let e = first_moved(&t, &[("model.periods", "model.transient.periods")]).unwrap();
        assert_eq!(e.field, "model.periods");
        assert!(e.message.contains("model.transient.periods"), "{e}");
        assert!(first_moved(&t, &[("model.time_step", "x")]).is_none());
    }
}
