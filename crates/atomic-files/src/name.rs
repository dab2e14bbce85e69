//! User-given names that become one path component (a scene, sweep or design name, a chart file).
//!
//! Rule: 1 to [`MAX_NAME_BYTES`] bytes of ASCII letters, digits, `-`, `_` and `.`, not starting
//! with `.`. This excludes every separator (`/`, `\`), the components `.` and `..`, hidden names
//! (which the staging and cache folders use), absolute paths, control characters and anything a
//! terminal would interpret. Valid on every file system the workspace writes to (case is kept
//! as given; no reserved Windows device names are checked, since results are written on Unix).

/// Longest accepted name, in bytes (file systems allow 255; the staging folder adds a prefix
/// and a process id to it).
pub const MAX_NAME_BYTES: usize = 100;

/// Why a name cannot be one path component; its `Display` says what would be accepted.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{shown} {problem}: use 1 to {MAX_NAME_BYTES} letters, digits, '-', '_' or '.', not starting with '.'"
)]
pub struct NameError {
    /// The name, quoted with control characters escaped (safe to print on a terminal).
    pub shown: String,
    /// What is wrong with it.
    pub problem: &'static str,
}

/// Check that `name` is one safe path component (see the module doc for the rule).
pub fn check_name(name: &str) -> Result<(), NameError> {
    let problem = if name.is_empty() {
        Some("is empty")
    } else if name.len() > MAX_NAME_BYTES {
        Some("is too long")
    } else if name.starts_with('.') {
        Some("starts with '.'")
    } else if name.contains(['/', '\\']) {
        Some("contains a path separator")
    } else if name.chars().any(char::is_control) {
        Some("contains a control character")
    } else if !name
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
    {
        Some("contains a character other than a letter, digit, '-', '_' or '.'")
    } else {
        None
    };
    match problem {
        None => Ok(()),
        Some(problem) => Err(NameError {
            shown: format!("{:?}", truncate(name)),
            problem,
        }),
    }
}

/// At most 60 characters of `name`, for messages.
fn truncate(name: &str) -> String {
    match name.char_indices().nth(60) {
        Some((i, _)) => format!("{}…", &name[..i]),
        None => name.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_names_are_accepted() {
        for name in [
            "paper-motor",
            "a",
            "sweep_2.v1",
            &"x".repeat(MAX_NAME_BYTES),
        ] {
            assert_eq!(check_name(name), Ok(()), "{name}");
        }
    }

    #[test]
    fn names_that_would_leave_or_replace_their_folder_are_refused() {
        for name in [
            "",
            ".",
            "..",
            "../victim",
            "/abs/path",
            "a/b",
            "a\\b",
            ".cache",
            "bell\u{7}",
            "new\nline",
            "é",
            "space name",
            &"x".repeat(MAX_NAME_BYTES + 1),
        ] {
            let err = check_name(name).expect_err(name);
            assert!(!err.to_string().contains('\n'), "one line: {err}");
            assert!(!err.to_string().contains('\u{7}'), "escaped: {err}");
        }
    }
}
