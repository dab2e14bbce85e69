//! The one cache folder of sawdrive: generated meshes, the gmsh scripts they are made from, and
//! anything else that is derived data, never in the source or build tree.
//!
//! [`cache_dir`] is, first match wins:
//! 1. the folder set by [`set_cache_dir`] (the command line's global `--cache DIR`);
//! 2. `$SAWDRIVE_CACHE` ([`CACHE_ENV`]);
//! 3. `$XDG_CACHE_HOME/sawdrive` (XDG Base Directory Specification, when set and absolute);
//! 4. `$HOME/.cache/sawdrive` (the specification's default);
//! 5. `<system temp dir>/sawdrive-cache` (no home folder).
//!
//! Meshes go to [`meshes_dir`] (`<cache>/meshes`, or `$SAWDRIVE_MESH_CACHE` when set, for scripts
//! that measure cold meshing in a scratch folder), gmsh scripts to `<cache>/geo`
//! ([`crate::geo_scripts`]). The FEM results cache of a sweep is not here: it is `OUT/.cache`
//! beside the results it serves, shared by the shards of one sweep.

use std::path::PathBuf;
use std::sync::OnceLock;

/// Environment variable naming the cache folder.
pub const CACHE_ENV: &str = "SAWDRIVE_CACHE";

/// Environment variable naming the mesh folder only (overrides `<cache>/meshes`).
pub const MESH_CACHE_ENV: &str = "SAWDRIVE_MESH_CACHE";

static OVERRIDE: OnceLock<PathBuf> = OnceLock::new();

/// Sets the cache folder for the rest of the process (the `--cache` flag); the first call wins.
/// Returns false if a different folder was already set.
pub fn set_cache_dir(dir: PathBuf) -> bool {
    OVERRIDE.get_or_init(|| dir.clone()) == &dir
}

/// Non-empty value of an environment variable.
fn env_path(name: &str) -> Option<PathBuf> {
    std::env::var_os(name)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
}

/// The cache folder (module docs for the order of the sources). Not created here.
pub fn cache_dir() -> PathBuf {
    if let Some(dir) = OVERRIDE.get() {
        return dir.clone();
    }
    if let Some(dir) = env_path(CACHE_ENV) {
        return dir;
    }
    if let Some(dir) = env_path("XDG_CACHE_HOME").filter(|d| d.is_absolute()) {
        return dir.join("sawdrive");
    }
    if let Some(home) = env_path("HOME") {
        return home.join(".cache").join("sawdrive");
    }
    std::env::temp_dir().join("sawdrive-cache")
}

/// The folder of generated meshes: `$SAWDRIVE_MESH_CACHE`, else `<cache>/meshes`.
pub fn meshes_dir() -> PathBuf {
    env_path(MESH_CACHE_ENV).unwrap_or_else(|| cache_dir().join("meshes"))
}

/// Makes `path` hold exactly `bytes`: left alone when it already does, else written atomically
/// (temporary sibling, then rename; parent folders created). For embedded files (gmsh scripts,
/// committed meshes) copied into the cache.
pub fn write_if_different(path: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    let same = std::fs::metadata(path).is_ok_and(|m| m.len() == bytes.len() as u64)
        && std::fs::read(path).is_ok_and(|b| b == bytes);
    if same {
        return Ok(());
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    atomic_files::write_atomically(path, bytes).map_err(std::io::Error::other)
}
