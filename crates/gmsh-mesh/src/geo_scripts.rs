//! The gmsh geometry scripts of `meshes/`, embedded in the binary (`include_str!`) so that a
//! binary or wheel used away from its checkout can still mesh: [`path`] writes a script into the
//! cache folder (`<cache>/geo/NAME.geo`, [`crate::cache`]) when it is missing or differs, and
//! returns the path gmsh is given. [`source`] is the script text, which caches of meshes and
//! results hash so that an edited script invalidates them.

use std::path::PathBuf;

use crate::cache::{cache_dir, write_if_different};

/// `meshes/punch.geo`: rigid punch on a half-space (validation of the springs).
pub const PUNCH: &str = include_str!("../../../meshes/punch.geo");
/// `meshes/slider-strip.geo`: strip of posts on a stator (static contact).
pub const SLIDER_STRIP: &str = include_str!("../../../meshes/slider-strip.geo");
/// `meshes/slider-body.geo`: the slider plate.
pub const SLIDER_BODY: &str = include_str!("../../../meshes/slider-body.geo");

/// Every embedded script by name (file name without `.geo`).
pub const SCRIPTS: &[(&str, &str)] = &[
    ("punch", PUNCH),
    ("slider-strip", SLIDER_STRIP),
    ("slider-body", SLIDER_BODY),
];

/// The text of the script `name` (e.g. `slider-strip`), or `None` for an unknown name.
pub fn source(name: &str) -> Option<&'static str> {
    SCRIPTS.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

/// The path of script `name` in the cache folder, written (atomically) when missing or
/// different from the embedded text.
pub fn path(name: &str) -> std::io::Result<PathBuf> {
    let text = source(name).ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!(
                "no embedded gmsh script `{name}` (known: {})",
                SCRIPTS
                    .iter()
                    .map(|(n, _)| *n)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )
    })?;
    let file = cache_dir().join("geo").join(format!("{name}.geo"));
    write_if_different(&file, text.as_bytes())?;
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_scripts_are_the_checkout_files() {
        for (name, text) in SCRIPTS {
            let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../meshes")
                .join(format!("{name}.geo"));
            assert_eq!(std::fs::read_to_string(&file).unwrap(), *text, "{name}");
        }
    }
}
